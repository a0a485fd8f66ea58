"""Every homogeneous test (docs/theory.md §13): kinematics, long-term stresses, viscosity.

The references below share nothing with vhfit's code: closed forms of the long-term
stresses written by hand, and for viscous histories a composite Gauss–Legendre
quadrature of the hereditary integral written from the tensor formula,

    σ_m(t) = σ_h,m(t) + Σ_i G_i h_i(t),
    h_i(t) = ŝ(t) e^(−t/τ_i) + (1/τ_i) ∫_0^t e^(−(t−u)/τ_i) [ŝ(t) − m(F_t τᴰ(u) F_tᵀ)/E∞] du,

with full 3×3 tensors: F(u) of the test, τ(u) = 2(W1 + I1 W2) B − 2 W2 B² (invariant
laws) or Σ_p (2μ_p/α_p) B^(α_p/2) (Ogden, by an eigen-decomposition of B), its
deviator τᴰ, the relative deformation gradient F_t = F(t) F(u)⁻¹, and the measured
component m(X) = X_aa − X_33 (principal tests) or X_12 (simple shear).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _budget import accuracy
from hypothesis import given
from hypothesis import strategies as st
from test_model import params_of, relative_error

from vhfit import _kernels, hyperelastic, modes
from vhfit.history import DEFORMATIONS, History
from vhfit.model import ViscoHyperelastic

PRINCIPAL = ("uniaxial", "equibiaxial", "planar", "biaxial")
# stretch ranges of the random tests (λ1; λ2 for biaxial; γ in simple shear)
RANGE = {"uniaxial": (0.3, 4.0), "equibiaxial": (0.5, 3.0), "planar": (0.4, 3.5),
         "biaxial": (0.5, 2.5), "simple_shear": (-3.0, 3.0)}


# ================================================================= references
def F_of(mode: str, x1, x2=None) -> np.ndarray:
    """Deformation gradients (n, 3, 3) of a test at λ1 = x1 (γ in simple shear), λ2 = x2."""
    x1 = np.atleast_1d(np.asarray(x1, dtype=np.float64))
    F = np.zeros((x1.size, 3, 3))
    if mode == "simple_shear":
        F[:, 0, 0] = F[:, 1, 1] = F[:, 2, 2] = 1.0
        F[:, 0, 1] = x1
        return F
    l2 = {"uniaxial": x1**-0.5, "equibiaxial": x1, "planar": np.ones_like(x1),
          "biaxial": np.atleast_1d(np.asarray(x2, dtype=np.float64))}[mode]
    l3 = {"uniaxial": x1**-0.5}.get(mode, 1.0 / (x1 * l2))
    F[:, 0, 0], F[:, 1, 1], F[:, 2, 2] = x1, l2, l3
    return F


def kirchhoff_ref(law: str, c, F: np.ndarray) -> np.ndarray:
    """Kirchhoff stress (n, 3, 3) of the law, up to a pressure."""
    B = F @ np.swapaxes(F, 1, 2)
    eye = np.eye(3)
    if law.startswith("ogden"):
        w, V = np.linalg.eigh(B)
        out = np.zeros_like(B)
        for mu, a in zip(c[0::2], c[1::2]):
            out += 2 * mu / a * np.einsum("nij,nj,nkj->nik", V, w ** (a / 2), V)
        return out
    I1 = np.trace(B, axis1=1, axis2=2)
    if law == "mooney_rivlin":
        W1, W2 = np.full_like(I1, c[0]), np.full_like(I1, c[1])
    elif law == "neo_hooke":
        W1, W2 = np.full_like(I1, c[0]), np.zeros_like(I1)
    elif law == "yeoh":
        x = I1 - 3
        W1, W2 = c[0] + 2 * c[1] * x + 3 * c[2] * x * x, np.zeros_like(I1)
    else:
        raise KeyError(law)
    return (2 * (W1 + I1 * W2))[:, None, None] * B - (2 * W2)[:, None, None] * (B @ B) + 0 * eye


def E_inf_ref(law: str, c) -> float:
    if law == "mooney_rivlin":
        return 6 * (c[0] + c[1])
    if law in ("neo_hooke", "yeoh"):
        return 6 * c[0]
    return 3 * sum(c[0::2])


def measured(mode: str, direction: int, X: np.ndarray) -> np.ndarray:
    if mode == "simple_shear":
        return X[:, 0, 1]
    return X[:, direction - 1, direction - 1] - X[:, 2, 2]


def deviator(X: np.ndarray) -> np.ndarray:
    return X - np.trace(X, axis1=1, axis2=2)[:, None, None] / 3 * np.eye(3)


_GL_X, _GL_W = np.polynomial.legendre.leggauss(20)


def _lag_nodes(t: float, taus, breaks) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights in the lag s = t − u over [0, t]: cut at the
    path's kinks, graded geometrically near s = 0 for each τ, panels ≤ t/32."""
    cuts = {0.0, t} | {t - b for b in breaks if 0 < b < t}
    for tau in taus:
        cuts |= {tau * 2.0**k for k in range(-6, 90) if tau * 2.0**k < t}
    cuts = np.array(sorted(cuts))
    s, w = [], []
    for a, b in zip(cuts[:-1], cuts[1:]):
        m = int(math.ceil((b - a) / (t / 32)))
        edges = np.linspace(a, b, m + 1)
        for lo, hi in zip(edges[:-1], edges[1:]):
            s.append(0.5 * (hi - lo) * _GL_X + 0.5 * (hi + lo))
            w.append(0.5 * (hi - lo) * _GL_W)
    return np.concatenate(s), np.concatenate(w)


