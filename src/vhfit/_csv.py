"""CSV and array tables -> curves: column recognition, the table layer, and the curves.

Recognises the columns of a header (role, unit, stress measure), reads and decodes a
CSV file (or wraps an array, DataFrame-like object or mapping) into a lazily split
table, and turns a table into :class:`vhfit.data.Curve` objects (groups, rates, metadata
lines). The public readers are :func:`vhfit.data.read_csv` and
:func:`vhfit.data.curves_from_arrays`.
"""

from __future__ import annotations

import codecs
import csv
import operator
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from vhfit._where import DataError, _Labels, _norm_key, _norm_measure, _Where

if TYPE_CHECKING:
    from vhfit.data import Curve

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
_UNITS = {"stress": _STRESS_UNITS, "strain": _STRAIN_UNITS, "stretch": _STRETCH_UNITS,
          "time": _TIME_UNITS, "rate": _RATE_UNITS}
_UNIT_HINT = {
    "stress": "Pa, kPa, MPa, GPa, N/mm2, psi, kgf/cm2",
    "strain": "none, -, mm/mm or %",
    "stretch": "none",
    "time": "s, ms, min or h",
    "rate": "1/s, 1/min, %/s or %/min",
}

_STRESS_WORDS = {"stress", "sigma", "σ", "spannung"}
_STRAIN_WORDS = {"strain", "epsilon", "eps", "ε", "dehnung"}
_STRETCH_WORDS = {"stretch", "lambda", "λ", "lam", "lambda1", "λ1"}
_TIME_WORDS = {"time", "zeit", "t"}
_RATE_NAMES = {"strainrate", "epsdot", "eps_dot", "de/dt", "dε/dt", "edot"}
_ENG_WORDS = {"engineering", "eng", "nominal", "nom", "piola", "pk1", "first", "1st"}
_TRUE_WORDS = {"true", "cauchy"}
_LOG_WORDS = {"true", "log", "logarithmic", "hencky", "natural"}
_AXIAL_WORDS = {"axial", "uniaxial"}
_ROLE_KEYS = ("strain", "stretch", "stress", "time", "rate")
_GROUP_NAMES = {"curve", "test", "specimen", "name"}


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
    kind: str = ""  # strain: "eng" | "log"; stress: "engineering" | "true" | ""


def _split_header(h: str) -> tuple[list[str], str | None]:
    h = h.replace("\ufeff", "").strip().strip("\"'").strip()
    unit = None
    m = re.match(r"^(?P<name>.*?)\s*[\[\(\{](?P<unit>[^\]\)\}]*)[\]\)\}]\s*$", h)
    if m and m["name"]:
        h, unit = m["name"], m["unit"].strip()
    base = re.sub(r"(?<=[a-zα-ω])-(?=[a-zα-ω])", "_", h.lower())
    return [tok for tok in re.split(r"[\s_]+", base) if tok], unit


def _classify(index: int, header: str) -> _Col | None:
    tokens, unit = _split_header(header)
    if not tokens:
        return None
    joined = "_".join(tokens)

    def after_unit(k: int, qualifiers: set[str]) -> tuple[list[str], str]:
        """Qualifier tokens after the keyword, and the unit (bracketed, or the rest)."""
        rest = tokens[k + 1 :]
        if unit is not None:
            return rest, unit
        quals = []
        while rest and rest[0] in qualifiers:
            quals.append(rest.pop(0))
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
    # time: "time_s", "t [ms]", "test time (min)"
    for k, tok in enumerate(tokens):
        if tok in _TIME_WORDS and (tok != "t" or k == 0):
            quals, u = after_unit(k, set())
            if tok == "t" and _unit_factor("time", u) is None:
                break
            return _Col(index, header, "time", float(k > 0 or bool(quals)), u)
    for k, tok in enumerate(tokens):
        before = set(tokens[:k])
        if tok in _STRESS_WORDS:
            quals, u = after_unit(k, _ENG_WORDS | _TRUE_WORDS)
            q = before | set(quals)
            kind = ("true" if q & _TRUE_WORDS else "engineering" if q & _ENG_WORDS else "")
            other = q - _ENG_WORDS - _TRUE_WORDS
            return _Col(index, header, "stress", 2.0 if other else 0.0, u, kind)
        if tok in _STRAIN_WORDS:
            quals, u = after_unit(k, _ENG_WORDS | _LOG_WORDS | _AXIAL_WORDS)
            q = before | set(quals)
            kind = "log" if q & _LOG_WORDS else "eng"
            other = q - _ENG_WORDS - _LOG_WORDS - _AXIAL_WORDS
            return _Col(index, header, "strain", 2.0 if other else (1.0 if kind == "log" else 0.0),
                        u, kind)
        if tok in _STRETCH_WORDS:
            rest = tokens[k + 1 :]
            u = unit if unit is not None else ""
            if unit is None and rest and _unit_factor("stretch", "_".join(rest)) is not None:
                rest = []
            other = (before | set(rest)) - _ENG_WORDS - _AXIAL_WORDS
            return _Col(index, header, "stretch", 0.5 + (1.5 if other else 0.0), u)
    return None


