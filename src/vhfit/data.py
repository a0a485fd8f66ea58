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

import codecs
import csv
import operator
import os
import re
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

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
#: A long time record's rate is estimated from this many bin means of its samples.
_RATE_BINS = 200
#: Resampling by arc length smooths the curve into this many bins first, so that sensor
#: noise does not count as length.
_ARC_BINS = 200
#: The strain must reverse by more than this fraction of its range to start a new loading
#: leg (smaller wiggles are noise or machine overshoot).
LEG_RTOL = 0.05
#: A hold: the strain stays within this fraction of its range ...
HOLD_RTOL = 0.002
#: ... for at least this fraction of the test's duration.
HOLD_MIN_DURATION = 0.05

_MEASURES = {
    "engineering": "engineering",
    "eng": "engineering",
    "nominal": "engineering",
    "nom": "engineering",
    "piola": "engineering",
    "first_piola": "engineering",
    "pk1": "engineering",
    "true": "true",
    "cauchy": "true",
}
_MODES = {
    "compression": "compression",
    "c": "compression",
    "tension": "tension",
    "t": "tension",
    "mixed": "mixed",
    "tension_compression": "mixed",
    "cyclic": "mixed",
}
_BYS = ("strain", "time", "arclength", "segments")


class DataError(ValueError):
    """Unusable test data; the message names the file, curve, row or column, and the fix."""


class DataWarning(UserWarning):
    """Something about the data was inferred rather than declared; the message says what."""


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


# ================================================================ error places
class _Where:
    """Formats "curve 'x' (file.csv, line 17, column 'stress')" for messages."""

    def __init__(self, name: str, source: str | None, rows: Sequence[Any] | None):
        self.name = name
        self.source = source
        self.rows = rows

    def label(self, k: int) -> str:
        if self.rows is None:
            return f"row {k}"
        r = self.rows[k]
        return r if isinstance(r, str) else f"row {r}"

    def __call__(self, k: int | None = None, column: str | None = None) -> str:
        parts = [self.source] if self.source else []
        if k is not None:
            parts.append(self.label(int(k)))
        if column:
            parts.append(f"column {column!r}")
        loc = ", ".join(parts)
        return f"curve {self.name!r}" + (f" ({loc})" if loc else "")

    def array(self, what: str, values: Any, n: int | None = None) -> np.ndarray:
        try:
            complex_ = np.iscomplexobj(values)
        except (TypeError, ValueError):
            complex_ = False
        if complex_:  # numpy would drop the imaginary part with only a warning
            raise DataError(f"{self()}: {what} holds complex numbers: give real values")
        try:
            arr = np.asarray(values, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise DataError(
                f"{self()}: {what} must be numbers ({exc}): fix the {what} data"
            ) from None
        if arr.ndim == 0:
            arr = arr.reshape(1)
        if arr.ndim != 1:
            raise DataError(
                f"{self()}: {what} must be 1-D, got shape {arr.shape}: pass one value per sample"
            )
        if n is not None and arr.size != n:
            raise DataError(
                f"{self()}: {what} has {arr.size} values but strain has {n}: give one per sample"
            )
        bad = ~np.isfinite(arr)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise DataError(
                f"{self(k)}: {what} = {arr[k]:g} is not finite: repair or delete that row"
            )
        return arr


class _Subset:
    """The labels ``rows[keep[k]]``, without building a list of them."""

    def __init__(self, rows: Sequence[Any], keep: np.ndarray):
        self.rows, self.keep = rows, keep

    def __len__(self) -> int:
        return len(self.keep)

    def __getitem__(self, k: int) -> Any:
        return self.rows[int(self.keep[k])]


class _Labels:
    """Lazy row labels ``"line 17"`` (files) or ``"row 3"`` (arrays)."""

    def __init__(self, numbers: Any, word: str):
        self.numbers = np.asarray(numbers, dtype=np.int64)
        self.word = word

    def __len__(self) -> int:
        return int(self.numbers.size)

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, (slice, np.ndarray, list)):
            return _Labels(self.numbers[i], self.word)
        return f"{self.word} {int(self.numbers[i])}"


def _warn(msg: str) -> None:
    warnings.warn(msg, DataWarning, stacklevel=4)


def _norm_key(s: Any) -> str:
    return re.sub(r"[\s\-]+", "_", str(s).strip().lower())


def _norm_measure(measure: Any, where: _Where) -> str:
    m = _MEASURES.get(_norm_key(measure))
    if m is None:
        raise DataError(
            f"{where()}: measure={measure!r} is not understood: use 'engineering' (nominal) "
            "or 'true' (Cauchy)"
        )
    return m


def _norm_mode(mode: Any, where: _Where) -> str:
    m = _MODES.get(_norm_key(mode))
    if m is None:
        raise DataError(
            f"{where()}: mode={mode!r} is not understood: use 'compression', 'tension' or "
            "'mixed'"
        )
    return m


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
                        else _segment_bounds(t, eps))
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
        t, e = self._time, self._strain
        if t[0] > 0.0:
            t = np.concatenate([[0.0], t])
            e = np.concatenate([[0.0], e])
        scale = max(float(np.ptp(e)), float(np.abs(e).max()))
        tol = PATH_RTOL * scale
        idx = _simplify_idx(t, e, tol, limit=MAX_BREAKPOINTS)
        if idx is None:
            return self._smoothed_history(tol, scale)
        return History.piecewise_linear(t[idx], e[idx], out_time=self._t_obj)

    def _smoothed_history(self, tol: float, scale: float) -> History:
        # Following every noisy sample would keep ~all of them as breakpoints and turn
        # the noise into strain-rate spikes of noise/Δt; follow bin means instead.
        t, e = _bin_means(self._time, self._strain, MAX_BREAKPOINTS)
        if t[0] > 0.0:
            t = np.concatenate([[0.0], t])
            e = np.concatenate([[0.0], e])
        tol_b = tol
        idx = _simplify_idx(t, e, tol_b, limit=MAX_BREAKPOINTS)
        while idx is None:
            tol_b *= 2.0
            idx = _simplify_idx(t, e, tol_b, limit=MAX_BREAKPOINTS)
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


