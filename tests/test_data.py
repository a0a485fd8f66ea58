"""Test data: Curve, objective points, histories, readers, and every kind of bad input."""

from __future__ import annotations

import io
import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import vhfit.data
import vhfit.data._paths
import vhfit.data._samples
from vhfit.data import (
    DEFAULT_N_POINTS,
    MAX_BREAKPOINTS,
    PATH_RTOL,
    Curve,
    DataError,
    DataWarning,
    curves_from_arrays,
    engineering_to_true,
    read_csv,
    read_history,
    true_to_engineering,
)
from vhfit.data._paths import _simplify_idx


def write(tmp_path, text, name="test.csv", encoding="utf-8"):
    p = tmp_path / name
    if isinstance(text, bytes):
        p.write_bytes(text)
    else:
        p.write_bytes(text.encode(encoding))
    return p


def raises(*parts):
    """pytest.raises(DataError) whose one-line message contains every part."""

    class _Check:
        def __enter__(self):
            self.ctx = pytest.raises(DataError)
            self.info = self.ctx.__enter__()
            return self.info

        def __exit__(self, *exc):
            out = self.ctx.__exit__(*exc)
            msg = str(self.info.value)
            assert "\n" not in msg, msg
            for p in parts:
                assert str(p) in msg, f"{p!r} not in {msg!r}"
            return out

    return _Check()


EPS = np.linspace(0.0, -0.5, 51)


# ===================================================================== Curve
def test_constant_rate_default_compares_every_sample():
    c = Curve(strain=EPS, stress=10 * EPS, strain_rate=-100.0)
    assert DEFAULT_N_POINTS is None and c.n_points == EPS.size and c.by == "samples"
    np.testing.assert_array_equal(c.target_strain, EPS)
    np.testing.assert_array_equal(c.target_stress, 10 * EPS)
    np.testing.assert_allclose(c.history.out_time, EPS / -100.0, rtol=1e-15)


def test_constant_rate_paper_scheme_on_request():
    c = Curve(strain=EPS, stress=10 * EPS, strain_rate=-100.0, n_points=10)
    assert c.n_points == 10
    assert c.by == "strain" and c.mode == "compression" and c.measure == "engineering"
    # evenly spaced in strain, the rest point left out, the last data strain included
    np.testing.assert_allclose(c.target_strain, -0.05 * np.arange(1, 11))
    np.testing.assert_allclose(c.target_stress, 10 * c.target_strain)
    h = c.history
    np.testing.assert_allclose(h.out_time, c.target_strain / -100.0)
    np.testing.assert_allclose(h.out_strain, c.target_strain)
    assert c.is_constant_rate and c.time is None and not c.strain_rate_estimated


def test_data_not_starting_at_rest_keep_both_ends():
    eps = np.linspace(-0.05, -0.5, 10)  # the paper-style 10 samples, no rest point
    c = Curve(eps, 3 * eps, strain_rate=-1.0)
    np.testing.assert_array_equal(c.target_strain, eps)
    np.testing.assert_array_equal(c.target_stress, 3 * eps)


def test_targets_interpolate_the_measured_stress():
    eps = np.array([0.0, 0.1, 0.3, 0.4])
    sig = np.array([0.0, 1.0, 2.0, 5.0])
    c = Curve(eps, sig, strain_rate=1.0, n_points=4)
    np.testing.assert_allclose(c.target_strain, [0.1, 0.2, 0.3, 0.4])
    np.testing.assert_allclose(c.target_stress, [1.0, 1.5, 2.0, 5.0])
    c = c.resample(None)
    np.testing.assert_array_equal(c.target_strain, eps)
    assert c.by == "samples"


@given(
    st.lists(st.floats(1e-3, 1.0), min_size=2, max_size=20),
    st.integers(1, 25),
    st.sampled_from([-1.0, 1.0]),
)
def test_objective_points_lie_on_the_data(steps, n, sgn):
    eps = sgn * 0.8 * np.concatenate([[0.0], np.cumsum(steps)]) / np.sum(steps)
    sig = np.sin(3 * eps) + eps
    c = Curve(eps, sig, strain_rate=sgn * 7.0, n_points=n)
    assert c.n_points == n
    assert np.all(np.diff(c.target_time) > 0)
    assert c.target_strain[-1] == pytest.approx(eps[-1])
    np.testing.assert_allclose(c.target_stress, np.interp(sgn * c.target_strain, sgn * eps, sig))
    np.testing.assert_allclose(np.diff(c.target_strain), eps[-1] / n)


def test_time_curve_history_follows_the_samples():
    t = np.array([0.5, 1.0, 2.0, 3.0])  # first sample after t = 0: a ramp from rest
    eps = np.array([-0.05, -0.1, -0.2, -0.1])
    c = Curve(eps, 2 * eps, time=t, n_points=3)
    h = c.history
    np.testing.assert_allclose(h.time, [0.0, 0.5, 1.0, 2.0, 3.0])
    np.testing.assert_allclose(h.stretch - 1, [0.0, -0.05, -0.1, -0.2, -0.1])
    np.testing.assert_allclose(h.out_time, c.target_time)
    np.testing.assert_allclose(h.out_strain, c.target_strain)
    assert c.n_segments == 2 and c.by == "segments" and c.n_points == 6
    assert -0.2 in c.target_strain  # the turning point


def test_rate_of_a_time_curve_is_estimated_ignoring_holds():
    # ramp at -0.01/s for 30 s, hold 1000 s with a little noise, unload at 0.05/s
    t = np.r_[np.linspace(0, 30, 31), np.linspace(31, 1030, 200), np.linspace(1031, 1036, 6)]
    eps = np.r_[-0.01 * t[:31], -0.3 + 1e-6 * np.sin(t[31:231]), np.linspace(-0.25, 0.0, 6)]
    c = Curve(eps, eps, time=t)
    assert c.strain_rate_estimated
    assert c.strain_rate == pytest.approx(-0.01, rel=1e-6)
    assert Curve(eps, eps, time=t, strain_rate=-0.02).strain_rate == -0.02


def test_loading_unloading_never_by_strain():
    t = np.linspace(0, 2, 41)
    eps = 0.5 - np.abs(0.5 - 0.5 * t)
    c = Curve(eps, eps**2, time=t)
    with raises("not monotonic", "by='segments'"):
        c.resample(10, by="strain")
    tc = c.resample(8, by="time")
    np.testing.assert_allclose(tc.target_time, 0.25 * np.arange(1, 9))
    ac = c.resample(8, by="arclength")
    assert ac.n_points == 8 and ac.target_time[-1] == pytest.approx(2.0)


