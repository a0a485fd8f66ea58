"""Master curves from multi-temperature sweeps by pairwise shifting of neighbours.

Each sweep (or relaxation test) at temperature T is a set of points (x, y) with
x = log10 f (or log10 t) and y = log10 E′ (or log10 E(t)). On the reduced axis
x_r = x + log10 a_T (frequency; x − log10 a_T for time) all sweeps lie on one curve.
Adjacent temperatures are shifted against each other where their moduli overlap:
with both curves made monotone, the horizontal distance x_cold(y) − x_warm(y) is
averaged over the common range of y (closed-form shifting: the area between the two
curves divided by the height of their overlap). Chaining these distances from the
reference temperature gives every log10 a_T.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vhfit._words import setting
from vhfit.data import DataError, FrequencySweep, Relaxation
from vhfit.tts._laws import fit_shift_law

#: Points of the y grid on which two neighbours' horizontal distance is averaged.
N_GRID = 200


@dataclass(frozen=True)
class MasterCurve:
    """A master curve at ``T_ref`` and the shift factors that built it.

    Attributes
    ----------
    domain : {"frequency", "time"}
        What ``x`` is: frequency in Hz, or time in s.
    x : ndarray
        Reduced frequency f·a_T (Hz) or reduced time t/a_T (s), ascending.
    storage, loss : ndarray or None
        E′ and E″ (frequency domain), MPa, at ``x``.
    modulus : ndarray or None
        E(t) (time domain), MPa, at ``x``.
    T_ref : float
        Reference temperature (a_T = 1).
    temperatures, log_aT : ndarray
        Each sweep's temperature and its log10 a_T.
    law : WLF, Arrhenius, PolynomialShift or None
        The law fitted to ``log_aT`` (when one was asked for).
    """

    domain: str
    x: np.ndarray
    storage: np.ndarray | None
    loss: np.ndarray | None
    modulus: np.ndarray | None
    T_ref: float
    temperatures: np.ndarray
    log_aT: np.ndarray
    law: object = None
    sets: list = field(default_factory=list, repr=False)

    @property
    def frequency(self) -> np.ndarray:
        """Reduced frequency, Hz (frequency domain)."""
        return self.x

    @property
    def time(self) -> np.ndarray:
        """Reduced time, s (time domain)."""
        return self.x

    def item(self, name: str = "master curve"):
        """The master curve as data at the reference temperature: a
        :class:`vhfit.FrequencySweep` or a :class:`vhfit.Relaxation` (``temperature=None``)."""
        if self.domain == "frequency":
            return FrequencySweep(frequency=self.x, storage=self.storage, loss=self.loss,
                                  name=name)
        return Relaxation(time=self.x, modulus=self.modulus, name=name)


def group_by_temperature(temperature, *columns, tolerance: float = 0.5) -> list[tuple]:
    """Split long-format columns into sets of (nearly) equal temperature.

    Consecutive rows whose temperatures stay within ``tolerance`` of the set's first
    temperature form one set (the usual layout of a DMA export). Returns a list of
    ``(mean temperature, column_1, column_2, ...)``, in the order of the rows.

    Examples
    --------
    >>> sets = group_by_temperature([20.0, 20.1, 40.0, 39.9], [1.0, 2.0, 3.0, 4.0])
    >>> [(round(T, 2), c.tolist()) for T, c in sets]
    [(20.05, [1.0, 2.0]), (39.95, [3.0, 4.0])]
    """
    T = np.asarray(temperature, dtype=np.float64)
    cols = [np.asarray(c, dtype=np.float64) for c in columns]
    if any(c.shape != T.shape for c in cols):
        raise DataError("temperature: every column needs one value per row")
    out, start = [], 0
    for k in range(1, T.size + 1):
        if k == T.size or abs(T[k] - T[start]) > tolerance:
            out.append((float(T[start:k].mean()), *(c[start:k] for c in cols)))
            start = k
    return out


def _monotone(x: np.ndarray, y: np.ndarray, increasing: bool) -> tuple[np.ndarray, np.ndarray]:
    """x as a function of y on the running envelope of y(x) (ties merged by mean x)."""
    order = np.argsort(x)
    x, y = x[order], y[order]
    env = np.maximum.accumulate(y) if increasing else -np.maximum.accumulate(-y)
    if not increasing:
        x, env = x[::-1], env[::-1]
    ys, inv = np.unique(env, return_inverse=True)
    xs = np.bincount(inv, weights=x) / np.bincount(inv)
    return ys, xs


def pair_shift(x_a, y_a, x_b, y_b, *, increasing: bool = True) -> float:
    """Horizontal distance d such that curve b moved by +d lies on curve a.

    ``x`` are log10 abscissae, ``y`` log10 moduli; the distance is averaged over the
    common range of the two curves' (monotone) moduli. Raises ValueError when the
    moduli do not overlap.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-1.0, 2.0, 10)
    >>> round(pair_shift(x, np.tanh(x), x, np.tanh(x + 1.5)), 3)   # b is a moved 1.5 left
    1.5
    """
    ya, xa = _monotone(np.asarray(x_a, float), np.asarray(y_a, float), increasing)
    yb, xb = _monotone(np.asarray(x_b, float), np.asarray(y_b, float), increasing)
    lo, hi = max(ya[0], yb[0]), min(ya[-1], yb[-1])
    if not hi > lo:
        raise ValueError(f"moduli do not overlap (10^[{ya[0]:.3g}, {ya[-1]:.3g}] and "
                         f"10^[{yb[0]:.3g}, {yb[-1]:.3g}])")
    grid = np.linspace(lo, hi, N_GRID)
    return float(np.mean(np.interp(grid, ya, xa) - np.interp(grid, yb, xb)))


def _sets_of(sweeps, domain: str | None):
    """(temperature, x, y1, y2) of each sweep-like item, and the domain."""
    out = []
    for k, s in enumerate(sweeps):
        if not isinstance(s, (FrequencySweep, Relaxation, _Set)):
            raise DataError(f"item {k + 1} is a {type(s).__name__}: give vhfit.FrequencySweep "
                            "or vhfit.Relaxation objects (or tts.sweeps_from_columns(...))")
        T = s.temperature
        if T is None:
            name = s.name or f"item {k + 1}"
            raise DataError(f"{name}: no temperature: give temperature= to every sweep of a "
                            "master curve")
        if isinstance(s, FrequencySweep) or (isinstance(s, _Set) and s.storage is not None):
            d = "frequency"
            out.append((float(T), np.asarray(s.frequency, float), np.asarray(s.storage, float),
                        np.asarray(s.loss, float)))
        else:
            d = "time"
            out.append((float(T), np.asarray(s.time, float), np.asarray(s.modulus, float), None))
        if domain is not None and d != domain:
            raise DataError("sweeps: mix of frequency and time data: build one master curve "
                            "per domain")
        domain = d
    return out, domain


def _merged(sets, names, tolerance: float):
    """Sets (sorted by temperature) within ``tolerance`` of a group's first joined into one
    at their mean temperature: a file read one item per recorded temperature gives each
    temperature level back whole."""
    out, out_names, k = [], [], 0
    while k < len(sets):
        j = k + 1
        while j < len(sets) and sets[j][0] - sets[k][0] <= tolerance:
            j += 1
        group = sets[k:j]
        cols = [np.concatenate([g[c] for g in group]) if group[0][c] is not None else None
                for c in (1, 2, 3)]
        T = float(np.average([g[0] for g in group], weights=[g[1].size for g in group]))
        out.append((T, *cols))
        out_names.append(names[k] if j == k + 1 else f"sweeps at T = {T:.4g}")
        k = j
    return out, out_names


def _known_shifts(temps: np.ndarray, shift_factors, tolerance: float):
    """log10 a_T of each set from the given shift information (None where unknown)."""
    known: list[float | None] = [None] * temps.size
    if shift_factors is None:
        return known, None
    if hasattr(shift_factors, "log_aT"):  # a law
        return [float(v) for v in shift_factors.log_aT(temps)], shift_factors
    if isinstance(shift_factors, dict):
        tt = np.array(list(shift_factors), dtype=np.float64)
        ll = np.array(list(shift_factors.values()), dtype=np.float64)
    else:
        try:
            tt, ll = (np.asarray(v, dtype=np.float64).ravel() for v in shift_factors)
        except (TypeError, ValueError):
            raise DataError("shift_factors: give a law (WLF, ...), a dict {temperature: "
                            "log10 a_T} or a pair (temperatures, log10 a_T)") from None
    if tt.shape != ll.shape or not (np.isfinite(tt).all() and np.isfinite(ll).all()):
        raise DataError("shift_factors: one finite log10 a_T per finite temperature")
    for k, T in enumerate(temps):
        j = int(np.argmin(np.abs(tt - T)))
        if abs(tt[j] - T) <= tolerance:
            known[k] = float(ll[j])
    return known, None


def _propagate(sets, known, names, domain: str) -> list[float]:
    """Fill the unknown log10 a_T by shifting each set against a known neighbour."""
    sign = 1.0 if domain == "frequency" else -1.0
    L = list(known)
    for order in (range(1, len(sets)), range(len(sets) - 2, -1, -1)):
        for k in order:
            nb = k - 1 if order.step == 1 else k + 1
            if L[k] is not None or L[nb] is None:
                continue
            Ta, xa, ya = sets[nb][0], np.log10(sets[nb][1]), np.log10(sets[nb][2])
            Tb, xb, yb = sets[k][0], np.log10(sets[k][1]), np.log10(sets[k][2])
            try:
                d = pair_shift(xa + sign * L[nb], ya, xb, yb, increasing=domain == "frequency")
            except ValueError as exc:
                raise DataError(
                    f"{names[k]}: no shift factor for T = {Tb:g} and its moduli do not "
                    f"overlap those at T = {Ta:g} ({exc}): give shift factors for it, "
                    + setting("shift_factors= a law or a table (vhfit.tts)",
                              "--shift wlf:C1,C2 --tref T")
                    + ", or sweeps that overlap their neighbours") from None
            L[k] = sign * d
    return [float(v) for v in L]


def master_curve(sweeps, *, T_ref: float | None = None, shift_factors=None,
                 law: str | None = None, tolerance: float = 1.0, **law_options) -> MasterCurve:
    """Build a master curve from sweeps (or relaxation tests) at several temperatures.

    Parameters
    ----------
    sweeps : sequence
        Items with ``temperature`` and either ``frequency``, ``storage``, ``loss``
        (:class:`vhfit.FrequencySweep`) or ``time``, ``modulus``
        (:class:`vhfit.Relaxation`); see :func:`sweeps_from_columns` for long-format
        columns.
    T_ref : float, optional
        Reference temperature: a sweep must have been measured within ``tolerance`` of
        it (default: the middle temperature, or the one the shift factors give
        log10 a_T = 0).
    shift_factors : law, dict or (temperatures, log10 a_T), optional
        Known shift factors. A law (:class:`WLF`, ...) shifts every sweep; a table
        shifts the sweeps within ``tolerance`` of its temperatures, and the others are
        shifted against a neighbour where their moduli overlap.
    law : {"wlf", "arrhenius", "polynomial"}, optional
        Fit this law to the resulting log10 a_T (see :func:`fit_shift_law`;
        ``law_options`` go there, e.g. ``degree=3``).
    tolerance : float
        Temperatures closer than this count as equal (same unit as the temperatures).

    Returns
    -------
    MasterCurve

    Raises
    ------
    DataError
        A sweep without temperature, or one without shift information whose moduli do
        not overlap a neighbour's (one line naming it and the fix).
    """
    sets, domain = _sets_of(sweeps, None)
    if len(sets) < 1:
        raise DataError("sweeps: give at least one sweep")
    names = [s.name or f"sweep at T = {float(s.temperature):g}" for s in sweeps]
    order = np.argsort([s[0] for s in sets], kind="stable")
    sets, names = _merged([sets[k] for k in order], [names[k] for k in order], tolerance)
    temps = np.array([s[0] for s in sets])
    known, given_law = _known_shifts(temps, shift_factors, tolerance)
    if T_ref is None:
        have = [k for k, v in enumerate(known) if v is not None]
        T_ref = float(temps[min(have, key=lambda k: abs(known[k]))] if have
                      else temps[(temps.size - 1) // 2])
        if given_law is not None:
            T_ref = float(given_law.T_ref)
    if all(v is None for v in known):
        k = int(np.argmin(np.abs(temps - T_ref)))
        if abs(temps[k] - T_ref) > tolerance:
            raise DataError(f"T_ref = {T_ref:g}: no sweep within {tolerance:g} of it (nearest "
                            f"{temps[k]:g}): give one of the sweep temperatures")
        known[k] = 0.0
    L = np.array(_propagate(sets, known, names, domain))
    fitted = given_law
    if law is not None:
        fitted = fit_shift_law(temps, L, law, T_ref=T_ref, **law_options)
    return _assemble(sets, L, domain, float(T_ref), temps, fitted)


def _assemble(sets, L, domain, T_ref, temps, fitted) -> MasterCurve:
    xs, y1, y2, info = [], [], [], []
    for (T, x, a, b), lg in zip(sets, L):
        xs.append(x * 10.0 ** lg if domain == "frequency" else x / 10.0 ** lg)
        y1.append(a)
        if b is not None:
            y2.append(b)
        info.append({"temperature": T, "x": x, "y1": a, "y2": b, "log_aT": float(lg)})
    x = np.concatenate(xs)
    order = np.argsort(x, kind="stable")
    first = np.concatenate(y1)[order]
    second = np.concatenate(y2)[order] if y2 else None
    if domain == "frequency":
        return MasterCurve(domain, x[order], first, second, None, T_ref, temps, L, fitted, info)
    return MasterCurve(domain, x[order], None, None, first, T_ref, temps, L, fitted, info)


@dataclass(frozen=True)
class _Set:
    temperature: float
    frequency: np.ndarray | None = None
    storage: np.ndarray | None = None
    loss: np.ndarray | None = None
    time: np.ndarray | None = None
    modulus: np.ndarray | None = None
    name: str | None = None


def sweeps_from_columns(temperature, *, frequency=None, storage=None, loss=None, time=None,
                        modulus=None, tolerance: float = 0.5) -> list:
    """Sweep-like sets from long-format columns (one row per point, a temperature column).

    Give ``frequency`` (Hz), ``storage`` and ``loss`` (MPa), or ``time`` (s) and
    ``modulus`` (MPa). Consecutive rows within ``tolerance`` of a set's first
    temperature form one set (see :func:`group_by_temperature`).

    Examples
    --------
    >>> s = sweeps_from_columns([0.0, 0.0, 10.0, 10.0], frequency=[1, 10, 1, 10],
    ...                         storage=[5, 6, 4, 5], loss=[1, 1, 1, 1])
    >>> [(x.temperature, x.storage.tolist()) for x in s]
    [(0.0, [5.0, 6.0]), (10.0, [4.0, 5.0])]
    """
    if frequency is not None:
        if storage is None or loss is None:
            raise DataError("sweeps: frequency columns need "
                            + setting("storage= and loss=", "storage and loss columns"))
        return [_Set(T, frequency=f, storage=e1, loss=e2) for T, f, e1, e2 in
                group_by_temperature(temperature, frequency, storage, loss, tolerance=tolerance)]
    if time is None or modulus is None:
        raise DataError("sweeps: give " + setting("frequency=, storage=, loss= or time=, "
                                                  "modulus=", "frequency, storage and loss "
                                                  "columns, or time and modulus columns"))
    return [_Set(T, time=t, modulus=e) for T, t, e in
            group_by_temperature(temperature, time, modulus, tolerance=tolerance)]


def _temperature_of(item) -> float | None:
    """A sweep's or relaxation test's temperature; a curve's from its file's metadata."""
    T = item.temperature
    return None if T is None else float(T)


def _label(item, k: int) -> str:
    src = item.source
    name = item.name or f"item {k + 1}"
    return f"{src}: {name}" if src and src not in str(name) else str(name)


def reduce_to_reference(items, *, shift_factors=None, T_ref: float | None = None,
                        tolerance: float = 1.0) -> tuple[list, object]:
    """Every item at the reference temperature, ready for one calibration.

    Items carry their test temperature as ``temperature`` (sweeps, relaxation tests) or
    ``metadata["temperature"]`` (stress–strain curves); ``None`` means "at the reference
    already" (then the reference must be said: ``T_ref`` or a law's). With one
    temperature (or none) and no ``shift_factors`` the items come back unchanged.
    Otherwise each item at T is replaced by ``item.shifted(a_T)``, with a_T
    from ``shift_factors`` (a law, a dict or a pair, as :func:`master_curve`) or, without
    them, from the master curve built by overlap of the frequency sweeps (or relaxation
    tests) among the items.

    Returns
    -------
    items : list
        The items at T_ref.
    shift : law, MasterCurve or None
        Where the shift factors came from.

    Raises
    ------
    DataError
        One line naming the item (and file) whose temperature has no shift factor and
        the fix.

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> from vhfit.tts import WLF
    >>> f = np.array([1.0, 10.0])
    >>> s = vhfit.FrequencySweep(frequency=f, storage=[2.0, 3.0], loss=[1.0, 1.0],
    ...                          temperature=40.0)
    >>> out, law = reduce_to_reference([s], shift_factors=WLF(8.0, 100.0, 20.0))
    >>> out[0].frequency.round(4).tolist(), out[0].temperature
    ([0.0464, 0.4642], None)
    """
    items = list(items)
    temps = [_temperature_of(it) for it in items]
    known = sorted({T for T in temps if T is not None})
    spread = known[-1] - known[0] if known else 0.0
    if shift_factors is None and spread <= tolerance:
        return items, None
    # getattr default: shift factors are a law (T_ref) or a table (none)
    if T_ref is None and getattr(shift_factors, "T_ref", None) is None and None in temps:
        k = temps.index(None)
        raise DataError(f"{_label(items[k], k)}: no temperature, beside tests at "
                        f"{len(known)} temperatures: "
                        + setting("say which is the reference (vhfit.tts.reduce_to_reference"
                                  "(items, T_ref=...)) or give every test its temperature",
                                  "give every test its temperature (a '# temperature: T' "
                                  "line in its file)"))
    source = shift_factors
    if shift_factors is None:
        moduli = [it for it, T in zip(items, temps) if T is not None
                  and isinstance(it, FrequencySweep)]
        if not moduli:
            moduli = [it for it, T in zip(items, temps) if T is not None
                      and isinstance(it, Relaxation)]
        if not moduli:
            k = next(i for i, T in enumerate(temps) if T is not None)
            raise DataError(f"{_label(items[k], k)}: tests at {len(known)} temperatures and "
                            "no shift factors: give "
                            + setting("shift_factors= a WLF law or a table",
                                      "--shift wlf:C1,C2 --tref T")
                            + " or DMA sweeps at those temperatures")
        source = master_curve(moduli, T_ref=T_ref, tolerance=tolerance)
        shift_factors = (source.temperatures, source.log_aT)
    law = shift_factors if hasattr(shift_factors, "log_aT") else None
    table = None if law is not None else _known_shifts(np.array(known), shift_factors,
                                                       tolerance)[0]
    out = []
    for k, (it, T) in enumerate(zip(items, temps)):
        if T is None:
            out.append(it)
            continue
        L = float(law.log_aT(T)) if law is not None else table[known.index(T)]
        if L is None:
            raise DataError(f"{_label(it, k)}: no shift factor for T = {T:g} (none within "
                            f"{tolerance:g} of it, and no sweep overlapping its neighbours):"
                            " give " + setting("shift_factors= a law or a table",
                                               "--shift wlf:C1,C2 --tref T")
                            + " that covers it")
        out.append(it.shifted(10.0 ** L))
    return out, source
