"""Every homogeneous incompressible test as a record, and its kinematics (docs/theory.md §13).

A test is a :class:`Deformation` record, registered by name (``@register_deformation``)
like the hyperelastic laws and the viscoelastic formulations; a curve, a history or a
model names it by its ``deformation`` string, and every other module asks the record
(:func:`get_deformation`) instead of testing the name. The built-in tests:

* ``"uniaxial"``     λ1 = λ, λ2 = λ3 = λ^(−1/2)
* ``"equibiaxial"``  λ1 = λ2 = λ, λ3 = λ^(−2)
* ``"planar"``       λ1 = λ, λ2 = 1, λ3 = 1/λ (pure shear)
* ``"biaxial"``      λ1, λ2 both prescribed, λ3 = 1/(λ1 λ2)
* ``"simple_shear"`` F = I + γ e1⊗e2 (principal stretches λ, 1/λ, 1 with
  λ = γ/2 + sqrt(1 + γ²/4)); out of plane stress-free.

Two tests that change the volume are registered too, so that a file or a curve can name
them and every incompressible law refuses them in one line (:func:`refusal_for`) instead
of fitting them as something else:

* ``"confined_compression"`` λ1 = λ, λ2 = λ3 = 1 (uniaxial strain, J = λ)
* ``"volumetric"``           λ1 = λ2 = λ3 = λ (hydrostatic, J = λ³)

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

from vhfit._deformation import (  # the record and its registry, re-exported
    NOISE_WORDS,  # noqa: F401
    Deformation,
    check_deformation,
    check_direction,
    deformation_mentioned,
    deformation_named,
    get_deformation,
    log_uniform,
    refusal_for,
    register_deformation,
    registered_deformations,
    unregister_deformation,
    with_second_stretch,  # noqa: F401
    with_two_directions,  # noqa: F401
)
from vhfit._derivatives import invariant_gradient
from vhfit._kirchhoff import (
    constant_columns,
    kirchhoff_stress,
    shear_factors,
    shear_kirchhoff,
    shear_kirchhoff_stress,
)
from vhfit.hyperelastic import Hyperelastic

__all__ = ["Deformation", "register_deformation", "get_deformation", "unregister_deformation",
           "registered_deformations", "deformation_named", "deformation_mentioned",
           "refusal_for", "DEFORMATIONS",
           "principal_stretches", "kirchhoff_stress", "shear_kirchhoff_stress",
           "long_term_stress"]


# ------------------------------------------------------------ the built-in tests
@register_deformation("uniaxial", aliases=("ut", "uc"))
class Uniaxial(Deformation):
    """The paper's test: λ1 = λ, λ2 = λ3 = λ^(−1/2)."""

    description = "uniaxial tension or compression: λ, λ^(−1/2), λ^(−1/2)"
    uniaxial = True
    drucker = True
    standard_test = "uniaxial"

    def stretches(self, x1, x2=None):
        return x1, x1**-0.5, x1**-0.5


@register_deformation("equibiaxial", aliases=("equi_biaxial", "eb", "et", "ebt",
                                              "balanced_biaxial"))
class Equibiaxial(Deformation):
    """Equibiaxial tension of a sheet: λ1 = λ2 = λ, λ3 = λ^(−2)."""

    description = "equibiaxial: λ, λ, λ^(−2)"
    measured = ("σ11", "σ22")
    step_power = 2.0  # ln λ3 = −2 ln λ
    signed = True
    drucker = True
    standard_test = "equibiaxial"

    def stretches(self, x1, x2=None):
        return x1, x1, x1**-2.0


@register_deformation("planar", aliases=("pure_shear", "ps", "pt"))
class Planar(Deformation):
    """Planar tension (pure shear): λ1 = λ, λ2 = 1 held, λ3 = 1/λ."""

    description = "planar (pure shear): λ, 1, 1/λ"
    signed = True
    drucker = True
    standard_test = "planar"

    def stretches(self, x1, x2=None):
        return x1, np.ones_like(x1), 1.0 / x1


@register_deformation("biaxial", aliases=("general_biaxial",))
class Biaxial(Deformation):
    """General biaxial test: λ1 and λ2 both prescribed, λ3 = 1/(λ1 λ2)."""

    description = "general biaxial: λ1, λ2, 1/(λ1 λ2)"
    second_stretch = True
    measured = ("σ11", "σ22")

    def stretches(self, x1, x2=None):
        x2 = np.asarray(x2, dtype=np.float64)
        return x1, x2, 1.0 / (x1 * x2)

    def steps(self, a, b, x1, x2, dlog):
        """λ1 and λ2 are both linear in t: the union of the nodes uniform in ln λ1 and in
        ln λ2 at dlog/2 bounds both steps by dlog/2, so ln λ3 = −ln λ1 − ln λ2 changes by
        at most dlog."""
        tt = [log_uniform(a, b, x1[0], x1[1], 0.5 * dlog),
              log_uniform(a, b, x2[0], x2[1], 0.5 * dlog)]
        return np.unique(np.concatenate([x for x in tt if x.size] or [np.array([b])]))