def test_ramp_and_hold_are_two_segments():
    t = np.linspace(0, 100, 1001)
    eps = np.minimum(0.01 * t, 0.2)
    sig = np.where(t < 20, eps, 0.2 * (0.5 + 0.5 * np.exp(-(t - 20) / 10)))
    c = Curve(eps, sig, time=t, n_points=10)
    assert c.n_segments == 2 and c.by == "segments" and c.n_points == 20
    assert (c.target_time > 20).sum() == 10 and (c.target_time <= 20).sum() == 10
    assert 20.0 in c.target_time and 100.0 in c.target_time  # hold start, test end


def test_multistep_relaxation_segments():
    # up in 3 steps with holds, back down in one ramp: 3 ramps + 3 holds + 1 ramp
    t = np.linspace(0, 700, 7001)
    eps = np.interp(t, [0, 10, 110, 120, 220, 230, 330, 700], [0, .1, .1, .2, .2, .3, .3, 0])
    c = Curve(eps, eps + 0.01 * np.sin(t), time=t, n_points=4)
    assert c.n_segments == 7 and c.n_points == 28


def test_sine_cycles_have_no_holds():
    t = np.linspace(0, 30, 3001)
    c = Curve(0.2 * np.sin(t), np.sin(t), time=t)
    assert c.n_segments == 10  # 9 turning points, no hold at any peak


def test_trim_restricts_points_not_history():
    c = Curve(EPS, 10 * EPS, strain_rate=-100.0, n_points=5)
    tr = c.trim(strain=(-0.4, -0.1))
    np.testing.assert_allclose(tr.target_strain, [-0.1, -0.175, -0.25, -0.325, -0.4])
    t = np.linspace(0, 2, 201)
    eps = 0.5 - np.abs(0.5 - 0.5 * t)
    lu = Curve(eps, eps, time=t)
    cut = lu.trim(time=(None, 1.5))  # drop the slack end of unloading
    assert cut.target_time.max() <= 1.5
    np.testing.assert_array_equal(cut.history.time, lu.history.time)
    both = cut.trim(strain=(0.1, None))
    assert both.target_strain.min() >= 0.1 - 1e-12 and both.target_time.max() <= 1.5
    with raises("keeps 0 sample", "widen it"):
        c.trim(strain=(0.1, 0.2))
    # n_points re-spaced points interpolate between samples: a window needs two of them
    ramp = Curve(np.linspace(0, -0.5, 11), np.linspace(0, -1, 11), strain_rate=-1.0,
                 n_points=5)
    with raises("keeps 1 sample", "widen it"):
        ramp.trim(strain=(-0.26, -0.24))
    with raises("low >= high"):
        c.trim(time=(2.0, 1.0))


def test_point_weights():
    c = Curve(EPS, 10 * EPS, strain_rate=-100.0, n_points=4)
    np.testing.assert_array_equal(c.target_weights, np.ones(4))
    w = c.with_point_weights([1, 2, 3, 4])
    np.testing.assert_array_equal(w.target_weights, [1, 2, 3, 4])
    assert w.resample(3).target_weights.tolist() == [1, 1, 1]  # stale array dropped
    f = c.with_point_weights(lambda e, t, s: np.where(e < -0.3, 0.0, 1.0))
    assert f.resample(5).target_weights.tolist() == [1, 1, 1, 0, 0]  # callable re-applied
    with raises("3 point weights for 4"):
        c.with_point_weights([1, 2, 3])
    with raises("not all 0"):
        c.with_point_weights([0, 0, 0, 0])


def test_stress_measures_round_trip():
    eps = np.array([0.0, -0.2, -0.5])
    sig = np.array([0.0, -1.0, -3.0])
    np.testing.assert_allclose(engineering_to_true(sig, eps), sig * (1 + eps))
    np.testing.assert_allclose(true_to_engineering(engineering_to_true(sig, eps), eps), sig)
    c = Curve(eps, sig, strain_rate=-1.0, n_points=None)
    tc = c.with_measure("cauchy")
    assert tc.measure == "true"
    np.testing.assert_allclose(tc.stress, [0.0, -0.8, -1.5])
    np.testing.assert_allclose(tc.with_measure("nominal").stress, sig)
    assert c.with_measure("engineering") is c


def test_replace_and_repr():
    c = Curve(EPS, EPS, strain_rate=-1.0, name="a").replace(name="b", weight=2.5)
    assert c.name == "b" and c.weight == 2.5
    assert "Curve('b': compression" in repr(c)


def test_arrays_are_read_only():
    c = Curve(EPS, EPS, strain_rate=-1.0)
    with pytest.raises(ValueError):
        c.strain[0] = 1.0
    with pytest.raises(ValueError):
        c.target_stress[0] = 1.0


# ------------------------------------------------------------------ signs
def test_declared_mode_contradicted_by_strain_names_the_row():
    with raises("row 1", "mode='compression'", "compression_positive=True"):
        Curve([0.0, 0.1, 0.2], [0.0, 1.0, 2.0], strain_rate=-1.0, mode="compression")


def test_compression_positive_flips_strain_stress_and_rate():
    c = Curve([0.0, 0.1, 0.2], [0.0, 1.0, 2.0], strain_rate=5.0, compression_positive=True)
    assert c.mode == "compression" and c.strain_rate == -5.0
    np.testing.assert_array_equal(c.strain, [0.0, -0.1, -0.2])
    np.testing.assert_array_equal(c.stress, [0.0, -1.0, -2.0])


def test_positive_magnitudes_with_negative_rate_are_inferred_with_a_warning():
    with pytest.warns(DataWarning, match="negated strain and stress"):
        c = Curve([0.0, 0.1, 0.2], [0.0, 1.0, 2.0], strain_rate=-5.0)
    assert c.mode == "compression" and c.strain.min() == -0.2 and c.stress.min() == -2.0


def test_rate_given_as_magnitude_is_signed_with_a_warning():
    with pytest.warns(DataWarning, match="took strain_rate = -5"):
        c = Curve([0.0, -0.1, -0.2], [0.0, -1.0, -2.0], strain_rate=5.0)
    assert c.strain_rate == -5.0


