"""``vhfit fit --each COLUMN``: one separate fit per value of a column, side by side.

Each value of the column is fitted as its own material, exactly as ``--select
COLUMN=VALUE`` would fit it, into its own folder ``OUT/<value>/``; ``each.txt`` and
``each.csv`` in ``OUT`` list the fits side by side. ``--group-by`` is the other reading of
such a column: its groups fitted together, as one material.
"""

from __future__ import annotations

import copy
import csv
import io
import json
import re
import sys
import warnings
from collections.abc import Callable
from pathlib import Path

from vhfit._io import atomic_write
from vhfit.cli._common import (
    EXIT_FAILED,
    EXIT_OK,
    EXIT_USAGE,
    FitFailed,
    UsageError,
    one_line,
    prepare_out,
)
from vhfit.cli._inputs import read_curves

__all__ = ["run_each", "group_values", "folder_name"]

RESULTS = "results.json"


def group_values(args) -> list[str]:
    """The values of ``--each COLUMN`` in the data, in order of appearance."""
    probe = copy.copy(args)
    probe.group_by = [args.each]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # each fit's own reading says what it assumed
        curves, _ = read_curves(args.curves, probe)
    values = [(c.metadata or {}).get("group_values", [""])[0] for c in curves]
    return list(dict.fromkeys(v for v in values if v))


def folder_name(value: str, taken: set[str]) -> str:
    """A folder name for ``value``: its letters, digits, ``.-_``; unique among ``taken``."""
    base = re.sub(r"[^\w.\-]+", "_", value).strip("._") or "group"
    name, k = base, 2
    while name.lower() in taken:
        name, k = f"{base}-{k}", k + 1
    taken.add(name.lower())
    return name


def run_each(args, fit: Callable[[object], int]) -> int:
    """Fit each value of ``--each`` separately with ``fit`` (the one-material fit of
    ``vhfit fit``); write the table; return the worst exit code of the fits."""
    if args.resume:
        raise UsageError("--resume with --each: resume one value's fit with --out "
                         "OUT/<value> --select COLUMN=VALUE --resume")
    if args.each in (args.group_by or []):
        raise UsageError(f"--each {args.each} and --group-by {args.each}: give one (--each "
                         "fits each value separately, --group-by fits them as one material)")
    values = group_values(args)
    if len(values) < 2:
        raise UsageError(f"--each {args.each}: the data hold {len(values)} value(s) of it; "
                         "fit them without --each")
    out = prepare_out(args.out, "vhfit-results", force=args.force, resume=False)
    quiet = bool(getattr(args, "quiet", False))
    rows, taken, worst = [], set(), EXIT_OK
    for value in values:
        sub = out / folder_name(value, taken)
        one = copy.copy(args)
        one.each = None
        one.select = [*(args.select or []), (args.each, value)]
        one.out = str(sub)
        if not quiet:
            print(f"--each {args.each}: {value} -> {sub}/", file=sys.stderr, flush=True)
        try:
            code = fit(one)
            why = ""
        except (UsageError, ValueError, OSError) as exc:  # this value refused: the others go on
            code, why = EXIT_USAGE, one_line(exc)
            print(f"vhfit: error: --each {args.each}={value}: {why}", file=sys.stderr)
        except FitFailed as exc:
            code, why = EXIT_FAILED, one_line(exc)
            print(f"vhfit: error: --each {args.each}={value}: {why}", file=sys.stderr)
        worst = max(worst, code)
        rows.append(_row(value, sub, code, why))
        write_table(out, args.each, rows)  # after every fit: an interrupt keeps the rest
    if not quiet:
        sys.stdout.write(table_text(args.each, rows))
    return worst


def _row(value: str, sub: Path, code: int, why: str) -> dict:
    row = {"value": value, "folder": sub.name, "exit": code, "law": "", "n_prony": "",
           "rmsape": "", "grade": "", "note": why}
    try:
        res = json.loads((sub / RESULTS).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return row
    from vhfit.calibration import grade_word  # loaded with the fit already

    rmsape = float(res["rmsape"])  # percent
    row.update(law=res.get("hyperelastic", ""), n_prony=res.get("n_prony", ""),
               rmsape=f"{rmsape:.4g}", grade=grade_word(rmsape),
               note=why or str(res.get("stop_reason", "")))
    return row


_COLUMNS = ("value", "law", "n_prony", "rmsape", "grade", "folder", "note")
_HEADS = ("{col}", "law", "Prony terms", "RMSAPE %", "grade", "folder", "note")


def table_text(column: str, rows: list[dict]) -> str:
    """The fits side by side, as text."""
    heads = [h.format(col=column) for h in _HEADS]
    cells = [[str(r[c]) for c in _COLUMNS] for r in rows]
    widths = [max(len(x) for x in col) for col in zip(heads, *cells)]
    line = "  ".join
    return "".join(line(x.ljust(w) for x, w in zip(r, widths)).rstrip() + "\n"
                   for r in [heads, *cells])


def write_table(out: Path, column: str, rows: list[dict]) -> None:
    """``each.txt`` and ``each.csv`` in ``out``."""
    atomic_write(out / "each.txt", f"vhfit fit --each {column}: one fit per value\n\n"
                 + table_text(column, rows))
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([column if c == "value" else c for c in _COLUMNS] + ["exit"])
    for r in rows:
        w.writerow([r[c] for c in _COLUMNS] + [r["exit"]])
    atomic_write(out / "each.csv", buf.getvalue())
