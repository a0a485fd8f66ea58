"""Objectives: RMSAPE (paper Eq. 20) against a loop-by-loop reference, its laws, batching."""

from __future__ import annotations

import math

import numpy as np
import pytest
from _budget import accuracy
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from vhfit.data import Curve
from vhfit.objective import (
    OBJECTIVES,
    Objective,
    per_curve_rmsape,
    register_objective,
    relative_l2,
    rmsape,
    rmse,
)


def eq20_reference(model, target):
    """Paper Eq. 20 written out: m curves of n points, loops, the curve mean in the divisor."""
    m, n = len(target), len(target[0])
    total = 0.0
    for i in range(m):
        mean = abs(sum(target[i]) / n)
        for j in range(n):
            total += ((target[i][j] - model[i][j]) / mean * 100.0) ** 2
    return math.sqrt(total / (n * m))


def weighted_reference(model, targets, weights):
    """RMS over all points of unequal curves, curve weights on the squared terms."""
    num = den = 0.0
    for mdl, tgt, w in zip(model, targets, weights):
        mean = sum(abs(v) for v in tgt) / len(tgt)
        for a, b in zip(mdl, tgt):
            num += w * ((b - a) / mean * 100.0) ** 2
            den += w
    return math.sqrt(num / den)


# one-signed stresses bounded away from 0 (compression, as in the paper)
stress = st.floats(0.01, 100.0).map(lambda x: -x)


@st.composite
def curves_and_model(draw, equal_n=True):
    m = draw(st.integers(1, 5))
    n = draw(st.integers(1, 12))
    sizes = [n] * m if equal_n else [draw(st.integers(1, 12)) for _ in range(m)]
    targets = [np.array(draw(st.lists(stress, min_size=k, max_size=k))) for k in sizes]
    rel = [np.array(draw(st.lists(st.floats(-0.5, 0.5), min_size=k, max_size=k)))
           for k in sizes]
    model = [t * (1 + r) for t, r in zip(targets, rel)]
    return targets, model


@accuracy
@given(curves_and_model())
def test_rmsape_matches_eq20_written_out(data):
    targets, model = data
    ref = eq20_reference(model, targets)
    assert rmsape(np.array(model), np.array(targets)) == pytest.approx(ref, rel=1e-12, abs=1e-12)
    # the same through the Objective, with concatenated points
    obj = Objective(targets)
    assert obj(np.concatenate(model)) == pytest.approx(ref, rel=1e-12, abs=1e-12)


@accuracy
@given(curves_and_model(equal_n=False), st.lists(st.floats(0.1, 10.0), min_size=5, max_size=5))
def test_unequal_curves_and_weights_match_a_weighted_reference(data, w):
    targets, model = data
    w = w[: len(targets)]
    ref = weighted_reference(model, targets, w)
    assert rmsape(model, targets, weights=w) == pytest.approx(ref, rel=1e-12, abs=1e-12)


@accuracy
@given(curves_and_model(), st.floats(0.1, 10.0))
def test_equal_weights_reproduce_eq20(data, w):
    targets, model = data
    ref = eq20_reference(model, targets)
    got = rmsape(np.array(model), np.array(targets), weights=[w] * len(targets))
    assert got == pytest.approx(ref, rel=1e-12, abs=1e-12)


@accuracy
@given(curves_and_model(), st.floats(1e-3, 1e3))
def test_rmsape_is_scale_invariant(data, c):
    targets, model = data
    a = rmsape(np.array(model), np.array(targets))
    b = rmsape(c * np.array(model), c * np.array(targets))
    assert b == pytest.approx(a, rel=1e-9, abs=1e-9)


