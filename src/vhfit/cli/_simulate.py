"""``vhfit simulate``: stress of a given material along given loadings, as CSV."""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import numpy as np

from vhfit.cli._common import EXIT_OK, UsageError, count_prony, emit, load_results, one_line
from vhfit.cli._plugins import resolve_model_name
from vhfit.history import History
from vhfit.model import ViscoHyperelastic

__all__ = ["cmd_simulate", "parse_params"]


def cmd_simulate(args) -> int:
    """``vhfit simulate``: stress of a given material along given loadings, to CSV."""
    if args.results is None and args.model is None:
        raise UsageError("simulate needs a material: --results RESULTS.json, or --model NAME "
                         "with --param NAME=VALUE for each constant")
    name, params, source = _material(args)
    n_prony = count_prony(params)
    try:
        model = ViscoHyperelastic(name, n_prony)
        x = model.check(params)
    except ValueError as exc:
        raise UsageError(f"parameters: {one_line(exc)}") from None
    loads = _loads(args)
    buf = io.StringIO()
    buf.write(f"# vhfit simulate: {name} + {n_prony} Prony term(s), from {source}\n")
    buf.write("# params: " + ", ".join(f"{k}={v:.9g}" for k, v in model.as_dict(x).items()) + "\n")
    buf.write(f"# stress measure: {args.measure} (MPa); strain: engineering; time: s\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["curve", "strain_rate", "time", "strain", "stress"])
    for label, r, h in loads:
        try:
            s = model.stress(x, h, measure=args.measure)
        except ValueError as exc:
            raise UsageError(f"{label}: {one_line(exc)}") from None
        rate = f"{r:g}" if math.isfinite(r) else ""
        for t, e, v in zip(h.out_time, h.out_strain, s):  # (+ 0.0: no "-0" in the file)
            w.writerow([label, rate, f"{t + 0.0:.9g}", f"{e + 0.0:.9g}", f"{v + 0.0:.9g}"])
    emit(buf.getvalue(), args.out, what="simulated curves")
    return EXIT_OK


def _material(args) -> tuple[str, dict[str, float], str]:
    """Model name, constants and where they came from (--results, then --param on top)."""
    params: dict[str, float] = {}
    if args.results is not None:
        res = load_results(args.results)
        name = args.model or res["hyperelastic"]
        params = dict(res["params"])
        source = f"results {args.results}"
    else:
        name = args.model
        source = "command line"
    for item in args.param or []:
        params.update(parse_params(item))
    return resolve_model_name(name), params, source


def _loads(args) -> list[tuple[str, float, History]]:
    """(label, rate or NaN, history) of each --rate ramp and --history file."""
    loads: list[tuple[str, float, History]] = []
    if not args.rate and not args.history:
        raise UsageError("give the loading: --rate R (repeatable, 1/s) with --strain-max, "
                         "or --history FILE.csv (time, strain columns)")
    for r in args.rate or []:
        if r == 0:
            raise UsageError("--rate 0: give a non-zero strain rate in 1/s "
                             "(negative = compression)")
        emax = args.strain_max if args.strain_max is not None else math.copysign(0.5, r)
        if emax * r <= 0:
            raise UsageError(
                f"--strain-max {emax:g} and --rate {r:g} have opposite signs: a constant-rate "
                "ramp from rest reaches strains of the rate's sign (compression: both negative)"
            )
        eps = np.linspace(0.0, emax, args.points)
        try:
            h = History.constant_rate(eps, r)
        except ValueError as exc:
            raise UsageError(f"--rate {r:g} --strain-max {emax:g}: {one_line(exc)}") from None
        loads.append((f"rate {r:g} 1/s", r, h))
    for path in args.history or []:
        t, e = _read_history(path)
        try:
            h = History.piecewise_linear(t, e)
        except ValueError as exc:
            raise UsageError(f"{path}: {one_line(exc)}") from None
        loads.append((Path(path).name, float("nan"), h))
    return loads


def parse_params(item: str) -> dict[str, float]:
    """``"C10=0.1, G1=2"`` (one ``--param``) -> ``{"C10": 0.1, "G1": 2.0}``."""
    out = {}
    for part in item.split(","):
        part = part.strip()
        if not part:
            continue
        key, sep, val = part.partition("=")
        if not sep or not key.strip():
            raise UsageError(f"--param {item!r}: write NAME=VALUE, e.g. --param C10=0.1 "
                             "(several: --param C10=0.1,C01=0.05)")
        try:
            out[key.strip()] = float(val)
        except ValueError:
            raise UsageError(f"--param {part!r}: {val!r} is not a number") from None
    return out


def _read_history(path: str) -> tuple[np.ndarray, np.ndarray]:
    """(time, strain) columns of a history CSV: named ``time*``/``strain*``, else the first two.

    The material is at rest at t = 0: a history that starts later gets a ramp from
    (0, 0) to its first sample.
    """
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            rows = [r for r in csv.reader(line for line in f if not line.lstrip().startswith("#"))
                    if any(c.strip() for c in r)]
    except OSError as exc:
        raise UsageError(f"{path}: cannot read ({exc.strerror}); check the path") from None
    if not rows:
        raise UsageError(f"{path}: empty; give a CSV with time and strain columns")
    head = [c.strip().lower() for c in rows[0]]

    def numeric(r):
        try:
            [float(c) for c in r]
        except ValueError:
            return False
        return True

    it, ie, data = 0, 1, rows
    if not numeric(rows[0]):
        data = rows[1:]
        t_cols = [j for j, h in enumerate(head) if h.startswith("time") or h in ("t", "t_s")]
        e_cols = [j for j, h in enumerate(head) if h.startswith("strain") and "rate" not in h]
        if not t_cols or not e_cols:
            raise UsageError(f"{path}: header {rows[0]} has no 'time' and 'strain' columns; "
                             "name them so (time in s, engineering strain)")
        it, ie = t_cols[0], e_cols[0]
    try:
        arr = np.array([[float(r[it]), float(r[ie])] for r in data])
    except (ValueError, IndexError):
        for k, r in enumerate(data):
            try:
                float(r[it]), float(r[ie])
            except (ValueError, IndexError):
                line = k + (2 if data is not rows else 1)
                raise UsageError(f"{path}: data row {line} {r} is not two numbers "
                                 "(time, strain); fix or remove it") from None
        raise
    if arr.shape[0] < 2:
        raise UsageError(f"{path}: needs at least 2 (time, strain) rows")
    t, e = arr[:, 0], arr[:, 1]
    if t[0] > 0:  # the material is at rest at t = 0: ramp to the first sample
        t, e = np.concatenate([[0.0], t]), np.concatenate([[0.0], e])
    return t, e
