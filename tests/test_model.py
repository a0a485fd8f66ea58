"""Tests of vhfit.model: the corrected Eq. 19 against quadrature, its limits and properties.

The reference below is written from docs/theory.md §4 directly — closed-form σ_h
(docs/theory.md §2), the stretch path λ(u), and ``scipy.integrate.quad`` of the
hereditary integral with break points near u = t (at t − kτ) and at the history's
breakpoints — and shares nothing with vhfit's grid, recursion or hyperelastic code.
"""

from __future__ import annotations

import bisect
import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest
from _budget import accuracy
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import quad

from vhfit import hyperelastic as hyp
from vhfit import model as vmodel
from vhfit.history import History
from vhfit.model import Batch, ViscoHyperelastic

U = np.finfo(np.float64).eps / 2  # unit round-off

# The domain the property tests draw from: stretches 1/20 to 20 (engineering strain
# -0.95 to 19), strain rates over 10 decades, relaxation times 1e-12 to 1e12 s.
LOG_RATE = (-5.0, 5.0)
LOG_TAU = (-12.0, 12.0)


@st.composite
def signed_strain(draw, low=0.05):
    """A strain of magnitude >= low: compression down to λ = 0.05, tension up to λ = 20."""
    if draw(st.booleans()):
        return -draw(st.floats(low, 0.95))
    return draw(st.floats(low, 19.0))


@st.composite
def mr_constants(draw):
    """C10, C01 >= 0 with C10 + C01 from 1e-3 to 2 MPa (E∞ > 0), generated directly."""
    total = 10 ** draw(st.floats(-3.0, math.log10(2.0)))
    kappa = draw(st.floats(0.0, 1.0))
    return ((1 - kappa) * total, kappa * total)


# ================================================================= reference
def sigma_h_ref(name: str, lam: float, c) -> float:
    """Closed-form uniaxial true stress of docs/theory.md §2."""
    if name == "mooney_rivlin":
        C10, C01 = c
        return 2 * C10 * (lam * lam - 1 / lam) + 2 * C01 * (lam - 1 / lam**2)
    if name == "neo_hooke":
        return 2 * c[0] * (lam * lam - 1 / lam)
    if name == "yeoh":
        C10, C20, C30 = c
        x = lam * lam + 2 / lam - 3
        return 2 * (lam * lam - 1 / lam) * (C10 + 2 * C20 * x + 3 * C30 * x * x)
    if name.startswith("ogden"):
        return sum(2 * m / a * (lam**a - lam ** (-a / 2)) for m, a in zip(c[0::2], c[1::2]))
    raise KeyError(name)


def E_inf_ref(name: str, c) -> float:
    """Long-term uniaxial modulus E∞ = 3 μ0."""
    if name == "mooney_rivlin":
        return 6 * (c[0] + c[1])
    if name in ("neo_hooke", "yeoh"):
        return 6 * c[0]
    if name.startswith("ogden"):
        return 3 * sum(c[0::2])
    raise KeyError(name)


class Path:
    """λ(u), linear between breakpoints (time[k], stretch[k])."""

    def __init__(self, time, stretch):
        self.t = [float(x) for x in time]
        self.lam = [float(x) for x in stretch]

    def __call__(self, u: float) -> float:
        if len(self.t) == 1:
            return self.lam[0]
        k = min(max(bisect.bisect_right(self.t, u) - 1, 0), len(self.t) - 2)
        w = (u - self.t[k]) / (self.t[k + 1] - self.t[k])
        return self.lam[k] + w * (self.lam[k + 1] - self.lam[k])


def _quad(f, t, tau, breaks, scale):
    """∫_0^t f(u) du, split near u = t (at t − kτ) and at the path's kinks."""
    pts = {t - k * tau for k in (1, 4, 16, 64)} | set(breaks)
    pts = sorted(p for p in pts if 0 < p < t)
    with warnings.catch_warnings():  # round-off notices once the integral has converged
        warnings.simplefilter("ignore")
        val, err = quad(f, 0.0, t, points=pts or None, epsabs=1e-14 * scale, epsrel=1e-12,
                        limit=1000)
    assert err <= 1e-10 * scale, f"reference quadrature did not converge: err {err:g}"
    return val


def reference_stress(name, c, G, tau, time, stretch, t_out, form="conditioned"):
    """σ(t) of the corrected Eq. 19 (docs/theory.md §4) at each time in ``t_out``.

    form="printed": σ0(t) − Σ (g_i/τ_i) ∫_0^t e^(−(t−u)/τ_i) σ0(u) K(u, t) du, σ0 = σ_h/g∞.
    form="conditioned": σ_h(t) + Σ G_i h_i(t),
        h_i = ŝ(t) e^(−t/τ_i) + (1/τ_i) ∫_0^t e^(−(t−u)/τ_i) [ŝ(t) − ŝ(u) K(u, t)] du.
    """
    lam_of = Path(time, stretch)
    breaks = [float(x) for x in time]
    E_inf = E_inf_ref(name, c)
    G0 = E_inf + sum(G)
    g_inf = E_inf / G0
    # scale of the integrands: |σ_h| along the path, every piece sampled
    samples = np.concatenate([np.linspace(a, b, 21) for a, b in zip(time[:-1], time[1:])]
                             + [np.asarray(time, float)])
    s_max = max(max(abs(sigma_h_ref(name, lam_of(u), c)) for u in samples), 1e-300)
    out = []
    for t in map(float, t_out):
        lt = lam_of(t)
        sh_t = sigma_h_ref(name, lt, c)

        def K(lu, lt=lt):
            return (2 / 3) * (lt / lu) ** 2 + (1 / 3) * lu / lt

        if form == "printed":
            s0 = sh_t / g_inf
            total = s0
            for Gi, ti in zip(G, tau):
                gi = Gi / G0

                def f(u, t=t, ti=ti):
                    lu = lam_of(u)
                    return math.exp(-(t - u) / ti) * sigma_h_ref(name, lu, c) / g_inf * K(lu) / ti

                total -= gi * _quad(f, t, ti, breaks, s_max / g_inf * 30)
        else:
            s_t = sh_t / E_inf
            total = sh_t
            for Gi, ti in zip(G, tau):

                def f(u, t=t, ti=ti, s_t=s_t):
                    lu = lam_of(u)
                    return math.exp(-(t - u) / ti) * (s_t - sigma_h_ref(name, lu, c) / E_inf
                                                      * K(lu)) / ti

                h = s_t * math.exp(-t / ti) + _quad(f, t, ti, breaks, s_max / E_inf * 30)
                total += Gi * h
        out.append(total)
    return np.array(out)


