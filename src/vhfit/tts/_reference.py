"""One calibration's tests at the reference temperature, and the law that put them there.

:func:`reduce_to_reference` answers "which items at T_ref"; :func:`shift_to_reference`
also answers "with which shift law" — what a calibration result and the solvers' cards
need (``*TRS``, ``TB,SHIFT``). Without given shift factors, the log10 a_T of the sweep
(or relaxation) temperatures come from the master curve built by overlap, and a WLF law
is fitted to them (or, where that fit degenerates, the law the data choose:
:func:`vhfit.tts.choose_shift_law`); a stress–strain test at a temperature without a
sweep is shifted by that law.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vhfit._words import setting
from vhfit.data import DataError, FrequencySweep, Relaxation
from vhfit.tts._laws import choose_shift_law
from vhfit.tts._master import MasterCurve, _temperature_of, reduce_to_reference

#: Temperatures closer than this (in the data's unit) are one level.
TOLERANCE = 1.0


@dataclass(frozen=True)
class ReferenceShift:
    """Items at the reference temperature and where their shift came from.

    Attributes
    ----------
    items : list
        The items at ``T_ref`` (each ``item.shifted(a_T)``; those without a temperature
        unchanged).
    law : WLF, Arrhenius, PolynomialShift or None
        The given law, or the WLF law fitted to the shift factors used (None when every
        item is at one temperature, or fewer than two temperatures define a law).
    T_ref : float or None
        Reference temperature.
    log_aT : dict
        Temperature -> log10 a_T applied to the items at it.
    source : {"law", "table", "overlap", "none"}
        Given law, given table, built from the sweeps' overlap, or no shift.
    notes : list of str
        What the law's fit found wrong (a degenerate WLF fit and the law chosen
        instead, :func:`vhfit.tts.choose_shift_law`).
    """

    items: list
    law: object = None
    T_ref: float | None = None
    log_aT: dict = field(default_factory=dict)
    source: str = "none"
    notes: list = field(default_factory=list)


def _moduli_items(items, temps) -> list:
    """The sweeps at a temperature (else the relaxation tests): what a master curve takes."""
    sweeps = [it for it, T in zip(items, temps) if T is not None
              and isinstance(it, FrequencySweep)]
    if sweeps:
        return sweeps
    return [it for it, T in zip(items, temps) if T is not None and isinstance(it, Relaxation)]


def _covered(T: float, table: dict) -> bool:
    return any(abs(T - t) <= TOLERANCE for t in table)


def _from_overlap(items, temps, T_ref):
    """(table, law, T_ref) from the master curve of the items' sweeps, or None when the
    sweeps are at fewer than two temperature levels."""
    moduli = _moduli_items(items, temps)
    if not moduli:
        return None
    _, mc = reduce_to_reference(moduli, T_ref=T_ref, tolerance=TOLERANCE)
    if not isinstance(mc, MasterCurve) or mc.temperatures.size < 2:
        return None
    law, note = choose_shift_law(mc.temperatures, mc.log_aT, T_ref=mc.T_ref)
    table = {float(T): float(L) for T, L in zip(mc.temperatures, mc.log_aT)}
    for T in sorted({T for T in temps if T is not None}):
        if not _covered(T, table):  # a stress–strain test between (or beyond) the sweeps
            table[T] = float(law.log_aT(T))
    return table, law, mc.T_ref, note


def shift_to_reference(items, *, shift_factors=None, T_ref: float | None = None
                       ) -> ReferenceShift:
    """Every item at the reference temperature, with the shift law that put it there.

    Parameters
    ----------
    items : sequence
        Curves (temperature in ``metadata["temperature"]``), frequency sweeps and
        relaxation tests (``temperature``); None means "at the reference already".
    shift_factors : law, dict or (temperatures, log10 a_T), optional
        Known shift factors (as :func:`master_curve` takes them). Without them, items at
        several temperatures are shifted with the log10 a_T of the master curve built
        from the sweeps' overlap, and a WLF law fitted to those shifts the others.
    T_ref : float, optional
        Reference temperature (default: the given law's, or the middle sweep level).

    Returns
    -------
    ReferenceShift

    Raises
    ------
    DataError
        A temperature with no shift factor and no overlap to build one (one line naming
        the item and the fix).

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> from vhfit.tts import WLF
    >>> s = vhfit.FrequencySweep(frequency=[1.0, 10.0], storage=[2.0, 3.0],
    ...                          loss=[1.0, 1.0], temperature=40.0)
    >>> ref = shift_to_reference([s], shift_factors=WLF(8.0, 100.0, 20.0))
    >>> ref.source, ref.T_ref, round(ref.log_aT[40.0], 6)
    ('law', 20.0, -1.333333)
    """
    items = list(items)
    temps = [_temperature_of(it) for it in items]
    known = sorted({T for T in temps if T is not None})
    source = "none"
    law = None
    notes: list[str] = []
    given_T = T_ref  # a test without temperature is at T_ref only when T_ref is said
    if shift_factors is None and known and known[-1] - known[0] > TOLERANCE:
        built = _from_overlap(items, temps, T_ref)
        if built is not None:
            shift_factors, law, T_ref, note = built
            source = "overlap"
            notes += [note] if note else []
    elif hasattr(shift_factors, "log_aT"):
        law, source = shift_factors, "law"
        T_ref = float(law.T_ref)
    elif shift_factors is not None:
        source = "table"
        if not known:
            raise DataError("shift_factors: a table of log10 a_T, but no test has a "
                            "temperature: give each test its temperature with "
                            + setting("temperature=, metadata={'temperature': T}",
                                      "a '# temperature: T' line in its file")
                            + ", or drop shift_factors")
    out, _ = reduce_to_reference(items, shift_factors=shift_factors,
                                 T_ref=T_ref if source == "law" else given_T,
                                 tolerance=TOLERANCE)
    if source == "none":  # one temperature (or none): nothing shifted
        return ReferenceShift(out, None, T_ref)
    table = _applied(known, shift_factors, law)
    if source == "table" and table:
        T_ref = T_ref if T_ref is not None else min(table, key=lambda T: abs(table[T]))
        if len(table) >= 2:
            law, note = choose_shift_law(list(table), list(table.values()), T_ref=T_ref)
            notes += [note] if note else []
    return ReferenceShift(out, law, None if T_ref is None else float(T_ref), table, source,
                          notes)


def _applied(known: list, shift_factors, law) -> dict:
    """Temperature -> log10 a_T applied to the items at it."""
    if law is not None and not isinstance(shift_factors, dict):
        return {float(T): float(law.log_aT(T)) for T in known}
    if isinstance(shift_factors, dict):
        tt, ll = list(shift_factors), list(shift_factors.values())
    else:
        tt, ll = shift_factors
    tt, ll = np.asarray(tt, dtype=np.float64).ravel(), np.asarray(ll, dtype=np.float64).ravel()
    out = {}
    for T in known:
        j = int(np.argmin(np.abs(tt - T)))
        out[float(T)] = float(ll[j])
    return out
