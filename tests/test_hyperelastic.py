"""Tests of vhfit.hyperelastic: kinematics, built-in laws, user energies, registry errors.

Closed forms are those of docs/theory.md §2, written out here by hand; stresses are true
(Cauchy) stresses on the incompressible uniaxial path λ1 = λ, λ2 = λ3 = λ^(-1/2).
"""

from __future__ import annotations

import numpy as np
import pytest
from _budget import accuracy
from hypothesis import given
from hypothesis import strategies as st

from vhfit import hyperelastic as hyp
from vhfit.model import ViscoHyperelastic

# A comparison "to 1e-12" is relative to the size of the terms that are summed, not to
# their (possibly cancelling) sum: near λ = 1 every σ_h vanishes while its terms do not.
REL = 1e-12

# the stretches the model accepts in practice: 1/20 to 20 (docs/theory.md §2)
stretches = st.floats(0.05, 20.0)
# Constants are 0 or of a physical size: the complex step of 1e-30 would underflow
# for moduli below ~1e-270 MPa, which no material has.
moduli = st.one_of(st.just(0.0), st.floats(1e-6, 10.0))
signed = st.one_of(moduli, moduli.map(lambda x: -x))


def assert_rel(actual, expected, scale, rel=REL):
    """|actual − expected| ≤ rel · scale, elementwise."""
    actual, expected, scale = np.broadcast_arrays(actual, expected, scale)
    err = np.abs(actual - expected)
    assert np.all(err <= rel * scale), f"max error {np.max(err / scale):.3e} of scale"


# --------------------------------------------------------------- kinematics


def principal(lam):
    lam = np.asarray(lam, dtype=np.float64)
    return lam, lam**-0.5, lam**-0.5


@accuracy
@given(st.floats(0.01, 100.0))
def test_incompressible_uniaxial_kinematics(lam):
    l1, l2, l3 = principal(lam)
    assert l1 * l2 * l3 == pytest.approx(1.0, rel=1e-15)
    I1, I2 = hyp.invariants(lam)
    assert I1 == pytest.approx(l1**2 + l2**2 + l3**2, rel=1e-14)
    assert I2 == pytest.approx((l1 * l2) ** 2 + (l2 * l3) ** 2 + (l3 * l1) ** 2, rel=1e-14)
    assert I1 >= 3.0 * (1 - 1e-15) and I2 >= 3.0 * (1 - 1e-15)


def test_stretch_energies_receive_a_volume_preserving_path():
    seen = []

    def spy(l1, l2, l3, mu):
        seen.append(np.real(l1 * l2 * l3))
        return mu * (l1**2 + l2**2 + l3**2 - 3)

    name = "_test_spy"
    hyp.register(name, example=(1.0,), overwrite=True)(spy)
    try:
        seen.clear()
        hyp.get(name).stress([0.3, 0.8, 1.0, 2.5, 7.0], [1.0])
        assert seen
        for J in seen:
            np.testing.assert_allclose(J, 1.0, rtol=1e-15)
    finally:
        hyp.unregister(name)


# ------------------------------------------------------ built-in closed forms


@accuracy
@given(stretches, moduli, moduli)
def test_mooney_rivlin_closed_form(lam, C10, C01):
    s = hyp.get("mooney_rivlin").stress([lam], [C10, C01])[0]
    a, b = 2 * C10 * (lam**2 - 1 / lam), 2 * C01 * (lam - 1 / lam**2)
    assert_rel(s, a + b, 2 * C10 * (lam**2 + 1 / lam) + 2 * C01 * (lam + 1 / lam**2) + 1e-300)


@accuracy
@given(stretches, moduli)
def test_neo_hooke_closed_form(lam, C10):
    s = hyp.get("neo_hooke").stress([lam], [C10])[0]
    assert_rel(s, 2 * C10 * (lam**2 - 1 / lam), 2 * C10 * (lam**2 + 1 / lam) + 1e-300)


