"""The global search: differential evolution over a search space, with checkpoints.

The search is :class:`vhfit.optimize.DifferentialEvolutionSolver` with its own stopping
criteria (:mod:`vhfit.optimize`'s ``TargetValue``, ``MaxTime``, ``BestMeanGap`` and
``MeanImprovement``), its generation history, and its state for checkpoints.
"""

from __future__ import annotations

import os
import time
import warnings
from dataclasses import dataclass

import numpy as np

from vhfit._pools import worker_map
from vhfit._words import Worded
from vhfit.calibration import _checkpoint
from vhfit.calibration._polish import ROUNDING_TOL
from vhfit.calibration._polish import polish as polish_fit
from vhfit.calibration._stop import Stop, StopKind
from vhfit.calibration._varpro import VARPRO_NFEV, varpro_polish, varpro_polish_many

__all__ = ["Search", "run_search", "check_de_options", "CalibrationError", "HOPELESS",
           "search_items", "search_problem", "final_polish", "SEARCH_POINTS",
           "SEARCH_RTOL"]


class CalibrationError(Worded, ValueError):
    """The calibration found no parameter set with a finite error: no result to return.

    A ``ValueError`` (the command line exits with code 2): the data, the law or the
    bounds given cannot go together; the message says which and what to change.
    """


#: Generations after which a search whose every individual so far had an infinite error
#: (the law undefined on the data everywhere it looked) gives up.
HOPELESS = 50

#: Solver keywords that calibrate sets itself, and what to do instead.
_ARGUMENT = "use its {} argument instead"
OWN_DE_KEYS = {
    "popsize": _ARGUMENT.format("popsize"), "population_size": _ARGUMENT.format("popsize"),
    "maxiter": _ARGUMENT.format("maxiter"), "tol": _ARGUMENT.format("tol"),
    "atol": _ARGUMENT.format("tol"), "stop": _ARGUMENT.format("tol, target, max_time or callback"),
    "rng": _ARGUMENT.format("seed"), "seed": _ARGUMENT.format("seed"),
    "polish": _ARGUMENT.format("polish"), "callback": _ARGUMENT.format("callback"),
    "workers": _ARGUMENT.format("workers"), "vectorized": _ARGUMENT.format("workers"),
    "preset": _ARGUMENT.format("method"),
    "history": "calibrate always records it (Calibration.history)",
    "snapshots": "calibrate keeps no population snapshots",
}


def check_de_options(de_options) -> dict:
    """The user's solver keywords, refused where calibrate owns the setting."""
    opts = dict(de_options or {})
    for k in opts:
        if k in OWN_DE_KEYS:
            raise ValueError(
                f"de_options[{k!r}] is set by calibrate: {OWN_DE_KEYS[k]}"
            )
    return opts


@dataclass
class Search:
    """Outcome of the global search."""

    z: np.ndarray
    nit: int
    nfev: int
    stop: Stop
    history: dict
    t0: float  # start time, moved back by the time a resumed run had already spent
    polished: tuple | None = None  # (x, error) of the polish that ended the search early


#: Objective points a curve keeps in the separable search when it has more (a long
#: record: hundreds of bin means, each an output node of the model's integration grid).
#: The search only has to find the basin of the best fit; the polish that follows and
#: the reported error use every point of the curve. On the shared real datasets the
#: fits from 50 points equal those from 100 (to 6 digits; VHB 4910 records 15-35 %
#: faster, benchmarks/bench_real.py).
SEARCH_POINTS = 50
#: Accuracy of the model in the separable search of every record with Prony terms
#: (``rtol`` of :class:`vhfit.ViscoHyperelastic`: steps of ln λ up to 0.06 instead of
#: 0.019 at the default 1e-6), far below the misfit of a real record; the polish and the
#: reported error use the calibration's own. (Exact data stop at this model's own floor,
#: ~1e-3 %: there a polish on every point decides whether the target is reached.)
SEARCH_RTOL = 1e-4
#: The fields of a :class:`Problem` that depend on its curves and model.
_CURVE_FIELDS = ("model", "hm", "batch", "objective", "y", "scale")


