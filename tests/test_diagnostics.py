"""Tests of vhfit.diagnostics: the rate-sensitivity bound of a Prony series (Eq. 19)."""

from __future__ import annotations

import numpy as np
import pytest

import vhfit
from vhfit.diagnostics import RatePair, rate_pairs, rate_ratio_bounds, rate_sensitivity


def linear_ve(strain, rate, E_inf, G, tau):
    """Closed form at small strain (docs/theory.md §4).

    σ = E∞ r t + Σ G_i r τ_i (1 − e^(−t/τ_i)).
    """
    t = np.asarray(strain) / rate
    s = E_inf * rate * t
    for g, ta in zip(G, tau):
        s = s + g * rate * ta * (1.0 - np.exp(-t / ta))
    return s


def curve(strain, stress, rate, name):
    return vhfit.Curve(strain=strain, stress=stress, strain_rate=rate, measure="true", name=name)


def test_closed_form_single_term_ratio_never_exceeds_k():
    # φ(a) = a (1 − e^(−ε/a)): φ(ka)/φ(a) rises from 1 (a → ∞) to k (a → 0), never above
    eps, k = 1e-3, 2.0
    a = np.logspace(-12, 6, 2001) * eps
    phi = a * -np.expm1(-eps / a)
    phik = k * a * -np.expm1(-eps / (k * a))
    r = phik / phi
    assert np.all(r <= k * (1 + 1e-12)) and np.all(r >= 1 - 1e-12)
    assert r[0] == pytest.approx(k, rel=1e-9) and r[-1] == pytest.approx(1.0, abs=1e-6)


def test_bound_matches_closed_form_at_small_strain():
    eps = np.linspace(-1e-4, -1e-3, 5)
    for k in (1.5, 2.0, 10.0):
        low, high = rate_ratio_bounds("mooney_rivlin", eps, -100.0, -100.0 * k, n_prony=3)
        np.testing.assert_allclose(high, k, rtol=1e-6)
        np.testing.assert_allclose(low, 1.0, rtol=1e-6)


@pytest.mark.parametrize("name", ["mooney_rivlin", "neo_hooke", "yeoh", "ogden"])
def test_bound_in_compression_is_the_rate_ratio_at_large_strain(name):
    eps = np.linspace(-0.05, -0.7, 8)
    low, high = rate_ratio_bounds(name, eps, -10.0, -20.0)
    np.testing.assert_allclose(high, 2.0, rtol=1e-6)
    assert np.all(low >= 1.0 - 1e-9)


def test_model_single_term_ratio_agrees_with_closed_form():
    # the model's own Eq. 19 at small strain reproduces the closed form's ratio
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    eps = np.linspace(-1e-4, -1e-3, 6)
    for tau in (1e-8, 1e-6, 1e-5, 1e-3):
        p = dict(C10=1e-9, C01=0.0, G1=1.0, tau1=tau)
        s1 = m.stress(p, strain=eps, strain_rate=-1.0)
        s2 = m.stress(p, strain=eps, strain_rate=-2.0)
        c1 = linear_ve(eps, -1.0, 6e-9, [1.0], [tau])
        c2 = linear_ve(eps, -2.0, 6e-9, [1.0], [tau])
        np.testing.assert_allclose(s2 / s1, c2 / c1, rtol=2e-3)
        assert np.all(s2 / s1 <= 2.0 * (1 + 1e-9))


def test_closed_form_curves_within_bound_give_no_warning():
    eps = np.linspace(-1e-4, -1e-3, 10)
    rng = np.random.default_rng(0)
    for _ in range(20):
        n = int(rng.integers(1, 4))
        E_inf = 10 ** rng.uniform(-6, 1)
        G = 10 ** rng.uniform(-1, 2, n)
        tau = 10 ** rng.uniform(-10, 0, n)
        rates = (-1.0, -2.0, -5.0)
        cs = [curve(eps, linear_ve(eps, r, E_inf, G, tau), r, f"{r:g}") for r in rates]
        assert rate_sensitivity(cs, "mooney_rivlin", n) == []
        for p in rate_pairs(cs, "mooney_rivlin", n):
            assert p.low * (1 - 1e-6) <= p.stress_ratio <= p.high * (1 + 1e-6)


def test_near_viscous_limit_approaches_but_respects_the_bound():
    eps = np.linspace(-1e-4, -1e-3, 10)
    cs = [curve(eps, linear_ve(eps, r, 1e-12, [5.0], [1e-9]), r, f"r{r:g}") for r in (-1.0, -2.0)]
    (p,) = rate_pairs(cs, "mooney_rivlin", 1)
    assert p.stress_ratio == pytest.approx(2.0, rel=1e-4)
    assert not p.too_steep and rate_sensitivity(cs, "mooney_rivlin", 1) == []


