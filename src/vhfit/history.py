"""Stretch histories λ(t) of a homogeneous uniaxial test (docs/theory.md §1).

A :class:`History` is a piecewise-linear stretch path through breakpoints
``(time[k], stretch[k])`` plus the times at which the stress is wanted. A constant
engineering strain rate ramp, ``λ(t) = 1 + r t``, is the two-breakpoint case; a
measured loading-unloading, ramp-hold or Hopkinson-bar history is the general case.

Engineering strain ε = λ − 1; compression is negative (strain, rate and stress). The
material is at rest before t = 0: :func:`from_rest` starts a measured path there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["History", "from_rest"]


def _as_1d(name: str, values, *, allow_empty: bool = False) -> np.ndarray:
    arr = np.asarray(values, dtype=np.float64)
    if arr.ndim == 0:
        arr = arr.reshape(1)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be a 1-D array, got shape {arr.shape}")
    if arr.size == 0 and not allow_empty:
        raise ValueError(f"{name} is empty: give at least one value")
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"{name}[{i}] = {float(arr[i])!r} is not finite: remove or repair that point"
        )
    return arr


def from_rest(t, strain) -> tuple[np.ndarray, np.ndarray]:
    """A measured (time, strain) path started from rest: ``(0, 0)`` prepended when the
    first sample comes later.

    The material is at rest at ε = 0 before t = 0 (docs/theory.md §1), so a record that
    starts at t > 0 is reached by a linear ramp from (0, 0). A path that starts at t = 0
    is returned as it is (a non-zero strain there is a jump at t = 0).

    Parameters
    ----------
    t : array_like, shape (k,)
        Sample times in s (k >= 1).
    strain : array_like, shape (k,)
        Engineering strain at each sample.

    Returns
    -------
    t, strain : ndarray
        As float arrays, with ``(0, 0)`` in front if ``t[0] > 0``.

    Raises
    ------
    ValueError
        If ``t`` and ``strain`` are not 1-D arrays of the same, non-zero length.

    Examples
    --------
    >>> from_rest([1.0, 2.0], [-0.1, -0.2])
    (array([0., 1., 2.]), array([ 0. , -0.1, -0.2]))
    >>> from_rest([0.0, 1.0], [0.0, 0.3])
    (array([0., 1.]), array([0. , 0.3]))
    """
    t = np.asarray(t, dtype=np.float64)
    e = np.asarray(strain, dtype=np.float64)
    if t.ndim != 1 or t.shape != e.shape or t.size == 0:
        raise ValueError(
            f"from_rest: t has shape {t.shape} and strain {e.shape}: give two 1-D arrays of "
            "the same, non-zero length"
        )
    if t[0] > 0.0:
        return np.concatenate([[0.0], t]), np.concatenate([[0.0], e])
    return t, e


@dataclass(frozen=True, eq=False)
class History:
    """A piecewise-linear stretch history and the times where stress is reported.

    Parameters
    ----------
    time : ndarray, shape (k,)
        Breakpoint times in s, strictly increasing, ``time[0] == 0``.
    stretch : ndarray, shape (k,)
        Stretch λ at each breakpoint, all > 0. Between breakpoints λ is linear in t.
    out_time : ndarray, shape (n,)
        Times (any order, within ``[0, time[-1]]``) at which the stress is evaluated.

    Notes
    -----
    Build histories with :meth:`constant_rate` or :meth:`piecewise_linear`; they check
    their input and say what is wrong. Before ``t = 0`` the material is at rest.
    """

    time: np.ndarray
    stretch: np.ndarray
    out_time: np.ndarray

    # ------------------------------------------------------------------ builders
    @classmethod
    def constant_rate(cls, strain, strain_rate: float) -> History:
        """Constant engineering strain-rate ramp from ε = 0 (docs/theory.md §1; paper Eq. 3).

        Parameters
        ----------
        strain : array_like
            Engineering strains at which the stress is wanted; all must have the
            sign of ``strain_rate`` (or be 0).
        strain_rate : float
            Engineering strain rate r in 1/s, non-zero (negative in compression).

        Examples
        --------
        >>> h = History.constant_rate([-0.1, -0.2], strain_rate=-100.0)
        >>> h.out_time
        array([0.001, 0.002])
        """
        eps = _as_1d("strain", strain)
        try:
            r = float(strain_rate)
        except (TypeError, ValueError):
            raise ValueError(
                f"strain_rate must be a number in 1/s, got {strain_rate!r}"
            ) from None
        if not np.isfinite(r) or r == 0.0:
            raise ValueError(
                f"strain_rate = {strain_rate!r} is invalid: give a finite, non-zero rate "
                "in 1/s (negative in compression)"
            )
        t = eps / r
        if (t < 0).any():
            i = int(np.flatnonzero(t < 0)[0])
            raise ValueError(
                f"strain[{i}] = {eps[i]:g} has the opposite sign to strain_rate = {r:g}: "
                "a constant-rate ramp from 0 only reaches strains of the rate's sign "
                "(compression: negative strain and rate)"
            )
        if (eps <= -1.0).any():
            i = int(np.flatnonzero(eps <= -1.0)[0])
            raise ValueError(
                f"strain[{i}] = {eps[i]:g} gives a non-positive stretch 1 + strain: "
                "engineering strain must be > -1"
            )
        t_end = float(t.max())
        if t_end == 0.0:
            # nothing happens: a degenerate but valid ramp of zero length
            return cls(np.array([0.0]), np.array([1.0]), t)
        return cls(np.array([0.0, t_end]), np.array([1.0, 1.0 + r * t_end]), t)

    @classmethod
    def piecewise_linear(cls, time, strain, out_time=None) -> History:
        """History through measured ``(time, strain)`` samples, linear in between.

        Parameters
        ----------
        time : array_like, shape (k,)
            Sample times in s, strictly increasing, starting at 0.
        strain : array_like, shape (k,)
            Engineering strain at each sample; ``strain[0]`` should be 0 (a non-zero
            start is applied as an instantaneous jump at t = 0).
        out_time : array_like, optional
            Times where the stress is wanted; default: the sample times.

        Examples
        --------
        >>> h = History.piecewise_linear([0, 1, 2], [0, -0.2, 0])   # load, unload
        >>> h.stretch
        array([1. , 0.8, 1. ])
        """
        t = _as_1d("time", time)
        eps = _as_1d("strain", strain)
        if t.shape != eps.shape:
            raise ValueError(
                f"time and strain must have the same length, got {t.size} and {eps.size}"
            )
        if t[0] != 0.0:
            raise ValueError(
                f"time[0] = {t[0]:g}: histories start at t = 0; subtract time[0] from "
                "the time column"
            )
        dt = np.diff(t)
        if (dt <= 0).any():
            i = int(np.flatnonzero(dt <= 0)[0]) + 1
            raise ValueError(
                f"time must be strictly increasing, but time[{i}] = {t[i]:g} <= "
                f"time[{i - 1}] = {t[i - 1]:g}: sort the samples or drop duplicates"
            )
        lam = 1.0 + eps
        if (lam <= 0).any():
            i = int(np.flatnonzero(lam <= 0)[0])
            raise ValueError(
                f"strain[{i}] = {eps[i]:g} gives a non-positive stretch 1 + strain: "
                "engineering strain must be > -1"
            )
        out = t.copy() if out_time is None else _as_1d("out_time", out_time)
        if (out < 0).any() or (out > t[-1]).any():
            raise ValueError(
                f"out_time must lie within the history [0, {t[-1]:g}] s"
            )
        return cls(t, lam, out)

    def with_outputs(self, out_time) -> History:
        """The same stretch path, with stress reported at other times."""
        out = _as_1d("out_time", out_time)
        if (out < 0).any() or (out > self.time[-1]).any():
            raise ValueError(f"out_time must lie within the history [0, {self.time[-1]:g}] s")
        return History(self.time, self.stretch, out)

    # ----------------------------------------------------------------- queries
    @property
    def duration(self) -> float:
        """Length of the history in s."""
        return float(self.time[-1])

    def stretch_at(self, t) -> np.ndarray:
        """λ(t), linear between breakpoints."""
        return np.interp(t, self.time, self.stretch)

    @property
    def out_stretch(self) -> np.ndarray:
        """λ at the output times."""
        return self.stretch_at(self.out_time)

    @property
    def out_strain(self) -> np.ndarray:
        """Engineering strain at the output times."""
        return self.out_stretch - 1.0

    # ------------------------------------------------------------ internal grid
    def grid(self, dlog: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Integration grid: node times, node stretches, and output node indices.

        Each linear piece of the path is cut into steps over which ln λ changes by at
        most ``dlog``; the output times are inserted as nodes (a node closer than a
        quarter step to an output time is moved onto it), so the stress at an output
        time is exact for the interpolant rather than interpolated between nodes.
        A hold (constant λ) needs no inner nodes: its decay is integrated exactly.
        """
        tb, lb = self.time, self.stretch
        nodes = [tb[:1]]
        for k in range(tb.size - 1):
            dl = abs(np.log(lb[k + 1] / lb[k]))
            m = max(1, int(np.ceil(dl / dlog)))
            # uniform in ln λ along the piece (λ is linear in t there)
            frac = np.linspace(0.0, 1.0, m + 1)[1:]
            if dl > 0:
                lam = lb[k] * np.exp(np.log(lb[k + 1] / lb[k]) * frac)
                tt = tb[k] + (lam - lb[k]) / (lb[k + 1] - lb[k]) * (tb[k + 1] - tb[k])
            else:
                tt = tb[k] + frac * (tb[k + 1] - tb[k])
            tt[-1] = tb[k + 1]  # exactly the breakpoint: rounding may land just below it
            nodes.append(tt)
        base = np.concatenate(nodes)
        out = self.out_time
        # snap near-coincident base nodes onto output times, but never move breakpoints
        is_break = np.zeros(base.size, dtype=bool)
        is_break[np.searchsorted(base, tb)] = True
        if base.size > 1:
            pos = np.clip(np.searchsorted(base, out), 1, base.size - 1)
            for side in (pos - 1, pos):
                spacing = np.minimum(
                    np.diff(base, prepend=base[0])[np.clip(side, 1, None)],
                    np.diff(base, append=base[-1])[np.clip(side, None, base.size - 2)],
                )
                near = (np.abs(base[side] - out) < 0.25 * spacing) & ~is_break[side]
                base[side[near]] = out[near]
        t_nodes = np.unique(np.concatenate([base, out]))
        idx = np.searchsorted(t_nodes, out)
        return t_nodes, self.stretch_at(t_nodes), idx