def path_of(mode, time, x1, x2):
    """u -> F(u) (n, 3, 3) along the piecewise-linear path through (time, x1, x2)."""
    def F_at(u):
        return F_of(mode, np.interp(u, time, x1),
                    None if x2 is None else np.interp(u, time, x2))
    return F_at


def reference_stress(law, c, G, tau, mode, direction, time, x1, x2, t_out) -> np.ndarray:
    """True stress of the tensor hereditary integral (module docstring) at ``t_out``."""
    E = E_inf_ref(law, c)
    F_at = path_of(mode, time, x1, x2)
    out = []
    for t in map(float, t_out):
        Ft = F_at(np.array([t]))
        sig_h = measured(mode, direction, kirchhoff_ref(law, c, Ft))[0]
        total = sig_h
        if t > 0:
            s, w = _lag_nodes(t, tau, time)
            Fu = F_at(t - s)
            Frel = Ft @ np.linalg.inv(Fu)
            X = Frel @ deviator(kirchhoff_ref(law, c, Fu)) @ np.swapaxes(Frel, 1, 2)
            gap = sig_h / E - measured(mode, direction, X) / E
        for Gi, ti in zip(G, tau):
            h = sig_h / E * math.exp(-t / ti)
            if t > 0:
                h += np.sum(w * np.exp(-s / ti) * gap) / ti
            total += Gi * h
        out.append(total)
    return np.array(out)


# ================================================================= strategies
@st.composite
def laws(draw, names=("mooney_rivlin", "ogden", "ogden2", "yeoh")):
    """A law and its constants: stable enough to be a material, drawn directly."""
    law = draw(st.sampled_from(names))
    if law == "mooney_rivlin":
        total = 10 ** draw(st.floats(-3.0, 0.3))
        k = draw(st.floats(0.0, 1.0))
        return law, ((1 - k) * total, k * total)
    if law == "yeoh":
        C10 = draw(st.floats(0.01, 1.0))
        return law, (C10, C10 * draw(st.floats(-0.05, 0.5)), C10 * draw(st.floats(0.0, 0.1)))
    terms = 1 if law == "ogden" else 2
    c = []
    for _ in range(terms):
        c += [draw(st.floats(0.01, 1.0)),
              draw(st.one_of(st.floats(-6.0, -0.5), st.floats(0.5, 8.0)))]
    return law, tuple(c)


@st.composite
def paths(draw, mode):
    """Breakpoints (time, x1, x2) of a ramp or a measured history, and output times."""
    lo, hi = RANGE[mode]
    rest = 0.0 if mode == "simple_shear" else 1.0
    k = draw(st.integers(2, 4))
    T_scale = 10 ** draw(st.floats(-4.0, 4.0))
    time = np.concatenate([[0.0], np.cumsum(draw(st.lists(st.floats(0.1, 1.0), min_size=k - 1,
                                                          max_size=k - 1)))]) * T_scale
    x1, x2 = [rest], [1.0]
    for j in range(k - 1):
        hold = j > 0 and draw(st.booleans())
        x1.append(x1[-1] if hold else draw(st.floats(lo, hi)))
        x2.append(x2[-1] if hold else draw(st.floats(lo, hi)))
        if j == 0 and abs(x1[1] - rest) < 0.05:  # the first piece loads by >= 5 %
            x1[1] = rest + 0.05 if x1[1] >= rest else rest - 0.05
    frac = draw(st.lists(st.floats(0.0, 1.0), min_size=2, max_size=5))
    out = np.unique(np.concatenate([np.asarray(frac) * time[-1], time[1:]]))
    return time, np.array(x1), (np.array(x2) if mode == "biaxial" else None), out


