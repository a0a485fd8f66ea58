"""Can the data tell elastic from viscous response? The guard behind the default N.

A Prony series is identified only when the curves show the material's memory: tests
at clearly different rates, a hold or an unloading, rate tests beside equilibrium
(fully relaxed) curves, which fix the long-term law on their own, or a frequency sweep
or relaxation test. A single monotonic
test at one rate is fitted just as well by a stiffer elastic law as by any Prony
series, so its "relaxation times" are noise and its g∞ drifts to the floor: by
default such data get no Prony terms, with the reason in one line (docs/theory.md
§11).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from vhfit.data import is_moduli

__all__ = ["DEFAULT_N_PRONY", "RATE_RATIO", "viscous_evidence", "default_n_prony"]

#: Prony terms fitted by default when the data can identify them.
DEFAULT_N_PRONY = 2
#: Nominal rates closer than this ratio count as one rate (scatter between repeats).
RATE_RATIO = 1.25


def _is_equilibrium(curve) -> bool:
    return bool(curve.is_equilibrium)


def _distinct_rates(rates: Sequence[float]) -> int:
    """Number of groups of nominal |rates| that differ by more than ``RATE_RATIO``."""
    r = np.sort(np.abs(np.asarray(rates, dtype=np.float64)))
    r = r[np.isfinite(r) & (r > 0)]
    if r.size == 0:
        return 0
    return 1 + int(np.count_nonzero(r[1:] > RATE_RATIO * r[:-1]))


def viscous_evidence(curves: Sequence) -> str | None:
    """Why these curves cannot separate elastic from viscous response, or None if they can.

    Parameters
    ----------
    curves : sequence of Curve

    Returns
    -------
    str or None
        One line saying what the data lack (None: a Prony series is identifiable).

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> eps = np.linspace(-0.05, -0.5, 10)
    >>> slow = vhfit.Curve(strain=eps, stress=eps, strain_rate=-0.01)
    >>> fast = vhfit.Curve(strain=eps, stress=3 * eps, strain_rate=-100.0)
    >>> viscous_evidence([slow, fast]) is None
    True
    >>> viscous_evidence([slow])
    'one strain rate (0.01 1/s) and monotonic loading, no hold or unloading'
    """
    if any(is_moduli(c) for c in curves):
        return None  # a frequency sweep's loss modulus or a relaxation test shows memory
    rated = [c for c in curves if not _is_equilibrium(c)]
    if not rated:
        return "only equilibrium (rate-free) curves, which carry no viscous response"
    if len(rated) < len(curves):
        return None  # the equilibrium curves fix the long-term law, the others the rest
    if any(int(c.n_segments) > 1 for c in rated):
        return None  # a hold or an unloading shows relaxation or hysteresis
    rates = [float(c.strain_rate) for c in rated]
    if _distinct_rates(rates) > 1:
        return None
    return (
        f"one strain rate ({abs(rates[0]):.3g} 1/s) and monotonic loading, no hold or "
        "unloading"
    )


def default_n_prony(curves: Sequence) -> tuple[int, str | None]:
    """The number of Prony terms fitted when the user gives none, and why if 0.

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> eps = np.linspace(-0.05, -0.5, 10)
    >>> default_n_prony([vhfit.Curve(strain=eps, stress=eps, strain_rate=-1.0)])[0]
    0
    """
    reason = viscous_evidence(curves)
    return (0, reason) if reason else (DEFAULT_N_PRONY, None)
