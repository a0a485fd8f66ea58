"""Tests of vhfit.optimize: SciPy compatibility, extras, determinism, bad input.

SciPy's own DE test suite runs against vhfit.optimize in tests/test_scipy_de_suite.py;
the tau bounds and the minimize plugin are in tests/test_optimize_tau.py and
tests/test_optimize_minimize.py.
"""

from __future__ import annotations

import inspect
import math
import warnings

import numpy as np
import pytest
import scipy.optimize as so
from numpy.testing import assert_array_equal
from scipy.optimize import Bounds, LinearConstraint, NonlinearConstraint, rosen

import vhfit.optimize as vo
from vhfit.optimize import (
    LSHADE,
    SHADE,
    BestMeanGap,
    DifferentialEvolutionSolver,
    EnergySpread,
    MaxEvaluations,
    MaxGenerations,
    MaxTime,
    MeanImprovement,
    StopCriterion,
    StopState,
    TargetValue,
    differential_evolution,
    paper_criteria,
)
from vhfit.optimize._strategies import _crossover, _repair_midpoint

BOUNDS3 = [(0.0, 2.0)] * 3


def sphere(x):
    return float(np.sum((x - 0.3) ** 2))


def sphere_vec(x):
    """x of shape (N, S)."""
    return np.sum((x - 0.3) ** 2, axis=0)


def _same_result(a, b):
    assert sorted(a) == sorted(b)
    for k in a:
        va, vb = a[k], b[k]
        if isinstance(va, np.ndarray):
            assert_array_equal(va, vb, err_msg=k)
        elif isinstance(va, list):
            for xa, xb in zip(va, vb, strict=True):
                assert_array_equal(xa, xb, err_msg=k)
        else:
            assert va == vb or (va != va and vb != vb), k


# ============================================================== SciPy compatibility
def test_signature_starts_with_scipys():
    ours = list(inspect.signature(differential_evolution).parameters.values())
    theirs = list(inspect.signature(so.differential_evolution).parameters.values())
    assert len(ours) > len(theirs)
    for p, q in zip(ours, theirs):
        assert (p.name, p.default, p.kind) == (q.name, q.default, q.kind)
    extras = ours[len(theirs):]
    assert {p.name for p in extras} >= {"population_size", "stop", "history", "preset"}
    assert all(p.kind is inspect.Parameter.KEYWORD_ONLY for p in extras)
    assert all(p.default in (None, False, 0) for p in extras)


def test_solver_signature_starts_with_scipys():
    from scipy.optimize._differentialevolution import (
        DifferentialEvolutionSolver as SciPySolver,
    )
    ours = list(inspect.signature(DifferentialEvolutionSolver.__init__).parameters.values())
    theirs = list(inspect.signature(SciPySolver.__init__).parameters.values())
    for p, q in zip(ours, theirs):
        assert (p.name, p.default, p.kind) == (q.name, q.default, q.kind)
    assert issubclass(DifferentialEvolutionSolver, SciPySolver)


def _c(x):
    return x[0] + x[1]