def history_of(mode, time, x1, x2, out, direction=1) -> History:
    strain = x1 if mode == "simple_shear" else x1 - 1.0
    h = History.piecewise_linear(time, strain, out, deformation=mode,
                                 strain2=None if x2 is None else x2 - 1.0)
    return h.with_outputs(out, np.full(out.size, direction))


# ========================================================== kinematics
@accuracy
@given(st.sampled_from(DEFORMATIONS), st.floats(0.05, 20.0), st.floats(0.05, 20.0),
       st.floats(-20.0, 20.0))
def test_every_test_is_incompressible(mode, lam, lam2, gamma):
    x1 = gamma if mode == "simple_shear" else lam
    l1, l2, l3 = modes.principal_stretches(mode, x1, lam2)
    assert l1 * l2 * l3 == pytest.approx(1.0, rel=4e-16 * 8)
    F = F_of(mode, x1, lam2)[0]
    assert np.linalg.det(F) == pytest.approx(1.0, rel=1e-12)
    # the principal stretches are the square roots of the eigenvalues of B = F Fᵀ
    eig = np.sort(np.linalg.eigvalsh(F @ F.T))
    np.testing.assert_allclose(np.sort(np.array([l1, l2, l3]) ** 2), eig, rtol=1e-9)


def test_simple_shear_principal_stretch_is_the_closed_form():
    for g in (-5.0, -0.3, 1e-9, 0.7, 40.0):
        lam = modes.principal_stretches("simple_shear", g)[0]
        assert lam == pytest.approx(g / 2 + math.sqrt(1 + g * g / 4), rel=1e-12)


# ==================================================== long-term closed forms
@accuracy
@given(st.floats(-3.0, 0.3), st.floats(0.0, 1.0), st.floats(0.3, 4.0), st.floats(0.3, 4.0),
       st.floats(-4.0, 4.0))
def test_mooney_rivlin_equilibrium_closed_forms(log_total, kappa, lam, lam2, gamma):
    """Equibiaxial 2(λ² − λ⁻⁴)(C10 + C01 λ²), planar 2(λ² − λ⁻²)(C10 + C01), biaxial
    σ_a = 2(λ_a² − λ3²)(C10 + C01 λ_b²), simple shear σ12 = 2(C10 + C01) γ; nominal = σ/λ."""
    C10, C01 = (1 - kappa) * 10**log_total, kappa * 10**log_total
    m = ViscoHyperelastic("mooney_rivlin", 0)
    p = [C10, C01]
    l3 = 1 / (lam * lam2)
    cases = [
        (dict(deformation="equibiaxial"), 2 * (lam**2 - lam**-4) * (C10 + C01 * lam**2)),
        (dict(deformation="planar"), 2 * (lam**2 - lam**-2) * (C10 + C01)),
        (dict(deformation="biaxial", stretch2=[lam2]),
         2 * (lam**2 - l3**2) * (C10 + C01 * lam2**2)),
        (dict(deformation="biaxial", stretch2=[lam2], direction=2),
         2 * (lam2**2 - l3**2) * (C10 + C01 * lam**2)),
    ]
    scale = 2 * (C10 + C01) * (lam**2 + lam**-4 + lam2**2 + l3**2) + 1e-300
    for kw, want in cases:
        s = m.stress(p, stretch=[lam], **kw)[0]
        assert abs(s - want) <= 1e-13 * scale, kw
        a = lam2 if kw.get("direction") == 2 else lam
        e = m.stress(p, stretch=[lam], measure="engineering", **kw)[0]
        assert abs(e - want / a) <= 1e-13 * scale / a, kw
    s = m.stress(p, strain=[gamma], deformation="simple_shear")[0]
    assert s == pytest.approx(2 * (C10 + C01) * gamma, rel=1e-13, abs=1e-300)
    # the normal stresses of simple shear: N1 = 2(C10 + C01) γ², σ22 − σ33 = −2 C01 γ²
    t11, t22, t33, t12 = modes.shear_kirchhoff_stress(hyperelastic.get("mooney_rivlin"), p,
                                                      gamma)
    assert float(t11[0] - t22[0]) == pytest.approx(2 * (C10 + C01) * gamma**2, rel=1e-12,
                                                   abs=1e-14)
    assert float(t22[0] - t33[0]) == pytest.approx(-2 * C01 * gamma**2, rel=1e-12, abs=1e-14)