def relative_error(s, ref) -> float:
    """max |σ − σ_ref| / max |σ_ref| (the issue's accuracy measure)."""
    return float(np.max(np.abs(s - ref)) / np.max(np.abs(ref)))


def params_of(c, G, tau) -> np.ndarray:
    return np.concatenate([np.asarray(c, float), np.ravel(np.column_stack([G, tau]))])


# ============================================================ API and params


def test_param_names_follow_the_spec():
    assert ViscoHyperelastic("mooney_rivlin", n_prony=2).param_names == [
        "C10", "C01", "G1", "tau1", "G2", "tau2"]
    assert ViscoHyperelastic("yeoh", 1).param_names == ["C10", "C20", "C30", "G1", "tau1"]
    assert ViscoHyperelastic("ogden2", 0).param_names == ["mu1", "alpha1", "mu2", "alpha2"]
    m = ViscoHyperelastic("mooney_rivlin", 1)
    assert m.units == ["MPa", "MPa", "MPa", "s"] and m.n_params == 4
    assert "mooney_rivlin" in repr(m) and "n_prony=1" in repr(m)


def test_dict_and_array_params_give_the_same_stress():
    m = ViscoHyperelastic("mooney_rivlin", 2)
    p = dict(C10=0.1, C01=0.2, G1=3.0, tau1=1e-3, G2=1.0, tau2=0.1)
    x = [0.1, 0.2, 3.0, 1e-3, 1.0, 0.1]
    eps = np.linspace(0, -0.5, 7)
    np.testing.assert_array_equal(m.stress(p, strain=eps, strain_rate=-10.0),
                                  m.stress(x, strain=eps, strain_rate=-10.0))
    assert m.as_dict(x) == p
    np.testing.assert_array_equal(m.as_array(p), x)


def test_stress_keeps_the_shape_of_strain_and_is_zero_at_rest():
    m = ViscoHyperelastic("mooney_rivlin", 1)
    x = [0.1, 0.1, 1.0, 1.0]
    s = m.stress(x, strain=[0.0, -0.1, -0.2], strain_rate=-1.0)
    assert s.shape == (3,) and s[0] == 0.0 and np.all(s[1:] < 0)
    one = m.stress(x, strain=-0.2, strain_rate=-1.0)
    assert one.shape == () and one == pytest.approx(s[2], rel=2e-6)


def test_prony_g_of_the_verification_case():
    g, g_inf = ViscoHyperelastic("mooney_rivlin", 1).prony_g([0.0, 5.0, 30.0, 1e-4])
    np.testing.assert_allclose(g, [0.5])
    assert g_inf == pytest.approx(0.5)


# ============================================================ accuracy vs quad

VERIFICATION_TAUS = [1e-10, 1e-6, 1e-5, 1e-4, 1.0]


@pytest.mark.parametrize("tau1", VERIFICATION_TAUS)
def test_verification_case_matches_the_printed_eq19_by_quadrature(tau1):
    """Paper §3.2: C10 = 0, C01 = 5 MPa, g1 = 0.5 (G1 = 30 MPa), −5700 1/s to λ = 0.45."""
    m = ViscoHyperelastic("mooney_rivlin", 1)
    rate = -5700.0
    eps = np.linspace(0.0, -0.55, 23)[1:]
    s = m.stress([0.0, 5.0, 30.0, tau1], strain=eps, strain_rate=rate)
    ref = reference_stress("mooney_rivlin", (0.0, 5.0), [30.0], [tau1],
                           [0.0, -0.55 / rate], [1.0, 0.45], eps / rate, form="printed")
    assert relative_error(s, ref) <= 1e-6


def test_the_two_reference_forms_agree():
    """Sanity of the reference: printed and conditioned Eq. 19 are the same function."""
    args = ("mooney_rivlin", (0.2, 0.1), [5.0, 1.0], [1e-3, 0.05],
            [0.0, 0.01, 0.03], [1.0, 0.6, 0.9], [0.005, 0.01, 0.02, 0.03])
    a = reference_stress(*args, form="printed")
    b = reference_stress(*args, form="conditioned")
    assert relative_error(a, b) <= 1e-10


HISTORIES = {
    # name: (time breakpoints, strain breakpoints, output times)
    "loading-unloading compression": ([0.0, 1e-3, 2e-3], [0.0, -0.5, 0.0],
                                      np.linspace(0, 2e-3, 17)),
    "ramp-hold compression": ([0.0, 0.01, 0.05], [0.0, -0.4, -0.4], np.linspace(0, 0.05, 21)),
    "tension ramp": ([0.0, 0.1], [0.0, 1.0], np.linspace(0, 0.1, 11)),
    "tension load-unload-reload": ([0.0, 1.0, 1.5, 3.0], [0.0, 0.8, 0.2, 0.9],
                                   np.linspace(0, 3.0, 25)),
    "cycles with holds": ([0.0, 0.2, 0.4, 0.6, 0.8, 1.0], [0.0, -0.3, -0.3, 0.3, 0.3, 0.0],
                          np.linspace(0, 1.0, 26)),
}
MATERIALS = {
    "mooney_rivlin": (0.3, 0.1),
    "yeoh": (0.3, -0.02, 0.01),
    "ogden": (0.5, 5.0),
    "ogden2": (0.5, 2.0, 0.1, -4.0),
}


@pytest.mark.parametrize("material", list(MATERIALS))
@pytest.mark.parametrize("history", list(HISTORIES))
def test_general_histories_match_quadrature(history, material):
    time, strain, out = HISTORIES[history]
    c = MATERIALS[material]
    T = time[-1]
    G = np.array([10.0, 2.0, 0.5]) * E_inf_ref(material, c)
    tau = np.array([1e-3, 0.1, 3.0]) * T
    m = ViscoHyperelastic(material, 3)
    s = m.stress(params_of(c, G, tau), History.piecewise_linear(time, strain, out))
    ref = reference_stress(material, c, G, tau, time, 1 + np.asarray(strain), out)
    assert relative_error(s, ref) <= 1e-6


