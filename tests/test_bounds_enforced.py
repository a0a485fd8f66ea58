"""``Calibration.bounds`` is the box the fit held its constants to (issue: a Gent fit
returned mu = 1.04 while its bounds said mu in (0, 0.299)).

The separable search solves the moduli by least squares and the polish refines them
with the law's limits only: their automatic ranges are where the all-parameter search
draws them, not limits of the result. So the reported box of a modulus is the law's
(or the user's), and every fitted constant lies inside the box reported.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import vhfit
from vhfit.calibration._bounds import auto_bounds, search_bounds


def _curves(law, true, n_prony=1):
    """Uniaxial tension to λ = 3 (and compression to 0.6) at two rates, of ``true``."""
    m = vhfit.ViscoHyperelastic(law, n_prony)
    out = []
    for eps in (np.linspace(0.05, 2.0, 16), np.linspace(-0.04, -0.4, 10)):
        for r in (0.01, 1.0):
            r_s = r if eps[-1] > 0 else -r
            out.append(vhfit.Curve(strain=eps, stress=m.stress(
                true, strain=eps, strain_rate=r_s, measure="engineering"), strain_rate=r_s))
    return out


CASES = {
    "neo_hooke": dict(C10=0.2),
    "mooney_rivlin": dict(C10=0.15, C01=0.03),
    "gent": dict(mu=0.4, Jm=30.0),
    "yeoh": dict(C10=0.2, C20=-0.01, C30=0.002),
    "ogden": dict(mu1=0.3, alpha1=3.0),
    "arruda_boyce": dict(mu=0.3, lambda_m=4.0),
}


@pytest.mark.parametrize("method", ["separable", "full"])
@pytest.mark.parametrize("law", sorted(CASES))
def test_every_fitted_constant_is_inside_the_reported_bounds(law, method):
    true = {**CASES[law], "G1": 0.5, "tau1": 0.5}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate(_curves(law, true), hyperelastic=law, n_prony=1, seed=0,
                              method=method, maxiter=30, popsize=16, uncertainty=False)
    assert set(cal.bounds) == set(cal.params)
    for name, v in cal.params.items():
        lo, hi = cal.bounds[name]
        assert lo <= v <= hi, (name, v, lo, hi)
    # the moduli: the law's limits (the search draws them from a range, the least squares
    # and the polish do not keep them in it)
    hm = cal.model.hyperelastic
    for k, name in enumerate(hm.param_names):
        if hm.units[k] == "MPa":
            assert cal.bounds[name] == hm.bounds[k], name
    assert cal.bounds["G1"] == (0.0, np.inf)


def test_gent_modulus_beyond_its_automatic_range_is_inside_the_bounds():
    """The issue's case: a stiffening tension curve to λ = 8; mu ends far above the
    automatic range (computed with Jm at its example value), and cal.bounds says so."""
    lam = np.linspace(1.05, 8.0, 40)
    m = vhfit.ViscoHyperelastic("gent", 0)
    c = vhfit.Curve(strain=lam - 1, stress=m.stress(dict(mu=0.3, Jm=90.0), strain=lam - 1,
                                                    measure="engineering"))
    auto = auto_bounds(m, [c])
    assert auto["mu"][1] < 0.3  # the premise: the truth is outside the automatic range
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate([c], hyperelastic="gent", n_prony=0, seed=0, maxiter=50)
    assert cal.params["mu"] > auto["mu"][1]
    assert cal.bounds["mu"] == (0.0, np.inf)
    assert cal.params["mu"] == pytest.approx(0.3, rel=1e-3)


def test_full_search_without_polish_reports_its_own_box():
    """Without the polish the all-parameter search holds every constant to its box: the
    automatic ranges, a signed modulus drawn non-negative."""
    true = {**CASES["mooney_rivlin"], "G1": 0.5, "tau1": 0.5}
    curves = _curves("mooney_rivlin", true)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate(curves, hyperelastic="mooney_rivlin", n_prony=1, seed=0,
                              method="full", polish=False, maxiter=20, popsize=16,
                              uncertainty=False)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    tau_b, auto = search_bounds(m, curves, "free", 3.0, 1.0, "auto")
    assert cal.bounds["C10"] == pytest.approx((0.0, auto["C10"][1]))
    assert cal.bounds["C01"] == pytest.approx((0.0, auto["C01"][1]))
    assert cal.bounds["G1"] == pytest.approx(auto["G1"])
    assert cal.bounds["tau1"] == pytest.approx(tuple(10.0 ** tau_b[0]))
    for name, v in cal.params.items():
        lo, hi = cal.bounds[name]
        assert lo <= v <= hi, (name, v, lo, hi)


def test_bounds_the_user_gave_are_reported_as_given():
    true = {**CASES["neo_hooke"], "G1": 0.5, "tau1": 0.5}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate(_curves("neo_hooke", true), hyperelastic="neo_hooke",
                              n_prony=1, seed=0, maxiter=30, popsize=16, uncertainty=False,
                              bounds={"C10": (0.05, 0.15), "G1": (0.1, 2.0)})
    assert cal.bounds["C10"] == (0.05, 0.15) and cal.bounds["G1"] == (0.1, 2.0)
    assert cal.params["C10"] == pytest.approx(0.15)  # the truth (0.2) is beyond the limit
