"""Warnings of the calibration report, each fired by a constructed case and silent on one
where it must not fire, at both sides of its threshold.

The rules, as documented in vhfit.calibration (written out here independently):

* slow τ: a Prony term with G > 0 and τ > 10 × the longest curve duration;
* fast τ: τ < 0.01 × the earliest first objective time (t > 0) over all curves;
* slack sheet: ≥ 2 objective points where the data are within 2 % of the curve's peak
  |stress| of zero while the model has the opposite sign, beyond 5 % of that peak;
* g∞ floor: g∞ = E∞ / (E∞ + ΣG_i) at g_inf_min (E∞ = 6 (C10 + C01) for Mooney–Rivlin);
* unidentifiable: a parameter along a null direction of the residual Jacobian (two
  Prony terms with the same τ: only G1 + G2 is seen);
* rate sensitivity: compression ramps whose stress rises more than the rate (beyond 5 %),
  or falls with it (beyond 5 %), cannot be fitted with G_i ≥ 0;
* Drucker: the fitted law unstable in some mode over stability_range.

Each threshold is bracketed (e.g. 5× and 20×, 9× and 11× the slow-τ limit), so moving
it by a factor of 10 — or a little — fails a test.
"""

from __future__ import annotations

import math
import re
import time

import numpy as np
import pytest

import vhfit
from vhfit.calibration import CalibrationSettings, calibrate
from vhfit.calibration._report import (
    confidence,
    finish,
    merge_terms,
    slack_warnings,
    time_window_warnings,
)
from vhfit.calibration._search import Search
from vhfit.calibration._space import Problem
from vhfit.diagnostics import rate_sensitivity

MR1 = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
MR2 = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
RATES = (-1.0, -100.0)  # ramps to -0.5: durations 0.5 s and 5 ms
LONGEST = 0.5  # s, the -1/s ramp
EARLIEST = 0.05 / 100.0  # s, first objective point (strain -0.05) of the -100/s ramp
NUM = r"([-+]?[0-9.]+(?:e[-+]?\d+)?)"


# the fits here warn by design; the tests read the warnings from the report
pytestmark = pytest.mark.filterwarnings("ignore::vhfit.calibration.CalibrationWarning")


def ramps(params, rates=RATES, model=MR1, n=10, noise=0.0, seed=0):
    rng = np.random.default_rng(seed)
    eps = np.linspace(-0.05, -0.5, n)
    out = []
    for r in rates:
        s = model.stress(params, strain=eps, strain_rate=r, measure="engineering")
        if noise:
            s = s * (1 + noise * rng.standard_normal(s.size))
        out.append(vhfit.Curve(strain=eps, stress=s, strain_rate=r))
    return out


CURVES = ramps([0.2, 0.1, 1.0, 0.01])


def test_the_constructed_time_window_is_as_computed():
    assert [c.history.duration for c in CURVES] == pytest.approx([LONGEST, 0.005])
    assert min(float(np.min(c.target_time)) for c in CURVES) == pytest.approx(EARLIEST)


# --------------------------------------------------------------------- slow τ


SLOW = (LONGEST, r"is longer than 10x every curve's duration \(longest {NUM} s\)")
FAST = (EARLIEST, r"relaxes before the first objective point of every curve \(earliest {NUM} s\)")


def check_window_warning(factor, fires, rule):
    """τ = factor × the rule's reference time: fires or not, quoting τ and that time."""
    ref, text = rule
    tau = factor * ref
    msgs = time_window_warnings(MR1, np.array([0.2, 0.1, 1.0, tau]), CURVES)
    assert bool(msgs) is fires
    if fires:
        (m,) = msgs
        got = re.search(rf"tau1 = {NUM} s " + text.format(NUM=NUM), m)
        assert got, m
        assert float(got.group(1)) == pytest.approx(tau, rel=5e-3)
        assert float(got.group(2)) == pytest.approx(ref, rel=5e-3)