@register_deformation("simple_shear", aliases=("shear", "ss"))
class SimpleShear(Deformation):
    """Simple shear F = I + γ e1⊗e2, out of plane stress-free; measures σ12 = P12.

    Not in principal axes: the kinematic methods are its own (docs/theory.md §13).
    """

    description = "simple shear: F = I + γ e1⊗e2"
    shear = True
    measured = ("σ12",)
    signed = True
    rest = 0.0
    strain_label = "amount of shear γ"
    stress_label = "shear stress σ12 (MPa)"

    def stretches(self, x1, x2=None):
        a = np.arcsinh(0.5 * x1)  # ln λ, exact for either sign of γ (no cancellation)
        return np.exp(a), np.exp(-a), np.ones_like(x1)

    def loaded_stretch(self, x1, x2=None, direction=1):
        return np.ones_like(np.asarray(x1, dtype=np.float64))

    def path(self, strain):
        return strain.copy()

    def strain(self, path):
        return path

    def steps(self, a, b, x1, x2, dlog):
        """Steps of at most dlog in γ, uniform in t (γ is linear in t)."""
        m = max(1, int(np.ceil(abs(x1[1] - x1[0]) / dlog)))
        return a + np.linspace(0.0, 1.0, m + 1)[1:] * (b - a)

    def long_term_coefficients(self, x1, x2=None, direction=1):
        """σ12 = 2γ (W1 + W2), I1 = I2 = 3 + γ²."""
        x1 = np.asarray(x1, dtype=np.float64)
        inv = 3.0 + x1 * x1
        return inv, inv, 2.0 * x1, 2.0 * x1

    def stretch_law_stress(self, model, cols, x1, x2=None, direction=1):
        return shear_kirchhoff(model, cols, x1)[3]

    def weights(self, x1, x2=None, direction=1):
        """c = (1, γ)."""
        x1 = np.asarray(x1, dtype=np.float64)
        return np.stack([np.ones_like(x1), x1])

    def invariant_coefficients(self, x1, x2=None, direction=1):
        """S = dev τ, I1 = I2 = 3 + γ²: S12 = 2γ (W1 + W2), S22 = −(2/3) γ² (W1 + 2 W2)."""
        x1 = np.asarray(x1, dtype=np.float64)
        g2 = x1 * x1
        inv = 3.0 + g2
        coef = np.stack([x1 + x1 * g2 / 3.0, x1 + 2.0 * x1 * g2 / 3.0, -g2 / 3.0,
                         -2.0 * g2 / 3.0])
        return inv, inv, coef

    def kirchhoff_factors(self, model, cols, E, x1, x2=None, direction=1):
        """f = ((S12 − γ S22), S22)/E∞ with S = dev τ."""
        return shear_factors(model, cols, E, x1)

    def green_factors(self, x1, x2=None, direction=1, deviatoric=False):
        """E = (FᵀF − I)/2: E12 = γ/2, E22 = γ²/2 and tr E = γ²/2; the weights (1, γ)
        then give σ12 = S12 + γ S22 (docs/theory.md §14)."""
        x1 = np.asarray(x1, dtype=np.float64)
        e22 = 0.5 * x1 * x1
        if deviatoric:
            e22 = e22 - e22 / 3.0
        return x1 / 3.0, (2.0 / 3.0) * e22


#: Names of the built-in tests a law is evaluated in (:func:`registered_deformations`
#: adds the plug-ins', and the two below, which are registered only to be recognised
#: and refused).
DEFORMATIONS = registered_deformations()


_WAIT = "or wait for a volumetric law"  # what vhfit lacks for these tests (none built in)


@register_deformation("confined_compression",
                      aliases=("confined", "uniaxial_strain", "oedometric", "oedometer",
                               "laterally_confined"))
class ConfinedCompression(Deformation):
    """Confined compression (uniaxial strain): the lateral stretches held at 1, J = λ.

    A specimen (a foam, a gel) in a rigid cup: an incompressible law cannot deform so at
    all, so it is registered to be named and refused, never fitted as uniaxial.
    """

    description = "confined compression (uniaxial strain): λ, 1, 1 (J = λ)"
    signed = True
    refusal = ("an incompressible law cannot deform in confined compression (J = λ); fit "
               f"the unconfined test, {_WAIT}")
    # not "uniaxial strain": a header "uniaxial strain (%)" is a uniaxial test's strain
    mentions = ("confined", "confining", "oedometer", "oedometric")

    def stretches(self, x1, x2=None):
        return x1, np.ones_like(x1), np.ones_like(x1)


@register_deformation("volumetric", aliases=("hydrostatic", "bulk", "hydrostatic_pressure"))
class Volumetric(Deformation):
    """A volumetric (hydrostatic) test: λ1 = λ2 = λ3 = λ, J = λ³."""

    description = "volumetric (hydrostatic): λ, λ, λ (J = λ³)"
    signed = True
    refusal = ("an incompressible law cannot deform in a volumetric test (J = λ³): its "
               "volume is fixed; fit an unconfined test (uniaxial, planar, biaxial or "
               f"shear), {_WAIT}")
    # phrases that name the test, not words of any file ("volumetric strain not measured")
    mentions = ("volumetric test", "volumetric compression", "hydrostatic test",
                "hydrostatic compression", "hydrostatic pressure test")

    def stretches(self, x1, x2=None):
        return x1, x1, x1