def search_items(curves, limit: int = SEARCH_POINTS) -> list | None:
    """The curves the global search compares, or None when they are the curves themselves.

    A curve of the model's time integration (not equilibrium, not moduli) with more
    than ``limit`` objective points is compared at fewer: the means of about ``limit``
    bins of its samples where its points are its samples or their bin means (the same
    policy as ``MAX_POINTS``, at a smaller cap), else ``limit`` points spaced as its own
    (divided among the segments of a curve spaced by segment). Its history, weight and
    window are kept. A curve with weights per point, or that cannot be resampled so,
    is compared as it is.
    """
    from vhfit.data import Curve

    out, changed = [], False
    for c in curves:
        long = isinstance(c, Curve) and not c.is_equilibrium and c.n_points > limit
        w = np.asarray(c.target_weights) if long else None
        if long and np.all(w == w[0]):  # per-point weights belong to the points they weigh
            try:
                if c.by in ("samples", "bins"):
                    r = c.resample(None, max_points=limit)
                else:
                    per = limit // max(1, c.n_segments) if c.by == "segments" else limit
                    r = c.resample(max(2, per), by=c.by)
            except ValueError:  # a DataError: the curve as it is
                r = c
            if r.n_points < c.n_points:
                out.append(r)
                changed = True
                continue
        out.append(c)
    return out if changed else None


def search_problem(prob, curves):
    """The problem the separable search compares: the same search space (bounds, τ
    range, admissible set) with a cheaper objective — a model of accuracy
    ``SEARCH_RTOL`` (with Prony terms: its time integration on a coarser grid), on
    fewer points for long records (:func:`search_items`); ``prob`` itself where
    neither applies (no Prony terms, or a model no finer than that)."""
    import copy

    from vhfit.calibration._space import Problem
    from vhfit.model import model_from_spec

    fewer = search_items(curves)
    m = prob.model
    if fewer is None:
        if m.rtol >= SEARCH_RTOL or m.n_prony == 0:  # nothing coarser to search on
            return prob
        fewer = curves  # the same points, the coarser model
    model = model_from_spec(m.spec().replace(rtol=max(m.rtol, SEARCH_RTOL)))
    short = Problem(model, fewer, prob.tau_b, prob.bounds, prob.g_inf_min,
                    prob.objective_spec)
    out = copy.copy(prob)
    for k in _CURVE_FIELDS:
        setattr(out, k, getattr(short, k))
    out.coarse = True
    return out


#: Tolerances (xtol, ftol, gtol) of the polish on every point after a search on the
#: coarser problem (:func:`search_problem`): the error is settled to ~1e-10 relative long
#: before the iterations reach rounding (a real record's last ~half of them, at the cost
#: of the whole record each).
FINAL_TOL = 1e-10


#: Tolerances of the polishes of the search's own members on the coarser problem (the
#: one that ends a gathered search, the other basins'): the polish on every point follows
#: from where they end, so settling them further only repeats its work.
COARSE_TOL = 1e-8


def gathered_polish(space, z, max_nfev: int = VARPRO_NFEV):
    """:func:`varpro_polish` of a search's member: to rounding on the problem's own
    points (its result is the fit), to :data:`COARSE_TOL` on the coarser problem
    (:func:`search_problem`; the polish on every point follows)."""
    return varpro_polish(space, z, max_nfev,
                         tol=COARSE_TOL if space.prob.coarse else ROUNDING_TOL)


def final_polish(space, found: Search, x: np.ndarray, err: float):
    """The polish after a search that did not end by a polish on ``space``'s own points:
    ``(x, err, evaluations)``, never a higher error than ``err`` at ``x``.

    A search on the coarser problem (:func:`search_problem`) that ended on a gathered
    population (:class:`_EarlyFinish`) continues in the space's coordinates on every
    point (:func:`varpro_polish` from ``found.z``, to :data:`FINAL_TOL`; a gathered
    search on the space's own points has its polish, ``found.polished``, as its result,
    a resumed one too); any other, the all-parameter polish, from its polish on the
    search's problem if that is lower on every point.
    """
    prob = space.prob
    if found.stop.kind is StopKind.GATHERED:
        _, x1, e1, n = varpro_polish(space, found.z, tol=FINAL_TOL)
        return (x1, e1, n) if e1 < err else (x, err, n)
    if found.polished is not None:  # polished on the search's points: start from it
        xp = found.polished[0]
        ep = float(prob.errors(xp[None, :])[0])
        if ep < err:
            x, err = xp, ep
    return polish_fit(prob, x)


