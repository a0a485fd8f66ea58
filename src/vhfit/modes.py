"""Kinematics and long-term stresses of every homogeneous incompressible test (docs/theory.md §13).

A test is named by its ``deformation``:

* ``"uniaxial"``     λ1 = λ, λ2 = λ3 = λ^(−1/2)
* ``"equibiaxial"``  λ1 = λ2 = λ, λ3 = λ^(−2)
* ``"planar"``       λ1 = λ, λ2 = 1, λ3 = 1/λ (pure shear)
* ``"biaxial"``      λ1, λ2 both prescribed, λ3 = 1/(λ1 λ2)
* ``"simple_shear"`` F = I + γ e1⊗e2 (principal stretches λ, 1/λ, 1 with
  λ = γ/2 + sqrt(1 + γ²/4)); out of plane stress-free.

The long-term (hyperelastic) Kirchhoff stress of an incompressible isotropic law is
known up to a pressure: τ_k = λ_k ∂W/∂λ_k in principal axes, or for W(I1, I2)
τ = 2 (W1 + I1 W2) B − 2 W2 B². The measured true stress in a loaded direction a is
σ_a = τ_a − τ_c (c the stress-free direction: 3, and 2 ≡ 3 in uniaxial), the nominal
stress P_a = σ_a / λ_a; in simple shear σ12 = τ12 = P12.

Every function takes the law's constants as an array (..., n_params): leading axes are
parameter sets, and the results have shape (..., m) for m stretches.
"""

from __future__ import annotations

import numpy as np

from vhfit._derivatives import invariant_gradient, outside_domain, stretch_gradient
from vhfit.hyperelastic import Hyperelastic

__all__ = ["DEFORMATIONS", "principal_stretches", "kirchhoff_stress", "shear_kirchhoff_stress",
           "long_term_stress"]

#: Names of the homogeneous tests.
DEFORMATIONS = ("uniaxial", "equibiaxial", "planar", "biaxial", "simple_shear")
#: Tests with a second loaded direction (``direction=2``).
TWO_DIRECTIONS = ("equibiaxial", "biaxial")


def check_deformation(deformation) -> str:
    """The deformation name, or a one-line error listing the valid ones."""
    if not isinstance(deformation, str) or deformation not in DEFORMATIONS:
        raise ValueError(
            f"deformation = {deformation!r} is unknown: choose one of {', '.join(DEFORMATIONS)}"
        )
    return deformation


def check_direction(deformation: str, direction) -> int:
    """1, or 2 for a test with a second loaded direction; else a one-line error."""
    if isinstance(direction, bool) or direction not in (1, 2):
        raise ValueError(f"direction = {direction!r} must be 1 or 2")
    if direction == 2 and deformation not in TWO_DIRECTIONS:
        raise ValueError(
            f"direction = 2 needs a second loaded direction: {deformation!r} has none "
            f"(only {' and '.join(TWO_DIRECTIONS)} do); use direction = 1"
        )
    return int(direction)


def principal_stretches(deformation: str, x1, x2=None):
    """Principal stretches (λ1, λ2, λ3) of a test, λ1 λ2 λ3 = 1.

    Parameters
    ----------
    deformation : str
        One of :data:`DEFORMATIONS`.
    x1 : array_like
        The stretch λ1, or the amount of shear γ in simple shear.
    x2 : array_like, optional
        The stretch λ2 (biaxial only).

    Returns
    -------
    l1, l2, l3 : ndarray
        In simple shear the principal stretches of B, ordered (λ, 1/λ, 1).

    Examples
    --------
    >>> [float(v) for v in principal_stretches("equibiaxial", 2.0)]
    [2.0, 2.0, 0.25]
    >>> [round(float(v), 12) for v in principal_stretches("simple_shear", 1.5)]
    [2.0, 0.5, 1.0]
    """
    x1 = np.asarray(x1, dtype=np.float64)
    one = np.ones_like(x1)
    if deformation == "uniaxial":
        return x1, x1**-0.5, x1**-0.5
    if deformation == "equibiaxial":
        return x1, x1, x1**-2.0
    if deformation == "planar":
        return x1, one, 1.0 / x1
    if deformation == "biaxial":
        x2 = np.asarray(x2, dtype=np.float64)
        return x1, x2, 1.0 / (x1 * x2)
    if deformation == "simple_shear":
        a = np.arcsinh(0.5 * x1)  # ln λ, exact for either sign of γ (no cancellation)
        return np.exp(a), np.exp(-a), one
    check_deformation(deformation)
    raise AssertionError  # pragma: no cover


def constant_columns(model: Hyperelastic, params) -> list[np.ndarray]:
    """The law's constants (..., n_params) as columns (..., 1) that broadcast over stretches."""
    p = np.asarray(params, dtype=np.float64)
    if p.ndim == 0 or p.shape[-1] != model.n_params:
        raise ValueError(
            f"params: model {model.name!r} takes {model.n_params} constants "
            f"{list(model.param_names)}, got shape {p.shape}"
        )
    return [p[..., k, None] for k in range(model.n_params)]