@dataclass
class _Plan:
    """Which columns feed a curve, and how to convert them."""

    deform: _Col
    stress: _Col
    time: _Col | None
    rate: _Col | None
    factors: dict[str, float] = field(default_factory=dict)
    measure: str | None = None  # from the header


def _resolve_columns(
    names: list[str],
    columns: Mapping[str, Any] | None,
    units: Mapping[str, str] | None,
    measure: str | None,
    src: str,
) -> _Plan:
    cols = [_classify(j, h) for j, h in enumerate(names)]
    explicit: dict[str, _Col | None] = {}
    for key, val in (columns or {}).items():
        role = _norm_key(key)
        role = {"strain_rate": "rate", "stretch_ratio": "stretch"}.get(role, role)
        if role not in _ROLE_KEYS:
            raise DataError(
                f"{src}: columns={{{key!r}: ...}}: unknown role; use {', '.join(_ROLE_KEYS)}"
            )
        if val is None:
            explicit[role] = None
            continue
        if isinstance(val, (int, np.integer)) and not isinstance(val, bool):
            j = int(val)
            if not 0 <= j < len(names):
                raise DataError(f"{src}: columns={{{key!r}: {j}}}: there are {len(names)} columns")
        else:
            wanted = str(val).strip().lower()
            hits = [j for j, h in enumerate(names) if _plain(h) == wanted]
            if not hits:
                raise DataError(
                    f"{src}: columns={{{key!r}: {val!r}}}: no such column; the header has "
                    f"{', '.join(map(repr, names))}"
                )
            j = hits[0]
        c = cols[j]
        if c is None or c.role != role:
            tokens, u = _split_header(names[j])
            c = _Col(j, names[j], role, 0.0, u if u is not None else "",
                     "eng" if role == "strain" else "")
            if role in ("stress", "time", "rate", "strain") and u is None and len(tokens) > 1:
                # "stress_kPa" mapped by hand: the last token may still be the unit
                if _unit_factor(role, tokens[-1]) is not None:
                    c.unit = tokens[-1]
        explicit[role] = c

    def best(roles: tuple[str, ...], what: str, prefer_measure: str | None = None) -> _Col | None:
        for r in roles:
            if r in explicit:
                return explicit[r]
        cands = [c for c in cols if c is not None and c.role in roles]
        if prefer_measure and what == "stress":
            matching = [c for c in cands if c.kind == prefer_measure]
            if matching:
                cands = matching
            else:
                cands = [c for c in cands if c.kind in ("", prefer_measure)] or cands
        elif what == "stress":
            # default measure: engineering/unqualified before true
            cands = sorted(cands, key=lambda c: (c.rank, c.kind == "true"))
            if cands:
                cands = [c for c in cands if (c.rank, c.kind == "true") ==
                         (cands[0].rank, cands[0].kind == "true")]
        if not cands:
            return None
        top = min(c.rank for c in cands)
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
                f"columns={{'{roles[0]}': '<header>'}}"
            )
        return cands[0]

    if "strain" in explicit and explicit["strain"] is not None:
        deform = explicit["strain"]
    elif "stretch" in explicit and explicit["stretch"] is not None:
        deform = explicit["stretch"]
    else:
        pool = {r: explicit[r] for r in ("strain", "stretch") if r in explicit}
        roles = tuple(r for r in ("strain", "stretch") if r not in pool)
        deform = best(roles, "strain or stretch") if roles else None
    stress = best(("stress",), "stress", prefer_measure=measure)
    time = best(("time",), "time")
    rate = best(("rate",), "strain rate")
    header_list = ", ".join(map(_short, names[:12])) + (
        f" and {len(names) - 12} more" if len(names) > 12 else "")
    if deform is None:
        raise DataError(
            f"{src}: no strain or stretch column among {header_list}: name one 'strain' "
            "(or 'stretch', 'strain_%'), or pass columns={'strain': '<header>'}"
        )
    if stress is None:
        raise DataError(
            f"{src}: no stress column among {header_list}: name one 'stress_MPa' (or "
            "'stress [kPa]', ...), or pass columns={'stress': '<header>'}; force and "
            "displacement must first be converted with the specimen's area and gauge length"
        )
    plan = _Plan(deform, stress, time, rate)
    for role, col in (("deform", deform), ("stress", stress), ("time", time), ("rate", rate)):
        if col is None:
            continue
        r = col.role
        u = (units or {}).get(r, (units or {}).get("strain_rate") if r == "rate" else None)
        u = col.unit if u is None else u
        f = _unit_factor(r, u)
        if f is None:
            raise DataError(
                f"{src}, column {col.header!r}: unit {u!r} is not understood for {r}: use "
                f"{_UNIT_HINT[r]} (e.g. '{r}_{'MPa' if r == 'stress' else 's'}'), or pass "
                f"units={{'{r}': ...}}"
            )
        plan.factors[role] = f
    if stress.kind:
        plan.measure = stress.kind
    return plan


