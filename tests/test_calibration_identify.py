"""The identifiability guard: which data can separate elastic from viscous response.

Rules (written out independently of vhfit.calibration._identify): a Prony series is
identified by (a) two nominal rates whose magnitudes differ by more than a factor 1.25,
(b) any curve with a hold or an unloading (more than one segment), or (c) rate curves
beside equilibrium (rate-free) curves. One monotonic rate alone, or equilibrium curves
alone, identify none: calibrate's default is then 0 terms with the reason; a forced
N > 0 is fitted with a headline warning.
"""

from __future__ import annotations

import warnings
from types import SimpleNamespace

import numpy as np
import pytest

import vhfit
from vhfit.calibration import CalibrationWarning
from vhfit.calibration._identify import DEFAULT_N_PRONY, default_n_prony, viscous_evidence

TRUE = dict(C10=0.1, C01=0.05, G1=1.0, tau1=0.01)
M1 = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
EPS = np.linspace(-0.05, -0.5, 12)


def ramp(rate):
    s = M1.stress(TRUE, strain=EPS, strain_rate=rate, measure="engineering")
    return vhfit.Curve(strain=EPS, stress=s, strain_rate=rate)


def load_unload():
    t = np.linspace(0.0, 2.0, 41)
    e = -0.4 * (1.0 - np.abs(1.0 - t))  # down to -0.4 at t = 1 s, back to 0
    s = M1.stress(TRUE, strain=e, time=t, measure="engineering")
    return vhfit.Curve(strain=e[1:], stress=s[1:], time=t[1:], strain_rate=-0.4)


@pytest.mark.parametrize("ratio, identified", [(1.2, False), (1.3, True), (100.0, True)])
def test_two_rates_identify_only_when_they_differ_by_more_than_a_quarter(ratio, identified):
    reason = viscous_evidence([ramp(-1.0), ramp(-1.0 * ratio)])
    assert (reason is None) is identified
    if not identified:
        assert reason.startswith("one strain rate (1 1/s) and monotonic loading")


def test_a_single_unloading_curve_identifies():
    c = load_unload()
    assert c.n_segments == 2
    assert viscous_evidence([c]) is None
    assert default_n_prony([c]) == (DEFAULT_N_PRONY, None) == (2, None)


def test_equilibrium_curves_alone_identify_nothing_but_beside_a_ramp_they_do():
    eq = SimpleNamespace(is_equilibrium=True, is_moduli=False)
    assert "only equilibrium" in viscous_evidence([eq, eq])
    assert viscous_evidence([eq, ramp(-1.0)]) is None


def test_calibrate_defaults_to_no_prony_terms_on_one_monotonic_rate():
    with warnings.catch_warnings():
        warnings.simplefilter("error", CalibrationWarning)  # no warning: it is the default
        cal = vhfit.calibrate([ramp(-10.0)], seed=0, uncertainty=False)
    assert cal.n_prony == 0 and list(cal.params) == ["C10", "C01"]
    reason = cal.options["n_prony_reason"]
    assert reason == ("no Prony terms by default: one strain rate (10 1/s) and monotonic "
                      "loading, no hold or unloading")
    assert cal.summary().splitlines()[3] == "note: " + reason  # after verdict, title, error
    assert not cal.headlines


def test_forced_prony_terms_on_unidentifiable_data_carry_a_headline_warning():
    with pytest.warns(CalibrationWarning, match="cannot separate elastic from viscous"):
        cal = vhfit.calibrate([ramp(-10.0)], n_prony=1, seed=0, uncertainty=False,
                              maxiter=30)
    assert cal.n_prony <= 1 and "n_prony_reason" not in cal.options
    assert cal.headlines and cal.headlines[0].startswith(
        "the data cannot separate elastic from viscous response (one strain rate")
    assert cal.summary().splitlines()[3] == "WARNING: " + cal.headlines[0]


@pytest.mark.filterwarnings("ignore::vhfit.calibration.CalibrationWarning")
def test_identifiable_data_keep_the_default_two_terms_silently():
    cal = vhfit.calibrate([ramp(-1.0), ramp(-100.0)], seed=0, uncertainty=False, maxiter=30)
    assert cal.options["n_prony"] == 2 and "n_prony_reason" not in cal.options
    assert not [h for h in cal.headlines if "cannot separate" in h]
