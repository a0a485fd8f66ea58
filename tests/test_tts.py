"""Time–temperature superposition (vhfit.tts): shift laws, their fits, master curves,
shifted stress–strain tests. References are written here from the documented formulas."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import curve_fit

import vhfit
from vhfit import tts
from vhfit.data import DataError

R = 8.314462618


def test_the_gas_constant_and_the_law_names():
    assert tts.GAS_CONSTANT == R  # J/(mol K), CODATA 2018 exact value
    assert set(tts.LAWS) == {"wlf", "arrhenius", "polynomial"}


# ------------------------------------------------------------------ the laws
def test_wlf_matches_hand_computed_values():
    law = tts.WLF(C1=17.44, C2=51.6, T_ref=0.0)
    # -17.44*10/61.6 and -17.44*(-10)/41.6
    np.testing.assert_allclose(law.log_aT([10.0, -10.0]), [-2.8311688311688, 4.1923076923077],
                               rtol=1e-12)
    assert float(law.log_aT(0.0)) == 0.0
    assert float(law.aT(10.0)) == pytest.approx(10 ** -2.8311688311688, rel=1e-12)


def test_wlf_refuses_temperatures_at_its_pole():
    with pytest.raises(ValueError, match="pole"):
        tts.WLF(10.0, 50.0, 20.0).log_aT(-30.0)
    with pytest.raises(ValueError, match="C2"):
        tts.WLF(10.0, -5.0, 20.0)


def test_arrhenius_matches_hand_computed_value():
    law = tts.Arrhenius(E_a=1.0e5, T_ref=25.0)
    expected = 1.0e5 / (R * math.log(10)) * (1 / 308.15 - 1 / 298.15)
    assert float(law.log_aT(35.0)) == pytest.approx(expected, rel=1e-12)
    assert float(tts.Arrhenius(1e5, 300.0, absolute_zero=0.0).log_aT(300.0)) == 0.0


def test_polynomial_shift_matches_hand_computed_value():
    law = tts.PolynomialShift((-0.1, 0.001), T_ref=20.0)
    assert float(law.log_aT(30.0)) == pytest.approx(-1.0 + 0.1, rel=1e-14)
    assert float(law.log_aT(10.0)) == pytest.approx(1.0 + 0.1, rel=1e-14)


# ------------------------------------------------------------------ the fits
def test_wlf_fit_recovers_exact_constants():
    T = np.linspace(-30.0, 80.0, 12)
    y = -8.86 * (T - 10.0) / (101.6 + T - 10.0)
    law = tts.fit_shift_law(T, y, "wlf", T_ref=10.0)
    # C2 = floor + span·e^u (floor 40, span 110) comes from a bounded Brent search on u,
    # which stops within 2·(sqrt(eps)·|u| + xatol/3) ≈ 1.7e-8 of the minimum (u ≈ -0.58):
    # C2 within 61.6 · 1.7e-8 ≈ 1e-6, i.e. 1e-8 relative, and C1 (solved for each C2)
    # 1.14 times that. On a zero-residual fit that is the whole error: rel = 1e-7.
    assert law.C1 == pytest.approx(8.86, rel=1e-7)
    assert law.C2 == pytest.approx(101.6, rel=1e-7)


def test_wlf_fit_agrees_with_a_direct_least_squares_fit_of_noisy_factors():
    rng = np.random.default_rng(3)
    T = np.linspace(-40.0, 100.0, 21)
    y = -12.0 * (T - 0.0) / (90.0 + T) + rng.normal(0, 0.15, T.size)
    y[np.argmin(abs(T))] = 0.0
    law = tts.fit_shift_law(T, y, "wlf", T_ref=0.0)
    ref, _ = curve_fit(lambda t, c1, c2: -c1 * t / (c2 + t), T, y, p0=(10.0, 100.0),
                       xtol=1e-14, ftol=1e-14, maxfev=20000)
    assert law.C1 == pytest.approx(ref[0], rel=1e-6)
    assert law.C2 == pytest.approx(ref[1], rel=1e-6)


def test_arrhenius_and_polynomial_fits_recover_their_constants():
    T = np.linspace(0.0, 90.0, 10)
    y = 6.0e4 / (R * math.log(10)) * (1 / (T + 273.15) - 1 / (40 + 273.15))
    assert tts.fit_shift_law(T, y, "arrhenius", T_ref=40.0).E_a == pytest.approx(6.0e4, rel=1e-10)
    y2 = -0.12 * (T - 40) + 4e-4 * (T - 40) ** 2
    c = tts.fit_shift_law(T, y2, "polynomial", T_ref=40.0, degree=2).coefficients
    np.testing.assert_allclose(c, [-0.12, 4e-4], rtol=1e-9)


def test_default_reference_is_the_temperature_with_zero_shift():
    T = np.array([0.0, 10.0, 20.0, 30.0])
    law = tts.fit_shift_law(T, [2.0, 1.0, 0.0, -0.8], "wlf")
    assert law.T_ref == 20.0


def test_bad_fit_arguments_are_refused():
    with pytest.raises(ValueError, match="law"):
        tts.fit_shift_law([0, 1], [0, 1], "vft")
    with pytest.raises(ValueError, match="2 temperatures"):
        tts.fit_shift_law([5, 5], [0, 1])
    with pytest.raises(ValueError, match="degree"):
        tts.fit_shift_law([0, 1, 2], [0, 1, 2], "polynomial", degree=5)


# ------------------------------------------------------------------ master curves
G_TRUE = np.array([300.0, 800.0, 1200.0, 900.0, 500.0, 200.0])
TAU_TRUE = 10.0 ** np.arange(-6.0, 0.0)
E_INF = 20.0


def storage_loss(f):
    """E' and E'' of the generalised Maxwell model, written from docs/theory.md §3."""
    w = 2 * np.pi * np.asarray(f)[:, None] * TAU_TRUE
    return E_INF + (G_TRUE * w**2 / (1 + w**2)).sum(1), (G_TRUE * w / (1 + w**2)).sum(1)