def test_stress_tripled_when_rate_doubled_is_flagged_by_name():
    eps = np.linspace(-0.05, -0.5, 10)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    p = dict(C10=0.01, C01=0.02, G1=2.0, tau1=1e-4, G2=0.5, tau2=1e-2)
    s = m.stress(p, strain=eps, strain_rate=-100.0)
    cs = [curve(eps, s, -100.0, "slow test"), curve(eps, 3.0 * s, -200.0, "fast test")]
    msgs = rate_sensitivity(cs, "mooney_rivlin", 2)
    assert len(msgs) == 1
    assert "'slow test'" in msgs[0] and "'fast test'" in msgs[0]
    assert "x3" in msgs[0] and "at most x2" in msgs[0]
    # a ViscoHyperelastic carries its own N
    assert len(rate_sensitivity(cs, m)) == 1


def test_model_generated_curves_pass_and_softer_faster_curve_is_flagged():
    eps = np.linspace(-0.05, -0.5, 10)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    p = dict(C10=0.01, C01=0.02, G1=2.0, tau1=1e-4, G2=0.5, tau2=1e-2)
    rates = (-1.0, -10.0, -100.0, -1000.0)
    cs = [curve(eps, m.stress(p, strain=eps, strain_rate=r), r, f"{r:g}") for r in rates]
    assert rate_sensitivity(cs, m) == []
    soft = cs[:3] + [curve(eps, 0.5 * np.asarray(cs[0].target_stress), -1000.0, "soft fast")]
    msgs = rate_sensitivity(soft, m)
    assert msgs and all("'soft fast'" in x for x in msgs)
    assert any("at least" in x for x in msgs)


def test_no_prony_terms_means_no_rate_dependence():
    eps = np.linspace(-0.05, -0.5, 10)
    s = -np.linspace(0.1, 1.0, 10)
    same = [curve(eps, s, -1.0, "a"), curve(eps, s * 1.01, -10.0, "b")]
    assert rate_sensitivity(same, "mooney_rivlin", 0) == []
    diff = [curve(eps, s, -1.0, "a"), curve(eps, 1.3 * s, -10.0, "b")]
    (msg,) = rate_sensitivity(diff, "mooney_rivlin", 0)
    assert "'a'" in msg and "'b'" in msg and "n_prony" in msg
    assert rate_sensitivity(diff, "mooney_rivlin", 1) == []


@pytest.mark.parametrize("n", [-1, 1.5, True, "two"])
def test_bad_number_of_prony_terms_is_named(n):
    eps = np.linspace(-0.05, -0.5, 10)
    with pytest.raises(ValueError, match=r"^n_prony = .* must be a whole number >= 0$"):
        rate_ratio_bounds("mooney_rivlin", eps, -1.0, -10.0, n_prony=n)


def test_pairs_skip_equal_rates_other_modes_and_time_histories():
    eps = np.linspace(-0.05, -0.5, 10)
    s = -np.linspace(0.1, 1.0, 10)
    t = np.concatenate([[0.0], eps / -5.0])
    cs = [
        curve(eps, s, -1.0, "a"),
        curve(eps, 1.5 * s, -1.0, "replicate"),  # same rate: scatter, not rate sensitivity
        curve(-eps, -s, 1.0, "tension"),
        vhfit.Curve(strain=np.concatenate([[0.0], eps]), stress=np.concatenate([[0.0], 9 * s]),
                    time=t, measure="true", name="timed"),
    ]
    assert rate_pairs(cs, "mooney_rivlin", 2) == []
    assert rate_sensitivity([cs[0]], "mooney_rivlin", 2) == []


def test_gelatin_as_reported_violates_and_table6_stand_in_does_not():
    # the paper: 2500 -> 5700 1/s (x2.28) raises gelatin's stress x4; its own Table 6
    # parameters, being a Prony model, cannot
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    p = dict(C10=0.0, C01=3.56e-4, G1=21.4, tau1=10**-5.76, G2=0.0211, tau2=10**0.871)
    eps = np.linspace(-0.05, -0.5, 10)
    rates = (-0.0107, -2500.0, -3600.0, -5700.0)
    cs = [curve(eps, m.stress(p, strain=eps, strain_rate=r), r, f"{r:g} 1/s") for r in rates]
    assert rate_sensitivity(cs, m) == []
    expo = np.log(4.0) / np.log(5700 / 2500)
    base = np.asarray(cs[1].target_stress)
    steep = cs[:2] + [curve(eps, base * (r / -2500.0) ** expo, r, f"{r:g} 1/s")
                      for r in rates[2:]]
    msgs = rate_sensitivity(steep, m)
    assert len(msgs) == 3
    assert any("'-2500 1/s'" in x and "'-5700 1/s'" in x and "x4" in x for x in msgs)


