"""The input files of ``vhfit fit`` and ``vhfit check``: curves, sweeps and relaxation
tests read with the command line's choices (rates, deformations, columns, units, groups,
selections, trims), and the record of each file (path, size, SHA-256) for the results."""

from __future__ import annotations

import glob
import hashlib
import os
from collections.abc import Sequence
from typing import Any

from vhfit.cli._common import (
    UsageError,
)
from vhfit.data import read_csv

__all__ = ["read_curves", "sha256"]


# ============================================================ reading inputs
def sha256(path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def read_curves(paths: Sequence[str], args) -> tuple[list, list[dict]]:
    """The curves of the CSV files (globs expanded, trimmed) and their paths and digests."""
    files = []
    for p in paths:
        matches = sorted(glob.glob(p)) if glob.has_magic(p) else [p]
        if not matches:
            raise UsageError(f"{p}: no file matches this pattern; check the path")
        files += matches
    for f in files:
        if not os.path.exists(f):
            raise UsageError(f"{f}: no such file; check the path (run 'vhfit demo' for an example)")
        if os.path.isdir(f):
            raise UsageError(f"{f}: is a folder; give the CSV files in it (e.g. {f}/*.csv)")
    kw: dict[str, Any] = {}
    if args.rate:
        if len(args.rate) not in (1, len(files)):
            raise UsageError(
                f"--rate given {len(args.rate)} times for {len(files)} files: give one rate "
                "for all files or one per file, in file order"
            )
        kw["rate"] = args.rate[0] if len(args.rate) == 1 else list(args.rate)
    if args.measure:
        kw["measure"] = args.measure
    tests = args.deformation
    if tests:
        if len(tests) not in (1, len(files)):
            raise UsageError(
                f"--deformation given {len(tests)} times for {len(files)} files: give one "
                "for all files or one per file, in file order"
            )
        kw["deformation"] = tests[0] if len(tests) == 1 else list(tests)
    kw["n_points"] = args.points
    kw.update(_data_choices(args))
    curves = read_csv(files, **kw)
    if not curves:
        raise UsageError(f"{', '.join(files)}: no curves found; check the files' columns")
    windows = {}
    for what in ("strain", "time"):
        given = getattr(args, f"trim_{what}") or []
        if len(given) not in (0, 1, len(files)):
            raise UsageError(
                f"--trim-{what} given {len(given)} times for {len(files)} files: give one "
                "window for all files or one per file, in file order (':' for no trim)")
        windows[what] = {os.path.abspath(f): given[0 if len(given) == 1 else k]
                         for k, f in enumerate(files)} if given else {}
    if windows["strain"] or windows["time"]:
        def trimmed(c):
            src = os.path.abspath(c.source) if c.source else None
            if c.is_moduli:  # a frequency sweep or relaxation test: no trim
                return c
            return c.trim(strain=windows["strain"].get(src), time=windows["time"].get(src))

        curves = [trimmed(c) for c in curves]
    inputs = [{"path": os.path.abspath(f), "sha256": sha256(f)} for f in files]
    return curves, inputs


def _data_choices(args) -> dict[str, Any]:
    """read_csv's ``columns=``, ``units=``, ``group_by=``, ``select=`` and ``sort=`` from
    ``--columns``, ``--units``, ``--group-by``, ``--select`` and ``--sort`` (pairs as parsed,
    or as a results file records them)."""
    kw: dict[str, Any] = {}
    columns: dict[str, Any] = {}
    for role, name in args.columns or []:
        if role.lower() == "ignore":
            columns.setdefault("ignore", []).append(name)
        elif role in columns:
            raise UsageError(f"--columns {role}= given twice: give each role once")
        else:
            columns[role] = name or None
    units: dict[str, str] = {}
    for role, unit in args.units or []:
        if role in units:
            raise UsageError(f"--units {role}= given twice: give each role once")
        units[role] = unit
    select: dict[str, Any] = {}
    for col, value in args.select or []:
        select.setdefault(col, []).append(value)
    select = {c: v[0] if len(v) == 1 else v for c, v in select.items()}
    for key, val in (("columns", columns), ("units", units), ("select", select),
                     ("group_by", list(args.group_by or [])), ("sort", bool(args.sort))):
        if val:
            kw[key] = val
    return kw
