"""Small-strain test data: frequency sweeps (DMA) and relaxation tests.

:class:`FrequencySweep` holds storage and loss moduli over frequency (or |E*| and tan δ,
converted), :class:`Relaxation` a relaxation modulus over time. Both keep E-type
(Young's) moduli in MPa: shear data (``kind="G"``) are multiplied by 3, the
incompressible E = 3G, and remember their kind. They are calibration items beside
stress–strain curves: :attr:`history` is the :class:`vhfit._linear.LinearLoad` the
model evaluates, :attr:`target_stress` the moduli it is compared with (a sweep's storage
moduli, then its loss moduli), :attr:`target_scale` the scale of each point's relative
error (docs/data.md, "Frequency sweeps and relaxation tests").
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from vhfit._linear import LinearLoad
from vhfit.data._columns import _STRESS_UNITS, _norm_unit
from vhfit.data._errors import DataError
from vhfit.data._samples import _check_weight
from vhfit.viscoelastic import loss_modulus, relaxation_modulus, storage_modulus

__all__ = ["FrequencySweep", "Relaxation"]

_KINDS = {"e": "E", "g": "G"}


class _Loc:
    """Where a value sits, for one-line messages: item, file, line and column."""

    def __init__(self, what: str, name: str, source: str | None,
                 headers: Mapping[str, str] | None = None, rows: Sequence[Any] | None = None):
        self.what, self.name, self.source = what, name, source
        self.headers = dict(headers or {})
        self.rows = rows

    def __call__(self, role: str | None = None, k: int | None = None) -> str:
        """"sweep 'x' (file.csv, line 7, column 'loss_MPa')", or "sweep 'x', loss[3]"."""
        head = f"{self.what} {self.name!r}"
        col = self.headers.get(role) if role is not None else None
        if role is not None and col is None:  # not from a file: name the argument
            src = f" ({self.source})" if self.source else ""
            return head + src + (f", {role}[{k}]" if k is not None else f", {role}=")
        parts = [self.source] if self.source else []
        if k is not None:
            parts.append(str(self.rows[k]) if self.rows is not None else f"row {k}")
        if col is not None:
            parts.append(f"column {col!r}")
        return head + (f" ({', '.join(parts)})" if parts else "")


def _values(loc: _Loc, role: str, values: Any, n: int | None = None) -> np.ndarray:
    """A 1-D float array of finite numbers, with a message naming the bad one."""
    try:
        if np.iscomplexobj(values):
            raise DataError(f"{loc(role)}: holds complex numbers: give real values")
        arr = np.array(values, dtype=np.float64).reshape(-1) if np.ndim(values) <= 1 else None
    except (TypeError, ValueError):
        raise DataError(f"{loc(role)}: must be numbers: fix the {role} data") from None
    if arr is None:
        raise DataError(f"{loc(role)}: must be 1-D, got shape {np.shape(values)}: give one "
                        "value per point")
    if arr.size == 0:
        raise DataError(f"{loc(role)}: no values: give at least one point")
    if n is not None and arr.size != n:
        raise DataError(f"{loc(role)}: {arr.size} values for {n} points: give one per point")
    bad = ~np.isfinite(arr)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise DataError(f"{loc(role, k)}: {float(arr[k])!r} is not a finite number: repair or "
                        "delete that row")
    return arr


def _positive(loc: _Loc, role: str, arr: np.ndarray, what: str, fix: str,
              strict: bool = True) -> None:
    bad = ~(arr > 0) if strict else arr < 0
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise DataError(f"{loc(role, k)}: {what} {arr[k]:g} {'<=' if strict else '<'} 0: "
                        f"{fix}")


def _kind(loc: _Loc, kind: Any) -> str:
    k = _KINDS.get(str(kind).strip().lower())
    if k is None:
        raise DataError(f"{loc()}: kind={kind!r}: give 'E' (Young's-type moduli) or 'G' "
                        "(shear moduli, E = 3G)")
    return k


def _unit(loc: _Loc, unit: str) -> float:
    f = _STRESS_UNITS.get(_norm_unit(unit))
    if f is None:
        raise DataError(f"{loc()}: unit={unit!r} is not understood: use Pa, kPa, MPa or GPa")
    return f


def _float(value: Any) -> float:
    """``float(value)``, NaN for anything that is not a number."""
    try:
        return float(value)
    except (TypeError, ValueError):
        return np.nan


def _temperature(loc: _Loc, temperature: Any) -> float | None:
    if temperature is None:
        return None
    t = _float(temperature)
    if not np.isfinite(t):
        raise DataError(f"{loc('temperature')}: temperature={temperature!r} is not a finite "
                        "number: give one temperature per item (or None)")
    return t


def _shift(loc: _Loc, a_T: Any) -> float:
    a = _float(a_T)
    if not (np.isfinite(a) and a > 0):
        raise DataError(f"{loc()}: shift factor a_T = {a_T!r} must be a finite number > 0")
    return a


def _point_scale(*blocks: np.ndarray) -> np.ndarray:
    """|value| of each point, or its block's mean |value| where it is 0."""
    out = []
    for b in blocks:
        a = np.abs(b)
        out.append(np.where(a > 0, a, np.mean(a)))
    return np.concatenate(out)