@accuracy
@given(stretches, moduli, signed, signed)
def test_yeoh_closed_form(lam, C10, C20, C30):
    x = lam**2 + 2 / lam - 3
    dW = C10 + 2 * C20 * x + 3 * C30 * x**2
    scale = 2 * (lam**2 + 1 / lam) * (abs(C10) + 2 * abs(C20 * x) + 3 * abs(C30) * x**2)
    s = hyp.get("yeoh").stress([lam], [C10, C20, C30])[0]
    assert_rel(s, 2 * (lam**2 - 1 / lam) * dW, scale + 1e-300)


@accuracy
@given(stretches, st.lists(signed, min_size=5, max_size=5))
def test_polynomial2_closed_form_through_complex_step(lam, c):
    C10, C01, C20, C11, C02 = c
    I1, I2 = lam**2 + 2 / lam, 2 * lam + 1 / lam**2
    x, y = I1 - 3, I2 - 3
    W1 = C10 + 2 * C20 * x + C11 * y
    W2 = C01 + C11 * x + 2 * C02 * y
    scale = 2 * (lam**2 + 1 / lam) * (
        abs(C10) + 2 * abs(C20 * x) + abs(C11 * y)
        + (abs(C01) + abs(C11 * x) + 2 * abs(C02 * y)) / lam
    )
    s = hyp.get("polynomial2").stress([lam], c)[0]
    assert_rel(s, 2 * (lam**2 - 1 / lam) * (W1 + W2 / lam), scale + 1e-300)


@accuracy
@given(stretches, st.lists(signed, min_size=9, max_size=9))
def test_polynomial3_reduces_to_its_terms(lam, c):
    # W is linear in the constants: σ_h(c) = Σ_k c_k σ_h(e_k), each e_k a single term
    m = hyp.get("polynomial3")
    basis = m.basis([lam])[:, 0]
    s = m.stress([lam], c)[0]
    assert_rel(s, np.dot(c, basis), np.dot(np.abs(c), np.abs(basis)) + 1e-300)


def ogden_closed(lam, *c):
    mus, alphas = c[0::2], c[1::2]
    terms = [2 * m / a * (lam**a - lam ** (-a / 2)) for m, a in zip(mus, alphas)]
    scale = [abs(2 * m / a) * (lam**a + lam ** (-a / 2)) for m, a in zip(mus, alphas)]
    return sum(terms), sum(scale)


alphas = st.one_of(st.floats(-8.0, -0.5), st.floats(0.5, 8.0))


@pytest.mark.parametrize("name,n_terms", [("ogden", 1), ("ogden2", 2), ("ogden3", 3)])
@accuracy
@given(lam=stretches, data=st.data())
def test_ogden_closed_form(name, n_terms, lam, data):
    c = []
    for _ in range(n_terms):
        c += [data.draw(signed), data.draw(alphas)]
    s = hyp.get(name).stress([lam], c)[0]
    expected, scale = ogden_closed(lam, *c)
    assert_rel(s, expected, scale + 1e-300)


def test_stress_broadcasts_over_parameter_sets():
    m = hyp.get("mooney_rivlin")
    P = np.array([[1.0, 0.0], [0.0, 1.0], [0.5, 0.25]])
    lam = np.array([0.5, 1.0, 2.0])
    s = m.stress(lam, P)
    assert s.shape == (3, 3)
    for k in range(3):
        np.testing.assert_array_equal(s[k], m.stress(lam, P[k]))


# ---------------------------------------------------------- initial modulus


@accuracy
@given(moduli, moduli)
def test_mooney_rivlin_mu0_and_E_inf(C10, C01):
    mu0 = hyp.get("mooney_rivlin").initial_shear_modulus([C10, C01])
    assert mu0 == pytest.approx(2 * (C10 + C01), rel=1e-15, abs=1e-300)
    E_inf = ViscoHyperelastic("mooney_rivlin", 0).long_term_modulus([C10, C01])
    assert E_inf == pytest.approx(6 * (C10 + C01), rel=1e-15, abs=1e-300)


@pytest.mark.parametrize(
    "name,params,mu0",
    [
        ("neo_hooke", [0.7], 1.4),
        ("yeoh", [0.7, -0.2, 0.05], 1.4),
        ("polynomial2", [0.7, 0.3, 9.0, 9.0, 9.0], 2.0),
        ("ogden", [0.7, -3.0], 0.7),
        ("ogden2", [0.7, 2.0, 0.2, -2.0], 0.9),
        ("ogden3", [0.7, 2.0, 0.2, -2.0, 0.1, 5.0], 1.0),
    ],
)
def test_initial_shear_modulus_of_built_ins(name, params, mu0):
    assert hyp.get(name).initial_shear_modulus(params) == pytest.approx(mu0, rel=1e-14)


