"""Example budgets of the accuracy property tests, and a check that each is met.

An accuracy test compares the code with a closed form or a quadrature reference on
cases Hypothesis draws. In CI (the ``ci`` profile of conftest.py) each must check at
least ``ACCURACY_EXAMPLES`` *valid* cases: :func:`accuracy` sets the test's
``max_examples`` (or the profile's, if larger: the ``long`` profile draws 1000), counts
the examples that ran to the end and fails the test if fewer did, or if ``assume``
discarded 20 % or more of those that reached the test body. The strategies generate
valid cases directly, so the discard share is normally zero.
"""

from __future__ import annotations

import functools

from hypothesis import settings
from hypothesis.errors import UnsatisfiedAssumption

#: Valid cases every accuracy property test checks in CI.
ACCURACY_EXAMPLES = 50
#: Largest share of the examples reaching the test body that ``assume`` may discard.
MAX_DISCARDED = 0.2


def accuracy(test=None, *, examples: int = ACCURACY_EXAMPLES):
    """Decorate a ``@given`` test (above ``@given``): run and check its example budget."""
    if test is None:
        return functools.partial(accuracy, examples=examples)
    budget = max(examples, settings.default.max_examples)
    test = settings(max_examples=budget)(test)
    inner = test.hypothesis.inner_test
    seen = {"valid": 0, "discarded": 0}

    @functools.wraps(inner)
    def counted(*args, **kwargs):
        try:
            result = inner(*args, **kwargs)
        except UnsatisfiedAssumption:
            seen["discarded"] += 1
            raise
        seen["valid"] += 1
        return result

    test.hypothesis.inner_test = counted

    @functools.wraps(test)
    def run(*args, **kwargs):
        seen.update(valid=0, discarded=0)
        test(*args, **kwargs)
        valid, discarded = seen["valid"], seen["discarded"]
        assert valid >= budget, f"only {valid} valid examples of the {budget} required"
        assert discarded < MAX_DISCARDED * (valid + discarded), (
            f"assume discarded {discarded} of {valid + discarded} examples")

    return run
