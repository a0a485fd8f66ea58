"""Column recognition: what a header says (role, unit, stress measure) and which columns
feed a curve.

``_classify`` reads one header (``stress_kPa``, ``Stress (Pa)``, ``true_strain``,
``time_ms``, ``nominal_strain_rate_per_s``, ...); ``_resolve_columns`` picks the strain
(or stretch), stress, time and rate columns of a table, honouring the user's ``columns=``
and ``units=``, and returns a ``_Plan`` with the unit factors to MPa, s and 1/s.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vhfit._words import setting
from vhfit.data._errors import DataError, _norm_key, _short

# ========================================================= column recognition
_STRESS_UNITS = {
    "": 1.0,
    "mpa": 1.0,
    "n/mm2": 1.0,
    "pa": 1e-6,
    "n/m2": 1e-6,
    "kpa": 1e-3,
    "kn/m2": 1e-3,
    "gpa": 1e3,
    "n/cm2": 1e-2,
    "bar": 0.1,
    "psi": 6.894757293168361e-3,
    "ksi": 6.894757293168361,
    "kgf/cm2": 0.0980665,
    "kg/cm2": 0.0980665,
}
_STRAIN_UNITS = {"": 1.0, "-": 1.0, "1": 1.0, "mm/mm": 1.0, "m/m": 1.0, "in/in": 1.0,
                 "ratio": 1.0, "%": 0.01, "percent": 0.01, "pct": 0.01}
_STRETCH_UNITS = {"": 1.0, "-": 1.0, "1": 1.0, "mm/mm": 1.0, "m/m": 1.0, "ratio": 1.0}
_TIME_UNITS = {"": 1.0, "s": 1.0, "sec": 1.0, "secs": 1.0, "second": 1.0, "seconds": 1.0,
               "ms": 1e-3, "us": 1e-6, "min": 60.0, "mins": 60.0, "h": 3600.0, "hr": 3600.0,
               "hour": 3600.0, "hours": 3600.0}
_RATE_UNITS = {"": 1.0, "1/s": 1.0, "/s": 1.0, "s-1": 1.0, "1/sec": 1.0, "/sec": 1.0,
               "mm/mm/s": 1.0, "1/ms": 1e3, "1/min": 1 / 60, "/min": 1 / 60, "min-1": 1 / 60,
               "1/h": 1 / 3600, "/h": 1 / 3600, "%/s": 0.01, "%/min": 0.01 / 60}
#: A test's temperature is kept in the unit it is written in (°C, K or °F): shift laws
#: are written in that scale; 'C', 'K' and 'F' are units after a temperature only.
_TEMPERATURE_UNITS = {"": 1.0, "c": 1.0, "°c": 1.0, "degc": 1.0, "deg/c": 1.0, "celsius": 1.0,
                      "k": 1.0, "kelvin": 1.0, "f": 1.0, "°f": 1.0, "degf": 1.0,
                      "fahrenheit": 1.0}
_UNITS = {"stress": _STRESS_UNITS, "strain": _STRAIN_UNITS, "stretch": _STRETCH_UNITS,
          "time": _TIME_UNITS, "rate": _RATE_UNITS, "temperature": _TEMPERATURE_UNITS}
_UNIT_HINT = {
    "stress": "Pa, kPa, MPa, GPa, N/mm2, psi, kgf/cm2",
    "strain": "none, -, mm/mm or %",
    "stretch": "none",
    "time": "s, ms, min or h",
    "rate": "1/s, 1/min, %/s or %/min",
    "temperature": "C, K or F",
}
#: A header of each role with a unit it understands, for the hint's example.
_UNIT_EXAMPLE = {"stress": "stress_MPa", "strain": "strain_%", "stretch": "stretch",
                 "time": "time_s", "rate": "rate_1/s", "temperature": "temperature_C"}

_STRESS_WORDS = {"stress", "sigma", "σ", "spannung"}
_STRAIN_WORDS = {"strain", "epsilon", "eps", "ε", "dehnung"}
_STRETCH_WORDS = {"stretch", "lambda", "λ", "lam", "lambda1", "λ1"}
_TIME_WORDS = {"time", "zeit", "t"}
_TEMPERATURE_WORDS = {"temperature", "temp"}
_RATE_NAMES = {"strainrate", "epsdot", "eps_dot", "de/dt", "dε/dt", "edot"}
_ENG_WORDS = {"engineering", "eng", "nominal", "nom", "piola", "pk1", "first", "1st"}
_TRUE_WORDS = {"true", "cauchy"}
_LOG_WORDS = {"true", "log", "logarithmic", "hencky", "natural"}
_AXIAL_WORDS = {"axial", "uniaxial"}
_SHEAR_WORDS = {"gamma", "γ"}  # the amount of shear of simple shear, alone
#: Measured channels, never an amount of shear ('shear_force_N', 'shear_displacement_mm').
_CHANNEL_WORDS = {"force", "load", "displacement", "disp", "position", "extension"}
_ROLE_KEYS = ("strain", "stretch", "stress", "time", "rate", "strain2", "stretch2", "stress2",
              "deformation", "temperature", "ignore")
#: Symbols that name a quantity: after its keyword a descriptive word, never a unit.
_SYMBOLS = {"sigma", "σ", "epsilon", "eps", "ε", "lambda", "λ", "gamma", "γ"}
#: Symbols a lab writes after a quantity's name (``shear_stress_tau_kPa``,
#: ``stress_sigma_MPa``, ``strain_eps``): they name it again, never a unit.
_NAME_SYMBOLS = _SYMBOLS | {"tau", "τ"}
_GROUP_NAMES = {"curve", "test", "specimen", "name"}
#: Headers of a text column naming each row's test (its values: deformation names).
_DEFORMATION_NAMES = {"deformation", "deformation_mode", "mode", "test_mode", "test_type",
                      "loading_mode", "test_kind"}



_DIRECTED = _STRESS_WORDS | _STRAIN_WORDS | _STRETCH_WORDS | {"lam", "l"}


def _direction(tokens: list[str]) -> tuple[list[str], int]:
    """The header's tokens without a direction mark, and the direction (1 or 2).

    ``stress2``, ``lambda_2``, ``nominal_stress_1``: a keyword ending in, or followed by,
    1 or 2 (``lambda1`` and ``λ1`` are direction 1 as they stand).
    """
    out, direction = [], 1
    for tok in tokens:
        m = re.fullmatch(r"(.+?)([12])", tok)
        if m and m.group(1) in _DIRECTED and tok not in _STRETCH_WORDS:
            out.append(m.group(1))
            direction = int(m.group(2))
        elif tok in ("1", "2") and out and out[-1] in _DIRECTED:
            direction = int(tok)
        else:
            out.append(tok)
    if out and out[0] == "l" and len(out) == 1:
        out = ["lambda"]
    return out, direction


def _norm_unit(u: str) -> str:
    s = u.strip().lower().replace("µ", "u").replace("μ", "u").replace("²", "2")
    s = s.replace("**", "^").replace("^", "").replace(" ", "")
    s = re.sub(r"(^|_)per_", lambda m: "1/" if not m.group(1) else "/", s)
    return s.replace("_", "/")


def _plain(header: str) -> str:
    return header.replace("\ufeff", "").strip().lower()


def _unit_factor(role: str, unit: str) -> float | None:
    return _UNITS[role].get(_norm_unit(unit))


@dataclass
class _Col:
    """What a header says about its column."""

    index: int
    header: str
    role: str  # strain | stretch | stress | time | rate
    rank: float  # lower is a better match
    unit: str  # as written ("" if none)
    kind: str = ""  # strain: "eng" | "log" | "shear"; stress: "engineering" | "true" | ""
    # stretch: "" | "or_shear" (a stretch, or the amount of shear on simple-shear rows)
    ambiguous: str = ""  # why the unit suffix may be a word instead ("" if it cannot)


def _split_header(h: str) -> tuple[list[str], str | None]:
    h = h.replace("\ufeff", "").strip().strip("\"'").strip()
    unit = None
    m = re.match(r"^(?P<name>.*?)\s*[\[\(\{](?P<unit>[^\]\)\}]*)[\]\)\}]\s*$", h)
    if m and m["name"]:
        h, unit = m["name"], m["unit"].strip()
    base = re.sub(r"(?<=[a-zα-ω])-(?=[a-zα-ω])", "_", h.lower())
    return [tok for tok in re.split(r"[\s_]+", base) if tok], unit


def _classify(index: int, header: str) -> _Col | None:
    """What one header says: its role (a direction-2 role ends in 2), unit and kind."""
    tokens, unit = _split_header(header)
    if not tokens:
        return None
    if "_".join(tokens) in _DEFORMATION_NAMES:
        return _Col(index, header, "deformation", 0.0, "")
    tokens, direction = _direction(tokens)
    col = _classify_tokens(index, header, tokens, unit)
    if col is not None and direction == 2 and col.role in ("strain", "stretch", "stress"):
        col.role += "2"
    return col


def _classify_tokens(index: int, header: str, tokens: list[str], unit: str | None
                     ) -> _Col | None:
    joined = "_".join(tokens)

    def after_unit(k: int, qualifiers: set[str]) -> tuple[list[str], str]:
        """Qualifier tokens after the keyword, and the unit (bracketed, or the rest)."""
        rest = tokens[k + 1 :]
        if unit is not None:
            return rest, unit
        quals = []
        while rest and (rest[0] in qualifiers or rest[0] in _NAME_SYMBOLS):
            tok = rest.pop(0)
            if tok not in _NAME_SYMBOLS:  # a symbol names the quantity: no qualifier
                quals.append(tok)
        return quals, "_".join(rest)

    # rate: "strain_rate", "rate [1/s]", "nominal_strain_rate_per_s" (not "..._from_rate")
    if ("rate" in tokens and "from" not in tokens) or joined in _RATE_NAMES:
        k = tokens.index("rate") if "rate" in tokens else len(tokens) - 1
        if any(t in tokens[:k] for t in ("stress", "load", "force", "heating", "sampling")):
            return None
        quals, u = after_unit(k, set())
        return _Col(index, header, "rate", float(k > 0 and tokens[k - 1] not in
                                                 _STRAIN_WORDS | _STRETCH_WORDS | _ENG_WORDS),
                    u)
    # temperature: "temperature_C", "nominal_temperature_C", "measured_sample_temperature_C"
    if set(tokens) & _TEMPERATURE_WORDS:
        k = next(i for i, t in enumerate(tokens) if t in _TEMPERATURE_WORDS)
        words = tokens[:k] + tokens[k + 1:]
        u = unit if unit is not None else ""
        if unit is None and words and _unit_factor("temperature", words[-1]) is not None:
            u = words.pop()  # 'C' or 'K' after the words: the unit
        return _Col(index, header, "temperature", 1.0 if words else 0.0, u)
    # time: "time_s", "t [ms]", "test time (min)"
    for k, tok in enumerate(tokens):
        if tok in _TIME_WORDS and (tok != "t" or k == 0):
            quals, u = after_unit(k, set())
            if tok == "t" and _unit_factor("time", u) is None:
                break
            return _Col(index, header, "time", float(k > 0 or bool(quals)), u)
    other_roles = set(tokens) & (_STRESS_WORDS | _STRETCH_WORDS | _CHANNEL_WORDS)
    if tokens[0] in _SHEAR_WORDS or (
            ("shear" in tokens or set(tokens) & _SHEAR_WORDS and set(tokens) & _STRAIN_WORDS)
            and not other_roles):
        # 'strain_gamma': the symbol γ says the strain is an amount of shear
        # "gamma", "shear_strain", "amount_of_shear": the amount of shear γ
        k = next(i for i, t in enumerate(tokens) if t in _SHEAR_WORDS | {"shear"})
        quals, u = after_unit(k, _STRAIN_WORDS | _SHEAR_WORDS | {"amount", "of", "shear"})
        return _Col(index, header, "strain", 0.0, u, "shear")
    for k, tok in enumerate(tokens):
        before = set(tokens[:k])
        if tok in _STRESS_WORDS:
            quals, u = after_unit(k, _ENG_WORDS | _TRUE_WORDS)
            q = before | set(quals)
            kind = ("true" if q & _TRUE_WORDS else "engineering" if q & _ENG_WORDS else "")
            other = q - _ENG_WORDS - _TRUE_WORDS - {"shear"}
            return _overbar(_Col(index, header, "stress", 2.0 if other else 0.0, u, kind),
                            tok, unit)
        if tok in _STRAIN_WORDS:
            quals, u = after_unit(k, _ENG_WORDS | _LOG_WORDS | _AXIAL_WORDS)
            q = before | set(quals)
            kind = "log" if q & _LOG_WORDS else "eng"
            other = q - _ENG_WORDS - _LOG_WORDS - _AXIAL_WORDS
            return _overbar(_Col(index, header, "strain",
                                 2.0 if other else (1.0 if kind == "log" else 0.0), u, kind),
                            tok, unit)
        if tok in _STRETCH_WORDS:
            rest = tokens[k + 1 :]
            u = unit if unit is not None else ""
            if unit is None and rest and _unit_factor("stretch", "_".join(rest)) is not None:
                rest = []
            if "shear" in rest:  # "stretch_or_shear_amount": γ on simple-shear rows
                return _Col(index, header, "stretch", 0.5, u, "or_shear")
            other = (before | set(rest)) - _ENG_WORDS - _AXIAL_WORDS - _NAME_SYMBOLS
            return _Col(index, header, "stretch", 0.5 + (1.5 if other else 0.0), u)
    return None


def _overbar(col: _Col, keyword: str, bracketed: str | None) -> _Col:
    """``sigma_bar``: 'bar' after a symbol may be the unit or an overbar (a mean)."""
    if keyword in _SYMBOLS and bracketed is None and _norm_unit(col.unit) == "bar":
        col.ambiguous = "'bar' after a symbol may be the unit or an overbar (a mean)"
    return col


@dataclass
class _Plan:
    """Which columns feed a curve, and how to convert them."""

    deform: _Col
    stress: _Col
    time: _Col | None
    rate: _Col | None
    factors: dict[str, float] = field(default_factory=dict)
    measure: str | None = None  # from the header
    deform2: _Col | None = None  # λ2 or λ2 − 1 of a biaxial test
    stress2: _Col | None = None  # stress in direction 2
    deformation: _Col | None = None  # a text column naming each row's test
    temperature: _Col | None = None  # the test temperature of each row
    #: other columns that could hold a role's quantity (plan role -> columns), to be
    #: compared with the chosen one by value (``_ambiguous._settle``)
    alternates: dict[str, list[_Col]] = field(default_factory=dict)
    alt_factors: dict[int, float] = field(default_factory=dict)  # column -> unit factor
    ignored: set[int] = field(default_factory=set)  # columns={'ignore': ...}



def _resolve_columns(
    names: list[str],
    columns: Mapping[str, Any] | None,
    units: Mapping[str, str] | None,
    measure: str | None,
    src: str,
) -> _Plan:
    """The columns that feed a curve and their unit factors, or a DataError saying why not."""
    columns = dict(columns or {})
    ignored = _ignored_columns(names, columns.pop("ignore", None), src)
    cols = [None if j in ignored else _classify(j, h) for j, h in enumerate(names)]
    explicit = _explicit_columns(names, cols, columns, src)
    alts: dict[str, list[_Col]] = {}
    deform = _deform_column(cols, explicit, src, alts.setdefault("deform", []))
    stress = _best_column(cols, explicit, ("stress",), "stress", src, prefer_measure=measure,
                          pool=alts.setdefault("stress", []))
    time = _best_column(cols, explicit, ("time",), "time", src, pool=alts.setdefault("time", []))
    rate = _best_column(cols, explicit, ("rate",), "strain rate", src,
                        pool=alts.setdefault("rate", []))
    header_list = ", ".join(map(_short, names[:12])) + (
        f" and {len(names) - 12} more" if len(names) > 12 else "")
    if deform is None:
        raise DataError(
            f"{src}: no strain or stretch column among {header_list}: name one 'strain' "
            "(or 'stretch', 'strain_%'), or pass "
            + setting("columns={'strain': '<header>'}", "--columns strain=NAME")
        )
    if stress is None:
        raise DataError(
            f"{src}: no stress column among {header_list}: name one 'stress_MPa' (or "
            "'stress [kPa]', ...), or pass "
            + setting("columns={'stress': '<header>'}", "--columns stress=NAME")
            + "; force and displacement must first be converted with the specimen's area "
            "and gauge length"
        )
    deform2 = _second_deform_column(cols, explicit, src, alts.setdefault("deform2", []))
    stress2 = _best_column(cols, explicit, ("stress2",), "second stress", src,
                           prefer_measure=measure, pool=alts.setdefault("stress2", []))
    dcol = _best_column(cols, explicit, ("deformation",), "deformation", src)
    temp = _best_column(cols, explicit, ("temperature",), "temperature", src,
                        pool=alts.setdefault("temperature", []))
    plan = _Plan(deform, stress, time, rate, deform2=deform2, stress2=stress2,
                 deformation=dcol, ignored=ignored, temperature=temp)
    for role, col in (("deform", deform), ("stress", stress), ("time", time), ("rate", rate),
                      ("deform2", deform2), ("stress2", stress2), ("temperature", temp)):
        if col is not None:
            plan.factors[role] = _column_factor(col, units, src)
        if col is not None and alts.get(role):
            plan.alternates[role] = alts[role]
            for c in alts[role]:
                plan.alt_factors[c.index] = _column_factor(c, units, src, rival=col)
    if stress.kind:
        plan.measure = stress.kind
    return plan


def _ignored_columns(names: list[str], given: Any, src: str) -> set[int]:
    """The columns of ``columns={'ignore': header or [headers]}``."""
    if given is None:
        return set()
    given = [given] if isinstance(given, (str, int, np.integer)) else list(given)
    return {_explicit_index("ignore", g, names, src) for g in given}


def _explicit_columns(
    names: list[str], cols: list[_Col | None], columns: Mapping[str, Any] | None, src: str
) -> dict[str, _Col | None]:
    """Role -> column (None: ignore the role) from the user's ``columns=`` mapping."""
    explicit: dict[str, _Col | None] = {}
    for key, val in (columns or {}).items():
        role = _norm_key(key)
        role = {"strain_rate": "rate", "stretch_ratio": "stretch", "gamma": "strain",
                "shear": "strain"}.get(role, role)
        if role not in _ROLE_KEYS:
            raise DataError(
                f"{src}: {setting(f'columns={{{key!r}: ...}}', f'--columns {key}=NAME')}: "
                f"unknown role; use {', '.join(_ROLE_KEYS)}"
            )
        if val is None:
            explicit[role] = None
            continue
        j = _explicit_index(key, val, names, src)
        c = cols[j]
        if c is None or c.role != role:
            tokens, u = _split_header(names[j])
            c = _Col(j, names[j], role, 0.0, u if u is not None else "",
                     "eng" if role in ("strain", "strain2") else "")
            base = role.rstrip("2")
            if base in ("stress", "time", "rate", "strain") and u is None and len(tokens) > 1:
                # "stress_kPa" mapped by hand: the last token may still be the unit
                if _unit_factor(base, tokens[-1]) is not None:
                    c.unit = tokens[-1]
        explicit[role] = c
    return explicit


