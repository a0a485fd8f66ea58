"""The example budget of the accuracy property tests (tests/_budget.py) is enforced."""

from __future__ import annotations

import pytest
from _budget import ACCURACY_EXAMPLES, accuracy
from hypothesis import assume, given
from hypothesis import strategies as st


def test_an_accuracy_test_runs_at_least_the_budget():
    ran = []

    @accuracy
    @given(st.floats(0.05, 20.0))
    def check(x):
        ran.append(x)

    check()
    assert ACCURACY_EXAMPLES == 50 and len(ran) >= 50


def test_an_accuracy_test_fails_when_assume_discards_a_fifth():
    @accuracy
    @given(st.floats(0.0, 1.0))
    def check(x):
        assume(x >= 0.3)  # discards about 30 %

    with pytest.raises(AssertionError, match="assume discarded"):
        check()


def test_an_accuracy_test_fails_when_fewer_examples_run():
    @accuracy(examples=60)
    @given(st.sampled_from([1, 2, 3]))  # three distinct examples exhaust the search
    def check(k):
        pass

    with pytest.raises(AssertionError, match="valid examples of the 60 required"):
        check()