@accuracy
@given(st.floats(0.01, 1.0), st.one_of(st.floats(-6.0, -0.5), st.floats(0.5, 8.0)),
       st.floats(0.5, 2.5), st.floats(-3.0, 3.0))
def test_ogden_equilibrium_closed_forms(mu, alpha, lam, gamma):
    """Equibiaxial Σ 2μ/α (λ^α − λ^(−2α)), planar 2μ/α (λ^α − λ^(−α)), simple shear
    2μ/α (Λ^α − Λ^(−α)) / (Λ + 1/Λ) with Λ = γ/2 + sqrt(1 + γ²/4)."""
    m = ViscoHyperelastic("ogden", 0)
    k = 2 * mu / alpha
    eq = m.stress([mu, alpha], stretch=[lam], deformation="equibiaxial")[0]
    assert eq == pytest.approx(k * (lam**alpha - lam ** (-2 * alpha)), rel=1e-9, abs=1e-12)
    pl = m.stress([mu, alpha], stretch=[lam], deformation="planar")[0]
    assert pl == pytest.approx(k * (lam**alpha - lam**-alpha), rel=1e-9, abs=1e-12)
    L = gamma / 2 + math.sqrt(1 + gamma**2 / 4)
    sh = m.stress([mu, alpha], strain=[gamma], deformation="simple_shear")[0]
    assert sh == pytest.approx(k * (L**alpha - L**-alpha) / (L + 1 / L), rel=1e-9, abs=1e-12)


@accuracy
@given(laws(("mooney_rivlin", "yeoh", "ogden", "ogden2", "polynomial2")), st.floats(-3.0, 3.0))
def test_simple_shear_obeys_rivlins_universal_relation(law_c, gamma):
    """σ11 − σ22 = γ σ12 for any isotropic law (the pressure cancels)."""
    law, c = law_c
    if law == "polynomial2":
        c = (0.1, 0.05, 0.01, 0.002, 0.003)
    t11, t22, _, t12 = modes.shear_kirchhoff_stress(hyperelastic.get(law), c, gamma)
    scale = abs(float(t11[0])) + abs(float(t22[0])) + abs(gamma * float(t12[0])) + 1e-300
    assert abs(float(t11[0] - t22[0]) - gamma * float(t12[0])) <= 1e-12 * scale


