"""The table layer: a CSV file (or an array, DataFrame-like object or mapping) as a table.

``_read_table`` decodes a file (BOMs, UTF-16, Latin-1), reads its ``# key: value`` lines,
finds the header (and a units line under it), the separator and the data lines, and
returns a ``_Table`` whose cells are split lazily (whole clean columns at C speed);
``_table_from_data`` wraps arrays, structured arrays, DataFrame-like objects and mappings.
``_Table.floats`` turns a column into numbers with a message naming the bad cell.
"""

from __future__ import annotations

import codecs
import csv
import operator
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from vhfit._words import setting
from vhfit.data._errors import DataError, _Labels, _norm_key, _short


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
    comments: tuple[str, ...] = ()  # the '#' lines above the header, '# key: value' ones too
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
                f"{src}: cannot decode as {encoding!r} ({exc}): check "
                + setting("encoding=", "the file's encoding (save it as UTF-8)")
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
    """The table of a CSV file or text stream (cells split lazily)."""
    src, text, note = _file_text(path, encoding)
    lines = text.splitlines()
    meta, header, header_no, forced = _preamble(lines, src)
    data, numbers = _data_lines(text, lines, header, header_no)
    delim = forced or next((d for d in ("\t", ";", ",", "|") if d in header), None)
    split = _splitter(delim)
    head = [h.strip() for h in split(header)]
    if all(_is_number(h) for h in head if h):
        if names is None:
            raise DataError(
                f"{src}, line {header_no}: the first line holds numbers, not column names: add "
                "a header row (e.g. 'strain,stress_MPa')"
                + setting(" or pass names=[...]", "")
            )
        data = [header, *data]
        numbers = np.concatenate([[header_no], np.asarray(numbers, dtype=np.int64)])
    if names is None and data:
        head, data, numbers = _fold_units_line(head, data, numbers, split)
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
    comments = tuple(s for s in map(str.strip, lines[:header_no]) if s.startswith("#"))
    table = _Table(head, None, _Labels(numbers, "line"), src, meta, lines=data,
                   split_line=split, delim=delim, fast=fast, note=note, comments=comments)
    table.check_shape()
    return table


def _file_text(path: Any, encoding: str | None) -> tuple[str, str, str]:
    """(name for messages, text, note on a guessed encoding) of a path or text stream."""
    if hasattr(path, "read"):
        # getattr default: a text stream (io.StringIO) has no name
        src = str(getattr(path, "name", "<stream>"))
        content = path.read()
        text, note = (content, "") if isinstance(content, str) else _decode(content, src,
                                                                              encoding)
        return src, text, note
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
    return src, text, note


def _preamble(lines: list[str], src: str) -> tuple[dict[str, str], str, int, str | None]:
    """The ``# key: value`` lines, the header line and its 1-based number, and Excel's
    ``sep=`` separator hint, if any."""
    meta: dict[str, str] = {}
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
        return meta, line, no, forced
    raise DataError(f"{src}: is empty (no header, no data): give a CSV file with a header "
                    "row such as 'strain,stress_MPa' and one row per sample")


def _data_lines(text: str, lines: list[str], header: str, header_no: int) -> tuple[list[str], Any]:
    """The data lines under the header (blank and comment lines dropped) and their numbers."""
    rest = lines[header_no:]
    if all(rest) and not any(map(str.isspace, rest)) and "#" not in text.partition(header)[2]:
        # the common case, checked at C speed: every line is data
        return rest, np.arange(header_no + 1, header_no + 1 + len(rest))
    data, numbers = [], []
    for no, line in enumerate(rest, header_no + 1):
        s = line.strip()
        if s and (not s.startswith("#") or _EXCEL_ERROR.match(s)):
            data.append(line)
            numbers.append(no)
    return data, numbers


def _splitter(delim: str | None) -> Callable[[str], list[str]]:
    """line -> fields, for a separator (None: runs of whitespace)."""

    def split(line: str) -> list[str]:
        if delim is None:
            return line.split()
        return next(csv.reader([line], delimiter=delim, skipinitialspace=True))

    return split


def _fold_units_line(
    head: list[str], data: list[str], numbers: Any, split: Callable[[str], list[str]]
) -> tuple[list[str], list[str], Any]:
    """A second header line with the units ("s", "mm", "[N]") folded into the names."""
    first = split(data[0])
    if any(f.strip() for f in first) and not any(_is_number(f) for f in first if f.strip()):
        units = [u.strip().strip("[](){}").strip() for u in first] + [""] * len(head)
        head = [f"{h} [{u}]" if u and not re.search(r"[\[\(\{]", h) else h
                for h, u in zip(head, units)]
        data = data[1:]
        numbers = np.asarray(numbers, dtype=np.int64)[1:]
    return head, data, numbers


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
                            + setting("names=['time_s', 'strain', 'stress_MPa', ...]",
                                      "a header row ('time_s,strain,stress_MPa,...')"))
    if len(head) != arr.shape[1]:
        raise DataError(f"{src}: {len(head)} names for {arr.shape[1]} columns: give one name per "
                        "column")
    return _Table([str(h) for h in head], [arr[:, j] for j in range(arr.shape[1])],
                  _Labels(np.arange(arr.shape[0]), "row"), src, {})


