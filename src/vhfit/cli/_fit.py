"""``vhfit fit`` and ``vhfit demo``: calibrate, then write every output into one folder.

The two commands share the whole workflow (:func:`run_fit`): they differ only in where
the curves come from. ``results.json`` is written by :meth:`Calibration.save`; the
files that only the command line writes (``fitted_curves.csv``, ``summary.txt``, the
solver cards and the plots) are written here.
"""

from __future__ import annotations

import csv
import glob
import hashlib
import io
import json
import os
import shlex
import sys
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from vhfit import datasets, plot, tts
from vhfit._io import atomic_write
from vhfit.calibration import (
    Calibration,
    CalibrationError,
    CalibrationWarning,
    calibrate,
    default_n_prony,
)
from vhfit.cli import _moduli
from vhfit.cli._cards import (
    CARD_FILES,
    SOLVERS,
    check_targets,
    plan_fits,
    write_cards,
)
from vhfit.cli._common import (
    EXIT_FAILED,
    EXIT_OK,
    FitFailed,
    Progress,
    Signals,
    UsageError,
    one_line,
    prepare_out,
)
from vhfit.cli._plugins import load_plugins, resolve_model_name, tau_strategies
from vhfit.data import is_moduli, read_csv
from vhfit.formulations import FORMULATIONS

__all__ = ["cmd_fit", "cmd_demo", "run_fit", "read_curves", "SOLVERS", "CARD_FILES",
           "DEMO_PRONY"]

RESULTS = "results.json"
CHECKPOINT = "checkpoint.json"
DEMO_PRONY = 4
DEMO_STRATEGY = "semifree"


# ================================================================== commands
def cmd_fit(args) -> int:
    """``vhfit fit CURVES...``."""
    if args.force and args.resume:
        raise UsageError("--force and --resume contradict each other: give one")
    _check_fit_flags(args)
    _check_card_flags(args)
    curves, inputs = read_curves(args.curves, args)  # bad data: nothing written
    _check_shift(curves, args)  # temperatures without shift information: nothing written
    with _out_folder(args, "vhfit-results") as out:
        return run_fit(curves, inputs, args, out, label=None, command=args._argv)


def cmd_demo(args) -> int:
    """``vhfit demo``: the bundled synthetic SEBS set, end to end."""
    if args.force and args.resume:
        raise UsageError("--force and --resume contradict each other: give one")
    args.model = "mooney_rivlin"
    _check_fit_flags(args)
    _check_card_flags(args)
    with _out_folder(args, "vhfit-demo") as out:
        return _run_demo(args, out)


def _run_demo(args, out: Path) -> int:
    path = datasets.sebs_path()
    curves = datasets.load_sebs()
    inputs = [{"path": str(path), "sha256": _sha256(path), "bundled": "vhfit.datasets.sebs"}]
    if args.out is None:
        args._argv = list(args._argv) + ["--out", str(out)]
    args.model, args.prony, args.strategy = "mooney_rivlin", args.prony, DEMO_STRATEGY
    if not args.quiet:
        print(
            f"vhfit demo: {len(curves)} synthetic SEBS curves (rates "
            f"{', '.join(f'{r:g}' for r in datasets.SEBS_RATES)} 1/s) generated from the paper's "
            f"Table 5 parameters; calibrating Mooney-Rivlin + {args.prony} Prony terms",
            file=sys.stderr,
        )
    code = run_fit(curves, inputs, args, out, label=datasets.SEBS_LABEL, command=args._argv,
                   demo=True)
    if code == EXIT_OK:
        _demo_check(out)
    return code


def _check_fit_flags(args) -> None:
    """``--max-prony``: refused before anything is written or printed (the law and the τ
    strategy are checked by :func:`run_fit`, whose bad input :func:`_out_folder` undoes)."""
    if args.max_prony < 1:
        raise UsageError(f"--max-prony {args.max_prony}: give a whole number >= 1 (the "
                         "largest N that --prony auto tries)")