def relax(t):
    return E_INF + (G_TRUE * np.exp(-np.asarray(t)[:, None] / TAU_TRUE)).sum(1)


LAW = tts.WLF(C1=9.0, C2=110.0, T_ref=20.0)
TEMPS = np.arange(-10.0, 61.0, 10.0)


def synthetic_sweeps():
    f = np.logspace(-1, 2, 13)
    sets = []
    for T in TEMPS:
        e1, e2 = storage_loss(f * LAW.aT(T))  # the sweep at T is the reference at f·a_T
        sets.append((T, f, e1, e2))
    T = np.concatenate([np.full(13, s[0]) for s in sets])
    return tts.sweeps_from_columns(T, frequency=np.tile(f, TEMPS.size),
                                   storage=np.concatenate([s[2] for s in sets]),
                                   loss=np.concatenate([s[3] for s in sets]))


def test_master_curve_recovers_known_shift_factors():
    mc = tts.master_curve(synthetic_sweeps(), T_ref=20.0, law="wlf")
    assert isinstance(mc, tts.MasterCurve) and mc.domain == "frequency"
    np.testing.assert_allclose(mc.log_aT, LAW.log_aT(TEMPS), atol=0.02)
    assert mc.log_aT[TEMPS == 20.0][0] == 0.0
    assert mc.law.C1 == pytest.approx(9.0, rel=0.03)
    e1, e2 = storage_loss(mc.frequency / 10 ** 0)  # the master curve is the reference
    np.testing.assert_allclose(mc.storage, e1, rtol=0.05)
    assert np.all(np.diff(mc.frequency) >= 0)