def _explicit_index(key: Any, val: Any, names: list[str], src: str) -> int:
    """The column a ``columns=`` entry names: a 0-based index or a header."""
    if isinstance(val, (int, np.integer)) and not isinstance(val, bool):
        j = int(val)
        if not 0 <= j < len(names):
            which = setting(f"columns={{{key!r}: {j}}}", f"--columns {key}={j}")
            raise DataError(f"{src}: {which}"
                            f": there are {len(names)} columns")
        return j
    wanted = str(val).strip().lower()
    hits = [j for j, h in enumerate(names) if _plain(h) == wanted]
    if not hits:
        raise DataError(
            f"{src}: {setting(f'columns={{{key!r}: {val!r}}}', f'--columns {key}={val}')}: "
            f"no such column; the header has {', '.join(map(repr, names))}"
        )
    return hits[0]


def _deform_column(
    cols: list[_Col | None], explicit: dict[str, _Col | None], src: str, pool: list[_Col]
) -> _Col | None:
    """The strain column, else the stretch column (a given one first)."""
    if "strain" in explicit and explicit["strain"] is not None:
        return explicit["strain"]
    if "stretch" in explicit and explicit["stretch"] is not None:
        return explicit["stretch"]
    roles = tuple(r for r in ("strain", "stretch") if r not in explicit)
    return (_best_column(cols, explicit, roles, "strain or stretch", src, pool=pool)
            if roles else None)


