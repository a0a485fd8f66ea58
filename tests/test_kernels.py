"""Tests of vhfit._kernels: the ψ_j functions, the Lobatto derivative map, the recursion.

The recursion integrates each step exactly for a quartic interpolant, so a quartic input
must come out exact to rounding, for any step length and any τ from 1e-12 to 1e12 of it.
"""

from __future__ import annotations

import math
import subprocess
import sys
import warnings

import numpy as np
import pytest
from _budget import accuracy
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import quad

from vhfit._kernels import (
    DERIV,
    LOBATTO,
    _psi,
    overstress,
    overstress_columns,
    overstress_general,
)


def psi_reference(x: float, j: int) -> float:
    """ψ_j(x) = ∫_0^1 e^(−x(1−v)) v^j dv by quadrature (= (1/x) ∫_0^x e^(−w) (1 − w/x)^j dw)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if x <= 50.0:
            return quad(lambda v: math.exp(-x * (1 - v)) * v**j, 0.0, 1.0,
                        epsabs=0, epsrel=2e-14, limit=200)[0]
        top = min(x, 800.0)
        return quad(lambda w: math.exp(-w) * (1 - w / x) ** j, 0.0, top,
                    epsabs=0, epsrel=2e-14, limit=200, points=[1.0, 10.0])[0] / x


X_VALUES = [0.0, 1e-300, 1e-12, 1e-6, 0.01, 0.3, 1 - 1e-9, 1.0, 1 + 1e-9, 2.0, 7.5, 40.0,
            1e3, 1e6, 1e12, 1e300]


@pytest.mark.parametrize("x", X_VALUES)
def test_psi_matches_quadrature_across_the_whole_range(x):
    e, *psi = _psi(x)
    assert e == pytest.approx(math.exp(-x), rel=1e-15, abs=1e-300)
    for j, p in enumerate(psi):
        assert p == pytest.approx(psi_reference(x, j), rel=2e-14, abs=1e-300), j


@accuracy
@given(st.floats(1e-15, 1e15))
def test_psi_bounds_and_limits(x):
    """0 < ψ_3 < ψ_2 < ψ_1 < ψ_0 ≤ 1 and ψ_j ≤ min(1/(j+1), 1/x)."""
    e, p0, p1, p2, p3 = _psi(x)
    assert 0.0 <= e <= 1.0
    assert 0 < p3 < p2 < p1 < p0 <= 1.0
    for j, p in enumerate((p0, p1, p2, p3)):
        assert p <= 1.0 / (j + 1) * (1 + 1e-15)
        assert p <= 1.0 / x * (1 + 1e-15)


def test_psi_limits_exactly():
    assert _psi(0.0) == (1.0, 1.0, 0.5, pytest.approx(1 / 3, rel=1e-15),
                         pytest.approx(1 / 4, rel=1e-15))
    assert _psi(math.inf) == (0.0, 0.0, 0.0, 0.0, 0.0)


def test_deriv_maps_lobatto_values_to_derivative_coefficients():
    rng = np.random.default_rng(3)
    for _ in range(20):
        c = rng.normal(size=5)  # p(v) = c0 + c1 v + c2 v² + c3 v³ + c4 v⁴
        values = np.polynomial.polynomial.polyval(LOBATTO, c)
        np.testing.assert_allclose(DERIV @ values, [c[1], 2 * c[2], 3 * c[3], 4 * c[4]],
                                   rtol=1e-13, atol=1e-13 * np.abs(c).max())
    assert LOBATTO[0] == 0.0 and LOBATTO[-1] == 1.0


def _samples(t_nodes):
    """Sample times of the kernel's layout: the first node, then 3 Lobatto points + end."""
    h = np.diff(t_nodes)
    inner = t_nodes[:-1, None] + h[:, None] * LOBATTO[None, 1:]
    return np.concatenate([t_nodes[:1], inner.ravel()]), h


