"""The curve: :class:`Curve`, one measured homogeneous test, its loading history and its
objective points.

The constructor runs the checks and inferences of :mod:`vhfit.data._samples` (and of
:mod:`vhfit.data._modes` for the test's deformation) in order; the objective points are
placed by :mod:`vhfit.data._points`. The history is built here (:func:`_build_history`,
every call of the :class:`~vhfit.history.History` builders the data package makes): a
constant-rate ramp, a measured (time, strain) path simplified to the breakpoints that
matter or followed through bin means when too noisy, or an equilibrium set of states.
:func:`_curves_from_table` builds the curves of a table (the readers' last step).
Conventions and errors: see :mod:`vhfit.data`.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from vhfit._words import setting
from vhfit.data._errors import DataError, _norm_measure, _Subset, _warn, _Where
from vhfit.data._modes import (
    _check_deformation,
    _check_mode_signs,
    _driving_strain,
    _mode_name,
    _second_path,
)
from vhfit.data._paths import (
    LEG_RTOL,
    _bin_means,
    _segment_bounds,
    _simplify_idx,
    _turning_points,
)
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
from vhfit.modes import get_deformation

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
#: segment of the history). 500 bins resolve a curve to 0.2 % of its length, far finer
#: than its features, and average its noise; the fit's cost grows with the points, about
#: in proportion. On 4 curves of 10^5 samples the fit scores the same RMSAPE on every
#: sample with 500 bins as with 1000 at 1 % and 0.1 % noise, and 3e-4 (relative) more at
#: 0.01 % noise, where the curvature within a bin begins to show (docs/data.md).
MAX_POINTS = 500


# ======================================================= the curve's history
@dataclass(frozen=True)
class _Path:
    """What a curve's history is made of: its samples and its objective points."""

    deformation: str
    rate: float | None  # constant-rate ramp; None for time paths and equilibrium
    time: np.ndarray | None  # sample times (None: constant rate or equilibrium)
    strain: np.ndarray  # λ1 − 1 (γ in simple shear) of the samples
    strain2: np.ndarray | None  # λ2 − 1 of the samples (a second prescribed stretch)
    e_obj: np.ndarray  # driving strain at the objective points (one direction)
    e2_obj: np.ndarray | None
    t_obj: np.ndarray  # their times (sample numbers at equilibrium)
    two: bool  # outputs in both loaded directions (stress2 measured)


def _build_history(p: _Path, path_rtol: float, max_breakpoints: int, where: _Where) -> History:
    """The history of path ``p`` with outputs at its objective points (both directions
    when ``p.two``); a History refusal becomes a DataError naming the curve."""
    try:
        return _history(p, path_rtol, max_breakpoints, where)
    except ValueError as exc:
        if isinstance(exc, DataError):
            raise
        raise DataError(f"{where()}: {exc}") from None


def _history(p: _Path, path_rtol: float, max_breakpoints: int, where: _Where) -> History:
    kw = {"deformation": p.deformation}
    if p.strain2 is not None:
        kw["strain2"] = p.e2_obj if p.time is None else None
    if p.time is None and p.rate is None:
        h = History.equilibrium(p.e_obj, **kw)
    elif p.time is None:
        h = History.constant_rate(p.e_obj, p.rate, **kw)
    else:
        h = _measured_path(p, kw, path_rtol, max_breakpoints, where)
    if not p.two:
        return h
    n = p.t_obj.size
    return h.with_outputs(np.concatenate([h.out_time, h.out_time]),
                          np.repeat(np.array([1, 2]), n))


def _measured_path(p: _Path, kw: dict, path_rtol: float, max_breakpoints: int,
                   where: _Where) -> History:
    """Through the measured samples, breakpoints dropped where that moves the path(s) by
    less than ``path_rtol`` of the range; through bin means when that keeps too many."""
    t, e = from_rest(p.time, p.strain)
    paths = [e] if p.strain2 is None else [e, from_rest(p.time, p.strain2)[1]]
    scale = max(max(float(np.ptp(x)), float(np.abs(x).max())) for x in paths)
    tol = path_rtol * scale
    idx = _union_idx(t, paths, tol, max_breakpoints)
    if idx is None:
        return _smoothed(p, kw, path_rtol, scale, max_breakpoints, where)
    if p.strain2 is not None:
        kw["strain2"] = paths[1][idx]
    return History.piecewise_linear(t[idx], e[idx], out_time=p.t_obj, **kw)