@pytest.mark.parametrize("factor, fires", [(5, False), (9, False), (11, True), (20, True),
                                           (100, True)])
def test_slow_tau_fires_beyond_ten_times_the_longest_duration(factor, fires):
    check_window_warning(factor, fires, SLOW)


def test_slow_tau_is_measured_against_the_longest_not_the_shortest_curve():
    # 20x the 5 ms ramp but 0.2x the 0.5 s ramp: the slow ramp sees it relax
    assert time_window_warnings(MR1, np.array([0.2, 0.1, 1.0, 20 * 0.005]), CURVES) == []


def test_a_term_without_modulus_is_not_warned_about():
    assert time_window_warnings(MR1, np.array([0.2, 0.1, 0.0, 1e6]), CURVES) == []
    assert time_window_warnings(MR1, np.array([0.2, 0.1, 0.0, 1e-12]), CURVES) == []


def test_the_warning_names_the_right_term():
    x = np.array([0.2, 0.1, 1.0, 0.01, 2.0, 20 * LONGEST])
    (m,) = time_window_warnings(MR2, x, CURVES)
    assert m.startswith("tau2 = 10 s")


# --------------------------------------------------------------------- fast τ


@pytest.mark.parametrize("factor, fires", [(0.001, True), (0.005, True), (0.009, True),
                                           (0.011, False), (0.02, False), (0.1, False)])
def test_fast_tau_fires_below_a_hundredth_of_the_earliest_point(factor, fires):
    check_window_warning(factor, fires, FAST)


def test_fast_tau_is_measured_against_the_earliest_point_of_all_curves():
    # 0.005x the slow ramp's first point (0.05 s), 0.5x the fast ramp's: seen by the latter
    assert time_window_warnings(MR1, np.array([0.2, 0.1, 1.0, 0.005 * 0.05]), CURVES) == []


def test_a_well_placed_tau_is_silent():
    assert time_window_warnings(MR1, np.array([0.2, 0.1, 1.0, 0.01]), CURVES) == []


# ---------------------------------------------------------------- slack sheet


T = np.array([0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.2, 3.4, 3.6, 3.8])
E = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.4, 0.3, 0.2, 0.15, 0.1])  # tension load-unload
PEAK = 2.0


def sheet(tail, sign=1.0):
    """A load-unload curve whose last four points carry `tail` × the peak stress."""
    d = np.array([0.4, 0.8, 1.2, 1.6, PEAK, 1.0, 0.5, 0.2, 0.1, 0.1])
    d[-4:] = tail * PEAK
    return vhfit.Curve(strain=sign * E, stress=sign * d, time=T, n_points=None,
                       name="sheet", mode="compression" if sign < 0 else None)


def model_with(tail, curve, n_bad=4):
    """The data, except `tail` × the peak (opposite sign) at the last `n_bad` points."""
    s = np.array(curve.target_stress, dtype=float)
    sign = np.sign(s[np.argmax(np.abs(s))])
    s[-n_bad:] = -sign * np.asarray(tail, dtype=float) * PEAK
    return s


def test_slack_fires_with_the_counts_times_strains_and_worst_value():
    c = sheet(0.015)
    s = model_with([0.06, 0.08, 0.1, 0.12], c)
    (m,) = slack_warnings([s], [c])
    assert m.startswith("curve 'sheet': at 4 objective points (time 3.2-3.8 s, strain 0.1 to 0.3)")
    got = re.search(rf"the model's reaches {NUM} \(opposite sign\)", m)
    assert float(got.group(1)) == pytest.approx(-0.12 * PEAK, rel=1e-3)
    assert "curve.trim(time=(None, 3.2))" in m and "--trim-time :3.2" in m