def _exact_branch(coef, tau, t):
    """a(0) e^(−t/τ) + ∫_0^t e^(−(t−u)/τ) a'(u) du for a polynomial a, by quadrature."""
    da = np.polynomial.polynomial.polyder(coef)
    pts = sorted(t - k * tau for k in (1, 4, 16, 64) if 0 < t - k * tau < t)
    scale = np.abs(coef).sum() * (1 + 4 * t**4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        val = quad(lambda u: math.exp(-(t - u) / tau) * np.polynomial.polynomial.polyval(u, da),
                   0.0, t, points=pts or None, epsabs=1e-15 * scale, epsrel=2e-14, limit=500)[0]
    return coef[0] * math.exp(-t / tau) + val


@accuracy
@given(st.lists(st.floats(-1.0, 1.0), min_size=5, max_size=5),
       st.lists(st.floats(0.01, 1.0), min_size=1, max_size=6),
       st.floats(-12.0, 12.0))
def test_recursion_is_exact_for_a_quartic(coef, steps, log_tau):
    """λ ≡ 1 makes a = b = ŝ, and h = (2/3) P + (1/3) Q = P: exact for a quartic ŝ(t)."""
    coef = np.asarray(coef)
    t_nodes = np.concatenate([[0.0], np.cumsum(steps)])
    tau = float(t_nodes[-1]) * 10.0**log_tau
    ts, h = _samples(t_nodes)
    s_hat = np.polynomial.polynomial.polyval(ts, coef)[None, :]
    out = overstress(s_hat, np.ones(ts.size), h, np.array([0, ts.size]),
                     np.array([0, h.size]), np.array([[1.0]]), np.array([[tau]]), DERIV)[0]
    exact = np.array([_exact_branch(coef, tau, t) for t in t_nodes])
    scale = np.abs(coef).sum() * max(1.0, t_nodes[-1] ** 4)
    np.testing.assert_allclose(out, exact, rtol=0, atol=1e-12 * scale)


@accuracy
@given(st.lists(st.floats(-1.0, 1.0), min_size=5, max_size=5),
       st.lists(st.floats(0.01, 1.0), min_size=1, max_size=6),
       st.floats(-12.0, 12.0), st.floats(0.05, 20.0))
def test_a_constant_stretch_leaves_the_branch_unchanged(coef, steps, log_tau, lam0):
    """At a constant stretch λ0, a = ŝ λ0⁻² and b = ŝ λ0, so P = P_ŝ λ0⁻², Q = P_ŝ λ0 and
    h = (2/3) λ0² P + (1/3) λ0⁻¹ Q = P_ŝ: the same exact branch as at λ ≡ 1, whatever λ0
    (this fixes both weights, λ0² and λ0⁻¹, and the initial states a(0), b(0))."""
    coef = np.asarray(coef)
    t_nodes = np.concatenate([[0.0], np.cumsum(steps)])
    tau = float(t_nodes[-1]) * 10.0**log_tau
    ts, h = _samples(t_nodes)
    s_hat = np.polynomial.polynomial.polyval(ts, coef)[None, :]
    out = overstress(s_hat, np.full(ts.size, lam0), h, np.array([0, ts.size]),
                     np.array([0, h.size]), np.array([[1.0]]), np.array([[tau]]), DERIV)[0]
    exact = np.array([_exact_branch(coef, tau, t) for t in t_nodes])
    scale = np.abs(coef).sum() * max(1.0, t_nodes[-1] ** 4)
    np.testing.assert_allclose(out, exact, rtol=0, atol=1e-11 * scale)


def test_overstress_layout_and_parallel_rows():
    """Several curves and parameter sets at once equal each alone; G scales linearly."""
    rng = np.random.default_rng(7)
    curves = [np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 1.0, n))]) for n in (3, 5, 1)]
    lam_parts, h_parts, s_off, k_off = [], [], [0], [0]
    for t_nodes in curves:
        ts, h = _samples(t_nodes)
        lam_parts.append(1.0 + 0.3 * np.sin(ts))
        h_parts.append(h)
        s_off.append(s_off[-1] + ts.size)
        k_off.append(k_off[-1] + h.size)
    lam = np.concatenate(lam_parts)
    h = np.concatenate(h_parts)
    P, N = 5, 3
    s_hat = lam[None, :] ** 2 - 1 / lam[None, :] * rng.uniform(0.5, 2.0, (P, 1))
    G = rng.uniform(0, 10, (P, N))
    tau = 10 ** rng.uniform(-3, 3, (P, N))
    so, ko = np.array(s_off), np.array(k_off)
    full = overstress(s_hat, lam, h, so, ko, G, tau, DERIV)
    assert full.shape == (P, h.size + len(curves))
    for p in range(P):
        for c in range(len(curves)):
            sl = slice(s_off[c], s_off[c + 1])
            one = overstress(s_hat[p:p + 1, sl], lam[sl], h[k_off[c]:k_off[c + 1]],
                             np.array([0, s_off[c + 1] - s_off[c]]),
                             np.array([0, k_off[c + 1] - k_off[c]]),
                             G[p:p + 1], tau[p:p + 1], DERIV)[0]
            nodes = slice(k_off[c] + c, k_off[c + 1] + c + 1)
            np.testing.assert_array_equal(full[p, nodes], one)
        # linear in G: the sum of the branches taken one at a time
        branches = sum(
            overstress(s_hat[p:p + 1], lam, h, so, ko, G[p:p + 1, i:i + 1],
                       tau[p:p + 1, i:i + 1], DERIV)[0] for i in range(N))
        np.testing.assert_allclose(full[p], branches, rtol=1e-13, atol=1e-14)
    # at each curve's first node the overstress is Σ G_i ŝ(0)
    for c in range(len(curves)):
        np.testing.assert_allclose(full[:, k_off[c] + c], G.sum(axis=1) * s_hat[:, s_off[c]],
                                   rtol=1e-15)