def test_stress_magnitudes_in_compression_are_inferred_or_rejected():
    with pytest.warns(DataWarning, match="negated it"):
        c = Curve([0.0, -0.1, -0.2], [0.0, 1.0, 2.0], strain_rate=-5.0)
    assert c.stress.max() == 0.0
    with raises("row 2", "wrong sign for a compression curve"):
        Curve([0.0, -0.1, -0.2], [0.0, 1.0, 2.0], strain_rate=-5.0, mode="compression")


def test_small_wrong_sign_noise_is_not_a_mode_change():
    eps = np.r_[[1e-4, -1e-4], np.linspace(-0.01, -0.5, 20)]
    c = Curve(eps, 2 * eps, strain_rate=-1.0, mode="compression")
    assert c.mode == "compression"
    assert np.all(c.target_strain < 0)


def test_mixed_signs_need_a_time_column():
    with raises("changes sign", "give the time column"):
        Curve([-0.1, 0.0, 0.1], [-1.0, 0.0, 1.0], strain_rate=0.01)
    c = Curve([0.0, -0.1, 0.0, 0.2], [0.0, -1.0, 0.0, 1.0], time=[0, 1, 2, 3])
    assert c.mode == "mixed" and c.strain_rate == pytest.approx(-0.1)


# -------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "kwargs, parts",
    [
        (dict(strain=[], stress=[], strain_rate=-1), ["has 0 samples"]),
        (dict(strain=[-0.1], stress=[-1], strain_rate=-1), ["has 1 sample", "at least 2"]),
        (dict(strain=[0, -0.1, np.nan], stress=[0, -1, -2], strain_rate=-1),
         ["row 2", "strain = nan", "not finite"]),
        (dict(strain=[0, -0.1, -0.2], stress=[0, np.inf, -2], strain_rate=-1),
         ["row 1", "stress = inf"]),
        (dict(strain=[0, -0.1, -0.2], stress=[0, -1], strain_rate=-1),
         ["stress has 2 values but strain has 3"]),
        (dict(strain=[0, -0.2, -0.1, -0.3], stress=[0, -2, -1, -3], strain_rate=-1),
         ["row 2", "goes back from -0.2 to -0.1", "time column", "sort"]),
        (dict(strain=[0, -0.1, -0.1, -0.2], stress=[0, -1, -1.5, -2], strain_rate=-1),
         ["row 2", "appears twice", "row 1"]),
        (dict(strain=[0, -0.5, -1.2], stress=[0, -1, -2], strain_rate=-1),
         ["row 2", "stretch 1 + strain <= 0"]),
        (dict(strain=[0, -0.5, -1.0], stress=[0, -1, -2], strain_rate=-1),
         ["row 2", "stretch 1 + strain <= 0"]),  # the edge: stretch exactly 0
        (dict(strain=[0, 0, 0], stress=[0, 1, 2], strain_rate=-1), ["strain is 0 at every"]),
        (dict(strain=[0, -0.1], stress=[0, -1], strain_rate=0.0), ["non-zero rate"]),
        (dict(strain=[0, -0.1], stress=[0, -1], strain_rate="fast"), ["not a number"]),
        (dict(strain=[0, -0.1], stress=[0, -1], time=[0, 1], measure="pk2"), ["'true'"]),
        (dict(strain=[0, -0.1], stress=[0, -1], time=[0, 1], mode="shear"), ["'mixed'"]),
        (dict(strain=[0, -0.1], stress=[0, -1], time=[0, 1], n_points=0), ["n_points=0"]),
        (dict(strain=[0, -0.1], stress=[0, -1], time=[0, 1], by="index"), ["by='index'"]),
        (dict(strain=[0, -0.1], stress=[0, -1], time=[0, 1], weight=-1), ["weight=-1"]),
        (dict(strain=[0, -0.1, -0.2], stress=[0, -1, -2], time=[0, 2, 1]),
         ["row 2", "time goes back"]),
        (dict(strain=[0, -0.1, -0.2], stress=[0, -1, -2], time=[-1, 0, 1]),
         ["row 0", "starts at -1"]),
        (dict(strain=[0, -0.1, -0.2], stress=[0, -1, -2], time=[0, 1, 1]),
         ["row 2", "same time (1 s)", "different strains"]),
    ],
)
def test_bad_curves_raise_a_clear_error(kwargs, parts):
    with raises("curve 'x'", *parts):
        Curve(name="x", **kwargs)


def test_errors_use_row_labels_and_source():
    with raises("curve 'fast' (tests.csv, line 7)"):
        Curve([0, -0.2, -0.1], [0, -1, -2], strain_rate=-1.0, name="fast", source="tests.csv",
              rows=["line 5", "line 6", "line 7"])


def test_duplicate_time_samples_are_merged():
    c = Curve([0, -0.1, -0.1, -0.2], [0, -1.0, -1.2, -2.0], time=[0, 1, 1, 2], n_points=None)
    np.testing.assert_allclose(c.time, [0, 1, 2])
    np.testing.assert_allclose(c.stress, [0, -1.1, -2.0])


def test_exact_duplicate_rows_are_dropped_at_constant_rate():
    c = Curve([0, -0.1, -0.1, -0.2], [0, -1.0, -1.0, -2.0], strain_rate=-1.0, n_points=None)
    np.testing.assert_allclose(c.strain, [0, -0.1, -0.2])


# ------------------------------------------------------- long histories
def test_a_million_samples_give_a_short_history():
    n = 1_000_000
    t = np.linspace(0.0, 200.0, n)
    eps = np.where(t < 100, 0.01 * t, 2.0 - 0.01 * t)  # load to 1, unload to 0
    sig = eps + 0.1 * np.sin(t)
    c = Curve(eps, sig, time=t, n_points=10)
    h = c.history
    assert h.time.size < 50
    np.testing.assert_allclose(h.stretch_at(t) - 1, eps, atol=PATH_RTOL * 1.0 + 1e-12)
    assert c.n_segments == 2 and c.n_points == 20
    assert float(c.target_strain[9]) == pytest.approx(1.0, abs=1e-5)  # the turning point