# ================================================================ table layer
@dataclass
class _Table:
    """A parsed table: column names, row labels, and the cells (split lazily for files)."""

    names: list[str]
    cols: list[np.ndarray] | None  # one per column (str/object or numbers); None until split
    labels: _Labels
    source: str
    meta: dict[str, str]
    lines: list[str] | None = None  # data lines of a file, for lazy splitting
    split_line: Any = None  # line -> fields
    delim: str | None = None
    fast: bool = False  # clean delimited numbers: np.loadtxt may read whole columns
    note: str = ""  # appended to column-recognition errors (e.g. about the encoding)
    _cache: dict[int, np.ndarray] = field(default_factory=dict)

    def label(self, i: int) -> str:
        return self.labels[i]

    @property
    def n_rows(self) -> int:
        return len(self.labels)

    def column(self, j: int) -> np.ndarray:
        if self.cols is None:
            self.cols = self._split_all()
        return self.cols[j]

    def _split_all(self) -> list[np.ndarray]:
        nh = len(self.names)
        assert self.lines is not None
        if self.fast:
            rows = [line.split(self.delim) for line in self.lines]
        else:
            rows = []
            for k, line in enumerate(self.lines):
                f = self.split_line(line)
                if len(f) > nh:
                    if any(x.strip() for x in f[nh:]):
                        sep = {"\t": "tab", None: "whitespace"}.get(self.delim, repr(self.delim))
                        raise DataError(
                            f"{self.source}, {self.label(k)}: {len(f)} fields but the header "
                            f"has {nh} ({sep}-separated): remove the extra values; if ',' is "
                            "the decimal mark, separate the columns with ';' instead"
                        )
                    f = f[:nh]
                elif len(f) < nh:
                    f = f + [""] * (nh - len(f))
                rows.append(f)
        return [np.array(c, dtype=object) for c in zip(*rows)]

    def check_shape(self) -> None:
        """Raise on rows with extra values (whatever columns are used)."""
        if not self.fast and self.lines is not None:
            self.column(0)

    def floats(self, j: int, rows: np.ndarray | None = None, empty: str = "") -> np.ndarray:
        if self.fast and self.cols is None:
            if j not in self._cache:
                try:
                    self._cache[j] = np.loadtxt(
                        self.lines, delimiter=self.delim, usecols=j, dtype=np.float64,
                        comments=None, ndmin=1,
                    )
                except ValueError:
                    self._cache[j] = None  # type: ignore[assignment]
            full = self._cache[j]
            if full is not None and np.isfinite(full).all():
                return full if rows is None else full[rows]
        col = self.column(j)
        sub = col if rows is None else col[rows]
        if sub.dtype.kind == "c":
            raise DataError(f"{self.source}, column {self.names[j]!r}: holds complex numbers: "
                            "give real values")
        if sub.dtype.kind in "iufb":
            arr = sub.astype(np.float64)
        else:
            try:
                if any(isinstance(v, str) and not _plain_number(v) for v in sub):
                    raise ValueError  # float() would take '1_000' and non-ASCII digits
                arr = np.asarray(sub, dtype=np.float64)
            except (TypeError, ValueError):
                arr = self._slow_floats(j, sub, rows, empty)
        bad = ~np.isfinite(arr)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            i = k if rows is None else int(rows[k])
            raise DataError(
                f"{self.source}, {self.label(i)}, column {self.names[j]!r}: value "
                f"{_short(str(sub[k]).strip())} is not a finite number: repair or delete that row"
            )
        return arr

    def _slow_floats(
        self, j: int, sub: np.ndarray, rows: np.ndarray | None, empty: str = ""
    ) -> np.ndarray:
        out = np.empty(len(sub))
        for k, v in enumerate(sub):
            s = "" if v is None else str(v).strip().strip("\"'").strip()
            try:
                if not _plain_number(s):
                    raise ValueError(s)
                out[k] = float(s)
                continue
            except ValueError:
                pass
            if s.count(",") == 1 and "." not in s and _plain_number(s):
                try:  # decimal comma
                    out[k] = float(s.replace(",", "."))
                    continue
                except ValueError:
                    pass
            i = k if rows is None else int(rows[k])
            if s == "" and empty:
                raise DataError(f"{self.source}, {self.label(i)}, column {self.names[j]!r}: "
                                f"{empty}")
            what = "is empty" if s == "" else f"{_short(s)} is not a number"
            if s == "":
                fix = "fill it in or delete the row"
            elif re.search(r"\d", s):
                fix = "use '.' or ',' as the decimal mark consistently, or fix or delete the row"
            else:
                fix = "delete that row (text among the numbers) or fix it"
            raise DataError(f"{self.source}, {self.label(i)}, column {self.names[j]!r}: {what}: "
                            f"{fix}")
        return out

    def texts(self, j: int) -> np.ndarray:
        return np.array([str(v).strip() for v in self.column(j)], dtype=object)


