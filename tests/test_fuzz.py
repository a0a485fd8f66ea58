"""Hostile-input fuzzing of the readers, of calibrate and of the command line.

Every generated input must end in either a correct result or a ``ValueError``
(``vhfit.DataError``) whose one-line message names the file (or curve), the line or
column where that is known, and what to do. A *misleading success* — curves whose
values differ from what the input meant — fails the test as surely as a crash.

Inputs are generated cheaply with numpy from a seed that Hypothesis draws: each
Hypothesis example checks a batch of ``BATCH`` inputs, so the ``ci`` profile runs
``EXAMPLES x BATCH`` >= 10 000 inputs per reader in seconds, and the ``long`` profile
(``pytest tests/test_fuzz.py --hypothesis-profile=long``) ten times more, with random
seeds. A failure prints the offending input.

Generators:

* valid CSV files with known meaning — separators, decimal commas, BOMs and
  encodings, units, percent strains and stretches, true/engineering stress, rate lines
  and columns, time columns, comments, extra columns, quoting, CRLF — read back and
  compared value by value;
* the same files mutated: cells made NaN/inf/empty/text/units, fields added or
  dropped, rows swapped or duplicated with another stress, columns dropped or renamed,
  decimal commas with a comma separator, single rows, headers only, truncation, byte
  flips, random bytes, invalid UTF-8, NUL bytes, empty files, directories, missing files;
* arrays for :class:`vhfit.Curve` and :func:`vhfit.data.curves_from_arrays`: valid
  ones (compared exactly) and hostile ones (NaN/inf, wrong lengths and shapes, text,
  objects, duplicates, unsorted, single points, stretch <= 0, bad rates and times).
"""

from __future__ import annotations

import codecs
import io
import itertools
import math
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest
from _fuzzing import accepted, refused, write_fresh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import vhfit
from vhfit.calibration import CalibrationWarning
from vhfit.data import Curve, DataError, curves_from_arrays, read_csv

BATCH = 100
#: Hypothesis examples per reader: >= 10 000 inputs in CI, 10x more with the long profile.
EXAMPLES = max(100, settings.default.max_examples * 100 // BATCH)
FUZZ = settings(max_examples=EXAMPLES, suppress_health_check=[HealthCheck.too_slow],
                deadline=None)
SEEDS = st.integers(0, 2**63 - 1)
#: Inputs each reader's fuzz test has checked in this session (read by the budget test).
CHECKED: dict[str, int] = {}

STRESS_UNITS = {"": 1.0, "MPa": 1.0, "kPa": 1e-3, "Pa": 1e-6, "GPa": 1e3,
                "psi": 6.894757293168361e-3, "N/mm2": 1.0, "bar": 0.1}
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "min": 60.0}
def _quiet():
    w = warnings.catch_warnings()
    w.__enter__()
    warnings.simplefilter("ignore")
    return w


# ================================================================ CSV generator
@dataclass
class CsvCase:
    """A CSV file's bytes and what it means (None fields: not checked)."""

    data: bytes
    strain: np.ndarray | None = None
    stress: np.ndarray | None = None
    time: np.ndarray | None = None
    rate: float | None = None
    measure: str = "engineering"
    kwargs: dict = field(default_factory=dict)
    expect: str = "same"  # "same": must read back as meant; "error"; "any"
    line: int | None = None  # 1-based file line an error must name
    what: str = ""

    def text(self) -> str:
        return self.data.decode("utf-8", errors="replace")


def _fmt(x: float, style: int) -> str:
    if style == 0:
        return repr(float(x))
    if style == 1:
        return f"{x:.6e}"
    if style == 2:
        return f"{x:.10g}"
    return f"{x:+.8f}"


