"""The curve: :class:`Curve`, one measured uniaxial test, its stretch history and its
objective points.

The constructor runs the checks and inferences of :mod:`vhfit.data._samples` in order;
the objective points are placed by :mod:`vhfit.data._points` and the history is
simplified by :mod:`vhfit.data._paths`. Conventions and errors: see :mod:`vhfit.data`.
:func:`_curves_from_table` builds the curves of a table (the readers' last step).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from functools import cached_property
from typing import Any

import numpy as np

from vhfit.data._errors import DataError, _norm_measure, _Subset, _warn, _Where
from vhfit.data._measures import engineering_to_true, true_to_engineering
from vhfit.data._paths import _bin_means, _segment_bounds, _simplify_idx
from vhfit.data._points import (
    DEFAULT_N_POINTS,
    _check_points_args,
    _point_weights,
    _points_of,
)
from vhfit.data._samples import (
    _check_deformed,
    _check_kinematics,
    _check_one_sign_at_constant_rate,
    _check_weight,
    _clean_samples,
    _default_name,
    _loading_mode,
    _nominal_rate,
    _parse_rate_value,
    _rate_with_sign,
    _sample_arrays,
    _sign_tolerance,
    _stress_with_sign,
)
from vhfit.data._specs import _curve_specs
from vhfit.data._table import _Table, _table_from_data
from vhfit.history import History, from_rest

#: A measured strain path is simplified (breakpoints dropped) only where that moves it by
#: less than this fraction of its strain range; turning points are always kept.
PATH_RTOL = 1e-4
#: ... unless that leaves more than this many breakpoints (a noisy strain signal keeps
#: nearly every sample, its noise then acts as strain-rate spikes, and the model's work
#: grows with them): the history then follows an average over this many bins of
#: consecutive samples, simplified likewise, with a DataWarning saying how closely.
MAX_BREAKPOINTS = 2000
#: By default a curve is compared with the model at its measured samples; a longer record
#: is compared at the means of this many bins of consecutive samples (each bin within one
#: segment of the history). 1000 bins resolve a curve to 0.1 % of its length, far finer
#: than its features, and average its noise; the fit's cost grows with the points (4
#: curves of 10^5 noisy samples: 3.1 s a fit at 1000 bins, 5.9 s at 2000, 2 cores).
MAX_POINTS = 1000


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
    n_points : int or None, default None
        ``None`` (the default, ``DEFAULT_N_POINTS``): the objective points are the
        measured samples themselves, or for a record of more than ``MAX_POINTS`` samples
        the means (of strain, time and stress) of ``MAX_POINTS`` bins of consecutive
        samples, no bin straddling a segment bound. An int: that many points placed
        ``by`` (per segment with ``by="segments"``), their target stresses interpolated
        linearly between samples; ``n_points=10`` is the paper's scheme (§2.2).
    by : {"strain", "time", "arclength", "segments"}, optional
        With an int ``n_points``, how the objective points are spaced: evenly in strain
        (the default for a strictly monotonic strain, as in the paper); in time; in arc
        length along the
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
    *Objective points.* By default every sample is compared (Eq. 20 normalises each
    curve by its own mean stress; a curve with more samples counts more, which
    ``weight`` can balance); a long record by bin means, which average its noise instead
    of picking noisy samples at chosen places. With ``n`` points on a curve whose data
    start from rest (ε ≈ 0),
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
    Curve('fast': compression, engineering stress, rate -100/s, 51 samples, 51 points by samples)
    >>> c.target_strain[:3]
    array([ 0.  , -0.01, -0.02])
    >>> c.history.out_time[1:3]
    array([0.0001, 0.0002])
    >>> c.resample(4).target_stress          # 4 points evenly in strain from rest
    array([-1.25, -2.5 , -3.75, -5.  ])
    >>> Curve(strain=eps, stress=10 * eps, strain_rate=-100.0, n_points=10).target_strain[:4]
    array([-0.05, -0.1 , -0.15, -0.2 ])

    A loading–unloading test with its time column is resampled along the curve:

    >>> t = np.linspace(0.0, 2.0, 201)
    >>> lu = Curve(strain=0.5 - np.abs(0.5 - 0.5 * t), stress=np.sin(t), time=t,
    ...            n_points=10)
    >>> lu.mode, lu.by, lu.n_segments, lu.n_points, lu.strain_rate
    ('tension', 'segments', 2, 20, 0.5)
    >>> float(lu.target_strain[9])           # the turning point is an objective point
    0.5

    A long record is compared at bin means of its samples:

    >>> t = np.linspace(0.0, 1.0, 10_001)
    >>> long = Curve(strain=0.2 * t, stress=t, time=t)
    >>> long.n_points, long.by, float(long.target_time[0])
    (1000, 'bins', 0.0005)
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
        # the arguments, checked at the front door in the order their messages are tested
        name = _default_name(name, strain_rate)
        src = None if source is None else str(source)
        where = _Where(name, src, rows)
        eps, sig, t = _sample_arrays(where, strain, stress, time, rows)
        measure = _norm_measure(measure, where)
        weight = _check_weight(weight, where)
        rate = None if strain_rate is None else _parse_rate_value(strain_rate, where)
        if rate is None and t is None:
            raise DataError(
                f"{where()}: no strain rate and no time column: give strain_rate in 1/s "
                "(negative in compression) or the time of each sample"
            )
        n_points, by = _check_points_args(n_points, by, where)
        _check_deformed(eps, where)
        # the samples: duplicates merged, then signs and mode, then kinematics
        eps, sig, t, keep = _clean_samples(eps, sig, t, where)
        tol = _sign_tolerance(eps, where)
        declared = mode is not None or compression_positive
        eps, sig, mode = _loading_mode(eps, sig, rate, mode, compression_positive, tol, keep,
                                         where)
        rate = _rate_with_sign(rate, mode, compression_positive, where)
        _check_one_sign_at_constant_rate(eps, t, mode, tol, keep, where)
        sig = _stress_with_sign(sig, mode, declared, keep, where)
        _check_kinematics(eps, t, rate, keep, where)
        rate_estimated = rate is None
        if rate is None:
            rate = _nominal_rate(t, eps, mode, tol, where)

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
    def from_array(
        cls,
        data: Any,
        *,
        names: Sequence[str] | None = None,
        source: str | None = None,
        **options: Any,
    ) -> Curve:
        """One curve from an array-like table; keywords as :func:`vhfit.data.curves_from_arrays`.

        Examples
        --------
        >>> import numpy as np
        >>> eps = np.linspace(0, 0.2, 5)
        >>> c = Curve.from_array({"strain": eps, "stress_kPa": 1e3 * eps}, rate=0.01)
        >>> c.target_stress[-1].item()
        0.2
        """
        curves = _curves_from_table(_table_from_data(data, names, source), **options)
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
        ``"segments"``, ``"samples"`` (the measured samples themselves) or ``"bins"``
        (means of bins of consecutive samples, a record longer than ``MAX_POINTS``)."""
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
        t, e = from_rest(self._time, self._strain)
        scale = max(float(np.ptp(e)), float(np.abs(e).max()))
        tol = PATH_RTOL * scale
        idx = _simplify_idx(t, e, tol, limit=MAX_BREAKPOINTS)
        if idx is None:
            return self._smoothed_history(tol, scale)
        return History.piecewise_linear(t[idx], e[idx], out_time=self._t_obj)

    def _smoothed_history(self, tol: float, scale: float) -> History:
        # Following every noisy sample would keep ~all of them as breakpoints and turn
        # the noise into strain-rate spikes of noise/Δt; follow bin means instead.
        t, e = from_rest(*_bin_means(self._time, self._strain, MAX_BREAKPOINTS))
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
        e_obj, s_obj, t_obj, self._by = _points_of(
            self._strain, self._stress, self._sample_time(),
            self._rate if self._time is None else None, self._window, self._bounds,
            self._n_req, self._by_req, self._monotone, self._tol, self._window_desc,
            MAX_POINTS, where,
        )
        self._e_obj = _frozen(e_obj)
        self._s_obj = _frozen(s_obj)
        self._t_obj = _frozen(t_obj)
        w_obj, self._point_weights = _point_weights(self._point_weights, e_obj, t_obj, s_obj,
                                                    where)
        self._w_obj = _frozen(w_obj)

    # ------------------------------------------------------------- variants
    def resample(self, n_points: int | None = DEFAULT_N_POINTS, by: str | None = None) -> Curve:
        """The same curve with ``n_points`` objective points spaced ``by`` (see :class:`Curve`).

        ``n_points=None`` compares at the measured samples themselves (bin means above
        ``MAX_POINTS``); ``n_points=10`` is the paper's scheme. ``by=None`` picks
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



def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=np.float64, copy=True)
    a.flags.writeable = False
    return a



def _curves_from_table(table: _Table, **options: Any) -> list[Curve]:
    """The curves of a table, built one by one (options as :func:`vhfit.data.read_csv`)."""
    return [Curve(**spec) for spec in _curve_specs(table, **options)]

