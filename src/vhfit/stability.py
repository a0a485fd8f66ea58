"""Drucker stability of a hyperelastic law in the one-stretch homogeneous test modes.

For an incompressible material Drucker's condition dτ : dε > 0 (Kirchhoff stress,
logarithmic strain) reduces, in each of the modes used to check hyperelastic fits (the
registered tests whose record says ``drucker``: uniaxial and the sheet tests, in tension
and compression), to a positive tangent of the mode's loaded principal stress difference
against ln λ1: d(σ1 − σ3)/d ln λ1 > 0, with the principal stretches of the test's record
(:meth:`vhfit.modes.Deformation.stretches`).

Scaling all moduli by a positive factor does not change stability, so the long-term
and instantaneous (= long-term / g∞) laws of a Prony model are stable together.

The range checked is either the loaded stretch λ of every mode (``principal=False``)
or, as a calibration states it, a range of *principal* stretches: each mode is checked
over the loaded stretches whose principal stretches all stay inside it
(:func:`mode_range`; equibiaxial tension at λ has λ3 = λ⁻², so principal stretches in
[0.3, 8.8] bound it to 0.34 <= λ <= 1.83). A law undefined somewhere in the range (past
a locking stretch) has no positive tangent there: unstable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vhfit._derivatives import invariant_gradient, stretch_gradient
from vhfit.hyperelastic import Hyperelastic
from vhfit.modes import constant_columns, get_deformation, registered_deformations

__all__ = ["drucker", "StabilityReport", "mode_range"]


def modes_checked() -> tuple[str, ...]:
    """The registered tests whose tangent is checked (``Deformation.drucker``)."""
    return tuple(n for n in registered_deformations() if get_deformation(n).drucker)


#: The tests checked when vhfit is imported (the built-in ones; plug-ins add theirs).
MODES = modes_checked()


def principal_difference(model: Hyperelastic, params, l1, l2, l3) -> np.ndarray:
    """σ1 − σ3 (true stress, MPa) of an incompressible hyperelastic law.

    With the pressure eliminated, σa − σb = λa ∂W/∂λa − λb ∂W/∂λb; for an invariant
    energy that is 2 W1 (λ1² − λ3²) + 2 W2 (I1 (λ1² − λ3²) − (λ1⁴ − λ3⁴)).

    Examples
    --------
    >>> from vhfit import hyperelastic
    >>> nh = hyperelastic.get("neo_hooke")          # σ1 − σ3 = 2 C10 (λ1² − λ3²)
    >>> float(principal_difference(nh, [0.5], 2.0, 2.0**-0.5, 2.0**-0.5)[0])
    3.5
    """
    cols = constant_columns(model, params)
    if model.kind == "invariant":
        I1 = l1**2 + l2**2 + l3**2
        I2 = (l1 * l2) ** 2 + (l2 * l3) ** 2 + (l3 * l1) ** 2
        W1, W2 = invariant_gradient(model.energy, model.derivatives, I1, I2, cols)
        a, c = l1**2, l3**2
        return 2 * W1 * (a - c) + 2 * W2 * (I1 * (a - c) - (a**2 - c**2))
    d1, d3 = stretch_gradient(model.energy, l1, l2, l3, cols, axes=(0, 2),
                              closed_form=model.derivatives)
    return d1 - d3


def mode_range(mode: str, stretch_range) -> tuple[float, float]:
    """The loaded stretches λ of a test whose principal stretches all lie in a range.

    The widest interval around λ = 1 over which every principal stretch of the test's
    record (:meth:`vhfit.modes.Deformation.stretches`) stays within ``stretch_range``,
    found by bisection in ln λ (the principal stretches of a one-stretch test move
    monotonically away from 1 with |ln λ|).

    Examples
    --------
    >>> lo, hi = mode_range("equibiaxial", (0.25, 4.0))   # λ3 = λ⁻² reaches 1/4 at λ = 2
    >>> round(lo, 9), round(hi, 9)
    (0.5, 2.0)
    >>> [round(v, 9) for v in mode_range("uniaxial", (0.25, 4.0))]  # λ2 = λ^(-1/2)
    [0.25, 4.0]
    """
    lo, hi = map(float, stretch_range)
    stretches = get_deformation(mode).stretches

    def inside(u: float) -> bool:
        with np.errstate(all="ignore"):
            ls = stretches(np.array([math.exp(u)]), None)
        return all(lo * (1 - 1e-12) <= float(np.reshape(v, -1)[0]) <= hi * (1 + 1e-12)
                   for v in ls)

    ends = []
    for edge in (math.log(lo), math.log(hi)):  # λ1 itself is a principal stretch
        if inside(edge):
            ends.append(math.exp(edge))
            continue
        a, b = 0.0, edge  # inside at a, outside at b
        for _ in range(60):
            m = 0.5 * (a + b)
            a, b = (m, b) if inside(m) else (a, m)
        ends.append(math.exp(a))
    return ends[0], ends[1]


@dataclass(frozen=True)
class StabilityReport:
    """Where a hyperelastic law violates Drucker's condition.

    Attributes
    ----------
    stable : bool
        True when every mode is stable over the whole checked range.
    stretch_range : (float, float)
        The checked range of λ.
    unstable : dict
        Mode -> list of (λ_lo, λ_hi) intervals where the tangent is not positive.
    principal : bool
        Whether ``stretch_range`` bounds every principal stretch (each mode checked over
        :func:`mode_range`) rather than the loaded stretch of each mode.
    """

    stable: bool
    stretch_range: tuple[float, float]
    unstable: dict
    principal: bool = False

    def describe(self) -> str:
        """One line: stable over the checked range, or the unstable intervals per mode.

        Examples
        --------
        >>> StabilityReport(True, (0.2, 5.0), {}).describe()  # doctest: +ELLIPSIS
        'Drucker-stable in uniaxial, ... modes for 0.2 <= λ <= 5'
        >>> StabilityReport(False, (0.2, 5.0), {"uniaxial": [(0.2, 0.498)]}).describe()
        'Drucker-UNSTABLE in uniaxial: 0.2 <= λ <= 0.498'
        """
        lo, hi = self.stretch_range
        if self.stable:
            names = modes_checked()
            listed = ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else names[0]
            return f"Drucker-stable in {listed} modes for {lo:g} <= λ <= {hi:g}"
        parts = [
            f"{mode}: " + ", ".join(f"{a:.3g} <= λ <= {b:.3g}" for a, b in iv)
            for mode, iv in self.unstable.items()
        ]
        return "Drucker-UNSTABLE in " + "; ".join(parts)


def drucker(model: Hyperelastic, params, stretch_range=(0.2, 5.0), n: int = 400,
            principal: bool = False) -> StabilityReport:
    """Check Drucker stability of a hyperelastic law over a stretch range.

    Parameters
    ----------
    model : Hyperelastic
    params : array_like
        The law's constants.
    stretch_range : (float, float)
        λ range checked in every mode (λ = 1 excluded from nothing: the tangent there
        is the initial modulus).
    n : int
        Number of stretches, log-spaced (per mode).
    principal : bool
        ``stretch_range`` bounds every principal stretch: each mode is checked over its
        :func:`mode_range` (a calibration's statement); else it is the loaded stretch of
        every mode.

    Returns
    -------
    StabilityReport

    Examples
    --------
    >>> from vhfit import hyperelastic
    >>> drucker(hyperelastic.get("mooney_rivlin"), [0.1, 0.05]).stable
    True
    >>> drucker(hyperelastic.get("mooney_rivlin"), [0.1, -0.2]).stable
    False
    """
    lo, hi = map(float, stretch_range)
    if not 0 < lo < 1 < hi:
        raise ValueError(f"stretch_range = {stretch_range!r} must satisfy 0 < lo < 1 < hi")
    d = 1e-4
    unstable: dict[str, list[tuple[float, float]]] = {}
    for mode in modes_checked():
        a, b = mode_range(mode, (lo, hi)) if principal else (lo, hi)
        lam = np.exp(np.linspace(np.log(a), np.log(b), n))
        stretches = get_deformation(mode).stretches
        with np.errstate(all="ignore"):
            up = principal_difference(model, params, *stretches(lam * np.exp(d), None))
            dn = principal_difference(model, params, *stretches(lam * np.exp(-d), None))
        tangent = np.reshape((up - dn) / (2 * d), -1)
        bad = ~(tangent > 0)
        if bad.any():
            edges = np.flatnonzero(np.diff(np.concatenate([[0], bad.astype(int), [0]])))
            unstable[mode] = [
                (float(lam[a]), float(lam[b - 1])) for a, b in zip(edges[::2], edges[1::2])
            ]
    return StabilityReport(not unstable, (lo, hi), unstable, principal)
