"""SciPy-compatible differential evolution with vhfit's extras.

:class:`DifferentialEvolutionSolver` subclasses SciPy's solver: with none of the
extras given, every code path is SciPy's own and results are bit-identical to
:func:`scipy.optimize.differential_evolution`. The extras (keyword-only, off by
default) hook into the generation loop: an absolute population size, composable
stopping criteria, a per-generation history, presets, bound-repair modes and
self-adaptive strategies (jDE, SHADE, L-SHADE).
"""

from __future__ import annotations

import functools
import inspect
import math
import time
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np
from scipy.optimize import Bounds, OptimizeResult

# vhfit.optimize builds on SciPy's DifferentialEvolutionSolver, which lives in a private
# module. The SciPy version is pinned by the environment this package is developed and
# tested in (SciPy 1.17); the import is guarded so that a SciPy that moved or renamed it
# fails here with a clear message instead of somewhere obscure.
try:
    from scipy.optimize._differentialevolution import (
        DifferentialEvolutionSolver as _SciPySolver,
    )
except ImportError as exc:  # pragma: no cover - depends on the installed SciPy
    raise ImportError(
        "vhfit.optimize subclasses scipy.optimize._differentialevolution."
        "DifferentialEvolutionSolver, which this SciPy does not provide; install the "
        "SciPy version vhfit is pinned to (1.17)."
    ) from exc
try:  # SciPy's termination messages (private, same pin as above)
    from scipy.optimize._optimize import _status_message
except ImportError:  # pragma: no cover
    _status_message = {
        "success": "Optimization terminated successfully.",
        "maxfev": "Maximum number of function evaluations has been exceeded.",
        "maxiter": "Maximum number of iterations has been exceeded.",
    }

from vhfit.optimize._history import DEHistory, _Recorder
from vhfit.optimize._presets import EXTRA_KEYS, SCIPY_DEFAULTS, preset_settings
from vhfit.optimize._state import from_plain, to_plain
from vhfit.optimize._stopping import StopCriterion, as_criterion
from vhfit.optimize._strategies import AdaptiveStrategy, _resolve, adaptive_strategies

__all__ = ["differential_evolution", "DifferentialEvolutionSolver"]

_SCIPY_STRATEGIES = tuple(_SciPySolver._binomial) + tuple(_SciPySolver._exponential)
_INITS = ("latinhypercube", "sobol", "halton", "random")
_REPAIRS = ("random", "clip", "midpoint")
_CALLBACK_STOP = "callback function requested stop early"
_STATE_FORMAT = "vhfit.DifferentialEvolutionSolver"
_STATE_VERSION = 1
_NO_CV = np.zeros((1, 1))  # constraint violation of an unconstrained trial (read-only use)


def _is_default(value: Any, default: Any) -> bool:
    """True when `value` is (equal to) SciPy's default, i.e. the user did not set it."""
    if value is default:
        return True
    if type(value) is not type(default):
        return False
    try:
        return bool(value == default)
    except (TypeError, ValueError):
        return False


class _NanToInf:
    """Objective wrapper: a NaN value becomes +inf (scalars and vectorized arrays).

    Module level and holding no solver reference, so it pickles for ``workers`` and
    creates no reference cycle.
    """

    def __init__(self, f: Callable) -> None:
        self.f = f

    def __call__(self, x):
        v = self.f(x)
        if isinstance(v, float):  # Python float and np.float64
            return math.inf if v != v else v
        try:
            a = np.asarray(v)
            if a.dtype.kind in "fc" and np.isnan(a).any():
                return np.where(np.isnan(a), np.inf, a.real if a.dtype.kind == "c" else a)
        except (TypeError, ValueError):
            pass
        return v


def _parse_bounds(bounds: Any) -> tuple[np.ndarray, np.ndarray] | None:
    """(lb, ub) as float arrays if `bounds` is well formed, else None (SciPy will complain)."""
    try:
        if isinstance(bounds, Bounds):
            lb = np.atleast_1d(np.asarray(bounds.lb, dtype=float))
            ub = np.atleast_1d(np.asarray(bounds.ub, dtype=float))
            lb, ub = np.broadcast_arrays(lb, ub)
        else:
            arr = np.array(bounds, dtype=float)
            if arr.ndim != 2 or arr.shape[1] != 2:
                return None
            lb, ub = arr[:, 0], arr[:, 1]
    except (TypeError, ValueError):
        return None
    return lb, ub


def _apply_preset(preset: str, given: dict) -> dict:
    """The arguments with a preset's settings where the caller left SciPy's default
    (vhfit's extras: where the caller left None)."""
    out = dict(given)
    for key, value in preset_settings(preset).items():
        if key in EXTRA_KEYS:
            if out[key] is None:
                out[key] = value
        elif _is_default(out[key], SCIPY_DEFAULTS[key]):
            out[key] = value
    return out


def _adaptive_or_scipy(strategy) -> AdaptiveStrategy | None:
    """The adaptive strategy named by ``strategy``, None for SciPy's; unknown names refused."""
    adaptive = _resolve(strategy)
    if adaptive is None and isinstance(strategy, str) and strategy not in _SCIPY_STRATEGIES:
        raise ValueError(
            f"strategy: unknown strategy {strategy!r}; available: "
            f"{list(_SCIPY_STRATEGIES) + list(adaptive_strategies())}, or a callable "
            "strategy(candidate, population, rng=None)")
    return adaptive


def _check_extras(population_size, history, snapshots, repair) -> tuple[int | None, int]:
    """Validate vhfit's extra keywords; the population size and snapshot step as ints."""
    if population_size is not None:
        if (isinstance(population_size, bool) or not np.isscalar(population_size)
                or int(population_size) != population_size or population_size < 5):
            raise ValueError(
                f"population_size must be an integer >= 5, got {population_size!r}")
        population_size = int(population_size)
    if history not in (True, False):
        raise ValueError(f"history must be True or False, got {history!r}")
    if (isinstance(snapshots, bool) or not np.isscalar(snapshots)
            or int(snapshots) != snapshots or snapshots < 0):
        raise ValueError(f"snapshots must be an integer >= 0, got {snapshots!r}")
    if repair is not None and repair not in _REPAIRS:
        raise ValueError(f"repair: unknown mode {repair!r}; available: {list(_REPAIRS)}")
    return population_size, int(snapshots)