def _estimate_rate(t, eps, sgn, tol) -> float:
    if t.size > 2 * _RATE_BINS:
        # sample-to-sample differences of a long record measure its noise, not its rate
        t, eps = _bin_means(t, eps, _RATE_BINS)
    dt = np.diff(t)
    de = np.diff(eps)
    ok = (dt > 0) & (de != 0)
    if not ok.any():
        return float("nan")
    r = np.abs(de[ok] / dt[ok])
    w = np.abs(de[ok])
    order = np.argsort(r)
    cw = np.cumsum(w[order])
    med = float(r[order][np.searchsorted(cw, 0.5 * cw[-1])])
    if sgn is None:  # mixed: the sign of the first loading
        k = int(np.flatnonzero(np.abs(eps) > tol)[0])
        sgn = float(np.sign(eps[k]))
    return sgn * med


def _arclength(eps: np.ndarray, sig: np.ndarray) -> np.ndarray:
    """Strictly increasing arc length along (strain, stress), both scaled to unit range."""
    n = eps.size
    x = eps / (np.ptp(eps) or 1.0)
    y = sig / (np.ptp(sig) or 1.0)
    k = np.arange(n, dtype=np.float64)
    if n > 4 * _ARC_BINS:  # average into bins so that noise does not add length
        edges = np.linspace(0, n, _ARC_BINS + 1).astype(np.intp)
        cnt = np.diff(edges)
        xs = np.add.reduceat(x, edges[:-1]) / cnt
        ys = np.add.reduceat(y, edges[:-1]) / cnt
        ks = np.add.reduceat(k, edges[:-1]) / cnt
        xs = np.concatenate([[x[0]], xs, [x[-1]]])
        ys = np.concatenate([[y[0]], ys, [y[-1]]])
        ks = np.concatenate([[0.0], ks, [n - 1.0]])
    else:
        xs, ys, ks = x, y, k
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(xs), np.diff(ys)))])
    s = np.interp(k, ks, s)
    total = s[-1] if s[-1] > 0 else 1.0
    return s + 1e-9 * total * k / max(n - 1, 1)


def _turning_points(e: np.ndarray, h: float) -> np.ndarray:
    """Sample indices ``[0, turns..., n-1]`` where the strain reverses by more than ``h``.

    A zigzag filter with hysteresis ``h``, run on the per-bin extremes of long series
    (the extremes of a leg are among them), so its Python loop stays short.
    """
    n = e.size
    if n > 8192:
        edges = np.linspace(0, n, 2049).astype(np.intp)
        lo = [a + int(np.argmin(e[a:b])) for a, b in zip(edges[:-1], edges[1:])]
        hi = [a + int(np.argmax(e[a:b])) for a, b in zip(edges[:-1], edges[1:])]
        cand = np.unique(np.concatenate([[0, n - 1], lo, hi]))
    else:
        cand = np.arange(n)
    v = e[cand]
    turns = []
    direction = 0
    lo_i = hi_i = ext = 0
    for i in range(1, v.size):
        x = v[i]
        if direction == 0:
            if x > v[hi_i]:
                hi_i = i
            if x < v[lo_i]:
                lo_i = i
            if v[hi_i] - v[lo_i] > h:
                direction = 1 if hi_i > lo_i else -1
                ext = hi_i if direction == 1 else lo_i
                first = lo_i if direction == 1 else hi_i
                if first != 0 and abs(v[first] - v[0]) > h:  # it went the other way first
                    turns.append(first)
        elif direction == 1:
            if x > v[ext]:
                ext = i
            elif v[ext] - x > h:
                turns.append(ext)
                direction, ext = -1, i
        else:
            if x < v[ext]:
                ext = i
            elif x - v[ext] > h:
                turns.append(ext)
                direction, ext = 1, i
    return np.array([0, *[int(cand[i]) for i in turns], n - 1], dtype=np.intp)