def valid_csv(rng: np.random.Generator) -> CsvCase:
    """A valid file with known meaning (compression or tension, rate or time)."""
    n = int(rng.choice([2, 3, 5, 10, 25, 60]))
    tension = rng.random() < 0.4
    sgn = 1.0 if tension else -1.0
    top = rng.uniform(0.05, 0.9)
    start = 0.0 if rng.random() < 0.5 else top / (2 * n)
    eps = sgn * np.linspace(start, top, n)
    stiff = 10 ** rng.uniform(-3, 2)
    sig = sgn * stiff * np.abs(eps) * (1 + rng.uniform(0, 0.5, n))
    sig[eps == 0] = 0.0
    style = int(rng.integers(4))
    sep = str(rng.choice([",", ";", "\t", " ", "|"]))
    dec_comma = sep in (";", "\t") and rng.random() < 0.4
    unit = str(rng.choice(list(STRESS_UNITS)))
    f_stress = STRESS_UNITS[unit]
    measure = "true" if rng.random() < 0.3 else "engineering"
    s_name = {"true": str(rng.choice(["true_stress", "cauchy_stress"])),
              "engineering": str(rng.choice(["stress", "nominal_stress",
                                             "engineering_stress"]))}[measure]
    s_head = s_name + (f"_{unit}" if unit and rng.random() < 0.5 else
                       f" [{unit}]" if unit else "")
    kind = str(rng.choice(["strain", "strain_%", "stretch"]))
    if kind == "strain":
        e_vals, e_head = eps, str(rng.choice(["strain", "engineering_strain", "strain [-]",
                                              "Strain (mm/mm)"]))
    elif kind == "strain_%":
        e_vals, e_head = 100 * eps, str(rng.choice(["strain_%", "strain [%]"]))
    else:
        e_vals, e_head = 1 + eps, str(rng.choice(["stretch", "lambda"]))
    s_vals = sig / f_stress
    cols = [(e_head, e_vals), (s_head, s_vals)]
    meta = []
    kwargs: dict = {}
    rate = sgn * 10 ** rng.uniform(-3, 3)
    timed = rng.random() < 0.3
    if timed:
        tu = str(rng.choice(list(TIME_UNITS)))
        dt = np.abs(np.diff(np.r_[0.0, eps])) / abs(rate)
        t_true = np.cumsum(np.where(dt > 0, dt, 1e-3))
        cols.append((f"time_{tu}", t_true / TIME_UNITS[tu]))
        rate = None
    else:
        how = int(rng.integers(3))
        if how == 0:
            meta.append(f"# strain_rate: {rate!r}")
        elif how == 1:
            cols.append(("strain_rate", np.full(n, rate)))
        else:
            kwargs["rate"] = rate
    if rng.random() < 0.3:  # an extra column the reader must ignore, or a temperature
        extra = str(rng.choice(["force_N", "displacement_mm", "temperature_C"]))
        # a test is at one temperature: its readings drift by less than a degree
        vals = (rng.uniform(-100, 100) + rng.uniform(0, 1, n) if extra == "temperature_C"
                else rng.uniform(-100, 100, n))
        cols.insert(int(rng.integers(len(cols) + 1)), (extra, vals))
    quote = sep in (",", ";", "\t") and rng.random() < 0.15
    lines = [f"# {w}" for w in rng.choice(["specimen A", "machine: Instron", "operator"],
                                          size=int(rng.integers(0, 3)))]
    lines += meta
    lines.append(sep.join(c[0] if sep != " " else c[0].replace(" ", "") for c in cols))
    if sep == " " and any(" " in c[0] for c in cols):
        # space-separated headers cannot hold spaces: use the suffix form of units
        lines[-1] = sep.join(h.replace(" [", "_").replace("]", "").replace(" (", "_")
                             .replace(")", "") for h, _ in cols)
    texts = [[_fmt(v, style) for v in vals] for _, vals in cols]
    meant = {j: np.array([float(t) for t in col]) for j, col in enumerate(texts)}
    heads = [h for h, _ in cols]
    if "strain_rate" in heads:  # the rate as written
        rate = float(meant[heads.index("strain_rate")][0])
    for i in range(n):
        cells = [texts[j][i] for j in range(len(cols))]
        if dec_comma:
            cells = [c.replace(".", ",") for c in cells]
        if quote:
            cells = [f'"{c}"' for c in cells]
        lines.append(sep.join(cells))
    header_line = len(lines) - n  # 1-based line number of the header
    # what the file means, from the numbers as written
    e_idx = next(j for j, (h, _) in enumerate(cols) if h == e_head)
    s_idx = next(j for j, (h, _) in enumerate(cols) if h == s_head)
    e_meant = meant[e_idx]
    strain = {"strain": e_meant, "strain_%": e_meant / 100, "stretch": e_meant - 1}[kind]
    stress = meant[s_idx] * f_stress
    time = None
    if timed:
        t_idx = next(j for j, (h, _) in enumerate(cols) if h.startswith("time_"))
        time = meant[t_idx] * TIME_UNITS[cols[t_idx][0][5:]]
    eol = "\r\n" if rng.random() < 0.2 else "\n"
    text = eol.join(lines) + (eol if rng.random() < 0.9 else "")
    enc = str(rng.choice(["utf-8", "utf-8-sig", "utf-16", "latin-1"], p=[0.7, 0.1, 0.1, 0.1]))
    case = CsvCase(text.encode(enc), strain, stress, time, rate, measure, kwargs)
    case.header_line = header_line  # type: ignore[attr-defined]
    case.n_rows = n  # type: ignore[attr-defined]
    case.sep = sep  # type: ignore[attr-defined]
    case.cols = [h for h, _ in cols]  # type: ignore[attr-defined]
    case.e_idx, case.s_idx = e_idx, s_idx  # type: ignore[attr-defined]
    heads = [h for h, _ in cols]
    case.temperature = (float(np.mean(meant[heads.index("temperature_C")]))  # type: ignore
                        if "temperature_C" in heads else None)
    case.what = f"valid ({enc}, sep {sep!r}, {kind}, {unit or 'MPa'}, {measure})"
    return case