def _kirchhoff(model: Hyperelastic, cols, l1, l2, l3):
    if model.kind == "invariant":
        a = (l1 * l1, l2 * l2, l3 * l3)
        I1 = a[0] + a[1] + a[2]
        I2 = a[0] * a[1] + a[1] * a[2] + a[2] * a[0]
        W1, W2 = invariant_gradient(model.energy, model.derivatives, I1, I2, cols)
        return tuple(2.0 * W1 * ak + 2.0 * W2 * (I1 * ak - ak * ak) for ak in a)
    if model.derivatives is not None:  # closed form (λ1 ∂W/∂λ1, λ2 ∂W/∂λ2, λ3 ∂W/∂λ3)
        return tuple(model.derivatives(l1, l2, l3, *cols))
    bad = outside_domain(model.energy, l1, l2, l3, *cols)
    return tuple(np.where(bad, np.nan, t) for t in stretch_gradient(model.energy, l1, l2, l3, cols))


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
    return _kirchhoff(model, cols, *(np.asarray(v, dtype=np.float64) for v in (l1, l2, l3)))


def _shear(model: Hyperelastic, cols, gamma):
    g = np.asarray(gamma, dtype=np.float64)
    if model.kind == "invariant":
        I = 3.0 + g * g  # I1 = I2 in simple shear
        W1, W2 = invariant_gradient(model.energy, model.derivatives, I, I, cols)
        A = 2.0 * (W1 + I * W2)
        b11 = 1.0 + g * g
        return (A * b11 - 2.0 * W2 * (b11 * b11 + g * g), A - 2.0 * W2 * b11, A - 2.0 * W2,
                2.0 * g * (W1 + W2))
    # principal values rotated into the (1, 2) frame: the eigenvector of B for λ² is
    # (1, 1/λ), so cos²θ = λ²/(1 + λ²) and sin²θ = 1/(1 + λ²), no division by γ
    la, lb, one = principal_stretches("simple_shear", g)
    ta, tb, t3 = _kirchhoff(model, cols, la, lb, one)
    q = 1.0 / (1.0 + la * la)
    return ((la * la * ta + tb) * q, (ta + la * la * tb) * q, t3, (ta - tb) * la * q)


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
    return _shear(model, constant_columns(model, params), gamma)


def long_term_coefficients(deformation: str, x1, x2=None, direction: int = 1):
    """(I1, I2, p, q) with σ = W1 p + W2 q for an invariant law W(I1, I2).

    σ_a = τ_a − τ_c = (λ_a² − λ_c²) (2 W1 + 2 W2 λ_b²), b the third direction;
    simple shear: σ12 = 2γ (W1 + W2). The kinematic part of :func:`long_term_stress`,
    computed once per history.
    """
    x1 = np.asarray(x1, dtype=np.float64)
    if deformation == "simple_shear":
        inv = 3.0 + x1 * x1
        return inv, inv, 2.0 * x1, 2.0 * x1
    a = [lk * lk for lk in principal_stretches(deformation, x1, x2)]
    I1 = a[0] + a[1] + a[2]
    I2 = a[0] * a[1] + a[1] * a[2] + a[2] * a[0]
    k = direction - 1
    p = 2.0 * (a[k] - a[2])
    return I1, I2, p, p * a[1 - k]


def long_term_stress(model: Hyperelastic, params, deformation: str, x1, x2=None,
                     direction: int = 1, coefficients=None):
    """Measured true stress of the long-term law: σ_a = τ_a − τ_c, or σ12 in simple shear.

    Parameters
    ----------
    model : Hyperelastic
    params : array_like, (n_params,) or (..., n_params)
    deformation : str
        One of :data:`DEFORMATIONS`.
    x1, x2 : array_like
        λ1 (γ in simple shear) and, for biaxial, λ2.
    direction : {1, 2}
        The loaded direction a (2: equibiaxial or biaxial only).
    coefficients : tuple, optional
        :func:`long_term_coefficients` of the same arguments, if already computed
        (invariant laws, not uniaxial).

    Returns
    -------
    ndarray, (..., m)
        True stress in MPa (divide by λ_a for the nominal stress).

    Examples
    --------
    >>> from vhfit import hyperelastic
    >>> nh = hyperelastic.get("neo_hooke")       # equibiaxial: 2 C10 (λ² − λ⁻⁴)
    >>> float(long_term_stress(nh, [0.5], "equibiaxial", [2.0])[0])
    3.9375
    """
    check_deformation(deformation)
    check_direction(deformation, direction)
    cols = constant_columns(model, params)
    x1 = np.asarray(x1, dtype=np.float64)
    if deformation == "uniaxial":
        return model.stress(x1, params)
    if model.kind == "invariant":
        I1, I2, p, q = (coefficients if coefficients is not None
                        else long_term_coefficients(deformation, x1, x2, direction))
        W1, W2 = invariant_gradient(model.energy, model.derivatives, I1, I2, cols)
        return W1 * p + W2 * q + 0.0 * cols[0]
    if deformation == "simple_shear":
        return _shear(model, cols, x1)[3] + 0.0 * cols[0]
    tau = _kirchhoff(model, cols, *principal_stretches(deformation, x1, x2))
    return tau[direction - 1] - tau[2] + 0.0 * cols[0]