# ----------------------------------------------------------- hypothesis

@st.composite
def ramps(draw):
    """Constant-rate ramps in tension or compression: (time, stretch, out_time)."""
    eps_max = draw(signed_strain())
    rate = 10 ** draw(st.floats(*LOG_RATE)) * np.sign(eps_max)
    T = eps_max / rate
    return [0.0, T], [1.0, 1.0 + eps_max], np.linspace(0.0, T, 9)[1:]


@st.composite
def measured_histories(draw):
    """Piecewise-linear histories (loading, unloading, holds) with outputs anywhere."""
    k = draw(st.integers(2, 5))
    dt = [10 ** draw(st.floats(-5.0, 5.0)) for _ in range(k - 1)]
    time = np.concatenate([[0.0], np.cumsum(dt)])
    strain = [0.0, draw(signed_strain(low=0.02))]  # the first piece loads by >= 2 %
    for _ in range(k - 2):
        strain.append(strain[-1] if draw(st.booleans())
                      else draw(st.floats(-0.95, 19.0)))
    frac = draw(st.lists(st.floats(0.0, 1.0), min_size=3, max_size=6))
    out = np.unique(np.concatenate([np.asarray(frac) * time[-1], time[1:]]))
    return list(time), list(1.0 + np.asarray(strain)), out


@st.composite
def materials(draw, T, names=("mooney_rivlin", "yeoh", "ogden")):
    """A hyperelastic law plus 1–3 Prony terms with τ from 1e-12 to 1e12 s (T unused).

    Ogden exponents stay within the model's stated accuracy contract (cubic
    interpolation of σ_h λ⁻² and σ_h λ with effective powers up to ~10 in λ).
    """
    name = draw(st.sampled_from(names))
    if name == "mooney_rivlin":
        c = draw(mr_constants())
    elif name == "yeoh":
        C10 = draw(st.floats(0.01, 1.0))
        c = (C10, C10 * draw(st.floats(-0.05, 0.5)), C10 * draw(st.floats(0.0, 0.1)))
    else:
        alpha = draw(st.one_of(st.floats(-6.0, -0.5), st.floats(0.5, 8.0)))
        c = (draw(st.floats(0.01, 1.0)), alpha)
    n = draw(st.integers(1, 3))
    E = E_inf_ref(name, c)
    G = [E * 10 ** draw(st.floats(-2.0, 3.0)) for _ in range(n)]
    tau = [10 ** draw(st.floats(*LOG_TAU)) for _ in range(n)]
    return name, c, G, tau


@accuracy
@given(st.data())
def test_random_ramps_and_materials_match_quadrature(data):
    time, stretch, out = data.draw(ramps())
    name, c, G, tau = data.draw(materials(time[-1]))
    h = History.piecewise_linear(time, np.asarray(stretch) - 1.0, out)
    s = ViscoHyperelastic(name, len(G)).stress(params_of(c, G, tau), h)
    ref = reference_stress(name, c, G, tau, time, stretch, out)
    assert relative_error(s, ref) <= 1e-6


@accuracy
@given(st.data())
def test_random_measured_histories_match_quadrature(data):
    time, stretch, out = data.draw(measured_histories())
    name, c, G, tau = data.draw(materials(time[-1]))
    h = History.piecewise_linear(time, np.asarray(stretch) - 1.0, out)
    s = ViscoHyperelastic(name, len(G)).stress(params_of(c, G, tau), h)
    ref = reference_stress(name, c, G, tau, time, stretch, out)
    assert relative_error(s, ref) <= 1e-6


# Regression: with a stiff fast branch (G/E∞ ~ 1e4, τ below one grid step) the overstress
# is τ × the slope of the last step's interpolant. With the former cubic (4 Lobatto points)
# that slope was third order and the error reached 3.6e-5 (Ogden α = −6) and 6.4e-6 (MR);
# the quartic (5 points) makes it fourth order.
@pytest.mark.parametrize("name,c,tau", [("ogden", (1.0, -6.0), 3e-4),
                                        ("mooney_rivlin", (0.0, 1.0), 1e-4)])
def test_stiff_fast_branch_matches_quadrature(name, c, tau):
    time, strain, out = [0.0, 1.0], [0.0, -0.3], np.linspace(0, 1.0, 11)[1:]
    G = [1e4 * E_inf_ref(name, c)]  # the paper's gelatin has G1/E∞ ≈ 1e4
    s = ViscoHyperelastic(name, 1).stress(params_of(c, G, [tau]),
                                          History.piecewise_linear(time, strain, out))
    ref = reference_stress(name, c, G, [tau], time, 1 + np.asarray(strain), out)
    assert relative_error(s, ref) <= 1e-6


@pytest.mark.parametrize("rtol", [1e-3, 1e-5, 1e-8])
def test_accuracy_follows_rtol(rtol):
    """The error against quadrature stays below the requested rtol (Ogden α = 5, MR)."""
    for name, c in [("ogden", (0.5, 5.0)), ("mooney_rivlin", (0.0, 5.0))]:
        time, strain, out = HISTORIES["loading-unloading compression"]
        G, tau = [3 * E_inf_ref(name, c)], [2e-4]
        m = ViscoHyperelastic(name, 1, rtol=rtol)
        s = m.stress(params_of(c, G, tau), History.piecewise_linear(time, strain, out))
        ref = reference_stress(name, c, G, tau, time, 1 + np.asarray(strain), out)
        assert relative_error(s, ref) <= rtol


# ==================================================================== limits

def rounding_floor(model, history, sigma_scale, G_over_E) -> float:
    """Worst-case rounding of the recursion on branch states that carry Σ G_i ŝ.

    Each step adds d0 ψ0 + d1 ψ1 + d2 ψ2 with d = D · (4 sample values); the rows of the
    cubic's derivative map D have absolute sums up to 97, so a step's increment carries
    up to ~(18 + 97/2 + 97/3) u ≈ 100 u of the state's size: 128 u per step, plus the
    first node and the final products.
    """
    n_steps = model.batch([history]).step.size
    return 128 * (n_steps + 4) * U * sigma_scale * (1 + G_over_E)