@accuracy
@given(curves_and_model(), st.data())
def test_rmsape_is_zero_exactly_when_model_equals_target(data, draw):
    targets, _ = data
    t = np.array(targets)
    assert rmsape(t, t) == 0.0
    i = draw.draw(st.integers(0, t.shape[0] - 1))
    j = draw.draw(st.integers(0, t.shape[1] - 1))
    bumped = t.copy()
    bumped[i, j] *= 1.0 + draw.draw(st.floats(1e-6, 1.0))
    assert rmsape(bumped, t) > 0.0


@accuracy
@given(curves_and_model(equal_n=False), st.integers(1, 6))
def test_batch_equals_one_by_one(data, p):
    targets, model = data
    obj = Objective(targets)
    rng = np.random.default_rng(p)
    pop = np.concatenate(model) * (1 + 0.1 * rng.standard_normal((p, obj.n_points)))
    errors = obj(pop)
    assert errors.shape == (p,)
    for k in range(p):
        assert errors[k] == pytest.approx(obj(pop[k]), rel=1e-12)
    # any batch shape
    assert obj(pop.reshape(1, p, -1)).shape == (1, p)


@accuracy
@given(curves_and_model(equal_n=False), st.lists(st.floats(0.1, 10.0), min_size=5, max_size=5))
def test_residuals_give_the_objective(data, w):
    targets, model = data
    obj = Objective(targets, weights=w[: len(targets)])
    s = np.concatenate(model)
    r = obj.residuals(s)
    assert r.shape == s.shape
    assert math.sqrt(np.mean(r**2)) == pytest.approx(obj(s), rel=1e-12, abs=1e-12)


def test_non_finite_model_stress_gives_inf_never_nan():
    obj = Objective([[-1.0, -2.0], [-3.0, -4.0]])
    pop = np.array([
        [-1.0, -2.0, -3.0, -4.0],
        [np.nan, -2.0, -3.0, -4.0],
        [-1.0, np.inf, -3.0, -4.0],
        [-1.0, -2.0, -np.inf, -4.0],
        [-1.0, -2.0, -3.0, 1e300],
    ])
    e = obj(pop)
    assert e[0] == 0.0
    assert np.all(np.isposinf(e[1:]))
    pc = obj.per_curve(pop)
    assert not np.isnan(pc).any()
    assert np.isposinf(pc[1, 0]) and pc[1, 1] == 0.0
    r = obj.residuals(pop)
    assert not np.isnan(r).any()
    assert np.isinf(r[1, 0])
    assert obj(pop[1]) == math.inf


def test_zero_weight_curve_is_ignored_but_still_checked():
    t = [np.array([-1.0, -2.0]), np.array([-5.0, -7.0])]
    m = [np.array([-1.1, -2.0]), np.array([-50.0, -70.0])]
    assert rmsape(m, t, weights=[1.0, 0.0]) == pytest.approx(rmsape(m[0], t[0]))


def test_per_curve_rmsape_matches_reference():
    t = np.array([[-1.0, -2.0, -3.0], [-10.0, -20.0, -30.0]])
    m = t * np.array([[1.1], [0.9]])
    pc = per_curve_rmsape(m, t)
    for i in range(2):
        assert pc[i] == pytest.approx(eq20_reference(m[i : i + 1], t[i : i + 1]))
    # with equal n and weights, Eq. 20 is the RMS of the per-curve values
    assert rmsape(m, t) == pytest.approx(math.sqrt(np.mean(pc**2)))


def test_mixed_sign_curve_is_scaled_by_mean_absolute_stress():
    t = np.array([-1.0, 1.0, -2.0, 2.0])  # signed mean 0
    m = t + 0.15
    assert rmsape(m, t) == pytest.approx(0.15 / 1.5 * 100)


def test_rmse_and_relative_l2_against_formulas():
    t = [np.array([-1.0, -2.0]), np.array([-30.0])]
    m = [np.array([-1.5, -2.0]), np.array([-33.0])]
    d = np.array([0.5, 0.0, 3.0])
    tt = np.array([-1.0, -2.0, -30.0])
    assert rmse(m, t) == pytest.approx(math.sqrt(np.mean(d**2)))
    assert relative_l2(m, t) == pytest.approx(100 * np.linalg.norm(d) / np.linalg.norm(tt))


