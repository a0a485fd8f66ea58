"""DifferentialEvolutionSolver.state_dict / load_state: a run saved and resumed is the run.

Every test compares a run cut at a generation boundary, saved through JSON text and
finished in a new solver with the same run uninterrupted: x, fun, nit, nfev and the
history must be equal bit for bit (``==``, never approximately).
"""

from __future__ import annotations

import itertools
import json
import math
import warnings

import numpy as np
import pytest
from numpy.testing import assert_array_equal
from scipy.optimize import NonlinearConstraint, rosen

from vhfit.optimize import (
    SHADE,
    DifferentialEvolutionSolver,
    MeanImprovement,
)
from vhfit.optimize._state import from_plain, plain_column, to_plain

BOUNDS = [(-2.0, 2.0)] * 3
N_GEN = 30  # generations of the uninterrupted run
CUT = 11  # generations before the state is taken


def rows_reach(n):
    """A criterion that looks at the whole history: it fires when it has n + 1 rows."""
    def enough_rows(state):
        return len(state.mean_history) > n and f"{n} generations in the history"
    return enough_rows


def make(strategy, updating, vectorized, criteria, **kw):
    opts = dict(strategy=strategy, maxiter=N_GEN, polish=False, updating=updating,
                vectorized=vectorized, rng=np.random.default_rng(5), popsize=6)
    if criteria:
        # the history-length criterion fires at generation 25 only if the resumed
        # solver sees the generations before the cut
        opts.update(history=True, snapshots=4,
                    stop=MeanImprovement(rel=1e-12, window=8) | rows_reach(25))
    else:
        opts.update(tol=0.0)
    opts.update(kw)
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "differential_evolution: the 'vectorized'",
                                UserWarning)
        return DifferentialEvolutionSolver(rosen, BOUNDS, **opts)


def json_round_trip(state):
    return json.loads(json.dumps(state, allow_nan=False))


def assert_same_result(res, ref):
    assert_array_equal(res.x, ref.x)
    assert res.fun == ref.fun
    assert res.nit == ref.nit
    assert res.nfev == ref.nfev
    assert res.message == ref.message
    assert res.success == ref.success
    assert_array_equal(res.population, ref.population)
    assert_array_equal(res.population_energies, ref.population_energies)
    assert getattr(res, "stop_reason", None) == getattr(ref, "stop_reason", None)
    if "history" in ref:
        h, g = res.history, ref.history
        for name in ("nit", "nfev", "best", "mean", "population_size", "snapshot_nit"):
            assert_array_equal(getattr(h, name), getattr(g, name))
        assert len(h.populations) == len(g.populations)
        for a, b in zip(h.populations + h.population_energies,
                        g.populations + g.population_energies):
            assert_array_equal(a, b)


CASES = list(itertools.product(
    ["best1bin", "rand1bin", "jde", "shade", "lshade"],
    ["deferred", "immediate"],
    [False, True],
    [False, True],
))


@pytest.mark.parametrize("strategy,updating,vectorized,criteria", CASES)
def test_resume_is_bit_identical(strategy, updating, vectorized, criteria):
    ref = make(strategy, updating, vectorized, criteria).solve()
    first = make(strategy, updating, vectorized, criteria)
    for _ in range(CUT):
        next(first)
    state = json_round_trip(first.state_dict())
    assert state["generations"] == CUT
    second = make(strategy, updating, vectorized, criteria)
    second.load_state(state)
    res = second.solve()
    assert_same_result(res, ref)
    if criteria:
        assert res.stop_reason == "enough_rows" and res.nit == 25
    else:
        assert res.nit == N_GEN


@pytest.mark.parametrize("strategy", ["rand1bin", "jde", "lshade"])
def test_state_taken_in_callback(strategy):
    saved = {}

    def callback(intermediate_result):
        if intermediate_result.nit == CUT:
            saved["state"] = json.dumps(solver.state_dict(), allow_nan=False)

    solver = make(strategy, "immediate", False, True, callback=callback)
    ref = solver.solve()
    resumed = make(strategy, "immediate", False, True, callback=callback)
    resumed.load_state(json.loads(saved["state"]))
    assert_same_result(resumed.solve(), ref)


def test_callback_sees_the_total_generation_count():
    seen = []

    def callback(intermediate_result):
        seen.append(intermediate_result.nit)

    solver = make("shade", "deferred", True, False, callback=callback)
    for _ in range(CUT):
        next(solver)
    resumed = make("shade", "deferred", True, False, callback=callback)
    resumed.load_state(solver.state_dict())
    assert resumed.solve().nit == N_GEN
    assert seen == list(range(CUT + 1, N_GEN + 1))


@pytest.mark.parametrize("strategy", ["best1bin", "shade"])
def test_resume_at_the_generation_where_the_run_converged(strategy):
    # SciPy tests convergence after the callback: a state taken in the callback of
    # the last generation resumes into an immediate, successful stop
    states = []

    def keep(intermediate_result):
        states.append(solver.state_dict())

    solver = make(strategy, "deferred", False, False, tol=0.3, maxiter=500, callback=keep)
    ref = solver.solve()
    assert ref.success and ref.nit < 500
    resumed = make(strategy, "deferred", False, False, tol=0.3, maxiter=500)
    resumed.load_state(json_round_trip(states[-1]))
    res = resumed.solve()
    assert (res.nit, res.nfev, res.message, res.success) == (
        ref.nit, ref.nfev, ref.message, ref.success)
    assert res.fun == ref.fun


