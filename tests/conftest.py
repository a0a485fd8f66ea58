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

import contextlib
import os

import numba
import numpy as np
import pytest
from hypothesis import HealthCheck, settings

# numba reads its thread count again at every compile (NUMBA_NUM_THREADS, else the CPUs
# of the process's affinity) and raises once its thread pool has started if that count
# changed: a full run on this 2-core machine failed so in nine tests whose kernels
# compiled late ("currently have 1, trying to set 2"). The count read at start-up is
# kept for the whole run (the same value; subprocesses inherit it)
os.environ.setdefault("NUMBA_NUM_THREADS", str(numba.config.NUMBA_NUM_THREADS))

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


@pytest.fixture(scope="session")
def write_ramps():
    """``write_ramps(folder, model, params, rates=(-1, -30, -1000))``: a model's noise-free
    constant-rate ramps (engineering strain 0 to -0.5, 21 points, one CSV file a rate with
    a ``# strain_rate:`` line) written into ``folder``; returns their paths."""

    def write(folder, model, params, rates=(-1.0, -30.0, -1000.0)) -> list[str]:
        paths = []
        for r in rates:
            eps = np.linspace(0.0, -0.5, 21)
            s = model.stress(params, strain=eps, strain_rate=r, measure="engineering")
            path = folder / f"ramp_{-r:g}.csv"
            path.write_text(f"# strain_rate: {r}\nstrain,stress_MPa\n"
                            + "".join(f"{float(e)!r},{float(v)!r}\n" for e, v in zip(eps, s)))
            paths.append(str(path))
        return paths

    return write


@pytest.fixture
def ctrl_c_in_fit(monkeypatch):
    """``with ctrl_c_in_fit(n): cli.main([...])``: the ``vhfit fit`` run in this process
    inside the block behaves as if Ctrl-C came during its n-th generation."""
    from vhfit import cli

    @contextlib.contextmanager
    def cut(n: int = 3):
        calls = []

        def check(self):
            calls.append(1)
            if len(calls) >= n:
                self.stopped_search = True
                raise KeyboardInterrupt

        with monkeypatch.context() as m:
            m.setattr(cli._fit.Signals, "check", check)
            yield

    return cut


@pytest.fixture(autouse=True)
def _fresh_nesting_cache():
    """Each test starts as in a fresh process: no fit remembered by an earlier test seeds
    its fits (vhfit.calibration._nesting), whatever order the tests run in."""
    import sys

    nesting = sys.modules.get("vhfit.calibration._nesting")  # (not loaded: nothing kept)
    if nesting is not None:
        nesting.clear_cache()
    yield
