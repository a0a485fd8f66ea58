"""Tests of vhfit.optimize.tau_bounds (SPEC §5, Eq. 22) and its strategy registry."""

from __future__ import annotations

import numpy as np
import pytest
from _budget import accuracy
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal

from vhfit.optimize import TauBounds, register_tau_strategy, tau_bounds, tau_range, tau_strategies
from vhfit.optimize._tau import _STRATEGIES

PAPER_RATES = [-1.0, -10.0, -100.0, -1000.0]


def test_eq22_range():
    # log10 tau_max = log10(1/min|r|) + 1 ; log10 tau_min = log10(1/max|r|) - 2
    assert tau_range(PAPER_RATES) == (-5.0, 1.0)
    a, b = tau_range([-0.0018, -0.18, -59.5, -820])  # the SEBS rates
    assert_allclose([a, b], [np.log10(1 / 820) - 2, np.log10(1 / 0.0018) + 1])
    assert tau_range([5.0], decades_above=0.5, decades_below=0.25) == pytest.approx(
        (np.log10(0.2) - 0.25, np.log10(0.2) + 0.5))


def test_three_strategies_on_the_papers_rates():
    free = tau_bounds(PAPER_RATES, 3, "free")
    assert_array_equal(np.asarray(free), [[-5, 1]] * 3)
    semi = tau_bounds(PAPER_RATES, 3)  # default: semifree
    assert semi.strategy == "semifree"
    assert_array_equal(np.asarray(semi), [[-5, -3], [-3, -1], [-1, 1]])
    fixed = tau_bounds(PAPER_RATES, 2, "fixed")
    assert_array_equal(np.asarray(fixed), [[-3, -3], [-1, -1]])
    assert fixed.fixed.all() and not semi.fixed.any()
    assert_allclose(fixed.tau(), [1e-3, 1e-1])


def test_paper_example_range_0_6():
    # the paper's example for 2 terms on [0, 6]: semifree [0,3],[3,6]; fixed 2 and 4
    rates = [10.0**-5]  # log10(1/r) = 5: range [5 - 5, 5 + 1] = [0, 6] with decades (1, 5)
    semi = tau_bounds(rates, 2, decades_above=1, decades_below=5)
    assert_array_equal(np.asarray(semi), [[0, 3], [3, 6]])
    fixed = tau_bounds(rates, 2, "fixed", decades_above=1, decades_below=5)
    assert_array_equal(np.asarray(fixed), [[2, 2], [4, 4]])


def test_taubounds_behaves_like_an_array_of_pairs():
    tb = tau_bounds(PAPER_RATES, 2)
    assert isinstance(tb, TauBounds) and len(tb) == 2 and tb.n_terms == 2
    assert list(tb) == [(-5.0, -2.0), (-2.0, 1.0)]
    assert tb[1] == (-2.0, 1.0)
    assert np.asarray(tb, dtype=np.float32).dtype == np.float32
    assert tb.log10_range == (-5.0, 1.0)
    assert "semifree" in repr(tb)
    # usable directly in a DE bounds list
    bounds = [(0.0, 1.0), *tb]
    assert len(bounds) == 3


@accuracy
@given(
    rates=st.lists(st.floats(1e-6, 1e6, allow_nan=False), min_size=1, max_size=6),
    n=st.integers(1, 8),
    above=st.floats(0.0, 3.0),
    below=st.floats(0.1, 3.0),
    signs=st.booleans(),
)
def test_strategy_invariants(rates, n, above, below, signs):
    r = np.array(rates) * (-1 if signs else 1)
    a, b = tau_range(r, above, below)
    free = np.asarray(tau_bounds(r, n, "free", above, below))
    semi = np.asarray(tau_bounds(r, n, "semifree", above, below))
    fixed = np.asarray(tau_bounds(r, n, "fixed", above, below))
    assert np.all(free == [a, b])
    # semifree: contiguous equal pieces covering [a, b]
    assert semi[0, 0] == pytest.approx(a) and semi[-1, 1] == pytest.approx(b)
    assert_allclose(semi[1:, 0], semi[:-1, 1])
    assert_allclose(np.diff(semi, axis=1), (b - a) / n, rtol=1e-9, atol=1e-12)
    # fixed: strictly inside (a, b), increasing, evenly spaced, lo == hi
    assert np.all(fixed[:, 0] == fixed[:, 1])
    assert np.all((fixed[:, 0] > a) & (fixed[:, 0] < b))
    assert_allclose(np.diff(fixed[:, 0]), (b - a) / (n + 1), rtol=1e-9, atol=1e-12)
    # one fixed tau in each semifree piece's closure
    assert np.all((fixed[:, 0] >= semi[:, 0] - 1e-12) & (fixed[:, 0] <= semi[:, 1] + 1e-12))


def test_registry_add_use_and_protect():
    name = "test_halves"
    try:
        @register_tau_strategy(name)
        def halves(a, b, n):
            m = 0.5 * (a + b)
            return np.array([[a, m]] * (n - 1) + [[m, b]])

        assert name in tau_strategies()
        assert_array_equal(np.asarray(tau_bounds(PAPER_RATES, 3, name)),
                           [[-5, -2], [-5, -2], [-2, 1]])
        with pytest.raises(ValueError, match="already registered"):
            register_tau_strategy(name, halves)
        register_tau_strategy(name, halves, overwrite=True)  # explicit replacement is fine
    finally:
        _STRATEGIES.pop(name, None)
    assert tau_strategies()[:3] == ("free", "semifree", "fixed")


def test_callable_strategy():
    tb = tau_bounds(PAPER_RATES, 2, lambda a, b, n: [[a, a + 1], [b - 1, b]])
    assert_array_equal(np.asarray(tb), [[-5, -4], [0, 1]])


@pytest.mark.parametrize(
    "rates, match",
    [([], "empty"), ([0.0, -1.0], "non-zero"), ([-1.0, np.nan], "finite"),
     ([np.inf], "finite"), ("fast", "numbers")],
)
def test_bad_rates(rates, match):
    with pytest.raises(ValueError, match=match):
        tau_bounds(rates, 2)


@pytest.mark.parametrize("n", [0, -1, 2.5, True, "3"])
def test_bad_n_terms(n):
    with pytest.raises(ValueError, match="n_terms"):
        tau_bounds(PAPER_RATES, n)


def test_unknown_strategy_lists_the_available_ones():
    with pytest.raises(ValueError, match="semifree") as e:
        tau_bounds(PAPER_RATES, 2, "loose")
    assert "'loose'" in str(e.value) and "fixed" in str(e.value)
    with pytest.raises(ValueError, match="strategy"):
        tau_bounds(PAPER_RATES, 2, 42)


@pytest.mark.parametrize(
    "f, match",
    [(lambda a, b, n: [[a, b]], "shape"), (lambda a, b, n: [[b, a]] * n, "lower bound above"),
     (lambda a, b, n: [[a, np.inf]] * n, "non-finite"), (lambda a, b, n: "x", "numeric")],
)
def test_bad_strategy_output(f, match):
    with pytest.raises(ValueError, match=match):
        tau_bounds(PAPER_RATES, 2, f)


def test_bad_decades_and_empty_range():
    with pytest.raises(ValueError, match="decades_above"):
        tau_bounds(PAPER_RATES, 2, decades_above=np.nan)
    with pytest.raises(ValueError, match="empty log10 tau range"):
        tau_bounds([-1.0], 2, decades_above=0, decades_below=0)
    with pytest.raises(ValueError, match="name"):
        register_tau_strategy("", lambda a, b, n: None)