def test_objective_reads_curve_weights_and_point_weights():
    eps = np.linspace(0, -0.3, 31)
    a = Curve(eps, 2 * eps, strain_rate=-1.0, n_points=3, weight=3.0)
    b = Curve(eps, 5 * eps, strain_rate=-10.0, n_points=3).with_point_weights([1.0, 0.0, 2.0])
    obj = Objective([a, b])
    assert obj.n_curves == 2 and obj.n_points == 6
    np.testing.assert_array_equal(obj.weights, [3, 3, 3, 1, 0, 2])
    np.testing.assert_array_equal(obj.target, np.r_[a.target_stress, b.target_stress])
    model = obj.target * np.array([1.1, 1, 1, 1, 1.5, 1.2])
    d = (model - obj.target) / obj.scale
    assert obj(model) == pytest.approx(math.sqrt(np.sum(obj.weights * d**2) / 12))
    # the rmsape scale of a curve is its point-weighted mean |stress|
    assert obj.scale[3] == pytest.approx(np.average(np.abs(b.target_stress), weights=[1, 0, 2])
                                         / 100)


def test_split_and_stack_round_trip():
    obj = Objective([[-1.0, -2.0], [-3.0], [-4.0, -5.0, -6.0]])
    v = np.arange(12.0).reshape(2, 6)
    parts = obj.split(v)
    assert [p.shape for p in parts] == [(2, 2), (2, 1), (2, 3)]
    np.testing.assert_array_equal(obj.stack(parts), v)
    # a list of per-curve arrays is accepted directly
    assert obj([[-1.0, -2.0], [-3.0], [-4.0, -5.0, -6.0]]) == 0.0


def test_registry_and_custom_scale_function():
    assert {"rmsape", "rmse", "relative_l2"} <= set(OBJECTIVES)

    @register_objective("half")
    def half(target, curve, weights):
        return np.full(target.shape, 0.5)

    try:
        assert Objective([[1.0, 1.0]], "half")([2.0, 1.0]) == pytest.approx(math.sqrt(2))
    finally:
        del OBJECTIVES["half"]
    assert Objective([[1.0, 1.0]], half)([2.0, 1.0]) == pytest.approx(math.sqrt(2))


@pytest.mark.parametrize(
    "args, match",
    [
        (([[-1.0, 0.0], [0.0, 0.0]],), "mean |stress|"),
        (([],), "no curves"),
        (([[-1.0, np.nan]],), "not finite"),
        (([[-1.0]], "nope"), "unknown objective"),
    ],
)
def test_bad_objective_setup_raises(args, match):
    with pytest.raises(ValueError, match=match.replace("|", r"\|")):
        Objective(*args)


def test_bad_weights_raise():
    with pytest.raises(ValueError, match="weights has 1 entries for 2 curves"):
        Objective([[-1.0], [-2.0]], weights=[1.0])
    with pytest.raises(ValueError, match="all weights are zero"):
        Objective([[-1.0], [-2.0]], weights=[0.0, 0.0])
    with pytest.raises(ValueError, match=">= 0"):
        Objective([[-1.0], [-2.0]], weights=[1.0, -1.0])


def test_wrong_model_shape_raises():
    obj = Objective([[-1.0, -2.0]])
    with pytest.raises(ValueError, match=r"shape \(\.\.\., 2\)"):
        obj([1.0, 2.0, 3.0])


@accuracy
@given(hnp.arrays(np.float64, st.integers(1, 30), elements=st.floats(-1e6, 1e6)))
def test_objective_is_never_nan(model_like):
    n = model_like.size
    target = -np.linspace(1, 2, n)
    for kind in OBJECTIVES:
        e = Objective([target], kind)(model_like)
        assert not math.isnan(e) and e >= 0