class _Item:
    """What frequency sweeps and relaxation tests share as test items
    (:class:`vhfit.data.TestItem`): a small-strain uniaxial (E-type) test."""

    is_moduli = True
    deformation = "uniaxial"
    measure = "true"  # at small strain the measures agree
    strain_rate = None
    is_equilibrium = False
    is_constant_rate = False
    n_segments = 1
    _what = "item"
    _axis = "x"

    name: str
    kind: str
    temperature: float | None
    weight: float
    source: str | None
    _history: LinearLoad

    @property
    def history(self) -> LinearLoad:
        """The small-strain load the model evaluates (:class:`vhfit._linear.LinearLoad`)."""
        return self._history

    @property
    def n_points(self) -> int:
        """Number of objective points (a sweep: twice its frequencies)."""
        return int(self._history.n_outputs)

    @property
    def target_weights(self) -> None:
        """Point weights: none (every point counts alike)."""
        return None

    def _moduli(self, model, params) -> tuple[float, np.ndarray, np.ndarray]:
        x = model.check(params)
        _, G, tau = model.split(x)
        return float(model.long_term_modulus(x)), G, tau

    def __repr__(self) -> str:
        t = "" if self.temperature is None else f", temperature={self.temperature:g}"
        return (f"{type(self).__name__}({self.name!r}, {self.n_points} points, "
                f"kind={self.kind!r}{t})")


