"""The search's early finish: a law with a nonlinear shape may stop when a polish of the
best member reaches the target; otherwise the search goes on exactly as it would have.
"""

from __future__ import annotations

import warnings

import numpy as np

import vhfit
from vhfit.calibration import CalibrationWarning, _search
from vhfit.calibration._bounds import search_bounds
from vhfit.calibration._space import FullSpace, Problem, SeparableSpace


class _Space:
    """A stand-in space: ``search_target`` is 100× the target, ``to_params`` is identity."""

    prob = None

    def __init__(self, loose=100.0):
        self.loose = loose

    def search_target(self, target):
        return self.loose * target

    def to_params(self, z):
        return z


def test_the_best_member_is_polished_once_below_the_looser_level(monkeypatch):
    calls = []

    def fake_polish(prob, x):
        calls.append(x.copy())
        return x, 5e-4, 7  # misses the target 1e-4

    monkeypatch.setattr(_search, "polish_fit", fake_polish)
    f = _search._EarlyFinish(_Space(), 1e-4)
    assert f.level == 1e-2
    assert f(2e-2, np.array([1.0])) is False and not calls  # above the level: no polish
    assert f(9e-3, np.array([2.0])) is False and len(calls) == 1  # polished, missed
    assert f(1e-3, np.array([3.0])) is False and len(calls) == 1  # never a second time
    assert not f.done and f.nfev == 7


def test_a_polish_that_reaches_the_target_stops_the_search(monkeypatch):
    monkeypatch.setattr(_search, "polish_fit", lambda prob, x: (x, 1e-5, 3))
    f = _search._EarlyFinish(_Space(), 1e-4)
    assert f(5e-3, np.array([1.0])) is True and f.done and f.nfev == 3


def test_no_looser_level_means_no_polish(monkeypatch):
    monkeypatch.setattr(_search, "polish_fit", lambda prob, x: 1 / 0)
    f = _search._EarlyFinish(_Space(loose=1.0), 1e-4)
    assert f(0.0, np.array([1.0])) is False


def _multimode(law, truth, n=24):
    m = vhfit.ViscoHyperelastic(law, 1)
    out = []
    for mode in ("uniaxial", "equibiaxial", "planar"):
        for r in (0.1, 10.0):
            eps = np.linspace(0.4 / n, 0.4, n)
            s = m.stress(truth, strain=eps, strain_rate=r, deformation=mode,
                         measure="engineering")
            out.append(vhfit.Curve(strain=eps, stress=s, strain_rate=r, deformation=mode))
    return out


def _space(law, curves, method=SeparableSpace):
    model = vhfit.ViscoHyperelastic(law, 1)
    tau_b, auto = search_bounds(model, curves, "free", 3, 1, "auto")
    return method(Problem(model, curves, tau_b, auto, 1e-6))


def test_only_laws_with_several_linear_constants_and_a_nonlinear_shape_loosen():
    og = dict(mu1=0.3, alpha1=1.8, mu2=0.01, alpha2=6.0, G1=1.0, tau1=0.3)
    curves = _multimode("ogden2", og)
    assert _space("ogden2", curves).search_target(1e-4) == 1e-2
    assert _space("ogden2", curves, FullSpace).search_target(1e-4) == 1e-4
    mr = dict(C10=0.1, C01=0.05, G1=1.0, tau1=0.3)
    assert _space("mooney_rivlin", _multimode("mooney_rivlin", mr)).search_target(1e-4) == 1e-4
    one = dict(mu1=0.3, alpha1=1.8, G1=1.0, tau1=0.3)
    assert _space("ogden", _multimode("ogden", one)).search_target(1e-4) == 1e-4


def test_an_ogden2_recovery_ends_by_the_polish_and_reaches_the_data():
    truth = dict(mu1=0.3, alpha1=1.8, mu2=0.01, alpha2=6.0, G1=1.0, tau1=0.3)
    curves = _multimode("ogden2", truth)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CalibrationWarning)
        cal = vhfit.calibrate(curves, hyperelastic="ogden2", n_prony=1, seed=0,
                              uncertainty=False)
    assert cal.stop_reason == "target reached by a polish of the best member"
    assert cal.rmsape <= 1e-6
    for k, v in truth.items():  # the terms may come back in either order
        j = k[-1]
        if k.startswith(("mu", "alpha")) and abs(cal.params[k] - v) > 1e-6 * abs(v):
            other = {"1": "2", "2": "1"}[j]
            assert abs(cal.params[k[:-1] + other] - v) <= 1e-6 * abs(v)
        elif not k.startswith(("mu", "alpha")):
            assert abs(cal.params[k] - v) <= 1e-6 * abs(v)
