"""Hyperelastic strain energies, their registry, and the uniaxial stress they give.

A model is a plain function of the kinematics and its constants, written as the
formula, and registered by name (Gent is built in as ``"gent"``; this is how it reads)::

    @register("my_gent", units=("MPa", "1"), linear_params=("mu",))
    def my_gent(I1, I2, mu, Jm):
        "W = -mu Jm / 2 ln(1 - (I1 - 3) / Jm)"
        return -mu * Jm / 2 * np.log(1 - (I1 - 3) / Jm)

``linear_params`` names the constants the stress is linear in (checked at
registration); the separable calibration solves those by least squares.
Built in: mooney_rivlin, neo_hooke, yeoh, polynomial2, polynomial3,
reduced_polynomial1..6, ogden..ogden6, arruda_boyce, gent, van_der_waals
(docs/theory.md §2).

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