#: Spreadsheet error cells (#DIV/0!, #N/A, ...) start a data row with '#': not a comment.
_EXCEL_ERROR = re.compile(r"#(DIV/0!|N/A|VALUE!|REF!|NAME\?|NUM!|NULL!|GETTING_DATA)", re.I)

_META_RE = re.compile(r"^#+\s*(?P<key>[A-Za-z_][\w \-]*?)\s*[:=]\s*(?P<val>.*?)\s*$")


_LATIN1_NOTE = (" (the file is not UTF-8 and was read as Latin-1: if the names look garbled, "
                "pass encoding=..., e.g. encoding='gbk')")


def _decode(raw: bytes, src: str, encoding: str | None) -> tuple[str, str]:
    """The text of a file, and a note for messages if it was a guess."""
    if encoding is not None:
        try:
            return raw.decode(encoding), ""
        except (UnicodeDecodeError, LookupError) as exc:
            raise DataError(
                f"{src}: cannot decode as {encoding!r} ({exc}): check encoding="
            ) from None
    if raw.startswith(b"PK\x03\x04") or raw.startswith(b"\xd0\xcf\x11\xe0"):
        raise DataError(
            f"{src}: is a spreadsheet (xlsx/xls), not a CSV file: save it as CSV first"
        )
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            return raw.decode("utf-16"), ""
        except UnicodeDecodeError as exc:
            raise DataError(f"{src}: is not valid UTF-16 text ({exc.reason}): the file looks "
                            "truncated or damaged; save it again as CSV") from None
    if raw.startswith(codecs.BOM_UTF8):
        raw = raw[3:]
    head = raw[:4096]
    if b"\x00" in head:
        if head[1::2].count(0) > 0.9 * len(head[1::2]):
            return raw.decode("utf-16-le", errors="replace"), ""
        if head[0::2].count(0) > 0.9 * len(head[0::2]):
            return raw.decode("utf-16-be", errors="replace"), ""
        raise DataError(f"{src}: is not a text file (binary data): give a CSV text file")
    try:
        return raw.decode("utf-8"), ""
    except UnicodeDecodeError:
        return raw.decode("latin-1"), _LATIN1_NOTE  # never fails; numbers are ASCII anyway


