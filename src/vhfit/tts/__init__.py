"""Time–temperature superposition: shift-factor laws, master curves, shifted tests.

A thermorheologically simple material relaxes at temperature T as at the reference
temperature T_ref with every relaxation time scaled: τ_i(T) = a_T τ_i(T_ref). So a
frequency sweep at T is the reference curve at the reduced frequency f·a_T, a
relaxation test at T the reference curve at the reduced time t/a_T, and a
stress–strain test at T the reference model driven through the reduced time t/a_T
(its strain rate × a_T). See docs/dma.md.

::

    from vhfit import tts
    law = tts.WLF(C1=17.4, C2=51.6, T_ref=20.0)
    mc = tts.master_curve(sweeps, law="wlf")          # shift factors built and fitted
    curve_ref = tts.shift_curve(curve_at_60C, law.aT(60.0))
    ref = tts.shift_to_reference(items)               # items at T_ref, ref.law, ref.log_aT
"""

from __future__ import annotations

import math

from vhfit.data import TestItem
from vhfit.tts._laws import (
    GAS_CONSTANT,
    LAWS,
    WLF,
    Arrhenius,
    PolynomialShift,
    choose_shift_law,
    fit_shift_law,
    wlf_degenerate,
)
from vhfit.tts._master import (
    MasterCurve,
    group_by_temperature,
    master_curve,
    pair_shift,
    reduce_to_reference,
    sweeps_from_columns,
)
from vhfit.tts._reference import ReferenceShift, shift_to_reference

__all__ = [
    "GAS_CONSTANT",
    "LAWS",
    "WLF",
    "Arrhenius",
    "PolynomialShift",
    "fit_shift_law",
    "choose_shift_law",
    "wlf_degenerate",
    "MasterCurve",
    "group_by_temperature",
    "master_curve",
    "pair_shift",
    "reduce_to_reference",
    "sweeps_from_columns",
    "ReferenceShift",
    "shift_to_reference",
    "shift_curve",
]


def shift_curve(item, a_T: float):
    """The item at the reference temperature, given its shift factor a_T.

    A stress–strain :class:`vhfit.Curve` gets its history in reduced time t/a_T (a
    constant rate × a_T); a frequency sweep its frequencies × a_T; a relaxation test its
    times / a_T. Anything with a ``shifted(a_T)`` method is shifted by it.

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> c = vhfit.Curve(strain=np.linspace(0, -0.3, 4), stress=[0, -1, -2, -3],
    ...                 strain_rate=-0.1)
    >>> shift_curve(c, 100.0).strain_rate     # 100x slower material: 100x faster rate
    -10.0
    """
    a = float(a_T)
    if not (math.isfinite(a) and a > 0):
        raise ValueError(f"a_T = {a_T!r}: a shift factor must be finite and > 0")
    if not isinstance(item, TestItem):
        raise TypeError(f"cannot shift a {type(item).__name__}: give a Curve, a frequency "
                        "sweep or a relaxation test")
    return item.shifted(a)
