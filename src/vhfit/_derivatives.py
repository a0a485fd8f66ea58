"""Derivatives of strain energies: the complex step, with a central-difference fallback.

The complex step f'(0) = Im f(i h) / h has no subtraction, so a tiny step (h = 1e-30)
is exact to rounding for any energy written with numpy's analytic functions. An energy
that rejects complex input (``np.floor``, ``np.logaddexp``, ...) falls back to a
fourth-order central difference with h = 1e-3. Both :mod:`vhfit.hyperelastic` (the
uniaxial stress) and :mod:`vhfit.stability` (the principal stresses of the three test
modes) take their derivatives here. See docs/theory.md §2.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

__all__ = ["H", "central", "derivatives", "outside_domain", "invariant_gradient",
           "stretch_gradient"]

H = 1e-30  # complex step: no subtractive cancellation, so any tiny step is exact


def central(f: Callable[[float], np.ndarray], h: float = 1e-3) -> np.ndarray:
    """Fourth-order central difference f'(0), for energies that reject complex input.

    Examples
    --------
    >>> round(float(central(lambda d: (1.0 + d) ** 3)), 12)   # d/dx x³ at x = 1
    3.0
    """
    return (8.0 * (f(h) - f(-h)) - (f(2 * h) - f(-2 * h))) / (12.0 * h)


def derivatives(fs: Sequence[Callable]) -> list[np.ndarray]:
    """f'(0) of each f by the complex step, or all by :func:`central` if one rejects complex input.

    One method for all of them, so that the partial derivatives of one energy are
    always taken the same way.

    Examples
    --------
    >>> [round(float(x), 12) for x in derivatives([lambda d: np.exp(2.0 + d),
    ...                                             lambda d: (3.0 + d) ** 2])]
    [7.389056098931, 6.0]
    """
    try:
        return [np.imag(f(1j * H)) / H for f in fs]
    except TypeError:
        return [central(f) for f in fs]


def outside_domain(energy: Callable, *args) -> np.ndarray:
    """Where the real energy is not finite (e.g. Gent past its locking stretch).

    The complex step continues W analytically past the edge of its real domain (the
    complex log of a negative number is finite), so its derivatives there would be
    finite garbage; callers set them to NaN instead.
    """
    with np.errstate(all="ignore"):
        return ~np.isfinite(energy(*args))


def invariant_gradient(energy: Callable, closed_form: Callable | None, I1, I2,
                       cols: Sequence) -> tuple[np.ndarray, np.ndarray]:
    """(∂W/∂I1, ∂W/∂I2) of an invariant energy W(I1, I2, *cols).

    ``closed_form`` (I1, I2, *cols) -> (W1, W2), when given, is used as is; otherwise
    the complex step, NaN where W itself is not finite.

    Examples
    --------
    >>> W = lambda I1, I2, c10, c01: c10 * (I1 - 3) + c01 * (I2 - 3)
    >>> [float(w) for w in invariant_gradient(W, None, 3.5, 3.2, [0.1, 0.05])]
    [0.1, 0.05]
    """
    if closed_form is not None:
        return closed_form(I1, I2, *cols)
    W1, W2 = derivatives([lambda d: energy(I1 + d, I2, *cols),
                          lambda d: energy(I1, I2 + d, *cols)])
    bad = outside_domain(energy, I1, I2, *cols)
    return np.where(bad, np.nan, W1), np.where(bad, np.nan, W2)


def stretch_gradient(energy: Callable, l1, l2, l3, cols: Sequence,
                     axes: Sequence[int] = (0, 1, 2),
                     closed_form: Callable | None = None) -> list[np.ndarray]:
    """λa ∂W/∂λa of a principal-stretch energy W(l1, l2, l3, *cols), for a in ``axes``.

    ``closed_form`` (l1, l2, l3, *cols) -> (λ1 ∂W/∂λ1, λ2 ∂W/∂λ2, λ3 ∂W/∂λ3), when given,
    is used as is; otherwise the complex step, relative (λa (1 + d)), which gives
    λa ∂W/∂λa directly.

    Examples
    --------
    >>> W = lambda l1, l2, l3, mu: mu / 2 * (l1**2 + l2**2 + l3**2 - 3)   # neo-Hooke
    >>> [float(x) for x in stretch_gradient(W, 2.0, 1.0, 0.5, [1.0])]   # mu λa²
    [4.0, 1.0, 0.25]
    """
    if closed_form is not None:
        d = closed_form(l1, l2, l3, *cols)
        return [d[a] for a in axes]
    lam = [l1, l2, l3]

    def along(a: int) -> Callable:
        def f(d):
            args = list(lam)
            args[a] = lam[a] * (1 + d)
            return energy(*args, *cols)
        return f

    return derivatives([along(a) for a in axes])