@accuracy
@given(laws(), st.sampled_from(DEFORMATIONS), st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_long_term_stress_matches_the_tensor_reference(law_c, mode, a, b):
    """Every mode and direction against τ of the full 3×3 reference (no closed form)."""
    law, c = law_c
    lo, hi = RANGE[mode]
    x1, x2 = lo + a * (hi - lo), lo + b * (hi - lo)
    X = kirchhoff_ref(law, c, F_of(mode, x1, x2))
    for d in ((1, 2) if mode in ("equibiaxial", "biaxial") else (1,)):
        want = measured(mode, d, X)[0]
        got = modes.long_term_stress(hyperelastic.get(law), c, mode, [x1],
                                     [x2] if mode == "biaxial" else None, d)[0]
        scale = np.abs(X).max()
        assert abs(got - want) <= 1e-10 * scale, (mode, d)
    principal = modes.kirchhoff_stress(hyperelastic.get(law), c,
                                       *modes.principal_stretches(mode, x1, x2))
    if mode != "simple_shear":  # principal axes are the lab axes: differences agree
        got = [float(np.ravel(t)[0]) for t in principal]
        assert got[0] - got[2] == pytest.approx(X[0, 0, 0] - X[0, 2, 2], rel=1e-9,
                                                abs=1e-10 * np.abs(X).max())


def test_equibiaxial_directions_give_the_same_stress():
    m = ViscoHyperelastic("ogden2", 2)
    p = [0.4, 3.0, 0.05, -2.0, 5.0, 0.01, 1.0, 1.0]
    t = [0.0, 1.0, 2.0, 4.0]
    e = [0.0, 0.8, 0.3, 0.3]
    one = m.stress(p, strain=e, time=t, deformation="equibiaxial")
    two = m.stress(p, strain=e, time=t, deformation="equibiaxial", direction=2)
    np.testing.assert_array_equal(one, two)


# ================================================== viscosity vs quadrature
@st.composite
def viscous_cases(draw):
    """(mode, direction, law, c, G, tau, time, x1, x2, out): a random viscous history,
    1–3 Prony terms with G_i/E∞ from 1e-2 to 1e3 and τ_i/T from 1e-6 to 1e6."""
    mode = draw(st.sampled_from(DEFORMATIONS))
    direction = draw(st.sampled_from((1, 2))) if mode in ("equibiaxial", "biaxial") else 1
    law, c = draw(laws())
    time, x1, x2, out = draw(paths(mode))
    n = draw(st.integers(1, 3))
    E = E_inf_ref(law, c)
    G = [E * 10 ** draw(st.floats(-2.0, 3.0)) for _ in range(n)]
    tau = [time[-1] * 10 ** draw(st.floats(-6.0, 6.0)) for _ in range(n)]
    return mode, direction, law, c, G, tau, time, x1, x2, out


@accuracy
@given(viscous_cases())
def test_viscous_histories_match_the_tensor_quadrature(case):
    """Every mode, random laws, ramps and piecewise-linear histories: ≤ 1e-6 relative."""
    mode, direction, law, c, G, tau, time, x1, x2, out = case
    s = ViscoHyperelastic(law, len(G)).stress(params_of(c, G, tau),
                                              history_of(mode, time, x1, x2, out, direction))
    ref = reference_stress(law, c, G, tau, mode, direction, time, x1, x2, out)
    assert relative_error(s, ref) <= 1e-6


@pytest.mark.parametrize("mode", DEFORMATIONS)
def test_load_unload_hold_cycles_match_the_tensor_quadrature(mode):
    """A fixed stiff case per mode: loading, unloading past the start, hold, reload."""
    lo, hi = RANGE[mode]
    rest = 0.0 if mode == "simple_shear" else 1.0
    time = np.array([0.0, 1.0, 2.0, 3.0, 4.5])
    x1 = np.array([rest, hi, lo, lo, 0.5 * (rest + hi)])
    x2 = np.array([1.0, lo, hi, hi, 1.0]) if mode == "biaxial" else None
    out = np.linspace(0.0, 4.5, 19)
    c = (0.3, 4.0, 0.02, -3.0)
    G, tau = [50.0, 2.0, 0.3], [1e-3, 0.2, 5.0]
    for d in ((1, 2) if mode in ("equibiaxial", "biaxial") else (1,)):
        s = ViscoHyperelastic("ogden2", 3).stress(params_of(c, G, tau),
                                                  history_of(mode, time, x1, x2, out, d))
        ref = reference_stress("ogden2", c, G, tau, mode, d, time, x1, x2, out)
        assert relative_error(s, ref) <= 1e-6, d


def test_the_general_kernel_reduces_to_the_uniaxial_one():
    """The factorised kernel of vhfit.modes, in uniaxial, is §3's K(u, t) (to rounding)."""
    hm = hyperelastic.get("ogden2")
    c = np.array([[0.3, 4.0, 0.02, -3.0], [0.1, 2.0, 0.05, -1.0]])
    h = History.piecewise_linear([0.0, 1.0, 2.0], [0.0, 0.9, -0.4], np.linspace(0, 2, 9))
    t, lam, idx = h.grid(0.02)
    v = _kernels.LOBATTO
    samples = np.concatenate([lam[:1], (lam[:-1, None] + np.diff(lam)[:, None] * v[1:]).ravel()])
    E = 3.0 * hm.initial_shear_modulus(c)
    G, tau = np.array([[2.0, 1.0], [0.5, 3.0]]), np.array([[1e-3, 0.3], [0.05, 10.0]])
    offs = (np.array([0, samples.size]), np.array([0, t.size - 1]))
    old = _kernels.overstress(hm.stress(samples, c) / E[:, None], samples, np.diff(t), *offs,
                              G, tau, _kernels.DERIV)
    f0, f1 = modes.hereditary_factors(hm, c, E, "uniaxial", samples)
    w = np.ascontiguousarray(modes.hereditary_weights("uniaxial", lam).T)
    new = _kernels.overstress_general(f0, f1, w, np.diff(t), *offs, G, tau, _kernels.DERIV)
    np.testing.assert_allclose(new, old, rtol=1e-11, atol=1e-13 * np.abs(old).max())


# ============================================================== limits
@accuracy
@given(laws(), st.sampled_from(DEFORMATIONS), st.data())
def test_vanishing_or_instant_relaxation_gives_the_long_term_response(law_c, mode, data):
    """g → 0 and τ → 0 give the hyperelastic (equilibrium) response in every mode."""
    law, c = law_c
    time, x1, x2, out = data.draw(paths(mode))
    h = history_of(mode, time, x1, x2, out)
    m = ViscoHyperelastic(law, 2)
    long_term = m.stress(params_of(c, [0.0, 0.0], [1.0, 1.0]), h)
    eq = ViscoHyperelastic(law, 0).stress(
        c, History.equilibrium(h.out_strain, deformation=mode,
                               strain2=None if x2 is None else np.interp(out, time, x2) - 1))
    np.testing.assert_allclose(long_term, eq, rtol=1e-12, atol=1e-12 * np.abs(eq).max())
    E = E_inf_ref(law, c)
    tiny_g = m.stress(params_of(c, [1e-12 * E, 1e-12 * E], [time[-1], 1e-3 * time[-1]]), h)
    assert np.max(np.abs(tiny_g - eq)) <= 1e-10 * np.abs(eq).max()
    tiny_tau = m.stress(params_of(c, [10 * E, E], [1e-13 * time[-1], 1e-14 * time[-1]]), h)
    assert np.max(np.abs(tiny_tau - eq)) <= 1e-9 * np.abs(eq).max()


@pytest.mark.parametrize("mode", DEFORMATIONS)
def test_ramp_then_hold_relaxes_to_the_long_term_stress(mode):
    hi = RANGE[mode][1] * 0.5
    h = History.piecewise_linear([0.0, 1.0, 200.0], [0.0, hi, hi], deformation=mode,
                                 strain2=[0.0, 0.2, 0.2] if mode == "biaxial" else None)
    p = [0.2, 0.1, 5.0, 0.5, 1.0, 3.0]
    s = ViscoHyperelastic("mooney_rivlin", 2).stress(p, h)
    eq = ViscoHyperelastic("mooney_rivlin", 0).stress(
        [0.2, 0.1], History.equilibrium([hi], deformation=mode,
                                        strain2=[0.2] if mode == "biaxial" else None))
    assert s[-1] == pytest.approx(eq[0], rel=1e-12)
    assert abs(s[1]) > abs(eq[0]) * 1.5  # and the ramp's end was well above it


# ============================================================== batches
def _mixed_histories():
    eps = np.linspace(0.05, 0.6, 6)
    return [
        History.constant_rate(-eps / 2, -10.0),
        History.constant_rate(eps, 1.0, deformation="equibiaxial"),
        History.piecewise_linear([0, 1, 2], [0, 0.5, 0.1], deformation="biaxial",
                                 strain2=[0, 0.2, 0.3]).with_outputs([0.5, 1, 1.5, 2],
                                                                     [1, 2, 2, 1]),
        History.piecewise_linear([0, 1, 3], [0, -1.5, 1.0], deformation="simple_shear"),
        History.equilibrium(eps[::-1], deformation="planar"),
        History.constant_rate(eps, 0.1, deformation="planar"),
        History.equilibrium([0.3, 0.1], deformation="biaxial", strain2=[0.1, 0.4]),
    ]


def test_a_mixed_batch_equals_each_history_alone_and_keeps_uniaxial_bits():
    m = ViscoHyperelastic("ogden2", 2)
    X = np.array([[0.3, 4.0, 0.02, -3.0, 5.0, 0.01, 1.0, 1.0],
                  [0.2, 2.0, 0.1, -2.0, 0.5, 0.3, 2.0, 30.0]])
    hs = _mixed_histories()
    measures = ["engineering", "true", "engineering", "true", "engineering", "true", "true"]
    b = m.batch(hs, measure=measures)
    all_s = b(X)
    for h, sl, meas in zip(hs, b.slices, measures):
        alone = np.array([m.stress(x, h, measure=meas) for x in X])
        np.testing.assert_allclose(all_s[:, sl], alone, rtol=1e-14, atol=0)
    # the uniaxial history alone runs today's plan: its bits do not depend on the others
    np.testing.assert_array_equal(all_s[:, b.slices[0]], m.batch(hs[:1], measure=measures[0])(X))


def test_shape_columns_rebuild_a_mixed_batch_and_equilibrium_columns_are_zero():
    m = ViscoHyperelastic("mooney_rivlin", 2)
    X = np.array([[0.2, 0.1, 3.0, 0.01, 1.0, 2.0], [0.05, 0.3, 0.5, 1.0, 4.0, 0.02]])
    hs = _mixed_histories()
    b = m.batch(hs, measure="engineering")
    hyper, G, tau = m.split(X)
    base, H = b.shape_columns(hyper, tau)
    E = m.long_term_modulus(X)
    rebuilt = E[:, None] * base + np.einsum("pi,pin->pn", G, H)
    np.testing.assert_allclose(rebuilt, b(X), rtol=1e-12, atol=1e-14)
    for k in (4, 6):  # the equilibrium histories
        assert np.all(H[:, :, b.slices[k]] == 0.0)
    # no Prony terms at all: the long-term columns alone
    base0, H0 = b.shape_columns(hyper, np.zeros((2, 0)))
    assert H0.shape == (2, 0, b.n_points)
    np.testing.assert_array_equal(base0, base)


def test_batch_marks_invalid_parameter_sets_in_every_mode():
    m = ViscoHyperelastic("mooney_rivlin", 1)
    X = np.array([[0.2, 0.1, 1.0, 0.1], [0.0, 0.0, 1.0, 0.1], [0.2, 0.1, -1.0, 0.1]])
    s = m.batch(_mixed_histories())(X)
    assert np.all(np.isfinite(s[0])) and np.all(np.isinf(s[1:]))


# ============================================================== bad input
@pytest.mark.parametrize("kwargs, message", [
    (dict(deformation="shear"), r"deformation = 'shear' is unknown: choose one of uniaxial, "
                                r"equibiaxial, planar, biaxial, simple_shear"),
    (dict(deformation="biaxial"), r"deformation='biaxial' needs strain2"),
    (dict(deformation="planar", strain2=[0.1, 0.2]), r"strain2 is only for "
                                                      r"deformation='biaxial', not 'planar'"),
    (dict(deformation="planar", direction=2), r"direction = 2 needs a second loaded direction: "
                                              r"'planar' has none"),
    (dict(deformation="simple_shear", direction=2), r"'simple_shear' has none"),
    (dict(direction=2), r"'uniaxial' has none"),
    (dict(direction=3), r"direction = 3 must be 1 or 2"),
    (dict(stretch=[1.1, 1.2]), r"give strain or stretch \(= 1 \+ strain\), not both"),
    (dict(deformation="biaxial", strain2=[0.1, 0.1], stretch2=[1.1, 1.1]),
     r"give strain2 or stretch2"),
    (dict(deformation="biaxial", strain2=[0.1]), r"strain2 must have one value per strain"),
    (dict(deformation="biaxial", strain2=[0.1, -1.0]), r"strain2\[1\] = -1 gives a "
                                                       r"non-positive stretch"),
])
def test_bad_mode_arguments_are_one_line_errors(kwargs, message):
    m = ViscoHyperelastic("mooney_rivlin", 1)
    with pytest.raises(ValueError, match=message) as err:
        m.stress([0.2, 0.1, 1.0, 0.1], strain=[0.1, 0.2], strain_rate=1.0, **kwargs)
    assert "\n" not in str(err.value)


def test_stretch_arguments_are_checked():
    m = ViscoHyperelastic("mooney_rivlin", 0)
    with pytest.raises(ValueError, match=r"stretch\[1\] = -0.5 must be > 0"):
        m.stress([0.2, 0.1], stretch=[1.2, -0.5], deformation="planar")
    with pytest.raises(ValueError, match=r"stretch2\[0\] = 0.0 must be > 0"):
        m.stress([0.2, 0.1], stretch=[1.2], stretch2=[0.0], deformation="biaxial")
    with pytest.raises(ValueError, match="simple_shear is driven by the amount of shear: give "
                                         "strain=γ, not stretch"):
        m.stress([0.2, 0.1], stretch=[1.2], deformation="simple_shear")
    # stretch and strain describe the same test
    np.testing.assert_array_equal(
        m.stress([0.2, 0.1], stretch=[1.5, 0.5], deformation="equibiaxial"),
        m.stress([0.2, 0.1], strain=[0.5, -0.5], deformation="equibiaxial"))
