"""Stopping: every criterion of calibrate and of vhfit.optimize fired and shown silent.

calibrate's search stops on the first of TargetValue(target), MaxTime(max_time),
BestMeanGap(tol), MeanImprovement(*stall), the generation cap (maxiter) and the user's
callback. With a fixed seed the search follows one trajectory whatever its stopping
settings (they only decide where it ends), so a reference run that no criterion stops
gives the per-generation best and mean; each test places a threshold between two of
those values and checks the run ends exactly at the generation the rule written out
here (not the code's) picks. The criteria of vhfit.optimize are then checked on
hand-built StopState objects at their exact boundary values.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import vhfit
from vhfit.calibration import CalibrationWarning, calibrate
from vhfit.optimize import (
    BestMeanGap,
    EnergySpread,
    MaxEvaluations,
    MaxGenerations,
    MaxTime,
    MeanImprovement,
    StopState,
    TargetValue,
    differential_evolution,
)

TRUTH = dict(C10=0.2, C01=0.1, G1=1.0, tau1=0.01)
CAP = 40  # generations of the reference run
NEVER = dict(target=0.0, tol=0.0, stall=(0.0, 1))  # no criterion but maxiter can fire


# the fits here warn by design; the tests read the warnings from the report
pytestmark = pytest.mark.filterwarnings("ignore::vhfit.calibration.CalibrationWarning")


@pytest.fixture(scope="module")
def curves():
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    eps = np.linspace(-0.05, -0.5, 10)
    return [vhfit.Curve(strain=eps, stress=m.stress(TRUTH, strain=eps, strain_rate=r,
                                                     measure="engineering"), strain_rate=r)
            for r in (-1.0, -100.0)]


def run(curves, **kw):
    opts = dict(n_prony=1, seed=0, uncertainty=False, polish=False, check_rates=False)
    return calibrate(curves, **{**opts, **kw})


@pytest.fixture(scope="module")
def reference(curves):
    """Best and mean of generations 1..CAP of a run that only the cap stops."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CalibrationWarning)
        cal = run(curves, maxiter=CAP, **NEVER)
    assert str(cal.stop_reason) == "maxiter" and cal.nit == CAP
    h = cal.history
    assert h["nit"] == list(range(1, CAP + 1))
    return np.array(h["best"]), np.array(h["mean"])


def first_drop(values) -> int:
    """Index k >= 2 of the first strict new minimum of `values` (a place for a threshold)."""
    for k in range(2, len(values)):
        if values[k] < min(values[:k]):
            return k
    raise AssertionError("no new minimum in the reference run")


# ------------------------------------------------------------------- target


def test_target_stops_at_the_first_generation_whose_best_is_below_it(curves, reference):
    best, _ = reference
    k = first_drop(best)
    # best < target is strict: a target equal to best[k] does not stop at generation k + 1
    at = run(curves, maxiter=CAP, target=float(best[k]), tol=0.0, stall=(0.0, 1))
    assert at.nit > k + 1
    above = math.nextafter(float(best[k]), math.inf)
    cal = run(curves, maxiter=CAP, target=above, tol=0.0, stall=(0.0, 1))
    assert str(cal.stop_reason) == "target reached"
    assert cal.nit == k + 1  # history index k is generation k + 1


def test_target_zero_is_silent(curves, reference):
    cal = run(curves, maxiter=5, **NEVER)
    assert str(cal.stop_reason) == "maxiter" and cal.nit == 5


# ---------------------------------------------------------------- best-mean gap


def test_tol_stops_at_the_first_generation_whose_gap_is_within_it(curves, reference):
    best, mean = reference
    gap = (mean - best) / np.abs(mean)
    k = first_drop(gap)
    tol = 0.5 * (gap[k] + gap[:k].min())  # within reach at generation k + 1 only
    cal = run(curves, maxiter=CAP, target=0.0, tol=float(tol), stall=(0.0, 1))
    assert str(cal.stop_reason) == "converged"
    assert cal.nit == k + 1
    assert gap[k] <= tol < gap[:k].min()


def test_tol_below_every_gap_is_silent(curves, reference):
    best, mean = reference
    gap = (mean - best) / np.abs(mean)
    cal = run(curves, maxiter=CAP, target=0.0, tol=float(0.5 * gap.min()), stall=(0.0, 1))
    assert str(cal.stop_reason) == "maxiter" and cal.nit == CAP


# ------------------------------------------------------------------- stall


@pytest.mark.parametrize("window", [1, 4])
def test_stall_with_a_large_rel_fires_as_soon_as_the_window_is_full(curves, window):
    # every generation improves the mean by less than 99.9 %: the rule fires at the first
    # generation that has `window` generations behind it (generation 0 is the start)
    cal = run(curves, maxiter=CAP, target=0.0, tol=0.0, stall=(0.999, window))
    assert str(cal.stop_reason) == f"mean error improved < 100% over {window} generations"
    assert cal.nit == window