class FrequencySweep(_Item):
    """Storage and loss moduli over frequency (a DMA sweep or master curve).

    Give ``storage`` and ``loss``, or ``storage`` and ``tan_delta`` (E″ = E′ tan δ), or
    ``modulus`` (|E*|) and ``tan_delta`` (E′ = |E*| cos δ, E″ = |E*| sin δ).

    Parameters
    ----------
    frequency : array_like
        Frequencies f in Hz (> 0); or give ``omega``.
    storage, loss : array_like, optional
        Storage modulus (> 0) and loss modulus (≥ 0), in ``unit``.
    modulus, tan_delta : array_like, optional
        Magnitude of the complex modulus |E*| (> 0) and the loss factor tan δ (≥ 0).
    kind : {"E", "G"}
        Young's-type (tension, compression, bending) or shear moduli; shear moduli are
        stored as E = 3G (incompressible).
    temperature : float, optional
        Test temperature (for time–temperature superposition); None at the reference.
    name : str, optional
        Name in messages and reports.
    omega : array_like, optional
        Angular frequencies ω = 2πf in rad/s, instead of ``frequency``.
    unit : str
        Unit of the moduli: "MPa" (default), "kPa", "Pa", "GPa".
    weight : float
        Weight of the sweep in the objective.
    source : str or path, optional
        Where the data came from (a file), for messages.

    Attributes
    ----------
    frequency, omega : ndarray
        f (Hz) and ω = 2πf (rad/s).
    storage, loss : ndarray
        E′ and E″, MPa (E-type).
    kind : str
        "E" or "G": the kind of the data given.

    Examples
    --------
    >>> s = FrequencySweep(frequency=[0.1, 1.0], storage=[2.0, 3.0], loss=[0.5, 0.4],
    ...                    kind="G", name="dma")
    >>> s.storage.tolist(), s.kind, s.n_points
    ([6.0, 9.0], 'G', 4)
    >>> s.shifted(10.0).frequency.tolist()
    [1.0, 10.0]
    >>> FrequencySweep(frequency=[0.0, 1.0], storage=[2.0, 3.0], loss=[0.5, 0.4])
    Traceback (most recent call last):
    ...
    vhfit.data._errors.DataError: sweep 'sweep', frequency[0]: frequency 0 <= 0: ...
    """

    _what = "sweep"

    def __init__(self, frequency=None, storage=None, loss=None, *, modulus=None,
                 tan_delta=None, kind: str = "E", temperature: float | None = None,
                 name: str | None = None, omega=None, unit: str = "MPa",
                 weight: float = 1.0, source: str | os.PathLike[str] | None = None,
                 _headers: Mapping[str, str] | None = None, _rows: Sequence[Any] | None = None
                 ) -> None:
        src = None if source is None else str(source)
        loc = _Loc("sweep", "sweep" if name is None else str(name), src, _headers, _rows)
        if (frequency is None) == (omega is None):
            raise DataError(f"{loc()}: give frequency= (Hz) or omega= (rad/s), one of them")
        role = "frequency" if omega is None else "omega"
        f = _values(loc, role, frequency if omega is None else omega)
        _positive(loc, role, f, role, "frequencies are > 0; delete that row")
        n = f.size
        k = _kind(loc, kind)
        scale = _unit(loc, unit) * (3.0 if k == "G" else 1.0)
        e1, e2 = _storage_loss(loc, n, storage, loss, modulus, tan_delta)
        self.name = loc.name
        self.kind = k
        self.temperature = _temperature(loc, temperature)
        self.weight = _check_weight(weight, loc)
        self.source = src
        self.omega = f if omega is not None else 2.0 * np.pi * f
        self.frequency = f if omega is None else f / (2.0 * np.pi)
        self.storage = e1 * scale
        self.loss = e2 * scale
        self._loc = loc
        self._history = LinearLoad("frequency", self.omega)

    @property
    def modulus(self) -> np.ndarray:
        """|E*| = √(E′² + E″²), MPa."""
        return np.hypot(self.storage, self.loss)

    @property
    def tan_delta(self) -> np.ndarray:
        """tan δ = E″/E′."""
        return self.loss / self.storage

    @property
    def target_stress(self) -> np.ndarray:
        """The moduli the model is compared with: E′ at every frequency, then E″, MPa."""
        return np.concatenate([self.storage, self.loss])

    @property
    def target_scale(self) -> np.ndarray:
        """Scale of each point's relative error: |E′| and |E″| (a zero E″: the mean |E″|)."""
        return _point_scale(self.storage, self.loss)

    def shifted(self, a_T: float) -> FrequencySweep:
        """The sweep at the reference temperature: frequencies × a_T, temperature None."""
        a = _shift(self._loc, a_T)
        out = FrequencySweep(frequency=self.frequency * a, storage=self.storage,
                             loss=self.loss, name=self.name, weight=self.weight,
                             source=self.source)
        out.kind = self.kind  # the moduli are E-type already
        out.omega = self.omega * a
        return out

    def fitted_curve(self, model, params, points: int = 200) -> dict[str, np.ndarray]:
        """Model moduli at the sweep's frequencies and on a fine log grid (MPa, E-type)."""
        E_inf, G, tau = self._moduli(model, params)
        lo, hi = np.log10(self.omega.min()), np.log10(self.omega.max())
        fine = np.logspace(lo, hi, int(points)) if hi > lo else self.omega[:1].copy()
        return {
            "frequency": self.frequency, "omega": self.omega,
            "storage": self.storage, "loss": self.loss,
            "model_storage": storage_modulus(self.omega, E_inf, G, tau),
            "model_loss": loss_modulus(self.omega, E_inf, G, tau),
            "fine_omega": fine, "fine_frequency": fine / (2.0 * np.pi),
            "fine_storage": storage_modulus(fine, E_inf, G, tau),
            "fine_loss": loss_modulus(fine, E_inf, G, tau),
        }

    def curve_info(self) -> dict[str, Any]:
        """What the results file records about the sweep."""
        return {"name": self.name, "type": "frequency_sweep", "kind": self.kind,
                "temperature": self.temperature, "n_points": self.n_points,
                "frequency_range_hz": [float(self.frequency.min()), float(self.frequency.max())],
                "source": self.source}


def _storage_loss(loc: _Loc, n: int, storage, loss, modulus, tan_delta
                  ) -> tuple[np.ndarray, np.ndarray]:
    """(E′, E″) from the combination given, each checked; one-line errors."""
    if tan_delta is not None and storage is None and modulus is None:
        fix = ("add a storage-modulus column (e.g. 'storage_MPa' or \"E' [MPa]\") or an |E*| "
               "column ('complex_modulus_MPa') to the file" if loc.headers else
               "give storage= (or modulus=, |E*|)")
        raise DataError(f"{loc('tan_delta')}: tan delta needs the storage modulus (or |E*|) "
                        f"beside it: {fix}")
    if storage is not None and modulus is not None:
        raise DataError(f"{loc('modulus')}: give storage= or modulus= (|E*|), not both")
    if storage is None and modulus is None:
        raise DataError(f"{loc()}: give storage= and loss= (or tan_delta=), or modulus= (|E*|) "
                        "and tan_delta=")
    if (loss is None) == (tan_delta is None):
        which = "loss= or tan_delta=, one of them" if loss is not None else (
            "loss= (or tan_delta=) beside it")
        raise DataError(f"{loc('loss')}: give {which}")
    if modulus is not None and loss is not None:
        raise DataError(f"{loc('loss')}: with modulus= (|E*|) give tan_delta=, not loss=")
    if tan_delta is not None:
        td = _values(loc, "tan_delta", tan_delta, n)
        _positive(loc, "tan_delta", td, "tan delta", "loss factors are >= 0; fix or delete "
                  "that row", strict=False)
    if storage is not None:
        e1 = _values(loc, "storage", storage, n)
        _positive(loc, "storage", e1, "storage modulus", "storage moduli are > 0; fix or "
                  "delete that row")
        if loss is None:
            return e1, e1 * td
        e2 = _values(loc, "loss", loss, n)
        _positive(loc, "loss", e2, "loss modulus", "loss moduli are >= 0 (a negative one "
                  "is a sign or phase error); fix or delete that row", strict=False)
        return e1, e2
    m = _values(loc, "modulus", modulus, n)
    _positive(loc, "modulus", m, "|E*|", "complex moduli are > 0; fix or delete that row")
    c = 1.0 / np.sqrt(1.0 + td * td)
    return m * c, m * c * td


