"""Checkpoints: the solver's state at a generation boundary, written atomically, resumed exactly.

The state itself is :meth:`vhfit.optimize.DifferentialEvolutionSolver.state_dict`; a
checkpoint adds a key that identifies the fit (data, model, search settings), so that a
file of another fit is refused, and marks a search that had already ended.
"""

from __future__ import annotations

import hashlib
import json

import numpy as np

from vhfit._io import atomic_write, dumps
from vhfit.calibration._stop import Stop
from vhfit.modes import get_deformation

__all__ = ["fit_key", "save", "load", "resume", "damaged", "FORMAT"]

FORMAT = "vhfit-checkpoint-2"


def fit_key(prob, layout, seed, popsize, tol, target, de_options) -> str:
    """A digest of everything that makes two fits the same search (``layout``: what its
    search vectors mean, the space's ``layout``)."""
    h = hashlib.sha256()
    for a in (prob.y, prob.scale, prob.batch.sample_stretch, prob.batch.step, prob.tau_b):
        h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
    form = prob.model.formulation
    for hist in prob.batch.histories:  # the paths the uniaxial arrays above do not cover
        if hist.is_linear:  # a sweep's frequencies or a relaxation test's times
            h.update(repr(("linear", hist.kind)).encode())
            h.update(np.ascontiguousarray(hist.x, dtype=np.float64).tobytes())
        elif (not get_deformation(hist.deformation).uniaxial or hist.is_equilibrium
              or form != "hereditary"):
            h.update(repr((hist.deformation, hist.is_equilibrium)).encode())
            for a in (hist.time, hist.stretch, hist.stretch2, hist.out_time,
                      hist.out_direction):
                if a is not None:
                    h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
    h.update(repr((prob.model.hyperelastic.name, prob.model.n_prony, layout, seed, popsize,
                   tol, target, sorted((de_options or {}).items()),
                   sorted(prob.bounds.items()))).encode())
    if form != "hereditary":  # (hereditary keys stay as they were)
        h.update(repr(("formulation", form)).encode())
    # the admissible set searched (docs/theory.md §11): another range, another search
    h.update(repr(("stability_range", prob.stability_range)).encode())
    if not prob.constrained:  # (no admissible set: a search of its own)
        h.update(b"unconstrained")
    return h.hexdigest()


def save(path, key: str, solver_state: dict, evaluations: int, done: Stop | None = None) -> None:
    """Write the solver state, the individuals evaluated so far and, once the search has
    ended, why it ended (its sentence), atomically."""
    atomic_write(path, dumps({"format": FORMAT, "key": key,
                              "done": None if done is None else done.message,
                              "evaluations": int(evaluations), "solver": solver_state}))


def load(path, key: str) -> tuple[dict, int, Stop | None]:
    """The solver state saved in ``path``, the individuals evaluated before it, and the
    stop reason if the search had ended."""
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, ValueError) as exc:
        raise ValueError(
            f"checkpoint {path} cannot be read ({exc}); delete it to start afresh"
        ) from None
    if not isinstance(data, dict) or data.get("format") != FORMAT or data.get("key") != key:
        raise ValueError(
            f"checkpoint {path} belongs to a different fit (data, model, seed or options "
            "differ, or an older vhfit wrote it); delete it or drop --resume"
        )
    evaluations, done = data["evaluations"], data.get("done")
    if type(evaluations) is not int or not 0 <= evaluations < 2**62:
        raise ValueError(f"its evaluation count {evaluations!r} is not a count")
    if done is not None and not (isinstance(done, str) and done):
        raise ValueError(f"its stop reason {done!r} is not one")
    return data["solver"], evaluations, None if done is None else Stop.read(done)


def resume(path, key: str, solver) -> tuple[dict, int, Stop | None, float]:
    """Restore the checkpoint ``path`` of the fit ``key`` into ``solver`` (a new
    :class:`vhfit.optimize.DifferentialEvolutionSolver` of that fit): its state, the
    individuals evaluated before it, the stop reason if the search had ended, and the
    seconds it had run. Anything unreadable or damaged is one ``ValueError`` naming the
    file and saying to delete it."""
    try:
        state, evaluations, done = load(path, key)
        solver.load_state(state)
        elapsed = float(state["elapsed"])
        if (solver.population_energies < 0.0).any():  # errors: >= 0, or +inf
            raise ValueError("its population's errors are negative")
    except (ValueError, KeyError, TypeError, AttributeError, IndexError,
            OverflowError) as exc:
        raise damaged(path, exc) from None
    return state, evaluations, done, elapsed


def damaged(path, exc: Exception) -> ValueError:
    """The one-line error of a checkpoint that cannot be resumed (its own message if it
    already names the file)."""
    why = f"no {exc.args[0]!r} entry" if isinstance(exc, KeyError) else " ".join(
        str(exc).split()) or type(exc).__name__
    if why.startswith(f"checkpoint {path} "):
        return ValueError(why)
    return ValueError(f"checkpoint {path} is damaged and cannot be resumed ({why}); delete "
                      "it to start afresh")
