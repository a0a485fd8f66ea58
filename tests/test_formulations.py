"""Viscoelastic formulations (docs/theory.md §14): the registry and LS-DYNA's MAT_077 law.

The reference for "lsdyna" shares nothing with vhfit's kernel: it is written from the
documented equations with full 3×3 tensors,

    σ(t) = σ_h(t) + F(t) S(t) F(t)ᵀ,
    S(t) = Σ_i 2 GI_i ∫_0^t e^(−(t−u)/τ_i) dÊ/du du,   GI_i = G_i / 3,
         = Σ_i 2 GI_i [ Ê(t) − (1/τ_i) ∫_0^t e^(−(t−u)/τ_i) Ê(u) du ]   (Ê(0) = 0),

with E = (FᵀF − I)/2 and Ê = E ("lsdyna") or dev E ("lsdyna_deviatoric"), the measured
component m(X) = X_aa − X_33 (principal tests) or X_12 (simple shear), and the lag
integral by the composite Gauss–Legendre rule of tests/test_modes.py.
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
from _budget import accuracy
from hypothesis import given
from hypothesis import strategies as st
from test_model import params_of, relative_error
from test_modes import _lag_nodes, history_of, kirchhoff_ref, measured, path_of, viscous_cases

import vhfit
from vhfit import formulations, modes
from vhfit.formulations import FORMULATIONS, Formulation, get_formulation, register_formulation
from vhfit.history import DEFORMATIONS, History
from vhfit.model import ViscoHyperelastic

LSDYNA = ("lsdyna", "lsdyna_deviatoric")


# ================================================================= reference
def green(F: np.ndarray, deviatoric: bool) -> np.ndarray:
    """E = (FᵀF − I)/2, or its deviator, for F of shape (n, 3, 3)."""
    E = 0.5 * (np.swapaxes(F, 1, 2) @ F - np.eye(3))
    if deviatoric:
        E = E - np.trace(E, axis1=1, axis2=2)[:, None, None] / 3.0 * np.eye(3)
    return E


def lsdyna_reference(law, c, G, tau, mode, direction, time, x1, x2, t_out,
                     deviatoric=False) -> np.ndarray:
    """True stress of the MAT_077 law (module docstring) at ``t_out``."""
    F_at = path_of(mode, time, x1, x2)
    out = []
    for t in map(float, t_out):
        Ft = F_at(np.array([t]))
        total = measured(mode, direction, kirchhoff_ref(law, c, Ft))[0]
        if t > 1e-12 * time[-1]:  # (below, S ~ 1e-12 of its scale: nothing to integrate)
            s, w = _lag_nodes(t, tau, time)
            Eu = green(F_at(t - s), deviatoric)
            Et = green(Ft, deviatoric)[0]
            S = np.zeros((3, 3))
            for Gi, ti in zip(G, tau):
                conv = np.einsum("n,nij->ij", w * np.exp(-s / ti), Eu) / ti
                S += 2.0 * (Gi / 3.0) * (Et - conv)
            total += measured(mode, direction, (Ft[0] @ S @ Ft[0].T)[None])[0]
        out.append(total)
    return np.array(out)


# ========================================================== against the reference
@accuracy
@given(st.sampled_from(LSDYNA), viscous_cases())
def test_lsdyna_matches_the_green_strain_quadrature(form, case):
    """Every mode, both readings, random laws, ramps and histories: ≤ 1e-6 relative."""
    mode, direction, law, c, G, tau, time, x1, x2, out = case
    s = ViscoHyperelastic(law, len(G), formulation=form).stress(
        params_of(c, G, tau), history_of(mode, time, x1, x2, out, direction))
    ref = lsdyna_reference(law, c, G, tau, mode, direction, time, x1, x2, out,
                           deviatoric=form == "lsdyna_deviatoric")
    assert relative_error(s, ref) <= 1e-6


@pytest.mark.parametrize("form", LSDYNA)
@pytest.mark.parametrize("mode", DEFORMATIONS)
def test_lsdyna_load_unload_hold_cycles_match_the_quadrature(mode, form):
    """A fixed stiff case per mode: loading, unloading past the start, hold, reload."""
    rest = 0.0 if mode == "simple_shear" else 1.0
    lo, hi = {"simple_shear": (-2.0, 2.5)}.get(mode, (0.5, 2.5))
    time = np.array([0.0, 1.0, 2.0, 3.0, 4.5])
    x1 = np.array([rest, hi, lo, lo, 0.5 * (rest + hi)])
    x2 = np.array([1.0, lo, hi, hi, 1.0]) if mode == "biaxial" else None
    out = np.linspace(0.0, 4.5, 19)
    c = (0.3, 0.1)
    G, tau = [50.0, 2.0, 0.3], [1e-3, 0.2, 5.0]
    for d in ((1, 2) if mode in ("equibiaxial", "biaxial") else (1,)):
        s = ViscoHyperelastic("mooney_rivlin", 3, formulation=form).stress(
            params_of(c, G, tau), history_of(mode, time, x1, x2, out, d))
        ref = lsdyna_reference("mooney_rivlin", c, G, tau, mode, d, time, x1, x2, out,
                               deviatoric=form == "lsdyna_deviatoric")
        assert relative_error(s, ref) <= 1e-6, d


def test_the_two_lsdyna_readings_differ_at_finite_strain():
    """Full or deviatoric E: the same small-strain law, not the same large-strain one."""
    p = params_of((0.1, 0.05), [2.0], [0.01])
    eps = np.linspace(0.0, -0.5, 6)
    full, dev = (ViscoHyperelastic("mooney_rivlin", 1, formulation=f).stress(
        p, strain=eps, strain_rate=-100.0) for f in LSDYNA)
    assert abs(full[-1] - dev[-1]) > 0.05 * abs(full[-1])


# =================================================================== limits
# the measured stress per unit uniaxial modulus at small strain and unit ε1:
# σ_a − σ_c = 2μ (ε_a − ε_c) with μ = E/3 and ε3 = −ε1 − ε2 (biaxial: ε2 = ε1/2);
# simple shear σ12 = μ γ
SMALL_STRAIN_FACTOR = {"uniaxial": 1.0, "equibiaxial": 2.0, "planar": 4.0 / 3.0,
                       "biaxial": 2.0 / 3.0 * 2.5, "simple_shear": 1.0 / 3.0}


@pytest.mark.parametrize("form", ("hereditary",) + LSDYNA)
@pytest.mark.parametrize("mode", DEFORMATIONS)
def test_small_strain_limit_is_the_prony_relaxation_modulus(mode, form):
    """E(t) = E∞ + Σ G_i e^(−t/τ_i): at rate r, σ = k (E∞ r t + Σ G_i r τ_i (1 − e^(−t/τ_i)))."""
    eps_max, T = 1e-6, 2.0
    t = np.linspace(0.0, T, 9)
    C10, C01 = 0.3, 0.2
    E_inf = 6.0 * (C10 + C01)
    G, tau = [5.0, 40.0], [0.1, 3.0]
    h = History.piecewise_linear([0.0, T], [0.0, eps_max], t, deformation=mode,
                                 strain2=[0.0, 0.5 * eps_max] if mode == "biaxial" else None)
    s = ViscoHyperelastic("mooney_rivlin", 2, formulation=form).stress(
        params_of((C10, C01), G, tau), h)
    r = eps_max / T
    ref = E_inf * r * t + sum(g * r * ti * (1.0 - np.exp(-t / ti)) for g, ti in zip(G, tau))
    ref = SMALL_STRAIN_FACTOR[mode] * ref
    assert relative_error(s, ref) <= 1e-5


@pytest.mark.parametrize("form", ("hereditary",) + LSDYNA)
@pytest.mark.parametrize("mode", DEFORMATIONS)
def test_ramp_then_hold_relaxes_to_the_long_term_stress(mode, form):
    hi = {"simple_shear": 1.5}.get(mode, 0.8)
    s2 = [0.0, 0.2, 0.2] if mode == "biaxial" else None
    h = History.piecewise_linear([0.0, 1.0, 200.0], [0.0, hi, hi], deformation=mode,
                                 strain2=s2)
    s = ViscoHyperelastic("mooney_rivlin", 2, formulation=form).stress(
        [0.2, 0.1, 5.0, 0.5, 1.0, 3.0], h)
    eq = ViscoHyperelastic("mooney_rivlin", 0, formulation=form).stress(
        [0.2, 0.1], History.equilibrium([hi], deformation=mode,
                                        strain2=[0.2] if mode == "biaxial" else None))
    assert s[-1] == pytest.approx(eq[0], rel=1e-12)
    assert abs(s[1]) > abs(eq[0]) * 1.5  # and the ramp's end was well above it


def test_lsdyna_overstress_does_not_depend_on_the_hyperelastic_constants():
    """MAT_077's viscous part is kinematic: the same Prony columns for any constants."""
    curves = [History.constant_rate(np.linspace(0, -0.5, 5), -10.0),
              History.constant_rate(np.linspace(0, 0.8, 4), 3.0, deformation="planar"),
              History.equilibrium(np.linspace(0.1, 0.5, 3), deformation="equibiaxial")]
    b = ViscoHyperelastic("mooney_rivlin", 2, formulation="lsdyna").batch(curves)
    tau = np.array([[0.01, 1.0], [0.01, 1.0]])
    base, H = b.shape_columns([[0.1, 0.05], [0.4, 0.0]], tau)
    np.testing.assert_array_equal(H[0], H[1])
    assert not np.allclose(base[0] / base[0].max(), base[1] / base[1].max())
    # and the columns rebuild the batch's stress
    X = np.array([[0.1, 0.05, 2.0, 0.01, 1.0, 1.0], [0.4, 0.0, 0.5, 0.01, 3.0, 1.0]])
    E_inf = 6.0 * X[:, :2].sum(axis=1)
    rebuilt = E_inf[:, None] * base + np.einsum("pi,pik->pk", X[:, 2::2], H)
    np.testing.assert_allclose(b(X), rebuilt, rtol=1e-12, atol=1e-14)


