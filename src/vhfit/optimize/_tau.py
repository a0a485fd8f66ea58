"""Search bounds for the Prony relaxation times, in log10 τ (the paper's Eq. 22).

The paper: *Visco-hyperelastic material model fitting to experimental stress–strain
curves using a genetic algorithm and its application to soft tissue simulants*, §2.2.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["TauBounds", "tau_bounds", "tau_range", "register_tau_strategy", "tau_strategies"]

TauStrategy = Callable[[float, float, int], Any]

_STRATEGIES: dict[str, TauStrategy] = {}


@dataclass(frozen=True, eq=False)
class TauBounds:
    """Per-term bounds on log10 τ, as returned by :func:`tau_bounds`.

    Behaves as an array of shape (n_terms, 2) of ``(lower, upper)`` pairs
    (``np.asarray(tb)``, ``list(tb)``, ``tb[i]``), so it can be passed straight into
    a bounds list for :func:`~vhfit.optimize.differential_evolution`.

    Attributes
    ----------
    lower, upper : ndarray, shape (n_terms,)
        Bounds on log10(τ_i / s). Equal for a fixed τ_i.
    log10_range : tuple of float
        ``(a, b)``: the whole log10 τ range from Eq. 22.
    strategy : str
        Name of the strategy that produced the bounds.
    """

    lower: np.ndarray
    upper: np.ndarray
    log10_range: tuple[float, float]
    strategy: str

    @property
    def fixed(self) -> np.ndarray:
        """Boolean mask of the terms whose τ is fixed (lower == upper)."""
        return self.lower == self.upper

    @property
    def n_terms(self) -> int:
        """Number of Prony terms."""
        return int(self.lower.size)

    def to_array(self) -> np.ndarray:
        """The bounds as a float array of shape (n_terms, 2)."""
        return np.column_stack([self.lower, self.upper])

    def tau(self) -> np.ndarray:
        """Midpoints of the bounds converted to τ in seconds (the τ_i when fixed)."""
        return 10.0 ** (0.5 * (self.lower + self.upper))

    def __array__(self, dtype=None, copy=None):
        arr = self.to_array()
        return arr if dtype is None else arr.astype(dtype)

    def __len__(self) -> int:
        return self.n_terms

    def __iter__(self) -> Iterator[tuple[float, float]]:
        return iter(zip(self.lower.tolist(), self.upper.tolist(), strict=True))

    def __getitem__(self, i: int) -> tuple[float, float]:
        return float(self.lower[i]), float(self.upper[i])

    def __repr__(self) -> str:
        pairs = ", ".join(f"({lo:.4g}, {hi:.4g})" for lo, hi in self)
        return f"TauBounds(strategy={self.strategy!r}, log10 tau: [{pairs}])"


def tau_range(rates: Any, decades_above: float = 1.0,
              decades_below: float = 2.0) -> tuple[float, float]:
    """The log10 τ range ``(a, b)`` of the paper's Eq. 22 for the given strain rates.

    ``b = log10(1 / min|r|) + decades_above`` and
    ``a = log10(1 / max|r|) - decades_below``.

    Parameters
    ----------
    rates : array_like
        Strain rates in 1/s (sign ignored); non-empty, finite and non-zero.
    decades_above, decades_below : float, optional
        Decades added above the slowest and below the fastest time scale (paper: 1, 2).

    Returns
    -------
    (a, b) : tuple of float
        Lower and upper limit of log10(τ / s), ``a < b``.

    Raises
    ------
    ValueError
        For empty, zero or non-finite rates, non-finite decades, or an empty range.

    Examples
    --------
    >>> from vhfit.optimize import tau_range
    >>> tau_range([-1, -10, -100, -1000])
    (-5.0, 1.0)
    """
    try:
        r = np.abs(np.asarray(rates, dtype=float)).ravel()
    except (TypeError, ValueError):
        raise ValueError(f"rates must be numbers (strain rates in 1/s), got {rates!r}") from None
    if r.size == 0:
        raise ValueError("rates is empty: give at least one strain rate")
    if not np.all(np.isfinite(r)):
        raise ValueError(f"rates must be finite, got {np.asarray(rates).tolist()!r}")
    if np.any(r == 0):
        raise ValueError("rates must be non-zero (a zero strain rate has no time scale)")
    for name, v in (("decades_above", decades_above), ("decades_below", decades_below)):
        try:
            ok = math.isfinite(float(v))
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ValueError(f"{name} must be a finite number, got {v!r}")
    b = float(-np.log10(r.min()) + float(decades_above))
    a = float(-np.log10(r.max()) - float(decades_below))
    if not b > a:
        raise ValueError(
            f"empty log10 tau range [{a:g}, {b:g}]: increase decades_above/decades_below")
    return a, b


def register_tau_strategy(name: str, func: TauStrategy | None = None, *,
                          overwrite: bool = False):
    """Register a τ-bound strategy under `name` (usable as a decorator).

    A strategy is a callable ``f(a, b, n_terms)`` that receives the log10 τ range
    ``[a, b]`` of Eq. 22 and the number of Prony terms, and returns an array of shape
    ``(n_terms, 2)`` of ``(lower, upper)`` log10 τ bounds per term (equal for a fixed
    τ). Returned bounds are checked: finite, ``lower <= upper``.

    Parameters
    ----------
    name : str
        Name to use as ``tau_bounds(..., strategy=name)``.
    func : callable, optional
        The strategy; omit to use as a decorator.
    overwrite : bool, optional
        Allow replacing an existing strategy of that name. Default False.

    Returns
    -------
    callable
        `func` (unchanged), or the decorator.

    Raises
    ------
    ValueError
        If `name` is taken and `overwrite` is False, or `name` is not a non-empty str.

    Examples
    --------
    >>> import numpy as np
    >>> from vhfit.optimize import register_tau_strategy, tau_bounds
    >>> @register_tau_strategy("overlapping")
    ... def overlapping(a, b, n):
    ...     # each term spans two neighbouring pieces of the semi-free split
    ...     edges = np.linspace(a, b, n + 2)
    ...     return np.column_stack([edges[:-2], edges[2:]])
    >>> np.asarray(tau_bounds([-1, -1000], 2, strategy="overlapping"))
    array([[-5., -1.],
           [-3.,  1.]])
    """
    if not isinstance(name, str) or not name:
        raise ValueError(f"name must be a non-empty string, got {name!r}")

    def decorator(f: TauStrategy) -> TauStrategy:
        if not callable(f):
            raise ValueError(f"tau strategy {name!r} must be callable, got {f!r}")
        if name in _STRATEGIES and not overwrite:
            raise ValueError(
                f"tau strategy {name!r} is already registered; pass overwrite=True to replace it")
        _STRATEGIES[name] = f
        return f

    return decorator if func is None else decorator(func)


def tau_strategies() -> tuple[str, ...]:
    """Names of the registered τ-bound strategies."""
    return tuple(_STRATEGIES)


@register_tau_strategy("free")
def _free(a: float, b: float, n: int) -> np.ndarray:
    """Every τ_i anywhere in [a, b]."""
    return np.tile([a, b], (n, 1))


@register_tau_strategy("semifree")
def _semifree(a: float, b: float, n: int) -> np.ndarray:
    """[a, b] cut into n equal consecutive pieces, one per term."""
    edges = np.linspace(a, b, n + 1)
    return np.column_stack([edges[:-1], edges[1:]])


@register_tau_strategy("fixed")
def _fixed(a: float, b: float, n: int) -> np.ndarray:
    """τ_i fixed at a + (b - a) i / (n + 1), i = 1..n."""
    t = a + (b - a) * np.arange(1, n + 1) / (n + 1)
    return np.column_stack([t, t])


def tau_bounds(rates: Any, n_terms: int, strategy: str | TauStrategy = "semifree",
               decades_above: float = 1, decades_below: float = 2) -> TauBounds:
    """Per-term bounds on log10 τ of the Prony terms (the paper's §2.2, Eq. 22).

    The whole range is ``[a, b]`` with ``b = log10(1 / min|r|) + decades_above`` and
    ``a = log10(1 / max|r|) - decades_below`` (:func:`tau_range`). Strategies:

    - ``"free"``: every τ_i in [a, b];
    - ``"semifree"``: [a, b] cut into `n_terms` equal consecutive pieces, one per
      term (the paper's best strategy; also removes the terms' permutation symmetry);
    - ``"fixed"``: τ_i fixed at ``a + (b - a) i / (n_terms + 1)``; only the G_i are
      searched (lower == upper);
    - a name registered with :func:`register_tau_strategy`, or a callable
      ``f(a, b, n_terms) -> (n_terms, 2)`` array.

    Search τ in log10 with these bounds: differential evolution (SciPy's strategies)
    replaces an out-of-bounds component by a uniform draw over the whole range, which
    is uniform in decades only in log10.

    Parameters
    ----------
    rates : array_like
        Strain rates of the test curves in 1/s (sign ignored): non-empty, finite,
        non-zero.
    n_terms : int
        Number of Prony terms, >= 1.
    strategy : str or callable, optional
        ``"semifree"`` (default), ``"free"``, ``"fixed"``, a registered name, or a
        callable.
    decades_above, decades_below : float, optional
        Decades beyond the slowest / fastest time scale (paper: 1 and 2).

    Returns
    -------
    TauBounds
        Per-term ``(lower, upper)`` bounds in log10(τ / s); ``np.asarray`` gives
        shape (n_terms, 2).

    Raises
    ------
    ValueError
        For empty, zero or non-finite rates, ``n_terms < 1``, an unknown strategy
        (the message lists the registered ones) or a strategy returning bad bounds.

    References
    ----------
    .. [1] *Visco-hyperelastic material model fitting to experimental stress–strain
       curves using a genetic algorithm and its application to soft tissue simulants*,
       §2.2 "Genetic algorithm", Eq. 22.

    Examples
    --------
    The paper's rates for Random_3, three semi-free terms:

    >>> import numpy as np
    >>> from vhfit.optimize import tau_bounds
    >>> tb = tau_bounds([-1, -10, -100, -1000], 3)
    >>> np.asarray(tb)
    array([[-5., -3.],
           [-3., -1.],
           [-1.,  1.]])
    >>> np.asarray(tau_bounds([-1, -1000], 2, "fixed"))
    array([[-3., -3.],
           [-1., -1.]])
    """
    if (isinstance(n_terms, bool) or not isinstance(n_terms, (int, np.integer))
            or n_terms < 1):
        raise ValueError(f"n_terms must be an integer >= 1, got {n_terms!r}")
    n = int(n_terms)
    a, b = tau_range(rates, decades_above, decades_below)
    if isinstance(strategy, str):
        try:
            f = _STRATEGIES[strategy]
        except KeyError:
            raise ValueError(
                f"strategy: unknown tau strategy {strategy!r}; available: "
                f"{list(_STRATEGIES)} (or register one with register_tau_strategy)") from None
        name = strategy
    elif callable(strategy):
        f = strategy
        # getattr default: a callable (functools.partial, an instance) may have no name
        name = getattr(strategy, "__name__", type(strategy).__name__)
    else:
        raise ValueError(
            f"strategy must be a name in {list(_STRATEGIES)} or a callable, got {strategy!r}")
    try:
        out = np.asarray(f(a, b, n), dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"tau strategy {name!r} did not return numeric bounds: {exc}") from exc
    if out.shape != (n, 2):
        raise ValueError(
            f"tau strategy {name!r} returned shape {out.shape}, expected ({n}, 2)")
    if not np.all(np.isfinite(out)):
        raise ValueError(f"tau strategy {name!r} returned non-finite bounds")
    if np.any(out[:, 0] > out[:, 1]):
        raise ValueError(f"tau strategy {name!r} returned a lower bound above its upper bound")
    return TauBounds(lower=out[:, 0].copy(), upper=out[:, 1].copy(), log10_range=(a, b),
                     strategy=name)
