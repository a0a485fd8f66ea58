"""Test data: measured stress–strain curves, their readers, and the objective points.

A :class:`Curve` holds one uniaxial test as measured — strain, stress, and either a
nominal constant strain rate or the time of every sample — plus the *objective points*
where the model is compared with it (paper: 10 points a curve, evenly spaced in strain).
It knows the stretch history the model must follow (:attr:`Curve.history`) and the
target stresses there (:attr:`Curve.target_stress`).

Readers turn files and arrays into curves: :func:`read_csv` (one file per curve, or one
long file with a rate column), :func:`curves_from_arrays` and :meth:`Curve.from_array`
(numpy arrays, anything with ``__array__``, DataFrame-like objects with ``.to_numpy()``
and ``.columns``, or a mapping of column name to values).

Conventions (SPEC §1, §7): compression is negative (strain, strain rate and stress);
units MPa, s, 1/s; engineering strain ε = λ − 1; true stress = engineering stress × λ.

Every problem with the data raises :class:`DataError` (a ``ValueError``) whose one-line
message names the file, the curve, the row or column, and the fix. What is *inferred*
rather than declared (e.g. compression given as positive numbers) is done with a
:class:`DataWarning` that says exactly what was assumed.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from functools import cached_property
from typing import Any

import numpy as np

from vhfit._csv import _curves_from_table, _read_table, _table_from_data
from vhfit._paths import HOLD_MIN_DURATION as HOLD_MIN_DURATION
from vhfit._paths import HOLD_RTOL as HOLD_RTOL
from vhfit._paths import LEG_RTOL as LEG_RTOL
from vhfit._paths import (
    _arclength,
    _bin_means,
    _estimate_rate,
    _place,
    _segment_bounds,
    _simplify_idx,
)
from vhfit._where import DataError, DataWarning, _norm_measure, _norm_mode, _Subset, _warn, _Where
from vhfit.history import History

__all__ = [
    "DEFAULT_N_POINTS",
    "Curve",
    "DataError",
    "DataWarning",
    "curves_from_arrays",
    "engineering_to_true",
    "read_csv",
    "true_to_engineering",
]

#: Objective points per curve when none are asked for (the paper's choice, §2.2).
DEFAULT_N_POINTS = 10
#: Strains of the "wrong" sign smaller than this fraction of max |strain| are noise (a
#: load-cell or extensometer offset), not a change of loading mode.
SIGN_RTOL = 0.01
#: A measured strain path is simplified (breakpoints dropped) only where that moves it by
#: less than this fraction of its strain range; turning points are always kept.
PATH_RTOL = 1e-4
#: ... unless that leaves more than this many breakpoints (a noisy strain signal keeps
#: nearly every sample, its noise then acts as strain-rate spikes, and the model's work
#: grows with them): the history then follows an average over this many bins of
#: consecutive samples, simplified likewise, with a DataWarning saying how closely.
MAX_BREAKPOINTS = 2000

_BYS = ("strain", "time", "arclength", "segments")


# ============================================================== stress measures
def engineering_to_true(stress: Any, strain: Any) -> np.ndarray:
    """True (Cauchy) stress from engineering stress: ``σ = σ_eng · λ``, ``λ = 1 + ε``.

    Examples
    --------
    >>> engineering_to_true([-1.0, -2.0], [-0.1, -0.5])
    array([-0.9, -1. ])
    """
    return np.asarray(stress, dtype=np.float64) * (1.0 + np.asarray(strain, dtype=np.float64))


def true_to_engineering(stress: Any, strain: Any) -> np.ndarray:
    """Engineering (nominal) stress from true stress: ``σ_eng = σ / λ``.

    Examples
    --------
    >>> true_to_engineering([-0.9, -1.0], [-0.1, -0.5])
    array([-1., -2.])
    """
    return np.asarray(stress, dtype=np.float64) / (1.0 + np.asarray(strain, dtype=np.float64))


# ================================================================= the curve
class Curve:
    """One uniaxial test: measured strain and stress, its loading history, objective points.

    Parameters
    ----------
    strain : array_like
        Engineering strain ε = λ − 1 of each sample (negative in compression).
    stress : array_like
        Stress of each sample in MPa, in the measure given by ``measure``.
    strain_rate : float, optional
        Engineering strain rate in 1/s (negative in compression). Without ``time`` the
        test is a constant-rate ramp from ε = 0 (paper Eq. 3), and the strain must be
        monotonic in the rate's direction; it need not start at 0. With ``time`` it is
        only the nominal rate (used e.g. for the τ bounds of Eq. 22).
    time : array_like, optional
        Time of each sample in s, for measured histories (loading–unloading, ramp–hold,
        drifting rates). The history is piecewise linear through the samples; the
        material is at rest at ε = 0 at t = 0, so a first sample at t > 0 is reached by
        a linear ramp from (0, 0). Samples at the same time and strain are merged (their
        stresses averaged).
    measure : {"engineering", "true"}
        Stress measure of ``stress`` ("nominal" and "cauchy" are accepted as aliases).
    mode : {"compression", "tension", "mixed"}, optional
        Declared loading mode. A declared mode that the signs of strain or stress
        contradict is an error. Undeclared, the mode is inferred from the strain's sign
        (strains of the other sign below ``SIGN_RTOL`` of the largest count as noise).
    name : str, optional
        Name used in messages, plots and reports.
    weight : float, default 1
        Weight of the curve in the objective (it multiplies each point's squared term).
    n_points : int or None, default DEFAULT_N_POINTS
        Number of objective points (per segment with ``by="segments"``); ``None`` uses
        the measured samples themselves.
    by : {"strain", "time", "arclength", "segments"}, optional
        How the objective points are spaced: evenly in strain (the default for a
        strictly monotonic strain, as in the paper); in time; in arc length along the
        (strain, stress) curve normalised by its ranges; or ``"segments"`` (the default
        otherwise): ``n_points`` on each segment of the history — a loading leg between
        reversals of the strain by more than ``LEG_RTOL`` of its range, or a hold (the
        strain within ``HOLD_RTOL`` of its range for at least ``HOLD_MIN_DURATION`` of the
        test) — evenly in arc length within the segment, each segment's end (a turning
        point, the start or end of a hold) included. A loading–unloading test has two
        segments, a ramp–hold test two (ramp, relaxation). Curves that unload or hold
        are never resampled by strain.
    compression_positive : bool, default False
        The data use the opposite sign convention (compression positive): strain and
        stress are negated, and the rate is taken with the sign of the resulting mode.
    source : str, optional
        Where the data came from (a file name), for messages.
    rows : sequence, optional
        A label for each sample used in messages, e.g. ``"line 17"`` for a file; default
        ``"row k"`` with the 0-based index.
    metadata : mapping, optional
        Free-form information kept with the curve.

    Raises
    ------
    DataError
        Fewer than 2 samples, NaN/inf, no rate and no time, strain going back and forth
        at constant rate, time running backwards, conflicting duplicate samples, signs
        contradicting the declared mode, stretch ≤ 0.

    Notes
    -----
    *Objective points.* With ``n`` points on a curve whose data start from rest (ε ≈ 0),
    the points sit at fractions ``1/n, 2/n, …, 1`` of the compared range: the rest point
    itself, where model and data are both 0, is not spent as a point (Eq. 20 divides by
    the curve's mean stress, not pointwise, so zero-stress points would be allowed, but
    they carry no information). Otherwise the ``n`` points span the range including
    both ends. Target stresses are linear interpolations of the measured ones. See
    :meth:`resample`, :meth:`trim`, :meth:`with_point_weights`.

    *History.* For a constant-rate curve, :attr:`history` is the ramp ``λ = 1 + r t``
    up to the last objective point. For a time curve it runs through the measured
    (time, strain) samples, with breakpoints dropped only where the path moves by less
    than ``PATH_RTOL`` of the strain range (turning points are kept), so 10⁶ samples
    cost the model little; a noisy signal that would keep more than
    ``MAX_BREAKPOINTS`` is averaged over that many bins first, with a
    :class:`DataWarning`.
    Trimming never shortens the history: the material remembers
    what happened before the compared window.

    Examples
    --------
    >>> import numpy as np
    >>> eps = np.linspace(0.0, -0.5, 51)
    >>> c = Curve(strain=eps, stress=10 * eps, strain_rate=-100.0, name="fast")
    >>> c
    Curve('fast': compression, engineering stress, rate -100/s, 51 samples, 10 points by strain)
    >>> c.target_strain[:4]
    array([-0.05, -0.1 , -0.15, -0.2 ])
    >>> c.history.out_time[:3]
    array([0.0005, 0.001 , 0.0015])
    >>> c.resample(4).target_stress
    array([-1.25, -2.5 , -3.75, -5.  ])

    A loading–unloading test with its time column is resampled along the curve:

    >>> t = np.linspace(0.0, 2.0, 201)
    >>> lu = Curve(strain=0.5 - np.abs(0.5 - 0.5 * t), stress=np.sin(t), time=t)
    >>> lu.mode, lu.by, lu.n_segments, lu.n_points, lu.strain_rate
    ('tension', 'segments', 2, 20, 0.5)
    >>> float(lu.target_strain[9])           # the turning point is an objective point
    0.5
    """

    def __init__(
        self,
        strain: Any,
        stress: Any,
        strain_rate: float | None = None,
        time: Any = None,
        *,
        measure: str = "engineering",
        mode: str | None = None,
        name: str | None = None,
        weight: float = 1.0,
        n_points: int | None = DEFAULT_N_POINTS,
        by: str | None = None,
        compression_positive: bool = False,
        source: str | os.PathLike[str] | None = None,
        rows: Sequence[Any] | None = None,
        metadata: Mapping[str, Any] | None = None,
    ) -> None:
        if name is None:  # name an unnamed curve by its rate, as reports list curves
            try:
                r = float(strain_rate)  # type: ignore[arg-type]
                name = f"{r:g} 1/s" if np.isfinite(r) else "curve"
            except (TypeError, ValueError):
                name = "curve"
        name = str(name)
        src = None if source is None else str(source)
        where = _Where(name, src, rows)
        eps = where.array("strain", strain)
        n = eps.size
        sig = where.array("stress", stress, n)
        t = None if time is None else where.array("time", time, n)
        if rows is not None and len(rows) != n:
            raise ValueError(f"rows has {len(rows)} labels for {n} samples")
        if n < 2:
            raise DataError(
                f"{where()}: has {n} sample{'s' if n != 1 else ''}: a curve needs at least 2 "
                "(check the file is complete and the rows were not filtered away)"
            )
        measure = _norm_measure(measure, where)
        try:
            weight = float(weight)
        except (TypeError, ValueError):
            raise DataError(f"{where()}: weight={weight!r} is not a number: give a number >= 0"
                            ) from None
        if not (np.isfinite(weight) and weight >= 0):
            raise DataError(f"{where()}: weight={weight!r}: give a finite weight >= 0")
        rate = None if strain_rate is None else _parse_rate_value(strain_rate, where)
        if rate is None and t is None:
            raise DataError(
                f"{where()}: no strain rate and no time column: give strain_rate in 1/s "
                "(negative in compression) or the time of each sample"
            )
        n_points, by = _check_points_args(n_points, by, where)
        keep = np.arange(n)
        if not np.any(eps):
            raise DataError(
                f"{where()}: strain is 0 at every sample: nothing was deformed; check that "
                "the strain (or stretch) column is the right one"
            )

        # ---- duplicates and order
        if t is not None:
            eps, sig, t, keep = _clean_time_series(eps, sig, t, keep, where)
        else:
            eps, sig, keep = _clean_rate_series(eps, sig, keep, where)
        if eps.size < 2:
            raise DataError(
                f"{where()}: only one distinct sample remains after merging duplicates: a "
                "curve needs at least 2"
            )

        # ---- signs and mode
        scale = float(np.abs(eps).max())
        if scale == 0.0:
            raise DataError(
                f"{where()}: strain is 0 at every sample: nothing was deformed; check that "
                "the strain (or stretch) column is the right one"
            )
        tol = SIGN_RTOL * scale
        declared = mode is not None or compression_positive
        if compression_positive:
            eps, sig = -eps, -sig
        cls = _sign_class(eps, tol)
        if mode is not None:
            mode = _norm_mode(mode, where)
            if mode != "mixed" and cls != mode:
                bad = eps > tol if mode == "compression" else eps < -tol
                k = int(np.flatnonzero(bad)[0])
                word = "positive" if mode == "compression" else "negative"
                raise DataError(
                    f"{where(keep[k])}: strain = {eps[k]:g} is {word} but the curve is "
                    f"declared mode={mode!r} (compression is negative): pass "
                    "compression_positive=True if compression is given as positive numbers, "
                    "or correct the mode"
                )
        else:
            mode = cls
            if rate is not None and cls == "tension" and rate < 0:
                eps, sig, mode = -eps, -sig, "compression"
                _warn(
                    f"{where()}: strain is >= 0 but strain_rate = {rate:g} < 0: took this as a "
                    "compression test given as positive magnitudes and negated strain and "
                    "stress (say compression_positive=True to silence this, or give a "
                    "positive rate for a tension test)"
                )
        sgn = {"compression": -1.0, "tension": 1.0}.get(mode)
        if rate is not None and sgn is not None and np.sign(rate) != sgn:
            if not compression_positive:
                _warn(
                    f"{where()}: strain_rate = {rate:g} has the sign of "
                    f"{'tension' if rate > 0 else 'compression'} but the strain is in {mode}: "
                    f"took strain_rate = {-rate:g} (compression is negative)"
                )
            rate = -rate
        if t is None and mode == "mixed":
            major = np.sign(eps[np.argmax(np.abs(eps))])
            k = int(np.flatnonzero(eps * major < -tol)[0])
            raise DataError(
                f"{where(keep[k])}: strain changes sign (strain = {eps[k]:g} here) but a "
                "constant-rate ramp from strain 0 only reaches one sign: give the time "
                "column, or split the curve at strain 0"
            )
        if sgn is not None:
            k = int(np.argmax(np.abs(sig)))
            if sig[k] * sgn < 0:
                if declared:
                    raise DataError(
                        f"{where(keep[k])}: stress = {sig[k]:g} (the largest in magnitude) has "
                        f"the wrong sign for a {mode} curve: negate the stress column "
                        "(compression is negative) or correct the mode"
                    )
                sig = -sig
                _warn(
                    f"{where()}: the stress has the opposite sign to the strain (largest "
                    f"|stress| {-sig[k]:g} at {where.label(keep[k])}): took it as {mode} stress "
                    "given as magnitudes and negated it"
                )

        # ---- kinematic checks
        if t is None:
            d = np.diff(eps) * np.sign(rate)
            if (d < 0).any():
                k = int(np.flatnonzero(d < 0)[0])
                raise DataError(
                    f"{where(keep[k + 1])}: strain goes back from {eps[k]:g} to {eps[k + 1]:g}: "
                    "a constant-rate curve must be monotonic; if this test loads and unloads "
                    "give its time column, if the rows are out of order sort them "
                    "(read_csv(..., sort=True))"
                )
        if (eps <= -1.0).any():
            k = int(np.flatnonzero(eps <= -1.0)[0])
            raise DataError(
                f"{where(keep[k])}: strain = {eps[k]:g} means a stretch 1 + strain <= 0: "
                "give engineering strain (> -1), or a stretch column"
            )
        rate_estimated = rate is None
        if rate is None:
            rate = _estimate_rate(t, eps, sgn, tol)
            if not (np.isfinite(rate) and rate != 0.0):
                raise DataError(
                    f"{where()}: the strain never changes with time: no loading to fit"
                )

        self._strain = _frozen(eps)
        self._stress = _frozen(sig)
        self._time = None if t is None else _frozen(t)
        self._rate = float(rate)
        self._rate_estimated = rate_estimated
        self._measure = measure
        self._mode = mode
        self._name = name
        self._weight = weight
        self._source = src
        self._where = _Where(name, src, None if rows is None else _Subset(rows, keep))
        self._metadata = dict(metadata or {})
        self._tol = tol
        d = np.diff(eps)
        self._monotone = bool((d > 0).all() or (d < 0).all())
        self._bounds = (np.array([0, eps.size - 1]) if t is None
                        else _segment_bounds(t, eps, MAX_BREAKPOINTS))
        self._n_req = n_points
        self._by_req = by
        self._window = None  # boolean mask over samples, or None
        self._window_desc: tuple[str, ...] = ()
        self._point_weights: Any = None
        self._set_points()

    # ------------------------------------------------------------- building
    @classmethod
    def from_array(cls, data: Any, **kwargs: Any) -> Curve:
        """One curve from an array-like table; keywords as :func:`curves_from_arrays`.

        Examples
        --------
        >>> import numpy as np
        >>> eps = np.linspace(0, 0.2, 5)
        >>> c = Curve.from_array({"strain": eps, "stress_kPa": 1e3 * eps}, rate=0.01)
        >>> c.target_stress[-1].item()
        0.2
        """
        curves = curves_from_arrays(data, **kwargs)
        if len(curves) != 1:
            raise DataError(
                f"{curves[0].source or 'data'}: holds {len(curves)} curves "
                f"({', '.join(c.name for c in curves[:4])}{', ...' if len(curves) > 4 else ''})"
                ": use curves_from_arrays(...) to get them all"
            )
        return curves[0]

    def _derive(self, **attrs: Any) -> Curve:
        new = object.__new__(Curve)
        new.__dict__.update({k: v for k, v in self.__dict__.items() if k != "history"})
        new.__dict__.update(attrs)
        new._set_points()
        return new

    # ------------------------------------------------------- measured data
    @property
    def strain(self) -> np.ndarray:
        """Measured engineering strain of each sample (after merging duplicates)."""
        return self._strain

    @property
    def stress(self) -> np.ndarray:
        """Measured stress of each sample in MPa, in :attr:`measure`."""
        return self._stress

    @property
    def time(self) -> np.ndarray | None:
        """Measured time of each sample in s, or ``None`` for a constant-rate curve."""
        return self._time

    @property
    def stretch(self) -> np.ndarray:
        """λ = 1 + ε of each sample."""
        return 1.0 + self._strain

    @property
    def strain_rate(self) -> float:
        """Nominal engineering strain rate in 1/s (negative in compression).

        As given; for a time curve without a given rate it is estimated as the median of
        |dε/dt| over the samples, each step weighted by the strain it applies (so holds
        and sensor noise do not count), with the sign of the loading mode (of the first
        loading for a mixed curve). See :attr:`strain_rate_estimated`.
        """
        return self._rate

    @property
    def strain_rate_estimated(self) -> bool:
        """True if :attr:`strain_rate` was estimated from the time column."""
        return self._rate_estimated

    @property
    def is_constant_rate(self) -> bool:
        """True if the history is a constant-rate ramp (no time column)."""
        return self._time is None

    @property
    def measure(self) -> str:
        """Stress measure: ``"engineering"`` or ``"true"``."""
        return self._measure

    @property
    def mode(self) -> str:
        """Loading mode: ``"compression"``, ``"tension"`` or ``"mixed"``."""
        return self._mode

    @property
    def name(self) -> str:
        """Name of the curve."""
        return self._name

    @property
    def weight(self) -> float:
        """Weight of the curve in the objective."""
        return self._weight

    @property
    def source(self) -> str | None:
        """File (or other source) the curve was read from."""
        return self._source

    @property
    def metadata(self) -> dict[str, Any]:
        """Free-form information (e.g. a file's ``# key: value`` lines)."""
        return self._metadata

    # ------------------------------------------------------- objective points
    @property
    def n_points(self) -> int:
        """Number of objective points."""
        return int(self._t_obj.size)

    @property
    def n_segments(self) -> int:
        """Number of segments of the history: loading legs between strain reversals, and holds.

        A constant-rate ramp is one segment; see ``by="segments"`` in :class:`Curve`.
        """
        return int(self._bounds.size - 1)

    @property
    def by(self) -> str:
        """How the objective points are spaced: ``"strain"``, ``"time"``, ``"arclength"``,
        ``"segments"``, or ``"samples"`` (the measured samples themselves)."""
        return self._by

    @property
    def target_strain(self) -> np.ndarray:
        """Strain at the objective points."""
        return self._e_obj

    @property
    def target_time(self) -> np.ndarray:
        """Time of the objective points in the history (``strain / rate`` at constant rate)."""
        return self._t_obj

    @property
    def target_stress(self) -> np.ndarray:
        """Measured stress at the objective points, in :attr:`measure` (MPa)."""
        return self._s_obj

    @property
    def target_weights(self) -> np.ndarray:
        """Weight of each objective point (all 1 unless set by :meth:`with_point_weights`)."""
        return self._w_obj

    @cached_property
    def history(self) -> History:
        """The stretch history to simulate, with ``out_time`` at the objective points."""
        if self._time is None:
            return History.constant_rate(self._e_obj, self._rate)
        t, e = _from_rest(self._time, self._strain)
        scale = max(float(np.ptp(e)), float(np.abs(e).max()))
        tol = PATH_RTOL * scale
        idx = _simplify_idx(t, e, tol, limit=MAX_BREAKPOINTS)
        if idx is None:
            return self._smoothed_history(tol, scale)
        return History.piecewise_linear(t[idx], e[idx], out_time=self._t_obj)

    def _smoothed_history(self, tol: float, scale: float) -> History:
        # Following every noisy sample would keep ~all of them as breakpoints and turn
        # the noise into strain-rate spikes of noise/Δt; follow bin means instead.
        t, e = _from_rest(*_bin_means(self._time, self._strain, MAX_BREAKPOINTS))
        idx = None
        while idx is None:
            idx = _simplify_idx(t, e, tol, limit=MAX_BREAKPOINTS)
            tol *= 2.0
        t, e = t[idx], e[idx]
        dev = np.interp(self._time, t, e) - self._strain
        rms = float(np.sqrt(np.mean(dev * dev)))
        _warn(
            f"{self._where()}: the measured strain path is noisy or too detailed to follow "
            f"sample by sample (more than {MAX_BREAKPOINTS} breakpoints within "
            f"{PATH_RTOL:g} of its range, and noise would become strain-rate spikes): the "
            f"simulated history follows a {MAX_BREAKPOINTS}-bin average of it with "
            f"{idx.size} breakpoints (RMS deviation from the samples {rms:.3g} strain, "
            f"{rms / scale:.2g} of the range); smooth the strain signal yourself, or raise "
            f"vhfit.data.MAX_BREAKPOINTS, to choose differently"
        )
        return History.piecewise_linear(t, e, out_time=self._t_obj)

    def _sample_time(self) -> np.ndarray:
        return self._time if self._time is not None else self._strain / self._rate

    def _set_points(self) -> None:
        where = self._where
        eps, sig, ts = self._strain, self._stress, self._sample_time()
        mask = np.ones(eps.size, dtype=bool) if self._window is None else self._window.copy()
        if self._time is None:
            mask &= ts >= 0.0  # noise of the wrong sign near strain 0
        if mask.sum() < 1 or (self._n_req is not None and mask.sum() < 2):
            raise DataError(
                f"{where()}: the compared window {' '.join(self._window_desc) or ''} keeps "
                f"{int(mask.sum())} sample(s): widen it (strain runs "
                f"{eps.min():g} to {eps.max():g}, time 0 to {ts.max():g} s)"
            )
        by = self._by_req
        if by is None:
            by = "strain" if self._monotone else "segments"
        if by == "strain" and not self._monotone:
            raise DataError(
                f"{where()}: cannot resample by strain: the strain is not monotonic (it "
                "unloads or holds): use by='segments', by='arclength' or by='time'"
            )
        if self._n_req is None:
            idx = np.flatnonzero(mask).astype(np.float64)
            self._by = "samples"
        else:
            if by == "strain":
                c = eps * np.sign(eps[-1] - eps[0])
            elif by == "time":
                c = ts
            else:
                c = _arclength(eps, sig)
            if by == "segments":
                parts = []
                k = np.arange(eps.size)
                for a, b in zip(self._bounds[:-1], self._bounds[1:]):
                    part = _place(c, mask & (k >= a) & (k <= b), self._n_req, True)
                    if part is not None:
                        parts.append(part)
                idx = np.concatenate(parts) if parts else None
            else:
                i0 = int(np.flatnonzero(mask)[0])
                rest = abs(eps[i0]) <= self._tol
                idx = _place(c, mask, self._n_req, rest)
            if idx is None:
                raise DataError(
                    f"{where()}: the compared window {' '.join(self._window_desc)} has no "
                    f"extent in {by}: widen it"
                )
            self._by = by
        k = np.arange(eps.size, dtype=np.float64)
        e_obj = np.interp(idx, k, eps)
        s_obj = np.interp(idx, k, sig)
        t_obj = e_obj / self._rate if self._time is None else np.interp(idx, k, ts)
        self._e_obj = _frozen(e_obj)
        self._s_obj = _frozen(s_obj)
        self._t_obj = _frozen(t_obj)
        w = self._point_weights
        if w is None:
            w_obj = np.ones(e_obj.size)
        elif callable(w):
            w_obj = np.broadcast_to(
                np.asarray(w(e_obj, t_obj, s_obj), dtype=np.float64), e_obj.shape
            ).copy()
        else:
            w_obj = np.asarray(w, dtype=np.float64)
            if w_obj.shape != e_obj.shape:
                w_obj = np.ones(e_obj.size)  # stale weights of other points: reset
                self._point_weights = None
        if not (np.isfinite(w_obj).all() and (w_obj >= 0).all() and w_obj.sum() > 0):
            raise DataError(
                f"{where()}: point weights must be finite, >= 0 and not all 0"
            )
        self._w_obj = _frozen(w_obj)

    # ------------------------------------------------------------- variants
    def resample(self, n_points: int | None = DEFAULT_N_POINTS, by: str | None = None) -> Curve:
        """The same curve with ``n_points`` objective points spaced ``by`` (see :class:`Curve`).

        ``n_points=None`` compares at the measured samples themselves. ``by=None`` picks
        ``"strain"`` for a strictly monotonic strain and ``"segments"`` otherwise.

        Examples
        --------
        >>> c = Curve([0.0, 0.1, 0.2], [0.0, 1.0, 2.0], strain_rate=0.1)
        >>> c.resample(2).target_strain, c.resample(None).target_strain
        (array([0.1, 0.2]), array([0. , 0.1, 0.2]))
        """
        n_points, by = _check_points_args(n_points, by, self._where)
        return self._derive(_n_req=n_points, _by_req=by)

    def trim(
        self,
        strain: tuple[float | None, float | None] | None = None,
        time: tuple[float | None, float | None] | None = None,
    ) -> Curve:
        """Compare the model with the data only inside a strain and/or time window.

        Bounds are signed (compression strains are negative) and inclusive; ``None``
        leaves a side open. Windows of successive calls combine. The objective points are
        re-spaced inside the window; the history still runs through all the data (what the
        material went through before the window matters).

        Examples
        --------
        >>> c = Curve([0.0, -0.1, -0.2, -0.3, -0.4], [0.0, -1.0, -2.0, -3.0, -4.0],
        ...           strain_rate=-1.0, n_points=3)
        >>> c.trim(strain=(-0.3, None)).target_strain
        array([-0.1, -0.2, -0.3])
        """
        ts = self._sample_time()
        mask = np.ones(self._strain.size, dtype=bool) if self._window is None else self._window
        desc = list(self._window_desc)
        for what, win, vals in (("strain", strain, self._strain), ("time", time, ts)):
            if win is None:
                continue
            try:
                lo, hi = win
            except (TypeError, ValueError):
                raise DataError(
                    f"{self._where()}: trim({what}={win!r}): give a (low, high) pair"
                ) from None
            lo = -np.inf if lo is None else float(lo)
            hi = np.inf if hi is None else float(hi)
            if not lo < hi:
                raise DataError(f"{self._where()}: trim({what}=({lo:g}, {hi:g})): low >= high")
            mask = mask & (vals >= lo) & (vals <= hi)
            desc.append(f"{what}=({lo:g}, {hi:g})")
        return self._derive(_window=mask, _window_desc=tuple(desc))

    def with_point_weights(self, weights: Any) -> Curve:
        """The same curve with a weight on each objective point.

        Parameters
        ----------
        weights : array_like or callable
            One weight per objective point, or ``f(strain, time, stress) -> weights``
            evaluated at the objective points (it is re-applied after :meth:`resample`
            or :meth:`trim`; an array is dropped when the points change).

        Examples
        --------
        >>> c = Curve([0.0, 0.1, 0.2], [0.0, 1.0, 2.0], strain_rate=0.1, n_points=4)
        >>> c.with_point_weights(lambda e, t, s: (e > 0.1) + 1.0).target_weights
        array([1., 1., 2., 2.])
        """
        if not callable(weights):
            w = np.asarray(weights, dtype=np.float64)
            if w.shape != (self.n_points,):
                raise DataError(
                    f"{self._where()}: {w.size} point weights for {self.n_points} objective "
                    "points: give one per point, or a function of (strain, time, stress)"
                )
            weights = w
        return self._derive(_point_weights=weights)

    def with_measure(self, measure: str) -> Curve:
        """The same curve with its stress converted to ``measure`` (true = engineering × λ).

        Examples
        --------
        >>> c = Curve([0.0, -0.5], [0.0, -2.0], strain_rate=-1.0, n_points=None)
        >>> c.with_measure("true").stress
        array([ 0., -1.])
        """
        m = _norm_measure(measure, self._where)
        if m == self._measure:
            return self
        conv = engineering_to_true if m == "true" else true_to_engineering
        return self._derive(_stress=_frozen(conv(self._stress, self._strain)), _measure=m)

    def replace(self, *, name: str | None = None, weight: float | None = None) -> Curve:
        """The same curve with another name and/or weight."""
        attrs: dict[str, Any] = {}
        if name is not None:
            attrs["_name"] = str(name)
            attrs["_where"] = _Where(str(name), self._source, self._where.rows)
        if weight is not None:
            w = float(weight)
            if not (np.isfinite(w) and w >= 0):
                raise DataError(f"{self._where()}: weight={weight!r}: give a finite weight >= 0")
            attrs["_weight"] = w
        return self._derive(**attrs)

    def __repr__(self) -> str:
        rate = f"rate {self._rate:g}/s" + (" (estimated)" if self._rate_estimated else "")
        hist = "constant rate" if self._time is None else "time history"
        win = f", window {' '.join(self._window_desc)}" if self._window_desc else ""
        extra = "" if self._time is None else f", {hist}"
        return (
            f"Curve({self._name!r}: {self._mode}, {self._measure} stress, {rate}{extra}, "
            f"{self._strain.size} samples, {self.n_points} points by {self._by}{win})"
        )


def _from_rest(t: np.ndarray, e: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The path (t, e), started from rest (0, 0) when its first sample comes later."""
    if t[0] > 0.0:
        return np.concatenate([[0.0], t]), np.concatenate([[0.0], e])
    return t, e


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=np.float64, copy=True)
    a.flags.writeable = False
    return a


def _check_points_args(n_points: Any, by: Any, where: _Where) -> tuple[int | None, str | None]:
    if n_points is not None:
        try:
            ok = int(n_points) == n_points and int(n_points) >= 1
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise DataError(
                f"{where()}: n_points={n_points!r}: give a whole number >= 1, or None for the "
                "measured samples"
            )
        n_points = int(n_points)
    if by is not None and by not in _BYS:
        raise DataError(f"{where()}: by={by!r}: use one of {', '.join(map(repr, _BYS))}")
    return n_points, by


def _parse_rate_value(value: Any, where: _Where) -> float:
    try:
        r = float(value)
    except (TypeError, ValueError):
        raise DataError(
            f"{where()}: strain_rate={value!r} is not a number: give it in 1/s"
        ) from None
    if not np.isfinite(r) or r == 0.0:
        raise DataError(
            f"{where()}: strain_rate={value!r}: give a finite, non-zero rate in 1/s "
            "(negative in compression)"
        )
    return r


def _sign_class(eps: np.ndarray, tol: float) -> str:
    pos = bool(eps.min() >= -tol)
    neg = bool(eps.max() <= tol)
    if pos and not neg:
        return "tension"
    if neg and not pos:
        return "compression"
    return "mixed"


def _clean_time_series(eps, sig, t, keep, where):
    if t[0] < 0:
        raise DataError(
            f"{where(keep[0])}: time starts at {t[0]:g} s: the test starts at t = 0; shift "
            "the time column"
        )
    dt = np.diff(t)
    if (dt < 0).any():
        k = int(np.flatnonzero(dt < 0)[0])
        de = np.diff(eps)
        if (de > 0).all() or (de < 0).all():
            fix = ("the strain keeps going the same way, so the time column looks wrong: fix "
                   "it, or ignore it (read_csv(..., columns={'time': None}, rate=...))")
        else:
            fix = ("sort the rows by time (read_csv(..., sort=True)); if the file holds "
                   "several tests, give each its own curve (a 'test' column)")
        raise DataError(
            f"{where(keep[k + 1])}: time goes back from {t[k]:g} to {t[k + 1]:g} s: {fix}"
        )
    dup = dt == 0
    if dup.any():
        bad = dup & (np.diff(eps) != 0)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise DataError(
                f"{where(keep[k + 1])}: two samples at the same time ({t[k]:g} s) have "
                f"different strains ({eps[k]:g} and {eps[k + 1]:g}): fix the time column (more "
                "digits) or drop one of them"
            )
        grp = np.concatenate([[0], np.cumsum(~dup)])
        first = np.flatnonzero(np.concatenate([[True], ~dup]))
        sig = np.bincount(grp, weights=sig) / np.bincount(grp)
        eps, t, keep = eps[first], t[first], keep[first]
    return eps, sig, t, keep


def _clean_rate_series(eps, sig, keep, where):
    dup = np.diff(eps) == 0
    if dup.any():
        conflict = dup & (np.diff(sig) != 0)
        if conflict.any():
            k = int(np.flatnonzero(conflict)[0])
            raise DataError(
                f"{where(keep[k + 1])}: strain {eps[k]:g} appears twice with different stresses "
                f"({sig[k]:g} at {where.label(keep[k])}, {sig[k + 1]:g} here): at a constant "
                "rate that is the same instant; average or drop one (separate tests need "
                "separate curves)"
            )
        first = np.concatenate([[True], ~dup])
        eps, sig, keep = eps[first], sig[first], keep[first]
    return eps, sig, keep


# ==================================================================== readers
def read_csv(
    path_or_paths: Any,
    *,
    rate: float | Sequence[float | None] | None = None,
    measure: str | None = None,
    mode: str | None = None,
    compression_positive: bool | None = None,
    columns: Mapping[str, Any] | None = None,
    units: Mapping[str, str] | None = None,
    names: Sequence[str] | None = None,
    group_by: str | Sequence[str] | None = None,
    select: Mapping[str, Any] | None = None,
    sort: bool = False,
    n_points: int | None = DEFAULT_N_POINTS,
    by: str | None = None,
    encoding: str | None = None,
) -> list[Curve]:
    """Read test curves from CSV files.

    One file per curve (columns such as ``strain``, ``stress_MPa``, optional ``time_s``
    and ``strain_rate``), or one long file with a rate column (one curve per distinct
    rate) or a ``test``/``curve``/``specimen``/``name`` column.

    Parameters
    ----------
    path_or_paths : path, file-like, or a sequence of them
        The file(s). Curves come back in file order, then in order of appearance.
    rate : float or sequence of float, optional
        Engineering strain rate in 1/s (one for all files, or one per file). Beats the
        file's rate column and its ``# strain_rate:`` line.
    measure : {"engineering", "true"}, optional
        Stress measure of the file when the header does not say (``true_stress``,
        ``nominal_stress``, ``cauchy_stress`` do); default engineering. When both an
        engineering and a true stress column exist, picks that column.
    mode : {"compression", "tension", "mixed"}, optional
        Declared loading mode (a contradiction by the data's signs is an error).
    compression_positive : bool, optional
        The file gives compression as positive numbers: negate strain and stress.
    columns : mapping, optional
        Role -> header name (or 0-based index) for ``"strain"``, ``"stretch"``,
        ``"stress"``, ``"time"``, ``"rate"``, overriding recognition; ``None`` ignores a
        column (e.g. ``{"time": None}`` to treat a test as constant-rate).
    units : mapping, optional
        Role -> unit, where the header has none or a wrong one, e.g. ``{"stress": "kPa"}``.
    names : sequence of str, optional
        Column names for files without a header row (or to replace the header).
    group_by : str or sequence of str, optional
        Column(s) whose values tell the curves of a long file apart.
    select : mapping, optional
        Keep only rows whose column equals a value (or one of a list), e.g.
        ``{"mode": "uniaxial_tension_compression"}``.
    sort : bool, default False
        Sort each curve's rows by time (or by |strain| without time) instead of
        rejecting rows out of order.
    n_points, by
        Objective points of each curve, as in :class:`Curve`.
    encoding : str, optional
        Text encoding; default: UTF-8 (with or without BOM), UTF-16 with BOM, else
        Latin-1.

    Returns
    -------
    list of Curve

    Raises
    ------
    DataError
        With the file, the line or column, and the fix.

    Notes
    -----
    *Headers* are matched case-insensitively, with units in brackets or as a suffix:
    ``stress_kPa``, ``stress [MPa]``, ``Stress (Pa)``, ``nominal_stress_MPa``,
    ``true_stress_MPa``, ``strain``, ``strain_%``, ``engineering_strain``,
    ``true_strain`` (logarithmic: converted), ``stretch``/``lambda``, ``time_s``,
    ``time_ms``, ``strain_rate``, ``rate_1/s``, ``nominal_strain_rate_per_s``. Other
    columns (force, displacement, text) are ignored. Stress units: Pa, kPa, MPa, GPa,
    N/mm², psi, ksi, kgf/cm², bar; no unit means MPa.

    *Format.* Separators ``,``, ``;``, tab, ``|`` or spaces (taken from the header
    line); a decimal comma is understood with ``;`` or tab separators; UTF-8/UTF-16
    BOMs are skipped; blank lines are skipped. Lines ``# key: value`` before the
    header set ``strain_rate`` (``-100`` or ``-100 1/s``), ``measure``, ``mode``,
    ``name``, ``weight``, ``compression_positive`` and ``<role>_unit``; other ``#``
    lines are comments.

    *Curves.* A file with a time column gives a time-history curve; without one, a
    constant-rate curve, which needs a rate (column, ``#`` line or ``rate=``). Rows
    at the same rate and strain with different stresses are an error (two tests
    mixed up). Separate files at the same rate are separate curves (replicates).

    Examples
    --------
    >>> import io
    >>> text = "# strain_rate: -100\\nstrain,stress_kPa\\n0,0\\n-0.1,-50\\n-0.2,-120\\n"
    >>> [c] = read_csv(io.StringIO(text), n_points=2)
    >>> c.strain_rate, c.target_stress
    (-100.0, array([-0.05, -0.12]))
    >>> long = "strain_rate,strain,stress\\n-1,-0.1,-1\\n-1,-0.2,-2\\n-10,-0.1,-3\\n-10,-0.2,-5\\n"
    >>> [c.name for c in read_csv(io.StringIO(long))]
    ['<stream> [rate -1/s]', '<stream> [rate -10/s]']
    """
    if isinstance(path_or_paths, (str, os.PathLike)) or hasattr(path_or_paths, "read"):
        paths = [path_or_paths]
    else:
        paths = list(path_or_paths)
        if not paths:
            raise DataError("read_csv: no files given")
    if rate is None or np.ndim(rate) == 0:
        rates = [rate] * len(paths)
    else:
        rates = list(rate)  # type: ignore[arg-type]
        if len(rates) != len(paths):
            raise DataError(f"read_csv: {len(rates)} rates for {len(paths)} files: give one "
                            "rate, or one per file")
    out: list[Curve] = []
    for p, r in zip(paths, rates):
        table = _read_table(p, names, encoding)
        out.extend(_curves_from_table(
            table, rate=None if r is None else float(r), measure=measure, mode=mode,
            compression_positive=compression_positive, columns=columns, units=units,
            group_by=group_by, select=select, sort=sort, n_points=n_points, by=by, name=None,
        ))
    return out


def curves_from_arrays(
    data: Any,
    *,
    names: Sequence[str] | None = None,
    rate: float | None = None,
    measure: str | None = None,
    mode: str | None = None,
    compression_positive: bool | None = None,
    columns: Mapping[str, Any] | None = None,
    units: Mapping[str, str] | None = None,
    group_by: str | Sequence[str] | None = None,
    select: Mapping[str, Any] | None = None,
    sort: bool = False,
    n_points: int | None = DEFAULT_N_POINTS,
    by: str | None = None,
    name: str | None = None,
    source: str | None = None,
) -> list[Curve]:
    """Curves from a table in memory: the array counterpart of :func:`read_csv`.

    Parameters
    ----------
    data : array_like, DataFrame-like or mapping
        A 2-D array (rows = samples; anything with ``__array__``), a structured array,
        an object with ``.to_numpy()`` and ``.columns`` (a pandas or polars DataFrame;
        pandas is not needed), or a mapping ``{column name: values}``.
    names : sequence of str, optional
        Column names (headers with units, as in a CSV file). An unnamed 2-column array
        is taken as ``["strain", "stress"]`` (MPa).
    name : str, optional
        Curve name (with the group appended when there are several).
    source : str, optional
        What to call the data in messages.
    rate, measure, mode, compression_positive, columns, units, group_by, select, sort, n_points, by
        As in :func:`read_csv`.

    Examples
    --------
    >>> import numpy as np
    >>> eps = np.linspace(0, -0.3, 4)
    >>> table = np.column_stack([np.r_[eps, eps], np.r_[eps, 2 * eps],
    ...                          np.r_[[-1.0] * 4, [-100.0] * 4]])
    >>> cs = curves_from_arrays(table, names=["strain", "stress_MPa", "rate_1/s"], n_points=3)
    >>> [(c.strain_rate, float(c.target_stress[-1])) for c in cs]
    [(-1.0, -0.3), (-100.0, -0.6)]
    """
    table = _table_from_data(data, names, source)
    return _curves_from_table(
        table, rate=rate, measure=measure, mode=mode,
        compression_positive=compression_positive, columns=columns, units=units,
        group_by=group_by, select=select, sort=sort, n_points=n_points, by=by, name=name,
    )