def kernel_bound(stretch) -> float:
    """max K(u, t) = (2/3)(λ(t)/λ(u))² + (1/3) λ(u)/λ(t) over a path's stretch range."""
    q = max(stretch) / min(stretch)
    return (2 / 3) * q**2 + (1 / 3) * q


@st.composite
def mr_cases(draw, n_min=1, compression=False):
    """Mooney–Rivlin, 1–3 Prony terms, a constant-rate ramp (tension or compression)."""
    c = draw(mr_constants())
    eps_max = -draw(st.floats(0.05, 0.95)) if compression else draw(signed_strain())
    rate = 10 ** draw(st.floats(*LOG_RATE)) * np.sign(eps_max)
    n = draw(st.integers(n_min, 3))
    E = 6 * sum(c)
    G = np.array([E * 10 ** draw(st.floats(-2.0, 3.0)) for _ in range(n)])
    eps = np.linspace(0.0, eps_max, 11)[1:]
    return c, G, rate, eps


def sigma_h_mr(c, lam):
    return np.array([sigma_h_ref("mooney_rivlin", x, c) for x in np.atleast_1d(lam)])


def test_zero_prony_moduli_give_the_hyperelastic_stress_exactly():
    m = ViscoHyperelastic("mooney_rivlin", 2)
    eps = np.linspace(0, -0.6, 13)
    s = m.stress([0.2, 0.3, 0.0, 1e-3, 0.0, 1.0], strain=eps, strain_rate=-50.0)
    np.testing.assert_allclose(s, sigma_h_mr((0.2, 0.3), 1 + eps), rtol=1e-13, atol=1e-15)


@accuracy
@given(mr_cases(), st.floats(-14.0, -6.0))
def test_vanishing_moduli_give_the_hyperelastic_stress(case, log_g):
    """|σ − σ_h| = |Σ G_i h_i| ≤ Σ G_i (1 + max K) max|ŝ|, so G_i → 0 gives σ_h."""
    c, G, rate, eps = case
    E = 6 * sum(c)
    G = np.full(G.size, E * 10**log_g)
    tau = np.full(G.size, abs(eps[-1] / rate))
    s = ViscoHyperelastic("mooney_rivlin", G.size).stress(
        params_of(c, G, tau), strain=eps, strain_rate=rate)
    sh = sigma_h_mr(c, 1 + eps)
    bound = G.sum() * (1 + kernel_bound([1.0, 1 + eps[-1]])) * np.max(np.abs(sh)) / E
    assert np.max(np.abs(s - sh)) <= bound + 64 * U * np.max(np.abs(sh))


@accuracy
@given(mr_cases())
def test_tiny_relaxation_times_give_the_hyperelastic_stress(case):
    """τ = 1e-14 s, far below every step: the overstress is the first-order term
    Σ G_i τ_i r (ŝ' − ŝ/λ) (expansion of h_i about u = t), i.e. ~1e-14 of σ."""
    c, G, rate, eps = case
    tau = np.full(G.size, 1e-14)
    s = ViscoHyperelastic("mooney_rivlin", G.size).stress(
        params_of(c, G, tau), strain=eps, strain_rate=rate)
    sh = sigma_h_mr(c, 1 + eps)
    first = first_order_overstress(c, G, tau, rate, 1 + eps)
    assert np.all(np.abs(s - sh) <= 2 * np.abs(first) + 64 * U * np.max(np.abs(sh)))


def first_order_overstress(c, G, tau, rate, lam):
    """Σ G_i τ_i r (ŝ'(λ) − ŝ(λ)/λ) · E∞ for Mooney–Rivlin (small-τ expansion of Eq. 19)."""
    C10, C01 = c
    dsh = 2 * C10 * (2 * lam + 1 / lam**2) + 2 * C01 * (1 + 2 / lam**3)
    sh = sigma_h_mr(c, lam)
    return np.sum(G * tau) * rate * (dsh - sh / lam) / (6 * (C10 + C01))


@accuracy
@given(mr_cases())
def test_small_relaxation_times_follow_the_first_order_expansion(case):
    """For τ|r| = 1e-8 the overstress matches the first-order term, relative to itself.

    The overstress is then ~1e-8 of σ, far below the model's rtol, so the model is run at
    rtol = 1e-10. Error budget relative to the first-order term τ F'(t) (F(u) = ŝ(u) K(u, t)):
    the next term of the expansion, τ|r| |F''/F'| ≲ 1e-8 · k/λ_min ≲ 1e-8 · 6/0.4 = 1.5e-7
    (k ≲ 6 the power of λ in σ_h λ⁻²); and, since h_i ≈ τ_i × the slope of the last step's
    cubic interpolant at its end, that slope's error 0.0083 (kδ)³ ≲ 1e-8 with δ = 0.0019
    the grid step in ln λ at rtol = 1e-10. Hence rtol = 1e-6; the absolute floor is the
    rounding of σ − σ_h.
    """
    c, G, rate, eps = case
    tau = np.full(G.size, 1e-8 / abs(rate))
    s = ViscoHyperelastic("mooney_rivlin", G.size, rtol=1e-10).stress(
        params_of(c, G, tau), strain=eps, strain_rate=rate)
    sh = sigma_h_mr(c, 1 + eps)
    first = first_order_overstress(c, G, tau, rate, 1 + eps)
    np.testing.assert_allclose(s - sh, first, rtol=1e-6, atol=64 * U * np.max(np.abs(sh)))


@accuracy
@given(mr_cases())
def test_huge_relaxation_times_give_the_instantaneous_stress(case):
    """τ = 1e15 s: |h_i − ŝ(t)| ≤ (t/τ_i)(2 + max K) max|ŝ|, so σ → σ_h/g∞ = σ_h G0/E∞."""
    c, G, rate, eps = case
    tau = np.full(G.size, 1e15)
    m = ViscoHyperelastic("mooney_rivlin", G.size)
    h = History.constant_rate(eps, rate)
    s = m.stress(params_of(c, G, tau), h)
    E = 6 * sum(c)
    sh = sigma_h_mr(c, 1 + eps)
    inst = sh * (E + G.sum()) / E
    t_end = eps[-1] / rate
    bound = G.sum() * t_end / 1e15 * (2 + kernel_bound([1, 1 + eps[-1]])) * np.max(np.abs(sh)) / E
    floor = rounding_floor(m, h, np.max(np.abs(sh)), G.sum() / E)
    assert np.max(np.abs(s - inst)) <= bound + floor