@accuracy
@given(st.lists(st.floats(-1.0, 1.0), min_size=5, max_size=5),
       st.lists(st.floats(-1.0, 1.0), min_size=5, max_size=5),
       st.lists(st.floats(0.01, 1.0), min_size=1, max_size=6),
       st.floats(-12.0, 12.0), st.floats(-3.0, 3.0), st.floats(-3.0, 3.0))
def test_general_recursion_is_exact_for_quartic_factors(c0, c1, steps, log_tau, w0, w1):
    """h = c_0 R_0 + c_1 R_1, each R_k the exact branch of its own quartic f_k (weights
    constant here, so h is the weighted sum of two exact branches)."""
    c0, c1 = np.asarray(c0), np.asarray(c1)
    t_nodes = np.concatenate([[0.0], np.cumsum(steps)])
    tau = float(t_nodes[-1]) * 10.0**log_tau
    ts, h = _samples(t_nodes)
    f0 = np.polynomial.polynomial.polyval(ts, c0)[None, :]
    f1 = np.polynomial.polynomial.polyval(ts, c1)[None, :]
    w = np.tile([w0, w1], (t_nodes.size, 1))
    out = overstress_general(f0, f1, w, h, np.array([0, ts.size]), np.array([0, h.size]),
                             np.array([[1.0]]), np.array([[tau]]), DERIV)[0]
    exact = np.array([w0 * _exact_branch(c0, tau, t) + w1 * _exact_branch(c1, tau, t)
                      for t in t_nodes])
    scale = (abs(w0) * np.abs(c0).sum() + abs(w1) * np.abs(c1).sum()) * max(1.0,
                                                                            t_nodes[-1] ** 4)
    np.testing.assert_allclose(out, exact, rtol=0, atol=1e-12 * scale)


_THREADED = """
import sys
import numpy as np
from vhfit._kernels import DERIV, overstress_general
a = np.load(sys.argv[1])
out = overstress_general(a["f0"], a["f1"], a["w"], a["h"], a["so"], a["ko"], a["G"], a["tau"],
                         DERIV, parallel=True)
np.save(sys.argv[2], out)
"""


