"""Optimisation for vhfit: SciPy-compatible differential evolution and τ search bounds.

``from vhfit.optimize import differential_evolution`` is a drop-in replacement for
SciPy's, with keyword-only extras (absolute population size, composable stopping
criteria, per-generation history, the paper's preset, self-adaptive strategies).
``de`` plugs the same solver into :func:`scipy.optimize.minimize`; ``tau_bounds``
gives the paper's search bounds for the Prony relaxation times (Eq. 22).

"The paper" here is *Visco-hyperelastic material model fitting to experimental
stress–strain curves using a genetic algorithm and its application to soft tissue
simulants*; its §2.2 describes the algorithm, the stopping criteria and the τ bounds.
"""

from vhfit.optimize._history import DEHistory
from vhfit.optimize._presets import preset_settings, presets
from vhfit.optimize._stopping import (
    AllOf,
    AnyOf,
    BestMeanGap,
    EnergySpread,
    FunctionCriterion,
    MaxEvaluations,
    MaxGenerations,
    MaxTime,
    MeanImprovement,
    StopCriterion,
    StopState,
    TargetValue,
    paper_criteria,
)
from vhfit.optimize._strategies import JDE, LSHADE, SHADE, AdaptiveStrategy, adaptive_strategies
from vhfit.optimize._tau import (
    TauBounds,
    register_tau_strategy,
    tau_bounds,
    tau_range,
    tau_strategies,
)

# the search itself needs scipy.optimize (~0.3 s): loaded when first asked, so that
# reading the τ strategies (``vhfit models``, the parser) does not pay for it
_LAZY = {"DifferentialEvolutionSolver": "vhfit.optimize._de",
         "differential_evolution": "vhfit.optimize._de",
         "de": "vhfit.optimize._minimize"}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'vhfit.optimize' has no attribute {name!r}")


__all__ = [
    "differential_evolution",
    "DifferentialEvolutionSolver",
    "de",
    "tau_bounds",
    "tau_range",
    "TauBounds",
    "register_tau_strategy",
    "tau_strategies",
    "DEHistory",
    "StopCriterion",
    "StopState",
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
    "AdaptiveStrategy",
    "JDE",
    "SHADE",
    "LSHADE",
    "adaptive_strategies",
    "presets",
    "preset_settings",
]