def _segment_bounds(t: np.ndarray, e: np.ndarray) -> np.ndarray:
    """Sample indices bounding the segments of a history: turning points and holds."""
    n = e.size
    rng = float(np.ptp(e))
    turns = _turning_points(e, LEG_RTOL * rng)
    tol = 0.5 * HOLD_RTOL * rng
    pts = _simplify_idx(t, e, tol, limit=MAX_BREAKPOINTS)
    if pts is None:  # noisy: look for holds in bin means (a sample index each)
        tb, eb = _bin_means(t, e, MAX_BREAKPOINTS)
        k = tb.size - 2
        centre = np.concatenate([[0], (np.arange(k) + 0.5) * n // k, [n - 1]]).astype(np.intp)
        sub = _simplify_idx(tb, eb, tol)
        tt, ee, si = tb[sub], eb[sub], centre[sub]
    else:
        tt, ee, si = t[pts], e[pts], pts
    band = 2 * HOLD_RTOL * rng
    min_dur = HOLD_MIN_DURATION * (t[-1] - t[0])
    holds = []  # (start sample, end sample) of runs of the path within a narrow band
    start = lo = hi = None
    for a in range(tt.size - 1):
        b = a + 1
        flat = abs(ee[b] - ee[a]) <= HOLD_RTOL * rng
        if flat and start is not None and max(hi, ee[b]) - min(lo, ee[b]) <= band:
            lo, hi = min(lo, ee[b]), max(hi, ee[b])
            end = b
            continue
        if start is not None and tt[end] - tt[start] >= min_dur:
            holds.append((int(si[start]), int(si[end])))
        start = lo = hi = None
        if flat:
            start, end, lo, hi = a, b, min(ee[a], ee[b]), max(ee[a], ee[b])
    if start is not None and tt[end] - tt[start] >= min_dur:
        holds.append((int(si[start]), int(si[end])))
    bounds = set(int(i) for i in turns)
    for a, b in holds:
        bounds = {i for i in bounds if not a < i < b} | {a, b}
    return np.array(sorted(bounds | {0, n - 1}), dtype=np.intp)


def _place(c: np.ndarray, mask: np.ndarray, n: int, rest: bool) -> np.ndarray | None:
    """Fractional sample indices of ``n`` points evenly spaced in coordinate ``c`` over the
    kept runs of ``mask`` (``c`` strictly increasing); None if the runs have no length."""
    m = np.concatenate([[False], mask, [False]])
    starts = np.flatnonzero(~m[:-1] & m[1:])
    ends = np.flatnonzero(m[:-1] & ~m[1:]) - 1
    lengths = c[ends] - c[starts]
    total = float(lengths.sum())
    if not total > 0:
        return None
    if n == 1:
        pos = np.array([total])
    elif rest:
        pos = total * np.arange(1, n + 1) / n
    else:
        pos = np.linspace(0.0, total, n)
    cum = np.concatenate([[0.0], np.cumsum(lengths)])
    run = np.clip(np.searchsorted(cum[1:], pos, side="left"), 0, starts.size - 1)
    out = np.empty(n)
    for r in np.unique(run):
        a, b = starts[r], ends[r]
        sel = run == r
        cv = np.clip(c[a] + (pos[sel] - cum[r]), c[a], c[b])
        out[sel] = np.interp(cv, c[a : b + 1], np.arange(a, b + 1, dtype=np.float64))
    return out


def _bin_means(t: np.ndarray, e: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    """The path averaged over ``k`` bins of consecutive samples, spanning t[0] to t[-1].

    The ends are extended linearly from the two outer bin means, so the path still
    covers every sample time (the objective's output times among them).
    """
    n = t.size
    k = max(2, min(k, n // 2))
    b = np.arange(n) * k // n
    cnt = np.bincount(b, minlength=k)
    tb = np.bincount(b, weights=t, minlength=k) / cnt
    eb = np.bincount(b, weights=e, minlength=k) / cnt

    def at(x, i, j):
        return eb[i] + (eb[j] - eb[i]) * (x - tb[i]) / (tb[j] - tb[i])

    return (np.concatenate([[t[0]], tb, [t[-1]]]),
            np.concatenate([[at(t[0], 0, 1)], eb, [at(t[-1], k - 2, k - 1)]]))


def _simplify_path(t: np.ndarray, e: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Drop breakpoints of a piecewise-linear path e(t) that move it by at most ``tol``."""
    idx = _simplify_idx(t, e, tol)
    return t[idx], e[idx]


def _simplify_idx(t: np.ndarray, e: np.ndarray, tol: float,
                  limit: int | None = None) -> np.ndarray | None:
    """Indices of the breakpoints kept by :func:`_simplify_path`.

    Douglas–Peucker on the vertical distance; segments shorter than 32 samples that need
    splitting are kept whole, which bounds the work on noisy data. With ``limit``,
    returns None as soon as more than ``limit`` breakpoints would be kept.
    """
    n = t.size
    if n <= 2 or not tol > 0:
        return None if limit is not None and n > limit else np.arange(n)
    keep = np.zeros(n, dtype=bool)
    keep[0] = keep[-1] = True
    kept = 2
    stack = [(0, n - 1)]
    while stack:
        a, b = stack.pop()
        if b - a < 2:
            continue
        tt = t[a : b + 1]
        line = e[a] + (e[b] - e[a]) * (tt - t[a]) / (t[b] - t[a])
        dev = np.abs(e[a : b + 1] - line)
        k = int(np.argmax(dev))
        if dev[k] <= tol:
            continue
        if b - a < 32:
            kept += b - a - 1
            keep[a : b + 1] = True
        else:
            kept += 1
            keep[a + k] = True
            stack.append((a, a + k))
            stack.append((a + k, b))
        if limit is not None and kept > limit:
            return None
    return np.flatnonzero(keep)


# ========================================================= column recognition
_STRESS_UNITS = {
    "": 1.0,
    "mpa": 1.0,
    "n/mm2": 1.0,
    "pa": 1e-6,
    "n/m2": 1e-6,
    "kpa": 1e-3,
    "kn/m2": 1e-3,
    "gpa": 1e3,
    "n/cm2": 1e-2,
    "bar": 0.1,
    "psi": 6.894757293168361e-3,
    "ksi": 6.894757293168361,
    "kgf/cm2": 0.0980665,
    "kg/cm2": 0.0980665,
}
_STRAIN_UNITS = {"": 1.0, "-": 1.0, "1": 1.0, "mm/mm": 1.0, "m/m": 1.0, "in/in": 1.0,
                 "ratio": 1.0, "%": 0.01, "percent": 0.01, "pct": 0.01}
_STRETCH_UNITS = {"": 1.0, "-": 1.0, "1": 1.0, "mm/mm": 1.0, "m/m": 1.0, "ratio": 1.0}
_TIME_UNITS = {"": 1.0, "s": 1.0, "sec": 1.0, "secs": 1.0, "second": 1.0, "seconds": 1.0,
               "ms": 1e-3, "us": 1e-6, "min": 60.0, "mins": 60.0, "h": 3600.0, "hr": 3600.0,
               "hour": 3600.0, "hours": 3600.0}
_RATE_UNITS = {"": 1.0, "1/s": 1.0, "/s": 1.0, "s-1": 1.0, "1/sec": 1.0, "/sec": 1.0,
               "mm/mm/s": 1.0, "1/ms": 1e3, "1/min": 1 / 60, "/min": 1 / 60, "min-1": 1 / 60,
               "1/h": 1 / 3600, "/h": 1 / 3600, "%/s": 0.01, "%/min": 0.01 / 60}
_UNITS = {"stress": _STRESS_UNITS, "strain": _STRAIN_UNITS, "stretch": _STRETCH_UNITS,
          "time": _TIME_UNITS, "rate": _RATE_UNITS}
_UNIT_HINT = {
    "stress": "Pa, kPa, MPa, GPa, N/mm2, psi, kgf/cm2",
    "strain": "none, -, mm/mm or %",
    "stretch": "none",
    "time": "s, ms, min or h",
    "rate": "1/s, 1/min, %/s or %/min",
}

_STRESS_WORDS = {"stress", "sigma", "σ", "spannung"}
_STRAIN_WORDS = {"strain", "epsilon", "eps", "ε", "dehnung"}
_STRETCH_WORDS = {"stretch", "lambda", "λ", "lam", "lambda1", "λ1"}
_TIME_WORDS = {"time", "zeit", "t"}
_RATE_NAMES = {"strainrate", "epsdot", "eps_dot", "de/dt", "dε/dt", "edot"}
_ENG_WORDS = {"engineering", "eng", "nominal", "nom", "piola", "pk1", "first", "1st"}
_TRUE_WORDS = {"true", "cauchy"}
_LOG_WORDS = {"true", "log", "logarithmic", "hencky", "natural"}
_AXIAL_WORDS = {"axial", "uniaxial"}
_ROLE_KEYS = ("strain", "stretch", "stress", "time", "rate")
_GROUP_NAMES = {"curve", "test", "specimen", "name"}


def _norm_unit(u: str) -> str:
    s = u.strip().lower().replace("µ", "u").replace("μ", "u").replace("²", "2")
    s = s.replace("**", "^").replace("^", "").replace(" ", "")
    s = re.sub(r"(^|_)per_", lambda m: "1/" if not m.group(1) else "/", s)
    return s.replace("_", "/")


def _plain(header: str) -> str:
    return header.replace("\ufeff", "").strip().lower()


def _unit_factor(role: str, unit: str) -> float | None:
    return _UNITS[role].get(_norm_unit(unit))


@dataclass
class _Col:
    """What a header says about its column."""

    index: int
    header: str
    role: str  # strain | stretch | stress | time | rate
    rank: float  # lower is a better match
    unit: str  # as written ("" if none)
    kind: str = ""  # strain: "eng" | "log"; stress: "engineering" | "true" | ""


def _split_header(h: str) -> tuple[list[str], str | None]:
    h = h.replace("\ufeff", "").strip().strip("\"'").strip()
    unit = None
    m = re.match(r"^(?P<name>.*?)\s*[\[\(\{](?P<unit>[^\]\)\}]*)[\]\)\}]\s*$", h)
    if m and m["name"]:
        h, unit = m["name"], m["unit"].strip()
    base = re.sub(r"(?<=[a-zα-ω])-(?=[a-zα-ω])", "_", h.lower())
    return [tok for tok in re.split(r"[\s_]+", base) if tok], unit


def _classify(index: int, header: str) -> _Col | None:
    tokens, unit = _split_header(header)
    if not tokens:
        return None
    joined = "_".join(tokens)

    def after_unit(k: int, qualifiers: set[str]) -> tuple[list[str], str]:
        """Qualifier tokens after the keyword, and the unit (bracketed, or the rest)."""
        rest = tokens[k + 1 :]
        if unit is not None:
            return rest, unit
        quals = []
        while rest and rest[0] in qualifiers:
            quals.append(rest.pop(0))
        return quals, "_".join(rest)

    # rate: "strain_rate", "rate [1/s]", "nominal_strain_rate_per_s" (not "..._from_rate")
    if ("rate" in tokens and "from" not in tokens) or joined in _RATE_NAMES:
        k = tokens.index("rate") if "rate" in tokens else len(tokens) - 1
        if any(t in tokens[:k] for t in ("stress", "load", "force", "heating", "sampling")):
            return None
        quals, u = after_unit(k, set())
        return _Col(index, header, "rate", float(k > 0 and tokens[k - 1] not in
                                                 _STRAIN_WORDS | _STRETCH_WORDS | _ENG_WORDS),
                    u)
    # time: "time_s", "t [ms]", "test time (min)"
    for k, tok in enumerate(tokens):
        if tok in _TIME_WORDS and (tok != "t" or k == 0):
            quals, u = after_unit(k, set())
            if tok == "t" and _unit_factor("time", u) is None:
                break
            return _Col(index, header, "time", float(k > 0 or bool(quals)), u)
    for k, tok in enumerate(tokens):
        before = set(tokens[:k])
        if tok in _STRESS_WORDS:
            quals, u = after_unit(k, _ENG_WORDS | _TRUE_WORDS)
            q = before | set(quals)
            kind = ("true" if q & _TRUE_WORDS else "engineering" if q & _ENG_WORDS else "")
            other = q - _ENG_WORDS - _TRUE_WORDS
            return _Col(index, header, "stress", 2.0 if other else 0.0, u, kind)
        if tok in _STRAIN_WORDS:
            quals, u = after_unit(k, _ENG_WORDS | _LOG_WORDS | _AXIAL_WORDS)
            q = before | set(quals)
            kind = "log" if q & _LOG_WORDS else "eng"
            other = q - _ENG_WORDS - _LOG_WORDS - _AXIAL_WORDS
            return _Col(index, header, "strain", 2.0 if other else (1.0 if kind == "log" else 0.0),
                        u, kind)
        if tok in _STRETCH_WORDS:
            rest = tokens[k + 1 :]
            u = unit if unit is not None else ""
            if unit is None and rest and _unit_factor("stretch", "_".join(rest)) is not None:
                rest = []
            other = (before | set(rest)) - _ENG_WORDS - _AXIAL_WORDS
            return _Col(index, header, "stretch", 0.5 + (1.5 if other else 0.0), u)
    return None


@dataclass
class _Plan:
    """Which columns feed a curve, and how to convert them."""

    deform: _Col
    stress: _Col
    time: _Col | None
    rate: _Col | None
    factors: dict[str, float] = field(default_factory=dict)
    measure: str | None = None  # from the header


def _resolve_columns(
    names: list[str],
    columns: Mapping[str, Any] | None,
    units: Mapping[str, str] | None,
    measure: str | None,
    src: str,
) -> _Plan:
    cols = [_classify(j, h) for j, h in enumerate(names)]
    explicit: dict[str, _Col | None] = {}
    for key, val in (columns or {}).items():
        role = _norm_key(key)
        role = {"strain_rate": "rate", "stretch_ratio": "stretch"}.get(role, role)
        if role not in _ROLE_KEYS:
            raise DataError(
                f"{src}: columns={{{key!r}: ...}}: unknown role; use {', '.join(_ROLE_KEYS)}"
            )
        if val is None:
            explicit[role] = None
            continue
        if isinstance(val, (int, np.integer)) and not isinstance(val, bool):
            j = int(val)
            if not 0 <= j < len(names):
                raise DataError(f"{src}: columns={{{key!r}: {j}}}: there are {len(names)} columns")
        else:
            wanted = str(val).strip().lower()
            hits = [j for j, h in enumerate(names) if _plain(h) == wanted]
            if not hits:
                raise DataError(
                    f"{src}: columns={{{key!r}: {val!r}}}: no such column; the header has "
                    f"{', '.join(map(repr, names))}"
                )
            j = hits[0]
        c = cols[j]
        if c is None or c.role != role:
            tokens, u = _split_header(names[j])
            c = _Col(j, names[j], role, 0.0, u if u is not None else "",
                     "eng" if role == "strain" else "")
            if role in ("stress", "time", "rate", "strain") and u is None and len(tokens) > 1:
                # "stress_kPa" mapped by hand: the last token may still be the unit
                if _unit_factor(role, tokens[-1]) is not None:
                    c.unit = tokens[-1]
        explicit[role] = c

    def best(roles: tuple[str, ...], what: str, prefer_measure: str | None = None) -> _Col | None:
        for r in roles:
            if r in explicit:
                return explicit[r]
        cands = [c for c in cols if c is not None and c.role in roles]
        if prefer_measure and what == "stress":
            matching = [c for c in cands if c.kind == prefer_measure]
            if matching:
                cands = matching
            else:
                cands = [c for c in cands if c.kind in ("", prefer_measure)] or cands
        elif what == "stress":
            # default measure: engineering/unqualified before true
            cands = sorted(cands, key=lambda c: (c.rank, c.kind == "true"))
            if cands:
                cands = [c for c in cands if (c.rank, c.kind == "true") ==
                         (cands[0].rank, cands[0].kind == "true")]
        if not cands:
            return None
        top = min(c.rank for c in cands)
        cands = [c for c in cands if c.rank == top]
        if len(cands) > 1 and what == "stress" and all(c.unit for c in cands):
            # the same stress in two units (e.g. kgf/cm2 and MPa): take the MPa one
            mpa = [c for c in cands if _norm_unit(c.unit) in ("mpa", "n/mm2")]
            if len(mpa) == 1:
                cands = mpa
        if len(cands) > 1:
            raise DataError(
                f"{src}: several columns could be the {what}: "
                f"{', '.join(repr(c.header) for c in cands)}: say which with "
                f"columns={{'{roles[0]}': '<header>'}}"
            )
        return cands[0]

    if "strain" in explicit and explicit["strain"] is not None:
        deform = explicit["strain"]
    elif "stretch" in explicit and explicit["stretch"] is not None:
        deform = explicit["stretch"]
    else:
        pool = {r: explicit[r] for r in ("strain", "stretch") if r in explicit}
        roles = tuple(r for r in ("strain", "stretch") if r not in pool)
        deform = best(roles, "strain or stretch") if roles else None
    stress = best(("stress",), "stress", prefer_measure=measure)
    time = best(("time",), "time")
    rate = best(("rate",), "strain rate")
    header_list = ", ".join(map(_short, names[:12])) + (
        f" and {len(names) - 12} more" if len(names) > 12 else "")
    if deform is None:
        raise DataError(
            f"{src}: no strain or stretch column among {header_list}: name one 'strain' "
            "(or 'stretch', 'strain_%'), or pass columns={'strain': '<header>'}"
        )
    if stress is None:
        raise DataError(
            f"{src}: no stress column among {header_list}: name one 'stress_MPa' (or "
            "'stress [kPa]', ...), or pass columns={'stress': '<header>'}; force and "
            "displacement must first be converted with the specimen's area and gauge length"
        )
    plan = _Plan(deform, stress, time, rate)
    for role, col in (("deform", deform), ("stress", stress), ("time", time), ("rate", rate)):
        if col is None:
            continue
        r = col.role
        u = (units or {}).get(r, (units or {}).get("strain_rate") if r == "rate" else None)
        u = col.unit if u is None else u
        f = _unit_factor(r, u)
        if f is None:
            raise DataError(
                f"{src}, column {col.header!r}: unit {u!r} is not understood for {r}: use "
                f"{_UNIT_HINT[r]} (e.g. '{r}_{'MPa' if r == 'stress' else 's'}'), or pass "
                f"units={{'{r}': ...}}"
            )
        plan.factors[role] = f
    if stress.kind:
        plan.measure = stress.kind
    return plan


# ================================================================ table layer
@dataclass
class _Table:
    """A parsed table: column names, row labels, and the cells (split lazily for files)."""

    names: list[str]
    cols: list[np.ndarray] | None  # one per column (str/object or numbers); None until split
    labels: _Labels
    source: str
    meta: dict[str, str]
    lines: list[str] | None = None  # data lines of a file, for lazy splitting
    split_line: Any = None  # line -> fields
    delim: str | None = None
    fast: bool = False  # clean delimited numbers: np.loadtxt may read whole columns
    note: str = ""  # appended to column-recognition errors (e.g. about the encoding)
    _cache: dict[int, np.ndarray] = field(default_factory=dict)

    def label(self, i: int) -> str:
        return self.labels[i]

    @property
    def n_rows(self) -> int:
        return len(self.labels)

    def column(self, j: int) -> np.ndarray:
        if self.cols is None:
            self.cols = self._split_all()
        return self.cols[j]

    def _split_all(self) -> list[np.ndarray]:
        nh = len(self.names)
        assert self.lines is not None
        if self.fast:
            rows = [line.split(self.delim) for line in self.lines]
        else:
            rows = []
            for k, line in enumerate(self.lines):
                f = self.split_line(line)
                if len(f) > nh:
                    if any(x.strip() for x in f[nh:]):
                        sep = {"\t": "tab", None: "whitespace"}.get(self.delim, repr(self.delim))
                        raise DataError(
                            f"{self.source}, {self.label(k)}: {len(f)} fields but the header "
                            f"has {nh} ({sep}-separated): remove the extra values; if ',' is "
                            "the decimal mark, separate the columns with ';' instead"
                        )
                    f = f[:nh]
                elif len(f) < nh:
                    f = f + [""] * (nh - len(f))
                rows.append(f)
        return [np.array(c, dtype=object) for c in zip(*rows)]

    def check_shape(self) -> None:
        """Raise on rows with extra values (whatever columns are used)."""
        if not self.fast and self.lines is not None:
            self.column(0)

    def floats(self, j: int, rows: np.ndarray | None = None, empty: str = "") -> np.ndarray:
        if self.fast and self.cols is None:
            if j not in self._cache:
                try:
                    self._cache[j] = np.loadtxt(
                        self.lines, delimiter=self.delim, usecols=j, dtype=np.float64,
                        comments=None, ndmin=1,
                    )
                except ValueError:
                    self._cache[j] = None  # type: ignore[assignment]
            full = self._cache[j]
            if full is not None and np.isfinite(full).all():
                return full if rows is None else full[rows]
        col = self.column(j)
        sub = col if rows is None else col[rows]
        if sub.dtype.kind == "c":
            raise DataError(f"{self.source}, column {self.names[j]!r}: holds complex numbers: "
                            "give real values")
        if sub.dtype.kind in "iufb":
            arr = sub.astype(np.float64)
        else:
            try:
                if any(isinstance(v, str) and not _plain_number(v) for v in sub):
                    raise ValueError  # float() would take '1_000' and non-ASCII digits
                arr = np.asarray(sub, dtype=np.float64)
            except (TypeError, ValueError):
                arr = self._slow_floats(j, sub, rows, empty)
        bad = ~np.isfinite(arr)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            i = k if rows is None else int(rows[k])
            raise DataError(
                f"{self.source}, {self.label(i)}, column {self.names[j]!r}: value "
                f"{_short(str(sub[k]).strip())} is not a finite number: repair or delete that row"
            )
        return arr

    def _slow_floats(
        self, j: int, sub: np.ndarray, rows: np.ndarray | None, empty: str = ""
    ) -> np.ndarray:
        out = np.empty(len(sub))
        for k, v in enumerate(sub):
            s = "" if v is None else str(v).strip().strip("\"'").strip()
            try:
                if not _plain_number(s):
                    raise ValueError(s)
                out[k] = float(s)
                continue
            except ValueError:
                pass
            if s.count(",") == 1 and "." not in s and _plain_number(s):
                try:  # decimal comma
                    out[k] = float(s.replace(",", "."))
                    continue
                except ValueError:
                    pass
            i = k if rows is None else int(rows[k])
            if s == "" and empty:
                raise DataError(f"{self.source}, {self.label(i)}, column {self.names[j]!r}: "
                                f"{empty}")
            what = "is empty" if s == "" else f"{_short(s)} is not a number"
            if s == "":
                fix = "fill it in or delete the row"
            elif re.search(r"\d", s):
                fix = "use '.' or ',' as the decimal mark consistently, or fix or delete the row"
            else:
                fix = "delete that row (text among the numbers) or fix it"
            raise DataError(f"{self.source}, {self.label(i)}, column {self.names[j]!r}: {what}: "
                            f"{fix}")
        return out

    def texts(self, j: int) -> np.ndarray:
        return np.array([str(v).strip() for v in self.column(j)], dtype=object)


#: Spreadsheet error cells (#DIV/0!, #N/A, ...) start a data row with '#': not a comment.
_EXCEL_ERROR = re.compile(r"#(DIV/0!|N/A|VALUE!|REF!|NAME\?|NUM!|NULL!|GETTING_DATA)", re.I)

_META_RE = re.compile(r"^#+\s*(?P<key>[A-Za-z_][\w \-]*?)\s*[:=]\s*(?P<val>.*?)\s*$")


_LATIN1_NOTE = (" (the file is not UTF-8 and was read as Latin-1: if the names look garbled, "
                "pass encoding=..., e.g. encoding='gbk')")


def _decode(raw: bytes, src: str, encoding: str | None) -> tuple[str, str]:
    """The text of a file, and a note for messages if it was a guess."""
    if encoding is not None:
        try:
            return raw.decode(encoding), ""
        except (UnicodeDecodeError, LookupError) as exc:
            raise DataError(
                f"{src}: cannot decode as {encoding!r} ({exc}): check encoding="
            ) from None
    if raw.startswith(b"PK\x03\x04") or raw.startswith(b"\xd0\xcf\x11\xe0"):
        raise DataError(
            f"{src}: is a spreadsheet (xlsx/xls), not a CSV file: save it as CSV first"
        )
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            return raw.decode("utf-16"), ""
        except UnicodeDecodeError as exc:
            raise DataError(f"{src}: is not valid UTF-16 text ({exc.reason}): the file looks "
                            "truncated or damaged; save it again as CSV") from None
    if raw.startswith(codecs.BOM_UTF8):
        raw = raw[3:]
    head = raw[:4096]
    if b"\x00" in head:
        if head[1::2].count(0) > 0.9 * len(head[1::2]):
            return raw.decode("utf-16-le", errors="replace"), ""
        if head[0::2].count(0) > 0.9 * len(head[0::2]):
            return raw.decode("utf-16-be", errors="replace"), ""
        raise DataError(f"{src}: is not a text file (binary data): give a CSV text file")
    try:
        return raw.decode("utf-8"), ""
    except UnicodeDecodeError:
        return raw.decode("latin-1"), _LATIN1_NOTE  # never fails; numbers are ASCII anyway


def _short(name: str, width: int = 40) -> str:
    """repr of a column name for a message, cut to ``width`` characters."""
    r = repr(name)
    return r if len(r) <= width else r[: width - 4] + "...'"


def _plain_number(s: str) -> bool:
    """Python's float() also takes '1_000' and non-ASCII digits: a CSV number does not."""
    return "_" not in s and s.isascii()


def _is_number(s: str) -> bool:
    s = s.strip().strip("\"'")
    try:
        float(s)
        return True
    except ValueError:
        return bool(re.fullmatch(r"[+-]?\d*,\d+([eE][+-]?\d+)?", s))


def _read_table(
    path: Any, names: Sequence[str] | None, encoding: str | None
) -> _Table:
    if hasattr(path, "read"):
        src = str(getattr(path, "name", "<stream>"))
        content = path.read()
        text, note = (content, "") if isinstance(content, str) else _decode(content, src,
                                                                              encoding)
    else:
        p = Path(path)
        src = str(path)
        if not p.exists():
            raise DataError(f"{src}: no such file: check the path")
        if p.is_dir():
            raise DataError(
                f"{src}: is a directory, not a CSV file: pass its files, e.g. "
                f"read_csv(sorted(Path({src!r}).glob('*.csv')))"
            )
        try:
            raw = p.read_bytes()
        except OSError as exc:
            raise DataError(f"{src}: cannot be read ({exc.strerror}): check permissions") from None
        text, note = _decode(raw, src, encoding)
    lines = text.splitlines()
    meta: dict[str, str] = {}
    header: str | None = None
    header_no = 0
    forced: str | None = None
    for no, line in enumerate(lines, 1):
        s = line.strip()
        if not s:
            continue
        if s.startswith("#"):
            m = _META_RE.match(s)
            if m:
                meta[_norm_key(m["key"])] = m["val"]
            continue
        m = re.fullmatch(r'"?sep=(.)"?', s, flags=re.IGNORECASE)
        if m:  # Excel's separator hint
            forced = m.group(1)
            continue
        header, header_no = line, no
        break
    if header is None:
        raise DataError(f"{src}: is empty (no header, no data): give a CSV file with a header "
                        "row such as 'strain,stress_MPa' and one row per sample")
    rest = lines[header_no:]
    if all(rest) and not any(map(str.isspace, rest)) and "#" not in text.partition(header)[2]:
        data: list[str] = rest  # the common case, checked at C speed: every line is data
        numbers: Any = np.arange(header_no + 1, header_no + 1 + len(rest))
    else:
        data, numbers = [], []
        for no, line in enumerate(rest, header_no + 1):
            s = line.strip()
            if s and (not s.startswith("#") or _EXCEL_ERROR.match(s)):
                data.append(line)
                numbers.append(no)
    delim = forced or next((d for d in ("\t", ";", ",", "|") if d in header), None)

    def split(line: str) -> list[str]:
        if delim is None:
            return line.split()
        return next(csv.reader([line], delimiter=delim, skipinitialspace=True))

    head = [h.strip() for h in split(header)]
    if all(_is_number(h) for h in head if h):
        if names is None:
            raise DataError(
                f"{src}, line {header_no}: the first line holds numbers, not column names: add "
                "a header row (e.g. 'strain,stress_MPa') or pass names=[...]"
            )
        data = [header, *data]
        numbers = np.concatenate([[header_no], np.asarray(numbers, dtype=np.int64)])
    if names is None and data:
        first = split(data[0])
        if any(f.strip() for f in first) and not any(_is_number(f) for f in first if f.strip()):
            # a second header line with the units ("s", "mm", "[N]"): fold it into the names
            units = [u.strip().strip("[](){}").strip() for u in first] + [""] * len(head)
            head = [f"{h} [{u}]" if u and not re.search(r"[\[\(\{]", h) else h
                    for h, u in zip(head, units)]
            data = data[1:]
            numbers = np.asarray(numbers, dtype=np.int64)[1:]
    if names is not None:
        head = [str(n) for n in names]
    if len(head) < 2:
        raise DataError(
            f"{src}, line {header_no}: the header has one column ({_short(head[0])}): separate the "
            "strain and stress columns by ',', ';' or tabs"
        )
    if not data:
        raise DataError(f"{src}: has a header but no data rows: the curve is empty; add the "
                        "data rows under the header (one row per sample)")
    nh = len(head)
    fast = (delim is not None and '"' not in text and "'" not in text
            and set(map(operator.methodcaller("count", delim), data)) == {nh - 1})
    table = _Table(head, None, _Labels(numbers, "line"), src, meta, lines=data,
                   split_line=split, delim=delim, fast=fast, note=note)
    table.check_shape()
    return table


def _table_from_data(data: Any, names: Sequence[str] | None, source: str | None) -> _Table:
    src = source or type(data).__name__
    if isinstance(data, Mapping):
        head = [str(k) for k in data]
        cols = [np.asarray(v).reshape(-1) for v in data.values()]
        if len({c.size for c in cols}) > 1:
            sizes = ", ".join(f"{h}: {c.size}" for h, c in zip(head, cols))
            raise DataError(f"{src}: columns have different lengths ({sizes}): give one value "
                            "per sample in every column")
        return _Table(head if names is None else list(names), cols,
                      _Labels(np.arange(cols[0].size if cols else 0), "row"), src, {})
    arr_names = None
    if hasattr(data, "to_numpy") and not isinstance(data, np.ndarray):
        arr = np.asarray(data.to_numpy())
        if hasattr(data, "columns"):
            arr_names = [str(c) for c in list(data.columns)]
    else:
        try:
            arr = np.asarray(data)
        except ValueError:
            raise DataError(f"{src}: the rows have different numbers of values: give every row "
                            "the same columns (a value for each)") from None
        if arr.dtype.names:
            head = list(arr.dtype.names)
            return _Table(head if names is None else list(names),
                          [np.asarray(arr[h]).reshape(-1) for h in head],
                          _Labels(np.arange(arr.size), "row"), src, {})
    if arr.ndim != 2:
        raise DataError(f"{src}: expected a 2-D table (rows x columns), got shape {arr.shape}: "
                        "pass np.column_stack([strain, stress]) or a mapping of columns")
    head = list(names) if names is not None else arr_names
    if head is None:
        if arr.shape[1] == 2:
            head = ["strain", "stress"]
        elif arr.shape[0] == 2 and arr.shape[1] > 2:
            raise DataError(f"{src}: got shape {arr.shape} (2 rows): samples must be rows; pass "
                            "np.column_stack([strain, stress])")
        else:
            raise DataError(f"{src}: {arr.shape[1]} unnamed columns: name them with "
                            "names=['time_s', 'strain', 'stress_MPa', ...]")
    if len(head) != arr.shape[1]:
        raise DataError(f"{src}: {len(head)} names for {arr.shape[1]} columns: give one name per "
                        "column")
    return _Table([str(h) for h in head], [arr[:, j] for j in range(arr.shape[1])],
                  _Labels(np.arange(arr.shape[0]), "row"), src, {})


# ================================================================ table -> curves
_META_KEYS = {
    "strain_rate": "rate", "rate": "rate", "nominal_strain_rate": "rate",
    "engineering_strain_rate": "rate", "measure": "measure", "stress_measure": "measure",
    "mode": "mode", "loading_mode": "mode", "name": "name", "curve": "name",
    "weight": "weight", "compression_positive": "compression_positive",
}


def _meta_rate(val: str, src: str) -> float:
    m = re.fullmatch(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*",
                     val.replace(",", "."))
    f = None if m is None else _unit_factor("rate", m.group(2))
    if m is None or f is None:
        raise DataError(f"{src}: '# strain_rate: {val}' is not a rate: write e.g. "
                        "'# strain_rate: -100' (1/s) or '# strain_rate: -6000 1/min'")
    return float(m.group(1)) * f


def _meta_bool(val: str, src: str, key: str) -> bool:
    v = val.strip().lower()
    if v in ("1", "true", "yes", "y", "on"):
        return True
    if v in ("0", "false", "no", "n", "off"):
        return False
    raise DataError(f"{src}: '# {key}: {val}': write true or false")


def _curves_from_table(
    table: _Table,
    *,
    rate: float | None,
    measure: str | None,
    mode: str | None,
    compression_positive: bool | None,
    columns: Mapping[str, Any] | None,
    units: Mapping[str, str] | None,
    group_by: str | Sequence[str] | None,
    select: Mapping[str, Any] | None,
    sort: bool,
    n_points: int | None,
    by: str | None,
    name: str | None,
) -> list[Curve]:
    src = table.source
    meta = dict(table.meta)
    known = {_META_KEYS[k]: v for k, v in meta.items() if k in _META_KEYS}
    units = dict(units or {})
    for k, v in meta.items():
        if k.endswith("_unit") and k[:-5] in _UNITS and k[:-5] not in units:
            units[k[:-5]] = v
    if measure is None and "measure" in known:
        measure = known["measure"]
    meas = None if measure is None else _norm_measure(measure, _Where(src, None, None))
    try:
        plan = _resolve_columns(table.names, columns, units, meas, src)
    except DataError as exc:
        if not table.note:
            raise
        raise DataError(f"{exc}{table.note}") from None
    if meas is not None and plan.measure is not None and plan.measure != meas:
        raise DataError(
            f"{src}, column {plan.stress.header!r}: the header says {plan.measure} stress but "
            f"measure={meas!r} was given: drop measure=, or name the right column with "
            "columns={'stress': ...}"
        )
    meas = meas or plan.measure or "engineering"
    if mode is None and "mode" in known:
        mode = known["mode"]
    if compression_positive is None:
        compression_positive = (_meta_bool(known["compression_positive"], src,
                                           "compression_positive")
                                if "compression_positive" in known else False)
    try:
        weight = float(known["weight"]) if "weight" in known else 1.0
    except ValueError:
        raise DataError(f"{src}: '# weight: {known['weight']}' is not a number: write e.g. "
                        "'# weight: 2'") from None
    meta_rate = _meta_rate(known["rate"], src) if "rate" in known else None

    def col_index(h: str) -> int:
        want = str(h).strip().lower()
        for j, nm in enumerate(table.names):
            if _plain(nm) == want:
                return j
        raise DataError(f"{src}: no column {h!r}; the header has "
                        f"{', '.join(map(repr, table.names))}")

    rows = np.arange(table.n_rows)
    for h, want in (select or {}).items():
        j = col_index(h)
        wants = want if isinstance(want, (list, tuple, set)) else [want]
        vals = table.texts(j)[rows]
        ok = np.zeros(rows.size, dtype=bool)
        for w in wants:
            if isinstance(w, (int, float)) and not isinstance(w, bool):
                ok |= np.array([_try_float(v) for v in vals]) == float(w)
            else:
                ok |= np.array([v.lower() == str(w).strip().lower() for v in vals], dtype=bool)
        rows = rows[ok]
        if rows.size == 0:
            raise DataError(f"{src}: select={{{h!r}: {want!r}}} keeps no rows; the column holds "
                            f"{', '.join(sorted(set(map(str, vals)))[:6])}")
    # ---- rate column
    rate_vals = None
    if plan.rate is not None:
        rate_vals = table.floats(
            plan.rate.index, rows,
            empty="the strain rate is missing: fill it in (1/s, negative in compression), or "
                  "ignore the column with columns={'rate': None}",
        ) * plan.factors["rate"]
    # ---- groups
    gcols: list[int] = []
    if group_by is not None:
        gcols = [col_index(g) for g in ([group_by] if isinstance(group_by, str) else group_by)]
    else:
        for j, h in enumerate(table.names):
            toks, _ = _split_header(h)
            if len(toks) == 1 and toks[0] in _GROUP_NAMES:
                if len(set(table.texts(j)[rows])) > 1:
                    gcols.append(j)
    key_cols = [table.texts(j)[rows] for j in gcols]
    use_rate_key = (rate_vals is not None and rate is None
                    and plan.rate.index not in gcols and len(np.unique(rate_vals)) > 1)
    if use_rate_key:
        uniq, first_k, counts = np.unique(rate_vals, return_index=True, return_counts=True)
        if counts.min() < 2:
            k = int(first_k[np.argmin(counts)])
            raise DataError(
                f"{src}, column {plan.rate.header!r}: {uniq.size} different rates in "
                f"{rows.size} rows, {table.label(int(rows[k]))} alone at {rate_vals[k]:g}: if "
                "this is a measured rate channel, not the nominal rate of each test, ignore "
                "it with columns={'rate': None} (and give rate= or a time column); otherwise "
                "give each rate at least 2 rows"
            )
        key_cols.append(np.array([f"{v:.12g}" for v in rate_vals], dtype=object))
    if key_cols:
        combo = np.array(["\x1f".join(map(str, t)) for t in zip(*key_cols)], dtype=object)
        _, first, inv = np.unique(combo, return_index=True, return_inverse=True)
        order = np.argsort(first)
        groups = [np.flatnonzero(inv == g) for g in order]
    else:
        groups = [np.arange(rows.size)]
    if rate is not None and rate_vals is not None and len(np.unique(rate_vals)) > 1:
        raise DataError(
            f"{src}, column {plan.rate.header!r}: holds {len(np.unique(rate_vals))} different "
            f"rates but rate={rate!r} was given: drop rate= to get one curve per rate"
        )
    stem = Path(src).stem if src and not src.startswith("<") else (src or "data")
    out = []
    for g in groups:
        r = rows[g]
        gname_parts = [str(kc[g[0]]) for kc in key_cols[: len(gcols)]]
        if rate_vals is not None:
            gr = rate_vals[g]
            if np.ptp(gr) != 0:
                k = int(np.flatnonzero(gr != gr[0])[0])
                raise DataError(
                    f"{src}, {table.label(int(r[k]))}, column {plan.rate.header!r}: the rate "
                    f"changes from {gr[0]:g} to {gr[k]:g} inside one curve: give each test its "
                    "own rate, or a 'test' column to tell them apart"
                )
        crate = rate if rate is not None else (
            float(rate_vals[g][0]) if rate_vals is not None else meta_rate)
        if use_rate_key:
            gname_parts.append(f"rate {rate_vals[g][0]:g}/s")
        if name is not None:
            cname = name if len(groups) == 1 else f"{name} [{', '.join(gname_parts)}]"
        elif "name" in known and len(groups) == 1:
            cname = known["name"]
        else:
            cname = stem if not gname_parts else f"{stem} [{', '.join(gname_parts)}]"
        where = _Where(cname, src, None)
        if crate is None and plan.time is None:
            raise DataError(
                f"{where()}: no strain rate and no time column: add a 'strain_rate' column, "
                "a '# strain_rate: -100' line (1/s, negative in compression), or pass rate=..."
            )
        d = table.floats(plan.deform.index, r) * plan.factors["deform"]
        if plan.deform.role == "stretch":
            d = d - 1.0
        elif plan.deform.kind == "log":
            d = np.expm1(d)
        s = table.floats(plan.stress.index, r) * plan.factors["stress"]
        t = None
        if plan.time is not None:
            t = table.floats(plan.time.index, r) * plan.factors["time"]
        labels = table.labels[r]
        if sort:
            key = t if t is not None else np.abs(d)
            o = np.argsort(key, kind="stable")
            d, s, labels = d[o], s[o], labels[o]
            t = None if t is None else t[o]
        cmeta = dict(meta)
        if gname_parts:
            cmeta["group"] = ", ".join(gname_parts)
        cmeta["columns"] = {
            "strain": plan.deform.header, "stress": plan.stress.header,
            "time": None if plan.time is None else plan.time.header,
            "rate": None if plan.rate is None else plan.rate.header,
        }
        out.append(Curve(
            d, s, strain_rate=crate, time=t, measure=meas, mode=mode, name=cname,
            weight=weight, n_points=n_points, by=by, compression_positive=compression_positive,
            source=src, rows=labels, metadata=cmeta,
        ))
    return out


def _try_float(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return float("nan")


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