def test_a_noisy_long_signal_is_averaged_with_a_warning():
    n = 200_000
    t = np.linspace(0.0, 200.0, n)
    clean = np.where(t < 100, 0.01 * t, 2.0 - 0.01 * t)
    eps = clean + 1e-3 * np.random.default_rng(0).standard_normal(n)  # 0.1 % of range
    c = Curve(eps, 2.0 * clean, time=t)
    # rate from the record's shape, not from sample-to-sample noise (1e-3 / 1e-3 s)
    assert c.strain_rate == pytest.approx(0.01, rel=0.02)
    with pytest.warns(DataWarning, match=r"noisy.*2000-bin average.*MAX_BREAKPOINTS"):
        h = c.history
    assert 2 <= h.time.size <= MAX_BREAKPOINTS + 1  # + the rest point at t = 0
    path = h.stretch_at(t) - 1
    # no noise spikes: the history is as smooth as a 100-sample average (σ 1e-4) ...
    assert np.sqrt(np.mean((path - clean) ** 2)) < 2e-4
    # ... and keeps the turning point to within a bin's rounding
    assert abs(path.max() - 1.0) < 2e-3


def test_a_noisy_long_ramp_hold_still_finds_its_hold():
    n = 200_000
    t = np.linspace(0.0, 10.0, n)
    clean = -0.3 * np.minimum(t, 1.0)
    eps = clean + 3e-4 * np.random.default_rng(2).standard_normal(n)
    c = Curve(eps, 2.0 * clean - 0.1, time=t)
    assert c.n_segments == 2  # the ramp and the hold, found in bin means
    assert c.strain_rate == pytest.approx(-0.3, rel=0.02)


def test_max_breakpoints_is_the_documented_knob(monkeypatch):
    """Setting vhfit.data.MAX_BREAKPOINTS, as the warning says, caps every path it names."""
    n = 5000
    t = np.linspace(0.0, 200.0, n)
    clean = np.where(t < 100, 0.01 * t, 2.0 - 0.01 * t)
    eps = clean + 3e-3 * np.random.default_rng(3).standard_normal(n)
    bins = []
    real = vhfit.data._paths._bin_means

    def spy(t, e, k):
        bins.append(k)
        return real(t, e, k)

    monkeypatch.setattr(vhfit.data._paths, "_bin_means", spy)
    monkeypatch.setattr(vhfit.data, "MAX_BREAKPOINTS", 50)
    c = Curve(eps, 2.0 * clean, time=t)
    with pytest.warns(DataWarning, match=r"50-bin average"):
        h = c.history
    assert 2 <= h.time.size <= 51
    assert c.n_segments == 2 and 50 in bins  # the hold search of the segments honours it too
    monkeypatch.setattr(vhfit.data, "MAX_BREAKPOINTS", 5000)
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataWarning)
        h = Curve(eps, 2.0 * clean, time=t).history
    assert h.time.size > 51


@given(
    st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=300),
    st.floats(1e-4, 0.2),
    st.integers(2, 60),
)
def test_path_simplification_limit(values, tol, limit):
    e = np.cumsum(values)
    t = np.arange(e.size, dtype=float)
    full = _simplify_idx(t, e, tol)
    capped = _simplify_idx(t, e, tol, limit=limit)
    if full.size <= limit:
        np.testing.assert_array_equal(capped, full)
    else:
        assert capped is None


@given(
    st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=300),
    st.floats(1e-4, 0.2),
)
def test_path_simplification_error_is_bounded(values, tol):
    e = np.cumsum(values)
    t = np.arange(e.size, dtype=float)
    idx = _simplify_idx(t, e, tol)
    ts, es = t[idx], e[idx]
    assert ts[0] == t[0] and ts[-1] == t[-1]
    assert np.max(np.abs(np.interp(t, ts, es) - e)) <= tol + 1e-12


# ==================================================================== readers
def test_csv_round_trip_with_unit_conversions(tmp_path):
    eps = np.linspace(0, -0.4, 9)
    sig = 3.0 * eps
    rows = "\n".join(f"{100 * e:.6f},{1e3 * s:.6f}" for e, s in zip(eps, sig))
    p = write(tmp_path, f"# strain_rate: -6000 1/min\nStrain [%],stress_kPa\n{rows}\n")
    [c] = read_csv(p, n_points=None)
    np.testing.assert_allclose(c.strain, eps, atol=1e-12)
    np.testing.assert_allclose(c.stress, sig, atol=1e-12)
    assert c.strain_rate == pytest.approx(-100.0)
    assert c.name == "test" and c.source == str(p)


@pytest.mark.parametrize(
    "header, factor, measure",
    [
        ("stress", 1.0, "engineering"),
        ("stress_MPa", 1.0, "engineering"),
        ("Stress [MPa]", 1.0, "engineering"),
        ("STRESS_KPA", 1e-3, "engineering"),
        ("stress (Pa)", 1e-6, "engineering"),
        ("stress {GPa}", 1e3, "engineering"),
        ("stress_N/mm^2", 1.0, "engineering"),
        ("Spannung [N/mm²]", 1.0, "engineering"),
        ("stress_psi", 6.894757293168361e-3, "engineering"),
        ("nominal_stress_kgf_per_cm2", 0.0980665, "engineering"),
        ("nominal_stress_MPa", 1.0, "engineering"),
        ("engineering stress (kPa)", 1e-3, "engineering"),
        ("true_stress_MPa", 1.0, "true"),
        ("Cauchy stress [kPa]", 1e-3, "true"),
        ("sigma_MPa", 1.0, "engineering"),
    ],
)
def test_stress_headers(tmp_path, header, factor, measure):
    p = write(tmp_path, f"strain,{header}\n0,0\n-0.1,-2\n-0.2,-5\n")
    [c] = read_csv(p, rate=-1.0, n_points=None)
    np.testing.assert_allclose(c.stress, np.array([0, -2, -5]) * factor)
    assert c.measure == measure


@pytest.mark.parametrize(
    "header, values, expected",
    [
        ("strain", "0,-0.1,-0.2", [0, -0.1, -0.2]),
        ("strain_%", "0,-10,-20", [0, -0.1, -0.2]),
        ("Strain (%)", "0,-10,-20", [0, -0.1, -0.2]),
        ("engineering_strain", "0,-0.1,-0.2", [0, -0.1, -0.2]),
        ("eps [-]", "0,-0.1,-0.2", [0, -0.1, -0.2]),
        ("true_strain", f"0,{float(np.log(0.9))!r},{float(np.log(0.8))!r}", [0, -0.1, -0.2]),
        ("stretch", "1,0.9,0.8", [0, -0.1, -0.2]),
        ("Lambda", "1,0.9,0.8", [0, -0.1, -0.2]),
        ("stretch_nominal_from_rate", "1,0.9,0.8", [0, -0.1, -0.2]),
    ],
)
def test_strain_headers(tmp_path, header, values, expected):
    vals = values.split(",")
    rows = "\n".join(f"{v},{s}" for v, s in zip(vals, ["0", "-1", "-2"]))
    p = write(tmp_path, f"{header},stress\n{rows}\n")
    [c] = read_csv(p, rate=-1.0, n_points=None)
    np.testing.assert_allclose(c.strain, expected, atol=1e-12)