def loaded_stretch(deformation: str, x1, x2=None, direction: int = 1) -> np.ndarray:
    """λ_a of the loaded direction (nominal = true / λ_a); 1 in simple shear."""
    if deformation == "simple_shear":
        return np.ones_like(np.asarray(x1, dtype=np.float64))
    return np.asarray(principal_stretches(deformation, x1, x2)[direction - 1], dtype=np.float64)


def hereditary_weights(deformation: str, x1, x2=None, direction: int = 1) -> np.ndarray:
    """c_k(t) of the factorised pushed-forward kernel K(u, t) = Σ_k c_k(t) f_k(u), (2, m).

    Principal axes: c = (λ_a², −λ_c²); simple shear: c = (1, γ) (docs/theory.md §13).
    """
    x1 = np.asarray(x1, dtype=np.float64)
    if deformation == "simple_shear":
        return np.stack([np.ones_like(x1), x1])
    lam = principal_stretches(deformation, x1, x2)
    return np.stack([lam[direction - 1] ** 2, -(lam[2] ** 2)])


def invariant_coefficients(deformation: str, x1, x2=None, direction: int = 1):
    """(I1, I2, coef) with f_k = (2/E∞)(W1 coef[2k] + W2 coef[2k + 1]) for W(I1, I2).

    The kinematic part of :func:`hereditary_factors` for an invariant law, computed
    once per history. Principal axes, with a_k = λ_k², b_k = I1 a_k − a_k² and bars for
    means over k: f_a = (2 W1 (a_a − ā) + 2 W2 (b_a − b̄)) / (E∞ a_a), likewise f_c.
    Simple shear (S = dev τ, I1 = I2 = 3 + γ²): S12 = 2γ (W1 + W2) and
    S22 = −(2/3) γ² (W1 + 2 W2).
    """
    x1 = np.asarray(x1, dtype=np.float64)
    if deformation == "simple_shear":
        g2 = x1 * x1
        inv = 3.0 + g2
        coef = np.stack([x1 + x1 * g2 / 3.0, x1 + 2.0 * x1 * g2 / 3.0, -g2 / 3.0,
                         -2.0 * g2 / 3.0])
        return inv, inv, coef
    a = [lk * lk for lk in principal_stretches(deformation, x1, x2)]
    I1 = a[0] + a[1] + a[2]
    I2 = a[0] * a[1] + a[1] * a[2] + a[2] * a[0]
    b = [I1 * ak - ak * ak for ak in a]
    a_bar, b_bar = I1 / 3.0, (b[0] + b[1] + b[2]) / 3.0
    k = direction - 1
    coef = np.stack([(a[k] - a_bar) / a[k], (b[k] - b_bar) / a[k],
                     (a[2] - a_bar) / a[2], (b[2] - b_bar) / a[2]])
    return I1, I2, coef


def hereditary_factors(model: Hyperelastic, params, E_inf, deformation: str, x1, x2=None,
                       direction: int = 1, coefficients=None) -> tuple[np.ndarray, np.ndarray]:
    """f_k(u) of the factorised kernel, per unit E∞: two arrays (P, m).

    Principal axes: f = (d_a/λ_a², d_c/λ_c²)/E∞ with d = dev τ; simple shear:
    f = ((S12 − γ S22), S22)/E∞ with S = dev τ (docs/theory.md §13). NaN where the
    energy is undefined. ``coefficients``: :func:`invariant_coefficients` of the same
    arguments, if already computed (invariant laws only).
    """
    cols = constant_columns(model, params)
    x1 = np.asarray(x1, dtype=np.float64)
    E = np.asarray(E_inf, dtype=np.float64)[..., None]
    if model.kind == "invariant":
        I1, I2, c = (coefficients if coefficients is not None
                     else invariant_coefficients(deformation, x1, x2, direction))
        W1, W2 = invariant_gradient(model.energy, model.derivatives, I1, I2, cols)
        W1, W2 = 2.0 * W1 / E, 2.0 * W2 / E  # (P, 1) for constant derivatives: cheap
        f0, f1 = W1 * c[0] + W2 * c[1], W1 * c[2] + W2 * c[3]
    elif deformation == "simple_shear":
        t11, t22, t33, t12 = _shear(model, cols, x1)
        s22 = (2.0 * t22 - t11 - t33) / 3.0
        f0, f1 = (t12 - x1 * s22) / E, s22 / E
    else:
        lam = principal_stretches(deformation, x1, x2)
        tau = _kirchhoff(model, cols, *lam)
        mean = (tau[0] + tau[1] + tau[2]) / 3.0
        a = direction - 1
        f0 = (tau[a] - mean) / (E * lam[a] ** 2)
        f1 = (tau[2] - mean) / (E * lam[2] ** 2)
    shape = np.broadcast_shapes(np.shape(f0), np.shape(f1), E.shape[:-1] + x1.shape)
    return tuple(f if np.shape(f) == shape else np.broadcast_to(f, shape).copy()
                 for f in (f0, f1))