# ================================================================ the registry
def test_the_built_ins_and_their_names():
    assert {"hereditary", "lsdyna", "lsdyna_deviatoric"} <= set(FORMULATIONS)
    assert isinstance(FORMULATIONS["lsdyna"], Formulation)
    assert get_formulation("lsdyna") is FORMULATIONS["lsdyna"]
    m = ViscoHyperelastic("neo_hooke", 1)
    assert m.formulation == "hereditary" and "formulation" not in repr(m)
    m = ViscoHyperelastic("neo_hooke", 1, formulation="lsdyna")
    assert m.formulation == "lsdyna" and "formulation='lsdyna'" in repr(m)
    assert pickle.loads(pickle.dumps(m))._formulation is FORMULATIONS["lsdyna"]


@pytest.mark.parametrize("bad", ["abaqus", "", None, 3])
def test_unknown_formulations_are_one_line_errors(bad):
    with pytest.raises(ValueError) as err:
        ViscoHyperelastic("neo_hooke", 1, formulation=bad)
    msg = str(err.value)
    assert "\n" not in msg and "formulation" in msg and "hereditary" in msg and "lsdyna" in msg
    c = vhfit.Curve(strain=np.linspace(-0.05, -0.3, 10), stress=-np.linspace(0.1, 0.6, 10),
                    strain_rate=-1.0)
    with pytest.raises(ValueError, match=r"^formulation = .*choose one of hereditary"):
        vhfit.calibrate([c], n_prony=1, formulation=bad)