@pytest.mark.parametrize("name", ["mooney_rivlin", "neo_hooke", "yeoh", "polynomial2",
                                  "polynomial3", "ogden", "ogden2", "ogden3"])
def test_three_mu0_is_the_initial_slope_of_every_built_in(name):
    """E∞ = 3 μ0 = dσ_h/dλ at λ = 1 (the small-strain Young's modulus)."""
    m = hyp.get(name)
    c = np.array(m.example)
    h = 1e-4
    lam = 1.0 + h * np.array([-2.0, -1.0, 1.0, 2.0])
    s = m.stress(lam, c)
    slope = (8 * (s[2] - s[1]) - (s[3] - s[0])) / (12 * h)  # O(h^4) central difference
    assert slope == pytest.approx(3 * m.initial_shear_modulus(c), rel=1e-9)


# -------------------------------------------------------------- user energies


@pytest.fixture
def user_models():
    """Register user energies for one test; remove them afterwards."""
    names = []

    def add(name, fn, **kw):
        hyp.register(name, overwrite=True, **kw)(fn)
        names.append(name)
        return hyp.get(name)

    yield add
    for n in names:
        hyp.unregister(n)


@accuracy
@given(stretches, moduli, moduli)
def test_user_mooney_rivlin_and_neo_hooke_reproduce_built_ins(lam, C10, C01):
    def my_mr(I1, I2, C10, C01):
        return C10 * (I1 - 3) + C01 * (I2 - 3)

    def my_nh(I1, I2, C10):
        return C10 * (I1 - 3)

    try:
        hyp.register("_test_mr", overwrite=True)(my_mr)
        hyp.register("_test_nh", overwrite=True)(my_nh)
        builtin = hyp.get("mooney_rivlin").stress([lam], [C10, C01])[0]
        mine = hyp.get("_test_mr").stress([lam], [C10, C01])[0]
        scale = 2 * C10 * (lam**2 + 1 / lam) + 2 * C01 * (lam + 1 / lam**2) + 1e-300
        assert_rel(mine, builtin, scale)
        assert_rel(
            hyp.get("_test_nh").stress([lam], [C10])[0],
            hyp.get("neo_hooke").stress([lam], [C10])[0],
            2 * C10 * (lam**2 + 1 / lam) + 1e-300,
        )
    finally:
        hyp.unregister("_test_mr")
        hyp.unregister("_test_nh")


def gent(I1, I2, mu, Jm):
    """Gent: W = −μ Jm / 2 ln(1 − (I1 − 3)/Jm)."""
    return -mu * Jm / 2 * np.log(1 - (I1 - 3) / Jm)


@accuracy
@given(stretches, st.floats(0.01, 10.0), st.floats(0.0, 2.0))
def test_gent_by_complex_step_matches_its_analytic_stress(lam, mu, log_margin):
    """Jm from 1 to 100 times what keeps (I1 − 3)/Jm ≤ 0.95 at this stretch (every draw
    stays away from the locking stretch, so none is wasted)."""
    I1 = lam**2 + 2 / lam
    Jm = max(1.0, (I1 - 3) / 0.95) * 10**log_margin
    try:
        hyp.register("_test_gent", example=(1.0, 50.0), overwrite=True)(gent)
        s = hyp.get("_test_gent").stress([lam], [mu, Jm])[0]
    finally:
        hyp.unregister("_test_gent")
    # ∂W/∂I1 = μ/2 / (1 − (I1−3)/Jm), ∂W/∂I2 = 0
    expected = mu * (lam**2 - 1 / lam) / (1 - (I1 - 3) / Jm)
    assert_rel(s, expected, mu * (lam**2 + 1 / lam) / (1 - (I1 - 3) / Jm))


def test_gent_initial_modulus_from_the_complex_step(user_models):
    m = user_models("_test_gent", gent, example=(1.0, 50.0))
    assert m.kind == "invariant" and m.param_names == ("mu", "Jm")
    assert m.initial_shear_modulus([0.8, 20.0]) == pytest.approx(0.8, rel=1e-14)