@pytest.mark.parametrize(
    "header, values, seconds",
    [
        ("time", "0,1,2", [0, 1, 2]),
        ("time_s", "0,1,2", [0, 1, 2]),
        ("Time [ms]", "0,1000,2000", [0, 1, 2]),
        ("t (min)", "0,1,2", [0, 60, 120]),
        ("test time_h", "0,1,2", [0, 3600, 7200]),
    ],
)
def test_time_headers(tmp_path, header, values, seconds):
    rows = "\n".join(f"{v},{e},{s}" for v, e, s in zip(values.split(","), [0, -0.1, 0],
                                                          [0, -1, 0]))
    p = write(tmp_path, f"{header},strain,stress\n{rows}\n")
    [c] = read_csv(p, n_points=None)
    np.testing.assert_allclose(c.time, seconds)


@pytest.mark.parametrize(
    "header, value, rate",
    [
        ("strain_rate", "-100", -100.0),
        ("rate_1/s", "-100", -100.0),
        ("Strain rate [1/min]", "-6000", -100.0),
        ("nominal_strain_rate_per_s", "-100", -100.0),
        ("rate (%/s)", "-10000", -100.0),
        ("de/dt", "-100", -100.0),
    ],
)
def test_rate_headers(tmp_path, header, value, rate):
    p = write(tmp_path, f"strain,stress,{header}\n0,0,{value}\n-0.1,-1,{value}\n")
    [c] = read_csv(p)
    assert c.strain_rate == pytest.approx(rate)


def test_metadata_header(tmp_path):
    p = write(tmp_path, "# vhfit test file\n# strain_rate = -100\n# measure: true\n"
                        "# name: gel fast\n# weight: 2\n# stress_unit: kPa\n# operator: me\n"
                        "strain,stress\n0,0\n-0.1,-1000\n")
    [c] = read_csv(p, n_points=None)
    assert (c.strain_rate, c.measure, c.name, c.weight) == (-100.0, "true", "gel fast", 2.0)
    assert c.stress[-1] == pytest.approx(-1.0)
    assert c.metadata["operator"] == "me"


def test_long_file_gives_one_curve_per_rate(tmp_path):
    text = "strain_rate,strain,stress_MPa\n"
    for r in (-1, -100, -10):
        for e in (0.0, -0.1, -0.2):
            text += f"{r},{e},{e * abs(r)}\n"
    cs = read_csv(write(tmp_path, text, "tests.csv"), n_points=2)
    assert [c.strain_rate for c in cs] == [-1.0, -100.0, -10.0]  # order of appearance
    assert [c.name for c in cs] == ["tests [rate -1/s]", "tests [rate -100/s]",
                                    "tests [rate -10/s]"]
    np.testing.assert_allclose(cs[1].target_stress, [-10.0, -20.0])


def test_long_file_conflicting_duplicates_name_both_lines(tmp_path):
    text = ("strain_rate,strain,stress\n-1,0,0\n-1,-0.1,-1\n-10,-0.1,-5\n-1,-0.1,-1.3\n"
            "-1,-0.2,-2\n-10,-0.2,-9\n")
    with raises("tests.csv", "line 5", "line 3", "appears twice"):
        read_csv(write(tmp_path, text, "tests.csv"))


def test_long_file_with_test_column_and_time(tmp_path):
    text = "test,time_s,strain,stress\n"
    for name, r in (("A", -0.01), ("B", -0.1)):
        for t in (0.0, 1.0, 2.0):
            text += f"{name},{t},{r * t},{10 * r * t}\n"
    cs = read_csv(write(tmp_path, text))
    assert [c.name for c in cs] == ["test [A]", "test [B]"]
    assert [c.strain_rate for c in cs] == pytest.approx([-0.01, -0.1])


def test_same_rate_twice_with_time_is_caught(tmp_path):
    text = "strain_rate,time_s,strain,stress\n-1,0,0,0\n-1,0.1,-0.1,-1\n-1,0,0,0\n-1,0.1,-0.1,-1\n"
    with raises("line 4", "time goes back", "'test' column"):
        read_csv(write(tmp_path, text))


def test_select_and_group_by(tmp_path):
    text = "region,mode,stretch,stress_kPa\n"
    for region in ("cortex", "callosum"):
        for lam in (1.0, 0.95, 0.9):
            text += f"{region},compression,{lam},{(lam - 1) * 10}\n"
        text += f"{region},shear,0.1,5\n"
    cs = read_csv(write(tmp_path, text, "brain.csv"), rate=-1e-3, group_by="region",
                  select={"mode": "compression"}, n_points=None)
    assert [c.name for c in cs] == ["brain [cortex]", "brain [callosum]"]
    np.testing.assert_allclose(cs[0].stress, [0.0, -5e-4, -1e-3])
    with raises("keeps no rows"):
        read_csv(write(tmp_path, text, "brain.csv"), rate=-1.0, select={"mode": "tension"})