@accuracy
@given(mr_cases(n_min=2))
def test_a_single_frozen_term_adds_its_instantaneous_stress(case):
    """τ1 → ∞ for one term only: that term contributes G1 ŝ(t), the others are unchanged."""
    c, G, rate, eps = case
    T = eps[-1] / rate
    tau = np.concatenate([[1e15], np.full(G.size - 1, T)])
    m = ViscoHyperelastic("mooney_rivlin", G.size)
    s = m.stress(params_of(c, G, tau), strain=eps, strain_rate=rate)
    G0 = G.copy()
    G0[0] = 0.0
    rest = m.stress(params_of(c, G0, tau), strain=eps, strain_rate=rate)
    sh = sigma_h_mr(c, 1 + eps)
    frozen = G[0] * sh / (6 * sum(c))
    # the frozen term still relaxes by ~T/τ1 (up to 2e-9 for the slowest ramps to λ = 20):
    # |h_1 − ŝ(t)| ≤ (t/τ1)(2 + max K) max|ŝ|, as in the test above
    decay = G[0] * T / 1e15 * (2 + kernel_bound([1, 1 + eps[-1]])) * np.max(np.abs(sh)) / (
        6 * sum(c))
    np.testing.assert_allclose(s, rest + frozen, rtol=1e-12,
                               atol=decay + 1e-12 * np.max(np.abs(s)))


@accuracy
@given(mr_cases())
def test_ramp_hold_relaxes_to_the_hyperelastic_stress(case):
    """During a hold the overstress of each branch decays exactly as e^(−s/τ_i);
    after 50 τ_max it is below e^(−50) of its start."""
    c, G, rate, eps = case
    T = eps[-1] / rate
    n = G.size
    tau = T * 10.0 ** np.linspace(-2, 1, n)
    hold = 50 * tau.max()
    t_out = np.array([T, T + 0.3 * tau[0], T + tau[-1], T + hold])
    h = History.piecewise_linear([0.0, T, T + hold], [0.0, eps[-1], eps[-1]], t_out)
    m = ViscoHyperelastic("mooney_rivlin", n)
    x = params_of(c, G, tau)
    s = m.stress(x, h)
    sh_hold = sigma_h_mr(c, 1 + eps[-1])[0]
    # each branch separately: exact exponential decay during the hold
    for i in range(n):
        Gi = np.zeros(n)
        Gi[i] = G[i]
        si = m.stress(params_of(c, Gi, tau), h) - sh_hold
        decay = np.exp(-(t_out - T) / tau[i])
        floor = rounding_floor(m, h, abs(sh_hold), G[i] / (6 * sum(c)))
        np.testing.assert_allclose(si, si[0] * decay, rtol=1e-9, atol=floor)
    over0 = abs(s[0] - sh_hold)
    floor = rounding_floor(m, h, abs(sh_hold), G.sum() / (6 * sum(c)))
    assert abs(s[-1] - sh_hold) <= over0 * math.exp(-50) + floor


@st.composite
def small_strain_cases(draw):
    c = draw(mr_constants())
    rate = 10 ** draw(st.floats(*LOG_RATE)) * draw(st.sampled_from([-1.0, 1.0]))
    eps_max = 10 ** draw(st.floats(-7.0, -5.0)) * np.sign(rate)
    T = eps_max / rate
    n = draw(st.integers(1, 3))
    E = 6 * sum(c)
    G = np.array([E * 10 ** draw(st.floats(-2.0, 3.0)) for _ in range(n)])
    tau = np.array([T * 10 ** draw(st.floats(-3.0, 3.0)) for _ in range(n)])
    return c, G, tau, rate, np.linspace(0.0, eps_max, 11)[1:]


@accuracy
@given(small_strain_cases())
def test_small_strain_closed_form(case):
    """σ = E∞ r t + Σ G_i r τ_i (1 − e^(−t/τ_i)) (docs/theory.md §4), pointwise to first order.

    Tolerance, derived for Mooney–Rivlin with κ = C01/(C10 + C01) ∈ [0, 1]:
    ŝ = ε − κε² + O(ε³) and K(u, t) − 1 = ε(t) − ε(u) + O(ε²). On a monotone ramp every
    term of the linear solution has the sign of r, and the corrections are bounded
    termwise: κ|ε| for σ_h; 2κ|ε| (from ε(t)² − ε(u)²) plus |ε| (from ŝ(u)(K − 1)) for
    each overstress. So |σ − σ_lin| ≤ (2κ + 1)|ε_max|(1 + O(ε)) |σ_lin|. Rounding of
    λ = 1 + ε and of λ² − 1/λ adds a few u in strain: ≤ 64 u / |ε_min| relative.
    """
    c, G, tau, rate, eps = case
    s = ViscoHyperelastic("mooney_rivlin", G.size).stress(
        params_of(c, G, tau), strain=eps, strain_rate=rate)
    t = eps / rate
    E = 6 * sum(c)
    lin = E * rate * t + np.sum(G * rate * tau * -np.expm1(-t[:, None] / tau), axis=1)
    kappa = c[1] / sum(c)
    e_max, e_min = abs(eps[-1]), abs(eps[0])
    tol = ((2 * kappa + 1) * e_max * (1 + 10 * e_max) + 64 * U / e_min) * np.abs(lin)
    assert np.all(np.abs(s - lin) <= tol)


@accuracy
@given(mr_cases(compression=True), st.floats(0.1, 3.0))
def test_stress_magnitude_never_decreases_with_rate_in_compression(case, decades):
    """Compression, C10, C01, G_i ≥ 0: the overstress is a sum of terms of one sign,
    each weighted by e^(−Δλ/(|r|τ)), which grows with |r| at fixed strain."""
    c, G, rate, eps = case
    tau = np.abs(eps[-1] / rate) * 10.0 ** np.linspace(-3, 2, G.size)
    m = ViscoHyperelastic("mooney_rivlin", G.size)
    x = params_of(c, G, tau)
    slow = m.stress(x, strain=eps, strain_rate=rate)
    fast = m.stress(x, strain=eps, strain_rate=rate * 10**decades)
    # both carry a relative error ≤ rtol = 1e-6 of their peak
    assert np.all(np.abs(fast) >= np.abs(slow) - 2e-6 * np.max(np.abs(fast)))


