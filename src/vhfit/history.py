"""Stretch histories λ(t) of a homogeneous test (docs/theory.md §1, §13).

A :class:`History` is a piecewise-linear stretch path through breakpoints
``(time[k], stretch[k])`` plus the times at which the stress is wanted. A constant
engineering strain rate ramp, ``λ(t) = 1 + r t``, is the two-breakpoint case; a
measured loading-unloading, ramp-hold or Hopkinson-bar history is the general case.
The test is named by ``deformation``, a registered :class:`vhfit.modes.Deformation`
whose record says how its path is built: a test with a second prescribed stretch
(general biaxial) also takes λ2(t) (``stretch2``); a test driven by shear follows the
amount of shear γ(t) instead of λ(t). An equilibrium history
(:meth:`History.equilibrium`) is a set of fully relaxed states with no time at all.

Engineering strain ε = λ − 1 (γ in simple shear); compression is negative (strain,
rate and stress). The material is at rest before t = 0: :func:`from_rest` starts a
measured path there.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vhfit.modes import (
    DEFORMATIONS,
    check_deformation,
    get_deformation,
    with_second_stretch,
    with_two_directions,
)

__all__ = ["History", "from_rest", "DEFORMATIONS"]


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


def _path2(deformation: str, strain2, n: int | None):
    """The second stretch path (a test with a second prescribed stretch) from ``strain2``,
    or None; one-line errors."""
    if not get_deformation(deformation).second_stretch:
        if strain2 is not None:
            only = " or ".join(f"deformation={n!r}" for n in with_second_stretch())
            raise ValueError(f"strain2 is only for {only}, not {deformation!r}: drop it")
        return None
    if strain2 is None:
        raise ValueError(
            f"deformation={deformation!r} needs strain2 (λ2 − 1 at each sample): give the "
            "second stretch path"
        )
    e2 = _as_1d("strain2", strain2)
    if n is not None and e2.size != n:
        raise ValueError(f"strain2 must have one value per strain value: got {e2.size}, "
                         f"expected {n}")
    _check_stretch("strain2", 1.0 + e2)
    return 1.0 + e2


def _check_stretch(name: str, lam: np.ndarray) -> None:
    if (lam <= 0).any():
        i = int(np.flatnonzero(lam <= 0)[0])
        raise ValueError(
            f"{name}[{i}] = {lam[i] - 1.0:g} gives a non-positive stretch 1 + strain: "
            "engineering strain must be > -1"
        )


def _loading(deformation: str, eps: np.ndarray) -> np.ndarray:
    """The path variable of ``stretch``: λ = 1 + ε, or γ itself in simple shear."""
    test = get_deformation(deformation)
    x = test.path(eps)
    if not test.shear:
        _check_stretch("strain", x)
    return x


@dataclass(frozen=True, eq=False)
class History:
    """A piecewise-linear stretch history and the times where stress is reported.

    Parameters
    ----------
    time : ndarray, shape (k,)
        Breakpoint times in s, strictly increasing, ``time[0] == 0``. For an
        equilibrium history: the sample numbers 0, 1, ..., k − 1 (no physical time).
    stretch : ndarray, shape (k,)
        Stretch λ1 at each breakpoint, all > 0; in simple shear the amount of shear
        γ (any sign). Between breakpoints it is linear in t.
    out_time : ndarray, shape (n,)
        Times (any order, within ``[0, time[-1]]``) at which the stress is evaluated.
    deformation : str
        The test, a registered deformation (default "uniaxial").
    stretch2 : ndarray, shape (k,), optional
        λ2 at each breakpoint; for a test with a second prescribed stretch only, where
        it is required.
    out_direction : ndarray of int, shape (n,), optional
        Loaded direction of each output: 1, or 2 for the second loaded direction of a
        test that has one; default all 1.
    is_equilibrium : bool
        Fully relaxed states: the long-term law alone at every sample, no history.

    Notes
    -----
    Build histories with :meth:`constant_rate`, :meth:`piecewise_linear` or
    :meth:`equilibrium`; they check their input and say what is wrong. Before ``t = 0``
    the material is at rest.
    """

    time: np.ndarray
    stretch: np.ndarray
    out_time: np.ndarray
    deformation: str = "uniaxial"
    stretch2: np.ndarray | None = None
    out_direction: np.ndarray | None = None
    is_equilibrium: bool = False
    #: Small-strain tests (frequency sweeps, relaxation tests) say True; they have no
    #: stretch history for the kernels.
    is_linear: ClassVar[bool] = False

    def __post_init__(self):
        check_deformation(self.deformation)
        if (self.stretch2 is None) == self._test.second_stretch:
            raise ValueError(f"stretch2 is required for deformation={self.deformation!r}"
                             if self.stretch2 is None else
                             f"stretch2 is only for a test with a second prescribed stretch, "
                             f"not deformation={self.deformation!r}")
        if self.out_direction is None:
            d = np.ones(np.shape(self.out_time), dtype=np.int64)
        else:
            d = np.asarray(self.out_direction)
            if d.shape != np.shape(self.out_time) or not np.isin(d, (1, 2)).all():
                raise ValueError(
                    "out_direction must give 1 or 2 for each output time, "
                    f"got {self.out_direction!r}"
                )
            d = d.astype(np.int64)
            if (d == 2).any() and self._test.directions < 2:
                raise ValueError(
                    f"out_direction 2 needs a second loaded direction: {self.deformation!r} "
                    f"has none (only {' and '.join(with_two_directions())} do)"
                )
        object.__setattr__(self, "out_direction", d)

    # ------------------------------------------------------------------ builders
    @classmethod
    def constant_rate(cls, strain, strain_rate: float, *, deformation: str = "uniaxial",
                      strain2=None) -> History:
        """Constant engineering strain-rate ramp from ε = 0 (docs/theory.md §1; paper Eq. 3).

        Parameters
        ----------
        strain : array_like
            Engineering strains λ1 − 1 (γ in simple shear) at which the stress is
            wanted; all must have the sign of ``strain_rate`` (or be 0).
        strain_rate : float
            Engineering strain rate r in 1/s, non-zero (negative in compression).
        deformation : str
            The test, a registered deformation (:data:`DEFORMATIONS` and plug-ins).
        strain2 : array_like, optional
            λ2 − 1 at each strain (a test with a second prescribed stretch only,
            required there); proportional to ``strain`` (λ2 also at a constant rate).

        Examples
        --------
        >>> h = History.constant_rate([-0.1, -0.2], strain_rate=-100.0)
        >>> h.out_time
        array([0.001, 0.002])
        >>> History.constant_rate([0.5], 1.0, deformation="simple_shear").stretch   # γ
        array([0. , 0.5])
        """
        check_deformation(deformation)
        eps = _as_1d("strain", strain)
        lam2 = _path2(deformation, strain2, eps.size)
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
        test = get_deformation(deformation)
        if not test.shear and (eps <= -1.0).any():
            i = int(np.flatnonzero(eps <= -1.0)[0])
            raise ValueError(
                f"strain[{i}] = {eps[i]:g} gives a non-positive stretch 1 + strain: "
                "engineering strain must be > -1"
            )
        t_end = float(t.max())
        x0 = test.rest
        kw = dict(deformation=deformation)
        if lam2 is not None:
            kw["stretch2"] = _ramp2(lam2, t, t_end)
        if t_end == 0.0:
            # nothing happens: a degenerate but valid ramp of zero length
            if lam2 is not None:
                kw["stretch2"] = np.array([1.0])
            return cls(np.array([0.0]), np.array([x0]), t, **kw)
        return cls(np.array([0.0, t_end]), np.array([x0, x0 + r * t_end]), t, **kw)

    @classmethod
    def piecewise_linear(cls, time, strain, out_time=None, *, deformation: str = "uniaxial",
                         strain2=None) -> History:
        """History through measured ``(time, strain)`` samples, linear in between.

        Parameters
        ----------
        time : array_like, shape (k,)
            Sample times in s, strictly increasing, starting at 0.
        strain : array_like, shape (k,)
            Engineering strain λ1 − 1 (γ in simple shear) at each sample;
            ``strain[0]`` should be 0 (a non-zero start is applied as an instantaneous
            jump at t = 0).
        out_time : array_like, optional
            Times where the stress is wanted; default: the sample times.
        deformation : str
            The test, a registered deformation (:data:`DEFORMATIONS` and plug-ins).
        strain2 : array_like, shape (k,), optional
            λ2 − 1 at each sample (a test with a second prescribed stretch only, required there).

        Examples
        --------
        >>> h = History.piecewise_linear([0, 1, 2], [0, -0.2, 0])   # load, unload
        >>> h.stretch
        array([1. , 0.8, 1. ])
        """
        check_deformation(deformation)
        t = _as_1d("time", time)
        eps = _as_1d("strain", strain)
        if t.shape != eps.shape:
            raise ValueError(
                f"time and strain must have the same length, got {t.size} and {eps.size}"
            )
        lam2 = _path2(deformation, strain2, eps.size)
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
        lam = _loading(deformation, eps)
        out = t.copy() if out_time is None else _as_1d("out_time", out_time)
        if (out < 0).any() or (out > t[-1]).any():
            raise ValueError(
                f"out_time must lie within the history [0, {t[-1]:g}] s"
            )
        return cls(t, lam, out, deformation=deformation, stretch2=lam2)

    @classmethod
    def equilibrium(cls, strain, *, deformation: str = "uniaxial", strain2=None) -> History:
        """Fully relaxed states: the long-term law alone at each sample (any order).

        Parameters
        ----------
        strain : array_like, shape (n,)
            Engineering strain λ1 − 1 (γ in simple shear) of each sample.
        deformation : str
            The test, a registered deformation (:data:`DEFORMATIONS` and plug-ins).
        strain2 : array_like, shape (n,), optional
            λ2 − 1 of each sample (a test with a second prescribed stretch only, required there).

        Examples
        --------
        >>> h = History.equilibrium([0.5, 0.1, 0.3], deformation="planar")
        >>> h.is_equilibrium, h.out_strain
        (True, array([0.5, 0.1, 0.3]))
        """
        check_deformation(deformation)
        eps = _as_1d("strain", strain)
        lam2 = _path2(deformation, strain2, eps.size)
        n = np.arange(eps.size, dtype=np.float64)
        return cls(n, _loading(deformation, eps), n.copy(), deformation=deformation,
                   stretch2=lam2, is_equilibrium=True)

    def with_outputs(self, out_time, out_direction=None) -> History:
        """The same stretch path, with stress reported at other times (and directions).

        For an equilibrium history, ``out_time`` numbers the samples (0, 1, ...).
        """
        out = _as_1d("out_time", out_time)
        if (out < 0).any() or (out > self.time[-1]).any():
            raise ValueError(f"out_time must lie within the history [0, {self.time[-1]:g}] s")
        if self.is_equilibrium and not np.array_equal(out, np.round(out)):
            raise ValueError("out_time of an equilibrium history numbers its samples: give "
                             "whole numbers 0, 1, ...")
        return History(self.time, self.stretch, out, self.deformation, self.stretch2,
                       out_direction, self.is_equilibrium)

    # ----------------------------------------------------------------- queries
    @property
    def duration(self) -> float:
        """Length of the history in s (0 for an equilibrium history)."""
        return 0.0 if self.is_equilibrium else float(self.time[-1])

    def stretch_at(self, t) -> np.ndarray:
        """λ1(t) (γ(t) in simple shear), linear between breakpoints."""
        return np.interp(t, self.time, self.stretch)

    def stretch2_at(self, t) -> np.ndarray | None:
        """λ2(t) of a biaxial history, linear between breakpoints; None otherwise."""
        return None if self.stretch2 is None else np.interp(t, self.time, self.stretch2)

    @property
    def out_stretch(self) -> np.ndarray:
        """λ1 (γ in simple shear) at the output times."""
        return self.stretch_at(self.out_time)

    @property
    def out_strain(self) -> np.ndarray:
        """Engineering strain λ1 − 1 (γ in simple shear) at the output times."""
        return self._test.strain(self.out_stretch)

    @property
    def out_loaded_stretch(self) -> np.ndarray:
        """Stretch of each output's loaded direction (λ1 or λ2; 1 in simple shear).

        The nominal stress is the true stress divided by it.
        """
        test = self._test
        x1, x2 = self.out_stretch, self.stretch2_at(self.out_time)
        second = test.loaded_stretch(x1, x2, 2) if test.directions == 2 else 0.0
        return np.where(self.out_direction == 2, second, test.loaded_stretch(x1, x2, 1))

    @property
    def _test(self):
        """The record of the deformation (:class:`vhfit.modes.Deformation`)."""
        return get_deformation(self.deformation)

    # ------------------------------------------------------------ internal grid
    def _piece_steps(self, k: int, dlog: float) -> np.ndarray:
        """Inner and end node times of piece k (a hold: its end alone), as the test's
        record lays them out (:meth:`vhfit.modes.Deformation.steps`)."""
        s2 = None if self.stretch2 is None else self.stretch2[k:k + 2]
        return self._test.steps(self.time[k], self.time[k + 1], self.stretch[k:k + 2], s2,
                                dlog)

    def grid(self, dlog: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Integration grid: node times, node stretches, and output node indices.

        Each linear piece of the path is cut into steps over which ln λ of every
        principal stretch changes by at most ``dlog`` (in simple shear: γ by at most
        ``dlog``); the output times are inserted as nodes (a node closer than a
        quarter step to an output time is moved onto it), so the stress at an output
        time is exact for the interpolant rather than interpolated between nodes.
        A hold (constant λ) needs no inner nodes: its decay is integrated exactly.
        """
        if self.is_equilibrium:
            raise ValueError("an equilibrium history has no time grid: it is the long-term "
                             "law at its samples")
        tb = self.time
        nodes = [tb[:1]]
        for k in range(tb.size - 1):
            tt = self._piece_steps(k, dlog)
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


def _ramp2(lam2: np.ndarray, t: np.ndarray, t_end: float) -> np.ndarray:
    """λ2 breakpoints of a constant-rate biaxial ramp; λ2 − 1 must be proportional to t."""
    e2 = lam2 - 1.0
    if t_end == 0.0:
        r2 = 0.0
    else:
        r2 = float(e2[np.argmax(t)] / t_end)
    if not np.allclose(e2, r2 * t, rtol=1e-9, atol=1e-12 * max(1.0, float(np.abs(e2).max()))):
        raise ValueError(
            "strain2 of a constant-rate biaxial ramp must be proportional to strain (λ2 at a "
            "constant rate too): give the history with time instead"
        )
    return np.array([1.0, 1.0 + r2 * t_end])