@pytest.mark.parametrize(
    "raw",
    [
        b"\xef\xbb\xbfstrain,stress_kPa\r\n0,0\r\n-0.1,-100\r\n-0.2,-300\r\n",  # UTF-8 BOM, CRLF
        "strain,stress_kPa\n0,0\n-0.1,-100\n-0.2,-300\n".encode("utf-16"),  # UTF-16 with BOM
        b"strain;stress_kPa\n0;0\n-0,1;-100\n-0,2;-300\n",  # decimal commas
        b"strain\tstress_kPa\n0\t0\n-0.1\t-100\n-0.2\t-300\n",  # tabs
        b"strain stress_kPa\n0 0\n  -0.1   -100\n-0.2 -300\n",  # spaces
        b'"strain","stress_kPa"\n"0","0"\n"-0.1","-100"\n"-0,2","-300"\n',  # quoted
        b"strain,stress_kPa,\n0,0,\n\n-0.1,-100,\n-0.2,-300,\n\n",  # trailing commas
        "strain;Spannung [kPa]\n0;0\n-0,1;-100\n-0,2;-300\n".encode("latin-1"),
        "Dehnung [%];Spannung [N/mm²]\n0;0\n-10;-0,1\n-20;-0,3\n".encode("latin-1"),
        b"sep=;\nstrain;stress_kPa\n0;0\n-0,1;-100\n-0,2;-300\n",  # Excel's separator hint
        b"strain,stress\n%,[kPa]\n0,0\n-10,-100\n-20,-300\n",  # a units row
    ],
)
def test_hostile_but_valid_files_read_correctly(tmp_path, raw):
    [c] = read_csv(write(tmp_path, raw), rate=-1.0, n_points=None)
    np.testing.assert_allclose(c.strain, [0, -0.1, -0.2])
    np.testing.assert_allclose(c.stress, [0, -0.1, -0.3])


@pytest.mark.parametrize(
    "text, parts",
    [
        ("", ["is empty"]),
        ("\n\n# only a comment\n", ["is empty"]),
        ("strain,stress\n", ["no data rows"]),
        ("0,0\n-0.1,-1\n", ["line 1", "holds numbers", "names=[...]"]),
        ("strain,stress\n0,0\n-0.1\n-0.2,-2\n", ["line 3", "column 'stress'", "empty"]),
        ("strain,stress\n0,0\n-0.1,-1,7\n", ["line 3", "3 fields", "header has 2"]),
        ("strain,stress\n0,0\n-0,1,-1,5\n", ["line 3", "4 fields", "decimal mark", "';'"]),
        ("strain,stress\n0,0\n-0.1,abc\n", ["line 3", "column 'stress'", "'abc'"]),
        ("strain,stress\n0,0\n-0.1,nan\n", ["line 3", "column 'stress'", "not a finite"]),
        ("strain,stress\n0,0\n-0.1,-inf\n", ["line 3", "not a finite"]),
        ("strain,stress_furlong\n0,0\n-0.1,-1\n", ["column 'stress_furlong'", "'furlong'",
                                                  "kPa"]),
        ("time_fortnights,strain,stress\n0,0,0\n1,-0.1,-1\n", ["'fortnights'"]),
        ("strain,force_N\n0,0\n-0.1,-1\n", ["no stress column", "'force_N'"]),
        ("displacement,stress\n0,0\n-0.1,-1\n", ["no strain or stretch column"]),
        ("strain_rate,strain,stress\n-1,0,0\n,-0.1,-1\n", ["line 3", "rate is missing"]),
        ("strain,stress,true_stress_MPa,nominal_stress_MPa\n0,0,0,0\n-0.1,-1.0,-1.0,-2.0\n",
         ["line 3", "'nominal_stress_MPa' and 'stress' could both be the stress",
          "--columns stress="]),
        ("strain,stress\n0,0\n-0.2,-2\n-0.1,-1\n", ["line 4", "goes back", "sort=True"]),
        ("strainstress\n0\n", ["one column"]),
        ("# strain_rate: fast\nstrain,stress\n0,0\n-0.1,-1\n", ["'# strain_rate: fast'"]),
        ("strain,stress\n0,0\n0.1,1\n0.2,2\n", ["mode='compression'", "line 3"]),
        ("strain_rate,strain,stress\n-1,0,0\n-2,-0.1,-1\n-3,-0.2,-2\n", ["measured rate"]),
        ("strain,stress\n0,0\n-0.1,-1\nend of test,\n", ["line 4", "'end of test'", "text"]),
        ("# weight: heavy\nstrain,stress\n0,0\n-0.1,-1\n", ["'# weight: heavy'"]),
    ],
)
def test_hostile_files_raise_a_one_line_error_naming_the_place(tmp_path, text, parts):
    p = write(tmp_path, text)
    kw = {}
    if "rate" not in text and not any("no strain rate" in x for x in parts):
        kw["rate"] = -1.0  # so that the error under test is the one reached
    if "0.1,1\n" in text:
        kw["mode"] = "compression"
    with raises("test.csv", *parts):
        read_csv(p, **kw)


def test_undecodable_header_hints_at_the_encoding(tmp_path):
    p = write(tmp_path, "时间,位移,力\n0,0,0\n1,1,1\n".encode("gbk"))
    with raises("test.csv", "no strain or stretch column", "encoding="):
        read_csv(p)


def test_measured_rate_channel_hint(tmp_path):
    text = "strain_rate,strain,stress\n-1,0,0\n-2,-0.1,-1\n-3,-0.2,-2\n-4,-0.3,-3\n"
    with raises("columns={'rate': None}"):
        read_csv(write(tmp_path, text))
    [c] = read_csv(write(tmp_path, text), columns={"rate": None}, rate=-1.0)
    assert c.strain_rate == -1.0


def test_sort_option_fixes_unsorted_rows(tmp_path):
    p = write(tmp_path, "strain,stress\n0,0\n-0.2,-2\n-0.1,-1\n")
    [c] = read_csv(p, rate=-1.0, sort=True, n_points=None)
    np.testing.assert_allclose(c.strain, [0, -0.1, -0.2])


def test_defective_time_column_message_suggests_ignoring_it(tmp_path):
    p = write(tmp_path, "time_s,strain,stress\n0,0,0\n40.9,0.1,1\n40.1,0.2,2\n41.2,0.3,3\n")
    with raises("line 4", "time column looks wrong", "columns={'time': None}"):
        read_csv(p)
    [c] = read_csv(p, columns={"time": None}, rate=0.01)
    assert c.is_constant_rate


def test_columns_mapping_and_units_override(tmp_path):
    p = write(tmp_path, "a,b,c\n0,0,9\n-0.1,-100,9\n")
    [c] = read_csv(p, columns={"strain": "A", "stress": 1}, units={"stress": "kPa"},
                   rate=-1.0, n_points=None)
    np.testing.assert_allclose(c.stress, [0.0, -0.1])
    with raises("no such column"):
        read_csv(p, columns={"strain": "zzz", "stress": "b"}, rate=-1.0)
    with raises("unknown role"):
        read_csv(p, columns={"force": "a"}, rate=-1.0)


