"""Non-negative least squares, the one entry point of vhfit: SciPy's solver, called cheaply.

A separable search solves one NNLS per member and generation — some 14 000 small
problems (a few hundred rows, 2–6 columns) per N on a long record — and
:func:`scipy.optimize.nnls` spends more time checking and converting its arguments
than its compiled core spends solving. :func:`nnls` hands arrays that are already
float64, C-ordered and finite straight to that core (``scipy.optimize._nnls._nnls``,
the same Lawson–Hanson routine with the same default iteration cap): the same numbers
to the bit, at about a fifth of the cost. A first check learns how the core says it
reached its cap (its ``info``: −1 in SciPy 1.15, 3 in 1.17) and that it answers like the
public function; where this SciPy has no such core, or the check fails, the public
function is used.
"""

from __future__ import annotations

import numpy as np

__all__ = ["nnls"]

_core = None  # None: not looked up yet; False: use the public function; else (core, cap)


def answers_alike(core, public) -> bool:
    """Whether ``core(A, b, maxiter)`` answers a small problem with an active bound as
    ``public(A, b)`` does, to the bit (any exception: no)."""
    A = np.array([[1.0, 0.5], [0.2, 1.0], [0.3, -0.4]])
    b = np.array([1.0, -2.0, 0.5])
    try:
        x, rnorm, info = core(A, b, 6)
        x_pub, r_pub = public(A, b)
        return np.array_equal(x, x_pub) and float(rnorm) == float(r_pub)
    except Exception:  # noqa: BLE001 - any surprise: the public function
        return False


def cap_code(core, public):
    """The ``info`` by which ``core`` says it reached its iteration cap (SciPy 1.15: −1,
    1.17: 3): the one it returns where ``public`` raises for the cap. None if that cannot
    be told (the public function then answers every call)."""
    A, b = np.eye(8), np.ones(8)  # NNLS adds one variable an iteration: 8 are needed
    try:
        public(A, b, maxiter=1)
        return None  # no cap reached where one must be: nothing to learn it from
    except RuntimeError:
        pass
    except Exception:  # noqa: BLE001
        return None
    try:
        capped, done = int(core(A, b, 1)[2]), int(core(A, b, 16)[2])
    except Exception:  # noqa: BLE001 - the core takes other arguments: the public one
        return None
    return capped if done != capped else None


def _lookup(core=None):
    """(SciPy's compiled NNLS core, or ``core``; its cap code) if it answers like
    :func:`scipy.optimize.nnls`; else False."""
    from scipy.optimize import nnls as public

    if core is None:
        try:
            from scipy.optimize._nnls import _nnls as core  # private: checked below
        except ImportError:
            return False
    cap = cap_code(core, public)
    return (core, cap) if cap is not None and answers_alike(core, public) else False


def nnls(A: np.ndarray, b: np.ndarray, maxiter: int | None = None) -> tuple[np.ndarray, float]:
    """``argmin ||A x − b||₂`` over x ≥ 0: (x, ||A x − b||₂), as :func:`scipy.optimize.nnls`.

    Parameters
    ----------
    A : (m, n) ndarray
        float64; any order (a copy in C order is made if needed).
    b : (m,) ndarray
        float64.
    maxiter : int, optional
        Iteration cap (default 3 n, SciPy's).

    Returns
    -------
    x : (n,) ndarray
    rnorm : float

    Raises
    ------
    RuntimeError
        The iteration cap was reached (as SciPy's function).
    ValueError
        A or b holds a NaN or an infinity (as SciPy's function).

    Examples
    --------
    >>> import numpy as np
    >>> x, r = nnls(np.array([[1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), np.array([2.0, 1.0, 1.0]))
    >>> np.round(x, 12).tolist(), round(r, 12)
    ([1.5, 1.0], 0.707106781187)
    """
    global _core
    if _core is None:
        _core = _lookup()
    if (_core is False or A.dtype != np.float64 or b.dtype != np.float64 or A.ndim != 2
            or b.ndim != 1 or not A.flags.c_contiguous or not b.flags.c_contiguous):
        from scipy.optimize import nnls as public

        return public(A, b, maxiter=maxiter) if maxiter else public(A, b)
    if not (np.isfinite(A).all() and np.isfinite(b).all()):
        raise ValueError("array must not contain infs or NaNs")
    core, cap = _core
    x, rnorm, info = core(A, b, maxiter or 3 * A.shape[1])
    if info == cap:
        raise RuntimeError("Maximum number of iterations reached.")
    return x, rnorm