@accuracy
@given(st.floats(0.01, 1.0), st.floats(-2.0, 3.0), st.floats(-3.0, 3.0),
       st.floats(0.05, 1.0), st.floats(0.1, 3.0))
def test_stress_never_decreases_with_rate_in_neo_hookean_tension(C10, log_g, log_rt, e, dec):
    rate = 10.0
    tau = 10**log_rt / rate
    m = ViscoHyperelastic("neo_hooke", 1)
    x = [C10, 6 * C10 * 10**log_g, tau]
    eps = np.linspace(0, e, 11)[1:]
    slow = m.stress(x, strain=eps, strain_rate=rate)
    fast = m.stress(x, strain=eps, strain_rate=rate * 10**dec)
    assert np.all(fast >= slow - 2e-6 * np.max(fast))


@pytest.mark.parametrize("tau", [1e-15, 1e15])
@pytest.mark.parametrize("rate", [-1e-4, -1.0, 1e4])
def test_extreme_relaxation_times_stay_finite(tau, rate):
    m = ViscoHyperelastic("mooney_rivlin", 2)
    eps = np.linspace(0, 0.5 * np.sign(rate), 11)
    s = m.stress([0.1, 0.05, 100.0, tau, 1.0, 1.0 / abs(rate)], strain=eps, strain_rate=rate)
    assert np.all(np.isfinite(s))
    b = m.batch([History.constant_rate(eps, rate)])
    assert np.all(np.isfinite(b([[0.1, 0.05, 100.0, tau, 1.0, tau]])))


# ========================================================== batch, measures


def test_batch_equals_one_by_one():
    m = ViscoHyperelastic("mooney_rivlin", 3)
    rng = np.random.default_rng(0)
    X = np.column_stack([rng.uniform(0, 0.03, (30, 2))] + [
        np.column_stack([rng.uniform(0, 30, 30), 10 ** rng.uniform(-5, 3, 30)])
        for _ in range(3)])
    hs = [History.constant_rate(np.linspace(0, -0.5, 11)[1:], r) for r in (-0.0018, -59.5, -820.0)]
    hs.append(History.piecewise_linear([0, 1, 2], [0, -0.3, 0.1], [0.5, 1.0, 1.5, 2.0]))
    b = m.batch(hs)
    S = b(X)
    assert S.shape == (30, b.n_points) and b.n_points == 34
    for p in range(30):
        one = np.concatenate([m.stress(X[p], h) for h in hs])
        np.testing.assert_allclose(S[p], one, rtol=1e-14, atol=0)
        for h, sl in zip(hs, b.slices):
            np.testing.assert_array_equal(S[p, sl], m.stress(X[p], h))


def test_engineering_stress_is_true_stress_over_stretch():
    m = ViscoHyperelastic("mooney_rivlin", 1)
    x = [0.1, 0.05, 2.0, 1e-3]
    eps = np.linspace(0, -0.5, 6)[1:]
    true = m.stress(x, strain=eps, strain_rate=-100.0)
    eng = m.stress(x, strain=eps, strain_rate=-100.0, measure="engineering")
    np.testing.assert_allclose(eng, true / (1 + eps), rtol=1e-15)
    hs = [History.constant_rate(eps, -100.0)] * 2
    S = m.batch(hs, measure=["true", "engineering"])(np.array([x]))[0]
    np.testing.assert_allclose(S[:5], true, rtol=1e-15)
    np.testing.assert_allclose(S[5:], true / (1 + eps), rtol=1e-15)


def test_batch_uses_each_curves_own_measure():
    m = ViscoHyperelastic("neo_hooke", 0)
    h = History.constant_rate([0.5, 1.0], 1.0)
    curves = [SimpleNamespace(history=h, measure="engineering"),
              SimpleNamespace(history=h, measure="true")]
    S = m.batch(curves)([[0.5]])[0]
    np.testing.assert_allclose(S[2:], [0.5 * 2 * (1.5**2 - 1 / 1.5), 3.5])
    np.testing.assert_allclose(S[:2], S[2:] / [1.5, 2.0])


def test_batch_marks_invalid_individuals_with_inf_never_nan():
    m = ViscoHyperelastic("mooney_rivlin", 2)
    b = m.batch([History.constant_rate(np.linspace(0, -0.5, 5)[1:], -10.0),
                 History.piecewise_linear([0, 1], [0, 0.5], [0.5, 1.0])])
    good = [0.1, 0.05, 2.0, 1e-2, 1.0, 1.0]
    X = np.array([
        good,
        [0.1, 0.05, -2.0, 1e-2, 1.0, 1.0],     # negative G1
        [0.1, 0.05, 2.0, 0.0, 1.0, 1.0],       # tau1 = 0
        [0.1, 0.05, 2.0, 1e-2, 1.0, -1.0],     # tau2 < 0
        [0.0, 0.0, 2.0, 1e-2, 1.0, 1.0],       # C10 = C01 = 0: no long-term stiffness
        [0.1, np.nan, 2.0, 1e-2, 1.0, 1.0],    # NaN constant
        [0.1, 0.05, np.inf, 1e-2, 1.0, 1.0],   # infinite G1
        [-0.1, -0.05, 2.0, 1e-2, 1.0, 1.0],    # negative E_inf
    ])
    S = b(X)
    assert not np.isnan(S).any()
    np.testing.assert_array_equal(S[1:], np.inf)
    assert np.all(np.isfinite(S[0]))
    np.testing.assert_array_equal(S[0], b(np.array([good]))[0])
    hyper, tau = X[:, :2], X[:, 3::2]
    base, h = b.shape_columns(hyper, tau)
    assert np.isinf(base[4]).all() and np.isinf(h[4]).all() and not np.isnan(h).any()