class Relaxation(_Item):
    """A relaxation modulus over time (a step-strain relaxation test).

    Parameters
    ----------
    time : array_like
        Times since the step, s (≥ 0).
    modulus : array_like
        Relaxation modulus E(t) (or G(t), ``kind="G"``) at each time (> 0), in ``unit``.
    kind : {"E", "G"}
        Young's-type or shear modulus; shear moduli are stored as E = 3G.
    temperature, name, unit, weight, source
        As in :class:`FrequencySweep`.

    Examples
    --------
    >>> r = Relaxation(time=[0.0, 1.0, 10.0], modulus=[3.0, 2.0, 1.5], name="relax")
    >>> r.shifted(2.0).time.tolist(), r.n_points
    ([0.0, 0.5, 5.0], 3)
    """

    _what = "relaxation"

    def __init__(self, time, modulus, *, kind: str = "E", temperature: float | None = None,
                 name: str | None = None, unit: str = "MPa", weight: float = 1.0,
                 source: str | os.PathLike[str] | None = None,
                 _headers: Mapping[str, str] | None = None, _rows: Sequence[Any] | None = None
                 ) -> None:
        src = None if source is None else str(source)
        loc = _Loc("relaxation", "relaxation" if name is None else str(name), src, _headers,
                   _rows)
        t = _values(loc, "time", time)
        _positive(loc, "time", t, "time", "times since the step are >= 0 s: fix or delete "
                  "that row", strict=False)
        k = _kind(loc, kind)
        scale = _unit(loc, unit) * (3.0 if k == "G" else 1.0)
        e = _values(loc, "modulus", modulus, t.size)
        _positive(loc, "modulus", e, "relaxation modulus", "moduli are > 0; fix or delete "
                  "that row")
        self.name = loc.name
        self.kind = k
        self.temperature = _temperature(loc, temperature)
        self.weight = _check_weight(weight, loc)
        self.source = src
        self.time = t
        self.modulus = e * scale
        self._loc = loc
        self._history = LinearLoad("relaxation", self.time)

    @property
    def target_stress(self) -> np.ndarray:
        """The relaxation moduli the model is compared with, MPa (E-type)."""
        return self.modulus

    @property
    def target_scale(self) -> np.ndarray:
        """Scale of each point's relative error: |E(t)|."""
        return _point_scale(self.modulus)

    def shifted(self, a_T: float) -> Relaxation:
        """The test at the reference temperature: times / a_T, temperature None."""
        a = _shift(self._loc, a_T)
        out = Relaxation(time=self.time / a, modulus=self.modulus, name=self.name,
                         weight=self.weight, source=self.source)
        out.kind = self.kind  # the moduli are E-type already
        return out

    def fitted_curve(self, model, params, points: int = 200) -> dict[str, np.ndarray]:
        """Model E(t) at the test's times and on a fine grid (log-spaced above 0), MPa."""
        E_inf, G, tau = self._moduli(model, params)
        pos = self.time[self.time > 0]
        if pos.size and pos.max() > pos.min():
            fine = np.logspace(np.log10(pos.min()), np.log10(pos.max()), int(points))
        else:
            fine = np.unique(self.time)
        return {
            "time": self.time, "modulus": self.modulus,
            "model": relaxation_modulus(self.time, E_inf, G, tau),
            "fine_time": fine, "fine_model": relaxation_modulus(fine, E_inf, G, tau),
        }

    def curve_info(self) -> dict[str, Any]:
        """What the results file records about the test."""
        return {"name": self.name, "type": "relaxation", "kind": self.kind,
                "temperature": self.temperature, "n_points": self.n_points,
                "time_range_s": [float(self.time.min()), float(self.time.max())],
                "source": self.source}
