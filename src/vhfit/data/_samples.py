"""The measured samples of a curve: the checks and inferences of ``Curve(...)``, in order.

Each step is a function of the samples so far that returns them checked, cleaned or
re-signed: the front-door checks of the arguments, merging duplicate samples, the
loading mode and the signs of strain, rate and stress (compression is negative,
docs/theory.md §1), the kinematic checks, and the nominal rate of a time history.
:class:`vhfit.data.Curve` runs them one after the other.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from vhfit._words import setting
from vhfit.data._errors import DataError, _norm_mode, _warn, _Where
from vhfit.data._paths import _estimate_rate

#: Strains of the "wrong" sign smaller than this fraction of max |strain| are noise (a
#: load-cell or extensometer offset), not a change of loading mode.
SIGN_RTOL = 0.01

# The warnings below are issued two calls deep (step <- Curve.__init__), one deeper than
# when these steps were inline, so they name the same frame as before.
_STACK = 5


def _default_name(name: str | None, strain_rate: Any) -> str:
    """The name of a curve; an unnamed one is named by its rate, as reports list curves."""
    if name is None:
        try:
            r = float(strain_rate)
            name = f"{r:g} 1/s" if np.isfinite(r) else "curve"
        except (TypeError, ValueError):
            name = "curve"
    return str(name)


def _sample_arrays(
    where: _Where, strain: Any, stress: Any, time: Any, rows: Sequence[Any] | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Strain, stress and time as finite 1-D float arrays of one length (at least 2)."""
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
    return eps, sig, t


def _check_weight(weight: Any, where: _Where) -> float:
    try:
        weight = float(weight)
    except (TypeError, ValueError):
        raise DataError(f"{where()}: {setting(f'weight={weight!r}', 'its weight')} is not a "
                        "number: give a number >= 0") from None
    if not (np.isfinite(weight) and weight >= 0):
        raise DataError(f"{where()}: {setting(f'weight={weight!r}', 'its weight')}: give a "
                        "finite weight >= 0")
    return weight


def _parse_rate_value(value: Any, where: _Where) -> float:
    try:
        r = float(value)
    except (TypeError, ValueError):
        raise DataError(
            f"{where()}: {setting(f'strain_rate={value!r}', f'--rate {value}')} is not a "
            "number: give it in 1/s"
        ) from None
    if not np.isfinite(r) or r == 0.0:
        raise DataError(
            f"{where()}: {setting(f'strain_rate={value!r}', f'--rate {value}')}: give a "
            "finite, non-zero rate in 1/s (negative in compression)"
        )
    return r


def _check_deformed(eps: np.ndarray, where: _Where) -> None:
    if not np.any(eps):
        raise DataError(
            f"{where()}: strain is 0 at every sample: nothing was deformed; check that "
            "the strain (or stretch) column is the right one"
        )


# ------------------------------------------------------------ duplicates and order
def _clean_samples(eps, sig, t, where, equilibrium=False, e2=None, s2=None):
    """Samples with duplicates merged: (strain, stress, time, index of each kept sample,
    second strain, second stress). Equilibrium samples are kept as they are: repeated
    states are repeated measurements, and their order means nothing."""
    keep = np.arange(eps.size)
    if equilibrium:
        return eps, sig, t, keep, e2, s2
    if t is not None:
        t0 = t
        eps, sig, t, keep = _clean_time_series(eps, sig, t, keep, where)
        if keep.size < t0.size:  # samples at one time: the second path merged alike
            e2, s2 = _merge_second(t0, keep, e2, s2, where)
    else:
        eps, sig, keep = _clean_rate_series(eps, sig, keep, where)
        e2 = None if e2 is None else e2[keep]
        s2 = None if s2 is None else s2[keep]
    if eps.size < 2:
        raise DataError(
            f"{where()}: only one distinct sample remains after merging duplicates: a "
            "curve needs at least 2; give the test's other samples"
        )
    return eps, sig, t, keep, e2, s2


def _merge_second(t, keep, e2, s2, where):
    """λ2 − 1 and stress2 of samples merged by time: λ2 must agree, stress2 is averaged."""
    dup = np.diff(t) == 0
    grp = np.concatenate([[0], np.cumsum(~dup)])
    if e2 is not None:
        _check_same_time(t, e2, dup, np.arange(t.size), "second strains", where)
        e2 = e2[keep]
    if s2 is not None:
        s2 = np.bincount(grp, weights=s2) / np.bincount(grp)
    return e2, s2


def _check_same_time(t, x, dup, keep, what, where):
    """Samples at one time (``dup``) must agree in ``x`` (a strain)."""
    bad = dup & (np.diff(x) != 0)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise DataError(
            f"{where(keep[k + 1])}: two samples at the same time ({t[k]:g} s) have "
            f"different {what} ({x[k]:g} and {x[k + 1]:g}): fix the time column (more "
            "digits) or drop one of them"
        )


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
                   "it, or ignore it (read_csv(..., columns={'time': None}, rate=...); command "
                   "line: --columns time= --rate R)")
        else:
            fix = ("sort the rows by time with " + setting("read_csv(..., sort=True)", "--sort")
                   + "; "
                   "if the file holds "
                   "several tests, give each its own curve (a 'test' column)")
        raise DataError(
            f"{where(keep[k + 1])}: time goes back from {t[k]:g} to {t[k + 1]:g} s: {fix}"
        )
    dup = dt == 0
    if dup.any():
        _check_same_time(t, eps, dup, keep, "strains", where)
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


