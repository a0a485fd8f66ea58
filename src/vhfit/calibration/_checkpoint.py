"""Checkpoints: the search state at a generation boundary, written atomically, resumed exactly."""

from __future__ import annotations

import hashlib
import json

import numpy as np

from vhfit._io import atomic_write, dumps

__all__ = ["fit_key", "snapshot", "save", "load"]


def fit_key(prob, method, seed, popsize, tol, target, de_options) -> str:
    h = hashlib.sha256()
    for a in (prob.y, prob.scale, prob.batch.sample_stretch, prob.batch.step, prob.tau_b):
        h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
    h.update(repr((prob.model.hyperelastic.name, prob.model.n_prony, method, seed, popsize,
                   tol, target, sorted((de_options or {}).items()),
                   sorted(prob.bounds.items()))).encode())
    return h.hexdigest()


def snapshot(solver, history, elapsed) -> dict:
    """The search state at a generation boundary (all a bit-identical resume needs)."""
    return {
        "format": "vhfit-checkpoint-1",
        "population": solver.population.tolist(),
        "energies": [float(e) if np.isfinite(e) else "inf" for e in solver.population_energies],
        "rng": solver.random_number_generator.bit_generator.state,
        # SciPy shuffles this array in place to pick donors: it is state too
        "index": solver._random_population_index.tolist(),
        "nfev": int(solver._nfev),
        "history": {k: list(v) for k, v in history.items()},
        "elapsed": elapsed,
    }


def save(path, key, snap: dict) -> None:
    atomic_write(path, dumps({**snap, "key": key}))


def load(path, key, solver, history) -> tuple[int, float, str | None]:
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, ValueError) as exc:
        raise ValueError(
            f"checkpoint {path} cannot be read ({exc}); delete it to start afresh"
        ) from None
    if data.get("format") != "vhfit-checkpoint-1" or data.get("key") != key:
        raise ValueError(
            f"checkpoint {path} belongs to a different fit (data, model, seed or options "
            "differ); delete it or drop --resume"
        )
    solver.population = np.array(data["population"], dtype=np.float64)
    solver.population_energies = np.array(
        [np.inf if e == "inf" else e for e in data["energies"]], dtype=np.float64
    )
    solver.random_number_generator.bit_generator.state = data["rng"]
    solver._nfev = int(data["nfev"])
    solver._random_population_index = np.array(data["index"], dtype=np.int64)
    for k in history:
        history[k][:] = data["history"][k]
    return len(history["nit"]), float(data["elapsed"]), data.get("done")
