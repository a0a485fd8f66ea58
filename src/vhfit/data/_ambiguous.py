"""Input ambiguities of a table, settled by a stated rule or refused with the fix.

Two kinds: several columns that could hold the same quantity (``stress_kPa`` beside
``stress_MPa``, ``strain`` beside ``stretch``, ``frequency_Hz`` beside ``omega_rad/s``),
and a text column whose values differ inside what would become one curve (a ``region``
column naming four specimens). ``_settle`` compares candidate columns value by value after
unit conversion: they agree when every pair of values differs by no more than twice the
rounding of the digits written (half a unit in each value's last digit, carried through
the conversion; twice, because a column computed from another's already rounded values
carries that rounding too — a lab's true strain from its rounded engineering strain),
and then the column written with the finest digits is read — nothing
the other holds is lost; otherwise a one-line ``DataError`` names both columns and how to
choose one. ``_check_text_columns`` refuses a varying label column (text, or numbers in
few contiguous blocks) that no option accounts for, naming ``group_by=`` / ``select=`` and
their command-line flags, and returns the columns the fit does not read (numeric channels
with ``nan``/``inf``/empty cells among them). ``_select_rows``
(``select=``) lives here so that curves and moduli tables share it.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from vhfit._words import setting
from vhfit.data._errors import DataError, _short
from vhfit.data._table import _Table

_NUMBER = re.compile(r"^[+-]?(\d*)(?:[.,](\d*))?(?:[eE]([+-]?\d+))?$")
#: Agreement of numbers that carry no rounding of their own (arrays): relative slack.
_FLOAT_RTOL = 1e-12
#: Columns agree within this many times the sum of their written roundings.
ROUNDINGS = 2.0
#: How many values of a varying text column a message lists.
_SHOWN = 4


@dataclass
class _Cand:
    """A column that could hold a quantity, and how to bring it to the quantity's unit.

    ``convert(v)`` returns the converted values and the derivative d(converted)/dv, with
    which the rounding of each written value is carried through the conversion.
    """

    index: int
    header: str
    key: str  # the role to name in ``columns={key: header}``
    convert: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]


def _cells(texts: Sequence[Any]) -> tuple[np.ndarray, np.ndarray]:
    """Value and rounding (half a unit in the last digit written) of each cell; NaN for
    a cell that is not a plain number (empty, text, nan, inf)."""
    strs = np.char.strip(np.char.strip(np.asarray([str(t) for t in texts], dtype=str)),
                         "\"' ")
    if strs.size and not (np.char.count(np.char.lower(strs), "e") > 0).any():
        try:  # the usual column of plain decimals, at numpy speed
            vals = np.asarray(np.char.replace(strs, ",", "."), dtype=np.float64)
        except ValueError:
            vals = None
        if vals is not None and np.isfinite(vals).all():
            mark = np.maximum(np.char.find(strs, "."), np.char.find(strs, ","))
            places = np.where(mark >= 0, np.char.str_len(strs) - mark - 1, 0)
            return vals, 0.5 * 10.0 ** -places.astype(np.float64)
    vals = np.full(strs.size, np.nan)
    res = np.full(strs.size, np.nan)
    for k, s in enumerate(strs.tolist()):
        m = _NUMBER.match(s)
        if m is None or not (m.group(1) or m.group(2)):
            continue
        try:
            v = float(s.replace(",", "."))
        except ValueError:
            continue
        if not np.isfinite(v):
            continue
        power = int(m.group(3) or 0) - len(m.group(2) or "")
        vals[k] = v
        res[k] = 0.5 * 10.0 ** min(max(power, -330), 300)
    return vals, res


#: Records of one temperature level: within this many degrees of the level's first.
LEVEL_TOLERANCE = 0.5


def _level_of(temps) -> list[int]:
    """The temperature level of each reading, in order of appearance: a reading joins the
    last level whose first reading is within :data:`LEVEL_TOLERANCE` of its own (the
    readings of one level drift by hundredths of a degree), else starts a new level."""
    firsts: list[float] = []
    out = []
    for T in temps:
        near = [k for k, v in enumerate(firsts) if abs(v - T) <= LEVEL_TOLERANCE]
        if not near:
            firsts.append(T)
            near = [len(firsts) - 1]
        out.append(near[-1])
    return out


def _n_levels(T: np.ndarray) -> int:
    """How many temperature levels the finite readings ``T`` fall into."""
    return len(set(_level_of(T[np.isfinite(T)].tolist())))


def _settle(table: _Table, rows: np.ndarray, cands: list[_Cand], what: str, unit: str) -> int:
    """Which of ``cands`` (the preferred first) to read: all must agree with the first to
    within :data:`ROUNDINGS` times the rounding of their digits; the finest-written one
    is read.

    Raises
    ------
    DataError
        Naming the first row where two of them disagree, both columns, and how to choose.
    """
    conv = []
    for c in cands:
        v, r = _cells(table.texts(c.index)[rows])
        with np.errstate(over="ignore", invalid="ignore"):
            x, d = c.convert(v)
        conv.append((x, np.abs(d) * r))
    x0, r0 = conv[0]
    for c, (x, r) in zip(cands[1:], conv[1:]):
        ok = np.isfinite(x0) & np.isfinite(x) & np.isfinite(r0) & np.isfinite(r)
        if not ok.any():
            continue
        scale = max(np.max(np.abs(x0[ok])), np.max(np.abs(x[ok])))
        bad = np.zeros_like(ok)
        bad[ok] = np.abs(x[ok] - x0[ok]) > ROUNDINGS * (r0[ok] + r[ok]) + _FLOAT_RTOL * scale
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            a, why = cands[0], ""
            if what == "temperature":  # a measured reading drifts; the test's own is steady
                n0, n1 = _n_levels(x0), _n_levels(x)
                if n0 != n1:
                    a, drift = (cands[0], c) if n0 < n1 else (c, cands[0])
                    why = (f"; {drift.header!r} drifts within the file ({max(n0, n1)} "
                           f"temperature levels against {min(n0, n1)}), so reading it would "
                           "split each test into several temperatures")
            raise DataError(
                f"{table.source}, {table.label(int(rows[i]))}: columns {cands[0].header!r} "
                f"and {c.header!r} could both be the {what} but differ ({x0[i]:.6g} vs "
                f"{x[i]:.6g}{unit}){why}: say which with "
                + setting(f"columns={{{a.key!r}: {a.header!r}}}", f"--columns {a.key}={a.header}")
            )
    finest = [float(np.nanmedian(r)) if np.isfinite(r).any() else np.inf for _, r in conv]
    return int(np.argmin(finest))


def _scaled(factor: float, offset: float = 0.0) -> Callable[[np.ndarray], tuple]:
    """v -> v × factor + offset."""
    return lambda v: (v * factor + offset, np.full_like(v, factor))


def _select_rows(table: _Table, select: Mapping[str, Any] | None) -> np.ndarray:
    """Rows whose columns hold the wanted values (``select=``); all rows without it."""
    rows = np.arange(table.n_rows)
    for h, want in (select or {}).items():
        j = _col_index(table, h, "select")
        wants = want if isinstance(want, (list, tuple, set)) else [want]
        vals = table.texts(j)[rows]
        numbers = _cells(vals)[0]
        ok = np.zeros(rows.size, dtype=bool)
        for w in wants:  # the same text, or the same number (40 selects 40.0)
            if not (isinstance(w, (int, float)) and not isinstance(w, bool)):
                ok |= np.array([v.lower() == str(w).strip().lower() for v in vals], dtype=bool)
            x = _cells([w])[0][0] if not isinstance(w, bool) else np.nan
            if np.isfinite(x):
                ok |= numbers == x
        if not ok.any():
            shown = ", ".join(sorted(set(map(str, vals)))[:6])
            first = wants[0] if wants else ""
            raise DataError(
                f"{table.source}: {setting(f'select={{{h!r}: {want!r}}}', f'--select {h}={first}')}"
                f" keeps no rows; column {table.names[j]!r} holds {shown}"
            )
        rows = rows[ok]
    return rows


def _col_index(table: _Table, h: str, what: str = "") -> int:
    """The column with header ``h`` (case-insensitive)."""
    want = str(h).strip().lower()
    for j, nm in enumerate(table.names):
        if nm.replace("\ufeff", "").strip().lower() == want:
            return j
    flag = {"select": f" (select=, --select {h}=VALUE)",
            "group_by": f" (group_by=, --group-by {h})"}.get(what, "")
    raise DataError(f"{table.source}: no column {h!r}{flag}; the header has "
                    f"{', '.join(map(repr, table.names))}")


#: Words a lab (or a DataFrame) writes for a number that is not finite: a numeric
#: channel with such cells (a derived quantity undefined at λ = 1) is still numbers.
_NOT_FINITE = {"nan", "+nan", "-nan", "inf", "+inf", "-inf", "infinity", "+infinity",
               "-infinity", "na", "n/a", "none", "null"}
#: A numeric column names specimens only with at most this many values, each in one block.
LABEL_VALUES = 20


def _numeric_cells(texts: np.ndarray) -> np.ndarray | None:
    """The values of a column of numbers (NaN where a cell is empty, nan or inf), or None
    if one of its cells is text."""
    vals = _cells(texts)[0]
    miss = np.isnan(vals)
    if miss.any():
        low = {str(t).strip().strip("\"'").lower() for t in texts[miss]}
        if low - _NOT_FINITE - {""}:
            return None
    return vals


def _is_block_label(vals: np.ndarray) -> bool:
    """Few values, each in one contiguous block of at least 2 rows (specimen = 1, 1, …,
    2, 2, …): numbers that name specimens, not a measured channel."""
    v = vals[np.isfinite(vals)]
    if v.size < 4:
        return False
    starts = np.flatnonzero(np.r_[True, v[1:] != v[:-1]])
    n_blocks = starts.size
    n_values = np.unique(v).size
    sizes = np.diff(np.r_[starts, v.size])
    return 2 <= n_values <= LABEL_VALUES and n_blocks == n_values and sizes.min() >= 2


def _check_text_columns(
    table: _Table, rows: np.ndarray, members: list[np.ndarray], skip: set[int]
) -> list[int]:
    """Refuse a label column whose values differ inside one curve (``members``: positions
    in ``rows`` of each curve), other than the columns in ``skip``; return the other
    columns (read and ignored by the fit).

    A column is a label when one of its non-empty cells is not a number (``nan``,
    ``inf`` count as numbers), or when its numbers are few values each in one contiguous
    block (:func:`_is_block_label`). Other numeric columns (force, displacement, a
    derived stress that is ``nan`` at λ = 1) are other channels, and so are text columns
    whose every value differs (a timestamp or row label names rows, not curves).
    """
    unused = []
    for j, h in enumerate(table.names):
        if j in skip:
            continue
        texts = table.texts(j)[rows]
        filled = texts != ""
        if not filled.any():
            continue  # an empty column (a trailing separator): nothing to say
        vals = _numeric_cells(texts)
        if vals is not None and not _is_block_label(vals):
            unused.append(j)
            continue  # numbers: another channel
        if vals is not None:
            keys = np.where(np.isfinite(vals), vals, np.nan)
            uniq_v, codes_v = np.unique(keys[filled], return_inverse=True)
            uniq = np.asarray(texts[filled])[
                [int(np.flatnonzero(codes_v == k)[0]) for k in range(uniq_v.size)]]
            codes = codes_v
        else:
            uniq, codes = np.unique(texts[filled].astype(str), return_inverse=True)
            if uniq.size < 2 or uniq.size == int(filled.sum()):
                unused.append(j)
                continue
        code = np.full(rows.size, -1)
        code[filled] = codes
        for g in members:
            c = code[g]
            c = c[c >= 0]
            if c.size and c.min() != c.max():
                runs = 1 + int(np.count_nonzero(np.diff(c)))
                _refuse_text_column(table, h, uniq[np.unique(c)],
                                    blocks=runs == np.unique(c).size)
        unused.append(j)
    return unused


def _refuse_text_column(table: _Table, h: str, values: np.ndarray, *, blocks: bool) -> None:
    """Refuse a label column that varies within one curve; ignoring it is offered only for
    interleaved values: a column in blocks separates tests, which merged are no test."""
    shown = ", ".join(_short(str(v)) for v in values[:_SHOWN]) + (
        ", ..." if values.size > _SHOWN else "")
    v0 = str(values[0])
    ignore = setting("columns={'ignore': " + repr(h) + "}", f"--columns ignore={h}")
    raise DataError(
        f"{table.source}, column {h!r}: {values.size} different values ({shown}) would be "
        f"merged into one curve: fit the groups as one material with "
        f"{setting(f'group_by={h!r}', f'--group-by {h}')}" + (", " if not blocks else " or ")
        + f"keep one with "
        f"{setting(f'select={{{h!r}: {v0!r}}}', f'--select {h}={v0}')}"
        + ("" if blocks else f", or ignore the column with {ignore}")
    )