def test_batch_inf_for_an_energy_undefined_on_the_history():
    def gent(I1, I2, mu, Jm):
        return -mu * Jm / 2 * np.log(1 - (I1 - 3) / Jm)

    hyp.register("_test_gent_model", example=(1.0, 50.0), overwrite=True)(gent)
    try:
        m = ViscoHyperelastic("_test_gent_model", 1)
        b = m.batch([History.constant_rate([0.5, 1.0, 2.0], 1.0)])
        with np.errstate(all="ignore"):
            S = b([[1.0, 2.0, 1.0, 1.0], [1.0, 50.0, 1.0, 1.0]])
        np.testing.assert_array_equal(S[0], np.inf)  # locks before λ = 3
        assert np.all(np.isfinite(S[1]))
        with pytest.raises(ValueError, match="the stress is not finite for params"):
            with np.errstate(all="ignore"):
                m.stress([1.0, 2.0, 1.0, 1.0], strain=[0.5, 1.0, 2.0], strain_rate=1.0)
    finally:
        hyp.unregister("_test_gent_model")


@accuracy
@given(st.data())
def test_shape_columns_rebuild_the_stress(data):
    """σ = E∞ ŝ + Σ G_i h_i: the model is linear in (E∞, G_i) for fixed shape and τ."""
    n = data.draw(st.integers(1, 3))
    P = 4
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    m = ViscoHyperelastic("mooney_rivlin", n)
    hyper = rng.uniform(0, 1, (P, 2))
    G = rng.uniform(0, 50, (P, n))
    tau = 10 ** rng.uniform(-5, 2, (P, n))
    hs = [History.constant_rate(np.linspace(0, -0.5, 6)[1:], -100.0),
          History.piecewise_linear([0, 0.1, 0.2], [0, 0.4, 0.0], [0.05, 0.1, 0.2])]
    b = m.batch(hs, measure=["engineering", "true"])
    X = np.empty((P, m.n_params))
    X[:, :2], X[:, 2::2], X[:, 3::2] = hyper, G, tau
    base, h = b.shape_columns(hyper, tau)
    assert base.shape == (P, b.n_points) and h.shape == (P, n, b.n_points)
    E = 6 * hyper.sum(axis=1)
    rebuilt = E[:, None] * base + np.einsum("pi,pik->pk", G, h)
    S = b(X)
    np.testing.assert_allclose(rebuilt, S, rtol=1e-12, atol=1e-13 * np.abs(S).max())


def test_residual_is_zero_on_the_model_own_curves():
    m = ViscoHyperelastic("mooney_rivlin", 1)
    x = [0.1, 0.05, 2.0, 1e-3]
    curves = []
    for r in (-10.0, -1000.0):
        h = History.constant_rate(np.linspace(0, -0.5, 11)[1:], r)
        curves.append(SimpleNamespace(history=h, measure="engineering",
                                      target_stress=m.stress(x, h, measure="engineering")))
    res = m.residual(x, curves)
    assert res.shape == (20,)
    np.testing.assert_allclose(res, 0.0, atol=1e-15)
    curves[1].target_stress = curves[1].target_stress + 1.0
    np.testing.assert_allclose(m.residual(x, curves)[10:], -1.0, rtol=1e-12)


def test_histories_and_strain_arguments_agree():
    m = ViscoHyperelastic("yeoh", 1)
    x = [0.1, -0.01, 0.002, 5.0, 0.01]
    t = np.array([0.0, 0.1, 0.2, 0.3])
    e = np.array([0.0, 0.3, 0.1, 0.5])
    np.testing.assert_array_equal(m.stress(x, strain=e, time=t),
                                  m.stress(x, History.piecewise_linear(t, e)))
    eps = np.linspace(0, 0.5, 6)
    ramp = m.stress(x, strain=eps, strain_rate=5.0)
    # same path, but cut into pieces at the samples: another grid, both within rtol
    np.testing.assert_allclose(ramp, m.stress(x, strain=eps, time=eps / 5.0),
                               rtol=0, atol=2e-6 * np.max(np.abs(ramp)))


# ================================================================ bad input


def test_unknown_model_lists_available_models():
    with pytest.raises(ValueError, match="unknown hyperelastic model 'mr'; available: ") as e:
        ViscoHyperelastic("mr", 1)
    assert "mooney_rivlin" in str(e.value) and "ogden" in str(e.value)


@pytest.mark.parametrize("n", [-1, 1.5, True, "2"])
def test_invalid_number_of_prony_terms(n):
    with pytest.raises(ValueError, match="n_prony = .* must be a whole number >= 0"):
        ViscoHyperelastic("mooney_rivlin", n)


@pytest.mark.parametrize("rtol", [0.0, 1.0, -1e-6])
def test_invalid_rtol(rtol):
    with pytest.raises(ValueError, match=r"rtol = .* must lie in \(0, 1\)"):
        ViscoHyperelastic("mooney_rivlin", 1, rtol=rtol)


@pytest.mark.parametrize("rtol", ["1e-6", None, True, float("nan"), float("inf")])
def test_rtol_that_is_not_a_number_is_named(rtol):
    with pytest.raises(ValueError, match=r"^rtol = .* must lie in \(0, 1\)[^\n]*$"):
        ViscoHyperelastic("mooney_rivlin", 1, rtol=rtol)


@pytest.mark.parametrize("model", [None, 3, ["mooney_rivlin"]])
def test_model_that_is_not_a_name_is_named(model):
    with pytest.raises(ValueError, match=r"^hyperelastic = .* must be a model name such as "
                                         r"'mooney_rivlin'[^\n]*$"):
        ViscoHyperelastic(model, 1)


@pytest.mark.parametrize("n", [np.int64(2), 0, 7])
def test_whole_numbers_of_prony_terms_are_accepted(n):
    m = ViscoHyperelastic("mooney_rivlin", n)
    assert m.n_prony == int(n) and isinstance(m.n_prony, int)
    assert len(m.param_names) == 2 + 2 * int(n)


def test_bad_arguments_fail_before_anything_is_computed(monkeypatch):
    # the front door checks every argument before the model lookup or the grid step
    calls = []
    monkeypatch.setattr(vmodel, "_dlog", lambda r: calls.append(r) or 0.1)
    monkeypatch.setattr(vmodel._hyper, "get", lambda name: calls.append(name))
    for kwargs in (dict(n_prony=-1), dict(n_prony=1.5), dict(rtol="x"), dict(hyperelastic=3)):
        with pytest.raises(ValueError):
            ViscoHyperelastic(**kwargs)
    assert calls == []


