"""Named bundles of solver settings (``preset=``)."""

from __future__ import annotations

from typing import Any

__all__ = ["presets", "preset_settings", "SCIPY_DEFAULTS"]

#: SciPy's defaults for the arguments a preset may set (differential_evolution's signature).
SCIPY_DEFAULTS: dict[str, Any] = {
    "strategy": "best1bin",
    "maxiter": 1000,
    "popsize": 15,
    "tol": 0.01,
    "mutation": (0.5, 1),
    "recombination": 0.7,
    "polish": True,
    "init": "latinhypercube",
    "atol": 0,
    "updating": "immediate",
}

#: vhfit extras a preset may set; their "not given" value is None.
EXTRA_KEYS = ("population_size", "stop", "repair")

_PRESETS: dict[str, dict[str, Any]] = {
    # The paper's DE (its §2.2; Rodríguez-Mier's tutorial code it was based on):
    # rand/1/bin, F = 0.8, CR = 0.7, NP = 60 absolute, immediate updating, uniform
    # random initial population, mutants clipped to the bounds, no polishing, the
    # four stopping criteria, up to 100 000 generations.
    "paper": {
        "strategy": "rand1bin",
        "mutation": 0.8,
        "recombination": 0.7,
        "updating": "immediate",
        "init": "random",
        "polish": False,
        "maxiter": 100_000,
        "population_size": 60,
        "stop": "paper",
        "repair": "clip",
    },
    # What vhfit recommends for calibration problems (benchmarks/bench_optimize.py:
    # about 15x fewer evaluations than the paper's DE to RMSAPE < 0.01 %, every run
    # reaching it): SHADE with NP = 60, deferred updating (so it vectorises and
    # parallelises), the paper's stopping criteria, up to 100 000 generations, no
    # final polish.
    "recommended": {
        "strategy": "shade",
        "updating": "deferred",
        "polish": False,
        "maxiter": 100_000,
        "population_size": 60,
        "stop": "paper",
    },
}


def presets() -> tuple[str, ...]:
    """Names accepted by ``preset=``."""
    return tuple(_PRESETS)


def preset_settings(name: str) -> dict[str, Any]:
    """A copy of the settings of preset `name`.

    Raises
    ------
    ValueError
        If `name` is not a known preset (the message lists them).
    """
    if not isinstance(name, str) or name not in _PRESETS:
        raise ValueError(f"preset: unknown preset {name!r}; available: {list(_PRESETS)}")
    return dict(_PRESETS[name])
