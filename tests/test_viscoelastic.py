"""Tests of vhfit.viscoelastic: the paper's Prony parameterisation (docs/theory.md §3)."""

from __future__ import annotations

import numpy as np
import pytest
from _budget import accuracy
from hypothesis import given
from hypothesis import strategies as st

from vhfit.viscoelastic import check_prony, from_dimensionless, prony_g, relaxation_modulus

positive = st.floats(1e-6, 1e6)
prony_moduli = st.lists(st.one_of(st.just(0.0), st.floats(1e-6, 1e6)), min_size=1, max_size=6)


def test_paper_verification_case_has_g1_one_half():
    """C01 = 5 MPa gives E∞ = 6·5 = 30 MPa; G1 = 30 MPa gives g1 = g∞ = 0.5."""
    g, g_inf = prony_g(30.0, [30.0])
    np.testing.assert_allclose(g, [0.5], rtol=1e-15)
    assert g_inf == pytest.approx(0.5, rel=1e-15)


@accuracy
@given(positive, prony_moduli)
def test_prony_g_weights_sum_to_one(E_inf, G):
    g, g_inf = prony_g(E_inf, G)
    G0 = E_inf + sum(G)
    np.testing.assert_allclose(g, np.asarray(G) / G0, rtol=1e-15)
    assert g_inf == pytest.approx(E_inf / G0, rel=1e-15)
    assert g_inf + g.sum() == pytest.approx(1.0, rel=1e-12)
    assert 0 < g_inf <= 1 and np.all(g >= 0)


def round_trip_rtol(n_terms: int, g_inf: float) -> float:
    """Rounding bound of g∞ = 1 − Σ g_i recomputed from n rounded weights.

    Each g_i carries a relative error ≤ u (unit round-off) and the sum another n·u, so
    1 − Σ g_i is off by ≤ (n + 1)·u in absolute terms: (n + 1)·u / g∞ relative. A
    factor 4 covers the few further roundings (G0, products) of the round trip.
    """
    u = np.finfo(np.float64).eps / 2
    return 4 * (n_terms + 1) * u / g_inf


@accuracy
@given(positive, prony_moduli)
def test_round_trip_through_the_long_term_modulus(E_inf, G):
    g, g_inf = prony_g(E_inf, G)
    G_back, E_back = from_dimensionless(g, E_inf=E_inf)
    rtol = round_trip_rtol(len(G), g_inf)
    np.testing.assert_allclose(G_back, G, rtol=rtol)
    assert E_back == pytest.approx(E_inf, rel=rtol)


@accuracy
@given(positive, prony_moduli)
def test_round_trip_through_the_instantaneous_modulus(E_inf, G):
    g, g_inf = prony_g(E_inf, G)
    G0 = E_inf + sum(G)
    G_back, E_back = from_dimensionless(g, E_0=G0)
    np.testing.assert_allclose(G_back, G, rtol=1e-14)  # g_i · G0: no cancellation
    assert E_back == pytest.approx(E_inf, rel=round_trip_rtol(len(G), g_inf))


@accuracy
@given(st.lists(st.floats(0.0, 0.3), min_size=1, max_size=3), positive)
def test_round_trip_from_dimensionless_weights(g, E_inf):
    G, E_back = from_dimensionless(g, E_inf=E_inf)
    g2, g_inf = prony_g(E_back, G)
    np.testing.assert_allclose(g2, g, rtol=1e-12, atol=1e-15)
    assert g_inf == pytest.approx(1 - sum(g), rel=1e-12)


def test_relaxation_modulus_limits():
    E_inf, G, tau = 2.0, [3.0, 5.0], [1e-3, 10.0]
    assert relaxation_modulus(0.0, E_inf, G, tau) == pytest.approx(10.0, rel=1e-15)  # G0
    assert relaxation_modulus(1e6, E_inf, G, tau) == pytest.approx(E_inf, rel=1e-15)  # E∞
    t = np.array([1e-3, 10.0])
    expected = E_inf + 3.0 * np.exp(-t / 1e-3) + 5.0 * np.exp(-t / 10.0)
    np.testing.assert_allclose(relaxation_modulus(t, E_inf, G, tau), expected, rtol=1e-15)


@accuracy
@given(positive, prony_moduli, st.data())
def test_relaxation_modulus_decreases_from_G0_to_E_inf(E_inf, G, data):
    tau = data.draw(st.lists(st.floats(1e-12, 1e12), min_size=len(G), max_size=len(G)))
    t = np.concatenate([[0.0], np.logspace(-14, 16, 80)])
    E = relaxation_modulus(t, E_inf, G, tau)
    assert E.shape == t.shape
    assert E[0] == pytest.approx(E_inf + sum(G), rel=1e-14)
    assert E[-1] == pytest.approx(E_inf, rel=1e-14)
    assert np.all(np.diff(E) <= 0)


def test_relaxation_modulus_broadcasts_over_time_arrays():
    t = np.zeros((2, 3))
    assert relaxation_modulus(t, 1.0, [1.0], [1.0]).shape == (2, 3)


# --------------------------------------------------------------- bad input


@pytest.mark.parametrize("G,name", [([1.0, -0.5], "G2 = -0.5"), ([np.nan], "G1 = nan"),
                                    ([np.inf], "G1 = inf")])
def test_negative_or_non_finite_modulus_is_named(G, name):
    with pytest.raises(ValueError, match=f"{name}: Prony moduli must be finite and >= 0"):
        check_prony(G, [1.0] * len(G))


@pytest.mark.parametrize("tau,name", [([1.0, 0.0], "tau2 = 0.0"), ([-1.0], "tau1 = -1.0"),
                                      ([np.nan], "tau1 = nan")])
def test_non_positive_relaxation_time_is_named(tau, name):
    with pytest.raises(ValueError, match=f"{name}: relaxation times must be > 0"):
        check_prony([1.0] * len(tau), tau)
    with pytest.raises(ValueError, match=name):
        relaxation_modulus(0.0, 1.0, [1.0] * len(tau), tau)


def test_mismatched_prony_lengths_are_refused():
    with pytest.raises(ValueError, match=r"one value per Prony term, got shapes \(2,\) and \(1,\)"):
        check_prony([1.0, 2.0], [1.0])


@pytest.mark.parametrize("E_inf", [0.0, -1.0, np.nan])
def test_prony_g_needs_a_positive_long_term_modulus(E_inf):
    with pytest.raises(ValueError, match="E_inf = .* must be > 0"):
        prony_g(E_inf, [1.0])


@pytest.mark.parametrize("g", [[0.5, 0.5], [0.7, 0.4], [-0.1]])
def test_from_dimensionless_refuses_impossible_weights(g):
    with pytest.raises(ValueError, match=r"g = .*: weights must be >= 0 with sum\(g\) < 1"):
        from_dimensionless(g, E_inf=1.0)


@pytest.mark.parametrize("kw", [{}, {"E_inf": 1.0, "E_0": 2.0}])
def test_from_dimensionless_needs_exactly_one_modulus(kw):
    with pytest.raises(ValueError, match="give exactly one of E_inf .* or E_0"):
        from_dimensionless([0.5], **kw)