def test_register_formulation_checks_its_arguments():
    with pytest.raises(ValueError, match="must be a word"):
        register_formulation("two words")
    with pytest.raises(TypeError, match="decorates a Formulation subclass"):
        register_formulation("plain")(object)


class _GeneralHereditary(Formulation):
    """The hereditary law again, but on the general kernel in uniaxial too."""

    description = "hereditary on the general kernel"

    def factors(self, hyperelastic, params, E_inf, deformation, x1, x2=None, direction=1,
                prepared=None):
        return modes.hereditary_factors(hyperelastic, params, E_inf, deformation, x1, x2,
                                        direction)


class _Linear(Formulation):
    """A tiny kinematic law: Boltzmann superposition of the engineering strain λ1 − 1."""

    kinematic = True
    description = "small-strain superposition of λ1 − 1"

    def factors(self, hyperelastic, params, E_inf, deformation, x1, x2=None, direction=1,
                prepared=None):
        return np.asarray(x1) - 1.0, np.zeros(np.shape(x1))

    def weights(self, deformation, x1, x2=None, direction=1):
        return np.stack([np.ones(np.shape(x1)), np.zeros(np.shape(x1))])


@pytest.fixture
def registered():
    register_formulation("test_general_hereditary")(_GeneralHereditary)
    register_formulation("test_linear")(_Linear)
    yield
    del FORMULATIONS["test_general_hereditary"], FORMULATIONS["test_linear"]


