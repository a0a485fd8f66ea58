"""Hyperelastic strain energies, their registry, and the uniaxial stress they give.

A model is a plain function of the kinematics and its constants, written as the
formula, and registered by name::

    @register("gent")
    def gent(I1, I2, mu, Jm):
        "W = -mu Jm / 2 ln(1 - (I1 - 3) / Jm)"
        return -mu * Jm / 2 * np.log(1 - (I1 - 3) / Jm)

Invariant models take ``(I1, I2, *constants)``; principal-stretch models take
``(l1, l2, l3, *constants)``. The derivatives the stress needs are taken by the
complex step (exact to rounding for any energy written with numpy's analytic
functions) unless the model gives them. On the incompressible uniaxial path
λ1 = λ, λ2 = λ3 = λ^(-1/2) (docs/theory.md §1–2):

* invariant models: σ_h = 2 (λ² − 1/λ) (∂W/∂I1 + ∂W/∂I2 / λ)
* stretch models:   σ_h = λ1 ∂W/∂λ1 − λ2 ∂W/∂λ2

Stresses are true (Cauchy), in MPa.
"""

from __future__ import annotations

# importing _laws registers the built-in laws
from vhfit.hyperelastic import _laws  # noqa: F401
from vhfit.hyperelastic._registry import (
    Hyperelastic,
    available,
    get,
    invariants,
    register,
    unregister,
)

__all__ = [
    "Hyperelastic",
    "register",
    "get",
    "available",
    "unregister",
    "invariants",
]