@contextmanager
def _out_folder(args, default: str) -> Iterator[Path]:
    """The ``--out`` folder of a fit, left as it was when the run ends in bad input.

    On exit 2 (a one-line error: bad data, a law that cannot reach the data, a flag the
    fit refuses) the files the run added are removed, the checkpoints it changed are
    restored and a folder it created is removed again: a rerun finds the folder as the
    user left it. Interrupts and failed fits (exit 1) keep their checkpoints for
    ``--resume``.
    """
    existed = _existing_out(args.out, default)
    out = prepare_out(args.out, default, force=args.force, resume=args.resume)
    existed = out.resolve() in existed
    names = set(os.listdir(out)) if existed else set()
    saved = {n: (out / n).read_text() for n in names
             if n.startswith(CHECKPOINT) and (out / n).is_file()}
    try:
        yield out
    except (UsageError, ValueError, OSError):  # exit 2: as it was
        _restore(out, existed, names, saved)
        raise


def _existing_out(given: str | None, default: str) -> set[Path]:
    """The folders that the ``--out`` of this run may be, among those that exist now."""
    if given is not None:
        cands = [Path(given)]
    else:
        base = Path(default)
        cands = [base] + list(base.parent.glob(base.name + "-*"))
    return {p.resolve() for p in cands if p.is_dir()}


def _restore(out: Path, existed: bool, names: set[str], saved: dict[str, str]) -> None:
    """Undo a run's writes into ``out`` (see :func:`_out_folder`)."""
    try:
        for p in out.iterdir():
            if p.name not in names and p.is_file():
                p.unlink()
        for n, data in saved.items():
            p = out / n
            if not p.is_file() or p.read_text() != data:
                atomic_write(p, data)
        if not existed and not any(out.iterdir()):
            out.rmdir()
    except OSError:  # the error being reported matters more than the cleanup
        pass


def _check_card_flags(args) -> None:
    """``--for`` a solver that lacks the law, or an unknown ``--formulation``: refused
    before anything is fitted or written."""
    form = getattr(args, "formulation", None)
    if form is not None and form not in FORMULATIONS:
        load_plugins()  # a plug-in may register it
        if form not in FORMULATIONS:
            raise UsageError(f"--formulation {form}: unknown; choose one of "
                             f"{', '.join(FORMULATIONS)} (or register one in a plug-in)")
    given = getattr(args, "targets", None)
    if given:  # --for a,b --for c: one list, each solver once
        args.targets = list(dict.fromkeys(s for group in given for s in group))
        check_targets(args.targets, resolve_model_name(args.model))


def _shift_law(args):
    """The law of ``--shift`` at ``--tref`` (None without ``--shift``)."""
    given = getattr(args, "shift", None)
    if given is None:
        return None
    name, vals = given
    text = f"{name}:{','.join(f'{v:g}' for v in vals)}"
    if args.tref is None:
        raise UsageError(f"--shift {text}: give --tref T, the reference temperature of the law")
    try:
        if name == "wlf":
            return tts.WLF(C1=vals[0], C2=vals[1], T_ref=args.tref)
        return tts.Arrhenius(vals[0], args.tref, *vals[1:])
    except ValueError as exc:
        raise UsageError(f"--shift {text}: {one_line(exc)}") from None


def _check_shift(curves, args) -> None:
    """Tests at several temperatures: their shift to --tref, checked before anything is
    written (the tests at the reference are kept in ``args._at_ref`` for the outputs)."""
    law = _shift_law(args)
    try:
        ref = tts.shift_to_reference(curves, shift_factors=law, T_ref=args.tref)
    except ValueError as exc:
        raise UsageError(f"{one_line(exc)} (command line: --shift wlf:C1,C2 --tref T)"
                         ) from None
    args._shift_law = law
    args._at_ref = ref.items if ref.source != "none" else None