# ------------------------------------------------------------------- stresses
def principal_stretches(deformation: str, x1, x2=None):
    """Principal stretches (λ1, λ2, λ3) of a test, λ1 λ2 λ3 = 1.

    Parameters
    ----------
    deformation : str
        A registered test (:func:`registered_deformations`).
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
    return get_deformation(deformation)._stretches(x1, x2)


def long_term_coefficients(deformation: str, x1, x2=None, direction: int = 1):
    """(I1, I2, p, q) with σ = W1 p + W2 q for an invariant law W(I1, I2).

    The kinematic part of :func:`long_term_stress`, computed once per history
    (:meth:`Deformation.long_term_coefficients` of the test).
    """
    return get_deformation(deformation).long_term_coefficients(
        np.asarray(x1, dtype=np.float64), x2, direction)


def long_term_stress(model: Hyperelastic, params, deformation: str, x1, x2=None,
                     direction: int = 1, coefficients=None):
    """Measured true stress of the long-term law: σ_a = τ_a − τ_c, or σ12 in simple shear.

    Parameters
    ----------
    model : Hyperelastic
    params : array_like, (n_params,) or (..., n_params)
    deformation : str
        A registered test (:func:`registered_deformations`).
    x1, x2 : array_like
        λ1 (γ in simple shear) and, for biaxial, λ2.
    direction : {1, 2}
        The loaded direction a (2: tests with two loaded directions only).
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
    test = get_deformation(deformation)
    cols = constant_columns(model, params)
    x1 = np.asarray(x1, dtype=np.float64)
    if test.uniaxial:
        return model.stress(x1, params)
    if model.kind == "invariant":
        I1, I2, p, q = (coefficients if coefficients is not None
                        else test.long_term_coefficients(x1, x2, direction))
        W1, W2 = invariant_gradient(model.energy, model.derivatives, I1, I2, cols)
        return W1 * p + W2 * q + 0.0 * cols[0]
    return test.stretch_law_stress(model, cols, x1, x2, direction) + 0.0 * cols[0]


def hereditary_weights(deformation: str, x1, x2=None, direction: int = 1) -> np.ndarray:
    """c_k(t) of the factorised pushed-forward kernel K(u, t) = Σ_k c_k(t) f_k(u), (2, m).

    Principal axes: c = (λ_a², −λ_c²); simple shear: c = (1, γ) (docs/theory.md §13).
    """
    return get_deformation(deformation).weights(np.asarray(x1, dtype=np.float64), x2,
                                                direction)


def invariant_coefficients(deformation: str, x1, x2=None, direction: int = 1):
    """(I1, I2, coef) with f_k = (2/E∞)(W1 coef[2k] + W2 coef[2k + 1]) for W(I1, I2).

    The kinematic part of :func:`hereditary_factors` for an invariant law, computed
    once per history (:meth:`Deformation.invariant_coefficients` of the test).
    """
    return get_deformation(deformation).invariant_coefficients(
        np.asarray(x1, dtype=np.float64), x2, direction)


def hereditary_factors(model: Hyperelastic, params, E_inf, deformation: str, x1, x2=None,
                       direction: int = 1, coefficients=None) -> tuple[np.ndarray, np.ndarray]:
    """f_k(u) of the factorised kernel, per unit E∞: two arrays (P, m).

    Principal axes: f = (d_a/λ_a², d_c/λ_c²)/E∞ with d = dev τ; simple shear:
    f = ((S12 − γ S22), S22)/E∞ with S = dev τ (docs/theory.md §13). NaN where the
    energy is undefined. ``coefficients``: :func:`invariant_coefficients` of the same
    arguments, if already computed (invariant laws only).
    """
    test = get_deformation(deformation)
    cols = constant_columns(model, params)
    x1 = np.asarray(x1, dtype=np.float64)
    E = np.asarray(E_inf, dtype=np.float64)[..., None]
    if model.kind == "invariant":
        I1, I2, c = (coefficients if coefficients is not None
                     else test.invariant_coefficients(x1, x2, direction))
        W1, W2 = invariant_gradient(model.energy, model.derivatives, I1, I2, cols)
        W1, W2 = 2.0 * W1 / E, 2.0 * W2 / E  # (P, 1) for constant derivatives: cheap
        f0, f1 = W1 * c[0] + W2 * c[1], W1 * c[2] + W2 * c[3]
    else:
        f0, f1 = test.kirchhoff_factors(model, cols, E, x1, x2, direction)
    shape = np.broadcast_shapes(np.shape(f0), np.shape(f1), E.shape[:-1] + x1.shape)
    return tuple(f if np.shape(f) == shape else np.broadcast_to(f, shape).copy()
                 for f in (f0, f1))
