"""The built-in laws added for multi-mode fits, their linear constants, and their search.

Arruda–Boyce, Gent, Van der Waals, reduced polynomial N = 1..6 and Ogden N = 4..6
(docs/theory.md §2). Every reference is written here from the formula: the uniaxial
closed forms σ = 2 (λ² − 1/λ)(∂W/∂I1 + ∂W/∂I2/λ) with the derivatives worked by hand,
or σ = λ dŴ/dλ with Ŵ(λ) the energy along the incompressible uniaxial path
(λ, λ^-1/2, λ^-1/2) differentiated numerically — no use of the library's derivatives.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _budget import accuracy
from hypothesis import given
from hypothesis import strategies as st

import vhfit
from vhfit import hyperelastic as hyp
from vhfit.stability import drucker

stretches = st.floats(0.3, 3.0)
moduli = st.floats(1e-3, 10.0)
AB_C = (1 / 2, 1 / 20, 11 / 1050, 19 / 7000, 519 / 673750)  # Abaqus' coefficients


def invariants(lam):
    return lam**2 + 2 / lam, 2 * lam + 1 / lam**2


def along_path(energy, lam, h=1e-5):
    """σ = λ dŴ/dλ, Ŵ(λ) = W(I1(λ), I2(λ)), by a 4th-order central difference in ln λ."""
    def w(t):
        return energy(*invariants(lam * math.exp(t)))
    return (8 * (w(h) - w(-h)) - (w(2 * h) - w(-2 * h))) / (12 * h)


def rel_close(actual, expected, scale, rel):
    assert abs(actual - expected) <= rel * scale, (actual, expected, scale)


# ------------------------------------------------------------- closed forms
@accuracy
@given(stretches, moduli, st.floats(1.05, 8.0))
def test_arruda_boyce_uniaxial_closed_form(lam, mu, lm):
    I1, _ = invariants(lam)
    W1 = mu * sum(i * c * I1 ** (i - 1) / lm ** (2 * i - 2) for i, c in enumerate(AB_C, 1))
    expected = 2 * (lam**2 - 1 / lam) * W1
    s = float(hyp.get("arruda_boyce").stress([lam], [mu, lm])[0])
    rel_close(s, expected, 2 * (lam**2 + 1 / lam) * W1, 1e-12)
    # and the energy itself, W = μ Σ C_i/λm^(2i−2) (I1^i − 3^i), differentiated along the path
    def W(I1, I2):
        return mu * sum(c / lm ** (2 * i - 2) * (I1**i - 3**i) for i, c in enumerate(AB_C, 1))
    rel_close(s, along_path(W, lam), 2 * (lam**2 + 1 / lam) * W1, 1e-7)


@accuracy
@given(stretches, moduli, st.floats(0.05, 2.0))
def test_gent_uniaxial_closed_form(lam, mu, log_margin):
    """σ = 2μ Jm/(Jm − I1 + 3) (λ² − 1/λ), with Jm beyond the locking limit of λ."""
    I1, _ = invariants(lam)
    Jm = (I1 - 3) * 10**log_margin + 0.1
    expected = mu * Jm / (Jm - I1 + 3) * (lam**2 - 1 / lam)
    s = float(hyp.get("gent").stress([lam], [mu, Jm])[0])
    rel_close(s, expected, abs(expected) + mu * Jm / (Jm - I1 + 3) * (lam**2 + 1 / lam), 1e-12)


def test_gent_past_its_locking_limit_has_no_stress():
    I1, _ = invariants(2.0)  # I1 − 3 = 2
    assert np.isnan(hyp.get("gent").stress([2.0], [0.1, 1.5])[0])
    with pytest.raises(ValueError, match="not finite"):
        vhfit.ViscoHyperelastic("gent", 0).stress(dict(mu=0.1, Jm=1.5), strain=[0.0, 1.0],
                                                  strain_rate=1.0)


@accuracy
@given(stretches, moduli, st.floats(2.0, 8.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_van_der_waals_uniaxial_from_its_energy(lam, mu, lm, a, beta):
    """Abaqus' form W = μ[−(λm² − 3)(ln(1 − η) + η) − 2/3 a ((Ĩ − 3)/2)^(3/2)],
    Ĩ = (1 − β) I1 + β I2, η = √((Ĩ − 3)/(λm² − 3)), differentiated along the path."""
    I1, I2 = invariants(lam)
    x = (1 - beta) * (I1 - 3) + beta * (I2 - 3)
    if x >= 0.8 * (lm**2 - 3):  # keep η < 0.9: the energy locks at η = 1
        lm = math.sqrt(3 + x / 0.8)

    def W(I1, I2):
        x = (1 - beta) * (I1 - 3) + beta * (I2 - 3)
        eta = math.sqrt(max(x, 0.0) / (lm**2 - 3))
        return mu * (-(lm**2 - 3) * (math.log(1 - eta) + eta) - 2 / 3 * a * (max(x, 0) / 2) ** 1.5)

    s = float(hyp.get("van_der_waals").stress([lam], [mu, lm, a, beta])[0])
    scale = mu * (lam**2 + 1 / lam) * (10 + a * math.sqrt(x + 1))
    rel_close(s, along_path(W, lam), scale, 1e-7)


@accuracy
@given(stretches, st.integers(1, 6), st.data())
def test_reduced_polynomial_uniaxial_closed_form(lam, n, data):
    C = data.draw(st.lists(st.floats(-1.0, 1.0), min_size=n, max_size=n))
    I1, _ = invariants(lam)
    x = I1 - 3
    W1 = sum(i * c * x ** (i - 1) for i, c in enumerate(C, 1))
    expected = 2 * (lam**2 - 1 / lam) * W1
    s = float(hyp.get(f"reduced_polynomial{n}").stress([lam], C)[0])
    scale = 2 * (lam**2 + 1 / lam) * sum(i * abs(c) * x ** (i - 1) for i, c in enumerate(C, 1))
    rel_close(s, expected, scale + 1e-300, 1e-12)


@accuracy
@given(stretches, st.integers(4, 6), st.data())
def test_ogden_four_to_six_terms_closed_form(lam, n, data):
    alpha = st.one_of(st.floats(-8.0, -0.5), st.floats(0.5, 8.0))
    c = data.draw(st.lists(st.tuples(st.floats(-2.0, 2.0), alpha), min_size=n, max_size=n))
    terms = [2 * mu / a * (lam**a - lam ** (-a / 2)) for mu, a in c]
    s = float(hyp.get(f"ogden{n}").stress([lam], [v for pair in c for v in pair])[0])
    scale = sum(abs(2 * mu / a) * (lam**a + lam ** (-a / 2)) for mu, a in c)
    rel_close(s, sum(terms), scale, 1e-12)


# ------------------------------------------------------------ initial modulus
NEW_LAWS = ["arruda_boyce", "gent", "van_der_waals", *(f"reduced_polynomial{n}" for n in
            range(1, 7)), "ogden4", "ogden5", "ogden6"]


@pytest.mark.parametrize("name", NEW_LAWS)
def test_three_mu0_is_the_small_strain_slope(name):
    m = hyp.get(name)
    c = np.array(m.example)
    # Van der Waals' interaction term a ((Ĩ − 3)/2)^(3/2) puts |ε|ε in σ: the difference
    # quotient then errs by O(h), not O(h⁴)
    h, rel = (1e-7, 1e-7) if name == "van_der_waals" else (1e-4, 1e-9)
    s = m.stress(1.0 + h * np.array([-2.0, -1.0, 1.0, 2.0]), c)
    slope = (8 * (s[2] - s[1]) - (s[3] - s[0])) / (12 * h)
    assert slope == pytest.approx(3 * m.initial_shear_modulus(c), rel=rel)


@pytest.mark.parametrize("lm", [1.2, 2.0, 5.0, 50.0])
def test_arruda_boyce_mu0_series(lm):
    """μ0 = 2 ∂W/∂I1 at I1 = 3 = μ Σ 2 i C_i 3^(i−1)/λm^(2i−2) = μ (1 + 3/(5λm²) + ...)."""
    mu0 = 0.3 * sum(2 * i * c * 3 ** (i - 1) / lm ** (2 * i - 2) for i, c in enumerate(AB_C, 1))
    assert hyp.get("arruda_boyce").initial_shear_modulus([0.3, lm]) == pytest.approx(
        mu0, rel=1e-14)
    assert mu0 == pytest.approx(0.3 * (1 + 3 / (5 * lm**2) + 99 / (175 * lm**4)
                                       + 513 / (875 * lm**6) + 42039 / (67375 * lm**8)),
                                rel=1e-14)


@pytest.mark.parametrize("name,params,mu0", [
    ("gent", [0.4, 7.0], 0.4), ("van_der_waals", [0.4, 5.0, 0.3, 0.5], 0.4),
    ("reduced_polynomial4", [0.4, -1.0, 2.0, 3.0], 0.8),
    ("ogden5", [0.1, 2.0, 0.2, -2.0, 0.3, 5.0, 0.4, 1.0, 0.5, -3.0], 1.5),
])
def test_initial_shear_modulus_by_hand(name, params, mu0):
    assert hyp.get(name).initial_shear_modulus(params) == pytest.approx(mu0, rel=1e-14)


# ---------------------------------------------------------------- stability
@pytest.mark.parametrize("name,params,stretch_range", [
    ("arruda_boyce", [0.27, 2.5], (0.2, 5.0)),
    ("gent", [0.2, 10.0], (0.6, 1.8)),  # every mode below the locking limit I1 − 3 = Jm
    ("van_der_waals", [0.1, 4.0, 0.1, 0.3], (0.5, 2.0)),
    ("reduced_polynomial6", list(hyp.get("reduced_polynomial6").example), (0.2, 5.0)),
    # Treloar-like Ogden-3 in the Abaqus form (every μp > 0), padded with small terms
    ("ogden6", [0.41, 1.3, 0.003, 5.0, 0.01, -2.0, 1e-4, 3.0, 1e-4, -1.0, 1e-4, 0.5],
     (0.2, 5.0)),
])
def test_typical_constants_are_drucker_stable(name, params, stretch_range):
    assert drucker(hyp.get(name), params, stretch_range).stable


def test_a_negative_ogden_modulus_can_be_unstable():
    # μ2 < 0 with a large stiffening exponent: the tangent turns negative in compression
    assert not drucker(hyp.get("ogden4"), [0.1, 2.0, -0.05, 4.0, 0.0, 1.0, 0.0, 1.0]).stable


# ------------------------------------------------------- linear declarations
EXPECTED_LINEAR = {
    "mooney_rivlin": ("C10", "C01"), "neo_hooke": ("C10",), "yeoh": ("C10", "C20", "C30"),
    "polynomial2": ("C10", "C01", "C20", "C11", "C02"),
    "arruda_boyce": ("mu",), "gent": ("mu",), "van_der_waals": ("mu",),
    **{f"ogden{s}": tuple(f"mu{p}" for p in range(1, n + 1))
       for n, s in enumerate(["", "2", "3", "4", "5", "6"], 1)},
    **{f"reduced_polynomial{n}": tuple(f"C{i}0" for i in range(1, n + 1)) for n in range(1, 7)},
}


@pytest.mark.parametrize("name", sorted(EXPECTED_LINEAR))
def test_linear_constants_are_declared_and_true(name):
    m = hyp.get(name)
    assert m.linear_params == EXPECTED_LINEAR[name]
    assert m.linear == (m.linear_params == m.param_names)
    # σ(a + b) = σ(a) + σ(b) in the linear constants, the others at the example values
    rng = np.random.default_rng(1)
    idx = [m.param_names.index(n) for n in m.linear_params]
    x = np.tile(np.array(m.example), (2, 1))
    x[:, idx] = rng.uniform(0.01, 0.1, (2, len(idx)))
    xs = x[0].copy()
    xs[idx] = x[0, idx] + x[1, idx]
    lam = np.array([0.7, 1.3, 1.8])
    a, b = m.stress(lam, x)
    np.testing.assert_allclose(m.stress(lam, xs), a + b, rtol=1e-12)


def _my_gent(I1, I2, mu, Jm):
    return -mu * Jm / 2 * np.log(1 - (I1 - 3) / Jm)


def test_user_law_linear_constants_inferred_declared_or_refused():
    try:
        hyp.register("_t_gent", units=("MPa", "1"), example=(0.1, 10.0))(_my_gent)
        assert hyp.get("_t_gent").linear_params == ("mu",)  # inferred: its MPa constant
        assert not hyp.get("_t_gent").linear

        def stiff(I1, I2, C1, C2):  # C2 in MPa (the default unit) but not linear
            return C1 * (np.exp(C2 * (I1 - 3)) - 1)
        hyp.register("_t_exp", example=(0.1, 0.5))(stiff)
        assert hyp.get("_t_exp").linear_params == ()  # the candidate failed the check
        hyp.register("_t_exp", example=(0.1, 0.5), linear_params=["C1"], overwrite=True)(stiff)
        assert hyp.get("_t_exp").linear_params == ("C1",)
        with pytest.raises(ValueError, match=r"declared linear but its stress is not"):
            hyp.register("_t_bad", example=(0.1, 0.5), linear_params=("C1", "C2"))(stiff)
        with pytest.raises(ValueError, match=r"declared linear in \['C2'\]"):
            hyp.register("_t_bad", example=(0.1, 0.5), linear_params=("C2",))(stiff)
        with pytest.raises(ValueError, match="must name distinct constants"):
            hyp.register("_t_bad", example=(0.1, 0.5), linear_params=("C3",))(stiff)
        with pytest.raises(ValueError, match="linear=True means every constant"):
            hyp.register("_t_bad", example=(0.1, 0.5), linear=True, linear_params=("C1",))(stiff)
        assert "_t_bad" not in hyp.available()
        with pytest.raises(ValueError, match="declares none"):
            hyp.register("_t_exp", example=(0.1, 0.5), overwrite=True)(stiff)
            vhfit.calibrate(
                [vhfit.Curve(strain=[0.0, 0.2, 0.4], stress=[0.0, 0.1, 0.3], strain_rate=1.0)],
                hyperelastic="_t_exp", n_prony=0)
    finally:
        for n in ("_t_gent", "_t_exp", "_t_bad"):
            hyp.unregister(n)


# ------------------------------------------------------ the separable search
def _curves(law, truth, n_prony, rates, emax, n=120):
    m = vhfit.ViscoHyperelastic(law, n_prony=n_prony)
    eps = np.linspace(0.0, emax, n)
    return [vhfit.Curve(strain=eps, stress=m.stress(truth, strain=eps, strain_rate=r,
                                                    measure="engineering"),
                        strain_rate=r) for r in rates]


@pytest.mark.parametrize("law,truth,n_prony,rates,emax,rel", [
    # n_prony = 0: the moduli by least squares, DE over the α's / λm only
    ("ogden2", dict(mu1=0.3, alpha1=2.5, mu2=0.02, alpha2=-3.0), 0, (0.1,), 3.0, 1e-2),
    ("arruda_boyce", dict(mu=0.2, lambda_m=2.5), 0, (0.1,), 1.5, 1e-4),
    # with a Prony term: the shape (μ2/μ1, α, λm) and log τ by DE, E∞ and G by NNLS
    ("ogden2", dict(mu1=0.2, alpha1=2.5, mu2=0.05, alpha2=-1.5, G1=0.5, tau1=0.1), 1,
     (0.01, 1.0), 1.5, 1e-2),
    ("arruda_boyce", dict(mu=0.2, lambda_m=2.5, G1=0.5, tau1=0.1), 1, (0.01, 1.0), 1.5, 1e-3),
])
def test_separable_search_recovers_known_constants(law, truth, n_prony, rates, emax, rel):
    """The recorded error is on the objective's points, linearly interpolated between
    the samples (paper Eq. 20): it bounds how closely the constants can come back."""
    curves = _curves(law, truth, n_prony, rates, emax)
    cal = vhfit.calibrate(curves, hyperelastic=law, n_prony=n_prony, seed=0, uncertainty=False)
    assert cal.rmsape < 1e-2
    got = dict(cal.params)
    if law.startswith("ogden"):  # the terms of an Ogden law may come back in any order
        def terms(p):
            return sorted((p[f"alpha{i}"], p[f"mu{i}"]) for i in (1, 2))
        for (a, m), (a0, m0) in zip(terms(got), terms(truth)):
            assert (a, m) == (pytest.approx(a0, rel=rel), pytest.approx(m0, rel=rel)), got
        got = {k: v for k, v in got.items() if k[:2] not in ("mu", "al")}
    for k, v in got.items():
        assert v == pytest.approx(truth[k], rel=rel), (k, cal.params)


def test_a_polynomial_law_without_prony_terms_needs_no_search():
    truth = dict(C10=0.2, C20=0.01, C30=0.002, C40=1e-4)
    cal = vhfit.calibrate(_curves("reduced_polynomial4", truth, 0, (0.1,), 1.5),
                          hyperelastic="reduced_polynomial4", n_prony=0, uncertainty=False)
    assert cal.nit == 0 and str(cal.stop_reason) == "nothing to search"
    for k, v in truth.items():
        assert cal.params[k] == pytest.approx(v, rel=1e-3)


@pytest.mark.filterwarnings("ignore:Drucker-UNSTABLE")
def test_exact_solve_searches_the_stable_set_and_keeps_the_users_lower_limits():
    """Data of a law (C01 < 0) unstable in uniaxial compression and equibiaxial tension
    inside the data's stretch range (every principal stretch within it): the exact solve
    returns the best law stable there (C01 < 0 still, between the
    truth and the non-negative proxy), the truth where the range allows it, and a user's
    lower limit C01 >= 0 is honoured."""
    truth = dict(C10=0.3, C01=-0.15)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 0)
    eps = np.linspace(0.0, 1.0, 50)
    curves = [vhfit.Curve(strain=eps, stress=m.stress(truth, strain=eps, strain_rate=1.0),
                          strain_rate=1.0, measure="true")]
    cal = vhfit.calibrate(curves, n_prony=0, uncertainty=False, polish=False)
    lo, hi = cal.options["stability_range"]
    assert not vhfit.stability.drucker(m.hyperelastic, [0.3, -0.15], (lo, hi),
                                       principal=True).stable
    assert cal.stability.stable and -0.15 < cal.params["C01"] < 0
    pos = vhfit.calibrate(curves, n_prony=0, uncertainty=False, polish=False,
                          bounds={"C01": (0.0, 1.0)})
    # on the limit, to the solve's rounding (exactly 0 with the newest numpy, 1.4e-17 MPa
    # with the oldest pinned one): never below it
    assert 0.0 <= pos.params["C01"] <= 1e-12 * pos.params["C10"] and pos.params["C10"] > 0
    assert cal.rmsape < pos.rmsape
    # a negative lower limit of the user's, above the stable best's C01: it is the answer
    low = vhfit.calibrate(curves, n_prony=0, uncertainty=False, polish=False,
                          bounds={"C01": (-0.01, 1.0)})
    assert cal.params["C01"] < -0.01
    assert low.params["C01"] == pytest.approx(-0.01, abs=1e-12)
    assert cal.rmsape < low.rmsape < pos.rmsape
    near = vhfit.calibrate(curves, n_prony=0, uncertainty=False, polish=False,
                           stability_range=(0.8, 1.25))
    assert near.params["C01"] == pytest.approx(-0.15, rel=1e-9)
    assert near.params["C10"] == pytest.approx(0.3, rel=1e-9)
    assert "unconstrained_fit" not in near.options  # the constraint is not active there
    assert "unconstrained_fit" in cal.options  # it is here
    # no lower limit at all given: the same as the law's own (none)
    unbounded = vhfit.calibrate(curves, n_prony=0, uncertainty=False, polish=False,
                                bounds={"C01": (-np.inf, np.inf)})
    assert unbounded.params == pytest.approx(cal.params, rel=1e-9)


def test_every_built_in_law_passes_the_registration_check():
    """The built-in laws are registered without register()'s check (it would load the
    Ogden laws' compiled kernel at every import): it runs here on each of them, with
    the outcome the registration would need — a finite stress at the example constants,
    and the stress linear in the constants declared linear."""
    from vhfit.hyperelastic import _registry

    builtin = [n for n in hyp.available()
               if hyp.get(n).energy.__module__ == "vhfit.hyperelastic._laws"]
    assert len(builtin) == 20
    lam = np.array([0.6, 0.9, 1.3, 2.0])
    for name in builtin:
        m = hyp.get(name)
        assert np.all(np.isfinite(m.stress(lam, np.array(m.example)))), name
        assert _registry._validate(m, strict=True, declared=True), name