def _demo_check(out: Path) -> None:
    """Print the fitted constants next to the generating ones."""
    with open(out / RESULTS) as f:
        res = json.load(f)
    p = res["params"]
    true = datasets.SEBS_PARAMS
    rows = ["", "fitted vs generating parameters (paper Table 5):"]
    for k, v in true.items():
        if k in p:
            rows.append(f"  {k:<6} fitted {p[k]:<12.6g} generating {v:<12.6g} "
                        f"rel. diff {abs(p[k] - v) / abs(v):.1e}")
    print("\n".join(rows))


# ============================================================ reading inputs
def _sha256(path) -> str:
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
    tests = getattr(args, "deformation", None)
    if tests:
        if len(tests) not in (1, len(files)):
            raise UsageError(
                f"--deformation given {len(tests)} times for {len(files)} files: give one "
                "for all files or one per file, in file order"
            )
        kw["deformation"] = tests[0] if len(tests) == 1 else list(tests)
    kw["n_points"] = args.points
    curves = read_csv(files, **kw)
    if not curves:
        raise UsageError(f"{', '.join(files)}: no curves found; check the files' columns")
    windows = {}
    for what in ("strain", "time"):
        given = getattr(args, f"trim_{what}", None) or []
        if len(given) not in (0, 1, len(files)):
            raise UsageError(
                f"--trim-{what} given {len(given)} times for {len(files)} files: give one "
                "window for all files or one per file, in file order (':' for no trim)")
        windows[what] = {os.path.abspath(f): given[0 if len(given) == 1 else k]
                         for k, f in enumerate(files)} if given else {}
    if windows["strain"] or windows["time"]:
        def trimmed(c):
            src = os.path.abspath(c.source) if c.source else None
            if not hasattr(c, "trim"):  # a frequency sweep or relaxation test
                return c
            return c.trim(strain=windows["strain"].get(src), time=windows["time"].get(src))

        curves = [trimmed(c) for c in curves]
    inputs = [{"path": os.path.abspath(f), "sha256": _sha256(f)} for f in files]
    return curves, inputs


# ================================================================ the fit job
def run_fit(curves, inputs, args, out: Path, *, label: str | None, command: list[str],
            demo: bool = False) -> int:
    """Calibrate, then write every output into ``out`` (also when interrupted)."""
    model = resolve_model_name(args.model)
    strategy = args.strategy
    if strategy not in tau_strategies():
        raise UsageError(
            f"--strategy {strategy!r}: choose one of {', '.join(tau_strategies())}"
        )
    if args.resume and not any(out.glob(CHECKPOINT + "*")):
        raise UsageError(
            f"--resume: no checkpoint in {out} (the fit ended, or never started there); "
            "drop --resume to fit afresh"
        )
    if not args.quiet:
        why = None
        if args.prony is None:
            n_txt, why = default_n_prony(curves)
        else:
            n_txt = (f"auto (N = 1..{args.max_prony})" if args.prony == "auto"
                     else str(args.prony))
        print(f"fitting {model} + {n_txt} Prony term(s), tau strategy {strategy}, seed "
              f"{args.seed}, to {len(curves)} curve(s); outputs in {out}/"
              + (" (resuming)" if args.resume else ""), file=sys.stderr, flush=True)
        if why:
            print(f"no Prony terms: {why} (give --prony N to fit some anyway)",
                  file=sys.stderr, flush=True)
    plan = plan_fits(getattr(args, "targets", None), getattr(args, "formulation", None))
    sigs = Signals()
    fits: dict[str, Calibration] = {}
    interrupted = False
    with sigs, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for form in plan:
            if len(plan) > 1 and not args.quiet:
                print(f"fit in the '{form}' formulation, for {', '.join(plan[form])}",
                      file=sys.stderr, flush=True)
            # a resumed scan starts mid-way: N cannot be counted from the generations then
            progress = Progress(sys.stderr, quiet=args.quiet, scan=args.prony == "auto",
                                first_n=None if args.resume else 1)
            fits[form] = cal = _search(curves, args, out, model, strategy, progress, sigs,
                                       command, form)
            interrupted = cal.stop_reason == "interrupted" or sigs.stopped_search
            if interrupted:
                break
        cal = next(iter(fits.values()))
        sigs.writing = True
        files = _write_outputs(fits, plan, curves, inputs, args, out, label=label,
                               command=command, interrupted=interrupted, demo=demo)
    _show_warnings(caught, [w for c in fits.values() for w in c.warnings])
    print(files.pop("_summary"))
    print("")
    print(f"outputs in {out}/: " + ", ".join(sorted(files)))
    if not all(np.isfinite(c.rmsape) for c in fits.values()):
        print("vhfit: error: the fit found no valid parameter set (RMSAPE is not finite); "
              "check the data and the model", file=sys.stderr)
        return EXIT_FAILED
    if interrupted:
        print(
            f"vhfit: interrupted: the outputs hold the best parameters found so far and are "
            f"marked 'interrupted'; continue with: {_resume_cmd(command)}",
            file=sys.stderr,
        )
        return EXIT_FAILED
    for f in out.glob(CHECKPOINT + "*"):  # finished: nothing left to resume
        f.unlink()
    return EXIT_OK


