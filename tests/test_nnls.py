"""vhfit's NNLS entry point: SciPy's answer to the bit, cheaper."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import nnls as scipy_nnls

from vhfit import _nnls


@settings(max_examples=60, deadline=None)
@given(m=st.integers(1, 40), n=st.integers(1, 7), seed=st.integers(0, 2**32 - 1),
       scale=st.floats(1e-6, 1e6))
def test_the_same_answer_as_scipy_to_the_bit(m, n, seed, scale):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(m, n)) * scale
    b = rng.normal(size=m)
    x, r = _nnls.nnls(A, b)
    x_ref, r_ref = scipy_nnls(A, b)
    assert np.array_equal(x, x_ref) and r == r_ref
    assert np.all(x >= 0)


def test_other_layouts_take_scipys_own_function():
    rng = np.random.default_rng(1)
    A = np.asfortranarray(rng.normal(size=(12, 3)))
    b = rng.normal(size=12)
    x, r = _nnls.nnls(A, b)
    x_ref, r_ref = scipy_nnls(A, b)
    assert np.array_equal(x, x_ref) and r == r_ref
    x, r = _nnls.nnls(A[:, ::2], b.astype(np.float32))
    assert np.array_equal(x, scipy_nnls(A[:, ::2], b.astype(np.float32))[0])


def test_bad_input_and_the_iteration_cap_raise_as_scipy_does():
    A = np.eye(3)
    with pytest.raises(ValueError, match="infs or NaNs"):
        _nnls.nnls(A, np.array([1.0, np.nan, 0.0]))
    rng = np.random.default_rng(3)
    A, b = rng.normal(size=(30, 8)), rng.normal(size=30)
    with pytest.raises(RuntimeError, match="Maximum number of iterations"):
        _nnls.nnls(A, b, maxiter=1)


def test_a_core_is_used_only_if_it_answers_as_scipy_does():
    """The private core is checked against the public function once: one whose answer
    differs (or that fails) is not used, and then every call takes the public one."""
    def wrong(A, b, maxiter):
        return np.zeros(A.shape[1]), 0.0, 1

    def failing(A, b, maxiter):
        raise TypeError("another signature")

    assert not _nnls.answers_alike(wrong, scipy_nnls)
    assert not _nnls.answers_alike(failing, scipy_nnls)
    assert _nnls._lookup(wrong) is False and _nnls._lookup(failing) is False
    import scipy.optimize._nnls as private

    core = getattr(private, "_nnls", None)  # SciPy 1.15-1.17 have it; a later one may not
    if core is not None:
        assert _nnls.answers_alike(core, scipy_nnls)
        # the code by which it says it hit its cap differs between versions (-1, 3)
        assert _nnls.cap_code(core, scipy_nnls) is not None


def test_without_the_core_the_public_function_answers(monkeypatch):
    monkeypatch.setattr(_nnls, "_core", False)
    rng = np.random.default_rng(5)
    A, b = rng.normal(size=(9, 3)), rng.normal(size=9)
    x, r = _nnls.nnls(A, b)
    assert np.array_equal(x, scipy_nnls(A, b)[0]) and r == scipy_nnls(A, b)[1]
