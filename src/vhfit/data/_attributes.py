"""The read-only attributes of :class:`vhfit.data.Curve`: its data and objective points.

A base class holding only properties, so that the curve module keeps the logic (the
checks, the points, the history, the variants) and stays short.
"""

from __future__ import annotations

from typing import Any

import numpy as np


class _CurveAttributes:
    """Properties of a curve; :class:`vhfit.data.Curve` sets the private fields."""

    # ------------------------------------------------------- measured data
    @property
    def strain(self) -> np.ndarray:
        """Measured engineering strain of each sample (after merging duplicates)."""
        return self._strain

    @property
    def stress(self) -> np.ndarray:
        """Measured stress of each sample in MPa, in :attr:`measure`."""
        return self._stress

    @property
    def time(self) -> np.ndarray | None:
        """Measured time of each sample in s, or ``None`` for a constant-rate curve."""
        return self._time

    @property
    def stretch(self) -> np.ndarray:
        """λ1 = 1 + ε of each sample (in simple shear :attr:`strain` is γ, not λ − 1)."""
        return 1.0 + self._strain

    @property
    def strain_rate(self) -> float | None:
        """Nominal engineering strain rate in 1/s (negative in compression); None for an
        equilibrium curve.

        As given; for a time curve without a given rate it is estimated as the median of
        |dε/dt| over the samples, each step weighted by the strain it applies (so holds
        and sensor noise do not count), with the sign of the loading mode (of the first
        loading for a mixed curve). See :attr:`strain_rate_estimated`. In simple shear
        it is the rate of γ; in a biaxial test, of the path (λ1 or λ2) that moves more.
        """
        return self._rate

    @property
    def strain_rate_estimated(self) -> bool:
        """True if :attr:`strain_rate` was estimated from the time column."""
        return self._rate_estimated

    @property
    def is_constant_rate(self) -> bool:
        """True if the history is a constant-rate ramp (a rate, no time column)."""
        return self._time is None and not self._equilibrium

    @property
    def is_equilibrium(self) -> bool:
        """True for an equilibrium curve (neither rate nor time): fully relaxed states,
        compared with the long-term law alone; its samples need no order."""
        return self._equilibrium

    @property
    def deformation(self) -> str:
        """The test: the name of a registered deformation (``"uniaxial"``, the paper's,
        or another, :func:`vhfit.modes.get_deformation` gives its record)."""
        return self._deformation

    @property
    def strain2(self) -> np.ndarray | None:
        """λ2 − 1 of each sample of a biaxial curve (None otherwise)."""
        return self._strain2

    @property
    def stress2(self) -> np.ndarray | None:
        """Stress in the second loaded direction of each sample, in :attr:`measure`
        (MPa), when it was measured (a test with two loaded directions; None otherwise)."""
        return self._stress2

    @property
    def measure(self) -> str:
        """Stress measure: ``"engineering"`` or ``"true"``."""
        return self._measure

    @property
    def mode(self) -> str:
        """Loading mode: ``"compression"``, ``"tension"`` or ``"mixed"``."""
        return self._mode

    @property
    def name(self) -> str:
        """Name of the curve."""
        return self._name

    @property
    def weight(self) -> float:
        """Weight of the curve in the objective."""
        return self._weight

    @property
    def source(self) -> str | None:
        """File (or other source) the curve was read from."""
        return self._source

    @property
    def metadata(self) -> dict[str, Any]:
        """Free-form information (e.g. a file's ``# key: value`` lines)."""
        return self._metadata

    # ------------------------------------------------------- objective points
    @property
    def n_points(self) -> int:
        """Number of objective points."""
        return int(self._t_obj.size)

    @property
    def n_segments(self) -> int:
        """Number of segments of the history: loading legs between strain reversals, and holds.

        A constant-rate ramp is one segment; see ``by="segments"`` in :class:`Curve`.
        """
        return int(self._bounds.size - 1)

    @property
    def by(self) -> str:
        """How the objective points are spaced: ``"strain"``, ``"time"``, ``"arclength"``,
        ``"segments"``, ``"samples"`` (the measured samples themselves) or ``"bins"``
        (means of bins of consecutive samples, a record longer than ``MAX_POINTS``)."""
        return self._by

    @property
    def target_strain(self) -> np.ndarray:
        """Strain at the objective points."""
        return self._e_obj

    @property
    def target_time(self) -> np.ndarray:
        """Time of the objective points in the history (``strain / rate`` at constant rate)."""
        return self._t_obj

    @property
    def target_stress(self) -> np.ndarray:
        """Measured stress at the objective points, in :attr:`measure` (MPa)."""
        return self._s_obj

    @property
    def target_weights(self) -> np.ndarray:
        """Weight of each objective point (all 1 unless set by :meth:`with_point_weights`)."""
        return self._w_obj

    @property
    def target_direction(self) -> np.ndarray:
        """Loaded direction of each objective point: 1, or 2 for the points of ``stress2``
        (they follow those of ``stress``)."""
        return self._d_obj

    @property
    def target_strain2(self) -> np.ndarray | None:
        """λ2 − 1 at the objective points of a biaxial curve (None otherwise)."""
        return self._e2_obj
