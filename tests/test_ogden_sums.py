"""The compiled Ogden sums against the formula λk ∂W/∂λk = Σ_p (2μp/αp) λk^αp.

The reference is written here with Python's own power function on each stretch of each
test's kinematics (λ1 λ2 λ3 = 1), term by term — none of the derived powers (1/√(λ^α),
1/(λ^α)², ...) the library takes from λ1^α. Errors are relative to Σ_p |terms|, the
scale of the rounding of a sum of terms of either sign.
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
from vhfit import modes
from vhfit.objective import Objective

DEFORMATIONS = ("uniaxial", "equibiaxial", "planar", "biaxial", "simple_shear")


def stretches_of(deformation, x1, x2):
    """(λ1, λ2, λ3) written from the kinematics, one sample at a time."""
    out = []
    for a, b in zip(x1, x2):
        if deformation == "uniaxial":
            out.append((a, a**-0.5, a**-0.5))
        elif deformation == "equibiaxial":
            out.append((a, a, a**-2))
        elif deformation == "planar":
            out.append((a, 1.0, 1 / a))
        elif deformation == "biaxial":
            out.append((a, b, 1 / (a * b)))
        else:  # simple shear, amount a: λ = a/2 + √(1 + a²/4), principal (λ, 1/λ, 1)
            lam = a / 2 + math.sqrt(1 + a * a / 4)
            out.append((lam, 1 / lam, 1.0))
    return out


def reference(deformation, x1, x2, consts):
    """Σ_p 2μp/αp λk^αp and Σ_p |...| per parameter set, sample and stretch."""
    ref = np.zeros((len(consts), 3, len(x1)))
    scale = np.zeros_like(ref)
    for p, c in enumerate(consts):
        for s, lam in enumerate(stretches_of(deformation, x1, x2)):
            for k in range(3):
                terms = [2 * mu / al * lam[k] ** al for mu, al in zip(c[::2], c[1::2])]
                ref[p, k, s] = sum(terms)
                scale[p, k, s] = sum(abs(t) for t in terms)
    return ref, scale


terms = st.integers(2, 6)
alphas = st.floats(-12.0, 12.0).filter(lambda a: abs(a) > 0.05)
mus = st.floats(-2.0, 2.0)


@accuracy
@given(st.sampled_from(DEFORMATIONS), terms, st.data())
def test_kirchhoff_of_ogden_laws_match_the_formula_in_every_test(deformation, n, data):
    x1 = data.draw(st.lists(st.floats(0.2, 4.0), min_size=1, max_size=6))
    if deformation == "simple_shear":
        x1 = [v - 1.0 for v in x1]  # an amount of shear of either sign
    x2 = data.draw(st.lists(st.floats(0.3, 3.0), min_size=len(x1), max_size=len(x1)))
    consts = data.draw(st.lists(
        st.lists(st.tuples(mus, alphas), min_size=n, max_size=n), min_size=1, max_size=4))
    consts = [[v for pair in c for v in pair] for c in consts]
    model = hyp.get(f"ogden{n}")
    lam = modes.principal_stretches(deformation, np.array(x1),
                                    np.array(x2) if deformation == "biaxial" else None)
    got = modes.kirchhoff_stress(model, np.array(consts), *lam)
    ref, scale = reference(deformation, x1, x2, consts)
    for k in range(3):
        assert np.all(np.abs(got[k] - ref[:, k]) <= 1e-13 * scale[:, k] + 1e-300)


@accuracy
@given(st.floats(0.2, 5.0), st.tuples(mus, alphas), st.tuples(mus, alphas))
def test_uniaxial_stress_of_ogden2_matches_the_formula(lam, t1, t2):
    # σ = λ1 ∂W/∂λ1 − λ2 ∂W/∂λ2 on the path (λ, λ^-1/2, λ^-1/2)
    c = [t1[0], t1[1], t2[0], t2[1]]
    terms = [2 * mu / al * (lam**al - lam ** (-al / 2)) for mu, al in (t1, t2)]
    scale = sum(2 * abs(mu / al) * (lam**al + lam ** (-al / 2)) for mu, al in (t1, t2))
    got = float(hyp.get("ogden2").stress([lam], c)[0])
    assert abs(got - sum(terms)) <= 1e-13 * scale


def test_large_exponents_take_every_power_by_its_own_exp():
    # |α ln λ| ≈ 345, past the range where the derived powers are used; λ3^α = e^(∓690)
    lam = np.array([1e3, 1e-3])
    consts = np.array([[1.0, 50.0, 0.5, -3.0]])
    got = modes.kirchhoff_stress(hyp.get("ogden2"), consts, *modes.principal_stretches(
        "equibiaxial", lam))
    ref, _ = reference("equibiaxial", lam, lam, consts.tolist())
    for k in range(3):
        assert np.all(np.isfinite(got[k]))
        np.testing.assert_allclose(got[k], ref[:, k], rtol=1e-12)


def test_invalid_constants_give_nan_not_a_number_from_a_derived_power():
    lam = modes.principal_stretches("uniaxial", np.array([1.5, 2.0]))
    got = modes.kirchhoff_stress(hyp.get("ogden2"), np.array([[1.0, np.nan, 0.5, 2.0]]), *lam)
    assert all(np.isnan(g).all() for g in got)


def test_a_term_without_modulus_adds_nothing_even_where_its_power_overflows():
    # the admissible set's rows are laws of one term each (the other μ = 0): 0 · ∞ must
    # not make them NaN. One term μ = 1, α = 2: λk ∂W/∂λk = 2 μ/α λk² = λk²
    from vhfit.hyperelastic._ogden import ogden_sums

    l1, l2, l3 = modes.principal_stretches("uniaxial", np.array([2.0, 3.0]))
    col = lambda v: np.array([[v]])  # noqa: E731 (one parameter set, as a column)
    got = ogden_sums(l1, l2, l3, [col(0.0), col(1.0)], [col(900.0), col(2.0)])
    for g, lam in zip(got, (l1, l2, l3)):
        np.testing.assert_allclose(g[0], lam**2, rtol=1e-14)


def test_scalar_constants_and_one_stretch_keep_their_shapes():
    nh_like = hyp.get("ogden2")  # μ1 = 0.5, α1 = 2, μ2 = 0: neo-Hooke with C10 = 0.25
    s = nh_like.stress([2.0], [0.5, 2.0, 0.0, 1.0])
    assert s.shape == (1,) and abs(float(s[0]) - 0.5 * (4.0 - 0.5)) < 1e-14
    s2 = nh_like.stress([[2.0, 1.5]], np.array([[[0.5, 2.0, 0.0, 1.0]]] * 3))
    assert s2.shape == (3, 1, 1, 2)


def test_a_parameter_sets_sums_do_not_depend_on_the_others_evaluated_with_it():
    """A NaN or huge α in one set must not change how the other sets' powers are taken
    (the results of a population and of a subset agree to the bit)."""
    lam = modes.principal_stretches("uniaxial", np.linspace(0.05, 3.0, 40))
    ok = np.array([[1.0, 2.0, 0.5, -3.0], [0.3, 5.0, 0.1, 1.5]])
    for odd in ([1.0, np.nan, 0.5, 2.0], [1.0, 400.0, 0.5, 2.0]):
        both = modes.kirchhoff_stress(hyp.get("ogden2"), np.vstack([ok, [odd]]), *lam)
        alone = modes.kirchhoff_stress(hyp.get("ogden2"), ok, *lam)
        for b, a in zip(both, alone):
            np.testing.assert_array_equal(b[:2], a)


# ------------------------------------------- the guard where exp over- or underflows
# Past |α ln λ| ≈ 708 a power λ^α = e^(α ln λ) leaves float64's normal range (e^709.78
# overflows, e^−708.4 is subnormal, e^−745.1 is 0), so a power derived from λ1^α
# (1/√(λ1^α), 1/(λ1^α λ2^α)) is wrong there even where the power itself is an ordinary
# number: uniaxial λ2^α = e^(−α ln λ1 / 2) is e^370 for α ln λ1 = −740, not 1/√(e^−740).
EPS = np.finfo(float).eps


def power(lam, alpha):
    """λ^α by Python's power function: the float64 value, inf where it overflows."""
    try:
        return lam**alpha
    except OverflowError:
        return math.inf