def test_resume_with_stop_criteria_at_the_stopping_generation():
    states = []

    def keep(intermediate_result):
        states.append(solver.state_dict())

    solver = make("jde", "deferred", False, True, callback=keep)
    ref = solver.solve()
    resumed = make("jde", "deferred", False, True)
    resumed.load_state(states[-1])
    res = resumed.solve()
    assert res.stop_reason == ref.stop_reason == "enough_rows"
    assert (res.nit, res.nfev, res.message) == (ref.nit, ref.nfev, ref.message)


def test_resumed_run_polishes_as_the_uninterrupted_one():
    ref = make("rand1bin", "deferred", False, True, polish=True).solve()
    first = make("rand1bin", "deferred", False, True, polish=True)
    for _ in range(CUT):
        next(first)
    second = make("rand1bin", "deferred", False, True, polish=True)
    second.load_state(json_round_trip(first.state_dict()))
    assert_same_result(second.solve(), ref)


def test_next_continues_after_load_state():
    a = make("lshade", "immediate", False, True)
    b = make("lshade", "immediate", False, True)
    for _ in range(CUT):
        next(a)
    b.load_state(json_round_trip(a.state_dict()))
    for _ in range(8):
        xa, fa = next(a)
        xb, fb = next(b)
        assert_array_equal(xa, xb)
        assert fa == fb
    assert a.state_dict()["population_size"] < 18  # L-SHADE has shrunk
    sa, sb = a.state_dict(), b.state_dict()
    for key in ("population", "population_energies", "random_state", "donor_index", "nfev",
                "generations", "evaluations", "strategy_state"):
        assert sa[key] == sb[key], key


def test_resume_twice_and_with_a_larger_maxiter():
    ref = make("shade", "deferred", False, False, maxiter=40).solve()
    a = make("shade", "deferred", False, False, maxiter=10)
    a.solve()
    b = make("shade", "deferred", False, False, maxiter=25)
    b.load_state(json_round_trip(a.state_dict()))
    assert b.solve().nit == 25
    c = make("shade", "deferred", False, False, maxiter=40)
    c.load_state(json_round_trip(b.state_dict()))
    assert_same_result(c.solve(), ref)


def test_nothing_left_to_do():
    a = make("best1bin", "deferred", False, True, maxiter=12)
    ref = a.solve()
    b = make("best1bin", "deferred", False, True, maxiter=12)
    b.load_state(a.state_dict())
    res = b.solve()
    assert res.nit == 12 and res.nfev == ref.nfev and res.stop_reason == "maxiter"
    assert len(res.history) == 13


def test_constraints_and_legacy_random_state():
    # infeasible members have infinite energy; a legacy RandomState (rng=int) keeps a
    # cached normal deviate (SHADE draws NP normals, NP odd)
    con = NonlinearConstraint(lambda x: x[0] + x[1], -np.inf, 1.0)

    def run(cut=None, state=None):
        s = DifferentialEvolutionSolver(rosen, BOUNDS, strategy="shade", maxiter=20,
                                        population_size=13, rng=3, constraints=con,
                                        polish=False, history=True)
        if state is not None:
            s.load_state(state)
        if cut is None:
            return s.solve()
        for _ in range(cut):
            next(s)
        return s.state_dict()

    state = json_round_trip(run(cut=7))
    assert state["random_state"]["kind"] == "RandomState"
    assert_same_result(run(state=state), run())


def test_history_time_continues_from_elapsed():
    a = make("rand1bin", "deferred", False, True)
    for _ in range(CUT):
        next(a)
    state = json_round_trip(a.state_dict())
    b = make("rand1bin", "deferred", False, True)
    b.load_state(state)
    h = b.solve().history
    saved = from_plain(state["history"]["time"])
    assert_array_equal(h.time[:CUT + 1], saved)
    assert h.time[CUT + 1] >= state["elapsed"] >= saved[-1]


def test_state_is_plain_json():
    s = make("lshade", "deferred", False, True)
    fresh = s.state_dict()  # before the initial population is evaluated: all inf
    text = json.dumps(fresh, allow_nan=False)
    assert np.isinf(from_plain(json.loads(text)["population_energies"])).all()
    for _ in range(25):
        next(s)
    state = s.state_dict()
    assert json.loads(json.dumps(state, allow_nan=False)) == state

    def plain(obj):
        if isinstance(obj, dict):
            return all(isinstance(k, str) and plain(v) for k, v in obj.items())
        if isinstance(obj, list):
            return all(plain(v) for v in obj)
        if isinstance(obj, float):
            return math.isfinite(obj)
        return obj is None or isinstance(obj, (bool, int, str))

    assert plain(state)
    assert state["format"] == "vhfit.DifferentialEvolutionSolver" and state["version"] == 1
    assert state["strategy"].startswith("LSHADE(")
    assert set(state["strategy_state"]) >= {"M_F", "M_CR", "k", "archive", "n_archive"}