def _check_bounds_and_x0(parsed, x0):
    """Refuse reversed bounds and an x0 that does not fit them; x0 as a flat array."""
    lb, ub = parsed
    reversed_ = np.flatnonzero(lb > ub)
    if reversed_.size:
        i = int(reversed_[0])
        raise ValueError(
            f"bounds: lower bound above upper bound for parameter {i} "
            f"({lb[i]!r} > {ub[i]!r}); give (min, max) pairs")
    if x0 is None:
        return None
    try:
        x0_arr = np.asarray(x0, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"x0 must be an array of {lb.size} numbers") from None
    if x0_arr.size != lb.size:
        raise ValueError(f"x0 has {x0_arr.size} entries but bounds define {lb.size} parameters")
    if not np.all(np.isfinite(x0_arr)):
        raise ValueError("x0 must be finite")
    return x0_arr.reshape(lb.size)


def _damaged_values(pop, energies, cv, index, counts, elapsed) -> str:
    """What in a loaded state no run can have produced ('' if nothing): members outside
    the unit cube or not finite, NaN energies, negative or non-finite constraint
    violations, a donor index that is no permutation, negative or huge counts, a
    negative or non-finite time."""
    if not (np.isfinite(pop).all() and (pop >= 0.0).all() and (pop <= 1.0).all()):
        return "population has members outside the unit cube [0, 1] or not finite"
    if np.isnan(energies).any():
        return "population energies hold NaN"
    if not (np.isfinite(cv).all() and (cv >= 0.0).all()):
        return "constraint violations are negative or not finite"
    if index.dtype.kind not in "iu" or not np.array_equal(np.sort(index),
                                                         np.arange(index.size)):
        return "donor index is not a permutation of the population"
    if not all(0 <= n < 2**62 for n in counts):
        return f"counts (nfev, generations, evaluations) {counts} are not counts"
    if not (math.isfinite(elapsed) and elapsed >= 0.0):
        return f"elapsed time {elapsed!r} is not a time"
    return ""