def guarded_reference(deformation, x1, x2, consts):
    """Kirchhoff sums term by term with Python's powers, and a bound on the difference
    from exp(α ln λ) of the library's own stretches: a stretch 1 ulp away moves λ^α by
    |α| ulp, rounding ln λ and α ln λ moves it by 2 |α ln λ| ulp, the exp and the power
    by an ulp each: (|α| + 2 |α ln λ| + 3) ε of each term, doubled."""
    ref = np.zeros((len(consts), 3, len(x1)))
    tol = np.zeros_like(ref)
    for p, c in enumerate(consts):
        for s, lam in enumerate(stretches_of(deformation, x1, x2)):
            for k in range(3):
                terms = [(2 * mu / al * power(lam[k], al), al, abs(al * math.log(lam[k])))
                         for mu, al in zip(c[::2], c[1::2])]
                ref[p, k, s] = sum(t for t, _, _ in terms)
                tol[p, k, s] = sum(2 * (abs(al) + 2 * x + 3) * EPS * abs(t)
                                   for t, al, x in terms)
    return ref, tol


def assert_matches(got, ref, tol):
    for k in range(3):
        assert not np.isnan(got[k]).any()
        inf = np.isinf(ref[:, k])
        np.testing.assert_array_equal(got[k][inf], ref[:, k][inf])
        assert np.all(np.abs(got[k][~inf] - ref[:, k][~inf]) <= tol[:, k][~inf])


