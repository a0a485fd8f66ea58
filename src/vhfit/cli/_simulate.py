"""``vhfit simulate``: stress of a given material along given loadings, as CSV."""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import numpy as np

from vhfit.cli._common import EXIT_OK, UsageError, emit, one_line
from vhfit.cli._plugins import resolve_model_name
from vhfit.cli._results import load_calibration
from vhfit.data import DataError, read_history
from vhfit.export import parse
from vhfit.export.check import network_stress
from vhfit.history import History
from vhfit.model import ModelSpec, ViscoHyperelastic, model_from_spec
from vhfit.modes import get_deformation
from vhfit.viscous import NetworkModel, ParamLayout

__all__ = ["cmd_simulate", "parse_params", "count_prony"]


def cmd_simulate(args, argv=()) -> int:
    """``vhfit simulate``: stress of a given material along given loadings, or its strain
    under a held stress (``--creep``), to CSV."""
    if args.card is not None:
        if args.results is not None or args.model is not None or args.param:
            raise UsageError(f"--card {args.card} gives the material: drop --results, "
                             "--model and --param")
        model, params, source = _card(args.card)
    elif args.results is None and args.model is None:
        raise UsageError("simulate needs a material: --card FILE, --results RESULTS.json, or "
                         "--model NAME with --param NAME=VALUE for each constant")
    else:
        model, params, source = _material(args)
    networks = isinstance(model, NetworkModel)
    if args.time is not None and args.creep is None:
        raise UsageError("--time gives the output times of a creep test: add --creep S (or "
                         "drop --time and give --rate or --history)")
    if args.creep is not None:
        if not networks:
            raise UsageError(f"--creep: the Prony model from {source} has no creep solver in "
                             "vhfit (only network models do): give a network card (--card "
                             "FILE with *VISCOELASTIC, NONLINEAR), or simulate the Prony model "
                             "with --rate or --history")
        return _creep(args, model, params, source)
    if networks:
        x = None
        describe = model.describe()
        shown = params
    else:
        _check_names(model, params)
        try:
            x = model.check(params)
        except ValueError as exc:
            raise UsageError(f"parameters: {one_line(exc)}") from None
        describe = model.spec().describe(formulation=True)
        shown = model.as_dict(x)
    loads = _loads(args)
    buf = io.StringIO()
    _head(buf, describe, source, shown)
    dfm = args.deformation
    test = get_deformation(dfm)
    if test.uniaxial:
        buf.write(f"# stress measure: {args.measure} (MPa); strain: engineering; time: s\n")
    elif test.shear:
        buf.write(f"# deformation: {dfm}; strain: {test.strain_label}; stress: "
                  f"{test.stress_label}; time: s\n")
    else:
        buf.write(f"# deformation: {dfm}; stress measure: {args.measure} (MPa) in the loaded "
                  "direction; strain: engineering λ1 − 1; time: s\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["curve", "strain_rate", "time", "strain", "stress"])
    for label, r, h in loads:
        try:
            s = (network_stress(model, h, args.measure) if networks
                 else model.stress(x, h, measure=args.measure))
        except ValueError as exc:
            raise UsageError(f"{label}: {one_line(exc)}") from None
        rate = f"{r:g}" if math.isfinite(r) else ""
        for t, e, v in zip(h.out_time, h.out_strain, s):  # (+ 0.0: no "-0" in the file)
            w.writerow([label, rate, f"{t + 0.0:.9g}", f"{e + 0.0:.9g}", f"{v + 0.0:.9g}"])
    emit(buf.getvalue(), args.out, what="simulated curves")
    return EXIT_OK


def _head(buf: io.StringIO, describe: str, source: str, params: dict[str, float]) -> None:
    """The first comment lines of the CSV: the material, where it came from, its constants."""
    buf.write(f"# vhfit simulate: {describe}, from {source}\n")
    buf.write("# params: " + ", ".join(f"{k}={v:.9g}" for k, v in params.items()) + "\n")


def _card(path: str) -> tuple[object, dict[str, float], str]:
    """The model and constants of a solver card (its format read from the text): a Prony
    model and its vhfit parameters, or a network model and its named constants."""
    try:
        text = Path(path).read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise UsageError(f"--card {path}: {one_line(exc)}") from None
    try:
        model, params = parse(text)
    except ValueError as exc:
        raise UsageError(f"--card {path}: {one_line(exc)}") from None
    return model, params, f"card {path}"


def _creep(args, model, params: dict[str, float], source: str) -> int:
    """``--creep S``: the stretch of a network model under the stress S applied at once at
    t = 0 (the instantaneous response) and held, at the ``--time`` output times."""
    if args.time is None:
        raise UsageError("--creep needs the output times: --time t1,t2,... (s, from 0)")
    if args.rate or args.history:
        raise UsageError("--creep is a test of its own: drop --rate and --history")
    times = np.asarray(args.time, dtype=np.float64)
    try:
        lam = np.asarray(model.creep(args.creep, times, deformation=args.deformation,
                                     measure=args.measure), dtype=np.float64)
    except ValueError as exc:
        raise UsageError(f"--creep {args.creep:g} --deformation {args.deformation}: "
                         f"{one_line(exc)}") from None
    buf = io.StringIO()
    _head(buf, model.describe(), source, params)
    buf.write(f"# creep: {args.measure} stress {args.creep:g} MPa in the loaded direction, "
              f"applied at t = 0 (the instantaneous response) and held; deformation: "
              f"{args.deformation}; stretch: λ1; strain: engineering λ1 − 1; time: s\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["time", "stretch", "strain", "stress"])
    for t, v in zip(times, lam):
        w.writerow([f"{t + 0.0:.9g}", f"{v:.12g}", f"{v - 1.0 + 0.0:.12g}",
                    f"{args.creep + 0.0:.9g}"])
    emit(buf.getvalue(), args.out, what="creep curve")
    return EXIT_OK


def _material(args) -> tuple[ViscoHyperelastic, dict[str, float], str]:
    """The model, its constants and where they came from: a results file's own model
    (law, terms, formulation, accuracy), or ``--model``; ``--param`` on top."""
    given: dict[str, float] = {}
    for item in args.param or []:
        given.update(parse_params(item))
    if args.results is None:
        params, spec, source = given, ModelSpec(), "command line"
    else:
        cal = load_calibration(args.results)
        params = {**cal.params, **given}
        if args.model is None and set(params) == set(cal.params):
            return cal.model, params, f"results {args.results}"
        spec, source = cal.model.spec(), f"results {args.results}"
    law = None if args.model is None else resolve_model_name(args.model)
    n_prony = count_prony(params)
    try:  # the results file's model (its formulation, accuracy), or the defaults
        model = model_from_spec(spec.replace(hyperelastic=law, n_prony=n_prony))
    except ValueError as exc:
        raise UsageError(f"parameters: {one_line(exc)}") from None
    return model, params, source


def _check_names(model: ViscoHyperelastic, params: dict[str, float]) -> None:
    """Missing or unknown constants, in the command line's words (the law's name as
    ``--model`` takes it, the constants as ``--param`` takes them)."""
    missing = [n for n in model.param_names if n not in params]
    extra = [k for k in params if k not in model.param_names]
    if not (missing or extra):
        return
    law = model.hyperelastic.name
    parts = []
    if missing:
        parts.append(f"missing {', '.join(missing)} (give "
                     + ", ".join(f"--param {n}=VALUE" for n in missing) + ")")
    if extra:
        parts.append(f"{', '.join(extra)} {'is' if len(extra) == 1 else 'are'} not among "
                     "them (drop --param " + ", ".join(extra) + ")")
    n = model.n_prony
    raise UsageError(f"--model {law} with {n} Prony term{'' if n == 1 else 's'} takes "
                     f"{', '.join(model.param_names)}: " + "; ".join(parts))


def _loads(args) -> list[tuple[str, float, History]]:
    """(label, rate or NaN, history) of each --rate ramp and --history file."""
    loads: list[tuple[str, float, History]] = []
    dfm = args.deformation
    if get_deformation(dfm).second_stretch:
        raise UsageError(f"--deformation {dfm} needs a second stretch path, which simulate "
                         "does not take: simulate it from Python (ViscoHyperelastic.stress "
                         "with a second stretch path), or a test with one stretch")
    kw = {"deformation": dfm}
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
            h = History.constant_rate(eps, r, **kw)
        except ValueError as exc:
            raise UsageError(f"--rate {r:g} --strain-max {emax:g}: {one_line(exc)}") from None
        loads.append((f"rate {r:g} 1/s", r, h))
    for path in args.history or []:
        try:
            t, e = read_history(path)
        except DataError as exc:
            raise UsageError(str(exc)) from None
        try:
            h = History.piecewise_linear(t, e, **kw)
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


def count_prony(params: dict) -> int:
    """The number N of Prony terms in ``params`` (``G1, tau1 ... GN, tauN``, all needed)."""
    try:
        return ParamLayout.count_terms(params)
    except ValueError as exc:
        raise UsageError(f"{exc} (give them with --param)") from None
