"""Stress measures: engineering (nominal) and true (Cauchy) stress in uniaxial tension or
compression, σ = σ_eng · λ with λ = 1 + ε (docs/theory.md §1)."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["engineering_to_true", "true_to_engineering"]


def engineering_to_true(stress: Any, strain: Any) -> np.ndarray:
    """True (Cauchy) stress from engineering stress: ``σ = σ_eng · λ``, ``λ = 1 + ε``.

    Examples
    --------
    >>> engineering_to_true([-1.0, -2.0], [-0.1, -0.5])
    array([-0.9, -1. ])
    """
    return np.asarray(stress, dtype=np.float64) * (1.0 + np.asarray(strain, dtype=np.float64))


def true_to_engineering(stress: Any, strain: Any) -> np.ndarray:
    """Engineering (nominal) stress from true stress: ``σ_eng = σ / λ``.

    Examples
    --------
    >>> true_to_engineering([-0.9, -1.0], [-0.1, -0.5])
    array([-1., -2.])
    """
    return np.asarray(stress, dtype=np.float64) / (1.0 + np.asarray(strain, dtype=np.float64))