def _search(curves, args, out: Path, model: str, strategy: str, progress: Progress,
            sigs: Signals, command: list[str], formulation: str = "hereditary") -> Calibration:
    """The calibration itself, with progress, signals and a checkpoint in ``out`` (one
    checkpoint per formulation: ``checkpoint.json`` for the first)."""
    def callback(d):
        progress(d)
        sigs.check()  # raises KeyboardInterrupt (caught by calibrate) after a signal
        return False

    kw = dict(
        hyperelastic=model, n_prony=args.prony, tau_strategy=strategy, method=args.method,
        seed=args.seed, workers=args.workers, popsize=args.popsize, maxiter=args.maxiter,
        target=args.target, polish=not args.no_polish, g_inf_min=args.g_inf_min,
        max_time=args.max_time, callback=callback, checkpoint=str(out / _checkpoint(formulation)),
        checkpoint_every=args.checkpoint_every, resume=args.resume,
    )
    if args.prony == "auto":
        kw["max_prony"] = args.max_prony
    if getattr(args, "stability_range", None) is not None:
        kw["stability_range"] = args.stability_range
    if formulation != "hereditary":  # the default, left out: the call is today's
        kw["formulation"] = formulation
    if getattr(args, "_shift_law", None) is not None:
        kw["shift_factors"] = args._shift_law
    if getattr(args, "tref", None) is not None:
        kw["T_ref"] = args.tref
    try:
        cal = calibrate(curves, **kw)
    except KeyboardInterrupt:
        progress.close()
        raise FitFailed(
            f"interrupted before a result was ready; continue with: {_resume_cmd(command)}"
            if any(out.glob(CHECKPOINT + "*")) else "interrupted before the search started"
        ) from None
    except CalibrationError as exc:  # no finite fit: the data, law or bounds
        progress.close()
        how = (" (bounds= is a keyword of vhfit.calibrate; on the command line choose "
               "another --model)" if "bounds=" in str(exc) else "")
        if args.resume:
            how += (f"; the checkpoint in {out} holds this failed search and resumes only "
                    "into it: start fresh with --force instead of --resume")
        raise UsageError(f"{one_line(exc)}{how}") from None
    except (ValueError, UsageError):
        progress.close()
        raise
    except Exception as exc:
        progress.close()
        raise FitFailed(f"the fit failed: {one_line(exc)}") from exc
    progress.close()
    return cal


def _checkpoint(formulation: str) -> str:
    return CHECKPOINT if formulation == "hereditary" else f"{CHECKPOINT}.{formulation}"


