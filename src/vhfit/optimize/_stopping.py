"""Composable stopping criteria for :func:`vhfit.optimize.differential_evolution`.

A stopping criterion is any object with a ``check(state)`` method (or any plain
callable ``f(state)``) that returns something falsy to keep going, and something
truthy to stop.  A string return value is used as the human-readable reason.
Criteria combine with ``|`` (stop when any one is met) and ``&`` (stop when all are
met at the same generation).

The four criteria of the paper (*Visco-hyperelastic material model fitting to
experimental stress–strain curves using a genetic algorithm and its application to soft
tissue simulants*, §2.2) are built in, each with the paper's values as defaults;
:func:`paper_criteria` combines them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

__all__ = [
    "StopState",
    "StopCriterion",
    "AnyOf",
    "AllOf",
    "FunctionCriterion",
    "MeanImprovement",
    "BestMeanGap",
    "MaxGenerations",
    "TargetValue",
    "MaxEvaluations",
    "MaxTime",
    "EnergySpread",
    "paper_criteria",
    "as_criterion",
]


class StopState:
    """What a stopping criterion can see after each generation.

    One instance per solver, updated in place (so a criterion must not keep a
    reference to it between calls and expect it to stay the same).

    Attributes
    ----------
    nit : int
        Number of completed generations (0 before the first generation).
    nfev : int
        Number of objective calls so far (SciPy's count: with ``vectorized=True``
        one call evaluates a whole population).
    best : float
        Lowest energy in the population (``population_energies[0]``).
    mean : float
        Mean energy of the population; ``inf`` while any member has infinite energy
        (infeasible, or a NaN objective value, which vhfit treats as ``inf``).
    population_energies : ndarray
        Energies of the current population, best first. Do not modify.
    best_history, mean_history : list of float
        ``best`` and ``mean`` of every generation recorded so far, the initial
        population (generation 0) first; ``mean_history[-1] == mean``.
    elapsed : float
        Wall time in seconds since the solve started.
    """

    __slots__ = (
        "nit",
        "nfev",
        "best",
        "mean",
        "population_energies",
        "best_history",
        "mean_history",
        "elapsed",
    )

    def __init__(self) -> None:
        self.nit = 0
        self.nfev = 0
        self.best = math.inf
        self.mean = math.inf
        self.population_energies = None
        self.best_history: list[float] = []
        self.mean_history: list[float] = []
        self.elapsed = 0.0

    def __repr__(self) -> str:
        return (
            f"StopState(nit={self.nit}, nfev={self.nfev}, best={self.best!r}, "
            f"mean={self.mean!r}, elapsed={self.elapsed:.3g})"
        )


class StopCriterion:
    """Base class of stopping criteria.

    Subclasses implement :meth:`check`. Instances combine with ``|`` (any) and
    ``&`` (all); a plain callable ``f(state) -> bool | str`` may appear on either
    side of the operator.

    Attributes
    ----------
    success : bool
        Whether a run stopped by this criterion counts as converged
        (``result.success``). Budget criteria (generations, evaluations, time) set
        it to False, like SciPy's ``maxiter``.

    Examples
    --------
    >>> from vhfit.optimize import TargetValue, MaxGenerations, StopCriterion
    >>> stop = TargetValue(1e-6) | MaxGenerations(500)
    >>> class Plateau(StopCriterion):
    ...     '''Stop when the best value has not moved for `n` generations.'''
    ...     def __init__(self, n):
    ...         self.n = n
    ...     def check(self, state):
    ...         h = state.best_history
    ...         if len(h) > self.n and h[-1] >= h[-1 - self.n]:
    ...             return f"best unchanged for {self.n} generations"
    ...         return False
    >>> stop = stop | Plateau(50)
    """

    success: bool = True

    def check(self, state: StopState) -> bool | str:
        """Return a truthy value (a reason string, ideally) to stop the run."""
        raise NotImplementedError

    # internal protocol: the leaf that fired and its reason, or None
    def _fire(self, state: StopState) -> tuple[StopCriterion, str] | None:
        verdict = self.check(state)
        if not verdict:
            return None
        reason = verdict if isinstance(verdict, str) else "criterion met"
        return self, reason

    def __call__(self, state: StopState) -> bool | str:
        fired = self._fire(state)
        return False if fired is None else fired[1]

    def __or__(self, other: Any) -> AnyOf:
        return AnyOf(self, other)

    def __ror__(self, other: Any) -> AnyOf:
        return AnyOf(other, self)

    def __and__(self, other: Any) -> AllOf:
        return AllOf(self, other)

    def __rand__(self, other: Any) -> AllOf:
        return AllOf(other, self)

    @property
    def name(self) -> str:
        """Short name used in ``result.stop_reason``."""
        return type(self).__name__

    def __repr__(self) -> str:
        fields = ", ".join(f"{k}={v!r}" for k, v in vars(self).items() if not k.startswith("_"))
        return f"{type(self).__name__}({fields})"


class FunctionCriterion(StopCriterion):
    """Adapt a plain callable ``f(state) -> bool | str`` to a criterion.

    Parameters
    ----------
    func : callable
        Called after every generation with the :class:`StopState`.
    name : str, optional
        Name reported in ``result.stop_reason``; defaults to ``func.__name__``.
    success : bool, optional
        Whether stopping by this criterion counts as success. Default True.
    """

    def __init__(self, func: Callable[[StopState], Any], name: str | None = None,
                 success: bool = True) -> None:
        if not callable(func):
            raise ValueError(f"stop: {func!r} is not callable")
        self.func = func
        # getattr default: a callable (functools.partial, an instance) may have no name
        self._name = name or getattr(func, "__name__", type(func).__name__)
        self.success = bool(success)

    def check(self, state: StopState) -> bool | str:
        return self.func(state)

    @property
    def name(self) -> str:
        return self._name

    def __repr__(self) -> str:
        return f"FunctionCriterion({self._name})"


class AnyOf(StopCriterion):
    """Stop when any member criterion is met; the first one met (in order) is reported."""

    def __init__(self, *criteria: Any) -> None:
        members: list[StopCriterion] = []
        for c in criteria:
            c = as_criterion(c)
            # flatten nested AnyOf so reports name the leaf criterion
            members.extend(c.criteria if isinstance(c, AnyOf) else [c])
        if not members:
            raise ValueError("stop: AnyOf needs at least one criterion")
        self.criteria = tuple(members)

    def _fire(self, state: StopState) -> tuple[StopCriterion, str] | None:
        for c in self.criteria:
            fired = c._fire(state)
            if fired is not None:
                return fired
        return None

    def check(self, state: StopState) -> bool | str:  # pragma: no cover - via _fire
        fired = self._fire(state)
        return False if fired is None else fired[1]

    def __repr__(self) -> str:
        return " | ".join(repr(c) for c in self.criteria)


class AllOf(StopCriterion):
    """Stop when every member criterion is met at the same generation."""

    def __init__(self, *criteria: Any) -> None:
        members = [as_criterion(c) for c in criteria]
        if not members:
            raise ValueError("stop: AllOf needs at least one criterion")
        self.criteria = tuple(members)
        self.success = all(c.success for c in members)

    def _fire(self, state: StopState) -> tuple[StopCriterion, str] | None:
        reasons = []
        for c in self.criteria:
            fired = c._fire(state)
            if fired is None:
                return None
            reasons.append(fired[1])
        return self, " and ".join(reasons)

    def check(self, state: StopState) -> bool | str:  # pragma: no cover - via _fire
        fired = self._fire(state)
        return False if fired is None else fired[1]

    @property
    def name(self) -> str:
        return "(" + " & ".join(c.name for c in self.criteria) + ")"

    def __repr__(self) -> str:
        return "(" + " & ".join(repr(c) for c in self.criteria) + ")"


def _check_positive_int(name: str, value: Any, minimum: int = 1) -> int:
    try:
        ok = int(value) == value and int(value) >= minimum
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok or isinstance(value, bool):
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def _check_nonneg_float(name: str, value: Any) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}") from None
    if not math.isfinite(v) or v < 0:
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    return v


class MeanImprovement(StopCriterion):
    """Stop when the population's mean energy improved by less than `rel` over `window` generations.

    The paper's first criterion (its §2.2): "mean generation error reduced by less
    than 2 % over the last 2000 generations", i.e. stop when
    ``(mean[g - window] - mean[g]) / |mean[g - window]| < rel``.
    Never fires before ``window`` generations, nor while either mean is infinite.

    Parameters
    ----------
    rel : float, optional
        Relative reduction threshold (0.02 = 2 %). Default 0.02.
    window : int, optional
        Number of generations to look back. Default 2000.
    """

    def __init__(self, rel: float = 0.02, window: int = 2000) -> None:
        self.rel = _check_nonneg_float("MeanImprovement: rel", rel)
        self.window = _check_positive_int("MeanImprovement: window", window)

    def check(self, state: StopState) -> bool | str:
        h = state.mean_history
        if len(h) <= self.window:
            return False
        old, new = float(h[-1 - self.window]), float(h[-1])
        if not (math.isfinite(old) and math.isfinite(new)):
            return False
        reduction = 0.0 if old == new else (old - new) / abs(old)
        if reduction < self.rel:
            return (f"mean energy improved by {reduction:.3g} (< {self.rel:g}) over the last "
                    f"{self.window} generations")
        return False


class BestMeanGap(StopCriterion):
    """Stop when the best and the mean energy of a generation are within `rel` of each other.

    The paper's second criterion (its §2.2, "relative gap between the best and the
    mean error < 0.001 %"): stop when ``mean - best <= rel * |mean|``. The gap is taken
    relative to the mean (the paper does not say which; relative to the mean it is
    bounded by 1 and defined when the best is 0). Never fires while the mean is
    infinite.

    Parameters
    ----------
    rel : float, optional
        Relative gap (1e-5 = 0.001 %). Default 1e-5.
    """

    def __init__(self, rel: float = 1e-5) -> None:
        self.rel = _check_nonneg_float("BestMeanGap: rel", rel)

    def check(self, state: StopState) -> bool | str:
        best, mean = float(state.best), float(state.mean)
        if not (math.isfinite(best) and math.isfinite(mean)):
            return False
        gap = mean - best
        if gap <= self.rel * abs(mean):
            rel = gap / abs(mean) if mean != 0 else 0.0
            return f"relative gap between best and mean energy {rel:.3g} <= {self.rel:g}"
        return False


class MaxGenerations(StopCriterion):
    """Stop after `n` generations (the paper's third criterion, 100 000).

    Counts as not successful, like SciPy's ``maxiter``. Note that ``maxiter`` still
    caps the run: give ``maxiter >= n`` for this criterion to matter.

    Parameters
    ----------
    n : int, optional
        Number of generations. Default 100 000.
    """

    success = False

    def __init__(self, n: int = 100_000) -> None:
        self.n = _check_positive_int("MaxGenerations: n", n)

    def check(self, state: StopState) -> bool | str:
        if state.nit >= self.n:
            return f"reached {self.n} generations"
        return False


class TargetValue(StopCriterion):
    """Stop when the best energy drops below `target` (the paper's fourth criterion).

    The target is in the objective's own units. With the paper's objective (RMSAPE,
    Eq. 20, in percent) "best error < 0.001 %" is ``TargetValue(1e-3)``.

    Parameters
    ----------
    target : float, optional
        Threshold on the best energy; stop when ``best < target``. Default 1e-3.
    """

    def __init__(self, target: float = 1e-3) -> None:
        try:
            t = float(target)
        except (TypeError, ValueError):
            raise ValueError(f"TargetValue: target must be a number, got {target!r}") from None
        if math.isnan(t):
            raise ValueError("TargetValue: target must not be NaN")
        self.target = t

    def check(self, state: StopState) -> bool | str:
        if float(state.best) < self.target:
            return f"best energy {float(state.best):.6g} < target {self.target:g}"
        return False


class MaxEvaluations(StopCriterion):
    """Stop once at least `n` objective calls were made (SciPy's ``nfev`` count).

    Parameters
    ----------
    n : int
        Number of objective calls.
    """

    success = False

    def __init__(self, n: int) -> None:
        self.n = _check_positive_int("MaxEvaluations: n", n)

    def check(self, state: StopState) -> bool | str:
        if state.nfev >= self.n:
            return f"reached {state.nfev} objective calls (limit {self.n})"
        return False


class MaxTime(StopCriterion):
    """Stop after `seconds` of wall time (checked once per generation).

    Parameters
    ----------
    seconds : float
        Wall-time budget in seconds.
    """

    success = False

    def __init__(self, seconds: float) -> None:
        self.seconds = _check_nonneg_float("MaxTime: seconds", seconds)

    def check(self, state: StopState) -> bool | str:
        if state.elapsed >= self.seconds:
            return f"wall time {state.elapsed:.3g} s >= {self.seconds:g} s"
        return False


class EnergySpread(StopCriterion):
    """SciPy's own convergence test, as a composable criterion.

    Stops when ``std(population_energies) <= atol + tol * |mean(population_energies)|``
    (never while any energy is infinite). Use it to keep SciPy's ``tol``/``atol``
    behaviour next to other criteria, since giving ``stop=`` replaces it.

    Parameters
    ----------
    tol, atol : float, optional
        Relative and absolute tolerances, as SciPy's ``tol`` and ``atol``.
    """

    def __init__(self, tol: float = 0.01, atol: float = 0.0) -> None:
        self.tol = _check_nonneg_float("EnergySpread: tol", tol)
        self.atol = _check_nonneg_float("EnergySpread: atol", atol)

    def check(self, state: StopState) -> bool | str:
        e = state.population_energies
        if e is None or not math.isfinite(state.mean):
            return False
        std = float(e.std())
        if std <= self.atol + self.tol * abs(float(state.mean)):
            return f"std of energies {std:.3g} <= atol + tol * |mean|"
        return False


def paper_criteria(
    mean_rel: float = 0.02,
    window: int = 2000,
    gap_rel: float = 1e-5,
    max_generations: int = 100_000,
    target: float = 1e-3,
) -> AnyOf:
    """The paper's four stopping criteria, any one of which ends the run (its §2.2).

    Parameters
    ----------
    mean_rel, window : float, int, optional
        :class:`MeanImprovement`: mean error improved by less than `mean_rel`
        (default 2 %) over `window` generations (default 2000).
    gap_rel : float, optional
        :class:`BestMeanGap`: relative best-mean gap (default 1e-5, i.e. 0.001 %).
    max_generations : int, optional
        :class:`MaxGenerations` (default 100 000).
    target : float, optional
        :class:`TargetValue` on the best energy, in the objective's units
        (default 1e-3: 0.001 % when the objective is RMSAPE in percent).

    Returns
    -------
    AnyOf
        The combined criterion.

    Examples
    --------
    >>> from vhfit.optimize import paper_criteria
    >>> paper_criteria(target=1e-2)  # doctest: +ELLIPSIS
    MeanImprovement(rel=0.02, window=2000) | BestMeanGap(rel=1e-05) | ...
    """
    return AnyOf(
        MeanImprovement(mean_rel, window),
        BestMeanGap(gap_rel),
        MaxGenerations(max_generations),
        TargetValue(target),
    )


_NAMED = {"paper": paper_criteria}


def as_criterion(stop: Any) -> StopCriterion:
    """Normalise what users may pass as ``stop=`` to a :class:`StopCriterion`.

    Accepts a criterion, a plain callable ``f(state)``, the name ``"paper"``, or a
    sequence of those (stop when any is met).

    Raises
    ------
    ValueError
        For an unknown name or an object that is not a criterion; the message names
        the ``stop`` argument and lists the known names.
    """
    if isinstance(stop, StopCriterion):
        return stop
    if isinstance(stop, str):
        try:
            return _NAMED[stop]()
        except KeyError:
            raise ValueError(
                f"stop: unknown stopping criterion {stop!r}; known names: "
                f"{sorted(_NAMED)}, or pass StopCriterion objects / callables f(state)"
            ) from None
    if callable(stop):
        return FunctionCriterion(stop)
    if isinstance(stop, Sequence) and not isinstance(stop, (bytes, bytearray)):
        return AnyOf(*stop)
    raise ValueError(
        f"stop: {stop!r} is not a stopping criterion; pass a StopCriterion, a callable "
        f"f(state) -> bool | str, a sequence of those, or one of {sorted(_NAMED)}"
    )