@pytest.mark.parametrize("data_tail, model_tail, n_bad", [
    (0.03, 0.1, 4),   # the data are not ~0 (3 % of the peak > 2 %)
    (0.015, 0.03, 4),  # the model pushes back only 3 % of the peak (< 5 %)
    (0.015, 0.1, 1),  # a single point
    (0.015, -0.1, 4),  # the model keeps the data's sign
])
def test_slack_is_silent_below_each_threshold(data_tail, model_tail, n_bad):
    c = sheet(data_tail)
    s = model_with(np.full(n_bad, model_tail), c, n_bad)
    assert slack_warnings([s], [c]) == []


def test_slack_in_compression_looks_for_tension_in_the_model():
    c = sheet(0.015, sign=-1.0)
    assert np.max(np.asarray(c.target_stress)) < 0.05  # stored with compression negative
    s = model_with([0.06, 0.08, 0.1, 0.12], c)
    assert np.all(s[-4:] > 0)
    (m,) = slack_warnings([s], [c])
    assert "at 4 objective points" in m
    assert slack_warnings([-np.abs(s)], [c]) == []  # compression everywhere: fine


def test_slack_of_a_real_buckled_sheet_through_calibrate():
    # a tension load-unload whose data stay at 0 where the solid model is compressed
    truth = dict(C10=0.2, C01=0.1, G1=1.0, tau1=1.0)
    t = np.linspace(0.0, 2.0, 201)
    eps = 0.5 - np.abs(0.5 - 0.5 * t)
    h = vhfit.History.piecewise_linear(t, eps, out_time=t)
    s = MR1.stress(truth, h, measure="engineering")
    c = vhfit.Curve(strain=eps, stress=np.maximum(s, 0.0), time=t, name="sheet", n_points=40)
    cal = calibrate([c], n_prony=1, seed=0, uncertainty=False, maxiter=30)
    assert [w for w in cal.warnings if w.startswith("curve 'sheet'") and "slack" in w]


# ------------------------------------------------------------------- finish()


def report(x, model=MR1, curves=CURVES, g_inf_min=0.0, stability_range=(0.2, 5.0),
           uncertainty=False):
    n = model.n_prony
    prob = Problem(model, curves, np.array([[-6.0, 3.0]] * n), {}, g_inf_min)
    err = float(prob.errors(np.asarray(x)[None, :])[0])
    found = Search(np.zeros(0), 1, 1, "maxiter", {"nit": [], "best": [], "mean": [], "time": []},
                   time.perf_counter())
    settings = CalibrationSettings(model.hyperelastic.name, prune_tol=0.0,
                                   stability_range=stability_range, uncertainty=uncertainty)
    return finish(prob, curves, model, np.array(x, dtype=float), err, found, 1, settings, {})


def floor_msgs(cal):
    return [w for w in cal.warnings if "g_inf sits at its floor" in w]


@pytest.mark.parametrize("g_inf, floor, fires", [
    (0.01, 0.01, True),  # exactly at the floor
    (0.02, 0.01, False),  # twice the floor
    (0.0101, 0.01, False),  # 1 % above it
    (1e-9, 0.0, False),  # no floor
])
def test_g_inf_floor_message(g_inf, floor, fires):
    C10, C01 = 0.1, 0.05
    E_inf = 6 * (C10 + C01)  # 3 × the initial shear modulus 2 (C10 + C01)
    assert MR1.long_term_modulus([C10, C01, 0.0, 1.0]) == pytest.approx(E_inf, rel=1e-12)
    G = E_inf * (1 / g_inf - 1)
    cal = report([C10, C01, G, 0.01], g_inf_min=floor)
    assert cal.g_inf == pytest.approx(g_inf, rel=1e-9)
    assert bool(floor_msgs(cal)) is fires
    if fires:
        assert floor_msgs(cal)[0].startswith("g_inf sits at its floor (0.01)")
    # a floor-bound g_inf changes how the result may be used: it heads the summary
    assert floor_msgs(cal) == cal.headlines
    if fires:
        # after the verdict, the model and its error
        assert cal.summary().splitlines()[3] == "WARNING: " + cal.headlines[0]
    else:
        assert not cal.headlines


