"""Time–temperature superposition through ``calibrate``: sweeps at several temperatures
and stress–strain curves at another, one material at T_ref, and the shift law kept in the
result, its summary and its results file.

The data are generated here from a known Mooney–Rivlin + Prony material at T_ref and a
known WLF law, with the closed forms written in this file: E′, E″ of the generalised
Maxwell model at the reduced frequency f·a_T, and a constant-rate ramp at T as the
reference material at the rate ε̇·a_T (reduced time t/a_T).
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

import vhfit
from vhfit import tts

TRUE = dict(C10=0.2, C01=0.05, G1=3.0, tau1=1e-3, G2=1.0, tau2=0.1)
C1, C2, T_REF = 8.86, 101.6, 20.0
SWEEP_TEMPS = (0.0, 20.0, 40.0, 60.0)
CURVE_TEMP = 30.0  # the stress–strain tests: at a temperature without a sweep


def log_aT(T: float) -> float:
    """WLF, written from its definition: −C1 (T − T_ref)/(C2 + T − T_ref)."""
    return -C1 * (T - T_REF) / (C2 + T - T_REF)


def maxwell(omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """E′, E″ of E∞ + Σ G_i iωτ_i/(1 + iωτ_i), E∞ = 3 μ0 = 6 (C10 + C01)."""
    E_inf = 6.0 * (TRUE["C10"] + TRUE["C01"])
    G = np.array([TRUE["G1"], TRUE["G2"]])
    wt = omega[:, None] * np.array([TRUE["tau1"], TRUE["tau2"]])
    return E_inf + (G * wt**2 / (1 + wt**2)).sum(1), (G * wt / (1 + wt**2)).sum(1)


def sweeps() -> list:
    f = np.logspace(-1, 2, 31)
    out = []
    for T in SWEEP_TEMPS:
        e1, e2 = maxwell(2 * np.pi * f * 10 ** log_aT(T))
        out.append(vhfit.FrequencySweep(frequency=f, storage=e1, loss=e2, temperature=T,
                                        name=f"dma {T:g}"))
    return out


def ramps() -> list:
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    eps = np.linspace(0.0, -0.4, 21)
    out = []
    for r in (-1.0, -100.0):
        s = m.stress(TRUE, strain=eps, strain_rate=r * 10 ** log_aT(CURVE_TEMP),
                     measure="engineering")
        out.append(vhfit.Curve(strain=eps, stress=s, strain_rate=r, measure="engineering",
                               metadata={"temperature": CURVE_TEMP}, name=f"rate {r:g}"))
    return out


def fit(items, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return vhfit.calibrate(items, n_prony=2, seed=0, **kw)


@pytest.fixture(scope="module")
def given():
    return fit([*sweeps(), *ramps()], shift_factors=tts.WLF(C1, C2, T_REF))


@pytest.fixture(scope="module")
def built():
    return fit([*sweeps(), *ramps()], T_ref=T_REF)


def test_a_given_wlf_law_recovers_the_material_at_t_ref(given):
    for k, v in TRUE.items():
        assert given.params[k] == pytest.approx(v, rel=1e-6), k
    assert given.shift == tts.WLF(C1, C2, T_REF)  # the given law, as is
    assert given.shift_source == "law" and given.T_ref == T_REF
    assert sorted(given.shift_table) == sorted((*SWEEP_TEMPS, CURVE_TEMP))
    for T, L in given.shift_table.items():
        assert L == pytest.approx(log_aT(T), rel=1e-12, abs=1e-14)


def test_shift_factors_built_from_the_sweeps_overlap_give_the_wlf_law(built):
    law = built.shift
    assert built.shift_source == "overlap" and isinstance(law, tts.WLF)
    assert law.T_ref == T_REF
    assert law.C1 == pytest.approx(C1, rel=0.01) and law.C2 == pytest.approx(C2, rel=0.01)
    for T in SWEEP_TEMPS:  # the table holds the master curve's own shifts
        assert built.shift_table[T] == pytest.approx(log_aT(T), abs=2e-3)
    # the curve at 30 (no sweep there) was shifted by the fitted law
    assert built.shift_table[CURVE_TEMP] == pytest.approx(float(law.log_aT(CURVE_TEMP)),
                                                         rel=1e-12)
    for k, v in TRUE.items():  # shifts from interpolated overlap: close, not exact
        assert built.params[k] == pytest.approx(v, rel=1e-3), k


def test_the_summary_and_the_results_file_keep_the_shift(given, tmp_path):
    text = given.summary()
    assert "time-temperature shift: WLF C1 = 8.86, C2 = 101.6 at T_ref = 20 (given)" in text
    assert "30: -0.7939" in text  # log10 a_T(30) = −8.86·10/111.6 = −0.79391
    path = tmp_path / "results.json"
    given.save(path)
    rec = json.loads(path.read_text())["shift"]
    assert rec["law"] == "wlf" and rec["T_ref"] == T_REF and rec["source"] == "law"
    assert rec["constants"] == {"T_ref": T_REF, "C1": C1, "C2": C2}
    table = dict(zip(rec["temperatures"], rec["log_aT"]))
    assert table[60.0] == pytest.approx(-C1 * 40 / (C2 + 40), rel=1e-12)
    back = vhfit.Calibration.load(path)
    assert back.shift == tts.WLF(C1, C2, T_REF)
    assert back.shift_table == given.shift_table and back.shift_source == "law"
    assert back.T_ref == T_REF and "time-temperature shift: WLF" in back.summary()


def test_a_table_of_shift_factors_is_applied_and_fitted_by_wlf():
    temps = (*SWEEP_TEMPS, CURVE_TEMP)
    table = {T: log_aT(T) for T in temps}
    ref = tts.shift_to_reference([*sweeps(), *ramps()], shift_factors=table)
    assert isinstance(ref, tts.ReferenceShift) and ref.source == "table"
    assert ref.T_ref == T_REF  # the temperature whose log10 a_T is 0
    assert ref.law.C1 == pytest.approx(C1, rel=1e-6) and ref.law.C2 == pytest.approx(C2,
                                                                                    rel=1e-6)
    rate = ref.items[-1].strain_rate  # −100 1/s at 30: −100·a_T at T_ref
    assert rate == pytest.approx(-100.0 * 10 ** log_aT(CURVE_TEMP), rel=1e-12)
    assert "temperature" not in ref.items[-1].metadata  # not shifted twice
    np.testing.assert_allclose(ref.items[0].frequency,
                               np.logspace(-1, 2, 31) * 10 ** log_aT(0.0), rtol=1e-12)


def test_stress_strain_at_one_temperature_has_no_shift():
    curves = ramps()
    ref = tts.shift_to_reference(curves)
    assert ref.source == "none" and ref.law is None and ref.items == curves
    cal = fit([curves[0].replace(name="a"), curves[1]], maxiter=5, polish=False,
              uncertainty=False)
    assert cal.shift is None and cal.shift_table == {} and "shift" not in cal.to_dict()
    assert "time-temperature" not in cal.summary()


def test_a_test_without_temperature_beside_built_shifts_needs_t_ref():
    plain = vhfit.Curve(strain=[0.0, -0.1], stress=[0.0, -1.0], strain_rate=-1.0, name="p")
    with pytest.raises(ValueError, match="^p: no temperature, beside tests at 5 temperatures"):
        tts.shift_to_reference([*sweeps(), *ramps(), plain])
    ref = tts.shift_to_reference([*sweeps(), *ramps(), plain], T_ref=T_REF)
    assert ref.items[-1] is plain and ref.source == "overlap"


def test_a_table_for_tests_without_temperatures_is_refused():
    with pytest.raises(ValueError, match="^shift_factors: a table of log10 a_T, but no test "
                       "has a temperature"):
        tts.shift_to_reference([vhfit.Curve(strain=[0.0, -0.1], stress=[0.0, -1.0],
                                            strain_rate=-1.0)], shift_factors={20.0: 0.0})


@pytest.mark.parametrize("kw, needle", [
    (dict(shift_factors="wlf"), "shift_factors = 'wlf': give a law"),
    (dict(shift_factors=([0.0, 20.0], [1.0])), "2 temperatures and 1 log10 a_T"),
    (dict(shift_factors={0.0: float("nan")}), "each with a finite log10 a_T"),
    (dict(T_ref="20"), "T_ref = '20': give the reference temperature"),
    (dict(shift_factors=tts.WLF(C1, C2, T_REF), T_ref=25.0),
     "T_ref = 25.0: the shift law is referred to T_ref = 20.0"),
])
def test_bad_shift_arguments_are_one_line_errors(kw, needle):
    with pytest.raises(ValueError) as exc:
        vhfit.calibrate(ramps(), n_prony=1, **kw)
    msg = str(exc.value)
    assert needle in msg and "\n" not in msg


def test_read_csv_gives_one_item_per_temperature_level(tmp_path):
    """Readings of one level drift by hundredths of a degree: one sweep per level, at the
    level's mean temperature; a set column decides alone."""
    T = [20.02, 19.97, 20.01, 39.96, 40.03, 40.01, 20.0]
    body = "\n".join(f"{f},{10 + k},{1 + k},{t}" for k, (f, t) in
                     enumerate(zip([0.1, 1, 10, 0.1, 1, 10, 100], T)))
    path = tmp_path / "drift.csv"
    path.write_text("frequency_Hz,storage_MPa,loss_MPa,temperature_C\n" + body + "\n")
    a, b = vhfit.read_csv(path)
    assert a.temperature == pytest.approx((20.02 + 19.97 + 20.01 + 20.0) / 4, rel=1e-14)
    assert b.temperature == pytest.approx((39.96 + 40.03 + 40.01) / 3, rel=1e-14)
    assert a.frequency.tolist() == [0.1, 1.0, 10.0, 100.0] and b.storage.tolist() == [13, 14, 15]
    sets = tmp_path / "sets.csv"  # the last row is a second sweep at 20, its own set
    sets.write_text("frequency_Hz,storage_MPa,loss_MPa,temperature_C,set_index\n" + "\n".join(
        f"{line},{s}" for line, s in zip(body.splitlines(), [0, 0, 0, 1, 1, 1, 2])) + "\n")
    items = vhfit.read_csv(sets)
    assert [x.frequency.size for x in items] == [3, 3, 1]
    assert items[2].temperature == 20.0