def test_measure_choice_and_conflict(tmp_path):
    p = write(tmp_path, "strain,engineering_stress_MPa,true_stress_MPa\n0,0,0\n-0.5,-2,-1\n")
    [c] = read_csv(p, rate=-1.0, n_points=None)
    assert c.measure == "engineering" and c.stress[-1] == -2
    [c] = read_csv(p, rate=-1.0, n_points=None, measure="true")
    assert c.measure == "true" and c.stress[-1] == -1
    q = write(tmp_path, "strain,nominal_stress\n0,0\n-0.5,-2\n", "q.csv")
    with raises("q.csv", "'nominal_stress'", "header says engineering"):
        read_csv(q, rate=-1.0, measure="true")


def test_headerless_file_with_names(tmp_path):
    p = write(tmp_path, "0 0\n-0.1 -100\n")
    [c] = read_csv(p, names=["strain", "stress_kPa"], rate=-1.0, n_points=None)
    np.testing.assert_allclose(c.stress, [0, -0.1])


def test_paths_streams_and_rates_per_file(tmp_path):
    a = write(tmp_path, "strain,stress\n0,0\n-0.1,-1\n", "a.csv")
    b = write(tmp_path, "strain,stress\n0,0\n-0.1,-2\n", "b.csv")
    cs = read_csv([a, str(b)], rate=[-1.0, -10.0])
    assert [(c.name, c.strain_rate) for c in cs] == [("a", -1.0), ("b", -10.0)]
    with raises("2 files", "3 rates"):
        read_csv([a, b], rate=[-1.0, -2.0, -3.0])
    [c] = read_csv(io.StringIO("strain,stress\n0,0\n-0.1,-1\n"), rate=-1.0)
    assert c.source == "<stream>"


def test_missing_paths_directories_and_binary_files(tmp_path):
    with raises("nope.csv", "no such file"):
        read_csv(tmp_path / "nope.csv")
    (tmp_path / "d").mkdir()
    with raises("is a directory", "glob"):
        read_csv(tmp_path / "d")
    with raises("spreadsheet", "save it as CSV"):
        read_csv(write(tmp_path, b"PK\x03\x04rest", "x.csv"))
    with raises("not a text file"):
        read_csv(write(tmp_path, b"\x00\x01\x02\x03\xff\x00\x10\x00\x00\x20\x31", "y.csv"))
    with raises("read_csv: no files"):
        read_csv([])


def test_a_million_row_csv(tmp_path):
    n = 1_000_000
    t = np.linspace(0, 100, n)
    eps = -0.005 * t
    body = "\n".join(f"{a:.5f},{b:.7f},{2 * b:.7f}" for a, b in zip(t, eps))
    p = write(tmp_path, "time_s,strain,stress_MPa\n" + body + "\n")
    [c] = read_csv(p)
    assert c.strain.size == n
    assert c.history.time.size < 20
    assert c.strain_rate == pytest.approx(-0.005, rel=1e-3)


# ------------------------------------------------------------- arrays
def test_curves_from_arrays_forms():
    eps = np.linspace(0, -0.3, 4)
    # unnamed 2-column array: strain, stress (MPa)
    [c] = curves_from_arrays(np.column_stack([eps, 2 * eps]), rate=-1.0, n_points=None)
    np.testing.assert_allclose(c.stress, 2 * eps)

    class ArrayLike:
        def __array__(self, dtype=None, copy=None):
            return np.column_stack([eps, 2 * eps])

    [c] = curves_from_arrays(ArrayLike(), rate=-1.0, n_points=None)
    np.testing.assert_allclose(c.stress, 2 * eps)

    class FrameLike:  # what a DataFrame offers, without pandas
        columns = ["Strain [%]", "stress_kPa", "note"]

        def to_numpy(self):
            return np.array([[100 * e, 2e3 * e, "x"] for e in eps], dtype=object)

    [c] = curves_from_arrays(FrameLike(), rate=-1.0, n_points=None, name="df")
    np.testing.assert_allclose(c.strain, eps)
    np.testing.assert_allclose(c.stress, 2 * eps)
    assert c.name == "df"

    [c] = curves_from_arrays({"time_ms": 1e3 * np.arange(4.0), "stretch": 1 + eps,
                              "stress": 2 * eps}, n_points=None)
    np.testing.assert_allclose(c.time, np.arange(4.0))

    rec = np.zeros(4, dtype=[("strain", float), ("stress_kPa", float)])
    rec["strain"], rec["stress_kPa"] = eps, 1e3 * eps
    [c] = curves_from_arrays(rec, rate=-1.0, n_points=None)
    np.testing.assert_allclose(c.stress, eps)


def test_array_errors():
    with raises("3 unnamed columns", "names="):
        curves_from_arrays(np.zeros((5, 3)))
    with raises("2 rows", "column_stack"):
        curves_from_arrays(np.zeros((2, 5)))
    with raises("different lengths"):
        curves_from_arrays({"strain": [0, 1], "stress": [0]})
    with raises("row 1", "column 'stress'", "'x'"):
        curves_from_arrays({"strain": [0.0, -0.1], "stress": ["0", "x"]}, rate=-1.0)
    two = {"strain": [0, -0.1, 0, -0.1], "stress": [0, -1, 0, -2], "rate": [-1, -1, -2, -2]}
    assert len(curves_from_arrays(two)) == 2
    with raises("holds 2 curves"):
        Curve.from_array(two)


def test_every_data_error_is_a_value_error():
    assert issubclass(DataError, ValueError)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Curve(EPS, EPS, strain_rate=-1.0)  # clean data: no warnings


def test_setting_a_tolerance_on_the_package_reaches_the_module_that_reads_it(monkeypatch):
    """vhfit.data.SIGN_RTOL (read by the curve's sign checks) behaves as a module global."""
    eps = np.linspace(0.0, -0.5, 51)
    eps[1] = 0.004  # an offset of the wrong sign, 0.8 % of the largest strain: noise
    assert Curve(eps, 10 * eps, time=np.linspace(0, 1, 51)).mode == "compression"
    monkeypatch.setattr(vhfit.data, "SIGN_RTOL", 0.001)
    assert vhfit.data._samples.SIGN_RTOL == 0.001
    assert Curve(eps, 10 * eps, time=np.linspace(0, 1, 51)).mode == "mixed"


