"""The search's early finish: a law with a nonlinear shape may stop when a polish of the
best member gets well below the target; otherwise the search goes on as it would have.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import vhfit
from vhfit.calibration import CalibrationWarning, Stop, StopKind, _search
from vhfit.calibration._bounds import search_bounds
from vhfit.calibration._space import FullSpace, Problem, SeparableSpace


class _Space:
    """A stand-in space: levels 1e4 and 1e2 times the target, ``to_params`` the identity."""

    prob = None
    separable = False  # no gathered-population finish: only the levels are tested here

    def __init__(self, levels=(1e4, 1e2)):
        self.levels = levels

    def finish_levels(self, target):
        return tuple(f * target for f in self.levels)

    def to_params(self, z):
        return z


def test_the_best_member_is_polished_once_per_level_it_passes(monkeypatch):
    calls = []

    def fake_polish(prob, x, max_nfev):
        calls.append(float(x[0]))
        return x, 5e-5, 7  # below the target 1e-4, not below 1e-2 of it: not accepted

    monkeypatch.setattr(_search, "polish_fit", fake_polish)
    f = _search._EarlyFinish(_Space(), 1e-4)
    assert f.levels == [1.0, 1e-2]
    assert f(2.0, np.array([1.0])) is False and calls == []  # above every level
    assert f(0.5, np.array([2.0])) is False and calls == [2.0]  # below 1: polished, missed
    assert f(0.1, np.array([3.0])) is False and calls == [2.0]  # no new level passed
    assert f(1e-3, np.array([4.0])) is False and calls == [2.0, 4.0]  # below 1e-2
    assert f(1e-5, np.array([5.0])) is False and calls == [2.0, 4.0]  # no level left
    assert not f.done and f.nfev == 14


def test_one_polish_covers_every_level_the_error_jumped_past(monkeypatch):
    calls = []
    monkeypatch.setattr(_search, "polish_fit",
                        lambda prob, x, n: (calls.append(1), (x, 1.0, 1))[1])
    f = _search._EarlyFinish(_Space(), 1e-4)
    assert f(1e-3, np.array([1.0])) is False and len(calls) == 1 and f.levels == []


def test_a_polish_well_below_the_target_stops_the_search(monkeypatch):
    monkeypatch.setattr(_search, "polish_fit", lambda prob, x, n: (x, 1e-6, 3))
    f = _search._EarlyFinish(_Space(), 1e-4)
    assert f(0.5, np.array([1.0])) is True and f.done and f.nfev == 3


def test_no_levels_means_no_polish(monkeypatch):
    monkeypatch.setattr(_search, "polish_fit", lambda prob, x, n: 1 / 0)
    f = _search._EarlyFinish(_Space(levels=()), 1e-4)
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


def test_only_laws_with_several_linear_constants_and_a_nonlinear_shape_finish_early():
    og = dict(mu1=0.3, alpha1=1.8, mu2=0.01, alpha2=6.0, G1=1.0, tau1=0.3)
    curves = _multimode("ogden2", og)
    levels = _space("ogden2", curves).finish_levels(1e-4)
    assert levels == pytest.approx((1.0, 0.3, 0.1, 0.03, 0.01))
    assert _space("ogden2", curves, FullSpace).finish_levels(1e-4) == ()
    mr = dict(C10=0.1, C01=0.05, G1=1.0, tau1=0.3)
    assert _space("mooney_rivlin", _multimode("mooney_rivlin", mr)).finish_levels(1e-4) == ()
    one = dict(mu1=0.3, alpha1=1.8, G1=1.0, tau1=0.3)
    assert _space("ogden", _multimode("ogden", one)).finish_levels(1e-4) == ()


def test_an_ogden2_recovery_ends_by_the_polish_and_reaches_the_data():
    truth = dict(mu1=0.3, alpha1=1.8, mu2=0.01, alpha2=6.0, G1=1.0, tau1=0.3)
    curves = _multimode("ogden2", truth)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CalibrationWarning)
        cal = vhfit.calibrate(curves, hyperelastic="ogden2", n_prony=1, seed=0,
                              uncertainty=False)
    assert str(cal.stop_reason) == "target reached by a polish of the best member"
    assert cal.rmsape <= 1e-6
    for k, v in truth.items():  # the terms may come back in either order
        j = k[-1]
        if k.startswith(("mu", "alpha")) and abs(cal.params[k] - v) > 1e-6 * abs(v):
            other = {"1": "2", "2": "1"}[j]
            assert abs(cal.params[k[:-1] + other] - v) <= 1e-6 * abs(v)
        elif not k.startswith(("mu", "alpha")):
            assert abs(cal.params[k] - v) <= 1e-6 * abs(v)


def test_a_search_whose_constants_fail_on_every_point_keeps_its_polished_result(
        monkeypatch):
    """The linear solve on every point can fail (+inf) for the search's vector where the
    search's own polish on fewer points had a finite fit: that polish is the result, not
    "no parameter set with a finite error"."""
    from vhfit.calibration import _workflow

    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    truth = dict(C10=0.2, C01=0.1, G1=1.0, tau1=0.01)
    eps = np.linspace(-0.05, -0.5, 12)
    curves = [vhfit.Curve(strain=eps, stress=m.stress(truth, strain=eps, strain_rate=r,
                                                      measure="engineering"), strain_rate=r)
              for r in (-1.0, -100.0)]
    good = m.as_array(truth)

    real = _workflow.run_search

    def search(space, settings, **kw):  # a vector whose solve fails, and a polished fit
        if space.prob.hm.name != "mooney_rivlin":  # the neo-Hooke fit that seeds it
            return real(space, settings, **kw)
        return _search.Search(np.array([np.nan, -2.0]), 3, 10, Stop.of(StopKind.GATHERED),
                              _search._history(None), kw["t0"], (good, 0.0))

    monkeypatch.setattr(_workflow, "run_search", search)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate(curves, n_prony=1, seed=0, uncertainty=False)
    assert cal.rmsape < 1e-9
    assert cal.params == pytest.approx(truth, rel=1e-9)


@pytest.mark.parametrize("law, truth", [
    ("ogden2", dict(mu1=0.3, alpha1=1.8, mu2=0.01, alpha2=6.0, G1=1.0, tau1=0.3)),
    ("mooney_rivlin", dict(C10=0.1, C01=0.05, G1=1.0, tau1=0.3)),
])
def test_the_polishs_residuals_of_the_linear_solve_are_the_models(law, truth):
    """The variable-projection polish takes the residuals of the least squares of the
    moduli (A a − y): they must be what the model gives for the assembled constants."""
    space = _space(law, _multimode(law, truth))
    rng = np.random.default_rng(3)
    b = np.asarray(space.bounds())
    Z = b[:, 0] + rng.random((12, len(b))) * (b[:, 1] - b[:, 0])
    X, R = space.fit_of(Z)
    solved = np.isfinite(space.errors(Z))
    assert solved.sum() >= 3  # admissible members to compare
    with np.errstate(all="ignore"):
        model = space.prob.residuals(X)
    scale = np.abs(space.prob.y * space.prob.scale).max()
    # rounding, and the vanishing E∞ (1e-12 ΣG_i) the assembly keeps where the solve
    # gave none, which shifts the model's stress by ~1e-11 of the data's scale
    assert np.allclose(R[solved], model[solved], rtol=0, atol=1e-10 * scale)
    assert np.array_equal(X, space.params_of(Z), equal_nan=True)


def test_forward_jacobian_reuses_the_residuals_least_squares_just_evaluated():
    from vhfit.calibration._polish import forward_jacobian

    M = np.array([[1.0, -2.0, 0.5], [3.0, 0.25, -1.0]])  # residuals r = M z + c
    rows = []

    def resid(Z):
        rows.append(len(Z))
        return Z @ M.T + np.array([0.3, -0.7])

    z = np.array([0.4, -1.2, 2.0])
    hi = np.array([10.0, 10.0, 2.0])  # the last one on its upper bound: a backward step
    J = forward_jacobian(resid, z, hi, [None, None])
    assert rows == [4] and np.allclose(J, M, rtol=1e-6, atol=1e-8)
    J2 = forward_jacobian(resid, z, hi, [z.copy(), resid(z[None, :])[0]])
    assert rows == [4, 1, 3] and np.array_equal(J, J2)  # no second evaluation at z
    J3 = forward_jacobian(resid, z, hi, [z + 1.0, np.zeros(2)])  # another point's: unused
    assert rows == [4, 1, 3, 4] and np.array_equal(J, J3)


def test_polishes_run_together_end_exactly_where_each_alone_ends():
    """The other basins' scouts run side by side with their residuals evaluated as one
    batch; each row is evaluated on its own, so every polish ends bit for bit where it
    ends alone (and counts the same evaluations)."""
    from vhfit.calibration._varpro import varpro_polish, varpro_polish_many

    truth = dict(mu1=0.3, alpha1=1.8, mu2=0.01, alpha2=6.0, G1=1.0, tau1=0.3)
    space = _space("ogden2", _multimode("ogden2", truth))
    b = np.asarray(space.bounds())
    Z0 = b[:, 0] + np.random.default_rng(5).random((5, len(b))) * (b[:, 1] - b[:, 0])
    together = varpro_polish_many(space, Z0, 12, tol=1e-8)
    alone = [varpro_polish(space, z, 12, tol=1e-8) for z in Z0]
    assert len(together) == 5
    for (z1, x1, e1, n1), (z2, x2, e2, n2) in zip(together, alone):
        assert np.array_equal(z1, z2) and np.array_equal(x1, x2, equal_nan=True)
        assert e1 == e2 and n1 == n2
    assert sum(np.isfinite(r[2]) for r in alone) >= 2  # polishes that went somewhere


def test_polishes_run_together_hand_an_error_of_one_to_the_caller(monkeypatch):
    from vhfit.calibration import _varpro

    truth = dict(mu1=0.3, alpha1=1.8, mu2=0.01, alpha2=6.0, G1=1.0, tau1=0.3)
    space = _space("ogden2", _multimode("ogden2", truth))
    b = np.asarray(space.bounds())
    Z0 = b[:, 0] + np.random.default_rng(5).random((3, len(b))) * (b[:, 1] - b[:, 0])
    real = _varpro.varpro_polish

    def failing(space, z0, *a, **k):
        if z0 is Z0[1] or np.array_equal(z0, Z0[1]):
            raise RuntimeError("scout 1 failed")
        return real(space, z0, *a, **k)

    monkeypatch.setattr(_varpro, "varpro_polish", failing)
    with pytest.raises(RuntimeError, match="scout 1 failed"):
        _varpro.varpro_polish_many(space, Z0, 12, tol=1e-8)
