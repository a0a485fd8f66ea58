"""The global search: differential evolution over a search space, with checkpoints."""

from __future__ import annotations

import os
import time
import warnings
from dataclasses import dataclass

import numpy as np

from vhfit._pools import worker_map
from vhfit.calibration import _checkpoint

__all__ = ["Search", "run_search", "check_de_options"]

#: Solver keywords that calibrate sets itself, and the argument to use instead.
OWN_DE_KEYS = {
    "popsize": "popsize", "population_size": "popsize", "maxiter": "maxiter",
    "tol": "tol", "atol": "tol", "stop": "tol, target, max_time or callback",
    "rng": "seed", "seed": "seed", "polish": "polish", "callback": "callback",
    "workers": "workers", "vectorized": "workers", "preset": "method",
}


def check_de_options(de_options, checkpoint) -> dict:
    """The user's solver keywords, refused where calibrate owns the setting."""
    if de_options is not None and not isinstance(de_options, dict):
        raise ValueError(f"de_options = {de_options!r}: give a dict of solver keywords or None")
    opts = dict(de_options or {})
    for k in opts:
        if k in OWN_DE_KEYS:
            raise ValueError(
                f"de_options[{k!r}] is set by calibrate: use its {OWN_DE_KEYS[k]} "
                "argument instead"
            )
    from vhfit.optimize import AdaptiveStrategy, adaptive_strategies

    strategy = opts.get("strategy")
    adaptive = isinstance(strategy, AdaptiveStrategy) or (
        isinstance(strategy, str) and strategy in adaptive_strategies())
    if adaptive and checkpoint is not None:
        raise ValueError(
            f"de_options['strategy'] = {strategy!r} adapts its own state, which checkpoints "
            "do not save: drop checkpoint/resume or use one of SciPy's strategies"
        )
    return opts


@dataclass
class Search:
    """Outcome of the global search."""

    z: np.ndarray
    nit: int
    nfev: int
    stop: str
    history: dict
    t0: float  # start time, moved back by the time a resumed run had already spent


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


def run_search(space, *, n_prony, seed, workers, popsize, maxiter, tol, target, stall, callback,
               de_options, checkpoint, checkpoint_every, resume, max_time, t0) -> Search:
    """Differential evolution over ``space`` until a stopping test fires."""
    prob = space.prob
    history = {"nit": [], "best": [], "mean": [], "time": []}
    state = {"best_x": None, "best_f": np.inf, "stop": None, "saved": time.perf_counter()}
    key = _checkpoint.fit_key(prob, space.method, seed, popsize, tol, target, de_options)
    ckpt = None if checkpoint is None else str(checkpoint)
    dbounds = space.bounds()
    npop = popsize or space.popsize
    cap = maxiter or space.maxiter

    def cb(intermediate_result):
        e = np.asarray(getattr(solver_ref.get("s"), "population_energies", [np.nan]))
        best = float(intermediate_result.fun)
        mean = float(np.mean(e[np.isfinite(e)])) if np.isfinite(e).any() else np.inf
        el = time.perf_counter() - t0
        history["nit"].append(len(history["nit"]) + 1)
        history["best"].append(best)
        history["mean"].append(mean)
        history["time"].append(el)
        if best < state["best_f"]:
            state["best_f"], state["best_x"] = best, np.array(intermediate_result.x)
        if ckpt is not None:
            # a Ctrl-C may land mid-generation: only boundary states are ever written
            state["snap"] = _checkpoint.snapshot(solver_ref["s"], history, el)
            if time.perf_counter() - state["saved"] >= checkpoint_every:
                _checkpoint.save(ckpt, key, state["snap"])
                state["saved"] = time.perf_counter()
        if callback is not None and callback({"generation": len(history["nit"]), "best": best,
                                             "mean": mean, "elapsed": el, "n_prony": n_prony,
                                             "x": np.array(intermediate_result.x)}):
            state["stop"] = "callback"
            return True
        if best <= target:
            state["stop"] = "target reached"
            return True
        if max_time is not None and el > max_time:
            state["stop"] = "max_time"
            return True
        if np.isfinite(mean) and mean - best <= tol * max(best, 1e-300):
            state["stop"] = "converged"
            return True
        rel, window = stall
        if len(history["mean"]) > window:
            old = history["mean"][-window - 1]
            if np.isfinite(old) and old - mean < rel * old:
                state["stop"] = f"mean error improved < {rel:.0%} over {window} generations"
                return True
        return False

    solver_ref: dict = {}
    if not dbounds:  # nothing nonlinear to search (e.g. neo-Hooke with fixed τ)
        return Search(np.zeros(0), 0, 0, "nothing to search", history, t0)
    from vhfit.optimize import DifferentialEvolutionSolver

    opts = dict(space.de_options)
    opts.update(check_de_options(de_options, ckpt))
    if workers != 1 and opts["updating"] != "deferred":
        raise ValueError(
            "updating='immediate' evaluates one trial at a time and cannot use workers: "
            "use workers=1 or deferred updating"
        )
    vec = opts["updating"] == "deferred"

    def make_solver(objective):
        with warnings.catch_warnings():
            # any prefix of a scrambled Sobol sequence fills the box well; its
            # "balance" needs a power of two only for quadrature, not for a start
            warnings.filterwarnings("ignore", "The balance properties of Sobol", UserWarning)
            return DifferentialEvolutionSolver(
                objective, dbounds, maxiter=cap, population_size=npop, tol=0.0, atol=0.0,
                rng=np.random.default_rng(seed), polish=False, callback=cb,
                vectorized=vec, **opts)

    with worker_map(workers) as (mapper, chunks):
        objective = _Objective(space, mapper, chunks)
        with make_solver(objective) as solver:
            solver_ref["s"] = solver
            finished = None
            if resume and ckpt is not None and os.path.exists(ckpt):
                done, elapsed, finished = _checkpoint.load(ckpt, key, solver, history)
                solver.maxiter = max(cap - done, 0)
                t0 -= elapsed - (time.perf_counter() - t0)
            try:
                if finished:  # the search had ended before the run was cut: don't extend it
                    z, stop = solver.x, finished
                else:
                    res = solver.solve()
                    z = res.x
                    stop = state["stop"] or (
                        "maxiter" if len(history["nit"]) >= cap else res.message)
            except KeyboardInterrupt:
                stop = "interrupted"
                z = state["best_x"] if state["best_x"] is not None else solver.x
            nit = len(history["nit"])
            if ckpt is not None and state.get("snap") is not None:
                snap = state["snap"] if stop == "interrupted" else {**state["snap"], "done": stop}
                _checkpoint.save(ckpt, key, snap)
        nfev = max(objective.nfev, int(getattr(solver, "_nfev", 0)))
    return Search(np.asarray(z), nit, nfev, stop, history, t0)
