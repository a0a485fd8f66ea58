"""The default objective points: every measured sample, bin means above MAX_POINTS."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import vhfit
import vhfit.data
from vhfit.data import MAX_POINTS, Curve


def test_a_short_record_is_compared_at_its_own_samples():
    t = np.array([0.0, 1.0, 2.5, 3.0, 5.0])
    eps = np.array([0.0, 0.1, 0.2, 0.15, 0.3])  # unloads, so not resampled by strain
    sig = np.array([0.0, 1.0, 3.0, 2.0, 4.0])
    c = Curve(eps, sig, time=t)
    assert c.by == "samples" and c.n_points == 5
    np.testing.assert_array_equal(c.target_time, t)
    np.testing.assert_array_equal(c.target_strain, eps)
    np.testing.assert_array_equal(c.target_stress, sig)
    np.testing.assert_array_equal(c.history.out_time, t)


def test_bins_are_means_of_consecutive_samples(monkeypatch):
    monkeypatch.setattr(vhfit.data, "MAX_POINTS", 4)
    t = np.arange(10.0)
    c = Curve(0.1 * t, t**2, time=t)  # one loading leg: 4 bins of 3, 2, 3, 2 samples
    assert c.by == "bins" and c.n_points == 4
    np.testing.assert_allclose(c.target_time, [1.0, 3.5, 6.0, 8.5], rtol=1e-15)
    np.testing.assert_allclose(c.target_strain, [0.1, 0.35, 0.6, 0.85], rtol=1e-15)
    # means of the stresses, not the stress at the mean time (1, 12.25, 36, 72.25)
    np.testing.assert_allclose(c.target_stress, [5 / 3, 12.5, 110 / 3, 72.5], rtol=1e-15)


def test_no_bin_straddles_a_turning_point(monkeypatch):
    monkeypatch.setattr(vhfit.data, "MAX_POINTS", 4)
    t = np.arange(21.0)
    eps = 0.1 * np.minimum(t, 20 - t)  # up to sample 10, then down
    c = Curve(eps, eps, time=t)
    assert c.n_segments == 2 and c.by == "bins"
    # loading leg: samples 0-10 in 4 * 11 // 21 = 2 bins (0-5, 6-10); unloading 11-20: 1
    np.testing.assert_allclose(c.target_time, [2.5, 8.0, 15.5], rtol=1e-15)
    np.testing.assert_allclose(c.target_strain, [0.25, 0.8, 0.45], rtol=1e-15)


def test_a_constant_rate_record_is_binned_in_strain_and_time(monkeypatch):
    monkeypatch.setattr(vhfit.data, "MAX_POINTS", 2)
    eps = -0.1 * np.arange(1.0, 7.0)
    c = Curve(eps, 2 * eps, strain_rate=-10.0)
    np.testing.assert_allclose(c.target_strain, [-0.2, -0.5], rtol=1e-15)
    np.testing.assert_allclose(c.target_stress, [-0.4, -1.0], rtol=1e-15)
    np.testing.assert_allclose(c.history.out_time, [0.02, 0.05], rtol=1e-15)


def test_a_trim_window_is_binned_inside_the_window(monkeypatch):
    monkeypatch.setattr(vhfit.data, "MAX_POINTS", 2)
    t = np.arange(12.0)
    c = Curve(0.1 * t, t, time=t).trim(time=(4.0, 11.0))  # 8 samples -> 2 bins of 4
    np.testing.assert_allclose(c.target_time, [5.5, 9.5], rtol=1e-15)


def test_a_long_noisy_record_is_averaged_not_picked():
    n = 100_000
    t = np.linspace(0.0, 10.0, n)
    clean = 0.05 * t
    noise = 0.01 * np.random.default_rng(3).standard_normal(n)  # 2 % of the mean stress
    c = Curve(clean, clean + noise, time=t)
    assert c.by == "bins" and c.n_points == MAX_POINTS
    # each bin averages 10^5 / MAX_POINTS samples: noise 0.01 / sqrt(that) is left
    left = 0.01 / np.sqrt(n / MAX_POINTS)
    resid = c.target_stress - 0.05 * c.target_time
    assert 0.8 * left < np.sqrt(np.mean(resid**2)) < 1.2 * left  # plain means


def test_the_paper_scheme_is_kept_on_request():
    eps = np.linspace(0.0, -0.5, 201)
    c = Curve(eps, 4 * eps, strain_rate=-1.0, n_points=10)
    np.testing.assert_allclose(c.target_strain, -0.05 * np.arange(1, 11), rtol=1e-12)
    assert c.resample(None).n_points == 201 and c.resample(None).by == "samples"


def test_exact_data_are_fitted_to_their_own_error_level():
    """The motivating case: 200 samples a curve generated from known constants."""
    truth = dict(C10=0.2, C01=0.1, G1=1.0, tau1=1e-2)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    curves = []
    for r in (-1.0, -100.0):
        eps = np.linspace(0.0, -0.5, 200)
        curves.append(Curve(eps, m.stress(truth, strain=eps, strain_rate=r,
                                          measure="engineering"), strain_rate=r))
    cal = vhfit.calibrate(curves, n_prony=1, seed=0)
    assert sum(c.n_points for c in curves) == 400
    assert cal.rmsape < 1e-6
    assert cal.params["tau1"] == pytest.approx(1e-2, rel=1e-6)


@settings(max_examples=50, deadline=None)
@given(n=st.integers(3, 400), cap=st.integers(2, 60), a=st.floats(0, 0.4), b=st.floats(0.5, 1),
       turn=st.floats(0.2, 0.8))
def test_bin_means_of_a_piecewise_linear_record_stay_on_it(n, cap, a, b, turn):
    """Means of a linear function are the function at the means, so on a load-unload
    record whose stress is linear in time on each leg, every bin's (time, stress) lies on
    the record: no bin mixes the legs, whatever the length and the cap."""
    import vhfit.data._curve as owner

    saved = owner.MAX_POINTS
    owner.MAX_POINTS = cap
    try:
        t = np.linspace(0.0, 1.0, n)
        k = int(turn * (n - 1))
        t_turn = t[k]
        eps = np.where(t <= t_turn, t, 2 * t_turn - t) + 0.5  # up to sample k, then down
        sig = np.where(t <= t_turn, a * t + b, -a * t + b + 2 * a * t_turn)
        c = Curve(eps, sig, time=t)
    finally:
        owner.MAX_POINTS = saved
    tt = c.target_time
    expect = np.where(tt <= t_turn, a * tt + b, -a * tt + b + 2 * a * t_turn)
    np.testing.assert_allclose(c.target_stress, expect, rtol=1e-9, atol=1e-9)
    assert (np.diff(tt) > 0).all()
    if n <= cap:
        assert c.by == "samples" and c.n_points == n
    else:  # about cap bins: at least one per leg
        assert c.by == "bins" and c.n_points <= cap + 2


def test_all_means_every_sample_even_above_the_cap(monkeypatch):
    monkeypatch.setattr(vhfit.data, "MAX_POINTS", 4)
    t = np.arange(10.0)
    c = Curve(0.1 * t, t**2, time=t)
    assert c.by == "bins" and c.n_points == 4
    every = c.resample("all")
    assert every.by == "samples" and every.n_points == 10
    np.testing.assert_array_equal(every.target_stress, t**2)
    with pytest.raises(vhfit.data.DataError, match="'all' for every sample"):
        c.resample("most")