def test_master_curve_in_the_time_domain_recovers_known_shift_factors():
    t = np.logspace(-2, 1, 13)
    temps = TEMPS[TEMPS <= 40.0]  # above, the window sees only the relaxed plateau
    cols = [(T, t, relax(t / LAW.aT(T))) for T in temps]  # reduced time t / a_T
    sweeps = tts.sweeps_from_columns(np.repeat(temps, 13), time=np.tile(t, temps.size),
                                     modulus=np.concatenate([c[2] for c in cols]))
    mc = tts.master_curve(sweeps, T_ref=20.0)
    np.testing.assert_allclose(mc.log_aT, LAW.log_aT(temps), atol=0.02)
    np.testing.assert_allclose(mc.modulus, relax(mc.time), rtol=0.02)


def test_given_shift_factors_are_used_and_missing_ones_built_from_overlap():
    sweeps = synthetic_sweeps()
    table = {T: float(LAW.log_aT(T)) + (0.3 if T == 0.0 else 0.0) for T in TEMPS if T != 40.0}
    mc = tts.master_curve(sweeps, shift_factors=table)
    assert mc.log_aT[TEMPS == 0.0][0] == pytest.approx(LAW.log_aT(0.0) + 0.3, abs=1e-12)
    assert mc.log_aT[TEMPS == 40.0][0] == pytest.approx(LAW.log_aT(40.0), abs=0.02)
    mc2 = tts.master_curve(sweeps, shift_factors=LAW)
    np.testing.assert_allclose(mc2.log_aT, LAW.log_aT(TEMPS), rtol=1e-14)
    assert mc2.law is LAW and mc2.T_ref == 20.0


def test_sweeps_without_shift_information_or_overlap_are_refused_in_one_line():
    f = np.logspace(-1, 0, 5)
    a = tts.sweeps_from_columns(np.zeros(5), frequency=f, storage=f * 10 + 1, loss=f)
    b = tts.sweeps_from_columns(np.full(5, 50.0), frequency=f, storage=f + 100.0, loss=f)
    with pytest.raises(DataError, match=r"^sweep at T = 50: no shift factor .* give shift "
                                        r"factors") as exc:
        tts.master_curve(a + b, T_ref=0.0)
    assert "\n" not in str(exc.value)
    with pytest.raises(DataError, match="T_ref = 25"):
        tts.master_curve(a + b, T_ref=25.0)


def test_pair_shift_is_the_mean_horizontal_distance():
    x = np.linspace(0.0, 3.0, 31)
    assert tts.pair_shift(x, x, x, x + 0.7) == pytest.approx(0.7, abs=1e-12)
    with pytest.raises(ValueError, match="overlap"):
        tts.pair_shift(x, x, x, x + 10.0)


def test_group_by_temperature_splits_consecutive_sets():
    sets = tts.group_by_temperature([1.0, 1.2, 5.0, 5.1, 1.0], [1, 2, 3, 4, 5])
    assert [round(s[0], 2) for s in sets] == [1.1, 5.05, 1.0]


# ------------------------------------------------------------------ shifted tests
def test_a_curve_at_temperature_is_the_reference_model_in_reduced_time():
    """τ_i(T) = a_T τ_i: the model with τ·a_T on the measured history equals the
    reference model on the shifted curve's history (reduced time t/a_T)."""
    m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=2)
    p = dict(C10=0.2, C01=0.1, G1=2.0, tau1=0.05, G2=1.0, tau2=2.0)
    t = np.array([0.0, 0.5, 1.0, 3.0, 4.0])
    eps = np.array([0.0, -0.2, -0.3, -0.3, -0.1])
    curve = vhfit.Curve(strain=eps, stress=[0.0, -1.0, -1.5, -1.2, -0.2], time=t)
    a = 25.0
    hot = tts.shift_curve(curve, a)
    np.testing.assert_allclose(hot.time, t / a, rtol=1e-15)
    slow = m.stress(dict(p, tau1=a * 0.05, tau2=a * 2.0), strain=eps, time=t)
    ref = m.stress(p, strain=hot.strain, time=hot.time)
    np.testing.assert_allclose(ref, slow, rtol=1e-10, atol=1e-13)
    ramp = vhfit.Curve(strain=[0.0, -0.1, -0.2], stress=[0.0, -1.0, -2.0], strain_rate=-0.5)
    assert tts.shift_curve(ramp, 4.0).strain_rate == -2.0