def test_g_inf_floor_through_calibrate_fires_and_stays_silent():
    # all stiffness in a slow branch: the best fit wants g_inf -> 0
    soft = ramps(dict(C10=1e-7, C01=0.0, G1=1.0, tau1=5.0), rates=(-1.0, -10.0))
    # target=0: run to the best (with C01 slightly negative, still stable, a fit just above
    # the floor already meets the default target)
    cal = calibrate(soft, n_prony=1, seed=0, g_inf_min=0.01, uncertainty=False, target=0.0)
    assert cal.g_inf == pytest.approx(0.01, rel=1e-6)
    assert floor_msgs(cal)
    # the generating material has g_inf = 0.9 / 1.9: the floor is far away
    well = ramps(dict(C10=0.1, C01=0.05, G1=1.0, tau1=0.01), rates=(-1.0, -100.0))
    cal = calibrate(well, n_prony=1, seed=0, g_inf_min=0.01, uncertainty=False, maxiter=40)
    assert cal.g_inf > 0.3
    assert not floor_msgs(cal)


# ------------------------------------------------------------ identifiability


FOUR = (-1.0, -10.0, -100.0, -1000.0)


def test_two_terms_at_one_tau_are_unidentifiable():
    x = np.array([0.2, 0.1, 1.0, 0.01, 0.5, 0.01])
    curves = ramps(x, FOUR, MR2, noise=0.01)
    prob = Problem(MR2, curves, np.array([[-6.0, 3.0]] * 2), {}, 0.0)
    _, unident = confidence(prob, x)
    assert sorted(unident) == ["G1", "G2", "tau1", "tau2"]  # C10, C01 stay identified
    # the report merges the coincident terms into one identified term of G1 + G2
    cal = report(x, MR2, curves, uncertainty=True)
    assert cal.n_prony == 1
    assert cal.params["G1"] == 1.5 and cal.params["tau1"] == pytest.approx(0.01, rel=1e-15)
    assert "tau1 and tau2" in " ".join(w for w in cal.warnings if "were merged" in w)
    assert not [w for w in cal.warnings if "cannot identify" in w]


@pytest.mark.parametrize("ratio, merged", [(1.005, True), (1.02, False)])
def test_coincident_relaxation_times_merge_at_one_percent(ratio, merged):
    G, tau, groups = merge_terms(np.array([1.0, 3.0, 2.0]), np.array([0.1, 0.1 * ratio, 10.0]))
    if merged:
        assert groups == [(0, 1), (2,)] and G.tolist() == [4.0, 2.0]
        # modulus-weighted geometric mean: 0.1 * ratio**(3/4)
        assert tau[0] == pytest.approx(0.1 * ratio**0.75, rel=1e-14) and tau[1] == 10.0
    else:
        assert groups == [(0,), (1,), (2,)] and G.tolist() == [1.0, 3.0, 2.0]
        assert tau.tolist() == [0.1, 0.1 * ratio, 10.0]


def test_well_separated_terms_are_identifiable():
    x = np.array([0.2, 0.1, 1.0, 0.001, 0.5, 0.1])
    curves = ramps(x, FOUR, MR2, noise=0.01)
    prob = Problem(MR2, curves, np.array([[-6.0, 3.0]] * 2), {}, 0.0)
    conf, unident = confidence(prob, x)
    assert unident == []
    for k, name in enumerate(MR2.param_names):  # finite, non-empty, around the value
        lo, hi = conf[name]
        assert lo < x[k] < hi and np.isfinite(hi)
    cal = report(x, MR2, curves, uncertainty=True)
    assert not [w for w in cal.warnings if "cannot identify" in w]


# ------------------------------------------------------------ Drucker in the report


def drucker_msgs(cal):
    return [w for w in cal.warnings if w.startswith("Drucker")]