BAD_CELLS = ["nan", "NaN", "inf", "-inf", "", "abc", "1e400", "--1", "1.2.3", "12 kPa",
             "5%", "0x1p3", "1_0", "½", "1e", "e5", ".", "-", "N/A", "null", "#DIV/0!", "∞",
             "١٢", "#N/A", "1 2", "+-3"]


def _lines(case: CsvCase) -> tuple[list[str], str, str]:
    """Decoded lines of a valid case, its encoding and its line ending."""
    raw = case.data
    for enc, bom in (("utf-16", codecs.BOM_UTF16_LE), ("utf-16", codecs.BOM_UTF16_BE),
                     ("utf-8-sig", codecs.BOM_UTF8)):
        if raw.startswith(bom):
            text = raw.decode(enc)
            break
    else:
        try:
            text, enc = raw.decode("utf-8"), "utf-8"
        except UnicodeDecodeError:
            text, enc = raw.decode("latin-1"), "latin-1"
    eol = "\r\n" if "\r\n" in text else "\n"
    return text.split(eol), enc, eol


def _join(lines, enc, eol) -> bytes:
    return eol.join(lines).encode(enc, errors="replace")


def hostile_csv(rng: np.random.Generator) -> CsvCase:
    """A valid file mutated in one way, with the outcome the mutation calls for."""
    base = valid_csv(rng)
    lines, enc, eol = _lines(base)
    h = base.header_line  # type: ignore[attr-defined]
    n = base.n_rows  # type: ignore[attr-defined]
    sep = base.sep  # type: ignore[attr-defined]
    first = h  # index in `lines` of the first data row (0-based) = header line number
    kind = int(rng.integers(22))
    c = CsvCase(base.data, base.strain, base.stress, base.time, base.rate, base.measure,
                dict(base.kwargs))

    def cell_row(i):
        return lines[first + i].split(sep) if sep != " " else lines[first + i].split()

    if kind == 0:  # a bad cell in the strain or stress column
        i = int(rng.integers(n))
        j = base.e_idx if rng.random() < 0.5 else base.s_idx  # type: ignore[attr-defined]
        bad = str(rng.choice(BAD_CELLS))
        cells = cell_row(i)
        cells[j] = bad if sep not in bad and bad else "abc"
        lines[first + i] = sep.join(cells)
        c.expect, c.line, c.what = "error", first + i + 1, f"bad cell {cells[j]!r}"
    elif kind == 1:  # a field too few or too many
        i = int(rng.integers(n))
        cells = cell_row(i)
        cells = cells[:-1] if rng.random() < 0.5 or len(cells) < 2 else cells + ["7"]
        lines[first + i] = sep.join(cells)
        c.expect, c.line, c.what = "error", first + i + 1, "wrong number of fields"
        if len(cells) and base.cols[-1] not in (  # type: ignore[attr-defined]
                base.cols[base.e_idx], base.cols[base.s_idx]) \
                and len(cells) < len(base.cols):  # type: ignore[attr-defined]
            c.expect, c.line = "any", None  # dropped an ignored last column: may be fine
    elif kind == 2 and n >= 2:  # two rows swapped: out of order
        i = int(rng.integers(n - 1))
        lines[first + i], lines[first + i + 1] = lines[first + i + 1], lines[first + i]
        c.expect, c.what = "error", "rows swapped"
    elif kind == 3:  # a row repeated with another stress: two tests mixed up
        i = int(rng.integers(n))
        cells = cell_row(i)
        j = base.s_idx  # type: ignore[attr-defined]
        cells[j] = cells[j].replace("1", "9").replace("2", "8") if any(
            d in cells[j] for d in "12") else "123"
        lines.insert(first + n, sep.join(cells))
        c.expect, c.what = "error", "repeated row, other stress"
        if base.time is not None:  # same time and strain: documented to be averaged
            c.expect = "any"
    elif kind == 4:  # one data row only
        lines = lines[: first + 1]
        c.expect, c.what = "error", "single row"
    elif kind == 5:  # header only / nothing at all / blank
        lines = [lines[: first][-1]] if rng.random() < 0.5 else (
            [""] if rng.random() < 0.5 else ["   ", "", "\t"])
        c.expect, c.what = "error", "no data"
    elif kind == 6:  # the stress column (or the strain column) removed
        j = base.s_idx if rng.random() < 0.5 else base.e_idx  # type: ignore[attr-defined]
        for k in range(first - 1, first + n):
            cells = lines[k].split(sep) if sep != " " else lines[k].split()
            del cells[j]
            lines[k] = sep.join(cells)
        c.expect, c.what = "error", "column removed"
        others = [h for k, h in enumerate(base.cols) if k != j]  # type: ignore[attr-defined]
        if any(re.search(r"stress|strain|stretch|lambda", x, re.I) for x in others
               if x != "strain_rate"):
            c.expect = "any"  # another column may legitimately stand in (e.g. rate only)
    elif kind == 7:  # an unknown stress unit
        cells = lines[first - 1].split(sep) if sep != " " else lines[first - 1].split()
        cells[base.s_idx] = "stress_furlongs"  # type: ignore[attr-defined]
        lines[first - 1] = sep.join(cells)
        c.expect, c.what = "error", "unknown unit"
    elif kind == 8 and sep == "," and n >= 2:  # decimal commas with a comma separator
        had_point = any("." in lines[k] for k in range(first, first + n))
        for k in range(first, first + n):
            lines[k] = ",".join(x.replace(".", ",") for x in lines[k].split(","))
        quoted = lines[first].startswith('"')  # "0,5","1,2" is unambiguous
        c.expect = "error" if had_point and not quoted else "same"
        c.what = "decimal comma with comma separator"
    elif kind == 9:  # truncated anywhere
        raw = _join(lines, enc, eol)
        c.data = raw[: int(rng.integers(len(raw) + 1))]
        c.expect, c.what = "any", "truncated"
        return c
    elif kind == 10:  # random byte flips
        raw = bytearray(_join(lines, enc, eol))
        for _ in range(int(rng.integers(1, 4))):
            raw[int(rng.integers(len(raw)))] = int(rng.integers(256))
        c.data, c.expect, c.what = bytes(raw), "any", "byte flips"
        return c
    elif kind == 11:  # random bytes
        c.data = rng.bytes(int(rng.integers(0, 400)))
        c.expect, c.what = "error", "random bytes"
        return c
    elif kind == 12:  # a NUL byte or invalid UTF-8 inside a strain or stress cell
        i = int(rng.integers(n))
        j = base.e_idx if rng.random() < 0.5 else base.s_idx  # type: ignore[attr-defined]
        cells = cell_row(i)
        pos = int(rng.integers(1, max(2, len(cells[j]))))
        cells[j] = cells[j][:pos] + "\ue000" + cells[j][pos:]
        lines[first + i] = sep.join(cells)
        bad = b"\x00" if rng.random() < 0.5 else b"\xff\xfe\xfd"
        if enc not in ("utf-8", "utf-8-sig"):  # only where such bytes are foreign
            c.what = "unchanged (utf-16 or latin-1 file)"
            return c
        raw = _join(lines, enc, eol)
        c.data = raw.replace("\ue000".encode("utf-8"), bad)
        c.expect, c.what = "error", f"{bad!r} inside a number"
        c.line = first + i + 1 if bad != b"\x00" else None
        return c
    elif kind == 13:  # strain beyond -1 (stretch <= 0)
        i = int(rng.integers(n))
        cells = cell_row(i)
        head = base.cols[base.e_idx]  # type: ignore[attr-defined]
        val = {"%": "-150", "stretch": "-0.2", "lambda": "0"}.get(
            "%" if "%" in head else head, "-1.5")
        cells[base.e_idx] = val  # type: ignore[attr-defined]
        lines[first + i] = sep.join(cells)
        c.expect, c.what = "error", "stretch <= 0"
    elif kind == 14 and base.rate is not None and base.kwargs == {}:  # a bad rate
        bad = str(rng.choice(["0", "nan", "inf", "fast", "", "-1e400"]))
        heads = base.cols  # type: ignore[attr-defined]
        if "strain_rate" in heads:  # the rate column
            j = heads.index("strain_rate")
            for k in range(first, first + n):
                cells = cell_row(k - first)
                cells[j] = bad or "x"
                lines[k] = sep.join(cells)
        else:
            drop = [k for k, x in enumerate(lines[:first]) if x.startswith("# strain_rate")]
            lines[drop[0]] = f"# strain_rate: {bad}"
        c.expect, c.what = "error", f"bad rate {bad!r}"
    elif kind == 15:  # the header removed
        lines = [x for k, x in enumerate(lines) if k != first - 1]
        c.expect, c.what = "error", "no header"
    elif kind == 16 and base.time is not None and n >= 3:  # time running backwards
        t_idx = next(j for j, hh in enumerate(base.cols) if hh.startswith("time_"))  # type: ignore[attr-defined]
        i = int(rng.integers(1, n))
        cells = cell_row(i)
        cells[t_idx] = "-5"
        lines[first + i] = sep.join(cells)
        c.expect, c.what = "error", "time backwards"
    elif kind in (17, 18):  # harmless: BOM, blank lines, comments, trailing spaces
        k = int(rng.integers(first, first + n + 1))
        choice = int(rng.integers(4))
        if choice == 0:
            lines.insert(k, "")
        elif choice == 1:
            lines.insert(k, "# a comment")
        elif choice == 2:
            lines = [x + "  " if sep not in (" ", "\t") else x for x in lines]
        else:
            lines.insert(0, "")
        c.what = "harmless edit"
    elif kind == 19:  # a mixed-up unit in one cell (e.g. a value typed in kPa)
        i = int(rng.integers(n))
        cells = cell_row(i)
        j = base.s_idx  # type: ignore[attr-defined]
        cells[j] = cells[j] + str(rng.choice(["kPa", " MPa", "Pa", "%"]))
        lines[first + i] = sep.join(cells)
        c.expect, c.line, c.what = "error", first + i + 1, "unit inside a cell"
    elif kind == 20:  # a huge number of columns in the header
        lines[first - 1] = lines[first - 1] + (sep or ",") + (sep or ",").join(
            f"x{k}" for k in range(2000))
        c.expect, c.what = "any", "2000 extra header columns"
    else:  # rows shuffled
        rows = lines[first: first + n]
        perm = rng.permutation(n)
        lines[first: first + n] = [rows[k] for k in perm]
        c.expect = "same" if (perm == np.arange(n)).all() else "error"
        c.what = "rows shuffled"
    c.data = _join(lines, enc, eol)
    return c