def _chunk_errors(args) -> np.ndarray:
    space, Z = args
    return space.errors(Z)


class _Objective:
    """The DE objective, vectorised (SciPy passes (d, S)); a map spreads the chunks."""

    def __init__(self, space, mapper=None, chunks: int = 1):
        self.space, self.mapper, self.chunks = space, mapper, chunks
        self.nfev = 0  # individuals evaluated

    def __call__(self, Zt: np.ndarray) -> np.ndarray:
        Z = np.atleast_2d(Zt.T) if Zt.ndim > 1 else Zt[None, :]
        self.nfev += Z.shape[0]
        if self.mapper is None:
            return self.space.errors(Z)
        parts = np.array_split(Z, min(self.chunks, Z.shape[0]))
        out = list(self.mapper(_chunk_errors, [(self.space, z) for z in parts]))
        return np.concatenate(out)


#: The lowest members of the first population that are polished after a search that
#: ended on a gathered population (briefly, side by side; the lowest of them to the end
#: if it beats the search's result). On the Ogden-2 recovery of
#: benchmarks/bench_admissible.py (μ2 < 0), searched on 50 points a curve: before the
#: admissible arc of each shape (docs/theory.md §11), 12 reached the material on seeds
#: 0-5 of 0-6, 8 on 5 of them, 16 as 12 at a third more time on the VHB 4910 records;
#: on the arc (50 samples a curve) 12 reach it on all of seeds 0-7, 8 on 7 (not seed 5).
OTHER_BASINS = 12
#: Least-squares steps of each of those polishes (their Jacobian rows not counted)
#: before the lowest goes on to the end (on the same recovery, searched on 100 points:
#: 12 steps reached the material on 4 of seeds 0, 2, 3, 4, 6, 40 on all 5 at twice the
#: cost, 6 on 3).
OTHER_NFEV = 12


def other_basins(space, z, polished, first):
    """The best of the search's result and polishes of the lowest members of its first
    population that lie in other basins: ``(z, polished, evaluations)``.

    A population that gathered has searched one basin; on a law whose constants can
    trade off in several (Ogden terms of either sign, τ shifted together) it may not be
    the lowest. The first population ``first`` (search vectors) is a Sobol sample of the
    whole box, the same for a search resumed from a checkpoint: its lowest members start
    a polish each (:func:`varpro_polish`, :data:`OTHER_NFEV` steps), and the lowest of
    those goes on to the end when it is below the result ``polished`` (x, error) at
    ``z``."""
    E = space.errors(first)
    err = polished[1]
    order = [i for i in np.argsort(E)[:OTHER_BASINS] if np.isfinite(E[i])]
    n, scouts = len(first), []
    # short polishes: which basin is lower
    for z1, _, e1, k in varpro_polish_many(space, first[order], OTHER_NFEV, tol=1e-8,
                                           on_arc=True):
        n += k
        scouts.append((e1, z1))
    if scouts:
        e1, z1 = min(scouts, key=lambda ez: ez[0])
        if e1 < err * (1 - 1e-9):
            z1, x1, e1, k = gathered_polish(space, z1)
            n += k
            if e1 < err * (1 - 1e-9):
                z, polished = z1, (x1, e1)
    return z, polished, n


def stop_criteria(tol, target, stall, max_time):
    """The criteria that end the search, in the order they are tested, and their reasons."""
    from vhfit.optimize import BestMeanGap, MaxTime, MeanImprovement, TargetValue

    rel, window = stall
    crits = [TargetValue(target)]
    if max_time is not None:
        crits.append(MaxTime(max_time))
    crits += [BestMeanGap(tol), MeanImprovement(rel, window)]
    reasons = {
        "TargetValue": Stop.of(StopKind.TARGET), "MaxTime": Stop.of(StopKind.MAX_TIME),
        "BestMeanGap": Stop.of(StopKind.CONVERGED),
        "MeanImprovement": Stop.stalled(rel, window),
        "maxiter": Stop.of(StopKind.MAX_ITER), "callback": Stop.of(StopKind.CALLBACK),
    }
    return crits, reasons