def test_report_carries_the_equibiaxial_instability_of_the_fitted_law():
    # C10 = 17c, C01 = -5c: uniaxially unstable for λ <= 1/2, equibiaxially for λ >= √2
    # (tests/test_stability.py derives both): the same states (equibiaxial tension at λ
    # is uniaxial compression at λ⁻² along the third axis). The stated range bounds every
    # principal stretch: over 0.4..5 the equibiaxial mode is checked up to 0.4^(-1/2)
    cal = report([0.17, -0.05, 1.0, 0.01], stability_range=(0.4, 5.0))
    assert set(cal.stability.unstable) == {"uniaxial", "equibiaxial"}
    (m,) = drucker_msgs(cal)
    got = re.fullmatch(rf"Drucker-UNSTABLE in uniaxial: {NUM} <= λ <= {NUM}; "
                       rf"equibiaxial: {NUM} <= λ <= {NUM}", m)
    assert got, m
    assert float(got.group(1)) == pytest.approx(0.4, abs=0.0005)
    assert float(got.group(2)) == pytest.approx(0.5, abs=0.01)
    assert float(got.group(3)) == pytest.approx(math.sqrt(2), abs=0.02)
    assert float(got.group(4)) == pytest.approx(0.4**-0.5, abs=0.005)  # (3 digits)
    # principal stretches within 0.6..5 never reach λ3 = 1/2: stable there
    cal = report([0.17, -0.05, 1.0, 0.01], stability_range=(0.6, 5.0))
    assert cal.stability.stable and not drucker_msgs(cal)


def test_report_is_silent_for_a_stable_law():
    cal = report([0.17, 0.05, 1.0, 0.01], stability_range=(0.05, 20.0))
    assert cal.stability.stable and not drucker_msgs(cal)


def test_calibrate_returns_a_law_stable_over_the_range_and_says_so():
    # compression data to λ = 0.6 from a law unstable in uniaxial compression below 1/2
    # (equibiaxial tension above √2): over principal stretches (0.4, 5) the fit is the
    # best stable law, not the truth; over a range where the truth is stable it is
    # recovered; the summary states the range either way
    truth = dict(C10=0.17, C01=-0.05, G1=1.0, tau1=0.01)
    eps = np.linspace(-0.04, -0.4, 10)
    curves = [vhfit.Curve(strain=eps, stress=MR1.stress(truth, strain=eps, strain_rate=r,
                                                        measure="engineering"), strain_rate=r)
              for r in RATES]
    hm = MR1.hyperelastic
    assert set(vhfit.stability.drucker(hm, [0.17, -0.05], (0.4, 5.0),
                                       principal=True).unstable) == {"uniaxial", "equibiaxial"}
    cal = calibrate(curves, n_prony=1, seed=0, uncertainty=False, maxiter=60,
                    bounds={"C10": (0.0, 1.0), "C01": (-0.2, 0.2)},
                    stability_range=(0.4, 5.0))
    assert cal.stability.stable and cal.stability.stretch_range == (0.4, 5.0)
    assert vhfit.stability.drucker(hm, [cal.params["C10"], cal.params["C01"]],
                                   (0.4, 5.0), n=4000, principal=True).stable
    assert drucker_msgs(cal) == []
    near = calibrate(curves, n_prony=1, seed=0, uncertainty=False, maxiter=60,
                     bounds={"C10": (0.0, 1.0), "C01": (-0.2, 0.2)},
                     stability_range=(0.6, 1.3))
    assert near.params["C01"] == pytest.approx(-0.05, rel=1e-3)
    assert near.stability.stable


# --------------------------------------------------------- rate sensitivity


def rate_pair(factor, n_prony=1):
    eps = np.linspace(-0.05, -0.5, 10)
    slow = vhfit.Curve(strain=eps, stress=0.5 * eps, strain_rate=-1000.0, name="slow")
    fast = vhfit.Curve(strain=eps, stress=factor * 0.5 * eps, strain_rate=-2000.0,
                       name="fast")
    return rate_sensitivity([slow, fast], "mooney_rivlin", n_prony)