def test_bad_arguments():
    with pytest.raises(ValueError):
        rate_ratio_bounds("mooney_rivlin", [-0.1], -2.0, -1.0)
    with pytest.raises(ValueError):
        rate_ratio_bounds("mooney_rivlin", [0.1], -1.0, -2.0)
    with pytest.raises(ValueError):
        rate_sensitivity([], "mooney_rivlin", -1)


def test_a_term_that_changes_sign_between_the_rates_leaves_the_ratio_unbounded():
    # In tension the overstress of a Mooney–Rivlin C01 shape changes sign at large
    # stretch, at a smaller strain for the faster ramp (here τ = 0.1 s: positive at rate 1,
    # negative at rate 2 at ε = 2.5, computed with the model). Where a term has opposite
    # signs no mediant bound exists: the bounds are (−inf, inf). Everywhere else every term
    # ratio is positive, so 0 < low <= 1 <= high.
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    with_g = dict(C10=0.0, C01=1.0, G1=1.0, tau1=0.1)
    elastic = dict(with_g, G1=0.0)
    over = [float((m.stress(with_g, strain=[2.5], strain_rate=r)
                   - m.stress(elastic, strain=[2.5], strain_rate=r))[0]) for r in (1.0, 2.0)]
    assert over[0] > 0 > over[1]
    eps = np.linspace(0.05, 4.0, 80)
    low, high = rate_ratio_bounds("mooney_rivlin", eps, 1.0, 2.0)
    unbounded = np.isneginf(low) & np.isposinf(high)
    assert unbounded[np.searchsorted(eps, 2.5)]
    assert np.all(unbounded | ((low > 0) & (low <= 1) & (high >= 1)))


def test_rate_pair_of_stress_tripled_when_rate_doubled():
    eps = np.linspace(-0.05, -0.5, 10)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    p = dict(C10=0.01, C01=0.02, G1=2.0, tau1=1e-4, G2=0.5, tau2=1e-2)
    s = m.stress(p, strain=eps, strain_rate=-100.0)
    cs = [curve(eps, 3.0 * s, -200.0, "fast"), curve(eps, s, -100.0, "slow")]
    (pair,) = rate_pairs(cs, "mooney_rivlin", 2)
    assert isinstance(pair, RatePair)
    assert (pair.slow, pair.fast, pair.rate_slow, pair.rate_fast) == ("slow", "fast", -100.0,
                                                                      -200.0)
    assert pair.rate_ratio == 2.0
    assert pair.stress_ratio == pytest.approx(3.0, rel=1e-12)  # the same factor at every strain
    np.testing.assert_allclose(pair.strain, eps, rtol=1e-12)
    # a Prony series at most doubles the stress when the rate doubles (the viscous limit)
    assert 0 < pair.low < pair.high <= 2.0 * (1 + 1e-9)
    assert pair.too_steep and not pair.too_flat
    # judge() moves the verdict with the tolerance: just above and just below 3 / high
    edge = 3.0 / pair.high - 1
    assert not pair.judge(edge * 1.001).too_steep
    assert pair.judge(edge * 0.999).too_steep
    flat = RatePair("a", "b", -1.0, -2.0, 2.0, 0.5, 0.9, 1.5, eps).judge(0.05)
    assert flat.too_flat and not flat.too_steep  # 0.5 < 0.9 / 1.05


def test_rate_check_compares_uniaxial_ramps_only():
    # a stress rising x3 between rates x2 apart is beyond any Prony series in uniaxial
    # compression; the same pair declared equibiaxial, or at equilibrium, is not checked
    # (the bound is derived for uniaxial loading)
    eps = np.linspace(-0.05, -0.5, 10)
    pair = [vhfit.Curve(strain=eps, stress=eps, strain_rate=-1000.0, name="slow"),
            vhfit.Curve(strain=eps, stress=3 * eps, strain_rate=-2000.0, name="fast")]
    assert len(rate_pairs(pair, "mooney_rivlin", 3)) == 1
    lam = 1.0 + np.linspace(0.05, 0.5, 10)
    equi = [vhfit.Curve(stretch=lam, stress=(lam - 1) * k, strain_rate=r,
                        deformation="equibiaxial", name=n)
            for k, r, n in ((1.0, 1000.0, "slow"), (3.0, 2000.0, "fast"))]
    assert rate_pairs(equi, "mooney_rivlin", 3) == []
    assert rate_sensitivity(equi, "mooney_rivlin", 3) == []
    eq = vhfit.Curve(stretch=lam, stress=lam - 1, name="relaxed")
    assert rate_pairs([eq, *pair], "mooney_rivlin", 3)[0].slow == "slow"