@accuracy
@given(stretches, st.data())
def test_user_stretch_ogden_reproduces_built_in(lam, data):
    def my_ogden(lambda1, lambda2, lambda3, mu1, alpha1, mu2, alpha2):
        def term(mu, a):
            return 2 * mu / a**2 * (lambda1**a + lambda2**a + lambda3**a - 3)

        return term(mu1, alpha1) + term(mu2, alpha2)

    c = [data.draw(signed), data.draw(alphas), data.draw(signed), data.draw(alphas)]
    try:
        hyp.register("_test_ogden", overwrite=True)(my_ogden)
        m = hyp.get("_test_ogden")
        assert m.kind == "stretch"
        mine = m.stress([lam], c)[0]
    finally:
        hyp.unregister("_test_ogden")
    expected, scale = ogden_closed(lam, *c)
    assert_rel(mine, hyp.get("ogden2").stress([lam], c)[0], scale + 1e-300)
    assert_rel(mine, expected, scale + 1e-300)


def test_energy_without_complex_support_falls_back_to_real_differences(user_models):
    """np.logaddexp rejects complex input: the 4th-order central difference is used."""

    def softplus(I1, I2, c):
        return c * np.logaddexp(0.0, I1 - 3)

    m = user_models("_test_softplus", softplus, example=(1.0,))
    lam = np.array([0.5, 0.9, 1.2, 2.0])
    x = lam**2 + 2 / lam - 3
    expected = 2 * (lam**2 - 1 / lam) * 0.7 / (1 + np.exp(-x))  # ∂W/∂I1 = c·sigmoid(I1 − 3)
    # truncation error of the h = 1e-3 fourth-order difference: h⁴/30 |W⁽⁵⁾| ~ 1e-13
    np.testing.assert_allclose(m.stress(lam, [0.7]), expected, rtol=1e-10)


def test_register_returns_the_function_and_infers_names(user_models):
    def my_energy(I1, I2, a, b):
        return a * (I1 - 3) + b * (I2 - 3) ** 2

    m = user_models("_test_names", my_energy, units=("MPa", "MPa"), example=(0.1, 0.2))
    assert m.param_names == ("a", "b") and m.units == ("MPa", "MPa")
    assert m.example == (0.1, 0.2)
    assert "_test_names" in hyp.available()
    assert hyp.get(m) is m


@pytest.mark.parametrize("term", [3, 4, -2, True, 1.5])
def test_register_refuses_terms_that_do_not_divide_the_constants(term):
    def two_terms(l1, l2, l3, mu1, alpha1, mu2, alpha2):
        return 0.0 * l1

    with pytest.raises(ValueError, match="like terms"):
        hyp.register("_test_terms", term=term, fewer="ogden",
                     units=("MPa", "1", "MPa", "1"))(two_terms)
    assert "_test_terms" not in hyp.available()


def test_ogden_laws_declare_their_like_terms():
    # each n-term Ogden law leads, one term at a time, to the one-term law
    for n in range(2, 7):
        m = hyp.get("ogden" if n == 1 else f"ogden{n}")
        assert m.term == 2 and hyp.get(m.fewer).n_params == m.n_params - 2
    assert hyp.get("ogden").term == 0 and hyp.get("ogden").fewer is None


def test_available_lists_the_built_ins():
    names = hyp.available()
    for n in ["mooney_rivlin", "neo_hooke", "yeoh", "polynomial2", "polynomial3",
              "ogden", "ogden2", "ogden3"]:
        assert n in names
    assert names == sorted(names)


# ------------------------------------------------------------ linear basis


@pytest.mark.parametrize("name", ["mooney_rivlin", "neo_hooke", "yeoh", "polynomial2",
                                  "polynomial3"])
def test_basis_of_linear_models_reproduces_the_stress(name):
    m = hyp.get(name)
    assert m.linear
    lam = np.array([0.45, 0.8, 1.0, 1.5, 3.0])
    c = np.random.default_rng(1).uniform(-1, 1, m.n_params)
    B = m.basis(lam)
    assert B.shape == (m.n_params, lam.size)
    assert_rel(c @ B, m.stress(lam, c), np.abs(c) @ np.abs(B) + 1e-300)