#: one term with α = 1000 (its μ small enough for stresses of order 1), one of
#: ordinary size, beside parameter sets of ordinary size only
HUGE = [1e-160, 1000.0, 0.5, 2.0]
SMALL = [[1.0, 2.0, 0.5, -3.0], [0.3, 5.0, 0.1, 1.5]]


@pytest.mark.parametrize("least", [-0.74, -0.8])  # ln λ1: 1000 ln λ1 = −740 (e0 subnormal)
def test_uniaxial_powers_past_the_exp_range_are_each_terms_own_exp(least):  # or −800 (0)
    x1 = [math.exp(least), 0.7, 1.0, 1.3]
    consts = [SMALL[0], HUGE, SMALL[1]]
    got = modes.kirchhoff_stress(hyp.get("ogden2"), np.array(consts),
                                 *modes.principal_stretches("uniaxial", np.array(x1)))
    ref, tol = guarded_reference("uniaxial", x1, x1, consts)
    # the regime: λ1^1000 subnormal or 0, λ2^1000 = e^370 or e^400 a visible share
    lam2_power = 2 * HUGE[0] / HUGE[1] * power(x1[0] ** -0.5, HUGE[1])
    assert power(x1[0], HUGE[1]) < np.finfo(float).tiny
    assert np.isfinite(ref).all() and lam2_power > 1e-3 * abs(ref[1, 1, 0])
    assert_matches(got, ref, tol)


def test_biaxial_third_power_past_the_exp_range_is_its_own_exp():
    """α ln λ = (−760, 400, 360): λ1^α is 0 in float64 but λ3^α = e^360 is not ∞."""
    x1, x2 = [math.exp(-0.76), 0.8, 1.2], [math.exp(0.4), 1.1, 0.9]
    consts = [SMALL[0], HUGE, SMALL[1]]
    got = modes.kirchhoff_stress(hyp.get("ogden2"), np.array(consts),
                                 *modes.principal_stretches("biaxial", np.array(x1),
                                                            np.array(x2)))
    ref, tol = guarded_reference("biaxial", x1, x2, consts)
    assert power(x1[0], HUGE[1]) == 0.0 and power(1 / (x1[0] * x2[0]), HUGE[1]) > 1e156
    assert np.isfinite(ref).all()
    assert_matches(got, ref, tol)