def test_stall_stops_where_the_mean_stops_improving_by_rel(curves, reference):
    _, mean = reference
    # generation w compares with generation 0 (not in the history); its mean m0 >= m1, so
    # its reduction 1 - m_w/m0 >= 1 - m_w/m1: if that is > rel it cannot fire early; the
    # first window (from 3) and new minimum k of the reductions where that holds (any
    # strict new minimum k places rel = the midpoint so that generation k is the first)
    def places():
        for w in range(3, 9):
            red = (mean[:-w] - mean[w:]) / np.abs(mean[:-w])  # red[i]: generation i + w + 1
            for k in range(2, len(red)):
                if red[k] < red[:k].min():
                    rel = 0.5 * (red[k] + red[:k].min())
                    if (mean[0] - mean[w - 1]) / mean[0] > rel:
                        return w, k, rel
        raise AssertionError("no place for the threshold in the reference run")

    w, k, rel = places()
    cal = run(curves, maxiter=CAP, target=0.0, tol=0.0, stall=(float(rel), w))
    assert str(cal.stop_reason).startswith("mean error improved <")
    assert str(cal.stop_reason).endswith(f"over {w} generations")
    assert cal.nit == k + w + 1


def test_stall_with_rel_zero_is_silent(curves):
    # a deferred DE never raises the mean: a reduction is never < 0
    cal = run(curves, maxiter=12, target=0.0, tol=0.0, stall=(0.0, 1))
    assert str(cal.stop_reason) == "maxiter" and cal.nit == 12


# ---------------------------------------------------- max_time, maxiter, callback


def test_max_time_zero_stops_after_the_first_generation(curves):
    cal = run(curves, maxiter=CAP, max_time=0.0, **NEVER)
    assert str(cal.stop_reason) == "max_time" and cal.nit == 1


def test_a_generous_max_time_is_silent(curves):
    cal = run(curves, maxiter=6, max_time=600.0, **NEVER)
    assert str(cal.stop_reason) == "maxiter" and cal.nit == 6


@pytest.mark.parametrize("cap", [1, 3, 7])
def test_maxiter_is_the_exact_number_of_generations(curves, cap):
    cal = run(curves, maxiter=cap, **NEVER)
    assert str(cal.stop_reason) == "maxiter"
    assert cal.nit == cap == len(cal.history["best"])


def test_callback_true_stops_at_that_generation_and_sees_the_history(curves, reference):
    best, mean = reference
    seen = []

    def cb(info):
        seen.append(info)
        return info["generation"] >= 3

    cal = run(curves, maxiter=CAP, callback=cb, **NEVER)
    assert str(cal.stop_reason) == "callback" and cal.nit == 3
    assert [d["generation"] for d in seen] == [1, 2, 3]
    assert [d["best"] for d in seen] == pytest.approx(best[:3], rel=1e-12)
    assert [d["mean"] for d in seen] == pytest.approx(mean[:3], rel=1e-12)
    # x is the search vector of the separable space: (C01 fraction, log10 tau1)
    assert all(d["n_prony"] == 1 and d["x"].shape == (2,) for d in seen)


def test_callback_false_is_silent(curves):
    cal = run(curves, maxiter=4, callback=lambda info: False, **NEVER)
    assert str(cal.stop_reason) == "maxiter" and cal.nit == 4


# --------------------------------------------- vhfit.optimize criteria, by hand


def state(**kw) -> StopState:
    s = StopState()
    for k, v in kw.items():
        setattr(s, k, v)
    return s


def test_mean_improvement_boundary():
    c = MeanImprovement(rel=0.1, window=3)
    # (10 - 9) / 10 == 0.1 exactly: not < 0.1, silent
    assert not c.check(state(mean_history=[10.0, 9.5, 9.2, 9.0], mean=9.0))
    assert c.check(state(mean_history=[10.0, 9.5, 9.2, math.nextafter(9.0, 10)]))
    # compared with the mean `window` generations back, not the first or the last
    assert not c.check(state(mean_history=[10.0, 10.0, 9.5, 9.2, 9.0]))
    assert c.check(state(mean_history=[100.0, 10.0, 9.5, 9.2, 9.5]))


def test_mean_improvement_needs_a_full_window_and_finite_means():
    c = MeanImprovement(rel=0.5, window=3)
    assert not c.check(state(mean_history=[1.0, 1.0, 1.0]))  # 3 entries: window not full
    assert c.check(state(mean_history=[1.0, 1.0, 1.0, 1.0]))
    assert not c.check(state(mean_history=[math.inf, 1.0, 1.0, 1.0]))
    assert not c.check(state(mean_history=[1.0, 1.0, 1.0, math.inf]))


def test_mean_improvement_rel_zero_fires_only_on_a_worse_mean():
    c = MeanImprovement(rel=0.0, window=1)
    assert not c.check(state(mean_history=[2.0, 2.0]))
    assert not c.check(state(mean_history=[2.0, 1.0]))
    assert c.check(state(mean_history=[2.0, 2.5]))


def test_mean_improvement_reason_quotes_the_reduction():
    reason = MeanImprovement(rel=0.3, window=2).check(state(mean_history=[4.0, 3.5, 3.0]))
    assert reason.startswith("mean energy improved by 0.25 (< 0.3)")
    assert "2 generations" in reason