def test_basis_of_a_non_linear_model_is_refused():
    with pytest.raises(ValueError, match="'ogden' is not linear"):
        hyp.get("ogden").basis([1.0])


# --------------------------------------------------------------- bad input


def test_unknown_model_name_lists_the_available_ones():
    with pytest.raises(ValueError, match="unknown hyperelastic model 'mooney'") as exc:
        hyp.get("mooney")
    for n in hyp.available():
        assert n in str(exc.value)
    with pytest.raises(ValueError, match="available: .*mooney_rivlin"):
        ViscoHyperelastic("extended_tube", 1)


def test_wrong_number_of_constants_is_named():
    m = hyp.get("mooney_rivlin")
    with pytest.raises(ValueError, match=r"'mooney_rivlin' takes 2 constants \['C10', 'C01'\]"):
        m.stress([1.1], [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match=r"takes 2 constants \['C10', 'C01'\], got 1"):
        m.check([1.0])
    with pytest.raises(ValueError, match="takes 1 constants"):
        hyp.get("neo_hooke").initial_shear_modulus(1.0)


def test_check_names_non_finite_and_out_of_range_constants():
    with pytest.raises(ValueError, match="C01 = nan is not finite"):
        hyp.get("mooney_rivlin").check([1.0, np.nan])
    with pytest.raises(ValueError, match=r"C10 = -1 is outside its physical range \[0, inf\]"):
        hyp.get("neo_hooke").check([-1.0])
    np.testing.assert_array_equal(hyp.get("mooney_rivlin").check([1.0, 2.0]), [1.0, 2.0])


def test_duplicate_registration_needs_overwrite(user_models):
    def e(I1, I2, c):
        return c * (I1 - 3)

    user_models("_test_dup", e)
    with pytest.raises(ValueError, match="'_test_dup' is already registered.*overwrite=True"):
        hyp.register("_test_dup")(e)
    with pytest.raises(ValueError, match="'mooney_rivlin' is already registered"):
        hyp.register("mooney_rivlin")(e)


def test_unrecognised_signature_is_refused():
    def e(x, y, c):
        return c * x

    with pytest.raises(ValueError, match=r"cannot tell the kinematics of e\(x, y, c\)"):
        hyp.register("_test_bad_sig")(e)
    assert "_test_bad_sig" not in hyp.available()


def test_energy_without_constants_is_refused():
    def e(I1, I2):
        return I1 - 3

    with pytest.raises(ValueError, match="has no material constants"):
        hyp.register("_test_no_constants")(e)


def test_energy_past_its_domain_gives_nan_not_a_complex_continuation(user_models):
    """The complex log of a negative number is finite; the stress must not be."""
    m = user_models("_test_gent_lock", gent, example=(1.0, 50.0))
    with np.errstate(all="ignore"):
        s = m.stress([1.5, 2.0, 3.0], [1.0, 2.0])  # I1 − 3 ≥ Jm from λ = 2 on
    assert np.isfinite(s[0])
    assert np.isnan(s[1:]).all()


def test_non_finite_energy_at_the_example_is_refused():
    with pytest.raises(ValueError, match="'_test_nan' gives a non-finite stress at its example"):
        hyp.register("_test_nan", example=(1.0, 0.1))(gent)  # Jm = 0.1 locks below λ = 2
    assert "_test_nan" not in hyp.available()


def test_false_linearity_claim_is_refused():
    def e(I1, I2, c):
        return c**2 * (I1 - 3)

    with pytest.raises(ValueError, match="'_test_lin' is declared linear but its stress is not"):
        hyp.register("_test_lin", linear=True)(e)


def test_metadata_lengths_must_match_the_constants():
    def e(I1, I2, a, b):
        return a * (I1 - 3) + b * (I2 - 3)

    with pytest.raises(ValueError, match=r"one entry per constant \['a', 'b'\]"):
        hyp.register("_test_meta", units=("MPa",))(e)


def test_empty_name_is_refused():
    with pytest.raises(ValueError, match="non-empty string"):
        hyp.register("")(gent)
