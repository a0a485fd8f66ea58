"""The speed-ups of the separable search on real records: the early finish once the
population has gathered (a polish in the space's own coordinates, variable
projection), and long records searched on fewer points (then polished on every point).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import vhfit
from vhfit.calibration import CalibrationWarning, StopKind, _search
from vhfit.calibration._bounds import search_bounds
from vhfit.calibration._space import Problem, SeparableSpace


class _Space:
    """A stand-in separable space without levels; ``to_params`` the identity."""

    prob = None

    def __init__(self, separable=True):
        self.separable = separable

    def finish_levels(self, target):
        return ()

    def to_params(self, z):
        return z


# ------------------------------------------------------------ the gathered population
def test_the_best_is_polished_once_when_the_members_are_within_1e3_of_it(monkeypatch):
    calls = []

    def fake_polish(space, z):
        calls.append(float(z[0]))
        return z, z, 0.6, 4  # not below the best 0.6 it is called with: the search goes on

    monkeypatch.setattr(_search, "gathered_polish", fake_polish)
    f = _search._EarlyFinish(_Space(), 1e-4)
    assert f(1.0, np.array([1.0]), 1.0 + 2e-3) is False and calls == []  # gap 2e-3
    assert f(1.0, np.array([2.0]), np.inf) is False and calls == []  # an infinite member
    assert f(0.6, np.array([3.0]), 0.6 * (1 + 0.9e-3)) is False and calls == [3.0]
    assert f(0.6, np.array([4.0]), 0.6) is False and calls == [3.0]  # never twice
    assert not f.done and f.nfev == 4


def test_a_polish_that_lowers_the_gathered_best_ends_the_search(monkeypatch):
    monkeypatch.setattr(_search, "gathered_polish", lambda space, z: (z + 2, z + 1, 0.999, 9))
    f = _search._EarlyFinish(_Space(), 1e-4)
    assert f(1.0, np.array([1.0]), 1.0) is True
    assert f.done and f.result[1] == 0.999 and f.nfev == 9
    assert f.result[0][0] == 2.0 and f.z[0] == 3.0  # the polished search vector is kept
    assert f.reason.kind is StopKind.GATHERED


def test_a_polish_that_does_not_lower_the_best_lets_the_search_go_on(monkeypatch):
    monkeypatch.setattr(_search, "gathered_polish", lambda space, z: (z, z, 1.0, 9))
    f = _search._EarlyFinish(_Space(), 1e-4)
    assert f(1.0, np.array([1.0]), 1.0) is False and not f.done


def test_a_search_without_the_best_mean_gap_stop_never_finishes_gathered(monkeypatch):
    monkeypatch.setattr(_search, "gathered_polish", lambda space, z: 1 / 0)
    f = _search._EarlyFinish(_Space(), 1e-4, tol=0.0)  # tol = 0: run to maxiter
    assert f(1.0, np.array([1.0]), 1.0) is False


def test_the_all_parameter_search_never_finishes_on_a_gathered_population(monkeypatch):
    monkeypatch.setattr(_search, "gathered_polish", lambda space, z: 1 / 0)
    f = _search._EarlyFinish(_Space(separable=False), 1e-4)
    assert f(1.0, np.array([1.0]), 1.0) is False


# ------------------------------------------------------------ fewer points for the search
def test_resample_max_points_gives_the_means_of_that_many_bins(monkeypatch):
    eps = np.linspace(0.001, 0.3, 12)
    c = vhfit.Curve(strain=eps, stress=3 * eps, strain_rate=0.1)
    r = c.resample(None, max_points=4)
    # 12 samples in 4 bins of 3 consecutive samples: their means, written out
    want = eps.reshape(4, 3).mean(axis=1)
    assert r.by == "bins" and np.allclose(r.target_strain, want, rtol=1e-14, atol=0)
    assert np.allclose(r.target_stress, 3 * want, rtol=1e-14, atol=0)
    assert c.resample(None).n_points == 12 and c.n_points == 12  # the default cap: 500
    assert r.resample(None).n_points == 12  # back to the package's cap
    monkeypatch.setattr(vhfit.data, "MAX_POINTS", 3)  # set after the curve was built
    assert c.resample(None).n_points == 3  # the package's cap, read when resampled
    for bad in (0, 2.5, True, "10"):
        with pytest.raises(ValueError, match="max_points"):
            c.resample(None, max_points=bad)


def _ramp_hold(n=450, rate=0.05, lam=2.0, truth=None, noise=0.0, seed=0):
    """A ramp to λ then a hold, sampled n times uniformly in time (MR + 1 Prony term):
    above 500 samples (``MAX_POINTS``) compared at bin means, below at every sample."""
    truth = truth or dict(C10=0.05, C01=0.02, G1=0.3, tau1=4.0)
    t_ramp = (lam - 1) / rate
    t = np.linspace(0.0, 3 * t_ramp, n)
    eps = np.minimum(t * rate, lam - 1)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    s = m.stress(truth, strain=eps, time=t, measure="engineering")
    s = s * (1 + np.random.default_rng(seed).uniform(-noise, noise, s.size))
    return vhfit.Curve(strain=eps[1:], stress=s[1:], time=t[1:], measure="engineering"), truth


def test_long_records_are_searched_on_about_search_points_bin_means():
    long, _ = _ramp_hold(n=1500)
    short = vhfit.Curve(strain=np.linspace(0.01, 0.5, 40), stress=np.linspace(0.01, 0.5, 40),
                        strain_rate=1.0)
    assert long.n_points > 400 and long.by == "bins"
    assert _search.search_items([short]) is None  # nothing long: the curves themselves
    out = _search.search_items([long, short])
    assert out[1] is short
    assert out[0].by == "bins"
    assert 0.9 * _search.SEARCH_POINTS <= out[0].n_points <= _search.SEARCH_POINTS
    assert out[0].weight == long.weight and out[0].n_segments == long.n_segments
    # the history still runs through every sample
    assert out[0].history.time[-1] == long.history.time[-1]
    eq = vhfit.Curve(strain=np.linspace(0.01, 0.5, 300), stress=np.linspace(0.01, 0.5, 300))
    assert eq.is_equilibrium and _search.search_items([eq]) is None  # no integration
    weighted = long.with_point_weights(np.linspace(1.0, 2.0, long.n_points))
    assert _search.search_items([weighted]) is None  # its weights belong to its points


def test_the_search_problem_keeps_the_space_and_shortens_the_objective():
    long, _ = _ramp_hold()
    model = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    tau_b, auto = search_bounds(model, [long], "free", 3, 1, "auto")
    prob = Problem(model, [long], tau_b, auto, 1e-6)
    short = _search.search_problem(prob, [long])
    assert short is not prob and short.batch.n_points < prob.batch.n_points
    assert short.model.rtol == _search.SEARCH_RTOL and prob.model.rtol == 1e-6
    assert short.bounds is prob.bounds and short.tau_b is prob.tau_b
    few = vhfit.Curve(strain=np.linspace(0.01, 0.5, 40), stress=np.linspace(0.01, 0.5, 40),
                      strain_rate=1.0)
    p2 = Problem(model, [few], tau_b, auto, 1e-6)
    same = _search.search_problem(p2, [few])  # few points: all of them, a coarser model
    assert same.batch.n_points == p2.batch.n_points and same.coarse
    assert same.model.rtol == _search.SEARCH_RTOL
    fine = vhfit.ViscoHyperelastic("mooney_rivlin", 1, rtol=1e-3)  # no finer than that
    p3 = Problem(fine, [few], tau_b, auto, 1e-6)
    assert _search.search_problem(p3, [few]) is p3
    elastic = vhfit.ViscoHyperelastic("mooney_rivlin", 0)  # nothing to integrate
    p4 = Problem(elastic, [few], np.zeros((0, 2)), {"C10": (0, 1), "C01": (-1, 1)}, 1e-6)
    assert _search.search_problem(p4, [few]) is p4


def test_the_search_problem_is_marked_coarse_and_its_members_polish_to_a_looser_tol(
        monkeypatch):
    long, _ = _ramp_hold()
    model = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    tau_b, auto = search_bounds(model, [long], "free", 3, 1, "auto")
    prob = Problem(model, [long], tau_b, auto, 1e-6)
    short = _search.search_problem(prob, [long])
    assert short.coarse and not prob.coarse
    tols = []
    monkeypatch.setattr(_search, "varpro_polish",
                        lambda space, z, n, tol: tols.append(tol) or (z, z, 1.0, 0))
    for p in (short, prob):
        _search.gathered_polish(SeparableSpace(p), np.zeros(2))
    assert tols == [_search.COARSE_TOL, _search.ROUNDING_TOL]


def test_a_level_polish_at_the_coarse_floor_is_checked_on_every_point(monkeypatch):
    """On fewer points and a coarser model exact data stop at the model's own floor
    (~1e-3 %): a level polish that gets below the lowest level goes on with the problem
    on every point, which may reach the target and end the search."""
    calls = []

    def fake_polish(prob, x, n):
        calls.append(prob)
        return (x, 2e-3, 5) if prob == "coarse" else (x + 1, 1e-9, 7)

    monkeypatch.setattr(_search, "polish_fit", fake_polish)

    class Coarse(_Space):
        prob = "coarse"

        def finish_levels(self, target):
            return (1e4 * target, 1e2 * target)

    f = _search._EarlyFinish(Coarse(), 1e-4, full="full")
    assert f(0.5, np.array([1.0])) is True and calls == ["coarse", "full"]
    assert f.result[1] == 1e-9 and f.result[0][0] == 2.0 and f.nfev == 12
    # above the lowest level the coarse points still tell: no polish on every point
    monkeypatch.setattr(_search, "polish_fit", lambda prob, x, n: (
        calls.append(prob), (x, 0.05, 5))[1])
    calls.clear()
    f = _search._EarlyFinish(Coarse(), 1e-4, full="full")
    assert f(0.5, np.array([1.0])) is False and calls == ["coarse"]


def test_a_long_exact_record_is_recovered_through_the_shortened_search():
    long, truth = _ramp_hold()
    faster, _ = _ramp_hold(rate=0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CalibrationWarning)
        cal = vhfit.calibrate([long, faster], n_prony=1, seed=0, uncertainty=False)
    assert cal.rmsape <= 1e-6
    for k, v in truth.items():
        assert cal.params[k] == pytest.approx(v, rel=1e-6)


def test_a_long_noisy_record_fits_at_least_as_well_as_the_truth():
    # the shortened search then the polish on every point: no worse than the constants
    # the data were made with (an independent upper bound of the best error)
    long, truth = _ramp_hold(noise=0.02, seed=1)
    faster, _ = _ramp_hold(rate=0.5, noise=0.02, seed=2)
    curves = [long, faster]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CalibrationWarning)
        cal = vhfit.calibrate(curves, n_prony=1, seed=0, uncertainty=False)
    from vhfit.objective import Objective

    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    at_truth = float(Objective(curves)(m.batch(curves)(m.as_array(truth)[None, :]))[0])
    assert cal.rmsape <= at_truth