def test_best_mean_gap_boundary():
    c = BestMeanGap(rel=0.01)
    assert c.check(state(best=99.0, mean=100.0))  # gap 1 == 0.01 * 100: fires (<=)
    assert not c.check(state(best=math.nextafter(99.0, 0.0), mean=100.0))
    assert c.check(state(best=-101.0, mean=-100.0))  # relative to |mean|
    assert not c.check(state(best=-101.5, mean=-100.0))
    assert not c.check(state(best=1.0, mean=math.inf))
    assert not BestMeanGap(rel=0.0).check(state(best=1.0, mean=1.0 + 1e-12))
    assert BestMeanGap(rel=0.0).check(state(best=1.0, mean=1.0))


@pytest.mark.parametrize("crit, field, at, reason", [
    (MaxGenerations(5), "nit", 5, "reached 5 generations"),
    (MaxEvaluations(100), "nfev", 100, "reached 100 objective calls (limit 100)"),
    (MaxTime(2.0), "elapsed", 2.0, "wall time 2 s >= 2 s"),
])
def test_budget_criteria_fire_at_their_limit_not_before(crit, field, at, reason):
    below = at - 1 if isinstance(at, int) else math.nextafter(at, 0.0)
    assert not crit.check(state(**{field: below}))
    assert crit.check(state(**{field: at})) == reason
    assert crit.success is False  # a budget, not convergence


def test_max_time_zero_fires_at_once():
    assert MaxTime(0.0).check(state(elapsed=0.0))


def test_target_value_boundary():
    c = TargetValue(1.0)
    assert not c.check(state(best=1.0))  # strict: best < target
    assert c.check(state(best=math.nextafter(1.0, 0.0)))
    assert TargetValue(-1.0).check(state(best=-2.0))
    assert not TargetValue(0.0).check(state(best=math.inf))


def energies(values):
    e = np.array(values, dtype=float)
    return state(population_energies=e, mean=float(e.mean()))


def test_energy_spread_tol_decides():
    s = energies([1.0, 3.0])  # std 1, mean 2
    assert EnergySpread(tol=0.5).check(s)  # 1 <= 0.5 * 2
    assert not EnergySpread(tol=math.nextafter(0.5, 0.0)).check(s)
    assert not EnergySpread(tol=0.4).check(s)
    # the default tol (0.01) would not stop this population; a large tol does
    wide = energies([1.0, 1.1])  # std 0.05, mean 1.05
    assert not EnergySpread().check(wide)
    assert EnergySpread(tol=0.05).check(wide)
    assert not EnergySpread(tol=0.04).check(wide)


def test_energy_spread_atol_and_negative_mean():
    s = energies([1.0, 3.0])
    assert EnergySpread(tol=0.0, atol=1.0).check(s)
    assert not EnergySpread(tol=0.0, atol=0.99).check(s)
    assert EnergySpread(tol=0.25, atol=0.5).check(s)  # 1 <= 0.5 + 0.25 * 2
    assert not EnergySpread(tol=0.24, atol=0.5).check(s)
    neg = energies([-1.0, -3.0])  # |mean| = 2
    assert EnergySpread(tol=0.5).check(neg)
    assert not EnergySpread(tol=0.4).check(neg)


def test_energy_spread_is_silent_with_an_infinite_energy_or_no_population():
    s = state(population_energies=np.array([1.0, math.inf]), mean=math.inf)
    assert not EnergySpread(tol=1e9, atol=1e9).check(s)
    assert not EnergySpread(tol=1e9).check(state())


def test_energy_spread_tol_is_honoured_by_the_solver():
    def sphere(x):
        return float(np.sum(x * x)) + 1.0  # mean far from 0: tol, not atol, decides

    out = {}
    for tol in (1e-2, 1e-6):
        res = differential_evolution(sphere, [(-5, 5)] * 2, rng=1, polish=False,
                                     stop=EnergySpread(tol=tol), maxiter=2000)
        e = res.population_energies
        assert res.stop_reason == "EnergySpread"
        assert e.std() <= tol * abs(e.mean())
        out[tol] = res.nit
    assert out[1e-6] > out[1e-2]


def test_checkpoint_key_tells_other_deformations_apart():
    from vhfit.calibration._bounds import search_bounds
    from vhfit.calibration._checkpoint import fit_key
    from vhfit.calibration._space import Problem

    lam = np.linspace(1.1, 1.6, 6)
    keys = set()
    for mode in ("equibiaxial", "planar"):
        for shift in (0.0, 1e-9):  # a change of one stretch by 1e-9 is another fit
            c = vhfit.Curve(stretch=lam + shift, stress=np.linspace(0.1, 0.6, 6),
                            deformation=mode)
            m = vhfit.ViscoHyperelastic("mooney_rivlin", 0)
            # fixed search limits: only the paths can tell the fits apart
            tau_b, b = search_bounds(m, [c], "free", 3, 1, {"C10": (0, 1), "C01": (0, 1)})
            prob = Problem(m, [c], tau_b, b, 0.0)
            keys.add(fit_key(prob, "separable", 0, 64, 1e-6, 1e-4, None))
    assert len(keys) == 4