def _short(name: str, width: int = 40) -> str:
    """repr of a column name for a message, cut to ``width`` characters."""
    r = repr(name)
    return r if len(r) <= width else r[: width - 4] + "...'"


def _plain_number(s: str) -> bool:
    """Python's float() also takes '1_000' and non-ASCII digits: a CSV number does not."""
    return "_" not in s and s.isascii()


def _is_number(s: str) -> bool:
    s = s.strip().strip("\"'")
    try:
        float(s)
        return True
    except ValueError:
        return bool(re.fullmatch(r"[+-]?\d*,\d+([eE][+-]?\d+)?", s))


def _read_table(
    path: Any, names: Sequence[str] | None, encoding: str | None
) -> _Table:
    if hasattr(path, "read"):
        src = str(getattr(path, "name", "<stream>"))
        content = path.read()
        text, note = (content, "") if isinstance(content, str) else _decode(content, src,
                                                                              encoding)
    else:
        p = Path(path)
        src = str(path)
        if not p.exists():
            raise DataError(f"{src}: no such file: check the path")
        if p.is_dir():
            raise DataError(
                f"{src}: is a directory, not a CSV file: pass its files, e.g. "
                f"read_csv(sorted(Path({src!r}).glob('*.csv')))"
            )
        try:
            raw = p.read_bytes()
        except OSError as exc:
            raise DataError(f"{src}: cannot be read ({exc.strerror}): check permissions") from None
        text, note = _decode(raw, src, encoding)
    lines = text.splitlines()
    meta: dict[str, str] = {}
    header: str | None = None
    header_no = 0
    forced: str | None = None
    for no, line in enumerate(lines, 1):
        s = line.strip()
        if not s:
            continue
        if s.startswith("#"):
            m = _META_RE.match(s)
            if m:
                meta[_norm_key(m["key"])] = m["val"]
            continue
        m = re.fullmatch(r'"?sep=(.)"?', s, flags=re.IGNORECASE)
        if m:  # Excel's separator hint
            forced = m.group(1)
            continue
        header, header_no = line, no
        break
    if header is None:
        raise DataError(f"{src}: is empty (no header, no data): give a CSV file with a header "
                        "row such as 'strain,stress_MPa' and one row per sample")
    rest = lines[header_no:]
    if all(rest) and not any(map(str.isspace, rest)) and "#" not in text.partition(header)[2]:
        data: list[str] = rest  # the common case, checked at C speed: every line is data
        numbers: Any = np.arange(header_no + 1, header_no + 1 + len(rest))
    else:
        data, numbers = [], []
        for no, line in enumerate(rest, header_no + 1):
            s = line.strip()
            if s and (not s.startswith("#") or _EXCEL_ERROR.match(s)):
                data.append(line)
                numbers.append(no)
    delim = forced or next((d for d in ("\t", ";", ",", "|") if d in header), None)

    def split(line: str) -> list[str]:
        if delim is None:
            return line.split()
        return next(csv.reader([line], delimiter=delim, skipinitialspace=True))

    head = [h.strip() for h in split(header)]
    if all(_is_number(h) for h in head if h):
        if names is None:
            raise DataError(
                f"{src}, line {header_no}: the first line holds numbers, not column names: add "
                "a header row (e.g. 'strain,stress_MPa') or pass names=[...]"
            )
        data = [header, *data]
        numbers = np.concatenate([[header_no], np.asarray(numbers, dtype=np.int64)])
    if names is None and data:
        first = split(data[0])
        if any(f.strip() for f in first) and not any(_is_number(f) for f in first if f.strip()):
            # a second header line with the units ("s", "mm", "[N]"): fold it into the names
            units = [u.strip().strip("[](){}").strip() for u in first] + [""] * len(head)
            head = [f"{h} [{u}]" if u and not re.search(r"[\[\(\{]", h) else h
                    for h, u in zip(head, units)]
            data = data[1:]
            numbers = np.asarray(numbers, dtype=np.int64)[1:]
    if names is not None:
        head = [str(n) for n in names]
    if len(head) < 2:
        raise DataError(
            f"{src}, line {header_no}: the header has one column ({_short(head[0])}): separate the "
            "strain and stress columns by ',', ';' or tabs"
        )
    if not data:
        raise DataError(f"{src}: has a header but no data rows: the curve is empty; add the "
                        "data rows under the header (one row per sample)")
    nh = len(head)
    fast = (delim is not None and '"' not in text and "'" not in text
            and set(map(operator.methodcaller("count", delim), data)) == {nh - 1})
    table = _Table(head, None, _Labels(numbers, "line"), src, meta, lines=data,
                   split_line=split, delim=delim, fast=fast, note=note)
    table.check_shape()
    return table