def _second_deform_column(
    cols: list[_Col | None], explicit: dict[str, _Col | None], src: str, pool: list[_Col]
) -> _Col | None:
    """The λ2 − 1 column, else the λ2 column, of a biaxial test (a given one first)."""
    for r in ("strain2", "stretch2"):
        if explicit.get(r) is not None:
            return explicit[r]
    roles = tuple(r for r in ("strain2", "stretch2") if r not in explicit)
    return (_best_column(cols, explicit, roles, "second strain or stretch", src, pool=pool)
            if roles else None)


def _best_column(
    cols: list[_Col | None],
    explicit: dict[str, _Col | None],
    roles: tuple[str, ...],
    what: str,
    src: str,
    prefer_measure: str | None = None,
    pool: list[_Col] | None = None,
) -> _Col | None:
    """The given column of one of ``roles``, else the best-ranked recognised one.

    With ``pool`` (a quantity that can be compared by value), ties are not refused here:
    the column read is the best-ranked (a stress in MPa first, then the first in the
    file), and every other column that could hold the same quantity — recognised without
    an unknown qualifier word (``crosshead_strain``, ``target_strain`` are other
    channels), of the same kind (an amount of shear is no stretch) — goes into ``pool``
    to be compared with it by value.
    """
    for r in roles:
        if r in explicit:
            return explicit[r]
    cands = [c for c in cols if c is not None and c.role in roles]
    if what in ("stress", "second stress"):
        cands = _stress_candidates(cands, prefer_measure)
    if not cands:
        return None
    top = min(c.rank for c in cands)
    if pool is not None:
        cands = [c for c in cands if (c.rank < 2.0 if top < 2.0 else c.rank == top)]
        cands.sort(key=lambda c: (c.rank, "stress" in what and _norm_unit(c.unit)
                                  not in ("mpa", "n/mm2"), c.index))
        pool.extend(c for c in cands[1:] if _family(c) == _family(cands[0]))
        return cands[0]
    cands = [c for c in cands if c.rank == top]
    if len(cands) > 1 and what == "stress" and all(c.unit for c in cands):
        # the same stress in two units (e.g. kgf/cm2 and MPa): take the MPa one
        mpa = [c for c in cands if _norm_unit(c.unit) in ("mpa", "n/mm2")]
        if len(mpa) == 1:
            cands = mpa
    if len(cands) > 1:
        raise DataError(
            f"{src}: several columns could be the {what}: "
            f"{', '.join(repr(c.header) for c in cands)}: say which with "
            + setting(f"columns={{'{roles[0]}': '<header>'}}", f"--columns {roles[0]}=NAME")
        )
    return cands[0]