EPS = np.linspace(0, -0.5, 6)
GOOD = dict(C10=0.1, C01=0.05, G1=2.0, tau1=1e-3)


@pytest.mark.parametrize("change,message", [
    (dict(G1=-1.0), "G1 = -1.0: Prony moduli must be finite and >= 0"),
    (dict(G1=np.inf), "G1 = inf: Prony moduli must be finite"),
    (dict(tau1=0.0), "tau1 = 0.0: relaxation times must be > 0"),
    (dict(tau1=-1e-3), "tau1 = -0.001: relaxation times must be > 0"),
    (dict(C01=np.nan), "C01 = nan is not finite"),
    (dict(C10=0.0, C01=0.0), "long-term modulus E_inf = 3 mu0 = 0 MPa must be > 0"),
])
def test_invalid_parameters_are_named(change, message):
    m = ViscoHyperelastic("mooney_rivlin", 1)
    with pytest.raises(ValueError, match=message):
        m.stress({**GOOD, **change}, strain=EPS, strain_rate=-1.0)


def test_wrong_parameter_count_or_names():
    m = ViscoHyperelastic("mooney_rivlin", 2)
    with pytest.raises(ValueError, match=r"params has shape \(5,\); expected 6 values"):
        m.stress([0.1, 0.05, 2.0, 1e-3, 1.0], strain=EPS, strain_rate=-1.0)
    with pytest.raises(ValueError, match=r"missing \['G2', 'tau2'\], unexpected \[\]"):
        m.stress(GOOD, strain=EPS, strain_rate=-1.0)
    with pytest.raises(ValueError, match=r"unexpected \['G3'\]"):
        m.stress({**GOOD, "G2": 1.0, "tau2": 1.0, "G3": 1.0}, strain=EPS, strain_rate=-1.0)
    with pytest.raises(ValueError, match="expected one parameter set"):
        m.check(np.zeros((2, 6)))
    b = m.batch([History.constant_rate(EPS, -1.0)])
    with pytest.raises(ValueError, match=r"X has 4 columns; the model has 6 parameters"):
        b(np.zeros((3, 4)))


@pytest.mark.parametrize("rate", [0.0, np.nan, np.inf])
def test_zero_or_non_finite_rate(rate):
    m = ViscoHyperelastic("mooney_rivlin", 1)
    with pytest.raises(ValueError, match="strain_rate = .* give a finite, non-zero rate"):
        m.stress(GOOD, strain=EPS, strain_rate=rate)


def test_non_positive_or_non_finite_stretch():
    m = ViscoHyperelastic("mooney_rivlin", 1)
    with pytest.raises(ValueError, match=r"strain\[1\] = -1 gives a non-positive stretch"):
        m.stress(GOOD, strain=[-0.5, -1.0], strain_rate=-1.0)
    with pytest.raises(ValueError, match=r"strain\[2\] = -1.5 gives a non-positive stretch"):
        m.stress(GOOD, strain=[0.0, -0.5, -1.5], time=[0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match=r"strain\[1\] = nan is not finite"):
        m.stress(GOOD, strain=[-0.1, np.nan], strain_rate=-1.0)


def test_mismatched_time_and_strain():
    m = ViscoHyperelastic("mooney_rivlin", 1)
    with pytest.raises(ValueError, match="time and strain must have the same length, got 3 and 2"):
        m.stress(GOOD, strain=[0.0, -0.1], time=[0.0, 1.0, 2.0])


def test_history_arguments_must_be_unambiguous():
    m = ViscoHyperelastic("mooney_rivlin", 1)
    h = History.constant_rate(EPS, -1.0)
    with pytest.raises(ValueError, match=r"give a history, or strain \(or stretch\) with "
                       "strain_rate, time or neither"):
        m.stress(GOOD)
    with pytest.raises(ValueError, match="give strain_rate .* or time .*, not both"):
        m.stress(GOOD, strain=EPS, strain_rate=-1.0, time=np.arange(6.0))
    with pytest.raises(ValueError, match="give either a history or strain"):
        m.stress(GOOD, h, strain=EPS)


def test_invalid_measure_and_histories():
    m = ViscoHyperelastic("mooney_rivlin", 1)
    h = History.constant_rate(EPS, -1.0)
    with pytest.raises(ValueError, match="measure = 'nominal'; choose 'true' or 'engineering'"):
        m.stress(GOOD, h, measure="nominal")
    with pytest.raises(ValueError, match="give one measure per history"):
        m.batch([h, h], measure=["true"])
    with pytest.raises(ValueError, match="give at least one history or curve"):
        m.batch([])
    with pytest.raises(TypeError, match="expected a vhfit.History or a Curve"):
        m.batch([np.zeros(3)])
    assert isinstance(m.batch([h]), Batch)


# ============================================================ equilibrium
@pytest.mark.parametrize("name, c", [("mooney_rivlin", (0.3, 0.1)), ("yeoh", (0.3, -0.02, 0.01)),
                                     ("ogden2", (0.5, 2.0, 0.1, -4.0))])
def test_neither_rate_nor_time_is_the_long_term_response(name, c):
    """A strain with no rate and no time: σ_h of docs/theory.md §2 at each sample, in any
    order, whatever the Prony terms; engineering = σ_h/λ."""
    eps = np.array([0.4, -0.3, 1.5, 0.0, -0.6])
    m = ViscoHyperelastic(name, 2)
    p = params_of(c, [5.0, 1.0], [1e-3, 1.0])
    ref = np.array([sigma_h_ref(name, 1 + e, c) for e in eps])
    np.testing.assert_allclose(m.stress(p, strain=eps), ref, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(m.stress(p, stretch=1 + eps, measure="engineering"),
                               ref / (1 + eps), rtol=1e-12, atol=1e-15)
    h = History.equilibrium(eps)
    base, H = m.batch([h]).shape_columns(np.array([c]), np.array([[1e-3, 1.0]]))
    np.testing.assert_allclose(base[0] * E_inf_ref(name, c), ref, rtol=1e-12, atol=1e-15)
    assert np.all(H == 0.0)