@pytest.mark.parametrize("factor, fires", [(2.2, True), (2.5, True), (2.05, False),
                                           (2.0, False), (1.5, False), (1.0, False),
                                           (0.97, False), (0.9, True), (0.5, True)])
def test_rate_sensitivity_bounds_are_one_and_the_rate_ratio(factor, fires):
    # in compression doubling the rate at most doubles the stress and cannot lower it;
    # 5 % of slack for noise: 2 × 1.05 = 2.1 and 1 / 1.05 = 0.952
    msgs = rate_pair(factor)
    assert bool(msgs) is fires
    if fires:
        (m,) = msgs
        assert m.startswith("curves 'slow' (-1000 1/s) and 'fast' (-2000 1/s): the rate rises x2 "
                            f"and the measured stress x{factor:.3g}")
        if factor > 1:
            got = re.search(rf"at most x{NUM} between", m)
            assert float(got.group(1)) == pytest.approx(2.0, rel=1e-3)
        else:
            got = re.search(rf"at least x{NUM} as stiff", m)
            assert float(got.group(1)) == pytest.approx(1.0, rel=1e-3)


def test_without_prony_terms_any_rate_effect_is_named():
    (m,) = rate_pair(1.2, n_prony=0)
    assert "'slow', 'fast' differ with the strain rate (stress ratios x1.2 to x1.2" in m
    assert rate_pair(1.03, n_prony=0) == []  # within 5 %


def test_calibrate_puts_the_rate_warning_first():
    eps = np.linspace(-0.05, -0.5, 10)
    slow = vhfit.Curve(strain=eps, stress=0.5 * eps, strain_rate=-1000.0, name="slow")
    fast = vhfit.Curve(strain=eps, stress=1.5 * eps, strain_rate=-2000.0, name="fast")
    cal = calibrate([slow, fast], n_prony=1, seed=0, uncertainty=False, maxiter=5)
    assert cal.warnings[0].startswith("curves 'slow' (-1000 1/s) and 'fast' (-2000 1/s)")
    cal = calibrate([slow, fast], n_prony=1, seed=0, uncertainty=False, maxiter=5,
                    check_rates=False)
    assert not [w for w in cal.warnings if w.startswith("curves 'slow'")]


# ------------------------------------------------------- the summary reads top-down
def _hand_made(rmsape, per_curve, warns=(), heads=()):
    import vhfit

    m = vhfit.ViscoHyperelastic("neo_hooke", 1)
    return vhfit.Calibration(model=m, params=dict(C10=0.5, G1=1.0, tau1=0.0086000212345),
                             rmsape=rmsape, per_curve_rmsape=list(per_curve), nit=1, nfev=1,
                             wall_time=0.0, stop_reason="converged",
                             curve_names=[f"c{i}" for i in range(len(per_curve))],
                             warnings=list(warns) + list(heads), headlines=list(heads),
                             T_ref=24.978180000000002, shift_source="table",
                             shift_table={24.978180000000002: 0.0})


def test_verdict_thresholds_are_the_documented_ones():
    from vhfit.calibration import GOOD_FIT, ROUGH_FIT, WITHIN_FIT, grade

    assert (GOOD_FIT, WITHIN_FIT, ROUGH_FIT) == (5.0, 10.0, 25.0)  # docs/cli.md
    assert grade(5.0) == ("good", "good fit")
    assert grade(5.0001)[1] == "fits within 10 %"
    assert grade(10.0)[1] == "fits within 10 %"
    assert grade(10.01)[1].startswith("rough fit")
    assert grade(25.0)[1].startswith("rough fit")
    assert grade(25.01)[1].startswith("poor: the law cannot follow the data; try")
    assert grade(float("nan"))[0] == "poor"