def _show_warnings(caught: list, shown: list[str]) -> None:
    """Warnings of the run on stderr, one line each, once each (``shown``: in the table)."""
    seen = set(shown)
    for w in caught:
        # the table lists the calibration's own warnings; numerical RuntimeWarnings of
        # trial individuals are noise; data warnings (what the reader assumed) are shown
        if issubclass(w.category, CalibrationWarning) or not issubclass(w.category,
                                                                         UserWarning):
            continue
        msg = one_line(w.message)
        if msg not in seen:
            seen.add(msg)
            print(f"warning: {msg}", file=sys.stderr)


def _resume_cmd(command: list[str]) -> str:
    cmd = [c for c in command if c not in ("--resume", "--force")]
    return shlex.join(["vhfit"] + cmd + ["--resume"])


# ================================================================== outputs
def _write_outputs(fits: dict, plan: dict, curves, inputs, args, out: Path, *, label, command,
                   interrupted, demo) -> dict[str, str]:
    """results JSON, fitted curves CSV, solver cards, plots and summary into ``out``; the
    first fit of ``plan`` is the results' own, the others are listed under ``fits``."""
    cal = next(iter(fits.values()))
    raw, curves = curves, getattr(args, "_at_ref", None) or curves  # tests at T_ref
    written: dict[str, str] = {}
    status = "INTERRUPTED (best so far, not converged)" if interrupted else "complete"
    head = [f"data: {label}"] if label else []
    head.append(f"status: {status}")

    fitted = cal.fitted_curves(curves)
    atomic_write(out / "fitted_curves.csv", _fitted_csv(cal, curves, fitted, label, interrupted))
    written["fitted_curves.csv"] = "data and model stress per curve"
    moduli = [(c, f) for c, f in zip(curves, fitted) if _moduli.is_moduli_fit(f)]
    if moduli:  # frequency sweeps and relaxation tests
        atomic_write(out / _moduli.FILE, _moduli.fitted_moduli_csv(*zip(*moduli)))
        written[_moduli.FILE] = "data and model moduli per sweep or relaxation test"

    cards = write_cards(fits, plan, curves, out, args)
    written.update({f: f"{solver} card" for solver, f in cards.files.items()})
    plots, plot_note = _draw_plots(cal, curves, out, skip=args.no_plot, demo=demo)
    written.update({p: "plot" for p in plots.values()})

    lines = head + [f"WARNING: {w}" for w in cards.warnings] + ["", cal.summary()]
    for form, other in list(fits.items())[1:]:
        lines += ["", f"== the fit in the '{form}' formulation, for "
                      f"{', '.join(plan[form])} ==", other.summary()]
    lines += [""] + cards.summary
    if plot_note:
        lines.append(plot_note)
    text = "\n".join(lines)
    atomic_write(out / "summary.txt", text + "\n")
    written["summary.txt"] = "this table"

    extra = {
        "data_label": label,
        "inputs": inputs,
        "command": ["vhfit"] + list(command),
        "cli_options": _jsonable(vars(args)),
        "seed": args.seed,
        "files": {**written, RESULTS: "this file"},
        "cards": cards.files,
        "card_errors": cards.errors,
        "card_notes": cards.notes,
        "card_fits": cards.fits,
        "card_check": cards.check_dict(),
        "card_check_warnings": cards.warnings,
    }
    if len(plan) > 1:
        extra["fits"] = {f: {"solvers": plan[f], **_fit_record(c)} for f, c in fits.items()}
    cal.save(out / RESULTS, status="interrupted" if interrupted else "complete", curves=raw,
             extra=extra)
    written[RESULTS] = "results"
    written["_summary"] = text
    return written


def _fit_record(cal: Calibration) -> dict:
    """One fit of several in results.json: its constants and errors (no history)."""
    d = cal.to_dict()
    d.pop("history", None)
    d["formulation"] = getattr(cal.model, "formulation", "hereditary")
    return d


