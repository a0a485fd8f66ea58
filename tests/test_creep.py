"""Creep (stress-controlled) histories of ``ViscoHyperelastic.creep`` against independent
references: the closed-form creep compliance of the generalised Maxwell model at small
strain, a trapezoid quadrature of the hereditary integral at finite strain, and the
limits of the Prony series (docs/theory.md §15)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from vhfit import _creep
from vhfit.model import ViscoHyperelastic

C10, C01 = 0.3, 0.2  # Mooney–Rivlin: E∞ = 6 (C10 + C01) = 3 MPa
E_INF = 6.0 * (C10 + C01)


def params(G, tau, c=(C10, C01)) -> list[float]:
    out = list(c)
    for g, t in zip(G, tau):
        out += [g, t]
    return out


# ------------------------------------------------------------------ small strain
def creep_compliance(t, E_inf, G, tau) -> np.ndarray:
    """J(t) of the generalised Maxwell model E(t) = E∞ + Σ G_i e^(−t/τ_i).

    Docs/theory.md §3: at small strain the relaxation modulus is E(t) = E∞ + Σ G_i
    e^(−t/τ_i). The creep compliance solves ∫_0^t E(t − s) dJ(s) = 1 (J(0−) = 0); by
    Laplace transform s Ē(s) · s J̄(s) = 1, so J̄(s) = 1/(s² Ē(s)) with

        s Ē(s) = E∞ + Σ G_i s/(s + a_i) = N(s)/D(s),   a_i = 1/τ_i,
        D(s) = Π_i (s + a_i),   N(s) = E∞ D(s) + Σ_i G_i s Π_(j≠i) (s + a_j).

    J̄(s) = D(s)/(s N(s)) has a simple pole at 0 (residue D(0)/N(0) = 1/E∞) and one at
    each root r_k of N (the retardation rates, real and negative), with residue
    D(r_k)/(r_k N'(r_k)); hence J(t) = 1/E∞ + Σ_k D(r_k)/(r_k N'(r_k)) e^(r_k t).
    """
    a = 1.0 / np.asarray(tau, dtype=np.float64)
    D = np.poly1d([1.0])
    for ai in a:
        D = D * np.poly1d([1.0, ai])
    N = E_inf * D
    for i, gi in enumerate(G):
        term = np.poly1d([gi, 0.0])
        for j, aj in enumerate(a):
            if j != i:
                term = term * np.poly1d([1.0, aj])
        N = N + term
    roots = np.roots(N.coeffs)
    assert np.all(np.abs(roots.imag) < 1e-12 * np.abs(roots.real))  # real, as they must be
    roots = roots.real
    dN = N.deriv()
    t = np.asarray(t, dtype=np.float64)
    return 1.0 / E_inf + sum(D(r) / (r * dN(r)) * np.exp(r * t) for r in roots)


def test_compliance_of_one_term_is_the_standard_solid():
    """The helper itself, against the standard linear solid's closed form: one term
    retards with τ_r = τ (E∞ + G)/E∞ from 1/(E∞ + G) to 1/E∞."""
    G, tau, t = 2.0, 0.5, np.array([0.0, 0.3, 2.0])
    tau_r = tau * (E_INF + G) / E_INF
    ref = 1 / E_INF - (1 / E_INF - 1 / (E_INF + G)) * np.exp(-t / tau_r)
    np.testing.assert_allclose(creep_compliance(t, E_INF, [G], [tau]), ref, rtol=1e-13)


#: The factor k of each test's small-strain stress, σ = k E(t) ∗ ε: the linearised
#: Mooney–Rivlin laws of docs/theory.md §13 — uniaxial 2(λ² − 1/λ)(C10 + C01/λ) ≈
#: 6 (C10 + C01) ε, equibiaxial 2(λ² − λ⁻⁴)(C10 + C01 λ²) ≈ 12 (C10 + C01) ε, planar
#: 2(λ² − λ⁻²)(C10 + C01) ≈ 8 (C10 + C01) ε — and the overstress linearises the same
#: way in every formulation (docs/theory.md §14, Limits).
MODE_FACTOR = {"uniaxial": 1.0, "equibiaxial": 2.0, "planar": 4.0 / 3.0}


@pytest.mark.parametrize("deformation, formulation", [
    ("uniaxial", "hereditary"), ("uniaxial", "lsdyna"), ("uniaxial", "lsdyna_deviatoric"),
    ("equibiaxial", "hereditary"), ("planar", "hereditary"), ("planar", "lsdyna"),
])
def test_small_strain_creep_is_the_maxwell_creep_compliance(deformation, formulation):
    """Two terms at σ = ±1e-4 E∞: the odd part in σ of the creep strain is σ J(t)/k.

    The strain's even part, O(σ²), is the finite-strain correction (4e-5 of the strain
    at this load, for this law: the kinematics of the kernels and of the law); the odd
    part keeps O(σ³), 1e-8 relative, so that the 1e-6 is the model's own accuracy (its
    default rtol).
    """
    G, tau = [2.0 * E_INF, 5.0 * E_INF], [0.01, 1.0]
    m = ViscoHyperelastic("mooney_rivlin", 2, formulation=formulation)
    t = np.concatenate([[0.0], np.logspace(-4, 2, 13)])
    s = 1e-4 * E_INF
    plus = m.creep(params(G, tau), s, t, deformation=deformation) - 1.0
    minus = m.creep(params(G, tau), -s, t, deformation=deformation) - 1.0
    ref = s * creep_compliance(t, E_INF, G, tau) / MODE_FACTOR[deformation]
    err = np.max(np.abs(0.5 * (plus - minus) / ref - 1.0))
    assert err < 1e-6, err


@pytest.mark.parametrize("rtol", [1e-3, 1e-4, 1e-6])
def test_stiff_wide_spectrum_meets_the_accuracy(rtol):
    """G/E∞ = 1e3 and τ over ten decades (1e-5 s and 1e5 s), outputs over twelve: the
    grid's fourth-order error is largest for the stiffest series and stays below the
    model's rtol (below 1e-6 the odd part's own O(σ²) = 1e-8 would blur the check)."""
    G, tau = [1e3 * E_INF, 1e-2 * E_INF], [1e-5, 1e5]
    m = ViscoHyperelastic("mooney_rivlin", 2, rtol=rtol)
    t = np.concatenate([[0.0], np.logspace(-6, 6, 25)])
    s = 1e-4 * E_INF
    odd = 0.5 * (m.creep(params(G, tau), s, t) - m.creep(params(G, tau), -s, t))
    err = np.max(np.abs(odd / (s * creep_compliance(t, E_INF, G, tau)) - 1.0))
    assert err < rtol, err


# ------------------------------------------------------------------ finite strain
STRETCHES = {  # (λ1, λ2, λ3) of each test at λ1 = λ (docs/theory.md §13)
    "uniaxial": lambda lam: (lam, lam**-0.5, lam**-0.5),
    "equibiaxial": lambda lam: (lam, lam, lam**-2.0),
    "planar": lambda lam: (lam, 1.0, 1.0 / lam),
}


def quadrature_creep(deformation, formulation, G, tau, target, t_end, n, measure="true"):
    """λ(t) on a uniform grid of n steps over [0, t_end]: the hereditary integral of the
    formulation by the trapezoid rule, and λ at each node by root finding.

    Mooney–Rivlin in principal axes, τ_k = 2 C10 λ_k² − 2 C01 λ_k⁻² up to the pressure;
    d = dev τ, a the loaded and c (= 3) the stress-free direction, σ_h = τ_a − τ_c.

    * "hereditary" (docs/theory.md §4, §13: the corrected Eq. 19 in tensor form):
      σ(t) = σ0(t) − Σ_i (g_i/τ_i) ∫_0^t e^(−(t−u)/τ_i) [λ_a(t)²/λ_a(u)² d0_a(u)
      − λ_c(t)²/λ_c(u)² d0_c(u)] du, with σ0 = σ_h/g∞, d0 = d/g∞, g_i = G_i/G0.
    * "lsdyna" (§14): σ = σ_h + Σ_i G_i (λ_a² S_a,i − λ_c² S_c,i), S_k,i =
      (2/3) ∫ e^(−(t−s)/τ_i) dÊ_k, with Ê = E = (λ² − 1)/2 or its deviator; by parts
      (Ê(0−) = 0, the jump at t = 0 included) S = (2/3)[Ê(t) − (1/τ) ∫ e^(−(t−s)/τ) Ê ds].

    The integral over [0, t_j] is a direct sum over every earlier node (O(n²)), with
    the unknown λ_j in its last term.
    """
    st = STRETCHES[deformation]
    G, tau = np.asarray(G), np.asarray(tau)
    G0 = E_INF + G.sum()
    g, g_inf = G / G0, E_INF / G0
    t = np.linspace(0.0, t_end, n + 1)
    h = t[1]

    def kinematics(lam):
        ls = [np.asarray(v, dtype=np.float64) for v in st(lam)]
        tk = [2 * C10 * v**2 - 2 * C01 * v**-2 for v in ls]
        mean = sum(tk) / 3
        d = [v - mean for v in tk]
        if formulation == "hereditary":
            f = (d[0] / ls[0] ** 2 / g_inf, d[2] / ls[2] ** 2 / g_inf)
        else:
            shift = sum(v**2 for v in ls) / 3 if formulation == "lsdyna_deviatoric" else 1.0
            f = ((ls[0] ** 2 - shift) / 3, (ls[2] ** 2 - shift) / 3)
        return ls, tk[0] - tk[2], f

    lam = np.empty(n + 1)
    fa, fc = np.empty(n + 1), np.empty(n + 1)
    for j in range(n + 1):
        w_end = 0.0 if j == 0 else h / 2
        w = np.full(j, h)
        w[:1] = h / 2
        decay = np.exp(-(t[j] - t[:j])[None, :] / tau[:, None])
        A, B = decay @ (w * fa[:j]), decay @ (w * fc[:j])

        def residual(x, A=A, B=B, w_end=w_end):
            ls, sigma_h, (ga, gc) = kinematics(x)
            la2, lc2 = ls[0] ** 2, ls[2] ** 2
            Ia, Ic = A + w_end * ga, B + w_end * gc
            if formulation == "hereditary":
                s = sigma_h / g_inf - np.sum(g / tau * (la2 * Ia - lc2 * Ic))
            else:
                s = sigma_h + np.sum(G * (la2 * (ga - Ia / tau) - lc2 * (gc - Ic / tau)))
            return (s / ls[0] if measure == "engineering" else s) - target

        lam[j] = brentq(residual, 1.0, 3.0, xtol=1e-15, rtol=1e-15)
        _, _, (fa[j], fc[j]) = kinematics(lam[j])
    return t, lam


@pytest.mark.parametrize("deformation, formulation, measure, target", [
    ("uniaxial", "hereditary", "true", 1.4),
    ("uniaxial", "hereditary", "engineering", 0.95),
    ("equibiaxial", "hereditary", "true", 3.2),
    ("planar", "hereditary", "true", 2.0),
    ("uniaxial", "lsdyna", "true", 1.4),
    ("equibiaxial", "lsdyna_deviatoric", "true", 3.0),
])
def test_finite_strain_creep_matches_a_trapezoid_quadrature(deformation, formulation,
                                                            measure, target):
    """Creep to a stretch of about 1.5 against the quadrature on two grids (h, h/2)
    extrapolated (Richardson: the trapezoid's error is a series in h²). The tolerance is
    the finer trapezoid's own error estimate |λ_(h/2) − λ_h|/3 (which bounds the
    extrapolation's), plus the model's rtol = 1e-6 of the creep strain."""
    G, tau = [0.8, 1.5], [0.2, 1.5]
    n = 600  # h = τ_1/30
    t_h, lam_h = quadrature_creep(deformation, formulation, G, tau, target, 4.0, n, measure)
    _, lam_h2 = quadrature_creep(deformation, formulation, G, tau, target, 4.0, 2 * n,
                                 measure)
    lam_h2 = lam_h2[::2]
    ref = (4.0 * lam_h2 - lam_h) / 3.0
    keep = slice(None, None, 25)
    m = ViscoHyperelastic("mooney_rivlin", 2, formulation=formulation)
    lam = m.creep(params(G, tau), target, t_h[keep], deformation=deformation, measure=measure)
    assert 1.4 < lam.max() < 1.6  # finite strain indeed
    tol = np.max(np.abs(lam_h2 - lam_h)) / 3.0 + 1e-6 * np.max(lam - 1.0)
    err = np.max(np.abs(lam - ref[keep]))
    assert err < tol, (err, tol)


# ------------------------------------------------------------------------ limits
ELASTIC = {  # the Mooney–Rivlin long-term stress of each test (docs/theory.md §13)
    "uniaxial": lambda lam: 2 * (lam**2 - 1 / lam) * (C10 + C01 / lam),
    "equibiaxial": lambda lam: 2 * (lam**2 - lam**-4) * (C10 + C01 * lam**2),
    "planar": lambda lam: 2 * (lam**2 - lam**-2) * (C10 + C01),
}


def elastic_stretch(deformation, stress, scale=1.0) -> float:
    """λ with scale · σ_h(λ) = stress."""
    return brentq(lambda x: scale * ELASTIC[deformation](x) - stress, 0.2, 5.0, xtol=1e-15,
                  rtol=1e-15)


T_OUT = np.array([0.0, 1e-3, 0.1, 1.0, 10.0, 1e3])
G_LIMIT = [1.0 * E_INF, 2.0 * E_INF]  # g∞ = 1/4: the instantaneous law is 4 σ_h


@pytest.mark.parametrize("deformation", list(ELASTIC))
@pytest.mark.parametrize("stress", [1.5, -0.9])
def test_vanishing_moduli_give_the_elastic_stretch(deformation, stress):
    """G_i → 0 (1e-12 E∞): λ(t) solves σ_h(λ) = σ at every time, to 1e-12 relative."""
    m = ViscoHyperelastic("mooney_rivlin", 2)
    lam = m.creep(params([1e-12 * E_INF] * 2, [0.01, 1.0]), stress, T_OUT,
                  deformation=deformation)
    ref = elastic_stretch(deformation, stress)
    np.testing.assert_allclose(lam - 1.0, ref - 1.0, rtol=1e-10)


@pytest.mark.parametrize("deformation", list(ELASTIC))
def test_huge_relaxation_times_keep_the_instantaneous_response(deformation):
    """τ_i → ∞ (1e15 s, outputs to 1e3 s): λ stays where the load put it, the
    instantaneous law σ_h/g∞ = σ (docs/theory.md §4), to the creep e^(−t/τ) allows."""
    m = ViscoHyperelastic("mooney_rivlin", 2)
    lam = m.creep(params(G_LIMIT, [1e15, 1e15]), 1.5, T_OUT, deformation=deformation)
    g_inf = E_INF / (E_INF + sum(G_LIMIT))
    ref = elastic_stretch(deformation, 1.5, 1.0 / g_inf)
    np.testing.assert_allclose(lam - 1.0, ref - 1.0, rtol=1e-9)


@pytest.mark.parametrize("deformation", list(ELASTIC))
def test_tiny_relaxation_times_give_the_long_term_response(deformation):
    """τ_i → 0 (1e-12 s): at t = 0 the jump is instantaneous (σ_h/g∞ = σ), from the
    first output (1e-3 s = 1e9 τ) on the long-term law σ_h(λ) = σ holds."""
    m = ViscoHyperelastic("mooney_rivlin", 2)
    lam = m.creep(params(G_LIMIT, [1e-12, 2e-12]), 1.5, T_OUT, deformation=deformation)
    g_inf = E_INF / (E_INF + sum(G_LIMIT))
    assert lam[0] == pytest.approx(elastic_stretch(deformation, 1.5, 1.0 / g_inf), rel=1e-12)
    np.testing.assert_allclose(lam[1:], elastic_stretch(deformation, 1.5), rtol=1e-9)


@pytest.mark.parametrize("formulation", ["hereditary", "lsdyna", "lsdyna_deviatoric"])
def test_long_hold_reaches_the_long_term_response(formulation):
    """Any formulation: after 1e4 τ_max the overstress is gone, σ_h(λ) = σ (1e-10)."""
    m = ViscoHyperelastic("mooney_rivlin", 2, formulation=formulation)
    lam = m.creep(params(G_LIMIT, [0.01, 1.0]), 1.5, [0.0, 1e4])
    assert lam[-1] == pytest.approx(elastic_stretch("uniaxial", 1.5), rel=1e-10)
    assert lam[0] < lam[-1]


def test_no_prony_terms_do_not_creep():
    m = ViscoHyperelastic("mooney_rivlin", 0)
    lam = m.creep([C10, C01], -0.7, T_OUT, deformation="planar")
    np.testing.assert_allclose(lam, elastic_stretch("planar", -0.7), rtol=1e-14)


def test_grid_is_the_outputs_and_the_accuracy_alone():
    """Output times are nodes, t = 0 the first; steps grow by at most the ratio of
    per_decade(rtol) a decade (plus a quarter, where an output time replaced a node)."""
    time = np.array([0.0, 0.0, 2e-3, 0.5, 0.5, 7.0])
    t, idx = _creep.creep_grid(time, 1e-6)
    assert t[0] == 0.0 and np.all(np.diff(t) > 0)
    np.testing.assert_array_equal(t[idx], time)
    assert t[1] == pytest.approx(2e-3 * 1e-3)
    ratio = t[2:] / t[1:-1]
    assert ratio.max() <= 10 ** (1.25 / _creep.per_decade(1e-6)) * (1 + 1e-12)
    assert _creep.creep_grid(np.zeros(3), 1e-6)[0].tolist() == [0.0]


def test_shape_follows_time():
    m = ViscoHyperelastic("mooney_rivlin", 1)
    lam = m.creep([C10, C01, 1.0, 0.1], 0.5, [[0.0, 0.1], [0.2, 0.3]])
    assert lam.shape == (2, 2) and np.all(np.diff(lam.reshape(-1)) > 0)


# --------------------------------------------------------------------- bad input
def one_line_error(call, match: str) -> str:
    with pytest.raises(ValueError, match=match) as info:
        call()
    text = str(info.value)
    assert "\n" not in text
    return text


def test_a_stress_the_law_cannot_carry_is_refused_in_one_line():
    """Mooney–Rivlin with C10 = 0 carries a nominal tension below 2 C01 (1 − λ⁻³ < 1):
    at once at most 2 C01/g∞, in the long term at most 2 C01."""
    m = ViscoHyperelastic("mooney_rivlin", 1)
    p = [0.0, 0.5, 3.0, 0.1]  # E∞ = 3, G = 3: g∞ = 1/2; limits 2 and 1 MPa
    one_line_error(lambda: m.creep(p, 2.5, [0.0, 1.0], measure="engineering"),
                   "instantaneous")
    one_line_error(lambda: m.creep(p, 1.5, [0.0, 1.0], measure="engineering"),
                   "without bound")
    lam = m.creep(p, 0.9, [0.0, 1.0], measure="engineering")  # within both: it creeps
    assert 1.0 < lam[0] < lam[1]


@pytest.mark.parametrize("time, match", [
    ([0.0, 2.0, 1.0], "must not decrease"),
    ([-1.0, 1.0], ">= 0"),
    ([0.0, np.nan], "finite"),
    ([], "empty"),
])
def test_bad_times_are_refused(time, match):
    m = ViscoHyperelastic("mooney_rivlin", 1)
    one_line_error(lambda: m.creep([C10, C01, 1.0, 0.1], 0.5, time), match)


@pytest.mark.parametrize("deformation, match", [
    ("simple_shear", "Poynting"),
    ("biaxial", "two held stresses"),
    ("volumetric", "incompressible"),
])
def test_tests_without_one_held_stress_are_refused(deformation, match):
    m = ViscoHyperelastic("mooney_rivlin", 1)
    one_line_error(lambda: m.creep([C10, C01, 1.0, 0.1], 0.5, [0.0, 1.0],
                                   deformation=deformation), match)


def test_bad_measure_and_stress_are_refused():
    m = ViscoHyperelastic("mooney_rivlin", 1)
    p = [C10, C01, 1.0, 0.1]
    one_line_error(lambda: m.creep(p, 0.5, [1.0], measure="nominal"), "measure")
    one_line_error(lambda: m.creep(p, np.inf, [1.0]), "finite")
    one_line_error(lambda: m.creep(p, "big", [1.0]), "number")
    one_line_error(lambda: m.creep([C10, C01, -1.0, 0.1], 0.5, [1.0]), "G1")