def _table_from_data(data: Any, names: Sequence[str] | None, source: str | None) -> _Table:
    src = source or type(data).__name__
    if isinstance(data, Mapping):
        head = [str(k) for k in data]
        cols = [np.asarray(v).reshape(-1) for v in data.values()]
        if len({c.size for c in cols}) > 1:
            sizes = ", ".join(f"{h}: {c.size}" for h, c in zip(head, cols))
            raise DataError(f"{src}: columns have different lengths ({sizes}): give one value "
                            "per sample in every column")
        return _Table(head if names is None else list(names), cols,
                      _Labels(np.arange(cols[0].size if cols else 0), "row"), src, {})
    arr_names = None
    if hasattr(data, "to_numpy") and not isinstance(data, np.ndarray):
        arr = np.asarray(data.to_numpy())
        if hasattr(data, "columns"):
            arr_names = [str(c) for c in list(data.columns)]
    else:
        try:
            arr = np.asarray(data)
        except ValueError:
            raise DataError(f"{src}: the rows have different numbers of values: give every row "
                            "the same columns (a value for each)") from None
        if arr.dtype.names:
            head = list(arr.dtype.names)
            return _Table(head if names is None else list(names),
                          [np.asarray(arr[h]).reshape(-1) for h in head],
                          _Labels(np.arange(arr.size), "row"), src, {})
    if arr.ndim != 2:
        raise DataError(f"{src}: expected a 2-D table (rows x columns), got shape {arr.shape}: "
                        "pass np.column_stack([strain, stress]) or a mapping of columns")
    head = list(names) if names is not None else arr_names
    if head is None:
        if arr.shape[1] == 2:
            head = ["strain", "stress"]
        elif arr.shape[0] == 2 and arr.shape[1] > 2:
            raise DataError(f"{src}: got shape {arr.shape} (2 rows): samples must be rows; pass "
                            "np.column_stack([strain, stress])")
        else:
            raise DataError(f"{src}: {arr.shape[1]} unnamed columns: name them with "
                            "names=['time_s', 'strain', 'stress_MPa', ...]")
    if len(head) != arr.shape[1]:
        raise DataError(f"{src}: {len(head)} names for {arr.shape[1]} columns: give one name per "
                        "column")
    return _Table([str(h) for h in head], [arr[:, j] for j in range(arr.shape[1])],
                  _Labels(np.arange(arr.shape[0]), "row"), src, {})


# ================================================================ table -> curves
_META_KEYS = {
    "strain_rate": "rate", "rate": "rate", "nominal_strain_rate": "rate",
    "engineering_strain_rate": "rate", "measure": "measure", "stress_measure": "measure",
    "mode": "mode", "loading_mode": "mode", "name": "name", "curve": "name",
    "weight": "weight", "compression_positive": "compression_positive",
}


def _meta_rate(val: str, src: str) -> float:
    m = re.fullmatch(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*(.*?)\s*",
                     val.replace(",", "."))
    f = None if m is None else _unit_factor("rate", m.group(2))
    if m is None or f is None:
        raise DataError(f"{src}: '# strain_rate: {val}' is not a rate: write e.g. "
                        "'# strain_rate: -100' (1/s) or '# strain_rate: -6000 1/min'")
    return float(m.group(1)) * f