def test_shift_curve_refuses_bad_factors_and_items():
    ramp = vhfit.Curve(strain=[0.0, -0.1, -0.2], stress=[0.0, -1.0, -2.0], strain_rate=-0.5)
    with pytest.raises(ValueError, match="a_T"):
        tts.shift_curve(ramp, 0.0)
    with pytest.raises(TypeError, match="cannot shift"):
        tts.shift_curve([1, 2], 2.0)


def test_master_curve_of_frequency_sweeps_merges_near_temperatures_and_gives_an_item():
    f = np.logspace(-1, 2, 13)
    items = []
    for T in TEMPS:
        e1, e2 = storage_loss(f * LAW.aT(T))
        # one level recorded at two slightly different temperatures, as files often are
        items.append(vhfit.FrequencySweep(frequency=f[:6], storage=e1[:6], loss=e2[:6],
                                          temperature=T - 0.2))
        items.append(vhfit.FrequencySweep(frequency=f[6:], storage=e1[6:], loss=e2[6:],
                                          temperature=T + 0.2))
    mc = tts.master_curve(items, T_ref=20.0)
    # each level at the point-weighted mean of its two records: (6 (T - 0.2) + 7 (T + 0.2)) / 13
    np.testing.assert_allclose(mc.temperatures, TEMPS + 0.2 / 13, atol=1e-12)
    np.testing.assert_allclose(mc.log_aT, LAW.log_aT(TEMPS), atol=0.02)
    sweep = mc.item()
    assert isinstance(sweep, vhfit.FrequencySweep) and sweep.temperature is None
    assert sweep.frequency.size == TEMPS.size * 13
    hot = tts.shift_curve(items[-1], float(LAW.aT(60.2)))
    np.testing.assert_allclose(hot.frequency, f[6:] * LAW.aT(60.2), rtol=1e-14)


def test_master_curve_of_relaxation_tests_gives_a_relaxation_item():
    t = np.logspace(-2, 1, 13)
    items = [vhfit.Relaxation(time=t, modulus=relax(t / LAW.aT(T)), temperature=T)
             for T in (10.0, 20.0, 30.0)]
    rel = tts.master_curve(items).item("E(t)")
    assert isinstance(rel, vhfit.Relaxation) and rel.time.size == 39


# ------------------------------------------------------------------ one calibration's items
def test_reduce_to_reference_shifts_every_item_with_factors_built_from_the_sweeps():
    f = np.logspace(-1, 2, 13)
    sweeps = []
    for T in TEMPS:
        e1, e2 = storage_loss(f * LAW.aT(T))
        sweeps.append(vhfit.FrequencySweep(frequency=f, storage=e1, loss=e2, temperature=T,
                                           name=f"dma {T:g}"))
    curve = vhfit.Curve(strain=[0.0, -0.1, -0.2], stress=[0.0, -1.0, -2.0], strain_rate=-1.0,
                        metadata={"temperature": 40.0})
    ref = vhfit.Curve(strain=[0.0, -0.1], stress=[0.0, -1.0], strain_rate=-1.0)
    with pytest.raises(DataError, match="no temperature, beside tests at 8 temperatures"):
        tts.reduce_to_reference([*sweeps, curve, ref])
    out, mc = tts.reduce_to_reference([*sweeps, curve, ref], T_ref=20.0)
    assert isinstance(mc, tts.MasterCurve)
    assert all(getattr(x, "temperature", None) is None for x in out[:-2])
    np.testing.assert_allclose(out[0].frequency, f * LAW.aT(TEMPS[0]), rtol=0.05)
    assert out[-2].strain_rate == pytest.approx(-LAW.aT(40.0), rel=0.05)
    assert out[-1] is ref  # no temperature: at the reference already