def _union_idx(t, paths, tol, limit):
    """Breakpoints that every path needs (None past ``limit`` of them)."""
    keep = None
    for x in paths:
        idx = _simplify_idx(t, x, tol, limit=limit)
        if idx is None:
            return None
        keep = idx if keep is None else np.union1d(keep, idx)
    if limit is not None and keep.size > limit:
        return None
    return keep


def _smoothed(p: _Path, kw: dict, path_rtol: float, scale: float, limit: int,
              where: _Where) -> History:
    # Following every noisy sample would keep ~all of them as breakpoints and turn
    # the noise into strain-rate spikes of noise/Δt; follow bin means instead.
    raws = [p.strain] if p.strain2 is None else [p.strain, p.strain2]
    binned = [from_rest(*_bin_means(p.time, x, limit)) for x in raws]
    t, xs = binned[0][0], [b[1] for b in binned]
    tol = path_rtol * scale
    idx = None
    while idx is None:
        idx = _union_idx(t, xs, tol, limit)
        tol *= 2.0
    t, xs = t[idx], [x[idx] for x in xs]
    dev = np.interp(p.time, t, xs[0]) - p.strain
    rms = float(np.sqrt(np.mean(dev * dev)))
    _warn(
        f"{where()}: the measured strain path is noisy or too detailed to follow "
        f"sample by sample (more than {limit} breakpoints within "
        f"{path_rtol:g} of its range, and noise would become strain-rate spikes): the "
        f"simulated history follows a {limit}-bin average of it with "
        f"{idx.size} breakpoints (RMS deviation from the samples {rms:.3g} strain, "
        f"{rms / scale:.2g} of the range); smooth the strain signal yourself, or raise "
        f"vhfit.data.MAX_BREAKPOINTS, to choose differently", 6
    )
    if p.strain2 is not None:
        kw["strain2"] = xs[1]
    return History.piecewise_linear(t, xs[0], out_time=p.t_obj, **kw)