def check_csv(case: CsvCase, path: Path) -> str:
    """Read ``case`` from ``path``; assert the outcome; return 'ok' or 'error'."""
    write_fresh(path, case.data)
    w = _quiet()
    try:
        curves = read_csv(path, **case.kwargs)
    except ValueError as exc:  # DataError is a ValueError
        return refused(case.expect, exc, names=path.name, line=case.line, limit=600)
    finally:
        w.__exit__(None, None, None)
    accepted(case.expect, f"{len(curves)} curve(s) read")
    assert len(curves) >= 1
    for cv in curves:
        assert np.all(np.isfinite(cv.strain)) and np.all(np.isfinite(cv.stress))
        assert np.all(cv.strain > -1)
    if case.expect == "same":
        [cv] = curves
        np.testing.assert_allclose(cv.strain, case.strain, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(cv.stress, case.stress, rtol=1e-12, atol=0)
        assert cv.measure == case.measure
        if case.rate is not None:
            assert cv.strain_rate == pytest.approx(case.rate, rel=1e-12)
        if case.time is not None:
            np.testing.assert_allclose(cv.time, case.time, rtol=1e-12)
        T = getattr(case, "temperature", None)  # set by the generator of valid files
        if T is not None:  # a temperature column: the mean of its readings
            assert cv.temperature == pytest.approx(T, rel=1e-12, abs=1e-12)
    return "ok"


def _explain(case: CsvCase) -> str:
    return f"[{case.what}; expect {case.expect}] input:\n{case.data[:3000]!r}"


def run_csv_batch(seed: int, tmp: Path, make) -> dict:
    rng = np.random.default_rng(seed)
    counts = {"ok": 0, "error": 0}
    path = tmp / "fuzz.csv"
    for _ in range(BATCH):
        case = make(rng)
        try:
            counts[check_csv(case, path)] += 1
        except AssertionError as exc:
            raise AssertionError(f"{exc}\n{_explain(case)}") from None
        except Exception as exc:  # a crash: anything but a ValueError
            raise AssertionError(f"crash {type(exc).__name__}: {exc}\n{_explain(case)}") from exc
    CHECKED["read_csv"] = CHECKED.get("read_csv", 0) + sum(counts.values())
    return counts


def _mix(rng):
    return valid_csv(rng) if rng.random() < 0.35 else hostile_csv(rng)


@FUZZ
@given(SEEDS)
def test_read_csv_fuzz(tmp_path_factory, seed):
    tmp = tmp_path_factory.getbasetemp() / "fuzz-read-csv"
    tmp.mkdir(exist_ok=True)
    counts = run_csv_batch(seed, tmp, _mix)
    assert counts["ok"] > 0 and counts["error"] > 0  # the mix exercises both outcomes


def test_read_csv_directories_missing_files_and_streams(tmp_path):
    for p in (tmp_path, tmp_path / "missing.csv"):
        with pytest.raises(DataError) as exc:
            read_csv(p)
        assert str(p) in str(exc.value) and "\n" not in str(exc.value)
    good = valid_csv(np.random.default_rng(1))
    good_text = good.data.decode("utf-16" if good.data[:2] in (b"\xff\xfe", b"\xfe\xff")
                                 else "utf-8-sig", errors="replace")
    for stream in (io.StringIO(good_text), io.BytesIO(good.data)):
        [c] = read_csv(stream, **good.kwargs)
        np.testing.assert_allclose(c.stress, good.stress, rtol=1e-12)
    with pytest.raises(DataError, match="<stream>"):
        read_csv(io.StringIO("strain,stress\n0.1,abc\n0.2,2\n"), rate=1.0)


# ============================================================== array generator
@dataclass
class ArrayCase:
    kwargs: dict
    expect: str  # "same", "error" or "any"
    what: str
    strain: np.ndarray | None = None
    stress: np.ndarray | None = None


def _monotone(rng, n, sgn):
    top = rng.uniform(0.01, 0.95)
    eps = sgn * np.sort(rng.uniform(0, top, n))
    eps = np.unique(eps) if sgn > 0 else -np.unique(-eps)
    eps = eps if sgn > 0 else np.sort(eps)[::-1]
    return eps


def array_case(rng: np.random.Generator) -> ArrayCase:
    """Arguments for Curve: valid (with meaning) or hostile."""
    n = int(rng.choice([2, 3, 10, 50, 1000]))
    sgn = -1.0 if rng.random() < 0.6 else 1.0
    eps = _monotone(rng, n, sgn)
    while eps.size < 2 or np.any(eps == 0) and eps.size < 3:
        eps = _monotone(rng, n, sgn)
    sig = sgn * np.abs(eps) * 10 ** rng.uniform(-6, 6) * (1 + rng.uniform(0, 1, eps.size))
    rate = sgn * 10 ** rng.uniform(-6, 6)
    kw = dict(strain=eps, stress=sig, strain_rate=rate)
    if rng.random() < 0.3:  # a measured history instead of a rate
        t = np.cumsum(rng.uniform(1e-3, 1.0, eps.size)) * 10 ** rng.uniform(-3, 3)
        kw = dict(strain=eps, stress=sig, time=t)
    if rng.random() < 0.3:
        kw["measure"] = str(rng.choice(["engineering", "true", "nominal", "cauchy"]))
    if rng.random() < 0.4:
        return ArrayCase(kw, "same", "valid", eps, sig)
    kind = int(rng.integers(18))
    bad = dict(kw)
    k = int(rng.integers(eps.size))
    if kind == 0:
        arr = np.array(eps, dtype=float)
        arr[k] = rng.choice([np.nan, np.inf, -np.inf])
        bad["strain"] = arr
        what = "non-finite strain"
    elif kind == 1:
        arr = np.array(sig, dtype=float)
        arr[k] = rng.choice([np.nan, np.inf, -np.inf])
        bad["stress"] = arr
        what = "non-finite stress"
    elif kind == 2:
        bad["stress"] = sig[:-1]
        what = "lengths differ"
    elif kind == 3:
        bad["strain"] = np.column_stack([eps, eps])
        what = "2-D strain"
    elif kind == 4:
        bad["strain"] = [str(x) for x in eps[:-1]] + ["abc"]
        what = "text in strain"
    elif kind == 5:
        bad["strain"], bad["stress"] = eps[:1], sig[:1]
        what = "single point"
    elif kind == 6:
        bad["strain"], bad["stress"] = np.array([]), np.array([])
        what = "empty"
    elif kind == 7:
        arr = np.array(eps)
        arr[k] = -1.0 - rng.uniform(0, 1)
        bad["strain"] = arr
        what = "stretch <= 0"
    elif kind == 8:
        bad.pop("time", None)
        opts = [0.0, np.nan, np.inf, "fast", [1.0, 2.0]]  # None: an equilibrium curve
        bad["strain_rate"] = opts[int(rng.integers(len(opts)))]
        what = f"bad rate {bad['strain_rate']!r}"
    elif kind == 9 and eps.size >= 3:
        bad["strain"] = eps[rng.permutation(eps.size)]
        if (bad["strain"] == eps).all():
            bad["strain"] = eps[::-1]
        bad.pop("time", None)
        bad["strain_rate"] = rate
        what = "unsorted at constant rate"
    elif kind == 10:
        arr = np.array(eps)
        s2 = np.array(sig)
        arr = np.insert(arr, k, arr[k])
        s2 = np.insert(s2, k, s2[k] * 2 + 1)
        bad["strain"], bad["stress"] = arr, s2
        bad.pop("time", None)
        bad["strain_rate"] = rate
        what = "duplicate strain, other stress"
    elif kind == 11:
        bad["strain"] = np.array(eps, dtype=object)
        bad["strain"][k] = None
        what = "None in strain"
    elif kind == 12:
        bad["stress"] = sig.astype(complex) + 1j
        what = "complex stress"
    elif kind == 13 and "time" in kw:
        t = np.array(kw["time"])
        t[k] = -1.0 if k else t[-1] + 1
        bad["time"] = t
        what = "time out of order"
    elif kind == 14:
        bad["strain"] = None
        what = "strain None"
    elif kind == 15:
        bad["measure"] = ["pressure", "", 3][int(rng.integers(3))]
        what = "bad measure"
    elif kind == 16:
        bad["weight"] = [-1.0, np.nan, "heavy", np.inf][int(rng.integers(4))]
        what = "bad weight"
    else:
        bad["stress"] = {"a": 1}
        what = "dict stress"
    return ArrayCase(bad, "error", what)


def check_curve(case: ArrayCase) -> str:
    w = _quiet()
    try:
        c = Curve(**case.kwargs, name="fuzzed")
    except ValueError as exc:
        return refused(case.expect, exc, names="fuzzed", limit=600)
    finally:
        w.__exit__(None, None, None)
    accepted(case.expect, c)
    if case.expect == "same":
        np.testing.assert_array_equal(c.strain, np.asarray(case.strain, dtype=float))
        np.testing.assert_array_equal(c.stress, np.asarray(case.stress, dtype=float))
        if "strain_rate" in case.kwargs:
            assert c.strain_rate == case.kwargs["strain_rate"]
    assert np.all(np.isfinite(c.strain)) and np.all(np.isfinite(c.target_stress))
    return "ok"


def _run_batch(seed, make, check, explain):
    name = check.__name__.removeprefix("check_")
    rng = np.random.default_rng(seed)
    counts = {"ok": 0, "error": 0}
    for _ in range(BATCH):
        case = make(rng)
        try:
            counts[check(case)] += 1
        except AssertionError as exc:
            raise AssertionError(f"{exc}\n{explain(case)}") from None
        except Exception as exc:
            raise AssertionError(f"crash {type(exc).__name__}: {exc}\n{explain(case)}") from exc
    CHECKED[name] = CHECKED.get(name, 0) + sum(counts.values())
    return counts


def _explain_array(case: ArrayCase) -> str:
    with np.printoptions(threshold=50):
        return f"[{case.what}; expect {case.expect}] kwargs: {case.kwargs!r}"


@FUZZ
@given(SEEDS)
def test_curve_fuzz(seed):
    counts = _run_batch(seed, array_case, check_curve, _explain_array)
    assert counts["ok"] > 0 and counts["error"] > 0


# ------------------------------------------------------------ curves_from_arrays
def table_case(rng: np.random.Generator) -> ArrayCase:
    """A table (dict, 2-D array with names, list of rows, DataFrame-like) for curves_from_arrays."""
    base = array_case(rng)
    kw = base.kwargs
    if base.expect == "error" and not all(k in kw for k in ("strain", "stress")):
        return ArrayCase({"data": {"stress": [1, 2]}, "rate": 1.0}, "error", "no strain")
    strain, stress = kw.get("strain"), kw.get("stress")
    cols = {"strain": strain, "stress_MPa": stress}
    if "time" in kw:
        cols["time_s"] = kw["time"]
    rate = kw.get("strain_rate")
    form = int(rng.integers(4))
    tidy = all(isinstance(v, np.ndarray) and v.ndim == 1 for v in cols.values())
    same_len = tidy and len({len(v) for v in cols.values()}) == 1
    if form == 1 and same_len:
        data, names = np.column_stack(list(cols.values())), list(cols)
    elif form == 2 and tidy:  # rows; a short column leaves its rows short (ragged)
        data = [[x for x in r if x is not None]
                for r in itertools.zip_longest(*cols.values(), fillvalue=None)]
        names = list(cols)
    elif form == 3 and same_len:
        data, names = _FakeFrame(cols), None
    else:
        data, names = cols, None
    args = {"data": data, "names": names, "name": "fuzzed"}
    if rate is not None or "strain_rate" in kw:
        args["rate"] = rate
    if "measure" in kw:
        args["measure"] = kw["measure"]
    expect = "same" if base.what == "bad weight" else base.expect  # not passed here
    if expect == "same":
        strain, stress = np.asarray(strain, dtype=float), np.asarray(stress, dtype=float)
    return ArrayCase(args, expect, f"{base.what} as {type(data).__name__}", strain, stress)


class _FakeFrame:
    """The two attributes of a DataFrame that curves_from_arrays relies on."""

    def __init__(self, cols: dict):
        self.columns = list(cols)
        self._cols = cols

    def to_numpy(self):
        return np.column_stack(list(self._cols.values()))

    def __repr__(self):
        return f"_FakeFrame({self._cols!r})"


def check_table(case: ArrayCase) -> str:
    w = _quiet()
    try:
        curves = curves_from_arrays(**case.kwargs)
    except ValueError as exc:
        return refused(case.expect, exc, limit=600)
    finally:
        w.__exit__(None, None, None)
    accepted(case.expect, curves)
    if case.expect == "same":
        [c] = curves
        np.testing.assert_array_equal(c.strain, np.asarray(case.strain, dtype=float))
        np.testing.assert_array_equal(c.stress, np.asarray(case.stress, dtype=float))
    return "ok"


@FUZZ
@given(SEEDS)
def test_curves_from_arrays_fuzz(seed):
    counts = _run_batch(seed, table_case, check_table, _explain_array)
    assert counts["ok"] > 0 and counts["error"] > 0


# ================================================================== calibrate
def _calibrate_input(rng: np.random.Generator):
    """Curves at extreme scales (stress 1e-6..1e6 MPa, rates 1e-6..1e6 1/s, 2..1000 samples)."""
    n_c = int(rng.integers(1, 4))
    curves = []
    for _ in range(n_c):
        case = array_case(rng)
        while case.expect != "same":
            case = array_case(rng)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            curves.append(Curve(**case.kwargs))
    if rng.random() < 0.15:  # zero stress everywhere on one curve
        c = curves[0]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            curves[0] = Curve(strain=c.strain, stress=np.zeros(c.strain.size),
                              strain_rate=c.strain_rate)
        return curves, "any"
    return curves, "ok"


@settings(max_examples=max(30, settings.default.max_examples * 2), deadline=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(SEEDS)
def test_calibrate_fuzz(seed):
    rng = np.random.default_rng(seed)
    curves, expect = _calibrate_input(rng)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            cal = vhfit.calibrate(curves, n_prony=int(rng.integers(0, 3)), seed=0, maxiter=3,
                                  popsize=8, polish=bool(rng.random() < 0.3),
                                  uncertainty=False)
        except ValueError as exc:
            assert expect != "ok", f"{type(exc).__name__}: {exc}\ncurves: {curves!r}"
            assert "\n" not in str(exc)
            return
    assert not math.isnan(cal.rmsape)
    if expect == "ok":
        assert np.isfinite(cal.rmsape), f"infinite error on {curves!r}"
        assert all(np.isfinite(v) for v in cal.params.values())
    assert all(not np.isnan(e) for e in cal.per_curve_rmsape)


def test_calibrate_without_curves_is_a_value_error():
    with pytest.raises(ValueError, match="at least one curve"):
        vhfit.calibrate([])


# (a str or path is a CSV file to read: calibrate accepts those)
@pytest.mark.parametrize("item", [None, np.zeros((10, 2)), {"strain": [0, 1]}],
                         ids=["None", "array", "dict"])
@pytest.mark.parametrize("n_prony", [0, 1])
def test_calibrate_refuses_what_is_not_a_curve(item, n_prony):
    with pytest.raises((TypeError, ValueError), match=r"curves\[0\]"):
        vhfit.calibrate([item], n_prony=n_prony)


# ======================================================================== CLI
def test_cli_bad_input_is_exit_code_2_and_one_line(tmp_path, capsys):
    from vhfit.cli import main

    rng = np.random.default_rng(2026)
    cases = [("directory", tmp_path), ("missing", tmp_path / "missing.csv")]
    while len(cases) < max(60, settings.default.max_examples * 3):
        case = hostile_csv(rng)
        # a rate given only as read_csv's argument is not in the file: for the command
        # line that file is an equilibrium curve, and its "error" may be none there
        if case.expect != "error" or "rate" in case.kwargs:
            continue
        p = tmp_path / f"input{len(cases)}.csv"
        p.write_bytes(case.data)
        cases.append((case.what, p))
    for what, path in cases:
        capsys.readouterr()
        code = main(["fit", str(path), "--out", str(tmp_path / "out" / path.name),
                     "--maxiter", "1", "--no-plot", "-q"])
        err = capsys.readouterr().err
        lines = [x for x in err.splitlines() if x.strip() and not x.startswith("warning:")]
        assert code == 2, f"{what}: exit code {code}, stderr {err!r}"
        assert len(lines) == 1 and lines[0].startswith("vhfit: error:"), f"{what}: {err!r}"
        assert "Traceback" not in err
        assert path.name in lines[0], f"{what}: the message does not name the file: {err!r}"


def test_fuzz_budget_reaches_ten_thousand_inputs_per_reader(tmp_path_factory):
    """Counts the inputs each reader's fuzz test really checked (runs it if it has not run).

    This test comes after the fuzz tests in the file, so in a whole run it only reads the
    counts; it fails if a profile, a ``settings`` or a batch loop lowers the budget.
    """
    runs = {"read_csv": lambda: test_read_csv_fuzz(tmp_path_factory=tmp_path_factory),
            "curve": test_curve_fuzz, "table": test_curves_from_arrays_fuzz}
    for reader, run in runs.items():
        if reader not in CHECKED:
            run()
        assert CHECKED[reader] >= 10_000, f"{reader}: only {CHECKED[reader]} inputs checked"


@pytest.fixture(autouse=True)
def _no_calibration_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CalibrationWarning)
        yield
