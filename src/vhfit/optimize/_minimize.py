"""vhfit's differential evolution as a custom method of :func:`scipy.optimize.minimize`."""

from __future__ import annotations

import inspect
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.optimize import Bounds, OptimizeResult, OptimizeWarning

from vhfit.optimize._de import _parse_bounds, differential_evolution

__all__ = ["de"]


class _XOnlyCallback:
    """Adapt minimize's ``callback(xk)`` to DE's ``callback(intermediate_result)``."""

    def __init__(self, callback: Callable) -> None:
        self.callback = callback

    def __call__(self, intermediate_result: OptimizeResult):
        return self.callback(np.copy(intermediate_result.x))


def de(fun: Callable[..., Any], x0: Any, args: tuple = (), jac: Any = None, hess: Any = None,
       hessp: Any = None, bounds: Any = None, constraints: Any = (),
       callback: Callable | None = None, **options: Any) -> OptimizeResult:
    """Differential evolution as a :func:`scipy.optimize.minimize` method.

    Pass the function itself as the method:
    ``scipy.optimize.minimize(fun, x0, method=de, bounds=..., options={...})``.
    `options` are any keyword arguments of
    :func:`vhfit.optimize.differential_evolution` (``strategy``, ``maxiter``,
    ``popsize``, ``rng``, ``polish``, ``workers``, ``population_size``, ``stop``,
    ``history``, ``preset``, ...); minimize's ``tol`` becomes DE's ``tol``.

    Parameters
    ----------
    fun : callable
        Objective ``fun(x, *args) -> float``.
    x0 : array_like, shape (N,)
        Initial guess; it replaces one member of the initial population. Values
        outside the bounds are clipped to them (with an `OptimizeWarning`), as
        `minimize` does for its bounded methods.
    args : tuple, optional
        Extra arguments of `fun`.
    jac, hess, hessp : optional
        Not used by differential evolution (a `RuntimeWarning` says so if given).
    bounds : sequence or `~scipy.optimize.Bounds`
        Required: finite ``(min, max)`` per parameter.
    constraints : optional
        As `differential_evolution`'s `constraints` (constraint objects).
    callback : callable, optional
        ``callback(intermediate_result)`` (an `OptimizeResult`) or minimize's
        ``callback(xk)``; returning True or raising `StopIteration` stops the run.
    **options
        Keyword arguments of :func:`~vhfit.optimize.differential_evolution`.

    Returns
    -------
    OptimizeResult
        The result of :func:`~vhfit.optimize.differential_evolution`.

    Raises
    ------
    ValueError
        Without `bounds`, or with bounds/`x0` that do not match; TypeError for an
        unknown option.

    See Also
    --------
    vhfit.optimize.differential_evolution

    Examples
    --------
    >>> from scipy.optimize import minimize, rosen
    >>> from vhfit.optimize import de
    >>> res = minimize(rosen, [0.5, 0.5], method=de, bounds=[(0, 2), (0, 2)],
    ...                options={"rng": 1, "popsize": 10})
    >>> bool(res.success), bool(abs(res.x - 1).max() < 1e-6)
    (True, True)
    """
    if bounds is None:
        raise ValueError("bounds: differential evolution needs finite bounds for every "
                         "parameter (minimize(..., method=de, bounds=[(lo, hi), ...]))")
    for name, value in (("jac", jac), ("hess", hess), ("hessp", hessp)):
        if value is not None and value is not False:
            warnings.warn(f"de does not use {name}; it is ignored", RuntimeWarning,
                          stacklevel=3)
    if isinstance(bounds, Bounds):
        lb, ub = np.broadcast_arrays(np.atleast_1d(bounds.lb), np.atleast_1d(bounds.ub))
        bounds = list(zip(lb.tolist(), ub.tolist(), strict=True))
    if x0 is not None:
        x = np.asarray(x0, dtype=float)
        parsed = _parse_bounds(bounds)
        if parsed is not None and x.size == parsed[0].size:
            clipped = np.clip(x.reshape(parsed[0].shape), parsed[0], parsed[1])
            if np.any(clipped != x.reshape(parsed[0].shape)):
                warnings.warn("Initial guess is not within the specified bounds; clipped",
                              OptimizeWarning, stacklevel=3)
            x = clipped
        x0 = x
    if callback is not None:
        params = set(inspect.signature(callback).parameters)
        if params != {"intermediate_result"}:
            callback = _XOnlyCallback(callback)
    if "x0" in options:
        raise TypeError("de: pass x0 as minimize's x0, not as an option")
    return differential_evolution(fun, bounds, args=args, constraints=constraints,
                                  callback=callback, x0=x0, **options)
