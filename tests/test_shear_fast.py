"""Simple shear on the compiled path: the law's closed form, the frame kept per plan, the
factors in one compiled pass — checked against references written here.

* the stress of a one-term Ogden law in a simple-shear ramp and hold, against the
  hereditary integral of docs/theory.md §13 by adaptive quadrature, with the principal
  Kirchhoff stresses rotated by an eigen-decomposition of B = F Fᵀ;
* a fit on the new path (closed form) against the same fit with the law's complex step
  (a user law written without one), equal errors to 1e-10 relative;
* the compiled factors against the formula of docs/theory.md §13 written here.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.integrate import quad

import vhfit
from vhfit import _kernels, hyperelastic
from vhfit._kirchhoff import shear_frame
from vhfit.calibration import CalibrationWarning

MU, ALPHA = 0.2, 2.5
PRONY = dict(G1=0.4, tau1=0.5, G2=0.2, tau2=5.0)
RATE, TOP, END = 0.2, 0.8, 12.0  # γ̇, γ at the end of the ramp, end of the hold (s)


def gamma_of(t):
    return np.minimum(RATE * t, TOP)


def dev_tau(g: float) -> np.ndarray:
    """dev τ of the one-term Ogden law at amount of shear g: τ = Σ_k τ_k n_k n_kᵀ over the
    eigenvectors of B = F Fᵀ, τ_k = (2μ/α) λ_k^α (3 × 3)."""
    F = np.eye(3)
    F[0, 1] = g
    w, n = np.linalg.eigh(F @ F.T)
    tau = (n * (2.0 * MU / ALPHA * w ** (ALPHA / 2.0))) @ n.T
    return tau - np.trace(tau) / 3.0 * np.eye(3)


def sigma12(g: float) -> float:
    return float(dev_tau(g)[0, 1])  # the pressure leaves the shear component alone


def reference(t: float) -> float:
    """σ12(t) = σ_h(t) + Σ_i G_i h_i(t), h_i of docs/theory.md §13 by quadrature."""
    E = 3.0 * MU  # E∞ = 3 μ0, μ0 = μ of a one-term Ogden law
    gt = float(gamma_of(t))
    s_t = sigma12(gt) / E

    def K(u):
        S = dev_tau(float(gamma_of(u)))
        return (S[0, 1] + (gt - float(gamma_of(u))) * S[1, 1]) / E

    out = sigma12(gt)
    for i in (1, 2):
        G, tau = PRONY[f"G{i}"], PRONY[f"tau{i}"]
        pts = [TOP / RATE] if t > TOP / RATE else None
        integral, _ = quad(lambda u, tau=tau: np.exp(-(t - u) / tau) * (s_t - K(u)), 0.0, t,
                           points=pts, epsabs=1e-14, epsrel=1e-12, limit=200)
        out += G * (s_t * np.exp(-t / tau) + integral / tau)
    return out


def test_ogden_shear_stress_matches_the_hereditary_integral_by_quadrature():
    t = np.linspace(0.0, END, 49)
    model = vhfit.ViscoHyperelastic("ogden", 2)
    got = model.stress(dict(mu1=MU, alpha1=ALPHA, **PRONY), strain=gamma_of(t), time=t,
                       deformation="simple_shear")
    want = np.array([reference(x) for x in t])
    # the model's rtol (1e-6) bounds its time stepping, which on this smooth history is
    # far better (5e-14 measured); the quadrature is exact to 1e-12; the Prony part is a
    # quarter of the stress, so a wrong overstress or long-term term is far outside
    assert np.max(np.abs(got - want)) <= 1e-8 * np.max(np.abs(want))


def _complex_step_ogden(l1, l2, l3, mu1, alpha1):
    """The one-term Ogden energy, written here, registered with no closed form."""
    return 2 * mu1 / alpha1**2 * (l1**alpha1 + l2**alpha1 + l3**alpha1 - 3)


@pytest.fixture
def complex_step_law():
    name = "_test_ogden_complex_step"
    hyperelastic.register(name, units=("MPa", "1"), example=(0.1, 2.0),
                          mu0=lambda mu1, a1: mu1, linear_params=("mu1",),
                          overwrite=True)(_complex_step_ogden)
    yield name
    hyperelastic.unregister(name)


def _shear_curves():
    model = vhfit.ViscoHyperelastic("ogden", 2)
    rng = np.random.default_rng(5)
    out = []
    for rate in (0.05, 0.5):
        t = np.concatenate([np.linspace(0, TOP / rate, 30), TOP / rate + np.linspace(
            0.2, 10.0, 30)])
        g = np.minimum(rate * t, TOP)
        s = model.stress(dict(mu1=MU, alpha1=ALPHA, **PRONY), strain=g, time=t,
                         deformation="simple_shear")
        out.append(vhfit.Curve(strain=g, stress=s * (1 + 0.01 * rng.standard_normal(t.size)),
                               time=t, deformation="simple_shear"))
    return out


def test_a_shear_fit_by_the_closed_form_has_the_complex_steps_error(complex_step_law):
    curves = _shear_curves()
    fits = {}
    for law in ("ogden", complex_step_law):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", CalibrationWarning)
            fits[law] = vhfit.calibrate(curves, hyperelastic=law, n_prony=2, seed=0,
                                        uncertainty=False)
    new, old = fits["ogden"], fits[complex_step_law]
    assert new.rmsape == pytest.approx(old.rmsape, rel=1e-10)
    assert 0.5 < new.rmsape < 2.0  # 1 % noise: the fit reached it, no better or worse


def test_the_one_term_ogden_law_has_a_closed_form_on_every_path():
    og = hyperelastic.get("ogden")
    lam = np.array([0.7, 1.3, 2.0])
    for f in (og.derivatives, og.kirchhoff_derivatives):
        got = f(lam, 1 / lam, np.ones(3), np.array([[MU]]), np.array([[ALPHA]]))
        for k, x in enumerate((lam, 1 / lam, np.ones(3))):
            np.testing.assert_allclose(got[k][0], 2 * MU / ALPHA * x**ALPHA, rtol=1e-14)
    # its uniaxial stress, 2μ/α (λ^α − λ^(−α/2)), on the closed form
    want = 2 * MU / ALPHA * (lam**ALPHA - lam ** (-ALPHA / 2))
    np.testing.assert_allclose(og.stress(lam, [MU, ALPHA]), want, rtol=1e-13)


def test_a_laws_general_derivatives_serve_every_test_but_uniaxial():
    # a stretch law with a closed form for the tests off the uniaxial path only: its
    # uniaxial stress by the complex step, the others by the closed form given
    calls = []

    def closed(l1, l2, l3, mu1, alpha1):
        calls.append(1)
        return tuple(2 * mu1 / alpha1 * x**alpha1 for x in (l1, l2, l3))

    name = "_test_general_only"
    hyperelastic.register(name, units=("MPa", "1"), example=(0.1, 2.0),
                          mu0=lambda mu1, a1: mu1, linear_params=("mu1",),
                          general_derivatives=closed, overwrite=True)(_complex_step_ogden)
    try:
        law = hyperelastic.get(name)
        assert law.derivatives is None and law.kirchhoff_derivatives is closed
        lam = np.array([0.7, 1.3, 2.0])
        want = 2 * MU / ALPHA * (lam**ALPHA - lam ** (-ALPHA / 2))
        np.testing.assert_allclose(law.stress(lam, [MU, ALPHA]), want, rtol=1e-12)
        assert not calls  # the uniaxial stress did not use it
    finally:
        hyperelastic.unregister(name)


def test_general_derivatives_are_refused_for_an_invariant_law():
    with pytest.raises(ValueError, match="general_derivatives"):
        hyperelastic.register("_test_bad_general", general_derivatives=lambda *a: a,
                              overwrite=True)(lambda I1, I2, C10: C10 * (I1 - 3))


def test_compiled_shear_factors_follow_the_formula():
    rng = np.random.default_rng(2)
    g = np.linspace(-1.5, 2.0, 11)
    lam = g / 2 + np.sqrt(1 + g * g / 4)
    ta, tb, t3 = rng.uniform(-1, 1, (3, 4, g.size))
    E = rng.uniform(0.5, 2.0, (4, 1))
    f0, f1 = _kernels.shear_factors(ta, tb, t3, g, lam, lam**2, 1 / (1 + lam**2), E)
    # docs/theory.md §13: rotate into the (1, 2) frame, S = dev τ, f = (S12 − γ S22, S22)/E∞
    c2, s2 = lam**2 / (1 + lam**2), 1 / (1 + lam**2)
    t11, t22 = c2 * ta + s2 * tb, s2 * ta + c2 * tb
    t12 = (ta - tb) / np.sqrt(4 + g * g)
    s22 = t22 - (t11 + t22 + t3) / 3
    np.testing.assert_allclose(f0, (t12 - g * s22) / E, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(f1, s22 / E, rtol=1e-13, atol=1e-15)
    # another layout is the caller's (numpy) business
    assert _kernels.shear_factors(ta[0], tb[0], t3[0], g, lam, lam**2, lam, E[:1, 0]) is None


def test_a_plans_shear_frame_is_computed_once():
    model = vhfit.ViscoHyperelastic("ogden", 2)
    batch = model.batch(_shear_curves())
    x1 = batch._general.x1
    assert not x1.flags.writeable
    assert shear_frame(x1) is shear_frame(x1)
    fresh = np.array(x1)  # a writeable array is never remembered
    assert shear_frame(fresh)[0] is not shear_frame(fresh)[0]


def test_kept_stretches_are_each_tests_own():
    x = np.array([0.8, 1.2, 2.0])
    x.flags.writeable = False  # kept for this array: each test keeps its own
    from vhfit import modes

    eb = modes.principal_stretches("equibiaxial", x)
    pl = modes.principal_stretches("planar", x)
    np.testing.assert_array_equal(eb[2], x**-2.0)
    np.testing.assert_array_equal(pl[2], 1.0 / x)
    assert modes.principal_stretches("planar", x)[2] is pl[2]