def test_population_past_the_exp_range_each_set_alone_and_overflow_is_inf_error():
    """Compression to λ = e^−0.8 of four sets: two ordinary, one with α1 = 1000 (finite
    stresses), one with α1 = −1000 (λ^α = e^800 overflows, so does its stress). Each
    set's stresses are those it has alone (to the bit) and the reference's; the
    overflowing set, and one whose overflowing terms have both signs (∞ − ∞), get +inf
    stresses and +inf error, never NaN."""
    lam = np.linspace(0.95, math.exp(-0.8), 12)
    law = hyp.get("ogden2")
    m = vhfit.ViscoHyperelastic("ogden2", 0)
    curve = vhfit.Curve(strain=lam - 1, stress=law.stress(lam, SMALL[0]), strain_rate=-1.0,
                        n_points=None)
    batch, obj = m.batch([curve]), Objective([curve])
    overflow = [1e-160, -1000.0, 0.5, 2.0]
    both_signs = [1e-160, -1000.0, -5e-161, -1100.0]
    population = np.array([SMALL[0], HUGE, overflow, SMALL[1], both_signs])
    s = batch(population)
    err = obj(s)
    assert not np.isnan(s).any() and not np.isnan(err).any()
    assert np.all(np.isposinf(s[[2, 4]])) and np.all(np.isposinf(err[[2, 4]]))
    for i in (0, 1, 3):
        np.testing.assert_array_equal(s[i], batch(population[i:i + 1])[0])
        np.testing.assert_array_equal(s[i], batch(population[::-1])[4 - i])
        ref, tol = guarded_reference("uniaxial", lam, lam, [population[i].tolist()])
        # nominal stress of the curve: (λ1 ∂W/∂λ1 − λ3 ∂W/∂λ3) / λ1
        sig = (ref[0, 0] - ref[0, 2]) / lam
        assert np.all(np.abs(s[i] - sig) <= (tol[0, 0] + tol[0, 2]) / lam + 4 * EPS * abs(sig))
        assert np.isfinite(err[i])


def test_plans_are_remembered_only_for_stretches_that_cannot_change():
    """The stretch plan (logarithms, derived powers) is kept by the arrays' identity only
    for read-only arrays; a writeable array changed in place is planned again."""
    from vhfit import _fixed
    from vhfit.hyperelastic import _ogden

    x = np.linspace(0.5, 2.0, 7)
    lam = [x, x**-0.5, x**-0.5]
    mu, al = [np.array([[0.4]]), np.array([[-0.05]])], [np.array([[3.0]]), np.array([[-2.0]])]
    _ogden.ogden_sums(*lam, mu, al)
    lam[0][:] = np.linspace(1.5, 3.0, 7)  # in place: the old logarithms would be stale
    lam[1][:] = lam[0] ** -0.5
    lam[2][:] = lam[0] ** -0.5
    got = np.array(_ogden.ogden_sums(*lam, mu, al))[:, 0, :]
    ref, scale = reference("uniaxial", lam[0], lam[0], [(0.4, 3.0, -0.05, -2.0)])
    assert np.all(np.abs(got - ref[0]) <= 1e-13 * scale[0])
    fixed = [v.copy() for v in lam]
    for v in fixed:
        v.flags.writeable = False
    _fixed._MEMO.clear()
    _ogden.ogden_sums(*fixed, mu, al)
    assert ("ogden plan", *map(id, fixed)) in _fixed._MEMO
    view = np.asarray(lam[0])[::1]  # a read-only view of writeable data is not fixed
    view.flags.writeable = False
    _ogden.ogden_sums(view, fixed[1], fixed[2], mu, al)
    assert len(_fixed._MEMO) == 1
