"""Tables of moduli: frequency sweeps and relaxation tests from CSV files and arrays.

``_moduli_plan`` reads a table's headers (``frequency_Hz``, ``omega [rad/s]``,
``E' [MPa]``, ``loss_modulus_kPa``, ``|G*| (Pa)``, ``tan_delta``, ``time_s``,
``E(t) [MPa]``, ``temperature_C``, ``set_index``) and says whether the table holds moduli
rather than a stress–strain curve; ``_moduli_items`` builds one :class:`FrequencySweep` or
:class:`Relaxation` per temperature level of the table (the rows of one set, or readings
within half a degree; one item when there is no temperature column), with messages that
name the file, line and column.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from vhfit._words import setting
from vhfit.data._ambiguous import (
    _Cand,
    _check_text_columns,
    _col_index,
    _level_of,
    _scaled,
    _select_rows,
    _settle,
)
from vhfit.data._columns import _STRESS_UNITS, _TIME_UNITS, _classify, _norm_unit
from vhfit.data._errors import DataError, _norm_key, _Subset
from vhfit.data._moduli import FrequencySweep, Relaxation
from vhfit.data._table import _Table

#: Frequency units: factor to Hz, or to rad/s for an angular frequency.
_HZ = {"hz": 1.0, "1/s": 1.0, "khz": 1e3, "cps": 1.0}
_RAD = {"rad/s": 1.0, "rad/sec": 1.0, "rad/min": 1 / 60}
_ROLES = ("frequency", "omega", "storage", "loss", "modulus", "tan_delta", "time",
          "relaxation", "temperature", "set")
_SET_NAMES = ("set", "set_index", "set_id", "set_no", "set_number", "segment")
_MODULUS_ROLES = ("storage", "loss", "modulus", "relaxation")


@dataclass
class _MCol:
    index: int
    header: str
    role: str
    unit: str
    kind: str = ""  # "E" | "G" | "" (moduli)


@dataclass
class _MPlan:
    cols: dict[str, _MCol] = field(default_factory=dict)
    #: other columns that could hold a role's quantity (a frequency also: an angular
    #: frequency), compared with the chosen one by value before it is read
    alternates: dict[str, list[_MCol]] = field(default_factory=dict)
    ignored: set[int] = field(default_factory=set)

    @property
    def is_sweep(self) -> bool:
        return "frequency" in self.cols or "omega" in self.cols


def _unit_and_name(header: str) -> tuple[str, str | None]:
    """(name, unit) with the unit of a last bracket group (``E(t) [MPa]``, ``f (Hz)``)."""
    h = header.replace("\ufeff", "").strip()
    if len(h) > 1 and h[0] == h[-1] and h[0] in "\"'":  # quoted; E' and E'' keep theirs
        h = h[1:-1].strip()
    m = re.match(r"^(?P<name>.+?)\s*[\[\(\{](?P<unit>[^\[\]\(\)\{\}]*)[\]\)\}]\s*$", h)
    if m and m["unit"].strip().lower() not in ("t", "ω", "w", "f"):  # E(t), G(ω)
        return m["name"], m["unit"].strip()
    return h, None


def _tokens(name: str) -> list[str]:
    s = name.lower().replace("′", "'").replace("″", "''").replace("δ", "delta")
    s = s.replace("’", "'").replace('"', "''")
    s = re.sub(r"\(t\)", "_of_t", s)
    return [t for t in re.split(r"[\s_\-]+", s) if t]


def _trailing_unit(tokens: list[str], table: dict[str, float]) -> tuple[list[str], str]:
    """Tokens without a trailing unit token, and that unit ("" if none)."""
    if len(tokens) > 1 and _norm_unit(tokens[-1]) in table:
        return tokens[:-1], tokens[-1]
    return tokens, ""


def _modulus_kind(tokens: list[str]) -> str:
    if "shear" in tokens or (tokens and tokens[0].lstrip("|").startswith("g")):
        return "G"
    return "E"


def _classify_modulus(tokens: list[str]) -> str | None:
    """storage | loss | modulus (|E*|) | tan_delta | relaxation, or None."""
    first = tokens[0] if tokens else ""
    joined = "_".join(tokens)
    if (first in ("tan", "tand", "tandelta", "tan(delta)") or "loss_factor" in joined
            or "loss_tangent" in joined or joined in ("damping", "damping_factor")):
        return "tan_delta"
    if "storage" in tokens or re.fullmatch(r"[eg]'|[eg]_?prime|[eg]1", first):
        return "storage"
    if "loss" in tokens or re.fullmatch(r"[eg]''|[eg]_?double_?prime|[eg]2", first):
        return "loss"
    if (re.fullmatch(r"\|?[eg]\*\|?|abs\([eg]\*\)", first) or
            ({"complex", "dynamic"} & set(tokens) and "modulus" in tokens)):
        return "modulus"
    if (re.fullmatch(r"[eg]", first) and (len(tokens) == 1 or tokens[1] == "of")) or (
            "modulus" in tokens or "relaxation" in tokens):
        return "relaxation"
    return None


def _classify_header(j: int, header: str) -> _MCol | None:
    name, unit = _unit_and_name(header)
    tokens = _tokens(name)
    if not tokens:
        return None
    first = tokens[0]
    if "_".join(tokens) in _SET_NAMES:
        return _MCol(j, header, "set", "")
    if first == "t" and unit is None and len(tokens) == 2 and _is_temperature(tokens[1]):
        return _MCol(j, header, "temperature", tokens[1])
    if (first in ("temperature", "temp", "t") and (first != "t" or _is_temperature(unit))) or (
            {"temperature", "temp"} & set(tokens) and "rate" not in tokens):
        # also with qualifiers: 'nominal_temperature_C', 'measured_sample_temperature_C'
        rest, u = _trailing_unit(tokens, {"c": 1, "°c": 1, "degc": 1, "k": 1})
        return _MCol(j, header, "temperature", unit if unit is not None else u)
    if first in ("omega", "ω", "w") or "angular" in tokens:
        rest, u = _trailing_unit(tokens, _RAD)
        return _MCol(j, header, "omega", unit if unit is not None else u)
    if first in ("frequency", "freq", "f", "frequenz"):
        if first == "f" and len(tokens) > 2:
            return None
        u = unit if unit is not None else "_".join(tokens[1:])  # "frequency_Hz"
        return _MCol(j, header, "omega" if _norm_unit(u) in _RAD else "frequency", u)
    if first in ("time", "zeit") or (first == "t" and len(tokens) <= 2):
        rest, u = _trailing_unit(tokens, _TIME_UNITS)
        return _MCol(j, header, "time", unit if unit is not None else u)
    rest, u = _trailing_unit(tokens, _STRESS_UNITS)
    role = _classify_modulus(rest)
    if role is None:
        return None
    u = unit if unit is not None else u
    return _MCol(j, header, role, u, "" if role == "tan_delta" else _modulus_kind(rest))


def _is_temperature(unit: str | None) -> bool:
    return unit is not None and unit.strip().lower().lstrip("°") in ("c", "k", "degc", "f")


def _moduli_plan(names: list[str], columns: Mapping[str, Any] | None, src: str
                 ) -> _MPlan | None:
    """The moduli columns of a table, or None for a stress–strain table.

    A frequency column with moduli beside it makes a sweep even if the file also has a
    strain column (a DMA export's strain amplitude); a time column with a modulus makes
    a relaxation test only in a file without strain and stress columns.
    """
    plan = _MPlan(ignored=_ignored(names, (columns or {}).get("ignore"), src))
    for j, h in enumerate(names):
        c = None if j in plan.ignored else _classify_header(j, h)
        if c is None:
            continue
        if c.role in plan.cols:
            plan.alternates.setdefault(c.role, []).append(c)
        else:
            plan.cols[c.role] = c
    if "frequency" in plan.cols and "omega" in plan.cols:  # the same axis twice
        plan.alternates.setdefault("frequency", []).append(plan.cols.pop("omega"))
        plan.alternates["frequency"] += plan.alternates.pop("omega", [])
    for key, val in (columns or {}).items():
        role = _norm_key(key)
        if role not in _ROLES:
            continue
        plan.alternates.pop(role, None)  # the user chose
        if role in ("frequency", "omega"):
            plan.alternates.pop("frequency", None)
            plan.cols.pop("omega" if role == "frequency" else "frequency", None)
        if val is None:  # ignore that column
            plan.cols.pop(role, None)
            continue
        hits = [j for j, h in enumerate(names) if h.strip().lower() == str(val).strip().lower()]
        if not hits and role == "time":
            continue  # a stress–strain role too: its reader names the problem
        if not hits:
            which = setting(f"columns={{{key!r}: {val!r}}}", f"--columns {key}={val}")
            raise DataError(f"{src}: {which}"
                            f": no such column; the header has {', '.join(map(repr, names))}")
        name, unit = _unit_and_name(names[hits[0]])
        plan.cols[role] = _MCol(hits[0], names[hits[0]], role, unit or "",
                                _modulus_kind(_tokens(name)))
    roles = set(plan.cols)
    if plan.is_sweep and roles & {"storage", "loss", "modulus", "tan_delta"}:
        return plan
    if any(c is not None and c.role in ("strain", "stretch", "stress")
           for c in (_classify(j, h) for j, h in enumerate(names))):
        return None
    if plan.is_sweep or roles & {"storage", "loss", "modulus", "tan_delta"}:
        return plan
    if "relaxation" in roles and "time" in roles:
        return plan
    return None


def _ignored(names: list[str], given: Any, src: str) -> set[int]:
    """Columns of ``columns={'ignore': header or [headers]}``."""
    if given is None:
        return set()
    out = set()
    for g in [given] if isinstance(given, (str, int)) else list(given):
        hits = [j for j, h in enumerate(names) if h.strip().lower() == str(g).strip().lower()
                or (isinstance(g, int) and j == g)]
        if not hits:
            ignore = setting("columns={'ignore': " + repr(g) + "}", f"--columns ignore={g}")
            raise DataError(f"{src}: {ignore}"
                            f": no such column; the header has {', '.join(map(repr, names))}")
        out.update(hits)
    return out


def _settle_moduli(table: _Table, plan: _MPlan, units: Mapping[str, str] | None,
                   rows: np.ndarray) -> None:
    """Each role with several columns: the finest-written one if they agree on ``rows`` to
    within their rounding (moduli as E = 3G, angular frequencies in Hz), else refused."""
    src = table.source
    for role, alts in list(plan.alternates.items()):
        cols = [plan.cols[role]] + alts
        cands = []
        for c in cols:
            f = _factor(c, units, src) * (3.0 if c.kind == "G" else 1.0)
            if c.role == "omega":
                f /= 2 * np.pi
            cands.append(_Cand(c.index, c.header, c.role, _scaled(f)))
        unit = {"frequency": " Hz", "time": " s", "temperature": "", "set": "",
                "tan_delta": ""}.get(role, " MPa")
        k = _settle(table, rows, cands, role.replace("_", " "), unit)
        plan.cols.pop(role)
        plan.cols[cols[k].role] = cols[k]
        del plan.alternates[role]


def _factor(col: _MCol, units: Mapping[str, str] | None, src: str) -> float:
    """Factor of a column to MPa, Hz, rad/s or s (the header's unit or ``units=``)."""
    u = (units or {}).get(col.role, (units or {}).get("modulus" if col.role in _MODULUS_ROLES
                                                      else col.role))
    u = col.unit if u is None else u
    nu = _norm_unit(u)
    table, hint = {
        "frequency": (_HZ, "Hz or kHz (rad/s: an angular frequency)"),
        "omega": (_RAD, "rad/s"),
        "time": (_TIME_UNITS, "s, ms, min or h"),
    }.get(col.role, (_STRESS_UNITS, "Pa, kPa, MPa or GPa"))
    if col.role in ("tan_delta", "temperature", "set"):
        return 1.0
    f = table.get(nu if col.role != "frequency" or nu else "hz")
    if f is None:
        raise DataError(f"{src}, column {col.header!r}: unit {u!r} is not understood for "
                        f"{col.role.replace('_', ' ')}: use {hint}, or pass "
                        f"{setting(f'units={{{col.role!r}: ...}}', f'--units {col.role}=UNIT')}")
    return float(f)


def _moduli_items(table: _Table, plan: _MPlan, units: Mapping[str, str] | None,
                  name: str | None, group_by: str | Sequence[str] | None = None,
                  select: Mapping[str, Any] | None = None) -> list[FrequencySweep | Relaxation]:
    """One sweep or relaxation test per group (``group_by``) and temperature of the
    table's selected rows (``select``)."""
    src = table.source
    meta = {_norm_key(k): v for k, v in table.meta.items()}
    units = {**{k[:-5]: v for k, v in meta.items() if k.endswith("_unit")}, **(units or {})}
    sel = _select_rows(table, select)
    _settle_moduli(table, plan, units, sel)
    cols = plan.cols
    if plan.is_sweep and not cols.keys() & {"storage", "loss", "modulus", "tan_delta"}:
        raise DataError(f"{src}: a frequency column but no moduli: add storage and loss "
                        "columns (e.g. 'storage_MPa', 'loss_MPa') or |E*| and tan delta")
    if not plan.is_sweep and "relaxation" not in cols:
        raise DataError(f"{src}: moduli columns but no frequency column: add 'frequency_Hz' "
                        "(or 'omega_rad/s')")
    if not plan.is_sweep and "time" not in cols:
        raise DataError(f"{src}: moduli columns but no frequency or time column: add "
                        "'frequency_Hz' (a sweep) or 'time_s' (a relaxation test)")
    values = {r: table.floats(c.index, sel) * _factor(c, units, src) for r, c in cols.items()}
    kinds = {c.kind for r, c in cols.items() if r in _MODULUS_ROLES}
    kind = meta.get("kind", "G" if kinds == {"G"} else "E")
    stem = Path(src).stem if src and not src.startswith("<") else (src or "data")
    base = name or meta.get("name") or stem
    temps = values.get("temperature")
    gcols = [_col_index(table, g, "group_by")
             for g in ([group_by] if isinstance(group_by, str) else group_by or [])]
    groups = []
    for part, m in _parts(table, sel, gcols):
        if temps is None:
            groups.append((part, None, m))
        else:
            sets = values.get("set")
            groups += [(part, T, m[r]) for T, r in _levels(temps[m], None if sets is None
                                                           else sets[m])]
    skip = {c.index for c in cols.values()} | plan.ignored | set(gcols)
    skip |= {_col_index(table, h, "select") for h in (select or {})}
    _check_text_columns(table, sel, [g[2] for g in groups], skip)
    values.pop("set", None)
    headers = {r: c.header for r, c in cols.items() if r != "set"}
    if "relaxation" in headers:
        headers["modulus"] = headers.pop("relaxation")
    out: list[FrequencySweep | Relaxation] = []
    for part, T, rows in groups:
        T = T if T is not None else meta.get("temperature")
        tags = ([part] if part else []) + ([] if temps is None else [f"T = {T:g}"])
        label = f"{base} [{', '.join(tags)}]" if tags else base
        v = {r: a[rows] for r, a in values.items()}
        common = dict(kind=kind, temperature=T, name=label, source=src, _headers=headers,
                      _rows=_Subset(table.labels, sel[rows]))
        if plan.is_sweep:
            if "frequency" in v:
                common["frequency"] = v["frequency"]
            else:
                common["omega"] = v["omega"]
            out.append(FrequencySweep(**_sweep_moduli(v), **common))
        else:
            out.append(Relaxation(time=v["time"], modulus=v["relaxation"], **common))
    return out


def _parts(table: _Table, sel: np.ndarray, gcols: list[int]) -> list[tuple[str, np.ndarray]]:
    """(label, positions in ``sel``) of each group of the ``group_by`` columns, in order
    of appearance; one unlabelled group without them."""
    if not gcols:
        return [("", np.arange(sel.size))]
    keys = [", ".join(t) for t in zip(*(table.texts(j)[sel] for j in gcols))]
    order: dict[str, list[int]] = {}
    for k, key in enumerate(keys):
        order.setdefault(key, []).append(k)
    return [(key, np.asarray(m)) for key, m in order.items()]


def _levels(temps: np.ndarray, sets: np.ndarray | None) -> list[tuple[float, np.ndarray]]:
    """(mean temperature, rows) of each temperature level, in order of appearance.

    A set column says which rows form one level; without one, a row joins the level
    whose first temperature is within ``LEVEL_TOLERANCE`` of its own (the readings
    of one level drift by hundredths of a degree), else starts a new level.
    """
    level = (_level_of(temps.tolist()) if sets is None else
             [list(dict.fromkeys(sets.tolist())).index(v) for v in sets.tolist()])
    rows: dict[int, list[int]] = {}
    for i, k in enumerate(level):
        rows.setdefault(k, []).append(i)
    return [(float(np.mean(temps[r])), np.asarray(r)) for r in rows.values()]


def _sweep_moduli(v: dict[str, np.ndarray]) -> dict[str, np.ndarray | None]:
    """The moduli a sweep is built from: E′ and E″ when both are there, else E′ or |E*|
    with tan δ (a file may hold all four; anything incomplete is left for the sweep to
    name)."""
    if "storage" in v and "loss" in v:
        return {"storage": v["storage"], "loss": v["loss"]}
    if "storage" in v and "tan_delta" in v:
        return {"storage": v["storage"], "tan_delta": v["tan_delta"]}
    return {r: v.get(r) for r in ("storage", "loss", "modulus", "tan_delta")}