# ================================================================ read_history
@pytest.mark.parametrize("text, t, e", [
    ("time_s,strain\n0,0\n1,-0.2\n2,0\n", [0, 1, 2], [0, -0.2, 0]),
    ("# ramp-hold\nTime [s],Force,Strain_eng\n\n1,5,-0.2\n4,3,-0.2\n", [0, 1, 4], [0, -0.2, -0.2]),
    ("t,strain_rate,strain\n0.5,-0.1,-0.05\n1,-0.1,-0.1\n", [0, 0.5, 1], [0, -0.05, -0.1]),
    ("\ufeff0,0\n2,0.3\n", [0, 2], [0, 0.3]),  # no header: the first two columns
])
def test_read_history_columns_and_start_from_rest(tmp_path, text, t, e):
    got_t, got_e = read_history(write(tmp_path, text))
    np.testing.assert_array_equal(got_t, t)
    np.testing.assert_array_equal(got_e, e)


@pytest.mark.parametrize("text, parts", [
    ("", ["empty; give a CSV with time and strain columns"]),
    ("# only a comment\n\n", ["empty;"]),
    ("seconds,strain\n0,0\n1,1\n", ["header ['seconds', 'strain'] has no 'time' and 'strain' "
                                    "columns; name them so"]),
    ("time,strain\n0,0\n1,abc\n2,0.1\n", ["data row 3 ['1', 'abc'] is not two numbers "
                                          "(time, strain); fix or remove it"]),
    ("0,0\n1\n", ["data row 2 ['1'] is not two numbers"]),
    ("time,strain\n1,0.1\n", ["needs at least 2 (time, strain) rows"]),
    (b"time,strain\n0,0\n1,\xff\n", ["is not UTF-8 text", "save it as a UTF-8 CSV"]),
])
def test_read_history_errors_name_the_file_and_the_fix(tmp_path, text, parts):
    p = write(tmp_path, text)
    with raises(str(p), *parts):
        read_history(p)


def test_read_history_missing_file_and_folder(tmp_path):
    with raises("cannot read (No such file or directory); check the path"):
        read_history(tmp_path / "nope.csv")
    with raises(str(tmp_path), "cannot read"):
        read_history(tmp_path)


def test_read_history_feeds_the_model(tmp_path):
    from vhfit.history import History

    h = History.piecewise_linear(*read_history(write(tmp_path, "time_s,strain\n1,-0.1\n2,0\n")))
    np.testing.assert_array_equal(h.time, [0.0, 1.0, 2.0])
    np.testing.assert_allclose(h.stretch, [1.0, 0.9, 1.0])


# ============================================================ package layout
_DATA_MODULES = ["_items", "_errors", "_measures", "_paths", "_points", "_samples", "_modes",
                 "_columns", "_table", "_ambiguous", "_specs",
                 "_curve", "_moduli", "_moduli_table", "_readers"]


def test_the_data_package_imports_one_way():
    """Each private module imports only those before it in the package's stated order
    (so the readers import the curve, never the reverse), at module level only."""
    import ast
    from pathlib import Path

    pkg = Path(vhfit.data.__file__).parent
    assert sorted(p.stem for p in pkg.glob("_*.py") if p.stem != "__init__") == sorted(
        _DATA_MODULES)
    for i, mod in enumerate(_DATA_MODULES):
        tree = ast.parse((pkg / f"{mod}.py").read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module:
                target = node.module
            elif isinstance(node, ast.Import):
                target = node.names[0].name
            else:
                continue
            assert node.col_offset == 0, f"{mod}: function-local import of {target}"
            if target.startswith("vhfit.data"):
                assert target != "vhfit.data", f"{mod} imports the package façade"
                dep = target.split(".")[2]
                assert dep in _DATA_MODULES[:i], f"{mod} imports {dep}, which comes after it"


@pytest.mark.parametrize("mod", ["__init__", *_DATA_MODULES])
def test_docstring_examples_of_the_data_package_run(mod):
    import doctest
    import importlib

    name = "vhfit.data" if mod == "__init__" else f"vhfit.data.{mod}"
    out = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
    assert out.failed == 0


# ------------------------------------------------- segment tolerances (docs of Curve's by=)
def _dip(d):
    """Up to 0.1, back by a fraction d of the range 0.2, up to 0.2 (30 s)."""
    t = np.linspace(0, 30, 3001)
    return t, np.interp(t, [0, 10, 20, 30], [0, 0.1, 0.1 - d * 0.2, 0.2])


def _ramp_hold(hold_fraction, creep=0.0):
    """A ramp to 0.2, then a hold of that fraction of 100 s, creeping by creep × 0.2."""
    t = np.linspace(0, 100.0, 2001)
    return t, np.interp(t, [0, 100 * (1 - hold_fraction), 100], [0, 0.2, 0.2 * (1 + creep)])


def test_a_reversal_starts_a_leg_beyond_leg_rtol(monkeypatch):
    assert vhfit.data.LEG_RTOL == 0.05
    t, eps = _dip(0.04)
    assert Curve(eps, eps, time=t).n_segments == 1  # a 4 % wiggle is noise
    t6, eps6 = _dip(0.06)
    assert Curve(eps6, eps6, time=t6).n_segments == 3  # up, down, up
    monkeypatch.setattr(vhfit.data, "LEG_RTOL", 0.03)  # set where it is read
    assert Curve(eps, eps, time=t).n_segments == 3


def test_a_hold_lasts_hold_min_duration_within_hold_rtol(monkeypatch):
    assert (vhfit.data.HOLD_RTOL, vhfit.data.HOLD_MIN_DURATION) == (0.002, 0.05)
    t, eps = _ramp_hold(0.07)
    assert Curve(eps, eps, time=t).n_segments == 2  # ramp + hold of 7 % of the test
    t, eps = _ramp_hold(0.03)
    assert Curve(eps, eps, time=t).n_segments == 1  # 3 %: too short for a hold
    monkeypatch.setattr(vhfit.data, "HOLD_MIN_DURATION", 0.02)
    assert Curve(eps, eps, time=t).n_segments == 2
    monkeypatch.undo()
    t, eps = _ramp_hold(0.8, creep=0.001)  # creeps by 0.1 % of its range: still a hold
    assert Curve(eps, eps, time=t).n_segments == 2
    t, eps = _ramp_hold(0.8, creep=0.004)  # 0.4 % > HOLD_RTOL: a slow ramp, not a hold
    assert Curve(eps, eps, time=t).n_segments == 1
    monkeypatch.setattr(vhfit.data, "HOLD_RTOL", 0.005)
    assert Curve(eps, eps, time=t).n_segments == 2