def test_plain_conversion_is_exact():
    values = {
        "f": np.array([0.1, -0.0, 5e-324, np.inf, -np.inf, np.nan, 1e308]),
        "f32": np.array([0.1, np.inf], dtype=np.float32),
        "u32": np.arange(4, dtype=np.uint32).reshape(2, 2),
        "b": np.array([True, False]),
        "empty": np.zeros((0, 3)),
        "scalars": [np.float64(0.3), np.int64(7), 0.2, math.inf, -math.inf, 2**100],
        "tuple": (1, "a", None, False),
    }
    back = from_plain(json.loads(json.dumps(to_plain(values), allow_nan=False)))
    for key in ("f", "f32", "u32", "b", "empty"):
        assert back[key].dtype == values[key].dtype
        assert back[key].shape == values[key].shape
        assert back[key].tobytes() == values[key].tobytes()
    assert back["scalars"] == values["scalars"]
    assert type(back["scalars"][0]) is np.float64 and type(back["scalars"][1]) is np.int64
    assert back["tuple"] == values["tuple"]
    with pytest.raises(TypeError):
        to_plain(object())
    # the fast path for history columns stores what to_plain stores
    for column, dtype in [([1.0, math.inf, math.nan, -0.0, -math.inf], "float64"),
                          ([1e308, 1e308], "float64"), ([3, 2**40], "int64"), ([], "float64")]:
        assert plain_column(column, dtype) == to_plain(np.asarray(column, dtype=dtype))


# ------------------------------------------------------------------ refusals
def saved_state(**kw):
    s = make("shade", "deferred", False, True, **kw)
    next(s)
    return s.state_dict()


@pytest.mark.parametrize("build,match", [
    (lambda: DifferentialEvolutionSolver(rosen, [(-2, 2)] * 4, strategy="shade",
                                         rng=1, history=True),
     "the state has 3 parameters but this solver's bounds define 4"),
    (lambda: DifferentialEvolutionSolver(rosen, [(-2, 2), (-2, 2), (-1, 2)],
                                         strategy="shade", rng=1, history=True),
     r"bounds differ from the saved run's \(parameter 2"),
    (lambda: make("lshade", "deferred", False, True),
     "saved with strategy 'SHADE.*' but this solver uses 'LSHADE"),
    (lambda: make(SHADE(memory_size=5), "deferred", False, True),
     "memory_size=6.*memory_size=5"),
    (lambda: make("rand1bin", "deferred", False, True), "uses 'rand1bin'"),
    (lambda: DifferentialEvolutionSolver(rosen, BOUNDS, rng=1), "uses 'best1bin'"),
    (lambda: make("shade", "deferred", False, True, rng=1),
     r"random generator is a Generator \(PCG64\) but this solver's is a RandomState"),
])
def test_mismatched_state_is_refused(build, match):
    solver = build()
    with pytest.raises(ValueError, match=match) as exc:
        solver.load_state(saved_state())
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith("load_state: ")


def test_extras_mismatch_is_refused():
    plain = make("best1bin", "deferred", False, False)
    next(plain)
    with pytest.raises(ValueError, match="saved by a solver without vhfit's extras"):
        make("best1bin", "deferred", False, True).load_state(plain.state_dict())
    extra = make("best1bin", "deferred", False, True)
    with pytest.raises(ValueError, match="saved by a solver with vhfit's extras"):
        make("best1bin", "deferred", False, False).load_state(extra.state_dict())


@pytest.mark.parametrize("edit,match", [
    (lambda s: {**s, "format": "something else"}, "not a solver state"),
    (lambda s: [1, 2], "not a solver state"),
    (lambda s: {**s, "version": 99}, "state version 99 is not supported"),
    (lambda s: {k: v for k, v in s.items() if k != "population"}, "incomplete or damaged"),
    (lambda s: {**s, "donor_index": to_plain(np.arange(3))}, "do not fit together"),
])
def test_damaged_state_is_refused(edit, match):
    with pytest.raises(ValueError, match=match):
        make("shade", "deferred", False, True).load_state(edit(saved_state()))


def test_refused_state_leaves_the_solver_untouched():
    s = make("shade", "deferred", False, True)
    before = s.state_dict()
    bad = {**saved_state(), "population": "oops"}
    with pytest.raises(ValueError):
        s.load_state(bad)
    assert s.state_dict()["population"] == before["population"]



def test_a_loaded_state_gives_the_criteria_the_best_and_mean_of_its_population():
    seen = []

    def spy(state):
        seen.append((state.best, state.mean))
        return False

    first = make("best1bin", "deferred", False, False, history=True, stop=spy)
    for _ in range(CUT):
        next(first)
    second = make("best1bin", "deferred", False, False, history=True, stop=spy)
    second.load_state(json_round_trip(first.state_dict()))
    seen.clear()
    assert not second.converged()
    e = second.population_energies
    assert e.min() < e.mean()  # the test below can tell best from mean
    assert seen == [(e.min(), pytest.approx(e.mean(), rel=1e-14))]