# ----------------------------------------------------------------- signs and mode
def _sign_tolerance(eps: np.ndarray, where: _Where) -> float:
    """Strains of the other sign below this are noise (``SIGN_RTOL`` of the largest)."""
    scale = float(np.abs(eps).max())
    if scale == 0.0:
        raise DataError(
            f"{where()}: strain is 0 at every sample: nothing was deformed; check that "
            "the strain (or stretch) column is the right one"
        )
    return SIGN_RTOL * scale


def _sign_class(eps: np.ndarray, tol: float) -> str:
    pos = bool(eps.min() >= -tol)
    neg = bool(eps.max() <= tol)
    if pos and not neg:
        return "tension"
    if neg and not pos:
        return "compression"
    return "mixed"


def _loading_mode(eps, sig, rate, mode, compression_positive, tol, keep, where, guess=True):
    """(strain, stress, mode): the declared mode checked against the strain's signs, or the
    mode inferred from them (with ``guess``, a tension-signed strain with a negative rate
    is compression given as magnitudes: negated, with a warning)."""
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
                f"declared {setting(f'mode={mode!r}', mode)} (compression is negative): "
                + setting("pass compression_positive=True", "give compression as negative "
                          "strain") + " if compression is given as positive numbers, "
                "or correct the mode"
            )
        return eps, sig, mode
    if guess and rate is not None and cls == "tension" and rate < 0:
        _warn(
            f"{where()}: strain is >= 0 but strain_rate = {rate:g} < 0: took this as a "
            "compression test given as positive magnitudes and negated strain and "
            "stress (say compression_positive=True to silence this, or give a "
            "positive rate for a tension test)", _STACK
        )
        return -eps, -sig, "compression"
    return eps, sig, cls


def _mode_sign(mode: str) -> float | None:
    """-1 for compression, +1 for tension, None for mixed."""
    return {"compression": -1.0, "tension": 1.0}.get(mode)


def _rate_with_sign(rate, mode, compression_positive, where):
    """The rate with the sign of the loading mode (a magnitude given as the rate is fixed,
    with a warning unless compression_positive says so)."""
    sgn = _mode_sign(mode)
    if rate is not None and sgn is not None and np.sign(rate) != sgn:
        if not compression_positive:
            _warn(
                f"{where()}: strain_rate = {rate:g} has the sign of "
                f"{'tension' if rate > 0 else 'compression'} but the strain is in {mode}: "
                f"took strain_rate = {-rate:g} (compression is negative)", _STACK
            )
        rate = -rate
    return rate


def _check_one_sign_at_constant_rate(eps, t, mode, tol, keep, where, equilibrium=False):
    if t is None and mode == "mixed" and not equilibrium:
        major = np.sign(eps[np.argmax(np.abs(eps))])
        k = int(np.flatnonzero(eps * major < -tol)[0])
        raise DataError(
            f"{where(keep[k])}: strain changes sign (strain = {eps[k]:g} here) but a "
            "constant-rate ramp from strain 0 only reaches one sign: give the time "
            "column, or split the curve at strain 0"
        )


def _stress_with_sign(sig, mode, declared, keep, where):
    """The stress with the sign of the loading mode at its largest magnitude: an error if
    the mode or sign convention was declared, else negated with a warning."""
    sgn = _mode_sign(mode)
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
                "given as magnitudes and negated it", _STACK
            )
    return sig


# --------------------------------------------------------------- kinematic checks
def _check_kinematics(eps, t, rate, keep, where, shear=False):
    """A constant-rate curve is monotonic in the rate's direction; every stretch is > 0
    (``shear``: the strain is an amount of shear γ, of any value)."""
    if t is None and rate is not None:
        d = np.diff(eps) * np.sign(rate)
        if (d < 0).any():
            k = int(np.flatnonzero(d < 0)[0])
            raise DataError(
                f"{where(keep[k + 1])}: strain goes back from {eps[k]:g} to {eps[k + 1]:g}: "
                "a constant-rate curve must be monotonic; if this test loads and unloads "
                "give its time column, if the rows are out of order sort them with "
                + setting("read_csv(..., sort=True)", "--sort")
            )
    if not shear and (eps <= -1.0).any():
        k = int(np.flatnonzero(eps <= -1.0)[0])
        raise DataError(
            f"{where(keep[k])}: strain = {eps[k]:g} means a stretch 1 + strain <= 0: "
            "give engineering strain (> -1), or a stretch column"
        )


def _nominal_rate(t, eps, mode, tol, where) -> float:
    """The rate of a time history given none: see ``Curve.strain_rate``."""
    rate = _estimate_rate(t, eps, _mode_sign(mode), tol)
    if not (np.isfinite(rate) and rate != 0.0):
        raise DataError(
            f"{where()}: the strain never changes with time: no loading to fit"
        )
    return rate
