"""A WLF fit of shift factors that degenerates (C1 and C2 growing together: a straight
line in T, as across a glass transition) is reported, the law the data choose replaces
it, the tests keep their measured shift factors, and the cards say what they carry."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import vhfit
from vhfit import tts
from vhfit.cli._cards import card_shift

T = np.linspace(0.0, 100.0, 11)
SLOPE = -0.05  # log10 a_T per degree: a straight line, no WLF curvature at all
LINE = SLOPE * (T - 50.0)


def test_a_straight_line_degenerates_the_wlf_fit_and_is_reported():
    """Least squares drives C2 to the top of its scan on a straight line (C1/C2 → the
    slope); the check names the degeneracy with the slope and the temperature range."""
    law = tts.fit_shift_law(T, LINE, "wlf", T_ref=50.0)
    assert law.C2 >= tts._laws.WLF_DEGENERATE * 50.0  # the fit did run away
    assert -law.C1 / law.C2 == pytest.approx(SLOPE, rel=1e-2)
    msg = tts.wlf_degenerate(law, T)
    assert msg is not None and "degenerates" in msg and "T = 0..100" in msg


@pytest.mark.parametrize("C1, C2", [(8.86, 101.6), (17.44, 51.6), (24.9, 138.5)])
def test_ordinary_wlf_laws_are_not_called_degenerate(C1, C2):
    """Textbook constants (and pyvisco's example's) over 100 degrees around T_ref: the fit
    recovers them and raises nothing; choose_shift_law keeps WLF."""
    Ts = np.linspace(-30.0, 70.0, 11)
    y = tts.WLF(C1, C2, 0.0).log_aT(Ts)
    law, msg = tts.choose_shift_law(Ts, y, T_ref=0.0)
    assert msg is None and law.name == "wlf"
    assert (law.C1, law.C2) == pytest.approx((C1, C2), rel=1e-6)


def test_a_wlf_whose_c2_is_just_below_the_limit_is_kept():
    """C2 = 50 times the data's reach: curved by 2 % over the data, still a WLF law."""
    Ts = np.linspace(-10.0, 10.0, 9)
    law = tts.WLF(5.0, 500.0, 0.0)
    assert tts.wlf_degenerate(law, Ts) is None
    assert tts.wlf_degenerate(tts.WLF(5.0, 1000.0, 0.0), Ts) is not None


def test_the_data_choose_the_straight_line_instead():
    """Exact straight-line factors: the polynomial of degree 1 fits them exactly (the
    known answer: its coefficient is the slope), Arrhenius does not; the one-line report
    says the measured factors are kept and names the law and the residuals."""
    law, msg = tts.choose_shift_law(T, LINE, T_ref=50.0)
    assert law.name == "polynomial" and len(law.coefficients) == 1
    assert law.coefficients[0] == pytest.approx(SLOPE, abs=1e-12)
    assert "measured shift" in msg and "polynomial of degree 1" in msg and "arrhenius" in msg


def test_an_arrhenius_material_chooses_arrhenius():
    """Factors of an Arrhenius law (E_a = 2e5 J/mol) over 20..120 °C: the WLF fit
    degenerates towards a line only if it cannot bend the right way; whenever it is
    replaced, the data choose Arrhenius back, with the same E_a."""
    Ts = np.linspace(20.0, 120.0, 11)
    y = tts.Arrhenius(2e5, 70.0).log_aT(Ts)
    law, msg = tts.choose_shift_law(Ts, y, T_ref=70.0)
    if msg is not None:
        assert law.name == "arrhenius"
        assert law.E_a == pytest.approx(2e5, rel=1e-9)
    else:  # WLF bends like 1/T: then it must reproduce the factors closely
        assert np.max(np.abs(law.log_aT(Ts) - y)) < 1e-2


def sweeps_at(temps, log_aT):
    """Exact sweeps of E∞ = 1.2 MPa + one Maxwell term G = 2 MPa, τ = 0.1 s at T_ref,
    measured at T: the reference curve at the reduced frequency f a_T."""
    f = np.logspace(-1, 1, 9)
    out = []
    for Tk, L in zip(temps, log_aT):
        w = 2 * np.pi * f * 10.0**L
        wt = w * 0.1
        e1 = 1.2 + 2.0 * wt**2 / (1 + wt**2)
        e2 = 2.0 * wt / (1 + wt**2)
        out.append(vhfit.FrequencySweep(frequency=f, storage=e1, loss=e2,
                                        temperature=float(Tk), name=f"{Tk:g} C"))
    return out


def test_calibration_reports_it_keeps_the_measured_table_and_the_cards_say_what_they_carry():
    """Sweeps at 0..100 °C with a straight-line table: the headline reports the
    degenerate WLF, the result's law is the line, its shift table is the measured one
    (so the exact data are fitted exactly), and the cards carry the WLF fitted to that
    table — which reproduces it within 1e-3 decades — with a note on where it holds."""
    table = dict(zip(T.tolist(), LINE.tolist()))
    items = sweeps_at(T, LINE)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate(items, hyperelastic="neo_hooke", n_prony=1,
                              shift_factors=table, T_ref=50.0)
    assert "degenerates" in cal.headlines[0] and cal.headlines[0] in cal.warnings
    assert cal.shift.name == "polynomial"
    assert cal.shift_table == pytest.approx(table)
    assert cal.rmsape < 1e-6
    assert cal.params["tau1"] == pytest.approx(0.1, rel=1e-6)
    law, note = card_shift(cal)
    assert law.name == "wlf"
    np.testing.assert_allclose(law.log_aT(T), LINE, atol=1e-3)
    assert "holds only for T = 0..100" in note


def test_cards_of_a_law_no_wlf_reproduces_say_they_carry_no_shift():
    """A strongly curved quadratic table (no WLF law of positive C2 follows it): the
    cards carry no shift and say so."""
    quad = 0.004 * (T - 50.0) ** 2 - 0.05 * (T - 50.0)
    cal = vhfit.Calibration.__new__(vhfit.Calibration)
    object.__setattr__(cal, "shift", tts.PolynomialShift((-0.05, 0.004), 50.0))
    object.__setattr__(cal, "shift_table", dict(zip(T.tolist(), quad.tolist())))
    object.__setattr__(cal, "T_ref", 50.0)
    law, note = card_shift(cal)
    assert law is None and note.startswith("no time-temperature shift in the card")