def _meta_bool(val: str, src: str, key: str) -> bool:
    v = val.strip().lower()
    if v in ("1", "true", "yes", "y", "on"):
        return True
    if v in ("0", "false", "no", "n", "off"):
        return False
    raise DataError(f"{src}: '# {key}: {val}': write true or false")


def _curves_from_table(
    table: _Table,
    *,
    rate: float | None,
    measure: str | None,
    mode: str | None,
    compression_positive: bool | None,
    columns: Mapping[str, Any] | None,
    units: Mapping[str, str] | None,
    group_by: str | Sequence[str] | None,
    select: Mapping[str, Any] | None,
    sort: bool,
    n_points: int | None,
    by: str | None,
    name: str | None,
) -> list[Curve]:
    from vhfit.data import Curve  # here: vhfit.data imports this module

    src = table.source
    meta = dict(table.meta)
    known = {_META_KEYS[k]: v for k, v in meta.items() if k in _META_KEYS}
    units = dict(units or {})
    for k, v in meta.items():
        if k.endswith("_unit") and k[:-5] in _UNITS and k[:-5] not in units:
            units[k[:-5]] = v
    if measure is None and "measure" in known:
        measure = known["measure"]
    meas = None if measure is None else _norm_measure(measure, _Where(src, None, None))
    try:
        plan = _resolve_columns(table.names, columns, units, meas, src)
    except DataError as exc:
        if not table.note:
            raise
        raise DataError(f"{exc}{table.note}") from None
    if meas is not None and plan.measure is not None and plan.measure != meas:
        raise DataError(
            f"{src}, column {plan.stress.header!r}: the header says {plan.measure} stress but "
            f"measure={meas!r} was given: drop measure=, or name the right column with "
            "columns={'stress': ...}"
        )
    meas = meas or plan.measure or "engineering"
    if mode is None and "mode" in known:
        mode = known["mode"]
    if compression_positive is None:
        compression_positive = (_meta_bool(known["compression_positive"], src,
                                           "compression_positive")
                                if "compression_positive" in known else False)
    try:
        weight = float(known["weight"]) if "weight" in known else 1.0
    except ValueError:
        raise DataError(f"{src}: '# weight: {known['weight']}' is not a number: write e.g. "
                        "'# weight: 2'") from None
    meta_rate = _meta_rate(known["rate"], src) if "rate" in known else None

    def col_index(h: str) -> int:
        want = str(h).strip().lower()
        for j, nm in enumerate(table.names):
            if _plain(nm) == want:
                return j
        raise DataError(f"{src}: no column {h!r}; the header has "
                        f"{', '.join(map(repr, table.names))}")

    rows = np.arange(table.n_rows)
    for h, want in (select or {}).items():
        j = col_index(h)
        wants = want if isinstance(want, (list, tuple, set)) else [want]
        vals = table.texts(j)[rows]
        ok = np.zeros(rows.size, dtype=bool)
        for w in wants:
            if isinstance(w, (int, float)) and not isinstance(w, bool):
                ok |= np.array([_try_float(v) for v in vals]) == float(w)
            else:
                ok |= np.array([v.lower() == str(w).strip().lower() for v in vals], dtype=bool)
        rows = rows[ok]
        if rows.size == 0:
            raise DataError(f"{src}: select={{{h!r}: {want!r}}} keeps no rows; the column holds "
                            f"{', '.join(sorted(set(map(str, vals)))[:6])}")
    # ---- rate column
    rate_vals = None
    if plan.rate is not None:
        rate_vals = table.floats(
            plan.rate.index, rows,
            empty="the strain rate is missing: fill it in (1/s, negative in compression), or "
                  "ignore the column with columns={'rate': None}",
        ) * plan.factors["rate"]
    # ---- groups
    gcols: list[int] = []
    if group_by is not None:
        gcols = [col_index(g) for g in ([group_by] if isinstance(group_by, str) else group_by)]
    else:
        for j, h in enumerate(table.names):
            toks, _ = _split_header(h)
            if len(toks) == 1 and toks[0] in _GROUP_NAMES:
                if len(set(table.texts(j)[rows])) > 1:
                    gcols.append(j)
    key_cols = [table.texts(j)[rows] for j in gcols]
    use_rate_key = (rate_vals is not None and rate is None
                    and plan.rate.index not in gcols and len(np.unique(rate_vals)) > 1)
    if use_rate_key:
        uniq, first_k, counts = np.unique(rate_vals, return_index=True, return_counts=True)
        if counts.min() < 2:
            k = int(first_k[np.argmin(counts)])
            raise DataError(
                f"{src}, column {plan.rate.header!r}: {uniq.size} different rates in "
                f"{rows.size} rows, {table.label(int(rows[k]))} alone at {rate_vals[k]:g}: if "
                "this is a measured rate channel, not the nominal rate of each test, ignore "
                "it with columns={'rate': None} (and give rate= or a time column); otherwise "
                "give each rate at least 2 rows"
            )
        key_cols.append(np.array([f"{v:.12g}" for v in rate_vals], dtype=object))
    if key_cols:
        combo = np.array(["\x1f".join(map(str, t)) for t in zip(*key_cols)], dtype=object)
        _, first, inv = np.unique(combo, return_index=True, return_inverse=True)
        order = np.argsort(first)
        groups = [np.flatnonzero(inv == g) for g in order]
    else:
        groups = [np.arange(rows.size)]
    if rate is not None and rate_vals is not None and len(np.unique(rate_vals)) > 1:
        raise DataError(
            f"{src}, column {plan.rate.header!r}: holds {len(np.unique(rate_vals))} different "
            f"rates but rate={rate!r} was given: drop rate= to get one curve per rate"
        )
    stem = Path(src).stem if src and not src.startswith("<") else (src or "data")
    out = []
    for g in groups:
        r = rows[g]
        gname_parts = [str(kc[g[0]]) for kc in key_cols[: len(gcols)]]
        if rate_vals is not None:
            gr = rate_vals[g]
            if np.ptp(gr) != 0:
                k = int(np.flatnonzero(gr != gr[0])[0])
                raise DataError(
                    f"{src}, {table.label(int(r[k]))}, column {plan.rate.header!r}: the rate "
                    f"changes from {gr[0]:g} to {gr[k]:g} inside one curve: give each test its "
                    "own rate, or a 'test' column to tell them apart"
                )
        crate = rate if rate is not None else (
            float(rate_vals[g][0]) if rate_vals is not None else meta_rate)
        if use_rate_key:
            gname_parts.append(f"rate {rate_vals[g][0]:g}/s")
        if name is not None:
            cname = name if len(groups) == 1 else f"{name} [{', '.join(gname_parts)}]"
        elif "name" in known and len(groups) == 1:
            cname = known["name"]
        else:
            cname = stem if not gname_parts else f"{stem} [{', '.join(gname_parts)}]"
        where = _Where(cname, src, None)
        if crate is None and plan.time is None:
            raise DataError(
                f"{where()}: no strain rate and no time column: add a 'strain_rate' column, "
                "a '# strain_rate: -100' line (1/s, negative in compression), or pass rate=..."
            )
        d = table.floats(plan.deform.index, r) * plan.factors["deform"]
        if plan.deform.role == "stretch":
            d = d - 1.0
        elif plan.deform.kind == "log":
            d = np.expm1(d)
        s = table.floats(plan.stress.index, r) * plan.factors["stress"]
        t = None
        if plan.time is not None:
            t = table.floats(plan.time.index, r) * plan.factors["time"]
        labels = table.labels[r]
        if sort:
            key = t if t is not None else np.abs(d)
            o = np.argsort(key, kind="stable")
            d, s, labels = d[o], s[o], labels[o]
            t = None if t is None else t[o]
        cmeta = dict(meta)
        if gname_parts:
            cmeta["group"] = ", ".join(gname_parts)
        cmeta["columns"] = {
            "strain": plan.deform.header, "stress": plan.stress.header,
            "time": None if plan.time is None else plan.time.header,
            "rate": None if plan.rate is None else plan.rate.header,
        }
        out.append(Curve(
            d, s, strain_rate=crate, time=t, measure=meas, mode=mode, name=cname,
            weight=weight, n_points=n_points, by=by, compression_positive=compression_positive,
            source=src, rows=labels, metadata=cmeta,
        ))
    return out


def _try_float(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return float("nan")