class DifferentialEvolutionSolver(_SciPySolver):
    """SciPy's differential evolution solver, with vhfit's extras.

    Takes exactly the arguments of
    :class:`scipy.optimize._differentialevolution.DifferentialEvolutionSolver` (see
    :func:`differential_evolution` for their meaning; the solver also accepts
    ``maxfun``), followed by vhfit's keyword-only extras. Without extras it *is*
    SciPy's solver: same code paths, same random stream, same results.

    Parameters
    ----------
    func, bounds, args, strategy, maxiter, popsize, tol, mutation, recombination, rng, \
maxfun, callback, disp, polish, init, atol, updating, workers, constraints, x0, \
integrality, vectorized
        As SciPy's solver; `strategy` also accepts ``"jde"``, ``"shade"``,
        ``"lshade"`` or an :class:`~vhfit.optimize.AdaptiveStrategy` instance.
    population_size, stop, history, snapshots, preset, repair
        vhfit's extras, see :func:`differential_evolution`.
    seeds : array_like, shape (k, N), optional
        Further starting points (vhfit's extra, with `population_size`): evaluated after
        the initial population, each lower than every member drawn replaces the highest
        one; a seed no better than the draw changes nothing.

    Notes
    -----
    Use as an iterator (``next(solver)`` evolves one generation) or call
    :meth:`solve`. Use it in a ``with`` block when ``workers`` creates a pool.
    """

    def __init__(self, func, bounds, args=(), strategy="best1bin", maxiter=1000, popsize=15,
                 tol=0.01, mutation=(0.5, 1), recombination=0.7, rng=None, maxfun=np.inf,
                 callback=None, disp=False, polish=True, init="latinhypercube", atol=0,
                 updating="immediate", workers=1, constraints=(), x0=None, *,
                 integrality=None, vectorized=False, population_size=None, stop=None,
                 history=False, snapshots=0, preset=None, repair=None, seeds=None):
        if preset is not None:
            given = {"strategy": strategy, "maxiter": maxiter, "popsize": popsize, "tol": tol,
                     "mutation": mutation, "recombination": recombination, "polish": polish,
                     "init": init, "atol": atol, "updating": updating,
                     "population_size": population_size, "stop": stop, "repair": repair}
            given = _apply_preset(preset, given)
            strategy, maxiter, popsize, tol = (given["strategy"], given["maxiter"],
                                               given["popsize"], given["tol"])
            mutation, recombination, polish = (given["mutation"], given["recombination"],
                                               given["polish"])
            init, atol, updating = given["init"], given["atol"], given["updating"]
            population_size, stop, repair = (given["population_size"], given["stop"],
                                             given["repair"])

        population_size, snapshots = _check_extras(population_size, history, snapshots, repair)
        stop_c: StopCriterion | None = None if stop is None else as_criterion(stop)

        adaptive = _adaptive_or_scipy(strategy)

        parsed = _parse_bounds(bounds)
        if parsed is not None:
            x0 = _check_bounds_and_x0(parsed, x0)

        real_init = None
        if population_size is not None:
            if isinstance(init, str):
                if init not in _INITS:
                    raise ValueError(
                        f"init: unknown initialisation {init!r}; available: {list(_INITS)} "
                        "or an array of shape (S, N)")
                if parsed is not None:
                    # SciPy sizes its population as popsize * N; build it with a tiny
                    # placeholder (no random draws) and initialise NP members below.
                    real_init = init
                    init = np.tile(0.5 * (parsed[0] + parsed[1]), (5, 1))
            elif np.shape(init)[0] != population_size:
                raise ValueError(
                    f"population_size={population_size} conflicts with the init array of "
                    f"{np.shape(init)[0]} members")

        super().__init__(
            func, bounds, args=args,
            strategy="rand1bin" if adaptive is not None else strategy,
            maxiter=maxiter, popsize=popsize, tol=tol, mutation=mutation,
            recombination=recombination, rng=rng, maxfun=maxfun, callback=callback,
            disp=disp, polish=polish, init=init, atol=atol, updating=updating,
            workers=workers, constraints=constraints, x0=x0, integrality=integrality,
            vectorized=vectorized)

        if real_init is not None:
            self._vh_initial_population(real_init, population_size, x0)

        self._vh_adaptive: AdaptiveStrategy | None = adaptive
        self._vh_astate = None
        if adaptive is not None:
            self.strategy = adaptive
            if self.num_population_members < adaptive.min_population:
                raise ValueError(
                    f"population_size: strategy {adaptive.name!r} needs at least "
                    f"{adaptive.min_population} members, got {self.num_population_members}")
        self._vh_extras = bool(
            population_size is not None or stop_c is not None or history or snapshots
            or preset is not None or repair is not None or adaptive is not None)
        self._vh_stop = stop_c
        self._vh_seeds = None
        if seeds is not None:
            if not self._vh_extras:
                raise ValueError("seeds need vhfit's extras (population_size=...)")
            rows = np.atleast_2d(np.asarray(seeds, dtype=np.float64))
            self._vh_seeds = np.array([self._unscale_parameters(
                _check_bounds_and_x0(parsed, r)) for r in rows]).reshape(-1, self.parameter_count)
        self._vh_history = bool(history or snapshots)
        self._vh_repair = repair
        self._vh_parents = None
        self._vh_gen = 0
        self._vh_nevals = 0
        self._vh_fired = None
        self._vh_last_message = None
        self._vh_rec = _Recorder(snapshots) if self._vh_extras else None
        if self._vh_extras:
            self.func = _NanToInf(self.func)
        # resumable state (state_dict/load_state): wall clock, and how solve() continues
        self._vh_t0: float | None = None
        self._vh_elapsed0 = 0.0
        self._vh_resumed = False
        self._vh_nit_offset = 0
        self._vh_preconverged = False

    def _vh_initial_population(self, init: str, size: int, x0) -> None:
        """Draw the exact population ``size`` (SciPy would size it popsize x N)."""
        self.num_population_members = size
        self.population_shape = (size, self.parameter_count)
        if init == "latinhypercube":
            self.init_population_lhs()
        elif init == "random":
            self.init_population_random()
        else:
            self.init_population_qmc(qmc_engine=init)
        if x0 is not None:
            self.population[0] = self._unscale_parameters(x0)
        self.constraint_violation = np.zeros((size, 1))
        self.feasible = np.ones(size, bool)
        self._random_population_index = np.arange(size)

    # ------------------------------------------------------------------ loop hooks
    def __next__(self):
        self._vh_clock()
        if not self._vh_extras:
            out = super().__next__()
            self._vh_gen += 1
            return out
        rec = self._vh_rec
        if not rec.recorded:
            self._vh_initial()
        if self._vh_adaptive is None:
            out = super().__next__()
        else:
            self._vh_adaptive_generation()
            out = (self.x, self.population_energies[0])
        self._vh_gen += 1
        rec.record(self._vh_gen, self._nfev, self.population_energies,
                   self._vh_scaled_population if rec.every else None)
        return out

    def converged(self):
        """Whether the run should stop: SciPy's tol/atol test, or the ``stop`` criteria."""
        if self._vh_stop is None:
            return super().converged()
        rec = self._vh_rec
        if not rec.recorded:
            return False
        fired = self._vh_stop._fire(rec.state)
        if fired is None:
            return False
        self._vh_fired = fired
        return True

    def solve(self):
        """Run the solver; see :func:`differential_evolution` for the result's fields.

        After :meth:`load_state`, the run continues where the state was taken: at most
        ``maxiter`` generations in all (those before the state included), ``nit``
        counting all of them.
        """
        self._vh_clock()
        self._vh_fired = None
        self._vh_last_message = None
        if self._vh_extras and not self._vh_rec.recorded:
            self._vh_initial()
        maxiter = self.maxiter
        done = self._vh_gen if self._vh_resumed else 0
        if done:
            # SciPy's loop tests convergence after each generation's callback; a state
            # taken in that callback resumes with the test the uninterrupted run made next
            self._vh_preconverged = bool(self.converged())
            self.maxiter = 0 if self._vh_preconverged else max(maxiter - done, 0)
            self._vh_nit_offset = done
        try:
            res = super().solve()
        finally:
            self.maxiter = maxiter
            self._vh_nit_offset = 0
            self._vh_preconverged = False
        if self._vh_extras:
            self._vh_finish(res)
        return res

    def _result(self, **kwds):
        if kwds.get("nit") is not None:
            kwds["nit"] += self._vh_nit_offset
        if self._vh_preconverged and kwds.get("message") == _status_message["maxiter"]:
            kwds["message"], kwds["warning_flag"] = _status_message["success"], False
        if self._vh_extras and kwds.get("message") != "in progress":
            self._vh_last_message = kwds.get("message")
        return super()._result(**kwds)

    @property
    def history(self) -> DEHistory | None:
        """The per-generation record of the run so far (None without vhfit's extras).

        The same rows as ``result.history``, available during the run (e.g. after a
        ``KeyboardInterrupt`` cut :meth:`solve` short).
        """
        return None if self._vh_rec is None else self._vh_rec.result()

    # ------------------------------------------------------------------ resumable state
    def state_dict(self) -> dict:
        """Everything needed to continue this run exactly, as plain JSON types.

        Take it at a generation boundary: before :meth:`solve`, between two
        ``next(solver)`` calls, or inside the ``callback`` (which runs after each
        generation). A state taken after :meth:`solve` has polished the best member
        (``polish=True``) carries the polished member.

        Returns
        -------
        dict
            Plain JSON types only (dicts, lists, str, int, finite float, bool, None):
            ``json.dumps(state, allow_nan=False)`` works and reading the text back
            gives a state that resumes bit for bit. Arrays are stored as
            ``{"__ndarray__": dtype, "shape": [...], "data": [...]}`` (non-finite
            values as the strings ``"inf"``, ``"-inf"``, ``"nan"``). Keys:

            ``format``, ``version``
                ``"vhfit.DifferentialEvolutionSolver"`` and 1.
            ``parameter_count``, ``bounds``, ``strategy``
                What :meth:`load_state` checks: number of parameters, the bounds
                (``(N, 2)``, after SciPy's integrality adjustment) and the strategy
                (its name, or the adaptive strategy's repr with its settings).
            ``population_size``, ``population``, ``population_energies``, \
``feasible``, ``constraint_violation``
                The population in the unit cube (best first), its energies,
                feasibility and constraint violations; the size changes with
                L-SHADE.
            ``random_state``
                ``{"kind": "Generator" | "RandomState", "state": ...}``: the
                bit-generator state (with a legacy ``RandomState``, also its
                cached normal deviate).
            ``donor_index``
                The index array SciPy shuffles in place to choose donors.
            ``nfev``, ``generations``, ``evaluations``
                Objective calls (SciPy's count), generations done, and individual
                evaluations (what L-SHADE's reduction counts).
            ``elapsed``
                Wall time in seconds spent in this run so far.
            ``extras``
                Whether the solver runs vhfit's extras (stop criteria, history, ...).
            ``strategy_state``
                The adaptive strategy's run-time state (jDE's per-member F and CR;
                SHADE/L-SHADE's memories, memory index, archive, ...), or None.
            ``history``
                The per-generation rows (``nit``, ``nfev``, ``best``, ``mean``,
                ``time``, ``population_size``) and snapshots, which also feed the
                stopping criteria; None without extras.

        See Also
        --------
        load_state : Continue a run from this state.

        Examples
        --------
        Run 30 generations, save the state as JSON text, and finish the run in a new
        solver; the result is the uninterrupted run's, bit for bit.

        >>> import json
        >>> from scipy.optimize import rosen
        >>> from vhfit.optimize import DifferentialEvolutionSolver
        >>> def solver():
        ...     return DifferentialEvolutionSolver(rosen, [(-2, 2)] * 3, rng=7,
        ...                                        maxiter=80, polish=False,
        ...                                        strategy="shade", history=True)
        >>> whole = solver().solve()
        >>> first = solver()
        >>> for _ in range(30):
        ...     _ = next(first)
        >>> text = json.dumps(first.state_dict(), allow_nan=False)
        >>> second = solver()
        >>> second.load_state(json.loads(text))
        >>> res = second.solve()
        >>> res.nit == whole.nit, res.nfev == whole.nfev, bool(res.fun == whole.fun)
        (True, True, True)
        >>> bool((res.history.best == whole.history.best).all())
        True
        """
        rng = self.random_number_generator
        if isinstance(rng, np.random.Generator):
            kind, rng_state = "Generator", rng.bit_generator.state
        else:  # legacy RandomState (seed=int): its state includes a cached normal deviate
            kind, rng_state = "RandomState", rng.get_state(legacy=False)
        strat = self._vh_adaptive
        return {
            "format": _STATE_FORMAT,
            "version": _STATE_VERSION,
            "parameter_count": int(self.parameter_count),
            "bounds": to_plain(self.limits.T.copy()),
            "strategy": self._vh_strategy_id(),
            "population_size": int(self.num_population_members),
            "population": to_plain(self.population),
            "population_energies": to_plain(self.population_energies),
            "feasible": to_plain(self.feasible),
            "constraint_violation": to_plain(self.constraint_violation),
            "random_state": {"kind": kind, "state": to_plain(rng_state)},
            "donor_index": to_plain(self._random_population_index),
            "nfev": int(self._nfev),
            "generations": int(self._vh_gen),
            "evaluations": int(self._vh_nevals),
            "elapsed": float(self._vh_elapsed()),
            "extras": self._vh_extras,
            "strategy_state": (None if strat is None or self._vh_astate is None
                               else strat.dump_state(self._vh_astate)),
            "history": None if self._vh_rec is None else self._vh_rec.dump(),
        }

    def load_state(self, state: dict) -> None:
        """Continue a run from a :meth:`state_dict`: restore it into this solver.

        Build the solver with the same arguments as the saved one (objective,
        bounds, strategy, seed, extras; ``maxiter`` may differ), then call
        ``load_state``. :meth:`solve` then continues the run: at most
        ``maxiter - state["generations"]`` more generations, ``result.nit`` and
        ``result.history`` counting every generation (those before the state
        included), wall times continuing from the saved ``elapsed``, and stopping
        criteria seeing the whole history. ``next(solver)`` also continues.

        Parameters
        ----------
        state : dict
            What :meth:`state_dict` returned (also after a JSON round trip).

        Raises
        ------
        ValueError
            When the state is not a solver state, or was saved with a different
            number of parameters, bounds, strategy, random generator kind or with(out)
            vhfit's extras; the message names what differs and how to fix it.

        See Also
        --------
        state_dict : The state, and an example of a resumed run.

        Examples
        --------
        >>> from scipy.optimize import rosen
        >>> from vhfit.optimize import DifferentialEvolutionSolver
        >>> a = DifferentialEvolutionSolver(rosen, [(-2, 2)] * 3, rng=1, polish=False)
        >>> for _ in range(5):
        ...     _ = next(a)
        >>> b = DifferentialEvolutionSolver(rosen, [(-2, 2)] * 3, rng=1, polish=False)
        >>> b.load_state(a.state_dict())
        >>> bool((next(b)[0] == next(a)[0]).all())
        True
        >>> c = DifferentialEvolutionSolver(rosen, [(-2, 2)] * 4, rng=1)
        >>> c.load_state(a.state_dict())  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        ValueError: load_state: the state has 3 parameters but this solver's bounds ...
        """
        self._vh_check_state(state)
        try:
            pop = np.array(from_plain(state["population"]), dtype=np.float64)
            energies = np.array(from_plain(state["population_energies"]), dtype=np.float64)
            feasible = np.array(from_plain(state["feasible"]), dtype=bool)
            cv = np.array(from_plain(state["constraint_violation"]), dtype=np.float64)
            index = np.array(from_plain(state["donor_index"]))
            rng_state = from_plain(state["random_state"]["state"])
            nfev, gen = int(state["nfev"]), int(state["generations"])
            nevals, elapsed = int(state["evaluations"]), float(state["elapsed"])
            history, strategy_state = state["history"], state["strategy_state"]
        except (KeyError, TypeError, ValueError) as exc:
            raise ValueError(
                f"load_state: the state is incomplete or damaged ({type(exc).__name__}: "
                f"{exc}); pass the dict that state_dict() returned") from None
        NP = pop.shape[0] if pop.ndim == 2 else -1
        if (pop.shape != (NP, self.parameter_count) or energies.shape != (NP,)
                or state.get("population_size") != NP
                or feasible.shape != (NP,) or cv.shape[:1] != (NP,) or index.shape != (NP,)):
            raise ValueError(
                "load_state: the state's population arrays do not fit together (damaged "
                "state); pass the dict that state_dict() returned")
        why = _damaged_values(pop, energies, cv, index, (nfev, gen, nevals), elapsed)
        if why:
            raise ValueError(f"load_state: the state's {why} (damaged state); pass the dict "
                             "that state_dict() returned")
        self.population, self.population_energies = pop, energies
        self.feasible, self.constraint_violation = feasible, cv
        self.num_population_members = NP
        self.population_shape = (NP, self.parameter_count)
        self._random_population_index = index
        self._nfev, self._vh_gen, self._vh_nevals = nfev, gen, nevals
        self._vh_elapsed0, self._vh_t0 = elapsed, None
        if self._vh_rec is not None:
            self._vh_rec.load(history, self.population_energies)
            self._vh_rec.t0 = None
        if self._vh_adaptive is not None:
            self._vh_astate = (None if strategy_state is None
                               else self._vh_adaptive.restore_state(self, strategy_state))
        # last: restoring a strategy's state may build it with init_state (no draws
        # by vhfit's strategies, but a user's might)
        rng = self.random_number_generator
        if isinstance(rng, np.random.Generator):
            rng.bit_generator.state = rng_state
        else:
            rng.set_state(rng_state)
        self._vh_resumed = True

    def _vh_check_state(self, state: Any) -> None:
        """Refuse a state that does not belong to a run of this solver (one-line errors)."""
        fmt = state.get("format") if isinstance(state, dict) else None
        if fmt != _STATE_FORMAT:
            raise ValueError(
                f"load_state: not a solver state (format {fmt!r}, expected "
                f"{_STATE_FORMAT!r}); pass the dict that state_dict() returned")
        if type(state.get("version")) is not int or state.get("version") != _STATE_VERSION:
            raise ValueError(
                f"load_state: state version {state.get('version')!r} is not supported "
                f"(this vhfit reads version {_STATE_VERSION}); resume with the vhfit "
                "that saved it")
        n = state.get("parameter_count")
        if n != self.parameter_count:
            raise ValueError(
                f"load_state: the state has {n} parameters but this solver's bounds "
                f"define {self.parameter_count}; build the solver with the bounds of the "
                "saved run")
        try:
            saved = np.asarray(from_plain(state["bounds"]), dtype=float).reshape(-1, 2)
        except (KeyError, TypeError, ValueError):
            raise ValueError(
                "load_state: the state's bounds are missing or damaged; pass the dict "
                "that state_dict() returned") from None
        given = self.limits.T
        if saved.shape != given.shape or not np.array_equal(saved, given):
            i = int(np.flatnonzero((saved != given).any(axis=1))[0]) \
                if saved.shape == given.shape else 0
            raise ValueError(
                f"load_state: bounds differ from the saved run's (parameter {i}: saved "
                f"{tuple(saved[i].tolist())}, given {tuple(given[i].tolist())}); build the "
                "solver with the bounds of the saved run")
        sid, mine = state.get("strategy"), self._vh_strategy_id()
        if sid != mine:
            raise ValueError(
                f"load_state: the state was saved with strategy {sid!r} but this solver "
                f"uses {mine!r}; build the solver with the saved run's strategy")
        if not isinstance(state.get("extras"), bool):
            raise ValueError(
                f"load_state: the state's extras entry is {state.get('extras')!r}, not true "
                "or false (damaged state); pass the dict that state_dict() returned")
        if state.get("extras") != self._vh_extras:
            how = "with" if state.get("extras") else "without"
            raise ValueError(
                f"load_state: the state was saved by a solver {how} vhfit's extras "
                "(population_size, stop, history, snapshots, preset, repair or an adaptive "
                "strategy); build the solver with the saved run's keyword arguments")
        rs = state.get("random_state") or {}
        saved_bg = (rs.get("state") or {}).get("bit_generator")
        rng = self.random_number_generator
        kind = "Generator" if isinstance(rng, np.random.Generator) else "RandomState"
        bg = (type(rng.bit_generator).__name__ if kind == "Generator"
              else rng.get_state(legacy=False)["bit_generator"])
        if rs.get("kind") != kind or saved_bg != bg:
            raise ValueError(
                f"load_state: the state's random generator is a {rs.get('kind')} "
                f"({saved_bg}) but this solver's is a {kind} ({bg}); pass rng= (or seed=) "
                "as for the saved run")

    def _vh_strategy_id(self) -> str:
        if self._vh_adaptive is not None:
            return repr(self._vh_adaptive)
        if isinstance(self.strategy, str):
            return self.strategy
        # getattr default: a callable (functools.partial, an instance) may have no name
        return "callable " + getattr(self.strategy, "__qualname__", type(self.strategy).__name__)

    def _vh_clock(self) -> None:
        """Start the run's wall clock (once), continuing from a loaded ``elapsed``."""
        if self._vh_t0 is None:
            self._vh_t0 = time.perf_counter() - self._vh_elapsed0
            if self._vh_rec is not None:
                self._vh_rec.t0 = self._vh_t0

    def _vh_elapsed(self) -> float:
        return self._vh_elapsed0 if self._vh_t0 is None else time.perf_counter() - self._vh_t0

    # ------------------------------------------------------------------ repair modes
    def _mutate(self, candidate):
        if self._vh_repair == "midpoint":
            self._vh_parents = candidate
        return super()._mutate(candidate)

    def _mutate_many(self, candidates):
        if self._vh_repair == "midpoint":
            self._vh_parents = candidates
        return super()._mutate_many(candidates)

    def _ensure_constraint(self, trial):
        mode = self._vh_repair
        if mode is None or mode == "random":
            return super()._ensure_constraint(trial)
        if mode == "clip":
            np.clip(trial, 0.0, 1.0, out=trial)
            return None
        # midpoint between the parent and the violated bound
        parents = self.population[self._vh_parents]
        low = trial < 0.0
        if low.any():
            trial[low] = 0.5 * np.broadcast_to(parents, trial.shape)[low]
        high = trial > 1.0
        if high.any():
            trial[high] = 0.5 * (1.0 + np.broadcast_to(parents, trial.shape)[high])
        return None

    # ------------------------------------------------------------------ internals
    def _vh_scaled_population(self):
        return self._scale_parameters(self.population)

    def _vh_initial(self):
        """Evaluate the initial population (as SciPy does), with the seeds in the same
        batch (:meth:`_vh_enter_seeds`), and record generation 0."""
        if np.all(np.isinf(self.population_energies)):
            self.feasible, self.constraint_violation = (
                self._calculate_population_feasibilities(self.population))
            seeds, self._vh_seeds = self._vh_seeds, None
            k = 0 if seeds is None else len(seeds)
            before = self._nfev
            batch = self.population[self.feasible]
            energies = self._calculate_population_energies(
                np.concatenate([batch, seeds]) if k else batch)
            self.population_energies[self.feasible] = energies[:len(batch)]
            self._vh_nevals += (len(batch) + k if self.vectorized
                                else self._nfev - before)
            if k:
                self._vh_enter_seeds(seeds, energies[len(batch):])
            self._promote_lowest_energy()
        self._vh_rec.record(0, self._nfev, self.population_energies,
                            self._vh_scaled_population if self._vh_rec.every else None)

    def _vh_enter_seeds(self, seeds, energies):
        """Each seed that is lower than every member drawn replaces the highest member
        (a seed no better than the draw leaves the population, and so the whole search,
        as it would have been without it)."""
        for z, e in zip(seeds, energies):
            e_pop = np.where(self.feasible, self.population_energies, np.inf)
            if not e < np.min(e_pop):
                continue
            worst = int(np.argmax(e_pop)) if np.isfinite(e_pop).all() else int(
                np.flatnonzero(~np.isfinite(e_pop))[0])
            self.population[worst] = z
            self.population_energies[worst] = e
            self.feasible[worst] = True
            self.constraint_violation[worst] = 0.0

    def _vh_promote(self):
        """SciPy's promotion of the best member to slot 0, telling the strategy."""
        feasible = np.flatnonzero(self.feasible)
        if feasible.size:
            best = int(feasible[np.argmin(self.population_energies[feasible])])
        else:
            best = int(np.argmin(np.sum(self.constraint_violation, axis=1)))
        if best != 0:
            sw = [0, best]
            rev = [best, 0]
            self.population_energies[sw] = self.population_energies[rev]
            self.population[sw, :] = self.population[rev, :]
            self.feasible[sw] = self.feasible[rev]
            self.constraint_violation[sw, :] = self.constraint_violation[rev, :]
            if self._vh_adaptive is not None and self._vh_astate is not None:
                self._vh_adaptive.swap(self._vh_astate, 0, best)

    def _vh_shrink(self, size: int):
        """Keep the `size` best members (population-size reduction), best stays first."""
        order = np.argsort(self.population_energies, kind="stable")
        keep = np.sort(order[:size])
        self.population = self.population[keep]
        self.population_energies = self.population_energies[keep]
        self.feasible = self.feasible[keep]
        self.constraint_violation = self.constraint_violation[keep]
        self.num_population_members = size
        self.population_shape = (size, self.parameter_count)
        self._random_population_index = np.arange(size)
        if self._vh_adaptive is not None and self._vh_astate is not None:
            self._vh_adaptive.resize(self._vh_astate, keep)
        self._vh_promote()

    def _vh_adaptive_generation(self):
        """One generation of a self-adaptive strategy (immediate or deferred updating)."""
        strat = self._vh_adaptive
        if self._vh_astate is None:
            self._vh_astate = strat.init_state(self)
        st = self._vh_astate
        constrained = bool(self._wrapped_constraints)
        if self._updating == "immediate":
            if self._nfev > self.maxfun:
                raise StopIteration
            strat.begin_generation(self, st)
            pop_e = self.population_energies
            for c in range(self.num_population_members):
                if self._nfev > self.maxfun:
                    raise StopIteration
                parent = self.population[c].copy()
                trial = strat.trial(self, st, c)
                params = self._scale_parameters(trial)
                feasible, cv, energy = True, _NO_CV, math.inf
                if constrained:
                    cv = self._constraint_violation_fn(params)
                    feasible = not np.sum(cv) > 0
                if feasible:
                    energy = self.func(params)
                    self._nfev += 1
                    self._vh_nevals += 1
                    if np.size(energy) != 1:
                        raise RuntimeError("func(x, *args) must return a scalar value")
                    energy = float(energy if isinstance(energy, float) else np.squeeze(energy))
                pe = float(pop_e[c])
                if constrained:
                    ok = bool(self._accept_trial(energy, feasible, cv, pe, self.feasible[c],
                                                 self.constraint_violation[c]))
                    better = ok and feasible and bool(self.feasible[c])
                else:
                    ok = better = energy <= pe
                delta = pe - energy if better and energy < pe and pe < math.inf else 0.0
                strat.report(self, st, c, ok, delta, parent)
                if ok:
                    self.population[c] = trial
                    pop_e[c] = energy
                    if constrained:
                        self.feasible[c] = feasible
                        self.constraint_violation[c] = cv
                        if self._accept_trial(energy, feasible, cv, pop_e[0], self.feasible[0],
                                              self.constraint_violation[0]):
                            self._vh_promote()
                    elif energy <= pop_e[0]:
                        self._vh_promote()
        else:
            if self._nfev >= self.maxfun:
                raise StopIteration
            NP = self.num_population_members
            cand = np.arange(NP)
            strat.begin_generation(self, st)
            trial_pop = strat.trials(self, st, cand)
            feasible, cv = self._calculate_population_feasibilities(trial_pop)
            trial_e = np.full(NP, np.inf)
            before = self._nfev
            trial_e[feasible] = self._calculate_population_energies(trial_pop[feasible])
            self._vh_nevals += (int(np.count_nonzero(feasible)) if self.vectorized
                                else self._nfev - before)
            pop_e = self.population_energies
            if constrained:
                loc = np.array([self._accept_trial(*v) for v in zip(
                    trial_e, feasible, cv, pop_e, self.feasible, self.constraint_violation)],
                    dtype=bool)
            else:
                loc = trial_e <= pop_e
            both = loc & feasible & self.feasible & np.isfinite(trial_e) & np.isfinite(pop_e)
            delta = np.zeros(NP)
            delta[both] = pop_e[both] - trial_e[both]
            parents = self.population
            strat.report_many(self, st, cand, loc, delta, parents)
            self.population = np.where(loc[:, None], trial_pop, parents)
            self.population_energies = np.where(loc, trial_e, pop_e)
            self.feasible = np.where(loc, feasible, self.feasible)
            self.constraint_violation = np.where(loc[:, None], cv, self.constraint_violation)
        strat.end_generation(self, st)
        self._vh_promote()

    def _vh_finish(self, res: OptimizeResult) -> None:
        """Add ``stop_reason`` (and ``history``) to the final result."""
        msg = self._vh_last_message
        if self._vh_fired is not None:
            crit, reason = self._vh_fired
            res.stop_reason = crit.name
            if res.message == _status_message["success"]:
                res.message = f"Stopped by {crit.name}: {reason}."
                res.success = bool(crit.success)
        elif msg == _status_message["maxiter"]:
            res.stop_reason = "maxiter"
        elif isinstance(msg, str) and msg.startswith("Maximum number of function evaluations"):
            res.stop_reason = "maxfun"
        elif msg == _CALLBACK_STOP:
            res.stop_reason = "callback"
        elif msg == _status_message["success"]:
            res.stop_reason = "tol"
        else:  # pragma: no cover - defensive
            res.stop_reason = "unknown"
        if self._vh_history:
            res.history = self._vh_rec.result()