def test_a_user_formulation_is_registered_and_used(registered):
    p = params_of((0.2, 0.1), [3.0, 1.0], [0.01, 1.0])
    h = History.piecewise_linear([0.0, 1.0, 2.0, 3.0], [0.0, -0.5, -0.5, 0.3],
                                 np.linspace(0.0, 3.0, 13))
    own = ViscoHyperelastic("mooney_rivlin", 2).stress(p, h)
    general = ViscoHyperelastic("mooney_rivlin", 2,
                                formulation="test_general_hereditary").stress(p, h)
    np.testing.assert_allclose(general, own, rtol=1e-9, atol=1e-12 * np.abs(own).max())
    # the linear law: σ_h + Σ G_i ∫ e^(−(t−u)/τ_i) dε/du du, a ramp-hold in closed form
    lin = ViscoHyperelastic("mooney_rivlin", 1, formulation="test_linear")
    t = np.linspace(0.0, 3.0, 7)
    s = lin.stress([0.2, 0.1, 3.0, 0.5], History.piecewise_linear([0.0, 1.0, 3.0],
                                                                    [0.0, 0.4, 0.4], t))
    sig_h = ViscoHyperelastic("mooney_rivlin", 0).stress(
        [0.2, 0.1], History.equilibrium(np.interp(t, [0.0, 1.0, 3.0], [0.0, 0.4, 0.4])))
    r, tau = 0.4, 0.5
    conv = np.where(t <= 1.0, r * tau * (1 - np.exp(-t / tau)),
                    r * tau * (1 - math.exp(-1.0 / tau)) * np.exp(-(t - 1.0) / tau))
    np.testing.assert_allclose(s, sig_h + 3.0 * conv, rtol=1e-9, atol=1e-12)


# ============================================================== calibration
@pytest.fixture(scope="module")
def lsdyna_curves():
    """Two rates of compression made with the MAT_077 law, one Prony term."""
    true = dict(C10=0.05, C01=0.02, G1=1.0, tau1=0.01)
    m = ViscoHyperelastic("mooney_rivlin", 1, formulation="lsdyna")
    eps = np.linspace(-0.05, -0.6, 10)
    return [vhfit.Curve(strain=eps, stress=m.stress(true, strain=eps, strain_rate=r,
                                                    measure="engineering"), strain_rate=r)
            for r in (-1.0, -100.0)]


def test_calibrate_fits_in_the_chosen_formulation(lsdyna_curves):
    """Data made with the MAT_077 law: an "lsdyna" fit finds them, the model says so;
    a "hereditary" fit cannot (the two laws differ at 60 % compression)."""
    cal = vhfit.calibrate(lsdyna_curves, n_prony=1, seed=0, formulation="lsdyna",
                          uncertainty=False)
    assert cal.model.formulation == "lsdyna"
    assert cal.rmsape < 1e-3
    assert formulations.get_formulation(cal.model.formulation).kinematic
    other = vhfit.calibrate(lsdyna_curves, n_prony=1, seed=0, uncertainty=False)
    assert other.model.formulation == "hereditary" and other.rmsape > 0.1


def test_pruned_terms_keep_the_formulation(lsdyna_curves):
    cal = vhfit.calibrate(lsdyna_curves, n_prony=3, seed=0, formulation="lsdyna",
                          uncertainty=False)
    assert cal.model.n_prony < 3 and cal.model.formulation == "lsdyna"


def test_resume_refuses_a_checkpoint_of_another_formulation(lsdyna_curves, tmp_path):
    ck = tmp_path / "ck.json"
    opts = dict(n_prony=1, seed=0, checkpoint=ck, uncertainty=False, maxiter=3, polish=False,
                bounds={"C10": (0, 1), "C01": (0, 1), "G1": (0, 10), "tau1": (1e-3, 1)})
    vhfit.calibrate(lsdyna_curves, formulation="lsdyna", **opts)
    vhfit.calibrate(lsdyna_curves, formulation="lsdyna", resume=True, **opts)  # its own: fine
    # "lsdyna_deviatoric" has the same arrays and bounds: only the formulation differs
    for other in ("hereditary", "lsdyna_deviatoric"):
        with pytest.raises(ValueError, match="different fit"):
            vhfit.calibrate(lsdyna_curves, formulation=other, resume=True, **opts)
