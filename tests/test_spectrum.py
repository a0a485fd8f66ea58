"""Prony spectrum (vhfit.spectrum): per-decade NNLS, pruning, error against N.
References: the generalised Maxwell moduli written here from docs/theory.md §3."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vhfit.spectrum import PronySpectrum, design_matrix, prony_spectrum, rms_relative_error

E_INF = 2.0
G = np.array([50.0, 20.0, 8.0])
TAU = np.array([1e-3, 1e-1, 1e1])


def moduli(f, E_inf=E_INF, g=G, tau=TAU):
    wt = 2 * math.pi * np.asarray(f)[:, None] * tau
    return E_inf + (g * wt**2 / (1 + wt**2)).sum(1), (g * wt / (1 + wt**2)).sum(1)


def test_grid_spectrum_recovers_a_series_whose_times_lie_on_the_grid():
    f = np.logspace(-3, 4, 71)
    e1, e2 = moduli(f)
    s = prony_spectrum(frequency=f, storage=e1, loss=e2, tolerance=0.0)
    assert s.error < 1e-10
    big = s.G > 1e-8 * s.G.max()
    np.testing.assert_allclose(s.tau[big], TAU, rtol=1e-12)
    np.testing.assert_allclose(s.G[big], G, rtol=1e-8)
    assert s.E_inf == pytest.approx(E_INF, rel=1e-8)


def test_pruning_reaches_the_true_number_of_terms_and_reports_error_against_n():
    f = np.logspace(-3, 4, 71)
    e1, e2 = moduli(f)
    s = prony_spectrum(frequency=f, storage=e1, loss=e2, tolerance=0.05)
    assert s.n_prony == 3
    n = s.table[:, 0]
    assert n[0] == len(n) and n[-1] == 1 and np.all(np.diff(n) == -1)
    assert s.table[n == 2, 1][0] > 1e-3  # two terms cannot represent three


def test_refined_times_recover_an_off_grid_series_in_time():
    tau = np.array([3e-3, 0.4, 25.0])
    t = np.logspace(-4, 3, 80)
    E = E_INF + (G * np.exp(-t[:, None] / tau)).sum(1)
    s = prony_spectrum(time=t, modulus=E, n_prony=3, refine=True)
    np.testing.assert_allclose(s.tau, tau, rtol=1e-6)
    np.testing.assert_allclose(s.G, G, rtol=1e-6)
    assert s.domain == "time" and s.params()["tau3"] == pytest.approx(25.0, rel=1e-6)


def test_rms_relative_error_is_that_of_storage_and_loss_rows_together():
    f = np.array([0.01, 1.0, 100.0])
    e1, e2 = moduli(f)
    data = np.concatenate([e1 * 1.1, e2])  # 10 % high on the three E' points only
    err = rms_relative_error("frequency", f, data, E_INF, G, TAU)
    expected = math.sqrt(3 * (1 / 1.1 - 1) ** 2 / 6)
    assert err == pytest.approx(expected, rel=1e-12)


def test_design_matrix_columns_are_the_unit_maxwell_terms():
    A = design_matrix("frequency", np.array([1 / (2 * math.pi)]), np.array([1.0]))
    np.testing.assert_allclose(A, [[1.0, 0.5], [0.0, 0.5]], rtol=1e-15)
    A = design_matrix("time", np.array([2.0]), np.array([2.0]))
    np.testing.assert_allclose(A, [[1.0, math.exp(-1)]], rtol=1e-15)


def test_items_with_attributes_are_accepted_and_bad_data_refused():
    class Sweep:
        frequency = np.logspace(-2, 2, 9)
        storage, loss = moduli(frequency)

    s = prony_spectrum(Sweep(), n_prony=2)
    assert isinstance(s, PronySpectrum) and s.n_prony == 2 and "N =" in s.summary()
    with pytest.raises(ValueError, match="loss"):
        prony_spectrum(frequency=[1.0, 2.0], storage=[1.0, 2.0], loss=[0.0, 1.0])
    with pytest.raises(ValueError, match="n_prony"):
        prony_spectrum(Sweep(), n_prony=0)
    with pytest.raises(ValueError, match="per_decade"):
        prony_spectrum(Sweep(), per_decade=0)


def test_the_chosen_n_is_the_smallest_within_the_stated_error_increase():
    rng = np.random.default_rng(0)
    f = np.logspace(-3, 4, 71)
    e1, e2 = moduli(f)
    noisy = dict(frequency=f, storage=e1 * (1 + 0.02 * rng.standard_normal(f.size)),
                 loss=e2 * (1 + 0.02 * rng.standard_normal(f.size)))
    chosen = []
    for tol in (0.0, 0.01, 0.05, 30.0):
        s = prony_spectrum(**noisy, tolerance=tol)
        n, err = s.table[:, 0], s.table[:, 1]
        assert s.n_prony == n[err <= (1 + tol) * err[0]].min()
        chosen.append(s.n_prony)
    # noise makes every extra term worth a little: more terms at 0, the true 3 at 5 %,
    # one at a 30-fold error
    assert chosen[0] > chosen[1] > chosen[2] == 3 > chosen[3]