def test_summary_first_line_is_the_verdict_then_warnings_then_constants():
    cal = _hand_made(7.0, [3.0, 9.5], warns=["a minor thing"], heads=["a major thing"])
    lines = cal.summary().splitlines()
    assert lines[0] == "RMSAPE 7 %: fits within 10 %; worst curve c1 (9.5 %)"
    assert lines[0] == cal.verdict()
    major = lines.index("WARNING: a major thing")
    minor = lines.index("warning: a minor thing")
    table = next(i for i, ln in enumerate(lines) if ln.startswith("parameter"))
    assert major < minor < table
    assert cal.summary(verdict=False).splitlines()[0].startswith("vhfit calibration:")
    assert cal.verdict(interrupted=True).startswith("INTERRUPTED (best so far, not converged): ")
    poor = _hand_made(40.0, [40.0])
    assert poor.summary().splitlines()[0].startswith("RMSAPE 40 %: poor: the law cannot")
    assert "worst curve" not in poor.verdict()  # one curve: no worst


def test_summary_numbers_are_rounded_for_reading():
    text = _hand_made(1.0, [1.0, 1.0]).summary()
    # constants: 6 significant digits (full precision stays in results.json and the cards)
    assert "0.0086000212345" not in text and "tau1" in text and " 0.00860002  s" in text
    assert "24.978180000000002" not in text and "T_ref 24.9782" in text


def test_rate_labels_round_but_keep_the_rates_apart():
    from vhfit.data._specs import rate_label

    assert rate_label(0.00860002, [0.00860002, 0.1]) == "0.0086"
    assert rate_label(0.1, [0.00860002, 0.1]) == "0.1"
    assert rate_label(0.00860002, [0.00860002, 0.0086]) == "0.00860002"
    assert rate_label(1.00001, [1.00001, 1.00002]) == "1.00001"


def test_a_warning_of_many_files_is_printed_once_with_the_list():
    from vhfit.cli._fit import group_by_file

    msgs = ["curve 'a' (d/a.csv): no rate column, assumed -1/s",
            "curve 'b' (d/b.csv): no rate column, assumed -10/s",
            "curve 'ab' (d/ab.csv): no rate column, assumed -1/s",
            "d/b.csv: row 3 skipped", "general", "curve 'a2' (d/a.csv): row 3 skipped"]
    got = group_by_file(msgs, ["d/a.csv", "d/b.csv", "d/ab.csv"])
    assert got == [
        "no rate column, assumed -1/-10/s (in 3 files: curve 'a' (d/a.csv); "
        "curve 'b' (d/b.csv); curve 'ab' (d/ab.csv))",
        "row 3 skipped (in 2 files: d/b.csv; curve 'a2' (d/a.csv))", "general"]
    assert group_by_file(msgs[:1], ["d/a.csv"]) == msgs[:1]
    # two curves of one file: one line, naming both
    two = group_by_file(["curve 'x' (f.csv): odd", "curve 'y' (f.csv): odd"], ["f.csv"])
    assert two == ["odd (curve 'x' (f.csv); curve 'y' (f.csv))"]


def test_cli_prints_a_reading_warning_of_several_files_once(tmp_path):
    import subprocess
    import sys

    for r in (1, 10):  # compression given as positive magnitudes: the reader says so
        (tmp_path / f"r{r}.csv").write_text(
            f"# strain_rate: -{r}\nstrain,stress_MPa\n0,0\n0.1,0.5\n0.2,1.1\n0.3,1.8\n")
    proc = subprocess.run([sys.executable, "-m", "vhfit", "fit", "r1.csv", "r10.csv",
                           "--prony", "0", "--no-plot", "--quiet", "--out", "o"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    warns = [ln for ln in proc.stderr.splitlines() if "strain is >= 0" in ln]
    assert len(warns) == 1, proc.stderr
    assert "strain_rate = -1/-10 < 0" in warns[0]
    assert warns[0].endswith("(in 2 files: curve 'r1' (r1.csv); curve 'r10' (r10.csv))")