def _rng_transition(fun: Callable) -> Callable:
    """Accept the legacy ``seed`` keyword exactly as SciPy's ``differential_evolution``.

    SciPy's semantics: ``rng=`` by keyword is normalised with
    :func:`numpy.random.default_rng`; the 10th positional argument or ``seed=`` is
    passed on as is (an int then seeds a legacy ``RandomState``). Giving two of these
    raises TypeError. ``seed`` is listed in the signature right after ``vectorized``,
    where SciPy's signature has it.
    """
    position = 9

    @functools.wraps(fun)
    def wrapper(*args, **kwargs):
        as_old = "seed" in kwargs
        as_new = "rng" in kwargs
        as_pos = len(args) >= position + 1
        if int(as_old) + int(as_new) + int(as_pos) > 1:
            raise TypeError(
                f"{fun.__name__}() got multiple values for argument now known as `rng`. "
                "Specify one of `rng` or `seed`.")
        if as_old:
            kwargs["rng"] = kwargs.pop("seed")
        elif as_new:
            kwargs["rng"] = np.random.default_rng(kwargs["rng"])
        return fun(*args, **kwargs)

    sig = inspect.signature(fun)
    params = list(sig.parameters.values())
    at = [p.name for p in params].index("vectorized") + 1
    params.insert(at, inspect.Parameter("seed", inspect.Parameter.KEYWORD_ONLY, default=None))
    wrapper.__signature__ = sig.replace(parameters=params)
    return wrapper


