"""One BLAS thread for the spectrum route's small dense solves, restored afterwards."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.optimize  # noqa: F401  (scipy's OpenBLAS loaded too)

import vhfit
from vhfit import _blas
from vhfit.calibration import _spectrum


@pytest.fixture
def two_threads():
    """Every OpenBLAS of the process at 2 threads (skip where none is found), then back."""
    libs = _blas._libraries()
    if not libs:
        pytest.skip("no OpenBLAS found in this process")
    before = [get() for get, _ in libs]
    for _, put in libs:
        put(2)
    yield libs
    for (_, put), n in zip(libs, before):
        put(n)


def test_one_blas_thread_inside_the_block_and_the_setting_back_after(two_threads):
    with _blas.one_blas_thread():
        inside = [get() for get, _ in two_threads]
        with _blas.one_blas_thread():  # nested: still one, and the outer one restores
            nested = [get() for get, _ in two_threads]
        after_nested = [get() for get, _ in two_threads]
    assert inside == nested == after_nested == [1] * len(two_threads)
    assert [get() for get, _ in two_threads] == [2] * len(two_threads)


def threads_seen(monkeypatch, module, name: str, libs) -> list:
    """Replace ``module.name`` by a spy that records every library's BLAS threads at each
    call (then calls the real one); returns the list it fills."""
    seen = []
    real = getattr(module, name)

    def spy(*a, **kw):
        seen.append([get() for get, _ in libs])
        return real(*a, **kw)

    monkeypatch.setattr(module, name, spy)
    return seen


def test_the_spectrum_route_runs_with_one_blas_thread(two_threads, monkeypatch):
    seen = threads_seen(monkeypatch, _spectrum, "_spectrum_fit", two_threads)
    t = np.logspace(-2, 2, 20)
    item = vhfit.Relaxation(time=t, modulus=1.0 + np.exp(-t))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vhfit.calibrate([item], hyperelastic="neo_hooke", n_prony=1, seed=0)
    assert seen == [[1] * len(two_threads)]
    assert [get() for get, _ in two_threads] == [2] * len(two_threads)


@pytest.mark.parametrize("n_prony", [1, "auto"])
def test_the_global_search_runs_with_one_blas_thread(two_threads, monkeypatch, n_prony):
    from vhfit.calibration import _workflow

    seen = threads_seen(monkeypatch, _workflow, "run_search", two_threads)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    eps = np.linspace(-0.05, -0.4, 12)
    truth = dict(C10=0.2, C01=0.1, G1=1.0, tau1=0.01)
    curves = [vhfit.Curve(strain=eps, stress=m.stress(truth, strain=eps, strain_rate=r,
                                                      measure="engineering"), strain_rate=r)
              for r in (-1.0, -100.0)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vhfit.calibrate(curves, n_prony=n_prony, max_prony=2, seed=0, uncertainty=False)
    assert seen and all(s == [1] * len(two_threads) for s in seen)
    assert [get() for get, _ in two_threads] == [2] * len(two_threads)
