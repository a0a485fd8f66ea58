"""Tests of the minimize plugin: scipy.optimize.minimize(..., method=vhfit.optimize.de)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from numpy.testing import assert_array_equal
from scipy.optimize import Bounds, OptimizeResult, OptimizeWarning, minimize, rosen

from vhfit.optimize import MaxGenerations, de, differential_evolution

B = [(0.0, 2.0), (0.0, 2.0), (0.0, 2.0)]


def test_minimize_runs_our_de_and_returns_its_result():
    x0 = [0.5, 0.5, 0.5]
    opts = {"rng": 3, "maxiter": 40, "polish": False, "strategy": "rand1bin"}
    res = minimize(rosen, x0, method=de, bounds=B, options=opts)
    ref = differential_evolution(rosen, B, x0=x0, **opts)
    assert isinstance(res, OptimizeResult)
    assert_array_equal(res.x, ref.x)
    assert res.fun == ref.fun and res.nfev == ref.nfev and res.nit == ref.nit


def test_minimize_with_extras_and_bounds_object():
    res = minimize(rosen, np.ones(3) * 0.2, method=de, bounds=Bounds([0] * 3, [2] * 3),
                   options={"rng": 0, "strategy": "shade", "population_size": 20,
                            "stop": MaxGenerations(25), "history": True, "maxiter": 100})
    assert res.stop_reason == "MaxGenerations" and len(res.history) == 26
    assert res.population.shape == (20, 3)


def test_minimize_tol_and_args_pass_through():
    def f(x, a):
        return float(np.sum((x - a) ** 2))

    res = minimize(f, [1.0, 1.0], args=(0.25,), method=de, bounds=[(0, 2), (0, 2)],
                   tol=1e-8, options={"rng": 1})
    assert res.success and np.allclose(res.x, 0.25, atol=1e-6)


def test_minimize_callbacks_both_styles():
    seen_x, seen_r = [], []

    def cb_x(xk):
        seen_x.append(np.array(xk))

    def cb_r(intermediate_result):
        seen_r.append(intermediate_result.nit)
        return intermediate_result.nit >= 3

    minimize(rosen, [1, 1, 1], method=de, bounds=B, callback=cb_x,
             options={"rng": 0, "maxiter": 4, "polish": False})
    assert len(seen_x) == 4 and all(x.shape == (3,) for x in seen_x)
    res = minimize(rosen, [1, 1, 1], method=de, bounds=B, callback=cb_r,
                   options={"rng": 0, "polish": False})
    assert seen_r == [1, 2, 3] and res.message == "callback function requested stop early"


def test_minimize_needs_bounds_and_rejects_bad_options():
    with pytest.raises(ValueError, match="bounds"):
        minimize(rosen, [1, 1], method=de)
    with pytest.raises(TypeError):
        minimize(rosen, [1, 1], method=de, bounds=B[:2], options={"no_such_option": 1})
    with pytest.raises(ValueError, match="x0"):
        minimize(rosen, [1, 1], method=de, bounds=B)


def test_minimize_clips_x0_and_ignores_jac_with_warnings():
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        res = minimize(rosen, [5.0, 1.0, 1.0], method=de, bounds=B, jac=lambda x: x,
                       options={"rng": 0, "maxiter": 3, "polish": False})
    kinds = {type(x.message) for x in w}
    assert OptimizeWarning in kinds and RuntimeWarning in kinds
    assert np.all((res.x >= 0) & (res.x <= 2))