def _family(col: _Col) -> str:
    """Columns of one family hold the same quantity after conversion."""
    if col.kind in ("shear", "or_shear"):
        return col.kind
    return col.role.rstrip("2").replace("stretch", "strain")


def _stress_candidates(cands: list[_Col], prefer_measure: str | None) -> list[_Col]:
    """Stress columns of the wanted measure; by default engineering/unqualified before true."""
    if prefer_measure:
        matching = [c for c in cands if c.kind == prefer_measure]
        if matching:
            return matching
        return [c for c in cands if c.kind in ("", prefer_measure)] or cands
    cands = sorted(cands, key=lambda c: (c.rank, c.kind == "true"))
    if cands:
        cands = [c for c in cands if (c.rank, c.kind == "true") ==
                 (cands[0].rank, cands[0].kind == "true")]
    return cands


def _column_factor(col: _Col, units: Mapping[str, str] | None, src: str,
                   rival: _Col | None = None) -> float:
    """Factor from the column's unit (the header's, or ``units=``) to MPa, s or 1/s
    (``rival``: the column read instead, when ``col`` is only compared with it)."""
    r = col.role.rstrip("2")
    u = (units or {}).get(col.role, (units or {}).get(r))
    if u is None and r == "rate":
        u = (units or {}).get("strain_rate")
    given = u is not None
    u = col.unit if u is None else u
    f = _unit_factor(r, u)
    if f is not None and (given or not col.ambiguous):
        return f
    why = col.ambiguous or f"unit {u!r} is not understood for {r}"
    if rival is not None:
        raise DataError(
            f"{src}, column {col.header!r}: could also be the {r} beside {rival.header!r}, "
            f"but {why}: say which column is the {r} with "
            f"{setting(f'columns={{{r!r}: {rival.header!r}}}', f'--columns {r}={rival.header}')}"
            f", or its unit with {setting(f'units={{{r!r}: ...}}', f'--units {r}=UNIT')}"
        )
    raise DataError(
        f"{src}, column {col.header!r}: {why}: use "
        f"{_UNIT_HINT[r]} (e.g. '{_UNIT_EXAMPLE[r]}'), or pass "
        f"{setting(f'units={{{r!r}: ...}}', f'--units {r}=UNIT')}"
    )