def _draw_plots(cal: Calibration, curves, out: Path, *, skip: bool,
                demo: bool) -> tuple[dict[str, str], str | None]:
    """The plots that apply ({kind: file}) and a note on those not drawn."""
    if skip:
        return {}, "plots skipped (--no-plot)"
    if not plot.have_matplotlib():
        return {}, f"plots skipped: {plot.INSTALL_HINT}"
    plots: dict[str, str] = {}
    try:
        if not all(is_moduli(c) for c in curves):
            plot.plot_fit(cal, curves, out / "fit.png",
                          title=None if not demo else
                          f"synthetic SEBS (paper Table 5): {cal.model.hyperelastic.name} + "
                          f"{cal.n_prony} Prony terms, RMSAPE {cal.rmsape:.3g} %")
            plots["fit"] = "fit.png"
        if any(is_moduli(c) for c in curves):  # frequency sweeps, relaxation tests
            plot.plot_moduli_fit(cal, curves, out / "moduli.png")
            plots["moduli"] = "moduli.png"
        if cal.history and cal.history.get("nit"):
            plot.plot_history(cal, out / "history.png")
            plots["history"] = "history.png"
        if cal.order_scan:
            plot.plot_order_scan(cal, out / "order_scan.png")
            plots["order_scan"] = "order_scan.png"
    except Exception as exc:
        return plots, f"plots failed: {one_line(exc)}"
    return plots, None


def _jsonable(d: dict) -> dict:
    out = {k: v for k, v in d.items() if not k.startswith("_") and not callable(v)}
    for later in ("deformation", "formulation", "tref", "shift"):
        if out.get(later, "") is None:  # not given: the record is as before the flag
            del out[later]
    return out


def _fitted_csv(cal: Calibration, curves, fits, label, interrupted) -> str:
    buf = io.StringIO()
    buf.write("# vhfit fitted curves: data and calibrated model, per curve\n")
    if label:
        buf.write(f"# data: {label}\n")
    buf.write(f"# model: {cal.model.hyperelastic.name} + {cal.n_prony} Prony term(s); "
              f"RMSAPE {cal.rmsape:.6g} %" + ("; INTERRUPTED" if interrupted else "") + "\n")
    buf.write("# kind=point: objective points (stress_data = data, stress_model = model); "
              "kind=fine: model on a fine time grid (stress_data empty)\n")
    buf.write("# units: s, engineering strain, MPa (in each curve's measure)\n")
    # other tests than the paper's add two columns: the test, and the loaded direction
    modes = any(getattr(c, "deformation", "uniaxial") != "uniaxial" for c in curves)
    if modes:
        buf.write("# deformation: the test; direction: 1, or 2 for the second stress of a "
                  "biaxial/equibiaxial curve; equilibrium curves: time = sample number, "
                  "strain_rate empty; simple shear: strain = amount of shear γ\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["curve", "strain_rate", "measure", "kind", "time", "strain", "stress_data",
                "stress_model"] + (["deformation", "direction"] if modes else []))
    for c, f in zip(curves, fits):
        if _moduli.is_moduli_fit(f):  # in fitted_moduli.csv
            continue
        name = str(getattr(c, "name", ""))
        r = getattr(c, "strain_rate", float("nan"))
        rate = "" if r is None else f"{float(r):g}"
        meas = getattr(c, "measure", "true")
        dfm = [getattr(c, "deformation", "uniaxial")] if modes else []
        dirs = getattr(c, "target_direction", np.ones(len(f["time"]), dtype=int))
        for t, e, s, m, d in zip(f["time"], f["strain"], f["stress"], f["model"], dirs):
            w.writerow([name, rate, meas, "point", f"{t:.9g}", f"{e:.9g}", f"{s:.9g}", f"{m:.9g}"]
                       + (dfm + [int(d)] if modes else []))
        for t, e, m in zip(f["fine_time"], f["fine_strain"], f["fine_model"]):
            w.writerow([name, rate, meas, "fine", f"{t:.9g}", f"{e:.9g}", "", f"{m:.9g}"]
                       + (dfm + [1] if modes else []))
    return buf.getvalue()
