"""Drucker stability (vhfit.stability) against answers derived by hand.

Mooney–Rivlin, W = C10 (I1 − 3) + C01 (I2 − 3), incompressible. With the pressure
eliminated, σ1 − σ3 = 2 (λ1² − λ3²) (C10 + C01 λ2²) for any principal stretches
(from σa = 2 λa² W1 − 2 W2 / λa² − p and λ1 λ2 λ3 = 1). Drucker's condition in each mode
is a positive tangent T = d(σ1 − σ3)/d ln λ = λ d(σ1 − σ3)/dλ:

uniaxial (λ, λ^-1/2, λ^-1/2): σ1 − σ3 = 2 (λ² − 1/λ)(C10 + C01/λ)
    = 2 C10 (λ² − λ⁻¹) + 2 C01 (λ − λ⁻²)
    T = 2 C10 (2λ² + λ⁻¹) + 2 C01 (λ + 2λ⁻²)
    λ² T / 2 = C10 λ (2λ³ + 1) + C01 (λ³ + 2)
    so with k = −C01/C10 (C10 > 0): T > 0  ⇔  f(λ) = λ (2λ³ + 1)/(λ³ + 2) > k.
    f' ∝ (8λ³ + 1)(λ³ + 2) − 3λ² (2λ⁴ + λ) = 2λ⁶ + 14λ³ + 2 > 0: f rises from 0 to ∞,
    so the uniaxial mode is unstable exactly for λ ≤ λu, the root of f(λu) = k, i.e. of
    2λ⁴ − k λ³ + λ − 2k = 0. Example: f(1/2) = (1/2)(5/4)/(17/8) = 5/17, so
    C10 = 17 c, C01 = −5 c puts the edge at λu = 1/2 exactly.

equibiaxial (λ, λ, λ⁻²): σ1 − σ3 = 2 (λ² − λ⁻⁴)(C10 + C01 λ²)
    = 2 C10 (λ² − λ⁻⁴) + 2 C01 (λ⁴ − λ⁻²)
    T = 4 [C10 (λ² + 2λ⁻⁴) + C01 (2λ⁴ + λ⁻²)]
    with μ = λ²: μ² T / 4 = C10 (μ³ + 2) + C01 μ (2μ³ + 1), so T > 0 ⇔ f(μ) < 1/k:
    unstable exactly for λ ≥ λe with f(λe²) = 1/k. The same law as uniaxial read
    backwards (equibiaxial at λ is uniaxial at λ⁻² along the third axis):
    f(λe²) f(λe⁻²) = 1 (f(1/x) = 1/f(x)), hence λe = λu^(−1/2). Example: 17/5 = f(2),
    so λe = √2 for C10 = 17 c, C01 = −5 c.

planar (λ, 1, 1/λ): σ1 − σ3 = 2 (C10 + C01)(λ² − λ⁻²), T = 4 (C10 + C01)(λ² + λ⁻²):
    stable over the whole range iff C10 + C01 > 0, unstable everywhere otherwise.

neo-Hooke (C01 = 0, C10 > 0): T = 2 C10 (2λ² + 1/λ), 4 C10 (λ² + 2λ⁻⁴), 4 C10 (λ² + λ⁻²),
    all > 0: stable in all three modes for every λ.

One-term Ogden (Abaqus form W = 2μ/α² Σ (λa^α − 1), so λa ∂W/∂λa = (2μ/α) λa^α):
    uniaxial    σ1 − σ3 = (2μ/α)(λ^α − λ^(−α/2)),  T = 2μ (λ^α + λ^(−α/2)/2)
    equibiaxial σ1 − σ3 = (2μ/α)(λ^α − λ^(−2α)),   T = 2μ (λ^α + 2λ^(−2α))
    planar      σ1 − σ3 = (2μ/α)(λ^α − λ^(−α)),    T = 2μ (λ^α + λ^(−α))
    each with the sign of μ, whatever α ≠ 0: stable everywhere iff μ > 0.

The check samples n stretches log-spaced over [lo, hi]; an edge it reports is the last
(first) sampled stretch of an unstable interval, so the true edge lies within one sample
step h = ln(hi/lo)/(n − 1) of it, on the stable side.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _budget import accuracy
from hypothesis import given
from hypothesis import strategies as st

from vhfit import hyperelastic as hyp
from vhfit.stability import MODES, StabilityReport, drucker, principal_difference

MR = hyp.get("mooney_rivlin")
NH = hyp.get("neo_hooke")
OGDEN = hyp.get("ogden")
LO, HI, N = 0.2, 5.0, 400
STEP = math.log(HI / LO) / (N - 1)  # grid step in ln λ
SLACK = 1e-6  # the tangent is a central difference: a band this narrow may go either way


def uniaxial_edge(k: float) -> float:
    """The positive root of 2λ⁴ − k λ³ + λ − 2k = 0 (unique: f is increasing)."""
    roots = np.roots([2.0, -k, 0.0, 1.0, -2.0 * k])
    (lam,) = [r.real for r in roots if abs(r.imag) < 1e-12 and r.real > 0]
    return float(lam)


def assert_upper_edge(reported: float, exact: float) -> None:
    """An interval [.., reported] unstable up to the exact edge: reported ≤ exact < next sample."""
    assert -SLACK <= math.log(exact / reported) < STEP + SLACK


def assert_lower_edge(reported: float, exact: float) -> None:
    """An interval [reported, ..] unstable from the exact edge: previous sample < exact ≤ it."""
    assert -SLACK <= math.log(reported / exact) < STEP + SLACK


# ------------------------------------------------------------ hand-computed edges


def test_mooney_rivlin_edges_at_one_half_and_root_two():
    # C10 = 17c, C01 = -5c: k = 5/17 = f(1/2), so λu = 1/2 and λe = √2 (module docstring)
    rep = drucker(MR, [0.17, -0.05])
    assert not rep.stable
    assert set(rep.unstable) == {"uniaxial", "equibiaxial"}  # C10 + C01 > 0: planar stable
    ((a, b),) = rep.unstable["uniaxial"]
    assert a == pytest.approx(LO) and b < 1.0
    assert_upper_edge(b, 0.5)
    ((a, b),) = rep.unstable["equibiaxial"]
    assert b == pytest.approx(HI)
    assert_lower_edge(a, math.sqrt(2.0))


def test_the_closed_form_root_is_the_hand_value():
    assert uniaxial_edge(5 / 17) == pytest.approx(0.5, rel=1e-12)
    assert 0.5 * (2 * 0.5**3 + 1) / (0.5**3 + 2) == pytest.approx(5 / 17, rel=1e-15)


@accuracy
@given(k=st.one_of(st.floats(0.12, 0.95), st.floats(1.05, 9.0)),
       c10=st.floats(1e-3, 1e2))
def test_mooney_rivlin_with_negative_c01_loses_stability_at_the_computed_stretch(k, c10):
    rep = drucker(MR, [c10, -k * c10])
    lam_u = uniaxial_edge(k)
    lam_e = lam_u**-0.5
    assert not rep.stable
    ((a, b),) = rep.unstable["uniaxial"]  # unstable exactly for λ ≤ λu
    assert a == pytest.approx(LO)
    assert_upper_edge(b, lam_u)
    ((a, b),) = rep.unstable["equibiaxial"]  # unstable exactly for λ ≥ λe = λu^(-1/2)
    assert b == pytest.approx(HI)
    assert_lower_edge(a, lam_e)
    if k < 1:  # C10 + C01 > 0
        assert "planar" not in rep.unstable
    else:  # C10 + C01 < 0: planar unstable over the whole range
        ((a, b),) = rep.unstable["planar"]
        assert (a, b) == pytest.approx((LO, HI))


def test_equibiaxial_edge_is_the_uniaxial_edge_read_backwards():
    # f(1/x) = 1/f(x): the identity behind λe = λu^(-1/2)
    x = np.linspace(0.1, 10, 50)
    f = x * (2 * x**3 + 1) / (x**3 + 2)
    g = (1 / x) * (2 / x**3 + 1) / (1 / x**3 + 2)
    np.testing.assert_allclose(f * g, 1.0, rtol=1e-14)


@pytest.mark.parametrize("c10, c01, planar_stable", [(0.1, -0.099, True), (0.1, -0.101, False)])
def test_planar_mode_follows_the_sign_of_c10_plus_c01(c10, c01, planar_stable):
    rep = drucker(MR, [c10, c01])
    assert ("planar" not in rep.unstable) is planar_stable
    if not planar_stable:
        assert rep.unstable["planar"] == [pytest.approx((LO, HI))]


def test_planar_yeoh_edges_are_the_hand_values():
    # Yeoh, C30 = 0: W1 = C10 + 2 C20 x with, in planar tension (λ, 1, 1/λ) and u = ln λ,
    # x = I1 − 3 = 2 cosh 2u − 2 and σ1 − σ3 = 2 W1 (λ² − λ⁻²) = 4 sinh 2u · W1. With
    # c = cosh 2u, T = dσ/du = 8 c (C10 + 4 C20 (c − 1)) + 32 C20 (c² − 1), which vanishes
    # where c C10 + 4 C20 (2c² − c − 1) = 0. C10 = 1, C20 = −0.05: c² − 3c − 1/2 = 0,
    # c = (3 + √11)/2; unstable for |u| ≥ acosh(c)/2, symmetric in ln λ (λ ↔ 1/λ).
    c = (3.0 + math.sqrt(11.0)) / 2.0
    edge = math.exp(math.acosh(c) / 2.0)  # ≈ 2.4808
    rep = drucker(hyp.get("yeoh"), [1.0, -0.05, 0.0])
    (lo_a, lo_b), (hi_a, hi_b) = rep.unstable["planar"]
    assert lo_a == pytest.approx(LO) and hi_b == pytest.approx(HI)
    assert_upper_edge(lo_b, 1.0 / edge)
    assert_lower_edge(hi_a, edge)


def test_interval_edges_move_with_the_grid_resolution():
    # a finer grid brings the reported edge closer to the exact 1/2
    for n in (50, 400, 4000):
        (_, b), = drucker(MR, [0.17, -0.05], n=n).unstable["uniaxial"]
        step = math.log(HI / LO) / (n - 1)
        assert -SLACK <= math.log(0.5 / b) < step + SLACK


# --------------------------------------------------------------- always stable


@accuracy
@given(c10=st.floats(1e-6, 1e4))
def test_neo_hooke_is_stable_in_every_mode_over_the_whole_range(c10):
    rep = drucker(NH, [c10], stretch_range=(0.05, 20.0))
    assert rep.stable and rep.unstable == {}


@accuracy
@given(c10=st.floats(1e-4, 1e2), ratio=st.floats(0.0, 1e2))
def test_mooney_rivlin_with_non_negative_constants_is_stable(c10, ratio):
    # all three tangents are sums of positive terms when C10 > 0 and C01 >= 0
    assert drucker(MR, [c10, ratio * c10]).stable


@accuracy
@given(mu=st.floats(1e-3, 10.0), sign=st.sampled_from([1.0, -1.0]),
       alpha=st.one_of(st.floats(-6.0, -0.5), st.floats(0.5, 6.0)))
def test_one_term_ogden_is_stable_iff_mu_is_positive(mu, sign, alpha):
    # T has the sign of μ in every mode, whatever α (module docstring)
    rep = drucker(OGDEN, [sign * mu, alpha])
    if sign > 0:
        assert rep.stable
    else:
        assert set(rep.unstable) == set(MODES)
        for iv in rep.unstable.values():
            assert iv == [pytest.approx((LO, HI))]


# ------------------------------------------------------------------- invariance


@accuracy
@given(c10=st.floats(1e-3, 1.0), c01=st.floats(-1.0, 1.0), e=st.integers(-20, 20))
def test_scaling_all_moduli_by_a_power_of_two_changes_nothing(c10, c01, e):
    # σ1 − σ3 is linear in the moduli; a power of two scales every rounding exactly, so
    # the report is identical, edges included
    p = np.array([c10, c01])
    assert drucker(MR, p * 2.0**e) == drucker(MR, p)


@accuracy
@given(k=st.one_of(st.floats(0.12, 0.95), st.floats(1.05, 9.0)), factor=st.floats(1e-3, 1e3))
def test_scaling_all_moduli_by_any_positive_factor_keeps_the_intervals(k, factor):
    # the long-term and the instantaneous (= long-term / g∞) laws are stable together
    p = np.array([0.1, -0.1 * k])
    a, b = drucker(MR, p), drucker(MR, factor * p)
    assert a.stable == b.stable and set(a.unstable) == set(b.unstable)
    for mode, iv in a.unstable.items():
        assert len(iv) == len(b.unstable[mode])
        for (lo1, hi1), (lo2, hi2) in zip(iv, b.unstable[mode]):
            assert abs(math.log(lo1 / lo2)) <= STEP * 1.001
            assert abs(math.log(hi1 / hi2)) <= STEP * 1.001


def test_the_stretch_path_agrees_with_the_invariant_path():
    # neo-Hooke written as a stretch energy (complex step along each axis) gives the
    # same principal differences as the invariant form
    hyp.register("_test_nh_stretch", example=(0.1,))(
        lambda l1, l2, l3, mu: mu / 2 * (l1**2 + l2**2 + l3**2 - 3))
    try:
        nh = hyp.get("_test_nh_stretch")
        lam = np.exp(np.linspace(np.log(LO), np.log(HI), 37))
        for l1, l2, l3 in [(lam, lam**-0.5, lam**-0.5), (lam, lam, lam**-2.0),
                           (lam, np.ones_like(lam), 1 / lam)]:
            np.testing.assert_allclose(principal_difference(nh, [0.2], l1, l2, l3),
                                       principal_difference(NH, [0.1], l1, l2, l3),
                                       rtol=1e-13, atol=1e-15)
    finally:
        hyp.unregister("_test_nh_stretch")


# ----------------------------------------------------------- closed forms, words


@accuracy
@given(c10=st.floats(-1.0, 1.0), c01=st.floats(-1.0, 1.0))
def test_principal_difference_matches_the_hand_formulas(c10, c01):
    lam = np.exp(np.linspace(np.log(LO), np.log(HI), 23))
    cases = [
        ((lam, lam**-0.5, lam**-0.5), 2 * (lam**2 - 1 / lam) * (c10 + c01 / lam)),
        ((lam, lam, lam**-2.0), 2 * (lam**2 - lam**-4) * (c10 + c01 * lam**2)),
        ((lam, np.ones_like(lam), 1 / lam), 2 * (c10 + c01) * (lam**2 - lam**-2)),
    ]
    for stretches, expected in cases:
        got = np.reshape(principal_difference(MR, [c10, c01], *stretches), -1)
        # the code's 2 W2 (I1 (λ1² − λ3²) − (λ1⁴ − λ3⁴)) cancels a few digits at λ = 0.2
        np.testing.assert_allclose(got, expected, rtol=1e-10, atol=1e-12)


@accuracy
@given(mu1=st.floats(-1.0, 1.0), a1=st.floats(-8.0, 8.0).filter(lambda a: abs(a) > 0.1),
       mu2=st.floats(-1.0, 1.0), a2=st.floats(-8.0, 8.0).filter(lambda a: abs(a) > 0.1))
def test_ogden2_principal_difference_is_the_sum_of_its_terms(mu1, a1, mu2, a2):
    # σ1 − σ3 = Σ_p (2 μp/αp)(λ1^αp − λ3^αp) in every test (the law's closed form here)
    lam = np.exp(np.linspace(np.log(0.5), np.log(2.0), 17))
    og2 = hyp.get("ogden2")
    for l1, l2, l3 in [(lam, lam**-0.5, lam**-0.5), (lam, lam, lam**-2.0),
                       (lam, np.ones_like(lam), 1 / lam)]:
        expected = sum(2 * m / a * (l1**a - l3**a) for m, a in ((mu1, a1), (mu2, a2)))
        got = np.reshape(principal_difference(og2, [mu1, a1, mu2, a2], l1, l2, l3), -1)
        scale = sum(abs(2 * m / a) * (l1**a + l3**a) for m, a in ((mu1, a1), (mu2, a2)))
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-12 * float(scale.max()))


def test_describe_stable():
    text = drucker(NH, [0.1]).describe()
    assert text == "Drucker-stable in uniaxial, equibiaxial and planar modes for 0.2 <= λ <= 5"


def test_describe_unstable_names_each_mode_and_interval():
    text = drucker(MR, [0.17, -0.05]).describe()
    assert text == "Drucker-UNSTABLE in uniaxial: 0.2 <= λ <= 0.498; equibiaxial: 1.42 <= λ <= 5"


def test_describe_of_a_hand_made_report():
    rep = StabilityReport(False, (0.5, 2.0), {"planar": [(0.5, 0.75), (1.5, 2.0)]})
    assert rep.describe() == "Drucker-UNSTABLE in planar: 0.5 <= λ <= 0.75, 1.5 <= λ <= 2"


# ------------------------------------------------------------------- bad input


@pytest.mark.parametrize("rng", [(1.0, 5.0), (0.5, 1.0), (0.0, 2.0), (2.0, 0.5)])
def test_stretch_range_must_straddle_one(rng):
    with pytest.raises(ValueError, match="stretch_range"):
        drucker(MR, [0.1, 0.05], stretch_range=rng)


def test_wrong_number_of_constants_is_named():
    with pytest.raises(ValueError, match=r"params: model 'mooney_rivlin' takes 2 constants"):
        drucker(MR, [0.1, 0.05, 0.0])
