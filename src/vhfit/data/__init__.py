"""Test data: measured stress–strain curves, their readers, and the objective points.

A :class:`Curve` holds one test as measured — uniaxial (the paper's) or any other
registered homogeneous test (:mod:`vhfit.modes`); strain (or stretch) and stress, and either a
nominal constant strain rate, the time of every sample, or neither (an equilibrium
curve, fully relaxed states) — plus the *objective points*
where the model is compared with it: by default its own samples (bin means of
consecutive samples above ``MAX_POINTS``); the paper's 10 points a curve, evenly spaced
in strain, with ``n_points=10``.
It knows the stretch history the model must follow (:attr:`Curve.history`) and the
target stresses there (:attr:`Curve.target_stress`).

A :class:`FrequencySweep` (storage and loss moduli over frequency, e.g. a DMA master
curve) and a :class:`Relaxation` (relaxation modulus over time) are small-strain
tests of the same material; :func:`read_csv` returns them for files of moduli, and
:func:`vhfit.calibrate` takes them beside curves.

Readers turn files and arrays into curves: :func:`read_csv` (one file per curve, or one
long file with a rate column), :func:`curves_from_arrays` and :meth:`Curve.from_array`
(numpy arrays, anything with ``__array__``, DataFrame-like objects with ``.to_numpy()``
and ``.columns``, or a mapping of column name to values); :func:`read_history` reads a
(time, strain) loading history to simulate.

Conventions (docs/theory.md §1): compression is negative (strain, strain rate and
stress); units MPa, s, 1/s; engineering strain ε = λ − 1; true stress = engineering
stress × λ.

Every problem with the data raises :class:`DataError` (a ``ValueError``) whose one-line
message names the file, the curve, the row or column, and the fix. What is *inferred*
rather than declared (e.g. compression given as positive numbers) is done with a
:class:`DataWarning` that says exactly what was assumed.

The tolerances below are module attributes read when a curve is built; setting one here
(e.g. ``vhfit.data.MAX_BREAKPOINTS = 5000``) changes it for the curves built afterwards.

Curves, sweeps and relaxation tests are *test items*: they share the protocol
:class:`TestItem` (name, kind of test, deformation, measure, history, targets, weights),
and every consumer reads them through it.

Layout (private modules, imported in this order, none importing a later one):
``_items`` (:class:`TestItem`, :func:`is_moduli`) → ``_errors`` (DataError, message
locations) → ``_measures`` → ``_paths`` (path geometry) → ``_points`` (objective points)
→ ``_samples`` (the checks of ``Curve(...)``) → ``_modes`` (the deformation's arguments
and signs) →
``_columns`` (header recognition, units) → ``_table`` (CSV decoding, tables) →
``_ambiguous`` (competing columns) → ``_specs`` (table → curve arguments) → ``_curve``
(:class:`Curve`) → ``_moduli`` (:class:`FrequencySweep`, :class:`Relaxation`:
small-strain moduli) → ``_moduli_table`` (tables of moduli → sweeps and relaxation tests)
→ ``_readers`` (:func:`read_csv`, :func:`curves_from_arrays`, :func:`read_history`).
"""

from __future__ import annotations

import sys
import types
from typing import Any

from vhfit.data import _curve, _paths, _samples
from vhfit.data._curve import MAX_BREAKPOINTS, MAX_POINTS, PATH_RTOL, Curve
from vhfit.data._errors import DataError, DataWarning
from vhfit.data._items import TestItem, is_moduli
from vhfit.data._measures import engineering_to_true, true_to_engineering
from vhfit.data._moduli import FrequencySweep, Relaxation
from vhfit.data._paths import HOLD_MIN_DURATION, HOLD_RTOL, LEG_RTOL
from vhfit.data._points import DEFAULT_N_POINTS
from vhfit.data._readers import curves_from_arrays, read_csv, read_history
from vhfit.data._samples import SIGN_RTOL

__all__ = [
    "DEFAULT_N_POINTS",
    "HOLD_MIN_DURATION",
    "HOLD_RTOL",
    "LEG_RTOL",
    "MAX_BREAKPOINTS",
    "MAX_POINTS",
    "PATH_RTOL",
    "SIGN_RTOL",
    "Curve",
    "DataError",
    "DataWarning",
    "FrequencySweep",
    "Relaxation",
    "TestItem",
    "curves_from_arrays",
    "engineering_to_true",
    "is_moduli",
    "read_csv",
    "read_history",
    "true_to_engineering",
]

# Tolerance -> the module that reads it when a curve is built.
_OWNERS: dict[str, types.ModuleType] = {
    "MAX_BREAKPOINTS": _curve,
    "MAX_POINTS": _curve,
    "PATH_RTOL": _curve,
    "SIGN_RTOL": _samples,
    "LEG_RTOL": _paths,
    "HOLD_RTOL": _paths,
    "HOLD_MIN_DURATION": _paths,
}


class _DataPackage(types.ModuleType):
    """This package, whose tolerances, when set, are set where they are read.

    Users (and the warning about noisy paths) set ``vhfit.data.MAX_BREAKPOINTS``; the
    curve module reads its own copy, so an assignment here is passed on to it.
    """

    def __setattr__(self, name: str, value: Any) -> None:
        owner = _OWNERS.get(name)
        if owner is not None:
            setattr(owner, name, value)
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _DataPackage
