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


# ------------------------------------------- relaxation times just outside the window
# The documented grid (docs/dma.md): τ per decade (10^(k/p), p = per_decade) spanning
# the data window [lo, hi] — 1/(2π f_max) to 1/(2π f_min), or t_min to t_max — one
# decade beyond each end: the smallest such grid covering [lo/10, 10 hi], so its ends
# are 10^(k0/p), k0 = floor(p log10(lo/10)), and 10^(k1/p), k1 = ceil(p log10(10 hi)).
LO, HI = 1.5e-3, 15.0  # s: a window whose ends are not whole decades
WINDOW_F = np.logspace(math.log10(1 / (2 * math.pi * HI)), math.log10(1 / (2 * math.pi * LO)),
                       41)
WINDOW_T = np.logspace(math.log10(LO), math.log10(HI), 41)


def grid_ends(p):
    return math.floor(p * math.log10(LO / 10)), math.ceil(p * math.log10(10 * HI))


def best_error_on(grid, domain, x, data):
    """The smallest RMS relative error any non-negative Prony series on ``grid`` reaches
    (NNLS on the relative residuals, columns written here from the moduli)."""
    from scipy.optimize import nnls

    if domain == "time":
        A = np.column_stack([np.ones_like(x), np.exp(-x[:, None] / grid)])
    else:
        wt = 2 * math.pi * x[:, None] * grid
        A = np.vstack([np.column_stack([np.ones_like(x), wt**2 / (1 + wt**2)]),
                       np.column_stack([np.zeros_like(x), wt / (1 + wt**2)])])
    coef, _ = nnls(A / data[:, None], np.ones_like(data), maxiter=100 * A.shape[1])
    return float(np.sqrt(np.mean(((A @ coef - data) / data) ** 2)))


@pytest.mark.parametrize("p", [1, 2, 3])
def test_grid_reaches_one_decade_beyond_each_end_of_a_sweeps_window(p):
    """Exact moduli with one τ at each end of the documented grid (1.2 decades below
    1/(2π f_max); 1.2 to 1.8 decades above 1/(2π f_min), by p) and one inside: the grid
    has the documented size, the spectrum finds the three τ exactly and fits to
    rounding."""
    k0, k1 = grid_ends(p)
    tau = np.array([10.0 ** (k0 / p), 0.1, 10.0 ** (k1 / p)])
    assert tau[0] < LO / 10 and tau[2] > 10 * HI  # both outside the data window
    e1, e2 = moduli(WINDOW_F, tau=tau)
    s = prony_spectrum(frequency=WINDOW_F, storage=e1, loss=e2, per_decade=p, n_prony=3)
    assert s.table[0, 0] == k1 - k0 + 1
    np.testing.assert_allclose(s.tau, tau, rtol=1e-12)
    np.testing.assert_allclose(s.G, G, rtol=1e-8)
    assert s.error < 1e-10


def test_a_grid_one_decade_short_at_either_end_could_not_fit_those_data():
    """What the same exact data allow on a grid cut short by one decade, at the fast or
    the slow end: errors of 2.5 % and 5e-4 — the full grid's 1e-10 is out of reach."""
    k0, k1 = grid_ends(1)
    tau = np.array([10.0**k0, 0.1, 10.0**k1])
    e1, e2 = moduli(WINDOW_F, tau=tau)
    data = np.r_[e1, e2]
    full = prony_spectrum(frequency=WINDOW_F, storage=e1, loss=e2, tolerance=0.0)
    assert full.error < 1e-10
    assert best_error_on(10.0 ** np.arange(k0, k1 + 1), "frequency", WINDOW_F, data) < 1e-10
    for short in (np.arange(k0 + 1, k1 + 1), np.arange(k0, k1)):
        assert best_error_on(10.0**short, "frequency", WINDOW_F, data) > 1e-4


def test_relaxation_times_beyond_a_relaxation_tests_window_are_on_the_grid():
    """In time the window is [t_min, t_max]: the grid has the documented size, and a
    τ 1.8 decades after t_max (the slow end of the grid) is found exactly, where a grid
    one decade short at that end stays at 2e-5. (A τ below t_min/10 has decayed to
    e^−10 of its modulus by the first point, so the fast end shows only in the size.)"""
    k0, k1 = grid_ends(1)
    tau = np.array([1e-2, 1.0, 10.0**k1])
    E = E_INF + (G * np.exp(-WINDOW_T[:, None] / tau)).sum(1)
    s = prony_spectrum(time=WINDOW_T, modulus=E, n_prony=3)
    assert s.table[0, 0] == k1 - k0 + 1
    np.testing.assert_allclose(s.tau, tau, rtol=1e-12)
    assert s.error < 1e-10
    assert best_error_on(10.0 ** np.arange(k0, k1), "time", WINDOW_T, E) > 1e-5


def test_pruning_path_of_weighted_columns_keeps_the_true_terms_to_the_end():
    """Columns of E(t) on a decade grid 1e-3..1e3 s, data of E∞ = 1 and two of its terms
    (τ = 1e-2 and 10 s, G = 4 and 2): the path goes from 7 terms to 1, its residual never
    falls as terms go, the two-term step keeps exactly the true columns with the true
    moduli and zero residual, and the one-term step's residual is that of a direct NNLS
    on the column it kept."""
    from scipy.optimize import nnls

    from vhfit.spectrum import pruning_path

    t = np.logspace(-3, 3, 41)
    grid = 10.0 ** np.arange(-3, 4)
    A = np.column_stack([np.ones_like(t), np.exp(-t[:, None] / grid)])
    b = 1.0 + 4.0 * np.exp(-t / 1e-2) + 2.0 * np.exp(-t / 10.0)
    path = pruning_path(A, b)
    assert [k.size for k, _, _ in path] == list(range(7, 0, -1))
    errs = [e for _, _, e in path]
    assert all(e2 >= e1 - 1e-12 for e1, e2 in zip(errs, errs[1:]))
    keep, coef, err = path[5]
    assert keep.tolist() == [1, 4] and err < 1e-10
    np.testing.assert_allclose(coef, [1.0, 4.0, 2.0], rtol=1e-9)
    keep1, _, err1 = path[6]
    assert err1 == pytest.approx(nnls(A[:, [0, keep1[0] + 1]], b)[1], rel=1e-9)