def test_general_kernel_threads_and_layout(tmp_path):
    """Several curves and parameter sets: the threaded kernel equals the serial one, each
    (set, curve) job equals that curve alone, and the weights are read per node. (The
    threaded kernel runs in a child process: loading it starts numba's thread pool, after
    which this test process could no longer fork calibration workers safely.)"""
    rng = np.random.default_rng(11)
    curves = [np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 1.0, n))]) for n in (4, 1, 6)]
    f_parts, h_parts, w_parts, s_off, k_off = [], [], [], [0], [0]
    for t_nodes in curves:
        ts, h = _samples(t_nodes)
        f_parts.append(ts)
        h_parts.append(h)
        w_parts.append(np.column_stack([1 + t_nodes, np.cos(t_nodes)]))
        s_off.append(s_off[-1] + ts.size)
        k_off.append(k_off[-1] + h.size)
    ts = np.concatenate(f_parts)
    P, N = 4, 2
    f0 = np.sin(ts)[None, :] * rng.uniform(0.5, 2.0, (P, 1))
    f1 = np.exp(-ts)[None, :] * rng.uniform(0.5, 2.0, (P, 1))
    w = np.ascontiguousarray(np.concatenate(w_parts))
    h = np.concatenate(h_parts)
    G = rng.uniform(0, 10, (P, N))
    tau = 10 ** rng.uniform(-3, 3, (P, N))
    so, ko = np.array(s_off), np.array(k_off)
    seq = overstress_general(f0, f1, w, h, so, ko, G, tau, DERIV, parallel=False)
    np.savez(tmp_path / "in.npz", f0=f0, f1=f1, w=w, h=h, so=so, ko=ko, G=G, tau=tau)
    subprocess.run([sys.executable, "-c", _THREADED, str(tmp_path / "in.npz"),
                    str(tmp_path / "out.npy")], check=True, timeout=600)
    np.testing.assert_array_equal(seq, np.load(tmp_path / "out.npy"))
    for c in range(len(curves)):
        sl, nodes = slice(s_off[c], s_off[c + 1]), slice(k_off[c] + c, k_off[c + 1] + c + 1)
        one = overstress_general(f0[:, sl].copy(), f1[:, sl].copy(),
                                 np.ascontiguousarray(w[nodes]), h[k_off[c]:k_off[c + 1]],
                                 np.array([0, s_off[c + 1] - s_off[c]]),
                                 np.array([0, k_off[c + 1] - k_off[c]]), G, tau, DERIV)
        np.testing.assert_array_equal(seq[:, nodes], one)
        # first node: Σ G_i (c_0 f_0(0) + c_1 f_1(0))
        first = G.sum(axis=1) * (w[k_off[c] + c, 0] * f0[:, s_off[c]]
                                 + w[k_off[c] + c, 1] * f1[:, s_off[c]])
        np.testing.assert_allclose(seq[:, k_off[c] + c], first, rtol=1e-14)
    # repeat: each row of the factors serves consecutive rows of G and tau, as copies would
    G2, tau2 = rng.uniform(0, 10, (2 * P, N)), 10 ** rng.uniform(-3, 3, (2 * P, N))
    np.testing.assert_array_equal(
        overstress_general(f0, f1, w, h, so, ko, G2, tau2, DERIV, repeat=2),
        overstress_general(np.repeat(f0, 2, axis=0), np.repeat(f1, 2, axis=0), w, h, so, ko,
                           G2, tau2, DERIV))
    with pytest.raises(ValueError, match="G has 8 rows; expected repeat"):
        overstress_general(f0, f1, w, h, so, ko, G2, tau2, DERIV)


def test_overstress_columns_is_the_repeated_unit_modulus_call_to_the_bit():
    # one interpolant per row serves every τ: the arithmetic per τ must be unchanged (the
    # threaded variant runs the same job function; it is not started here, see above)
    import vhfit
    from vhfit.history import History

    parallel = False
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 3)
    hs = [History.constant_rate(np.linspace(-0.01, -0.5, 40), r) for r in (-0.01, -100.0)]
    hs.append(History.piecewise_linear([0.0, 1.0, 1.5, 3.0], [0.0, -0.3, -0.3, 0.2]))
    b = m.batch(hs)
    rng = np.random.default_rng(7)
    P, N = 5, 3
    s_hat = b._s_hat(rng.uniform(0.01, 1.0, (P, 2)))[0]
    tau = 10.0 ** rng.uniform(-6.0, 3.0, (P, N))
    ref = overstress(np.repeat(s_hat, N, axis=0), b.sample_stretch, b.step, b.sample_off,
                     b.step_off, np.ones((P * N, 1)), tau.reshape(P * N, 1), DERIV, parallel)
    got = overstress_columns(s_hat, b.sample_stretch, b.step, b.sample_off, b.step_off, tau,
                             DERIV, parallel)
    assert got.shape == ref.shape and np.array_equal(got, ref)


def test_serial_keeps_every_kernel_call_off_the_threads():
    """Inside serial() (an order scan's two processes) no call takes the threaded kernel,
    however large; nested blocks end with the outermost; outside, large calls do."""
    from vhfit import _kernels

    big = (_kernels.PARALLEL_MIN_JOBS, 4, 1000, 1)
    assert _kernels.use_threads(*big)
    with _kernels.serial():
        assert not _kernels.use_threads(*big)
        with _kernels.serial():
            assert not _kernels.use_threads(*big)
        assert not _kernels.use_threads(*big)  # still inside the outer block
    assert _kernels.use_threads(*big)
