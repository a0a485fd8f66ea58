"""Shared pytest configuration: Hypothesis profiles.

Two profiles are registered:

``ci`` (the default)
    Derandomised (the same examples on every run and every machine, no example
    database written to disk), no per-example deadline (the first call of a numba
    kernel compiles or loads its cache) and no wall-clock health check (a loaded
    machine is not a failed test), and a small example budget so that the
    whole suite stays fast. Accuracy property tests (comparisons with closed forms
    and quadrature) draw at least 50 valid cases each instead, whatever the
    profile: ``tests/_budget.py`` sets and checks their budget.
``long``
    Random, many examples, for a thorough search run by hand::

        pytest --hypothesis-profile=long

The profile can also be chosen with the ``HYPOTHESIS_PROFILE`` environment variable;
``--hypothesis-profile`` on the command line takes precedence.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci",
    max_examples=20,
    derandomize=True,
    database=None,
    deadline=None,
    print_blob=True,
    # the "too slow" health check times data generation against the wall clock: on a
    # loaded machine it would fail a test for the machine's load, not for the test
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "long",
    max_examples=1000,
    derandomize=False,
    deadline=None,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