def _history(solver, setup: float = 0.0) -> dict:
    """The generations of the run (not the initial population); times include ``setup``."""
    h = None if solver is None else solver.history
    if h is None or len(h) < 2:
        return {"nit": [], "best": [], "mean": [], "time": []}
    return {"nit": h.nit[1:].tolist(), "best": h.best[1:].tolist(),
            "mean": h.mean[1:].tolist(), "time": (h.time[1:] + setup).tolist()}


def run_search(space, settings, *, n_prony: int, checkpoint, max_time: float | None,
               t0: float, x0: np.ndarray | None = None, full=None, seeds=None) -> Search:
    """Differential evolution over ``space`` until a stopping criterion is met.

    ``settings`` (a :class:`CalibrationSettings`) gives the search's seed, population,
    stopping tests, workers, callback, solver options and checkpoint period;
    ``checkpoint`` and ``max_time`` are this search's own (one of a scan over N). With
    ``settings.polish`` a polish follows the search, which may then stop as soon as a
    polish of its best member reaches the target (:class:`_EarlyFinish`). ``x0``, a
    search vector inside the bounds, replaces the first member of the first population;
    ``seeds`` (k, d), search vectors inside the bounds, each replace the highest member
    where they are lower than every member drawn (the fits of contained laws).
    ``full``: the :class:`Problem` on every point at the calibration's accuracy when
    ``space`` compares the coarser one (:func:`search_problem`), where a polish that
    reaches the coarser problem's floor checks the target.
    """
    s = settings
    seed, workers, popsize = s.seed, s.workers, s.popsize
    tol, target, de_options = s.effective_tol, s.target, s.de_options
    if not space.bounds():  # nothing nonlinear to search (e.g. neo-Hooke with fixed τ)
        return Search(np.zeros(0), 0, 0, Stop.of(StopKind.NOTHING), _history(None), t0)
    opts = {**space.de_options, **check_de_options(de_options)}
    if workers != 1 and opts["updating"] != "deferred":
        raise ValueError(
            "updating='immediate' evaluates one trial at a time and cannot use workers: "
            "use workers=1 or deferred updating"
        )
    key = _checkpoint.fit_key(space.prob, space.layout, seed, popsize, tol, target, de_options)
    ckpt = None if checkpoint is None else str(checkpoint)
    left = None if max_time is None else max(0.0, max_time - (time.perf_counter() - t0))
    crits, reasons = stop_criteria(tol, target, s.stall, left)
    t_in = t0
    track = _Tracker(s.callback, n_prony, ckpt, key, s.checkpoint_every, t0)
    if s.polish:
        track.finish = _EarlyFinish(space, target, tol, full)
    with worker_map(workers) as (mapper, chunks):
        objective = _Objective(space, mapper, chunks)
        solver = new_solver(space, s, objective, track, crits, x0=x0, seeds=seeds)
        b = np.asarray(space.bounds(), dtype=np.float64).reshape(-1, 2)
        first = b[:, 0] + solver.population * (b[:, 1] - b[:, 0])  # (before any resume)
        with solver:
            track.solver = solver
            finished = None
            if s.resume and ckpt is not None and os.path.exists(ckpt):
                state, done_before, finished, elapsed = _checkpoint.resume(ckpt, key, solver)
                track.state, track.evaluations = state, done_before
                objective.nfev = done_before
                t0 -= elapsed
                track.t0 = t0
            setup = time.perf_counter() - t_in  # the solver's clock counts the search only
            track.objective = objective
            z, stop = _solve(solver, track, finished, reasons)
            polished = None
            if track.finish is not None and track.finish.done:
                stop = track.finish.reason
                polished = track.finish.result
                if track.finish.z is not None:
                    z = track.finish.z
            if track.finish is not None:
                objective.nfev += track.finish.nfev
            if stop.kind is StopKind.GATHERED and polished is None:
                # resumed after it had ended: its polish again, to end where it did
                z, x, e, n = gathered_polish(space, z)
                polished = (x, e)
                objective.nfev += n
            elif (stop.kind is StopKind.TARGET_POLISHED and polished is None
                  and track.finish is not None):
                x, e, n = track.finish.level_polish(z)  # (the same: resumed after it)
                polished = (x, e)
                objective.nfev += n
            if stop.kind is StopKind.GATHERED and space.several_basins():
                z, polished, n = other_basins(space, z, polished, first)
                objective.nfev += n
            if ckpt is not None and track.state is not None:
                _checkpoint.save(ckpt, key, track.state, track.evaluations,
                                 None if stop.interrupted else stop)
            history = _history(solver, setup)
    return Search(np.asarray(z), len(history["nit"]), objective.nfev, stop, history, t0,
                  polished)