@pytest.mark.parametrize(
    "kw",
    [
        dict(rng=1),
        dict(seed=4, maxiter=60),
        dict(rng=np.random.default_rng(7), strategy="rand1exp", polish=False, maxiter=60),
        dict(rng=2, updating="deferred", strategy="currenttobest1bin", init="sobol",
             maxiter=60),
        dict(rng=3, mutation=0.6, recombination=0.9, init="halton", tol=1e-4, atol=1e-9),
        dict(rng=5, x0=[0.1, 0.2, 0.3], init="random", maxiter=20, popsize=7),
        dict(rng=6, integrality=[True, False, False], polish=False, maxiter=30),
        dict(rng=8, constraints=NonlinearConstraint(_c, -np.inf, 1.0), polish=False,
             maxiter=30),
        dict(rng=9, constraints=LinearConstraint([[1, 1, 1]], -np.inf, 2.0), polish=False,
             maxiter=30, updating="deferred"),
        dict(rng=10, init=np.linspace(0, 2, 24).reshape(8, 3), maxiter=15),
    ],
    ids=lambda kw: ",".join(k for k in kw if k != "rng"),
)
def test_bit_identical_to_scipy_without_extras(kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = so.differential_evolution(rosen, BOUNDS3, **kw)
        if "rng" in kw and isinstance(kw["rng"], np.random.Generator):
            kw = dict(kw, rng=np.random.default_rng(7))
        b = differential_evolution(rosen, BOUNDS3, **kw)
    _same_result(a, b)


def test_bit_identical_vectorized_and_positional_seed():
    a = so.differential_evolution(rosen, BOUNDS3, (), "best1bin", 50, 5, 0.01, (0.5, 1), 0.7,
                                  3)
    b = differential_evolution(rosen, BOUNDS3, (), "best1bin", 50, 5, 0.01, (0.5, 1), 0.7, 3)
    _same_result(a, b)
    kw = dict(vectorized=True, updating="deferred", rng=11, maxiter=40)
    _same_result(so.differential_evolution(sphere_vec, BOUNDS3, **kw),
                 differential_evolution(sphere_vec, BOUNDS3, **kw))


def test_callable_strategy_and_callback_like_scipy():
    def strat(candidate, population, rng=None):
        r = rng.permutation(len(population))[:3]
        return np.clip(population[r[0]] + 0.5 * (population[r[1]] - population[r[2]]), 0, 2)

    seen = []

    def cb(intermediate_result):
        seen.append(intermediate_result.nit)

    a = so.differential_evolution(rosen, BOUNDS3, strategy=strat, rng=1, maxiter=5,
                                  polish=False)
    b = differential_evolution(rosen, BOUNDS3, strategy=strat, rng=1, maxiter=5,
                               polish=False, callback=cb)
    assert_array_equal(a.x, b.x)
    assert seen == [1, 2, 3, 4, 5]


def test_seed_and_rng_together_is_a_type_error():
    with pytest.raises(TypeError, match="multiple values"):
        differential_evolution(rosen, BOUNDS3, rng=1, seed=1)


def test_no_extras_result_has_only_scipy_fields():
    r = differential_evolution(sphere, BOUNDS3, rng=0, maxiter=5)
    assert not {"stop_reason", "history"} & set(r)


# ============================================================== determinism
def test_same_seed_same_result_with_extras():
    kw = dict(rng=42, history=True, snapshots=5, population_size=20, maxiter=40,
              stop=TargetValue(1e-12) | MaxGenerations(30), polish=False)
    a = differential_evolution(rosen, BOUNDS3, **kw)
    b = differential_evolution(rosen, BOUNDS3, **kw)
    _same_result({k: v for k, v in a.items() if k != "history"},
                 {k: v for k, v in b.items() if k != "history"})
    assert_array_equal(a.history.best, b.history.best)
    assert_array_equal(a.history.mean, b.history.mean)
    for pa, pb in zip(a.history.populations, b.history.populations, strict=True):
        assert_array_equal(pa, pb)


@pytest.mark.parametrize("strategy", ["best1bin", "shade", "lshade", "jde"])
def test_workers_1_and_2_bit_identical(strategy):
    # rosen is a module-level function: it pickles for the process pool
    kw = dict(rng=5, strategy=strategy, updating="deferred", maxiter=15, polish=False,
              popsize=6, history=True)
    one = differential_evolution(rosen, BOUNDS3, workers=1, **kw)
    two = differential_evolution(rosen, BOUNDS3, workers=2, **kw)
    assert_array_equal(one.x, two.x)
    assert one.fun == two.fun and one.nfev == two.nfev and one.nit == two.nit
    assert_array_equal(one.population, two.population)
    assert_array_equal(one.history.best, two.history.best)


def test_workers_2_plain_scipy_path_identical():
    kw = dict(rng=3, updating="deferred", maxiter=10, polish=False)
    one = differential_evolution(rosen, BOUNDS3, workers=1, **kw)
    two = differential_evolution(rosen, BOUNDS3, workers=2, **kw)
    assert_array_equal(one.population, two.population)
    assert one.fun == two.fun


# ============================================================== population_size
@pytest.mark.parametrize("init", ["latinhypercube", "random", "halton", "sobol"])
def test_population_size_is_absolute(init):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Sobol' warns that 37 is not a power of 2
        res = differential_evolution(sphere, [(-1, 1)] * 7, population_size=37, init=init,
                                     maxiter=3, rng=0, polish=False)
    assert res.population.shape == (37, 7)
    assert res.population_energies.shape == (37,)
    assert np.all(np.abs(res.population) <= 1)


def test_population_size_uses_scipys_random_stream():
    # NP = popsize * N: the same population and trajectory as SciPy's
    a = so.differential_evolution(rosen, BOUNDS3, popsize=4, rng=2, maxiter=10, polish=False)
    b = differential_evolution(rosen, BOUNDS3, population_size=12, rng=2, maxiter=10,
                               polish=False)
    assert_array_equal(a.population, b.population)


def test_population_size_with_x0_and_init_array():
    x0 = np.array([0.25, 0.5, 1.75])
    s = DifferentialEvolutionSolver(sphere, BOUNDS3, population_size=9, x0=x0, rng=1)
    assert s.population.shape == (9, 3)
    assert_array_equal(s._scale_parameters(s.population[0]), x0)
    assert s.feasible.shape == (9,) and s.constraint_violation.shape == (9, 1)
    with pytest.raises(ValueError, match="population_size"):
        DifferentialEvolutionSolver(sphere, BOUNDS3, population_size=9,
                                    init=np.zeros((6, 3)))
    s = DifferentialEvolutionSolver(sphere, BOUNDS3, population_size=6, init=np.ones((6, 3)))
    assert s.num_population_members == 6


@pytest.mark.parametrize("bad", [4, 0, 6.5, "60", True, [60]])
def test_population_size_bad(bad):
    with pytest.raises(ValueError, match="population_size"):
        differential_evolution(sphere, BOUNDS3, population_size=bad)


# ============================================================== stopping criteria
def _state(best, mean, nit=10, means=None, nfev=100, elapsed=1.0, energies=None):
    st = StopState()
    st.nit, st.best, st.mean, st.nfev, st.elapsed = nit, best, mean, nfev, elapsed
    st.mean_history = list(means) if means is not None else [mean]
    st.best_history = [best]
    st.population_energies = energies
    return st


def test_paper_criteria_defaults_and_logic():
    mi = MeanImprovement()
    assert (mi.rel, mi.window) == (0.02, 2000)
    # 2001 recorded means: generation 0..2000
    flat = [1.0] * 1000 + [0.985] * 1001  # 1.5 % better over 2000 generations
    assert mi(_state(0.5, 0.985, nit=2000, means=flat))
    assert not mi(_state(0.5, 0.985, nit=1999, means=flat[1:]))  # window not yet full
    better = [1.0] * 1000 + [0.97] * 1001  # 3 % better
    assert not mi(_state(0.5, 0.97, nit=2000, means=better))
    assert not mi(_state(0.5, math.inf, nit=2000, means=[math.inf] * 2001))

    gap = BestMeanGap()
    assert gap.rel == 1e-5
    assert gap(_state(1.0, 1.0 + 0.9e-5))
    assert not gap(_state(1.0, 1.0 + 2e-5))
    assert gap(_state(0.0, 0.0))  # a population of identical zeros has converged
    assert gap(_state(100.0, 100.0 + 0.9e-3))  # relative to the mean: 9e-6 <= 1e-5
    assert not gap(_state(0.01, 0.01 + 0.9e-6))  # 9e-5 > 1e-5, although 0.9e-6 < 1e-5
    assert not gap(_state(1.0, math.inf))

    # the window reaches back exactly `window` generations: a 3 % drop in generation 1,
    # flat since, is 3 % over the 2000 generations from 0 to 2000 (no stop), and 0 %
    # over the 1999 from 1 to 2000 (which must not be what is compared)
    early = [1.0] + [0.97] * 2000
    assert not mi(_state(0.5, 0.97, nit=2000, means=early))
    assert MeanImprovement(window=1)(_state(0.5, 0.99, nit=1, means=[1.0, 0.99]))  # 1 % < 2 %
    assert not MeanImprovement(window=1)(_state(0.5, 0.97, nit=1, means=[1.0, 0.97]))

    assert MaxGenerations().n == 100_000
    assert MaxGenerations(10)(_state(1, 1, nit=10)) and not MaxGenerations(10)(_state(1, 1, nit=9))
    assert TargetValue().target == 1e-3
    assert TargetValue()(_state(0.99e-3, 1)) and not TargetValue()(_state(1e-3, 1))

    # SciPy's test std(E) <= atol + tol |mean(E)|: energies 0.95 and 1.05 have std 0.05
    # and mean 1, so tol = 0.06 stops, tol = 0.04 does not; atol adds to it
    e = np.array([0.95, 1.05])
    assert EnergySpread(tol=0.06)(_state(0.95, 1.0, energies=e))
    assert not EnergySpread(tol=0.04)(_state(0.95, 1.0, energies=e))
    assert EnergySpread(tol=0.04, atol=0.011)(_state(0.95, 1.0, energies=e))
    assert not EnergySpread(tol=0.0, atol=0.049)(_state(0.95, 1.0, energies=e))
    assert not EnergySpread(tol=1.0)(_state(0.95, math.inf, energies=np.array([0.95, math.inf])))
    assert MaxEvaluations(100)(_state(1, 1, nfev=100))
    assert not MaxEvaluations(100)(_state(1, 1, nfev=99))
    assert MaxTime(0.5)(_state(1, 1, elapsed=0.6))
    assert not MaxTime(0.5)(_state(1, 1, elapsed=0.4))

    pc = paper_criteria()
    assert [type(c).__name__ for c in pc.criteria] == [
        "MeanImprovement", "BestMeanGap", "MaxGenerations", "TargetValue"]
    assert pc._fire(_state(1e-4, 1.0))[0].name == "TargetValue"
    assert pc._fire(_state(1.0, 2.0)) is None
    assert MaxGenerations.success is False and TargetValue.success is True


def test_composition_any_all_and_callables():
    stop = TargetValue(1.0) | MaxGenerations(5)
    assert stop._fire(_state(2.0, 3.0, nit=5))[0].name == "MaxGenerations"
    both = TargetValue(1.0) & MaxGenerations(5)
    assert both._fire(_state(0.5, 3.0, nit=4)) is None
    assert both._fire(_state(0.5, 3.0, nit=5)) is not None
    assert both.success is False  # one member is a budget criterion

    def early(state):
        return state.nit >= 3 and "three is enough"

    c = early | TargetValue(0.0)  # plain callable on the left of |
    fired = c._fire(_state(2.0, 3.0, nit=3))
    assert fired[0].name == "early" and fired[1] == "three is enough"
    seq = vo._stopping.as_criterion([MaxGenerations(2), early])
    assert isinstance(seq, vo.AnyOf) and len(seq.criteria) == 2


def test_stop_reason_message_success_in_a_run():
    r = differential_evolution(sphere, BOUNDS3, rng=0, stop=TargetValue(1e-6), polish=False)
    assert r.stop_reason == "TargetValue" and r.success
    assert "TargetValue" in r.message and r.fun < 1e-6
    r = differential_evolution(sphere, BOUNDS3, rng=0, stop=MaxGenerations(7), polish=False)
    assert r.stop_reason == "MaxGenerations" and not r.success and r.nit == 7


def test_stop_replaces_tol_and_maxiter_still_caps():
    # tol=1 would stop SciPy after a few generations; with stop= it is not used
    r = differential_evolution(sphere, BOUNDS3, rng=0, tol=1.0, stop=MaxGenerations(40),
                               maxiter=1000, polish=False)
    assert r.nit == 40
    r = differential_evolution(sphere, BOUNDS3, rng=0, stop=MaxGenerations(400), maxiter=25,
                               polish=False)
    assert r.nit == 25 and r.stop_reason == "maxiter" and not r.success
    # without stop=, SciPy's tol test and its message stand
    r = differential_evolution(sphere, BOUNDS3, rng=0, history=True)
    assert r.stop_reason == "tol" and r.message == "Optimization terminated successfully."


def test_user_criterion_subclass_sees_state():
    class Plateau(StopCriterion):
        def __init__(self, n):
            self.n = n

        def check(self, state):
            h = state.best_history
            assert len(h) == state.nit + 1 and h[-1] == state.best
            assert state.population_energies[0] == state.best
            if len(h) > self.n and h[-1] >= h[-1 - self.n]:
                return f"best unchanged for {self.n} generations"
            return False

    r = differential_evolution(lambda x: float(np.round(np.sum(x**2), 1)), BOUNDS3, rng=1,
                               stop=Plateau(15), polish=False)
    assert r.stop_reason == "Plateau" and "unchanged for 15" in r.message


def test_callback_stop_and_maxfun_reasons():
    r = differential_evolution(sphere, BOUNDS3, rng=0, history=True,
                               callback=lambda intermediate_result: True)
    assert r.stop_reason == "callback" and r.nit == 1
    s = DifferentialEvolutionSolver(sphere, BOUNDS3, rng=0, history=True, maxfun=100,
                                    polish=False)
    assert s.solve().stop_reason == "maxfun"


@pytest.mark.parametrize("bad", ["papr", 3, object()])
def test_unknown_stop_is_value_error_naming_stop(bad):
    with pytest.raises(ValueError, match="stop"):
        differential_evolution(sphere, BOUNDS3, stop=bad)


@pytest.mark.parametrize("make", [lambda: MeanImprovement(rel=-1), lambda: MeanImprovement(
    window=0), lambda: BestMeanGap(math.nan), lambda: MaxGenerations(1.5),
    lambda: TargetValue("x"), lambda: MaxTime(-1)])
def test_bad_criterion_parameters(make):
    with pytest.raises(ValueError):
        make()


# ============================================================== history
def test_history_contents():
    r = differential_evolution(rosen, BOUNDS3, rng=3, history=True, snapshots=4,
                               population_size=15, maxiter=30, tol=0, polish=False)
    h = r.history
    assert len(h) == r.nit + 1 == 31
    assert_array_equal(h.nit, np.arange(31))
    assert np.all(np.diff(h.best) <= 0)  # greedy selection: best never worsens
    assert np.all(np.diff(h.mean) <= 1e-12 * np.abs(h.mean[1:]))  # nor the mean
    assert np.all(h.mean >= h.best)
    assert h.nfev[0] == 15 and np.all(np.diff(h.nfev) == 15)
    assert np.all(np.diff(h.time) >= 0) and h.time[0] >= 0
    assert h.best[-1] == r.fun
    assert_array_equal(h.population_size, np.full(31, 15))
    assert_array_equal(h.snapshot_nit, [0, 4, 8, 12, 16, 20, 24, 28])
    assert all(p.shape == (15, 3) for p in h.populations)
    assert np.all((h.populations[0] >= 0) & (h.populations[0] <= 2))  # parameter units
    assert h.population_energies[0][0] == h.best[0]
    assert set(h.as_dict()) == {"nit", "nfev", "best", "mean", "time", "population_size"}
    assert "31 rows" in repr(h)


def test_history_with_solver_iteration():
    s = DifferentialEvolutionSolver(sphere, BOUNDS3, rng=0, history=True, polish=False)
    for _ in range(3):
        next(s)
    res = s.solve()  # continues; generation 0 recorded once
    assert res.history.nit[0] == 0 and np.all(np.diff(res.history.nit) == 1)


def test_history_off_by_default_but_stop_reason_with_extras():
    r = differential_evolution(sphere, BOUNDS3, rng=0, population_size=10, maxiter=5)
    assert "history" not in r and r.stop_reason == "maxiter"


@pytest.mark.parametrize("kw", [dict(history="yes"), dict(snapshots=-1), dict(snapshots=1.5)])
def test_history_bad(kw):
    with pytest.raises(ValueError, match=next(iter(kw))):
        differential_evolution(sphere, BOUNDS3, **kw)


# ============================================================== presets
def test_paper_preset_settings():
    s = DifferentialEvolutionSolver(sphere, BOUNDS3, preset="paper")
    assert s.strategy == "rand1bin" and s.scale == 0.8 and s.dither is None
    assert s.cross_over_probability == 0.7
    assert s.num_population_members == 60 and s._updating == "immediate"
    assert s.polish is False and s.maxiter == 100_000 and s._vh_repair == "clip"
    names = [c.name for c in s._vh_stop.criteria]
    assert names == ["MeanImprovement", "BestMeanGap", "MaxGenerations", "TargetValue"]


def test_preset_explicit_arguments_win():
    s = DifferentialEvolutionSolver(sphere, BOUNDS3, preset="paper", mutation=0.5,
                                    population_size=30, stop=MaxGenerations(3), maxiter=50)
    assert s.scale == 0.5 and s.num_population_members == 30 and s.maxiter == 50
    assert isinstance(s._vh_stop, MaxGenerations)


def test_paper_preset_runs_and_stops_by_a_paper_criterion():
    r = differential_evolution(sphere, BOUNDS3, preset="paper", rng=1, history=True)
    assert r.stop_reason in {"TargetValue", "BestMeanGap"} and r.success
    assert r.fun < 1e-3 and r.population.shape == (60, 3)
    assert "jac" not in r  # no polishing


def test_recommended_preset_is_adaptive():
    s = DifferentialEvolutionSolver(sphere, BOUNDS3, preset="recommended")
    assert isinstance(s.strategy, vo.AdaptiveStrategy) and s._updating == "deferred"
    assert vo.presets() == ("paper", "recommended")


def test_unknown_preset():
    with pytest.raises(ValueError, match="preset"):
        differential_evolution(sphere, BOUNDS3, preset="fast")


# ============================================================== adaptive strategies
@pytest.mark.parametrize("strategy", ["jde", "shade", "lshade"])
@pytest.mark.parametrize("updating", ["immediate", "deferred"])
def test_adaptive_strategies_solve(strategy, updating):
    r = differential_evolution(rosen, [(-2, 2)] * 4, strategy=strategy, updating=updating,
                               population_size=30, rng=1, polish=False, maxiter=3000,
                               stop=TargetValue(1e-8))
    assert r.stop_reason == "TargetValue", r.message
    # f < 1e-8 puts x within sqrt(2e-8 / 0.49) ≈ 2e-4 of the minimum (0.49: the
    # smallest eigenvalue of the 4-D Rosenbrock Hessian there), whatever the path
    assert np.allclose(r.x, 1, atol=1e-3)


@pytest.mark.parametrize("strategy", ["jde", "shade", "lshade"])
def test_adaptive_trials_stay_inside_bounds_and_vectorize(strategy):
    lo, hi = np.array([-1.0, 0.0, 2.0]), np.array([1.0, 0.5, 9.0])
    calls = []

    def f(x):  # vectorized, optimum outside the box so trials push on the bounds
        calls.append(x.shape)
        assert np.all(x >= lo[:, None]) and np.all(x <= hi[:, None])
        return np.sum((x - np.array([3.0, -1.0, 20.0])[:, None]) ** 2, axis=0)

    r = differential_evolution(f, list(zip(lo, hi)), strategy=strategy, vectorized=True,
                               updating="deferred", population_size=12, rng=0, maxiter=100,
                               tol=0, polish=False, history=True)
    assert all(len(s) == 2 and s[0] == 3 for s in calls)
    assert np.allclose(r.x, [1.0, 0.0, 9.0], atol=1e-3)
    assert r.nfev == len(calls)  # SciPy's count: one call per population


def test_adaptive_same_seed_identical_and_instance_reusable():
    strat = SHADE(memory_size=4)
    kw = dict(strategy=strat, rng=9, population_size=20, maxiter=30, polish=False)
    a = differential_evolution(rosen, BOUNDS3, **kw)
    b = differential_evolution(rosen, BOUNDS3, **kw)
    assert_array_equal(a.population, b.population) and a.fun == b.fun
    s = DifferentialEvolutionSolver(rosen, BOUNDS3, strategy=strat)
    assert s.strategy is strat


def test_lshade_population_shrinks_linearly():
    r = differential_evolution(rosen, BOUNDS3, strategy=LSHADE(max_nfev=2000, min_size=5),
                               population_size=40, rng=2, maxiter=400, polish=False,
                               history=True, updating="deferred", tol=0)
    sizes = r.history.population_size
    assert sizes[0] == 40 and np.all(np.diff(sizes) <= 0) and sizes[-1] == 5
    # shrinking drops the worst members: the best energy never gets worse (elitism)
    assert np.all(np.diff(r.history.best) <= 0)
    assert r.population.shape == (5, 3)
    # about linear in evaluations: halfway through the budget, about halfway down
    half = np.searchsorted(r.history.nfev, 1000)
    assert abs(sizes[half] - 22.5) <= 3


def test_adaptive_with_constraints():
    nlc = NonlinearConstraint(lambda x: x[0] + x[1], -np.inf, 1.0)
    for updating in ("immediate", "deferred"):
        r = differential_evolution(lambda x: -x[0] - 2 * x[1], [(0, 1), (0, 1)],
                                   strategy="shade", constraints=nlc, rng=0, polish=False,
                                   updating=updating, maxiter=200)
        assert r.x[0] + r.x[1] <= 1.0 + 1e-12 and r.fun < -1.99


def test_adaptive_parameter_validation():
    with pytest.raises(ValueError, match="memory_size"):
        SHADE(memory_size=0)
    with pytest.raises(ValueError, match="max_nfev"):
        LSHADE(max_nfev=-5)
    with pytest.raises(ValueError, match="tau_F"):
        vo.JDE(tau_F=2)
    assert vo.adaptive_strategies() == ("jde", "shade", "lshade")


# ============================================================== repair modes and NaN
def test_repair_modes():
    s = DifferentialEvolutionSolver(sphere, [(0, 1)] * 3, repair="clip", rng=0)
    t = np.array([[-0.5, 0.5, 1.5]])
    s._ensure_constraint(t)
    assert_array_equal(t, [[0.0, 0.5, 1.0]])
    s = DifferentialEvolutionSolver(sphere, [(0, 1)] * 3, repair="midpoint", rng=0, mutation=0.5,
                                    updating="deferred")
    s.population[:] = 0.6
    s._mutate_many(np.arange(s.num_population_members))  # remembers the parents
    t = np.tile([-0.5, 0.5, 1.5], (s.num_population_members, 1))
    s._ensure_constraint(t)
    assert_array_equal(t[0], [0.3, 0.5, 0.8])
    with pytest.raises(ValueError, match="repair"):
        DifferentialEvolutionSolver(sphere, BOUNDS3, repair="wrap")


def test_adaptive_strategies_repair_and_crossover_by_hand():
    """The self-adaptive strategies' own midpoint repair and binomial crossover."""
    # a component below 0 goes halfway from its parent to 0, one above 1 halfway to 1
    trial = np.array([[1.5, -0.5, 0.3], [2.0, 0.7, -1.0]])
    parents = np.array([[0.8, 0.4, 0.1], [0.2, 0.9, 0.6]])
    assert_array_equal(_repair_midpoint(trial, parents), [[0.9, 0.2, 0.3], [0.6, 0.7, 0.3]])
    # binomial crossover: component j from the mutant where u_j < CR, and j_rand always
    u = np.array([[0.1, 0.95, 0.5, 0.7], [0.6, 0.2, 0.9, 0.3]])
    jrand = np.array([3, 0])
    cand = np.array([0, 1])
    mutants = np.ones((2, 4))
    parents = np.zeros((2, 4))
    out = _crossover(u, jrand, np.array([0.6, 0.25]), cand, mutants, parents)
    assert_array_equal(out, [[1, 0, 1, 1], [1, 1, 0, 0]])


def test_nan_objective_is_inf_with_extras():
    def f(x):
        return math.nan if x[0] > 1.0 else float(np.sum((x - 0.5) ** 2))

    r = differential_evolution(f, BOUNDS3, rng=1, history=True, polish=False, maxiter=50)
    assert not np.isnan(r.population_energies).any()
    assert np.isinf(r.population_energies[r.population[:, 0] > 1.0]).all()
    assert np.isfinite(r.fun) and r.x[0] <= 1.0
    assert not np.isnan(r.history.best).any()

    def fv(x):
        v = np.sum((x - 0.5) ** 2, axis=0)
        v[x[0] > 1.0] = np.nan
        return v

    r = differential_evolution(fv, BOUNDS3, rng=1, vectorized=True, strategy="shade",
                               updating="deferred", polish=False, maxiter=50)
    assert not np.isnan(r.population_energies).any() and np.isfinite(r.fun)


# ============================================================== bad input
@pytest.mark.parametrize("bounds", [[(0, 1), (2, 1)], [(1.0, 0.0)], np.array([[0, 1], [3, -3]])])
def test_lower_above_upper_is_value_error_naming_bounds(bounds):
    with pytest.raises(ValueError, match="bounds"):
        differential_evolution(sphere, bounds)


def test_bounds_object_reversed_and_nonfinite():
    with pytest.raises(ValueError):  # SciPy's Bounds itself may refuse; either way ValueError
        differential_evolution(sphere, Bounds([0.0, 2.0], [1.0, 1.0]))
    with pytest.raises(ValueError, match="finite"):  # SciPy's own message
        differential_evolution(sphere, [(0, 1), (0, np.inf)])
    with pytest.raises(ValueError, match="finite"):
        differential_evolution(sphere, [(np.nan, 1), (0, 1)])


@pytest.mark.parametrize("x0", [[0.5], [0.5, 0.5, 0.5, 0.5], [0.5, np.nan, 0.5]])
def test_mismatched_x0(x0):
    with pytest.raises(ValueError, match="x0"):
        differential_evolution(sphere, BOUNDS3, x0=x0)


def test_x0_outside_bounds_is_scipys_value_error():
    with pytest.raises(ValueError, match="outside the specified bounds"):
        differential_evolution(sphere, BOUNDS3, x0=[0.5, 0.5, 3.0])


def test_unknown_strategy_lists_available():
    with pytest.raises(ValueError, match="strategy") as e:
        differential_evolution(sphere, BOUNDS3, strategy="best3bin")
    assert "rand1bin" in str(e.value) and "shade" in str(e.value)


def test_unknown_init_with_population_size():
    with pytest.raises(ValueError, match="init"):
        differential_evolution(sphere, BOUNDS3, population_size=10, init="grid")


# ============================================================== housekeeping
@pytest.mark.parametrize("resumed", [False, True])
@pytest.mark.parametrize(
    "kw",
    [dict(), dict(history=True, snapshots=2, stop="paper", strategy="lshade",
                  repair="midpoint", population_size=10, updating="deferred")],
)
def test_solver_has_no_reference_cycles(kw, resumed):
    import gc
    import weakref

    gc.disable()
    try:
        s = DifferentialEvolutionSolver(rosen, [(0, 10)] * 2, maxiter=10, **kw)
        if resumed:  # a solver that continues a saved run (load_state)
            donor = DifferentialEvolutionSolver(rosen, [(0, 10)] * 2, maxiter=10, **kw)
            for _ in range(3):
                next(donor)
            s.load_state(donor.state_dict())
            del donor
        s.solve()
        # SciPy < 1.17 keeps its strategy as a bound method on the solver (a cycle of
        # SciPy's own, freed by the garbage collector); vhfit must add none of its own
        vars(s).pop("mutation_func", None)
        ref = weakref.ref(s)
        del s
        assert ref() is None, "solver kept alive by a reference cycle"
    finally:
        gc.enable()


def test_docstring_examples():
    import doctest

    from vhfit.optimize import _de, _minimize, _stopping, _tau

    for mod in (_de, _minimize, _stopping, _tau):
        saved = dict(_tau._STRATEGIES)
        try:
            out = doctest.testmod(mod, optionflags=doctest.ELLIPSIS)
        finally:
            _tau._STRATEGIES.clear()
            _tau._STRATEGIES.update(saved)
        assert out.failed == 0 and (out.attempted > 0 or mod is _stopping), mod.__name__


# ================================================= criteria combinators, history, presets
def test_preset_settings_are_the_papers_and_a_copy():
    """The paper's DE (its §2.2): rand/1/bin, F = 0.8, CR = 0.7, NP = 60, no polish."""
    s = vo.preset_settings("paper")
    assert (s["strategy"], s["mutation"], s["recombination"]) == ("rand1bin", 0.8, 0.7)
    assert s["population_size"] == 60 and s["polish"] is False and s["maxiter"] == 100_000
    s["mutation"] = 0.1  # a copy: changing it does not change the preset
    assert vo.preset_settings("paper")["mutation"] == 0.8
    assert vo.preset_settings("recommended")["strategy"] == "shade"
    with pytest.raises(ValueError, match="available: \\['paper', 'recommended'\\]"):
        vo.preset_settings("fast")


def test_all_of_fires_only_when_every_member_does():
    both = vo.AllOf(MaxGenerations(10), TargetValue(1e-3))
    assert not both(_state(1.0, 2.0, nit=10))  # generations reached, target not
    assert not both(_state(1e-4, 2.0, nit=9))  # target reached, generations not
    reason = both(_state(1e-4, 2.0, nit=10))
    assert reason and " and " in reason
    assert both.name == "(MaxGenerations & TargetValue)"
    assert both.success is False  # a budget member makes the conjunction a budget stop
    assert vo.AllOf(TargetValue(1e-3), BestMeanGap()).success is True
    assert isinstance(MaxGenerations(5) & TargetValue(0.0), vo.AllOf)
    with pytest.raises(ValueError, match="at least one"):
        vo.AllOf()


def test_function_criterion_reports_its_name_and_success():
    calls = []

    def below_half(state):
        calls.append(state.nit)
        return state.best < 0.5 and "best below one half"

    c = vo.FunctionCriterion(below_half, success=False)
    assert c.name == "below_half" and c.success is False
    assert not c(_state(0.7, 1.0, nit=3)) and c(_state(0.4, 1.0, nit=4)) == "best below one half"
    assert calls == [3, 4]
    assert vo.FunctionCriterion(lambda s: True, name="always").name == "always"
    with pytest.raises(ValueError, match="not callable"):
        vo.FunctionCriterion(3.0)
    r = differential_evolution(sphere, BOUNDS3, rng=0, polish=False,
                               stop=vo.FunctionCriterion(lambda s: s.nit >= 7, name="seven"))
    assert r.nit == 7 and r.stop_reason == "seven" and r.success


def test_energy_spread_is_scipys_tolerance_test():
    """std(E) <= atol + tol |mean(E)|, with both tolerances honoured."""
    e = np.array([1.0, 1.1, 1.2, 1.3])  # std = 0.1118..., mean = 1.15
    std, mean = float(e.std()), float(e.mean())
    assert vo.EnergySpread(tol=std / mean * 1.001)(_state(1.0, mean, energies=e))
    assert not vo.EnergySpread(tol=std / mean * 0.999)(_state(1.0, mean, energies=e))
    assert vo.EnergySpread(tol=0.0, atol=std * 1.001)(_state(1.0, mean, energies=e))
    assert not vo.EnergySpread(tol=0.0, atol=std * 0.999)(_state(1.0, mean, energies=e))
    inf = np.array([1.0, np.inf])
    assert not vo.EnergySpread(tol=1e9, atol=1e9)(_state(1.0, math.inf, energies=inf))
    with pytest.raises(ValueError, match="EnergySpread: tol"):
        vo.EnergySpread(tol=-1.0)
    # as the only criterion it reproduces SciPy's stop at the same generation
    ref = so.differential_evolution(sphere, BOUNDS3, rng=4, polish=False, tol=0.01)
    mine = differential_evolution(sphere, BOUNDS3, rng=4, polish=False,
                                  stop=vo.EnergySpread(tol=0.01))
    assert mine.nit == ref.nit and mine.stop_reason == "EnergySpread"
    assert_array_equal(mine.x, ref.x)


def test_de_history_rows_match_the_run():
    r = differential_evolution(sphere, BOUNDS3, rng=2, history=True, snapshots=10,
                               population_size=12, stop=MaxGenerations(25), maxiter=25,
                               polish=False)
    h = r.history
    assert isinstance(h, vo.DEHistory)
    assert len(h) == r.nit + 1 == 26  # row 0 is the initial population
    assert_array_equal(h.nit, np.arange(26))
    assert h.nfev[0] == 12 and np.all(np.diff(h.nfev) == 12)  # one call per member
    assert h.nfev[-1] == r.nfev
    assert h.best[-1] == r.fun and np.all(np.diff(h.best) <= 0)  # elitist: never worse
    assert np.all(h.mean >= h.best) and np.all(np.diff(h.time) >= 0)
    assert_array_equal(h.snapshot_nit, [0, 10, 20])
    pop = h.populations[-1]
    assert pop.shape == (12, 3)
    np.testing.assert_allclose([sphere(x) for x in pop], h.population_energies[-1], rtol=1e-15)
    assert set(h.as_dict()) == {"nit", "nfev", "best", "mean", "time", "population_size"}
    assert_array_equal(h.population_size, 12)
