"""Constants that end on a bound no widening moves are named (issue: bounds named).

A relaxation time or a modulus on a bound the user gave, and a relaxation time on an end
of the automatic τ range, each get one WARNING line naming the constant, the bound and a
wider interval to try; an optimum inside its bounds gets none.
"""

from __future__ import annotations

import warnings

import numpy as np

import vhfit


def _curves(tau1=2.0):
    """Loading-unloading of a neo-Hooke material with one Prony term (τ1 = ``tau1``)."""
    m = vhfit.ViscoHyperelastic("neo_hooke", 1)
    out = []
    for r in (0.05, 0.5):
        tmax = 1.0 / r
        t = np.linspace(0.0, 2 * tmax, 41)
        e = 1.0 - np.abs(t - tmax) * r
        s = m.stress(dict(C10=0.1, G1=0.3, tau1=tau1), strain=e, time=t,
                     measure="engineering")
        out.append(vhfit.Curve(strain=e[1:-1], stress=s[1:-1], time=t[1:-1],
                               measure="engineering"))
    return out


def _fit(**kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return vhfit.calibrate(_curves(), hyperelastic="neo_hooke", n_prony=1, seed=0, **kw)


def _pinned(cal, name):
    return [w for w in cal.summary().splitlines()
            if "WARNING" in w and f"{name} = " in w and "search bound" in w]


def test_a_user_bound_that_binds_tau_is_named_with_the_bound_and_a_wider_interval():
    cal = _fit(bounds={"tau1": (0.1, 0.5)})  # the material's τ1 is 2
    assert abs(cal.params["tau1"] - 0.5) < 1e-3 * 0.5
    [line] = _pinned(cal, "tau1")
    assert "tau1 <= 0.5" in line and "given in bounds=" in line
    assert "--bounds tau1=0.1:" in line


def test_a_user_bound_that_binds_a_modulus_is_named():
    cal = _fit(bounds={"G1": (0.0, 0.1)})  # the material's G1 is 0.3
    assert cal.params["G1"] <= 0.1 * (1 + 1e-9)
    [line] = _pinned(cal, "G1")
    assert "G1 <= 0.1" in line


def test_an_interior_optimum_names_no_bound():
    cal = _fit(bounds={"tau1": (0.1, 50.0)})
    assert abs(cal.params["tau1"] - 2.0) < 0.02
    assert cal.rmsape < 0.1
    assert _pinned(cal, "tau1") == [] and _pinned(cal, "G1") == []