def new_solver(space, settings, objective, callback=None, stop=None, x0=None, seeds=None):
    """The search's :class:`vhfit.optimize.DifferentialEvolutionSolver` over ``space``
    (its population, generations, seed and solver options from ``settings``; ``x0``, if
    given, the first member of its first population; ``seeds`` (k, d), members where
    they are lower than every member drawn), before any generation: the one a
    checkpoint of this search is resumed into."""
    from vhfit.optimize import DifferentialEvolutionSolver

    s = settings
    opts = {**space.de_options, **check_de_options(s.de_options)}
    with warnings.catch_warnings():
        # any prefix of a scrambled Sobol sequence fills the box well; its
        # "balance" needs a power of two only for quadrature, not for a start
        warnings.filterwarnings("ignore", "The balance properties of Sobol", UserWarning)
        return DifferentialEvolutionSolver(
            objective, space.bounds(), maxiter=s.maxiter or space.maxiter,
            population_size=s.popsize or space.popsize, tol=0.0, atol=0.0,
            rng=np.random.default_rng(s.seed), polish=False, callback=callback,
            vectorized=opts["updating"] == "deferred", stop=stop, history=True,
            x0=x0, seeds=seeds, **opts)


def _solve(solver, track, finished, reasons) -> tuple[np.ndarray, Stop]:
    """Run (or, for a search that had ended, do not run) the solver: (z, stop reason)."""
    if finished:  # the search had ended before the run was cut: don't extend it
        return solver.x, finished
    try:
        res = solver.solve()
    except KeyboardInterrupt:
        best = track.best_x if track.best_x is not None else solver.x
        return best, Stop.of(StopKind.INTERRUPTED)
    if track.hopeless:
        return res.x, Stop.no_finite(HOPELESS)
    return res.x, reasons.get(res.stop_reason) or Stop(StopKind.OTHER, str(res.message))


class _Tracker:
    """The solver's callback: best member so far, checkpoints, the user's callback."""

    def __init__(self, callback, n_prony, ckpt, key, every, t0):
        self.callback, self.n_prony = callback, n_prony
        self.t0 = t0  # calibrate's start: the callback's "elapsed" counts from it
        self.ckpt, self.key, self.every = ckpt, key, every
        self.solver = self.objective = None
        self.state = None  # the last generation boundary's solver state
        self.evaluations = 0  # individuals evaluated up to that boundary
        self.best_x, self.best_f = None, np.inf
        self.saved = time.perf_counter()
        self.finish = None  # an _EarlyFinish, if a polish follows the search
        self.hopeless = False  # stopped: no finite individual in HOPELESS generations

    def __call__(self, intermediate_result) -> bool:
        r = intermediate_result
        best = float(r.fun)
        e = np.asarray(r.population_energies)
        mean = float(e.sum()) / e.size
        if best < self.best_f:
            self.best_f, self.best_x = best, np.array(r.x)
        if self.ckpt is not None:
            # a Ctrl-C may land mid-generation: only boundary states are ever written
            self.state = self.solver.state_dict()
            self.evaluations = self.objective.nfev
            if time.perf_counter() - self.saved >= self.every:
                _checkpoint.save(self.ckpt, self.key, self.state, self.evaluations)
                self.saved = time.perf_counter()
        if self.best_f == np.inf and int(r.nit) >= HOPELESS:
            self.hopeless = True  # nothing finite anywhere it looked: give up
            return True
        if self.finish is not None and self.finish(best, np.asarray(r.x), mean):
            return True
        if self.callback is None:
            return False
        return bool(self.callback({
            "generation": int(r.nit), "best": best, "mean": mean,
            "elapsed": time.perf_counter() - self.t0, "n_prony": self.n_prony,
            "x": np.array(r.x)}))