# ================================================================= the curve
class Curve:
    """One test: measured deformation and stress, its loading history, objective points.

    Parameters
    ----------
    strain : array_like
        Engineering strain ε = λ − 1 of each sample (negative in compression), in the
        loaded direction 1; in simple shear, the amount of shear γ. Or give ``stretch``.
    stress : array_like
        Stress of each sample in MPa, in the measure given by ``measure``: the stress in
        direction 1 (nominal P1 or true σ1), in simple shear the shear stress σ12 = P12.
    strain_rate : float, optional
        Engineering strain rate in 1/s (negative in compression). Without ``time`` the
        test is a constant-rate ramp from ε = 0 (paper Eq. 3), and the strain must be
        monotonic in the rate's direction; it need not start at 0. With ``time`` it is
        only the nominal rate (used e.g. for the τ bounds of Eq. 22). With neither rate
        nor time the curve is an *equilibrium* curve: fully relaxed states compared with
        the long-term law alone (:attr:`is_equilibrium`); its samples need no order.
    time : array_like, optional
        Time of each sample in s, for measured histories (loading–unloading, ramp–hold,
        drifting rates). The history is piecewise linear through the samples; the
        material is at rest at ε = 0 at t = 0, so a first sample at t > 0 is reached by
        a linear ramp from (0, 0). Samples at the same time and strain are merged (their
        stresses averaged).
    stretch : array_like, optional
        Stretch λ1 of each sample, instead of ``strain`` (not in simple shear).
    deformation : str
        The test, a registered :class:`vhfit.modes.Deformation` (docs/modes.md):
        ``"uniaxial"`` (default, the paper's) or another homogeneous test. Lab names
        such as ``"pure shear"`` or ``"uniaxial tension"`` are understood.
    strain2, stretch2 : array_like, optional
        λ2 − 1 or λ2 of each sample: required for a test with a second prescribed
        stretch (general biaxial), refused otherwise.
    stress2 : array_like, optional
        Stress in direction 2 of each sample (a test with two loaded directions), same
        measure:
        both stresses are then compared, the points of ``stress2`` after those of
        ``stress`` (:attr:`target_direction`).
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
        ``"all"``: every sample, never binned (e.g. to score a fit made on bins on
        every sample of a long record).
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
        Fewer than 2 samples, NaN/inf, strain going back and forth at constant rate,
        time running backwards, conflicting duplicate samples, signs contradicting the
        declared mode (or, in the tests of a known stress sign, a stress whose sign
        contradicts the strain), stretch ≤ 0, an unknown deformation, a biaxial curve
        without its second stretch, a simple-shear curve given stretches.

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

    Every homogeneous test, at a rate, along a time history, or at equilibrium:

    >>> lam = np.linspace(1.0, 2.0, 6)
    >>> ps = Curve(stretch=lam, stress=0.3 * (lam - lam**-3), deformation="pure shear")
    >>> ps.name, ps.deformation, ps.mode, ps.n_points
    ('planar (equilibrium)', 'planar', 'tension', 6)
    >>> ps.is_equilibrium, ps.history.is_equilibrium, ps.strain_rate
    (True, True, None)

    A long record is compared at bin means of its samples:

    >>> t = np.linspace(0.0, 1.0, 10_001)
    >>> long = Curve(strain=0.2 * t, stress=t, time=t)
    >>> long.n_points, long.by, round(float(long.target_time[0]), 12)
    (500, 'bins', 0.001)
    """

    #: A stress–strain test, not data of moduli (see :class:`vhfit.data.TestItem`).
    is_moduli = False

    def __init__(
        self,
        strain: Any = None,
        stress: Any = None,
        strain_rate: float | None = None,
        time: Any = None,
        *,
        stretch: Any = None,
        deformation: str = "uniaxial",
        strain2: Any = None,
        stretch2: Any = None,
        stress2: Any = None,
        measure: str = "engineering",
        mode: str | None = None,
        name: str | None = None,
        weight: float = 1.0,
        n_points: int | str | None = DEFAULT_N_POINTS,
        by: str | None = None,
        compression_positive: bool = False,
        source: str | os.PathLike[str] | None = None,
        rows: Sequence[Any] | None = None,
        metadata: Mapping[str, Any] | None = None,
    ) -> None:
        # the arguments, checked at the front door in the order their messages are tested
        src = None if source is None else str(source)
        where = _Where(_default_name(name, strain_rate), src, rows)
        deformation = _check_deformation(deformation, where)
        test = get_deformation(deformation)
        if name is None and (not test.uniaxial or (strain_rate is None and time is None)):
            where = _Where(_mode_name(deformation, strain_rate, time), src, rows)
        strain = _driving_strain(strain, stretch, deformation, where)
        if stress is None:
            raise DataError(f"{where()}: no {setting('stress=', 'stress column')} given: give "
                            "the stress of each sample")
        eps, sig, t = _sample_arrays(where, strain, stress, time, rows)
        e2, s2 = _second_path(deformation, strain2, stretch2, stress2, eps.size, where)
        measure = _norm_measure(measure, where)
        weight = _check_weight(weight, where)
        rate = None if strain_rate is None else _parse_rate_value(strain_rate, where)
        equilibrium = rate is None and t is None
        n_points, by = _check_points_args(n_points, by, where)
        paths = eps if e2 is None else np.concatenate([eps, e2])
        _check_deformed(paths, where)
        # the samples: duplicates merged, then signs and mode, then kinematics
        eps, sig, t, keep, e2, s2 = _clean_samples(eps, sig, t, where, equilibrium, e2, s2)
        eps, sig, e2, s2, mode, rate, tol = _signed_samples(
            eps, sig, t, e2, s2, rate, mode, compression_positive, deformation, keep, where)
        rate_estimated = rate is None and t is not None
        if rate_estimated:
            lead = eps if e2 is None or np.ptp(eps) >= np.ptp(e2) else e2
            rate = _nominal_rate(t, lead, mode, tol, where)

        self._strain = _frozen(eps)
        self._stress = _frozen(sig)
        self._time = None if t is None else _frozen(t)
        self._strain2 = None if e2 is None else _frozen(e2)
        self._stress2 = None if s2 is None else _frozen(s2)
        self._deformation = deformation
        self._equilibrium = equilibrium
        self._rate = None if rate is None else float(rate)
        self._rate_estimated = rate_estimated
        self._measure = measure
        self._mode = mode
        self._name = where.name
        self._weight = weight
        self._source = src
        self._where = _Where(where.name, src, None if rows is None else _Subset(rows, keep))
        self._metadata = dict(metadata or {})
        self._tol = tol
        d = np.diff(eps)
        self._monotone = bool((d > 0).all() or (d < 0).all())
        self._bounds = _bounds_of(t, eps, e2, equilibrium, MAX_BREAKPOINTS)
        self._n_req = n_points
        self._by_req = by
        self._cap = None  # bins of a long record's samples (None: MAX_POINTS when built)
        self._window = None  # boolean mask over samples, or None
        self._window_desc: tuple[str, ...] = ()
        self._point_weights: Any = None
        self._set_points()
        if e2 is not None and self.is_constant_rate:
            _ = self.history  # λ2 must ramp at a constant rate too: say so now, not later

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
        """λ1 = 1 + ε of each sample (in simple shear :attr:`strain` is γ, not λ − 1)."""
        return 1.0 + self._strain

    @property
    def strain_rate(self) -> float | None:
        """Nominal engineering strain rate in 1/s (negative in compression); None for an
        equilibrium curve.

        As given; for a time curve without a given rate it is estimated as the median of
        |dε/dt| over the samples, each step weighted by the strain it applies (so holds
        and sensor noise do not count), with the sign of the loading mode (of the first
        loading for a mixed curve). See :attr:`strain_rate_estimated`. In simple shear
        it is the rate of γ; in a biaxial test, of the path (λ1 or λ2) that moves more.
        """
        return self._rate

    @property
    def strain_rate_estimated(self) -> bool:
        """True if :attr:`strain_rate` was estimated from the time column."""
        return self._rate_estimated

    @property
    def is_constant_rate(self) -> bool:
        """True if the history is a constant-rate ramp (a rate, no time column)."""
        return self._time is None and not self._equilibrium

    @property
    def is_equilibrium(self) -> bool:
        """True for an equilibrium curve (neither rate nor time): fully relaxed states,
        compared with the long-term law alone; its samples need no order."""
        return self._equilibrium

    @property
    def deformation(self) -> str:
        """The test: the name of a registered deformation (``"uniaxial"``, the paper's,
        or another, :func:`vhfit.modes.get_deformation` gives its record)."""
        return self._deformation

    @property
    def strain2(self) -> np.ndarray | None:
        """λ2 − 1 of each sample of a biaxial curve (None otherwise)."""
        return self._strain2

    @property
    def stress2(self) -> np.ndarray | None:
        """Stress in the second loaded direction of each sample, in :attr:`measure`
        (MPa), when it was measured (a test with two loaded directions; None otherwise)."""
        return self._stress2

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

    @property
    def temperature(self) -> float | None:
        """Test temperature: ``metadata["temperature"]`` (None when not stated)."""
        T = self._metadata.get("temperature")
        return None if T is None else float(T)

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

    @property
    def target_direction(self) -> np.ndarray:
        """Loaded direction of each objective point: 1, or 2 for the points of ``stress2``
        (they follow those of ``stress``)."""
        return self._d_obj

    @property
    def target_strain2(self) -> np.ndarray | None:
        """λ2 − 1 at the objective points of a biaxial curve (None otherwise)."""
        return self._e2_obj

    @property
    def target_scale(self) -> None:
        """Scale of each point's relative error: none, a curve's points are scaled by the
        curve's own RMS stress (paper Eq. 20); frequency sweeps and relaxation tests give
        one per point."""
        return None

    @cached_property
    def history(self) -> History:
        """The loading history to simulate, with ``out_time`` at the objective points
        (and ``out_direction`` saying which loaded direction each one is)."""
        n = self._t1_obj.size
        path = _Path(
            self._deformation, self._rate if self.is_constant_rate else None, self._time,
            self._strain, self._strain2, self._e_obj[:n],
            None if self._e2_obj is None else self._e2_obj[:n], self._t1_obj,
            self._stress2 is not None,
        )
        return _build_history(path, PATH_RTOL, MAX_BREAKPOINTS, self._where)

    def _sample_time(self) -> np.ndarray:
        if self._equilibrium:  # no time: the sample numbers order the samples
            return np.arange(self._strain.size, dtype=np.float64)
        return self._time if self._time is not None else self._strain / self._rate

    def _set_points(self) -> None:
        where = self._where
        cols = [self._strain, self._stress, self._sample_time()]
        cols += [v for v in (self._strain2, self._stress2) if v is not None]
        out, self._by = _points_of(
            tuple(cols), self._rate if self.is_constant_rate else None, self._window,
            self._bounds, self._n_req, self._by_req, self._monotone, self._tol,
            self._window_desc, MAX_POINTS if self._cap is None else self._cap, where,
        )
        e_obj, s_obj, t_obj = out[:3]
        rest = list(out[3:])
        e2_obj = rest.pop(0) if self._strain2 is not None else None
        if self._equilibrium:  # the history's outputs are its samples, numbered
            t_obj = np.arange(e_obj.size, dtype=np.float64)
        self._t1_obj = _frozen(t_obj)
        d_obj = np.ones(e_obj.size, dtype=np.int64)
        if self._stress2 is not None:  # both directions compared: points concatenated
            e_obj, t_obj = np.tile(e_obj, 2), np.tile(t_obj, 2)
            e2_obj = None if e2_obj is None else np.tile(e2_obj, 2)
            s_obj = np.concatenate([s_obj, rest[0]])
            d_obj = np.concatenate([d_obj, 2 * d_obj])
        self._d_obj = d_obj
        self._d_obj.flags.writeable = False
        self._e2_obj = None if e2_obj is None else _frozen(e2_obj)
        self._e_obj = _frozen(e_obj)
        self._s_obj = _frozen(s_obj)
        self._t_obj = _frozen(t_obj)
        w_obj, self._point_weights = _point_weights(self._point_weights, e_obj, t_obj, s_obj,
                                                    where)
        self._w_obj = _frozen(w_obj)

    # ------------------------------------------------------------- variants
    def resample(self, n_points: int | str | None = DEFAULT_N_POINTS,
                 by: str | None = None, *, max_points: int | None = None) -> Curve:
        """The same curve with ``n_points`` objective points spaced ``by`` (see :class:`Curve`).

        ``n_points=None`` compares at the measured samples themselves (bin means above
        ``max_points``, by default ``MAX_POINTS``; ``"all"``: never binned);
        ``n_points=10`` is the paper's scheme. ``by=None`` picks ``"strain"`` for a
        strictly monotonic strain and ``"segments"`` otherwise.

        Examples
        --------
        >>> c = Curve([0.0, 0.1, 0.2], [0.0, 1.0, 2.0], strain_rate=0.1)
        >>> c.resample(2).target_strain, c.resample(None).target_strain
        (array([0.1, 0.2]), array([0. , 0.1, 0.2]))
        >>> c.resample(None, max_points=2).target_strain   # the means of 2 bins
        array([0.05, 0.2 ])
        """
        n_points, by = _check_points_args(n_points, by, self._where)
        if max_points is not None and (
                isinstance(max_points, bool) or not isinstance(max_points, (int, np.integer))
                or max_points < 1):
            raise ValueError(f"max_points = {max_points!r}: give a whole number >= 1")
        return self._derive(_n_req=n_points, _by_req=by,
                            _cap=None if max_points is None else int(max_points))

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
        if time is not None and self._equilibrium:
            raise DataError(f"{self._where()}: {setting('trim(time=...)', '--trim-time')}: an "
                            "equilibrium curve has no time: trim it by strain"
                            f" ({setting('trim(strain=...)', '--trim-strain')})")
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
        # nominal = true / λ_a, λ_a the loaded stretch of the test's record (1 in shear)
        test = get_deformation(self._deformation)
        x1 = 1.0 + self._strain
        x2 = None if self._strain2 is None else 1.0 + self._strain2
        attrs: dict[str, Any] = {"_measure": m}
        for key, d in (("_stress", 1), ("_stress2", 2)):
            s = getattr(self, key)
            if s is not None:
                lam = test.loaded_stretch(x1, x2, d)
                attrs[key] = _frozen(s * lam if m == "true" else s / lam)
        return self._derive(**attrs)

    def replace(self, *, name: str | None = None, weight: float | None = None) -> Curve:
        """The same curve with another name and/or weight."""
        attrs: dict[str, Any] = {}
        if name is not None:
            attrs["_name"] = str(name)
            attrs["_where"] = _Where(str(name), self._source, self._where.rows)
        if weight is not None:
            w = float(weight)
            if not (np.isfinite(w) and w >= 0):
                raise DataError(f"{self._where()}: {setting(f'weight={weight!r}', 'its weight')}"
                                ": give a finite weight >= 0")
            attrs["_weight"] = w
        return self._derive(**attrs)

    def shifted(self, a_T: float) -> Curve:
        """The test at the reference temperature: history in reduced time t/a_T (rate × a_T),
        without ``metadata["temperature"]``."""
        a = float(a_T)
        if not (np.isfinite(a) and a > 0):
            raise DataError(f"{self._where()}: a_T = {a_T!r}: give a finite shift factor > 0")
        # at the reference now: no temperature left to shift it by again
        meta = {k: v for k, v in self._metadata.items() if k != "temperature"}
        if self._equilibrium:  # fully relaxed: no time to shift
            return self._derive(_metadata=meta)
        t = None if self._time is None else _frozen(self._time / a)
        return self._derive(_rate=self._rate * a, _time=t, _metadata=meta)

    def __repr__(self) -> str:
        if self._equilibrium:
            rate = "equilibrium"
        else:
            rate = f"rate {self._rate:g}/s" + (" (estimated)" if self._rate_estimated else "")
        win = f", window {' '.join(self._window_desc)}" if self._window_desc else ""
        extra = "" if self._time is None else ", time history"
        mode = self._mode
        test = get_deformation(self._deformation)
        if test.shear:
            mode = {"tension": "γ > 0", "compression": "γ < 0"}.get(mode, "γ of both signs")
        test = "" if test.uniaxial else f"{self._deformation} "
        return (
            f"Curve({self._name!r}: {test}{mode}, {self._measure} stress, {rate}{extra}, "
            f"{self._strain.size} samples, {self.n_points} points by {self._by}{win})"
        )



