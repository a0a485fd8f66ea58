"""What every test item offers: :class:`TestItem`, the protocol of curves, frequency
sweeps and relaxation tests.

A calibration, the objective, the plots, the results file, the card check and the
command line take a list of *test items* — :class:`vhfit.Curve` (a stress–strain test),
:class:`vhfit.FrequencySweep` and :class:`vhfit.Relaxation` (small-strain tests, data of
moduli) — and read them through this protocol only: an item says what it is
(:attr:`~TestItem.is_moduli`), which test it is (:attr:`~TestItem.deformation`, a
registered :mod:`vhfit.modes` record), the history the model must follow and the
targets there. A small-strain item is a uniaxial (E-type) test with no strain rate,
one segment and the "true" measure (at small strain the measures agree).
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np

from vhfit._linear import LinearLoad
from vhfit.history import History

__all__ = ["TestItem", "is_moduli"]


@runtime_checkable
class TestItem(Protocol):
    """A calibration item: a curve, a frequency sweep or a relaxation test.

    Attributes
    ----------
    name : str
        Name in messages, reports and output files.
    source : str or None
        The file it was read from.
    weight : float
        Weight of the item in the objective.
    is_moduli : bool
        True for a small-strain test (frequency sweep, relaxation test: data of moduli),
        False for a stress–strain curve.
    deformation : str
        The name of the test's registered deformation (:func:`vhfit.modes.get_deformation`).
    measure : str
        Stress measure of the targets: ``"true"`` or ``"engineering"``.
    strain_rate : float or None
        Nominal strain rate, 1/s (None: equilibrium curves and small-strain tests).
    temperature : float or None
        Test temperature (None: not stated, or already at the reference temperature).
    is_equilibrium : bool
        Fully relaxed states, compared with the long-term law alone.
    is_constant_rate : bool
        A constant-rate ramp from rest.
    n_segments : int
        Loading legs and holds of the history (1 for a ramp or a small-strain test).
    history : History or LinearLoad
        What the model evaluates.
    n_points : int
        Number of objective points.
    target_stress : ndarray
        The values the model is compared with, MPa.
    target_weights : ndarray or None
        Weight of each point (None: all alike).
    target_scale : ndarray or None
        Scale of each point's relative error (None: the item's RMS, paper Eq. 20).

    Examples
    --------
    >>> import vhfit
    >>> from vhfit.data import TestItem
    >>> c = vhfit.Curve(strain=[-0.1, -0.2], stress=[-0.1, -0.2], strain_rate=-1.0)
    >>> r = vhfit.Relaxation(time=[0.0, 1.0], modulus=[2.0, 1.0])
    >>> isinstance(c, TestItem), isinstance(r, TestItem)
    (True, True)
    >>> c.is_moduli, r.is_moduli, r.deformation
    (False, True, 'uniaxial')
    """

    name: str
    source: str | None
    weight: float
    is_moduli: bool
    deformation: str
    measure: str
    strain_rate: float | None
    temperature: float | None
    is_equilibrium: bool
    is_constant_rate: bool
    n_segments: int
    n_points: int

    @property
    def history(self) -> History | LinearLoad: ...

    @property
    def target_stress(self) -> np.ndarray: ...

    @property
    def target_weights(self) -> np.ndarray | None: ...

    @property
    def target_scale(self) -> np.ndarray | None: ...

    def shifted(self, a_T: float) -> Any: ...


def is_moduli(item: TestItem) -> bool:
    """Whether ``item`` is a small-strain test — a frequency sweep or a relaxation test,
    data of moduli — rather than a stress–strain curve (its :attr:`TestItem.is_moduli`).

    Examples
    --------
    >>> import vhfit
    >>> is_moduli(vhfit.Relaxation(time=[0.0, 1.0], modulus=[2.0, 1.0]))
    True
    >>> is_moduli(vhfit.Curve(strain=[-0.1, -0.2], stress=[-0.1, -0.2], strain_rate=-1.0))
    False
    """
    return bool(item.is_moduli)