class _EarlyFinish:
    """Stop the search once a polish of its best member reaches the target, or once the
    population has gathered in one basin and a polish of its best member finds the
    bottom of it.

    *Levels.* Where the space allows it (``space.finish_levels``: laws with several
    linear constants and a nonlinear shape, such as Ogden with 2+ terms) the best member
    is polished the first time its error falls below each level: DE's approach crawls
    along curved valleys that least squares crosses in a few steps. If a polish gets
    well below the target (``ACCEPT`` times it: where the search would have stopped,
    the final polish usually goes that far too) the search stops and hands the
    polished point to the caller (``Search.polished``: its polish would repeat the same
    steps); if not, the search goes on as it would have, having spent that polish.

    *Collapse* (the separable search only, ``space.separable``): data that
    no member of the law fits exactly (every real record) never reach the target, and
    the search used to run until the best–mean gap of its generation fell below
    ``tol`` (1e-6), hundreds of generations after the population had settled in one
    valley, crawling along it to the minimum the final polish then finds anyway. The
    first time the gap falls below ``COLLAPSE`` (every member within 1e-3 of the best
    error, on average) the best member is polished once, in the space's own coordinates with the
    linear constants solved exactly (:func:`varpro_polish`); if the polish lowers its
    error the search stops with it (it is at the bottom of the basin where the
    population has gathered, where the search would have ended; ``Search.z`` is the
    polished vector); if not, the search goes on as it would have. A search whose
    ``tol`` is 0 (no stop by the best–mean gap) never ends this way.
    """

    ACCEPT = 1e-2
    MAX_NFEV = 200  # the final polish's own budget
    # best–mean gap, relative to the mean, at which the best is polished: at 1e-3 rather
    # than 1e-4 the VHB 4910 records and the Ogden-2 recoveries of bench_admissible end
    # 10-25 % sooner in the same minima (the other basins' scouts follow either way)
    COLLAPSE = 1e-3

    def __init__(self, space, target: float, tol: float = 1e-6, full=None):
        self.space, self.target = space, float(target)
        self.full = full  # the calibration's own problem, when the search's is coarser
        self.levels = sorted((float(v) for v in space.finish_levels(target)
                              if v > self.target), reverse=True)
        # below the lowest level the search's own points no longer tell the bottom
        self.floor = self.levels[-1] if self.levels else 0.0
        # a shortcut to the stop by the best–mean gap: never where tol = 0 turns that off
        self.collapse = space.separable and tol > 0
        self.done = False
        self.nfev = 0
        self.result = None  # (x, error) of the last polish
        self.reason = None  # why the search stopped (a Stop), once done
        self.z = None  # the search vector of a polish in the space's own coordinates

    def __call__(self, best: float, z: np.ndarray, mean: float = np.inf) -> bool:
        if self.levels and best <= self.levels[0]:
            while self.levels and best <= self.levels[0]:
                self.levels.pop(0)  # one polish covers every level the error has passed
            x, err, n = self.level_polish(z)
            self.nfev += n
            self.result = (x, err)
            self.done = bool(err <= self.ACCEPT * self.target)
            self.reason = Stop.of(StopKind.TARGET_POLISHED)
            return self.done
        if self.collapse and np.isfinite(mean) and mean - best <= self.COLLAPSE * mean:
            self.collapse = False  # once: a polish that did not help is not repeated
            z1, x, err, n = gathered_polish(self.space, z)
            self.nfev += n
            self.result = (x, err)
            self.z = z1
            self.done = bool(err < best)
            self.reason = Stop.of(StopKind.GATHERED)
            return self.done
        return False

    def level_polish(self, z: np.ndarray) -> tuple[np.ndarray, float, int]:
        """The polish of the best member ``z`` at a level: ``(x, error, evaluations)``."""
        x, err, n = polish_fit(self.space.prob, self.space.to_params(z), self.MAX_NFEV)
        if self.full is not None and self.target < err <= self.floor:
            # a coarser model (and fewer points) have an error floor of their own
            # (~1e-3 % on exact data): whether the target is in reach is a question
            # for every point at the calibration's accuracy
            x, err, n2 = polish_fit(self.full, x, self.MAX_NFEV)
            n += n2
        return x, err, n