def _signed_samples(eps, sig, t, e2, s2, rate, mode, compression_positive, deformation, keep,
                    where):
    """The samples with the signs of their loading mode, checked (``Curve`` steps 3-4):
    (strain, stress, strain2, stress2, mode, rate, sign tolerance)."""
    test = get_deformation(deformation)
    tol = _sign_tolerance(eps if e2 is None else np.concatenate([eps, e2]), where)
    declared = mode is not None or compression_positive
    eps, sig, mode = _loading_mode(eps, sig, rate, mode, compression_positive, tol, keep,
                                     where, guess=test.uniaxial)
    if compression_positive:
        e2 = None if e2 is None else -e2
        s2 = None if s2 is None else -s2
    rate = _rate_with_sign(rate, mode, compression_positive, where)
    _check_one_sign_at_constant_rate(eps, t, mode, tol, keep, where, rate is None and t is None)
    if test.uniaxial:
        sig = _stress_with_sign(sig, mode, declared, keep, where)
    else:
        _check_mode_signs(eps, sig, deformation, mode, keep, where)
    _check_kinematics(eps, t, rate, keep, where, shear=test.shear)
    return eps, sig, e2, s2, mode, rate, tol


def _bounds_of(t, eps, e2, equilibrium: bool, max_breakpoints: int) -> np.ndarray:
    """Sample indices bounding the segments of a curve's path (see ``Curve.n_segments``):
    of the path that moves more (λ1, or λ2 of a biaxial test); at equilibrium, the
    reversals of the samples' order; at constant rate, none."""
    lead = eps if e2 is None or np.ptp(eps) >= np.ptp(e2) else e2
    if equilibrium:
        turns = [_turning_points(x, LEG_RTOL * float(np.ptp(x))) for x in (eps, e2)
                 if x is not None]
        return np.unique(np.concatenate(turns))
    if t is None:
        return np.array([0, eps.size - 1])
    return _segment_bounds(t, lead, max_breakpoints)


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=np.float64, copy=True)
    a.flags.writeable = False
    return a



def _curves_from_table(table: _Table, **options: Any) -> list[Curve]:
    """The curves of a table, built one by one (options as :func:`vhfit.data.read_csv`)."""
    return [Curve(**spec) for spec in _curve_specs(table, **options)]

