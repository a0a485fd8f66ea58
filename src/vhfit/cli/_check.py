"""``vhfit check``: the error each solver will show with the cards of a fit, on the data,
each card graded on its own error, and the warnings of the cards' own fits."""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

from vhfit import datasets, tts
from vhfit.cli._cards import CARD_FILES, check_table, solver_of
from vhfit.cli._common import EXIT_OK, UsageError, one_line
from vhfit.cli._fit import read_curves
from vhfit.cli._results import load_calibration
from vhfit.export import parse
from vhfit.export.check import card_solver, check_card, own_fit_warnings

__all__ = ["cmd_check"]

_DATA_OPTIONS = ("rate", "measure", "deformation", "points", "trim_strain", "trim_time",
                 "columns", "units", "group_by", "select", "sort")


def cmd_check(args, argv=()) -> int:
    """``vhfit check RESULTS.json [--data FILE...] [--card FILE...]``."""
    cal = load_calibration(args.results)
    res = cal.context
    folder = Path(args.results).resolve().parent
    cards = _cards(args, res, folder)
    curves = _curves(args, cal)
    card_fits = res.get("card_fits") or {}
    checks, served = {}, {}
    for key, (solver, text) in cards.items():
        fit = cal.fits.get(card_fits.get(key, card_fits.get(solver)), cal)
        served.setdefault(fit.model.formulation, []).append(solver)
        try:
            checks[key] = check_card(text, curves, solver=solver, fit=fit)
        except ValueError as exc:
            raise UsageError(f"{key} card: {one_line(exc)}") from None
    if args.json:
        print(json.dumps({"card_check": {k: c.to_dict() for k, c in checks.items()}}, indent=2))
        return EXIT_OK
    names = [str(c.name) for c in curves]
    for c in checks.values():
        if c.warning():
            print(f"WARNING: {c.warning()}")
    fits = {cal.model.formulation: cal, **cal.fits}  # the main fit first
    for w in own_fit_warnings(fits, served):
        print(f"WARNING: {w}")
    print("\n".join(check_table(checks, names)))
    return EXIT_OK


def _curves(args, cal) -> list:
    """The data: ``--data``, else the input files the results record (the demo's bundled
    set as the demo reads it)."""
    res = cal.context
    inputs = res.get("inputs") or []
    if not args.data and any(i.get("bundled") == "vhfit.datasets.sebs" for i in inputs):
        return datasets.load_sebs()
    data = args.data or [i["path"] for i in inputs if "path" in i]
    if not data:
        raise UsageError(f"{args.results}: no input files recorded; give the data with --data")
    curves, _ = read_curves(data, _data_args(args, res.get("cli_options") or {}))
    return _at_reference(curves, cal)


def _at_reference(curves, cal) -> list:
    """Tests at several temperatures shifted to T_ref as the fit shifted them: its table of
    log10 a_T (the fit's own temperatures), else its law."""
    if cal.shift_source is None:
        return curves
    table, law = dict(cal.shift_table), cal.shift
    law = law if law is not None and law.name == "wlf" else None
    try:
        return tts.shift_to_reference(curves, shift_factors=table or law,
                                      T_ref=cal.T_ref).items
    except ValueError:
        if law is None:
            raise
        return tts.shift_to_reference(curves, shift_factors=law).items


def _cards(args, res: dict, folder: Path) -> dict:
    """Card key -> (solver, text): the ``--card`` files, else the results folder's cards."""
    out = {}
    if args.card:
        for f in args.card:
            text = _read(f)
            try:
                model_solver = card_solver(text)
                parse(text, model_solver)
            except ValueError as exc:
                raise UsageError(f"--card {f}: {one_line(exc)}") from None
            out[os.path.basename(f)] = (model_solver, text)
        return out
    listed = res.get("cards") or {}
    for key in CARD_FILES:
        if key == "json" or key not in listed:
            continue
        out[key] = (solver_of(key), _read(str(folder / listed[key])))
    if not out:
        raise UsageError(f"{folder}: the results list no solver cards; give them with --card")
    return out


def _read(path: str) -> str:
    try:
        with open(path, encoding="utf-8") as f:
            return f.read()
    except OSError as exc:
        raise UsageError(f"{path}: cannot read ({exc.strerror}); give the card's path with "
                         "--card") from None


def _data_args(args, saved: dict) -> argparse.Namespace:
    """The data options: given on the command line, else the fit's own."""
    ns = argparse.Namespace()
    for k in _DATA_OPTIONS:
        v = getattr(args, k) if hasattr(args, k) else saved.get(k)
        if k.startswith("trim_") and v:
            v = [None if w is None else tuple(w) for w in v]
        setattr(ns, k, v)
    return ns
