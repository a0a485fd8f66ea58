"""The long-term Kirchhoff stress of a hyperelastic law in principal axes and in simple shear.

The part of the homogeneous tests (:mod:`vhfit.modes`) that evaluates the law: every
function takes the law's constants as an array (..., n_params), leading axes parameter
sets, and gives results of shape (..., m) for m stretches.
"""

from __future__ import annotations

import numpy as np

from vhfit import _kernels
from vhfit._derivatives import invariant_gradient, outside_domain, stretch_gradient
from vhfit._fixed import remembered
from vhfit.hyperelastic import Hyperelastic


def constant_columns(model: Hyperelastic, params) -> list[np.ndarray]:
    """The law's constants (..., n_params) as columns (..., 1) that broadcast over stretches."""
    p = np.asarray(params, dtype=np.float64)
    if p.ndim == 0 or p.shape[-1] != model.n_params:
        raise ValueError(
            f"params: model {model.name!r} takes {model.n_params} constants "
            f"{list(model.param_names)}, got shape {p.shape}"
        )
    return [p[..., k, None] for k in range(model.n_params)]


def principal_kirchhoff(model: Hyperelastic, cols, l1, l2, l3):
    if model.kind == "invariant":
        a = (l1 * l1, l2 * l2, l3 * l3)
        I1 = a[0] + a[1] + a[2]
        I2 = a[0] * a[1] + a[1] * a[2] + a[2] * a[0]
        W1, W2 = invariant_gradient(model.energy, model.derivatives, I1, I2, cols)
        return tuple(2.0 * W1 * ak + 2.0 * W2 * (I1 * ak - ak * ak) for ak in a)
    closed = model.kirchhoff_derivatives
    t = stretch_gradient(model.energy, l1, l2, l3, cols, closed_form=closed)
    if closed is not None:  # the closed form is used as it is
        return tuple(t)
    bad = outside_domain(model.energy, l1, l2, l3, *cols)
    return tuple(np.where(bad, np.nan, x) for x in t)


def kirchhoff_stress(model: Hyperelastic, params, l1, l2, l3):
    """Principal Kirchhoff stresses (τ1, τ2, τ3) of the long-term law, up to one pressure.

    τ_k = λ_k ∂W/∂λ_k; for W(I1, I2), τ_k = 2 W1 λ_k² + 2 W2 (I1 λ_k² − λ_k⁴).
    Only differences τ_a − τ_b, and the deviator, are meaningful. NaN where the energy
    is undefined.

    Examples
    --------
    >>> from vhfit import hyperelastic
    >>> nh = hyperelastic.get("neo_hooke")               # τ_k = 2 C10 λ_k²
    >>> [float(t[0]) for t in kirchhoff_stress(nh, [0.5], 2.0, 1.0, 0.5)]
    [4.0, 1.0, 0.25]
    """
    cols = constant_columns(model, params)
    lam = (np.asarray(v, dtype=np.float64) for v in (l1, l2, l3))
    return principal_kirchhoff(model, cols, *lam)


def shear_kirchhoff(model: Hyperelastic, cols, gamma):
    g = np.asarray(gamma, dtype=np.float64)
    if model.kind == "invariant":
        I = 3.0 + g * g  # I1 = I2 in simple shear
        W1, W2 = invariant_gradient(model.energy, model.derivatives, I, I, cols)
        A = 2.0 * (W1 + I * W2)
        b11 = 1.0 + g * g
        return (A * b11 - 2.0 * W2 * (b11 * b11 + g * g), A - 2.0 * W2 * b11, A - 2.0 * W2,
                2.0 * g * (W1 + W2))
    la, lb, one, la2, q = shear_frame(g)
    ta, tb, t3 = principal_kirchhoff(model, cols, la, lb, one)
    return ((la2 * ta + tb) * q, (ta + la2 * tb) * q, t3, (ta - tb) * la * q)


def shear_factors(model: Hyperelastic, cols, E, gamma):
    """f = ((S12 − γ S22), S22)/E∞ of simple shear, S = dev τ, for a law in principal
    stretches: its τ at the stretches of the frame (:func:`shear_frame`), combined by a
    compiled pass (:func:`vhfit._kernels.shear_factors`) when they are a population's
    (P, m) arrays, by numpy otherwise; the same arithmetic either way."""
    g = np.asarray(gamma, dtype=np.float64)
    if model.kind != "invariant":
        la, lb, one, la2, q = shear_frame(g)
        ta, tb, t3 = principal_kirchhoff(model, cols, la, lb, one)
        fused = _kernels.shear_factors(ta, tb, t3, g, la, la2, q, E)
        if fused is not None:
            return fused
    t11, t22, t33, t12 = shear_kirchhoff(model, cols, g)
    s22 = (2.0 * t22 - t11 - t33) / 3.0
    return (t12 - g * s22) / E, s22 / E


def shear_frame(gamma: np.ndarray) -> tuple[np.ndarray, ...]:
    """Principal stretches λ, 1/λ, 1 of simple shear and the rotation into its (1, 2)
    frame (λ², 1/(1 + λ²)).

    The eigenvector of B for λ² is (1, 1/λ), so cos²θ = λ²/(1 + λ²) and
    sin²θ = 1/(1 + λ²): no division by γ. They depend on the data alone: for a γ that
    cannot change (an evaluation plan's samples) they are computed once and kept,
    read-only, so that what the law derives from them is kept too
    (:mod:`vhfit._fixed`: the Ogden sums' logarithms).

    Examples
    --------
    >>> [round(float(v[0]), 12) for v in shear_frame(np.array([1.5]))]
    [2.0, 0.5, 1.0, 4.0, 0.2]
    """
    def frame():
        a = np.arcsinh(0.5 * gamma)  # ln λ, exact for either sign of γ (no cancellation)
        la, lb, one = np.exp(a), np.exp(-a), np.ones_like(gamma)
        out = tuple(np.asarray(v) for v in (la, lb, one, la * la, 1.0 / (1.0 + la * la)))
        for v in out:
            v.flags.writeable = False
        return out

    return remembered("shear frame", (gamma,), frame)


def shear_kirchhoff_stress(model: Hyperelastic, params, gamma):
    """Kirchhoff stress (τ11, τ22, τ33, τ12) of the long-term law in simple shear.

    F = I + γ e1⊗e2; τ11, τ22, τ33 share one undetermined pressure (σ33 = 0 fixes it:
    the measured normal stresses are τ11 − τ33 and τ22 − τ33); τ12 = σ12.

    Examples
    --------
    >>> from vhfit import hyperelastic
    >>> mr = hyperelastic.get("mooney_rivlin")           # σ12 = 2 (C10 + C01) γ
    >>> float(shear_kirchhoff_stress(mr, [0.3, 0.1], 0.5)[3][0])
    0.4
    """
    return shear_kirchhoff(model, constant_columns(model, params), gamma)