@_rng_transition
def differential_evolution(
    func: Callable[..., Any],
    bounds: Any,
    args: tuple = (),
    strategy: str | Callable | AdaptiveStrategy = "best1bin",
    maxiter: int = 1000,
    popsize: int = 15,
    tol: float = 0.01,
    mutation: float | tuple[float, float] = (0.5, 1),
    recombination: float = 0.7,
    rng: Any = None,
    callback: Callable | None = None,
    disp: bool = False,
    polish: bool | Callable = True,
    init: str | Any = "latinhypercube",
    atol: float = 0,
    updating: str = "immediate",
    workers: int | Callable = 1,
    constraints: Any = (),
    x0: Any = None,
    *,
    integrality: Any = None,
    vectorized: bool = False,
    population_size: int | None = None,
    stop: StopCriterion | Callable | str | Iterable | None = None,
    history: bool = False,
    snapshots: int = 0,
    preset: str | None = None,
    repair: str | None = None,
) -> OptimizeResult:
    r"""Find the global minimum of a function with differential evolution.

    A drop-in replacement for :func:`scipy.optimize.differential_evolution`: same
    signature, defaults, semantics and :class:`~scipy.optimize.OptimizeResult`
    fields, built on SciPy's own solver (with no extra given, results are
    bit-identical to SciPy's). Keyword-only extras add what the paper's calibration
    needs: an absolute population size, composable stopping criteria, a
    per-generation history, the paper's preset, bound-repair modes and self-adaptive
    strategies.

    Parameters
    ----------
    func : callable
        Objective ``func(x, *args) -> float``, ``x`` a 1-D array of N parameters
        (with ``vectorized=True``: ``x`` of shape (N, S), returning shape (S,)).
    bounds : sequence or `~scipy.optimize.Bounds`
        ``(min, max)`` pairs, one per parameter, or a `Bounds` instance. Finite, and
        ``min <= max`` (equal bounds fix a parameter).
    args : tuple, optional
        Extra arguments passed to `func`.
    strategy : str or callable or AdaptiveStrategy, optional
        SciPy's strategies ``'best1bin'`` (default), ``'best1exp'``, ``'rand1bin'``,
        ``'rand1exp'``, ``'rand2bin'``, ``'rand2exp'``, ``'randtobest1bin'``,
        ``'randtobest1exp'``, ``'currenttobest1bin'``, ``'currenttobest1exp'``,
        ``'best2exp'``, ``'best2bin'``; a callable
        ``strategy(candidate, population, rng=None)`` returning a trial of shape (N,);
        or one of vhfit's self-adaptive variants ``'jde'``, ``'shade'``, ``'lshade'``
        (or an instance of :class:`~vhfit.optimize.JDE`, :class:`~vhfit.optimize.SHADE`,
        :class:`~vhfit.optimize.LSHADE` to change their settings). The adaptive
        variants choose F and CR themselves, so `mutation` and `recombination` are
        ignored for them.
    maxiter : int, optional
        Maximum number of generations. Default 1000. Also caps runs with `stop`.
    popsize : int, optional
        Population size multiplier: ``popsize * (N - N_equal)`` members (at least 5),
        unless `population_size` or an `init` array sets the size.
    tol, atol : float, optional
        SciPy's convergence test: stop when ``std(population_energies) <= atol +
        tol * |mean(population_energies)|``. Not used when `stop` is given.
    mutation : float or tuple(float, float), optional
        Differential weight F in [0, 2), or ``(min, max)`` for dithering (a new F
        from U[min, max) each generation). Default (0.5, 1).
    recombination : float, optional
        Crossover probability CR in [0, 1]. Default 0.7.
    rng : {None, int, `numpy.random.Generator`}, optional
        Random generator or seed: by keyword it goes through
        :func:`numpy.random.default_rng`. The legacy spelling ``seed=`` (or this
        argument by position) keeps SciPy's legacy meaning (an int seeds a
        `~numpy.random.RandomState`). The same seed gives bit-identical results,
        for any `workers`.
    callback : callable, optional
        ``callback(intermediate_result)`` with an `OptimizeResult` (fields ``x``,
        ``fun``, ``nit``, ``population``, ...), or the legacy
        ``callback(x, convergence)``. Returning True or raising `StopIteration`
        stops the run (polishing still happens).
    disp : bool, optional
        Print the best energy at every generation.
    polish : bool or callable, optional
        Polish the best member with `~scipy.optimize.minimize` (L-BFGS-B, or
        trust-constr with constraints) at the end, or with a callable
        ``polish(func, x0, **kwds)`` returning an `OptimizeResult`. Default True.
    init : str or array_like, optional
        ``'latinhypercube'`` (default), ``'sobol'``, ``'halton'``, ``'random'``, or
        an initial population of shape (S, N), clipped to the bounds.
    updating : {'immediate', 'deferred'}, optional
        Update the best member after every trial, or once per generation.
        ``workers != 1`` and ``vectorized=True`` switch to ``'deferred'`` (with a
        warning, as SciPy).
    workers : int or map-like callable, optional
        Evaluate the population in parallel: an int (a `multiprocessing.Pool` of that
        many processes; -1 for all cores) or a map-like callable
        ``workers(func, iterable)``. `func` must then pickle.
    constraints : {NonlinearConstraint, LinearConstraint, Bounds} or sequence, optional
        Constraints beyond `bounds` (Lampinen's approach).
    x0 : array_like, optional
        Initial guess of shape (N,), placed in the initial population.
    integrality : array_like of bool, optional
        Which parameters are integers.
    vectorized : bool, optional
        `func` evaluates a whole population at once: ``x.shape == (N, S)``.
    seed : optional
        Legacy name of `rng` (SciPy's ``seed`` keyword).
    population_size : int, optional
        *vhfit extra.* Absolute number of population members (NP, as in the paper),
        instead of SciPy's per-parameter multiplier `popsize`. At least 5.
    stop : StopCriterion or callable or str or sequence, optional
        *vhfit extra.* Stopping criteria checked after every generation, replacing
        SciPy's `tol`/`atol` test (`maxiter` still caps the run). Criteria combine
        with ``|`` (any) and ``&`` (all); a plain callable ``f(state) -> bool | str``
        is accepted; ``"paper"`` is the paper's four criteria
        (:func:`~vhfit.optimize.paper_criteria`). Built in:
        :class:`~vhfit.optimize.MeanImprovement`, :class:`~vhfit.optimize.BestMeanGap`,
        :class:`~vhfit.optimize.MaxGenerations`, :class:`~vhfit.optimize.TargetValue`,
        :class:`~vhfit.optimize.MaxEvaluations`, :class:`~vhfit.optimize.MaxTime`,
        :class:`~vhfit.optimize.EnergySpread`. Targets are in the objective's units.
    history : bool, optional
        *vhfit extra.* Record, per generation, the best and mean energy, generation
        number, objective calls, wall time and population size, returned as
        ``result.history`` (a :class:`~vhfit.optimize.DEHistory`). Cheap enough to
        leave on.
    snapshots : int, optional
        *vhfit extra.* Also store the whole population (and its energies) every
        `snapshots`-th generation in ``result.history`` (implies `history`).
        Default 0 (none).
    preset : str, optional
        *vhfit extra.* A named bundle of settings: ``"paper"`` reproduces the paper's
        DE (rand/1/bin, F = 0.8, CR = 0.7, NP = 60, immediate updating, random
        initial population, mutants clipped to the bounds, no polish, the paper's
        four stopping criteria, ``maxiter=100_000``); ``"recommended"`` is what vhfit
        recommends for calibration (see ``docs/optimizer.md``). A preset only fills in
        arguments left at SciPy's default (and extras left at None): anything you
        set explicitly wins.
    repair : {'random', 'clip', 'midpoint'}, optional
        *vhfit extra.* What happens to a trial component that leaves its bounds with
        SciPy's strategies (including callable ones): ``'random'`` (SciPy's
        behaviour: a uniform random value over the whole range), ``'clip'`` (onto
        the bound) or ``'midpoint'`` (halfway between the parent and the bound).
        The adaptive strategies always use ``'midpoint'``.

    Returns
    -------
    res : OptimizeResult
        SciPy's fields: ``x``, ``fun``, ``nfev``, ``nit``, ``success``, ``message``,
        ``population``, ``population_energies``, and ``jac`` (after a successful
        polish) and ``constr``, ``constr_violation``, ``maxcv`` (with constraints).
        When any extra is given, also ``stop_reason`` (the name of the stopping
        criterion that ended the run, or ``'maxiter'``, ``'maxfun'``,
        ``'callback'``, ``'tol'``; ``message`` then names it too), and
        ``history`` when requested. Without extras the result is SciPy's, field for
        field.

    Raises
    ------
    ValueError
        For bounds that are not finite or have a lower bound above the upper one, an
        `x0` whose size does not match the bounds, an unknown strategy, stopping
        criterion, preset or repair mode, or an invalid extra (the message names the
        argument). SciPy's own checks raise what SciPy raises.

    See Also
    --------
    scipy.optimize.differential_evolution : The SciPy function this one extends.
    vhfit.optimize.de : The same solver as a `scipy.optimize.minimize` method.

    Notes
    -----
    *Compatibility.* Every SciPy call works unchanged and SciPy's own test suite for
    differential evolution passes against this function and
    :class:`DifferentialEvolutionSolver`. One deliberate difference: bounds with a
    lower bound above the upper bound are rejected up front (SciPy runs and fails
    only in the final polish, or not at all with ``polish=False``), and so is an
    `x0` of the wrong size (SciPy may broadcast it silently).

    *NaN.* When any extra is used, an objective value of NaN counts as ``+inf``
    (the trial loses every comparison and never becomes the best); plain SciPy
    semantics otherwise.

    *Stopping.* With `stop`, the criteria are checked after each generation, in
    the order given; the first met ends the run, and its name is in
    ``result.stop_reason``. Budget criteria (:class:`~vhfit.optimize.MaxGenerations`,
    :class:`~vhfit.optimize.MaxEvaluations`, :class:`~vhfit.optimize.MaxTime`) give
    ``success=False``, convergence criteria ``success=True``.

    *Bounds and τ.* SciPy's strategies replace an out-of-bounds trial component by
    a uniform random value over the whole range; search relaxation times in
    ``log10 τ`` (see :func:`~vhfit.optimize.tau_bounds`) so that such a draw is
    uniform in decades, or choose ``repair='clip'`` / ``'midpoint'``.

    References
    ----------
    .. [1] R. Storn, K. Price, "Differential evolution - a simple and efficient
       heuristic for global optimization over continuous spaces", J. Glob. Optim.
       11, 341-359 (1997).
    .. [2] SciPy's :func:`scipy.optimize.differential_evolution` and its references.
    .. [3] R. Tanabe, A. Fukunaga, "Improving the search performance of SHADE using
       linear population size reduction", IEEE CEC 2014, 1658-1665.

    Examples
    --------
    Exactly as with SciPy:

    >>> from scipy.optimize import rosen
    >>> from vhfit.optimize import differential_evolution
    >>> res = differential_evolution(rosen, [(0, 2)] * 3, rng=1)
    >>> bool(res.success), bool(abs(res.x - 1).max() < 1e-4)
    (True, True)

    With the extras: the paper's DE, with its stopping criteria and a history.

    >>> import numpy as np
    >>> def sphere(x):
    ...     return np.sum(x**2)
    >>> res = differential_evolution(sphere, [(-5, 5)] * 4, preset="paper",
    ...                              history=True, rng=0)
    >>> res.stop_reason
    'TargetValue'
    >>> int(res.history.nit[-1]) == res.nit
    True

    A self-adaptive strategy with an absolute population size and custom criteria:

    >>> from vhfit.optimize import TargetValue, MaxGenerations
    >>> res = differential_evolution(rosen, [(-2, 2)] * 3, strategy="shade",
    ...                              population_size=30, polish=False, rng=3,
    ...                              stop=TargetValue(1e-8) | MaxGenerations(2000),
    ...                              maxiter=2000)
    >>> res.stop_reason, bool(res.fun < 1e-8)
    ('TargetValue', True)
    """
    with DifferentialEvolutionSolver(
        func, bounds, args=args, strategy=strategy, maxiter=maxiter, popsize=popsize,
        tol=tol, mutation=mutation, recombination=recombination, rng=rng, polish=polish,
        callback=callback, disp=disp, init=init, atol=atol, updating=updating,
        workers=workers, constraints=constraints, x0=x0, integrality=integrality,
        vectorized=vectorized, population_size=population_size, stop=stop,
        history=history, snapshots=snapshots, preset=preset, repair=repair,
    ) as solver:
        ret = solver.solve()
    return ret