def test_reduce_to_reference_leaves_one_temperature_alone_and_refuses_uncovered_ones():
    f = np.logspace(-1, 1, 5)
    a = vhfit.FrequencySweep(frequency=f, storage=10 + f, loss=f, temperature=20.0)
    items, how = tts.reduce_to_reference([a])
    assert items == [a] and how is None
    b = vhfit.FrequencySweep(frequency=f, storage=100 + f, loss=f, temperature=60.0,
                             name="hot", source="hot.csv")
    with pytest.raises(DataError, match="no shift factor for T = 60.*give shift factors"):
        tts.reduce_to_reference([a, b])
    with pytest.raises(DataError, match="^hot.csv: hot: no shift factor for T = 60.*covers"):
        tts.reduce_to_reference([a, b], shift_factors={20.0: 0.0})
    curve = vhfit.Curve(strain=[0.0, -0.1], stress=[0.0, -1.0], strain_rate=-1.0,
                        metadata={"temperature": 0.0})
    with pytest.raises(DataError, match="no shift factors: give shift_factors="):
        tts.reduce_to_reference([curve, vhfit.Curve(
            strain=[0.0, -0.1], stress=[0.0, -1.0], strain_rate=-1.0,
            metadata={"temperature": 50.0})])
    out, law = tts.reduce_to_reference([a, b], shift_factors=LAW)
    assert out[1].frequency[0] == pytest.approx(f[0] * LAW.aT(60.0), rel=1e-14)


def test_calibrate_fits_sweeps_at_several_temperatures_at_the_reference():
    """calibrate puts tests at several temperatures at T_ref first: the fit of the raw
    sweeps equals the fit of their master curve."""
    import warnings

    f = np.logspace(-1, 2, 13)
    sweeps = []
    for T in (10.0, 20.0, 30.0):
        e1, e2 = storage_loss(f * LAW.aT(T))
        sweeps.append(vhfit.FrequencySweep(frequency=f, storage=e1, loss=e2, temperature=T))
    master = tts.master_curve(sweeps).item()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = vhfit.calibrate(sweeps, hyperelastic="neo_hooke", n_prony=2, seed=0, maxiter=30)
        b = vhfit.calibrate([master], hyperelastic="neo_hooke", n_prony=2, seed=0, maxiter=30)
    # Two code paths (three items shifted one by one; one merged item) fit the same 39
    # points in another order, so the objectives differ by rounding only (~n·eps), the
    # seeded searches make the same choices and hand the polish the same start. The
    # polish's Jacobian is forward differences with steps 1e-7·|z|: the rounding of the
    # stresses (eps·|σ|, up to ~5·|r| at this fit's 18 %) enters each column as noise of
    # ~5·eps/1e-7 ≈ 1e-8 relative, and where the polish stops moves by up to κ² times
    # that, κ ≈ 3.4 the condition number of the column-scaled Jacobian here (x_scale =
    # "jac"): ~1e-7. Measured: 3e-10 on one machine, 1.2e-9 on another. rel = 1e-6 keeps
    # a margin of ten over that bound; a shift of a_T by 0.001 decades, the smallest
    # misplacement worth the name, moves τ by 2.3e-3.
    assert a.params == pytest.approx(b.params, rel=1e-6)
    # the errors: rounding (1e-14) plus what the parameters' difference moves them by,
    # which at the polish's minimum (gradient ≈ 0) is second order in it (≪ 1e-12)
    assert a.rmsape == pytest.approx(b.rmsape, rel=1e-10)
    far = vhfit.FrequencySweep(frequency=f, storage=1e6 + f, loss=f, temperature=90.0,
                               name="far")
    with pytest.raises(DataError, match="^far: no shift factor for T = 90"):
        vhfit.calibrate([*sweeps, far], hyperelastic="neo_hooke", n_prony=1)
