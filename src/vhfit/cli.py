"""The ``vhfit`` command line: fit, demo, simulate, export, models.

Run ``vhfit --help`` or ``python -m vhfit --help``; docs/cli.md documents every
command, flag, file and exit code. Exit codes:

* 0 — success;
* 1 — the fit failed, or was interrupted (outputs are still written, marked
  "interrupted", and the message says how to ``--resume``);
* 2 — bad input (a file, a flag, an option): one line naming the file and the fix.

Errors are one line on stderr (``vhfit: error: ...``), never a traceback; ``--debug``
shows the traceback instead.
"""

from __future__ import annotations

import argparse
import csv
import glob
import hashlib
import importlib
import inspect
import io
import json
import math
import os
import shlex
import signal
import sys
import time
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TextIO

import numpy as np

__all__ = ["main", "load_plugins", "EXIT_OK", "EXIT_FAILED", "EXIT_USAGE"]

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_USAGE = 2

PLUGIN_GROUP = "vhfit.models"
SOLVERS = ("abaqus", "lsdyna", "ansys")
CARD_FILES = {"abaqus": "abaqus.inp", "lsdyna": "lsdyna.k", "ansys": "ansys.mac",
              "json": "material.json"}
RESULTS = "results.json"
CHECKPOINT = "checkpoint.json"
DEMO_PRONY = 4
DEMO_STRATEGY = "semifree"


class UsageError(Exception):
    """Bad input on the command line or in a file: exit code 2, one-line message."""


class FitFailed(Exception):
    """The calibration could not produce a result: exit code 1."""


# ==================================================================== plug-ins
def load_plugins(strict: bool = False) -> list[dict[str, Any]]:
    """Import the hyperelastic models that installed packages declare as plug-ins.

    A package registers models through the entry-point group ``vhfit.models``; each
    entry point names a module whose import registers models with
    :func:`vhfit.hyperelastic.register` (``gent = "mypkg.models"``), or a function
    with no required arguments that registers them when called
    (``gent = "mypkg.models:register_all"``).

    Parameters
    ----------
    strict : bool
        Raise if a plug-in fails to load (default: report it and go on).

    Returns
    -------
    list of dict
        One per entry point: ``name``, ``value``, ``distribution``, ``models`` (the
        model names it registered) and ``error`` (None, or the message).
    """
    from importlib.metadata import entry_points

    from vhfit import hyperelastic

    out = []
    for ep in entry_points(group=PLUGIN_GROUP):
        before = set(hyperelastic.available())
        info = {"name": ep.name, "value": ep.value, "models": [], "error": None,
                "distribution": getattr(getattr(ep, "dist", None), "name", None)}
        try:
            obj = ep.load()
            if inspect.isfunction(obj) and not any(
                p.default is p.empty and p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)
                for p in inspect.signature(obj).parameters.values()
            ):
                obj()
        except Exception as exc:  # a broken plug-in must not break vhfit
            if strict:
                raise
            info["error"] = f"{type(exc).__name__}: {exc}"
        info["models"] = sorted(set(hyperelastic.available()) - before)
        out.append(info)
    return out


def _resolve_model_name(name: str) -> str:
    """A registered model name, loading plug-ins if it is not (yet) known."""
    from vhfit import hyperelastic

    if name in hyperelastic.available():
        return name
    plugins = load_plugins()
    if name in hyperelastic.available():
        return name
    broken = [f"{p['name']} ({p['error']})" for p in plugins if p["error"]]
    hint = f"; plug-ins that failed to load: {', '.join(broken)}" if broken else ""
    raise UsageError(
        f"unknown model {name!r}: choose one of {', '.join(hyperelastic.available())} "
        f"(see 'vhfit models'){hint}"
    )


def _tau_strategies() -> list[str]:
    try:
        from vhfit.optimize import tau_strategies
    except ImportError:
        return ["free", "semifree", "fixed"]
    return list(tau_strategies())


# ==================================================================== helpers
def _sha256(path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _write(path: Path, text: str) -> None:
    from vhfit._io import atomic_write

    atomic_write(path, text)


def _one_line(exc: BaseException) -> str:
    text = str(exc) or type(exc).__name__
    if isinstance(exc, (OSError,)) and getattr(exc, "filename", None):
        text = f"{exc.filename}: {exc.strerror or text}"
    return " ".join(part.strip() for part in text.splitlines() if part.strip())


def _is_tty(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


def _prepare_out(out: str | None, default: str, *, force: bool, resume: bool) -> Path:
    """The output folder: created, and never a non-empty one unless asked.

    With no ``--out``, the default name is used, or ``NAME-2``, ``NAME-3``, ... if it
    is taken (a fresh folder every run); an explicit non-empty ``--out`` needs
    ``--force`` (overwrite) or ``--resume``.
    """
    if out is None:
        path = Path(default)
        if not resume:
            k = 2
            while path.exists() and (not path.is_dir() or any(path.iterdir())):
                path = Path(f"{default}-{k}")
                k += 1
    else:
        path = Path(out)
    if path.exists() and not path.is_dir():
        raise UsageError(f"--out {path}: exists and is not a folder; choose another --out")
    if resume:
        if not path.is_dir():
            raise UsageError(
                f"--resume: output folder {path} does not exist; give the --out of the "
                "interrupted run"
            )
        return path
    if path.is_dir() and any(path.iterdir()) and not force:
        raise UsageError(
            f"output folder {path} is not empty: choose another --out, add --force to "
            "overwrite it, or --resume to continue an interrupted fit there"
        )
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UsageError(f"--out {path}: cannot create the folder ({exc.strerror})") from None
    return path


# ================================================================== progress
class Progress:
    """Live progress of a fit: one updating line on a terminal, periodic lines otherwise.

    Parameters
    ----------
    stream : text stream
        Where to write (stderr).
    quiet : bool
        Write nothing.
    every : float
        Seconds between lines when ``stream`` is not a terminal.
    scan : bool
        The fit scans the number of Prony terms: N is shown, from the callback's
        ``n_prony`` if it has one, else counted (a restart of the generation count
        means the next N, starting from ``first_n``; None hides N).
    """

    def __init__(self, stream: TextIO, *, quiet: bool = False, every: float = 2.0,
                 scan: bool = False, first_n: int | None = 1):
        self.stream = stream
        self.quiet = quiet
        self.tty = _is_tty(stream)
        self.every = every
        self.scan = scan
        self.n = first_n
        self.last_gen = 0
        self.last_print = -math.inf
        self.width = 0
        self.last: dict | None = None

    def _text(self, d: dict) -> str:
        n = d.get("n_prony", self.n)
        pre = f"N={n}  " if self.scan and n is not None else ""
        return (
            f"{pre}generation {d['generation']:>5}  best {d['best']:.4g} %  "
            f"mean {d['mean']:.4g} %  elapsed {d['elapsed']:.1f} s"
        )

    def __call__(self, d: dict) -> None:
        if d["generation"] < self.last_gen and self.n is not None:
            self.n += 1
        self.last_gen = d["generation"]
        self.last = d
        if self.quiet:
            return
        now = time.perf_counter()
        if self.tty:
            if now - self.last_print >= 0.1:
                text = self._text(d)
                self.stream.write("\r" + text.ljust(self.width))
                self.stream.flush()
                self.width = len(text)
                self.last_print = now
        elif now - self.last_print >= self.every:
            self.stream.write(self._text(d) + "\n")
            self.stream.flush()
            self.last_print = now

    def close(self) -> None:
        """End the updating line (terminal) or print the last state (not a terminal)."""
        if self.quiet or self.last is None:
            return
        if self.tty:
            self.stream.write("\r" + self._text(self.last).ljust(self.width) + "\n")
        else:
            self.stream.write(self._text(self.last) + "\n")
        self.stream.flush()


class _Signals:
    """SIGINT/SIGTERM handling around a fit.

    The first signal asks the search to stop at the end of the current generation
    (the progress callback then raises KeyboardInterrupt, which :func:`vhfit.calibrate`
    catches to return the best individual so far): stopping on a generation boundary
    keeps the checkpoint consistent, so ``--resume`` reaches exactly the result of an
    uninterrupted run. A second signal interrupts at once. While the outputs are
    written, signals are deferred (the third one aborts anyway), so that an
    interrupted fit still leaves complete files.
    """

    def __init__(self):
        self.count = 0
        self.writing = False
        self.stopped_search = False
        self.old: dict = {}

    def __enter__(self):
        for sig in (signal.SIGINT, signal.SIGTERM):
            try:
                self.old[sig] = signal.signal(sig, self._handler)
            except (ValueError, OSError):  # not the main thread
                pass
        return self

    def __exit__(self, *exc):
        for sig, old in self.old.items():
            signal.signal(sig, old)
        return False

    @property
    def hit(self) -> bool:
        return self.count > 0

    def _handler(self, signum, frame):
        self.count += 1
        if self.writing:
            if self.count < 3:
                sys.stderr.write("\nvhfit: interrupted: finishing the output files...\n")
                return
        elif self.count == 1:
            sys.stderr.write("\nvhfit: interrupted: stopping after this generation and "
                             "writing the outputs (interrupt again to stop at once)\n")
            return
        raise KeyboardInterrupt

    def check(self) -> None:
        """Called at each generation boundary: stop the search if a signal came."""
        if self.count and not self.writing:
            self.stopped_search = True
            raise KeyboardInterrupt


# ============================================================ reading inputs
def _read_curves(paths: Sequence[str], args) -> tuple[list, list[dict]]:
    from vhfit.data import read_csv

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
            return c.trim(strain=windows["strain"].get(src), time=windows["time"].get(src))

        curves = [trimmed(c) for c in curves]
    inputs = [{"path": os.path.abspath(f), "sha256": _sha256(f)} for f in files]
    return curves, inputs


def _points(text: str) -> int | None:
    if text.lower() in ("all", "none"):
        return None
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"--points {text!r}: give a whole number >= 2 or 'all'"
        ) from None
    if n < 2:
        raise argparse.ArgumentTypeError(f"--points {n}: give at least 2 (or 'all')")
    return n


def _ramp_points(text: str) -> int:
    n = _points(text)
    if n is None:
        raise argparse.ArgumentTypeError("--points: give a whole number >= 2")
    return n


def _prony(text: str) -> int | str:
    if text.lower() == "auto":
        return "auto"
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"--prony {text!r}: give the number of Prony terms (e.g. 3) or 'auto'"
        ) from None
    if n < 0:
        raise argparse.ArgumentTypeError(f"--prony {n}: give a whole number >= 0 or 'auto'")
    return n


def _window(what: str) -> Callable[[str], tuple[float | None, float | None] | None]:
    def conv(text: str) -> tuple[float | None, float | None] | None:
        lo, sep, hi = text.partition(":")
        if not sep:
            raise argparse.ArgumentTypeError(
                f"{what} {text!r}: give LOW:HIGH, either side may be empty (e.g. :120)")
        number = _float(what)
        out = tuple(number(v) if v.strip() else None for v in (lo, hi))
        if out[0] is not None and out[1] is not None and not out[0] < out[1]:
            raise argparse.ArgumentTypeError(f"{what} {text!r}: LOW must be below HIGH")
        return None if out == (None, None) else out

    return conv


def _positive(kind: type, what: str) -> Callable[[str], Any]:
    def conv(text: str):
        try:
            v = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{what} {text!r}: not a {kind.__name__}") from None
        if not v > 0:
            raise argparse.ArgumentTypeError(f"{what} {text!r}: must be > 0")
        return v

    return conv


def _float(what: str) -> Callable[[str], float]:
    def conv(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{what} {text!r}: not a number") from None
        if not math.isfinite(v):
            raise argparse.ArgumentTypeError(f"{what} {text!r}: must be finite")
        return v

    return conv


# ================================================================ the fit job
def _run_fit(curves, inputs, args, out: Path, *, label: str | None, command: list[str],
             demo: bool = False) -> int:
    """Calibrate, then write every output into ``out`` (also when interrupted)."""
    from vhfit.calibration import calibrate

    model = _resolve_model_name(args.model)
    strategy = args.strategy
    if strategy not in _tau_strategies():
        raise UsageError(
            f"--strategy {strategy!r}: choose one of {', '.join(_tau_strategies())}"
        )
    ckpt = out / CHECKPOINT
    if args.resume and not any(out.glob(CHECKPOINT + "*")):
        raise UsageError(
            f"--resume: no checkpoint in {out} (the fit ended, or never started there); "
            "drop --resume to fit afresh"
        )
    say = (lambda *a: None) if args.quiet else (lambda msg: print(msg, file=sys.stderr,
                                                                  flush=True))
    n_txt = f"auto (N = 1..{args.max_prony})" if args.prony == "auto" else str(args.prony)
    say(
        f"fitting {model} + {n_txt} Prony term(s), tau strategy {strategy}, seed {args.seed}, "
        f"to {len(curves)} curve(s); outputs in {out}/" + (" (resuming)" if args.resume else "")
    )
    # a resumed scan starts mid-way: N cannot be counted from the generations then
    progress = Progress(sys.stderr, quiet=args.quiet, scan=args.prony == "auto",
                        first_n=None if args.resume else 1)
    sigs = _Signals()

    def callback(d):
        progress(d)
        sigs.check()  # raises KeyboardInterrupt (caught by calibrate) after a signal
        return False

    kw = dict(
        hyperelastic=model, n_prony=args.prony, tau_strategy=strategy, method=args.method,
        seed=args.seed, workers=args.workers, popsize=args.popsize, maxiter=args.maxiter,
        target=args.target, polish=not args.no_polish, g_inf_min=args.g_inf_min,
        max_time=args.max_time, callback=callback, checkpoint=str(ckpt),
        checkpoint_every=args.checkpoint_every, resume=args.resume,
    )
    if args.prony == "auto":
        kw["max_prony"] = args.max_prony
    with sigs, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            cal = calibrate(curves, **kw)
        except KeyboardInterrupt:
            progress.close()
            raise FitFailed(
                f"interrupted before a result was ready; continue with: {_resume_cmd(command)}"
                if any(out.glob(CHECKPOINT + "*")) else "interrupted before the search started"
            ) from None
        except (ValueError, UsageError):
            progress.close()
            raise
        except Exception as exc:
            progress.close()
            raise FitFailed(f"the fit failed: {_one_line(exc)}") from exc
        progress.close()
        interrupted = cal.stop_reason == "interrupted" or sigs.stopped_search
        sigs.writing = True
        files = _write_outputs(cal, curves, inputs, args, out, label=label, command=command,
                               interrupted=interrupted, demo=demo)
    from vhfit.calibration import CalibrationWarning

    seen = set(cal.warnings)
    for w in caught:
        # the table lists the calibration's own warnings; numerical RuntimeWarnings of
        # trial individuals are noise; data warnings (what the reader assumed) are shown
        if issubclass(w.category, CalibrationWarning) or not issubclass(w.category,
                                                                         UserWarning):
            continue
        msg = _one_line(w.message)
        if msg not in seen:
            seen.add(msg)
            print(f"warning: {msg}", file=sys.stderr)
    print(files.pop("_summary"))
    print("")
    print(f"outputs in {out}/: " + ", ".join(sorted(files)))
    if not np.isfinite(cal.rmsape):
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


def _resume_cmd(command: list[str]) -> str:
    cmd = [c for c in command if c not in ("--resume", "--force")]
    return shlex.join(["vhfit"] + cmd + ["--resume"])


def _write_outputs(cal, curves, inputs, args, out: Path, *, label, command, interrupted,
                   demo) -> dict[str, str]:
    """results JSON, fitted curves CSV, solver cards, plots and summary into ``out``."""
    from vhfit import plot

    written: dict[str, str] = {}
    status = "INTERRUPTED (best so far, not converged)" if interrupted else "complete"
    head = []
    if label:
        head.append(f"data: {label}")
    head.append(f"status: {status}")
    summary = "\n".join(head + ["", cal.summary()])

    fits = cal.fitted_curves(curves)
    _write(out / "fitted_curves.csv", _fitted_csv(cal, curves, fits, label, interrupted))
    written["fitted_curves.csv"] = "data and model stress per curve"

    cards_ok, card_errors, card_notes = {}, {}, {}
    for solver in SOLVERS + ("json",):
        try:
            with warnings.catch_warnings(record=True) as ws:
                warnings.simplefilter("always")
                text = _card(cal, solver)
        except Exception as exc:  # a solver that cannot take this model is not fatal
            card_errors[solver] = _one_line(exc)
            continue
        notes = list(dict.fromkeys(_one_line(w.message) for w in ws))
        if notes:
            card_notes[solver] = notes
        _write(out / CARD_FILES[solver], text)
        cards_ok[solver] = CARD_FILES[solver]
        written[CARD_FILES[solver]] = f"{solver} card"

    plots, plot_note = {}, None
    if args.no_plot:
        plot_note = "plots skipped (--no-plot)"
    elif not plot.have_matplotlib():
        plot_note = f"plots skipped: {plot.INSTALL_HINT}"
    else:
        try:
            plot.plot_fit(cal, curves, out / "fit.png",
                          title=None if not demo else
                          f"synthetic SEBS (paper Table 5): {cal.model.hyperelastic.name} + "
                          f"{cal.n_prony} Prony terms, RMSAPE {cal.rmsape:.3g} %")
            plots["fit"] = "fit.png"
            if cal.history and cal.history.get("nit"):
                plot.plot_history(cal, out / "history.png")
                plots["history"] = "history.png"
            if cal.order_scan:
                plot.plot_order_scan(cal, out / "order_scan.png")
                plots["order_scan"] = "order_scan.png"
        except Exception as exc:
            plot_note = f"plots failed: {_one_line(exc)}"
    for p in plots.values():
        written[p] = "plot"

    lines = [summary, ""]
    if cards_ok:
        lines.append("solver cards: " + ", ".join(f"{k} -> {v}" for k, v in cards_ok.items()))
    for k, v in card_notes.items():
        lines += [f"note ({k} card): {n}" for n in v]
    for k, v in card_errors.items():
        lines.append(f"no {k} card: {v}")
    if plot_note:
        lines.append(plot_note)
    text = "\n".join(lines)
    _write(out / "summary.txt", text + "\n")
    written["summary.txt"] = "this table"

    cal.save(out / RESULTS, status="interrupted" if interrupted else "complete", curves=curves,
             extra={
                 "data_label": label,
                 "inputs": inputs,
                 "command": ["vhfit"] + list(command),
                 "cli_options": _jsonable(vars(args)),
                 "seed": args.seed,
                 "files": {**written, RESULTS: "this file"},
                 "cards": cards_ok,
                 "card_errors": card_errors,
                 "card_notes": card_notes,
             })
    written[RESULTS] = "results"
    written["_summary"] = text
    return written


def _jsonable(d: dict) -> dict:
    return {k: v for k, v in d.items() if not k.startswith("_") and not callable(v)}


def _fitted_csv(cal, curves, fits, label, interrupted) -> str:
    buf = io.StringIO()
    buf.write("# vhfit fitted curves: data and calibrated model, per curve\n")
    if label:
        buf.write(f"# data: {label}\n")
    buf.write(f"# model: {cal.model.hyperelastic.name} + {cal.n_prony} Prony term(s); "
              f"RMSAPE {cal.rmsape:.6g} %" + ("; INTERRUPTED" if interrupted else "") + "\n")
    buf.write("# kind=point: objective points (stress_data = data, stress_model = model); "
              "kind=fine: model on a fine time grid (stress_data empty)\n")
    buf.write("# units: s, engineering strain, MPa (in each curve's measure)\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["curve", "strain_rate", "measure", "kind", "time", "strain", "stress_data",
                "stress_model"])
    for c, f in zip(curves, fits):
        name = str(getattr(c, "name", ""))
        rate = f"{float(getattr(c, 'strain_rate', float('nan'))):g}"
        meas = getattr(c, "measure", "true")
        for t, e, s, m in zip(f["time"], f["strain"], f["stress"], f["model"]):
            w.writerow([name, rate, meas, "point", f"{t:.9g}", f"{e:.9g}", f"{s:.9g}", f"{m:.9g}"])
        for t, e, m in zip(f["fine_time"], f["fine_strain"], f["fine_model"]):
            w.writerow([name, rate, meas, "fine", f"{t:.9g}", f"{e:.9g}", "", f"{m:.9g}"])
    return buf.getvalue()


def _card(cal_or_results, solver: str, **kw) -> str:
    """Solver card text from a Calibration or a results mapping."""
    try:
        export = importlib.import_module("vhfit.export")
    except ImportError as exc:
        raise FitFailed(f"vhfit.export is not available ({exc})") from None
    fn = getattr(export, f"to_{solver}", None)
    if fn is None:
        try:
            fn = importlib.import_module(f"vhfit.export.{solver}").__dict__[f"to_{solver}"]
        except (ImportError, KeyError):
            raise FitFailed(f"this vhfit has no {solver} exporter") from None
    return fn(cal_or_results, **kw)


# ================================================================== commands
def cmd_fit(args) -> int:
    """``vhfit fit CURVES...``."""
    if args.force and args.resume:
        raise UsageError("--force and --resume contradict each other: give one")
    out = _prepare_out(args.out, "vhfit-results", force=args.force, resume=args.resume)
    curves, inputs = _read_curves(args.curves, args)
    return _run_fit(curves, inputs, args, out, label=None, command=args._argv)


def cmd_demo(args) -> int:
    """``vhfit demo``: the bundled synthetic SEBS set, end to end."""
    from vhfit import datasets

    if args.force and args.resume:
        raise UsageError("--force and --resume contradict each other: give one")
    out = _prepare_out(args.out, "vhfit-demo", force=args.force, resume=args.resume)
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
    code = _run_fit(curves, inputs, args, out, label=datasets.SEBS_LABEL, command=args._argv,
                    demo=True)
    if code == EXIT_OK:
        _demo_check(out, datasets)
    return code


def _demo_check(out: Path, datasets) -> None:
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


def cmd_simulate(args) -> int:
    """``vhfit simulate``: stress of a given material along given loadings, to CSV."""
    from vhfit.history import History
    from vhfit.model import ViscoHyperelastic

    if args.results is None and args.model is None:
        raise UsageError("simulate needs a material: --results RESULTS.json, or --model NAME "
                         "with --param NAME=VALUE for each constant")
    params: dict[str, float] = {}
    source = ""
    if args.results is not None:
        res = _load_results(args.results)
        name = args.model or res["hyperelastic"]
        params = dict(res["params"])
        source = f"results {args.results}"
    else:
        name = args.model
        source = "command line"
    for item in args.param or []:
        params.update(_parse_params(item))
    name = _resolve_model_name(name)
    n_prony = _count_prony(params)
    try:
        model = ViscoHyperelastic(name, n_prony)
        x = model.check(params)
    except ValueError as exc:
        raise UsageError(f"parameters: {_one_line(exc)}") from None
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
            raise UsageError(f"--rate {r:g} --strain-max {emax:g}: {_one_line(exc)}") from None
        loads.append((f"rate {r:g} 1/s", r, h))
    for path in args.history or []:
        t, e = _read_history(path)
        try:
            h = History.piecewise_linear(t, e)
        except ValueError as exc:
            raise UsageError(f"{path}: {_one_line(exc)}") from None
        loads.append((Path(path).name, float("nan"), h))
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
            raise UsageError(f"{label}: {_one_line(exc)}") from None
        rate = f"{r:g}" if math.isfinite(r) else ""
        for t, e, v in zip(h.out_time, h.out_strain, s):  # (+ 0.0: no "-0" in the file)
            w.writerow([label, rate, f"{t + 0.0:.9g}", f"{e + 0.0:.9g}", f"{v + 0.0:.9g}"])
    _emit(buf.getvalue(), args.out, what="simulated curves")
    return EXIT_OK


def _emit(text: str, out: str | None, *, what: str) -> None:
    if out in (None, "-"):
        sys.stdout.write(text)
        return
    try:
        parent = Path(out).resolve().parent
        if not parent.is_dir():
            raise UsageError(f"--out {out}: folder {parent} does not exist; create it first")
        _write(Path(out), text)
    except OSError as exc:
        raise UsageError(f"--out {out}: cannot write ({exc.strerror})") from None
    print(f"wrote {what} to {out}", file=sys.stderr)


def _parse_params(item: str) -> dict[str, float]:
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


def _count_prony(params: dict) -> int:
    idx = set()
    for k in params:
        for pre in ("G", "tau"):
            if k.startswith(pre) and k[len(pre):].isdigit():
                idx.add(int(k[len(pre):]))
    n = max(idx) if idx else 0
    missing = [f"{p}{i}" for i in range(1, n + 1) for p in ("G", "tau") if f"{p}{i}" not in params]
    if missing:
        raise UsageError(f"Prony terms need G_i and tau_i for i = 1..{n}: missing "
                         f"{', '.join(missing)} (give them with --param)")
    return n


def _read_history(path: str) -> tuple[np.ndarray, np.ndarray]:
    """(time, strain) columns of a history CSV: named ``time*``/``strain*``, else the first two."""
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


def _load_results(path: str) -> dict:
    try:
        with open(path, encoding="utf-8") as f:
            res = json.load(f)
    except OSError as exc:
        raise UsageError(f"{path}: cannot read ({exc.strerror}); give the results.json "
                         "written by 'vhfit fit' or 'vhfit demo'") from None
    except ValueError as exc:
        raise UsageError(f"{path}: not valid JSON ({exc}); give the results.json written "
                         "by 'vhfit fit' or 'vhfit demo'") from None
    if not isinstance(res, dict) or "params" not in res or "hyperelastic" not in res:
        raise UsageError(f"{path}: not a vhfit results file (no 'hyperelastic' and 'params'); "
                         "give the results.json written by 'vhfit fit' or 'vhfit demo'")
    return res


def cmd_export(args) -> int:
    """``vhfit export RESULTS.json --to SOLVER``."""
    from vhfit.model import ViscoHyperelastic

    res = _load_results(args.results)
    name = _resolve_model_name(res["hyperelastic"])
    params = res["params"]
    try:
        model = ViscoHyperelastic(name, _count_prony(params))
        model.check(params)
    except ValueError as exc:
        raise UsageError(f"{args.results}: {_one_line(exc)}") from None
    kw = {}
    if args.name:
        kw["name"] = args.name
    try:
        text = _card(_ModelParams(model, params), args.to, **kw)
    except ValueError as exc:
        raise UsageError(f"--to {args.to}: {_one_line(exc)}") from None
    if not text.endswith("\n"):
        text += "\n"
    _emit(text, args.out, what=f"{args.to} card")
    return EXIT_OK


class _ModelParams:
    """What the exporters accept: an object with ``.model`` and ``.params``."""

    def __init__(self, model, params):
        self.model, self.params = model, dict(params)


def cmd_models(args) -> int:
    """``vhfit models``: registered models, τ strategies, plug-ins."""
    from vhfit import hyperelastic

    builtin = set(hyperelastic.available())
    plugins = load_plugins()
    origin = {m: f"plug-in {p['name']} ({p['value']})" for p in plugins for m in p["models"]}
    models = []
    for name in hyperelastic.available():
        hm = hyperelastic.get(name)
        models.append({
            "name": name,
            "parameters": [{"name": n, "unit": u} for n, u in zip(hm.param_names, hm.units)],
            "kind": hm.kind,
            "linear": bool(hm.linear),
            "origin": "built-in" if name in builtin and name not in origin else
                      origin.get(name, "registered"),
            "doc": (hm.doc or "").strip().splitlines()[0] if hm.doc else "",
        })
    strategies = _tau_strategies()
    if args.json:
        print(json.dumps({"models": models, "tau_strategies": strategies, "plugins": plugins,
                          "plugin_group": PLUGIN_GROUP}, indent=2))
        return EXIT_OK
    print("hyperelastic models (vhfit fit --model NAME):")
    w = max(len(m["name"]) for m in models)
    for m in models:
        pars = ", ".join(f"{p['name']} [{p['unit']}]" for p in m["parameters"])
        tag = "" if m["origin"] == "built-in" else f"   <- {m['origin']}"
        print(f"  {m['name']:<{w}}  {pars}{tag}")
        if m["doc"]:
            print(f"  {'':<{w}}    {m['doc']}")
    print("")
    print("Prony terms add G_i [MPa] and tau_i [s] for i = 1..N (vhfit fit --prony N|auto)")
    print("")
    print("tau strategies (vhfit fit --strategy NAME): " + ", ".join(strategies))
    print("")
    if plugins:
        print(f"plug-ins (entry-point group '{PLUGIN_GROUP}'):")
        for p in plugins:
            state = (f"error: {p['error']}" if p["error"] else
                     "models: " + (", ".join(p["models"]) or "none new"))
            print(f"  {p['name']} = {p['value']}   {state}")
    else:
        print(f"plug-ins: none installed (a package adds models through the entry-point "
              f"group '{PLUGIN_GROUP}'; see docs/cli.md)")
    return EXIT_OK


# ==================================================================== parser
class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit code 2)."""

    def error(self, message: str):  # noqa: D401 - argparse API
        raise UsageError(f"{message} (see '{self.prog} --help')")


def _add_fit_options(p: argparse.ArgumentParser, *, demo: bool) -> None:
    if not demo:
        p.add_argument("--model", default="mooney_rivlin",
                       help="hyperelastic model (default mooney_rivlin; see 'vhfit models')")
    p.add_argument("--prony", type=_prony, default=DEMO_PRONY if demo else 2, metavar="N|auto",
                   help=f"number of Prony terms, or 'auto' to scan N = 1..--max-prony "
                        f"(default {DEMO_PRONY if demo else 2})")
    p.add_argument("--max-prony", type=int, default=5, metavar="N",
                   help="largest N of --prony auto (default 5)")
    if not demo:
        p.add_argument("--strategy", default="free",
                       help="tau strategy: free, semifree or fixed (default free; "
                            "see 'vhfit models')")
    p.add_argument("--method", choices=("separable", "full"), default="separable",
                   help="separable (DE over tau + NNLS for moduli, default) or full "
                        "(the paper's all-parameter DE)")
    p.add_argument("--seed", type=int, default=0,
                   help="random seed of the search (default 0: runs are reproducible)")
    p.add_argument("--out", metavar="DIR",
                   help="output folder (default ./vhfit-{}, or -2, -3... if taken)".format(
                       "demo" if demo else "results"))
    p.add_argument("--force", action="store_true", help="write into a non-empty --out")
    p.add_argument("--resume", action="store_true",
                   help="continue an interrupted fit from the checkpoint in --out "
                        "(same command otherwise)")
    p.add_argument("--popsize", type=_positive(int, "--popsize"),
                   help="population size (absolute; default 64 separable, 60 full)")
    p.add_argument("--maxiter", type=_positive(int, "--maxiter"),
                   help="generation cap (default 1000 separable, 100000 full)")
    p.add_argument("--max-time", type=_positive(float, "--max-time"), metavar="SECONDS",
                   help="stop the search after this many seconds with the best so far")
    p.add_argument("--target", type=_float("--target"), default=1e-4, metavar="PERCENT",
                   help="stop as soon as RMSAPE <= this (percent, default 1e-4)")
    p.add_argument("--g-inf-min", type=_float("--g-inf-min"), default=1e-6,
                   help="floor on g_inf (FE solvers reject 0; default 1e-6)")
    p.add_argument("--workers", type=_positive(int, "--workers"), default=1,
                   help="parallel processes for the full method (default 1)")
    p.add_argument("--no-polish", action="store_true",
                   help="skip the final least-squares polish")
    p.add_argument("--checkpoint-every", type=_positive(float, "--checkpoint-every"),
                   default=5.0, metavar="SECONDS",
                   help="seconds between checkpoints for --resume (default 5)")
    p.add_argument("--no-plot", action="store_true", help="do not draw plots")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")


def build_parser() -> argparse.ArgumentParser:
    """The ``vhfit`` argument parser (all sub-commands)."""
    from vhfit import __version__

    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--debug", action="store_true",
                        help="show a traceback instead of a one-line error")
    parser = _Parser(
        prog="vhfit", parents=[common],
        description="Calibrate visco-hyperelastic models (hyperelastic law + Prony series) to "
                    "stress-strain curves at several strain rates.",
        epilog="Start with 'vhfit demo'. Exit codes: 0 success, 1 fit failed or interrupted, "
               "2 bad input. Docs: docs/cli.md.",
    )
    parser.add_argument("--version", action="version", version=f"vhfit {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    p = sub.add_parser("fit", parents=[common], help="calibrate a model to CSV curves",
                       description="Calibrate a model to stress-strain curves (CSV) and write "
                                   "results JSON, fitted curves, solver cards and plots.")
    p.add_argument("curves", nargs="+", metavar="CURVES",
                   help="CSV files: one curve per file, or long files with a strain_rate column")
    p.add_argument("--rate", type=_float("--rate"), action="append", metavar="R",
                   help="strain rate in 1/s for files without one (once for all, or once "
                        "per file)")
    p.add_argument("--measure", choices=("engineering", "true"),
                   help="stress measure when the file does not say (default engineering)")
    p.add_argument("--points", type=_points, default=10, metavar="N|all",
                   help="objective points per curve (default 10, the paper's; 'all' = every "
                        "sample)")
    p.add_argument("--trim-strain", type=_window("--trim-strain"), metavar="LOW:HIGH",
                   action="append",
                   help="compare model and data only where LOW <= strain <= HIGH (signed; "
                        "either side may be empty, e.g. -0.4: ); once for all files or once "
                        "per file; the history keeps all data")
    p.add_argument("--trim-time", type=_window("--trim-time"), metavar="LOW:HIGH",
                   action="append",
                   help="compare only where LOW <= time (s) <= HIGH, e.g. :120 to leave out "
                        "a slack end of unloading; once for all files or once per file")
    _add_fit_options(p, demo=False)
    p.set_defaults(func=cmd_fit)

    p = sub.add_parser("demo", parents=[common],
                       help="calibrate the bundled synthetic SEBS set end to end",
                       description="Calibrate Mooney-Rivlin + 4 Prony terms (semifree) to the "
                                   "bundled synthetic SEBS curves (generated from the paper's "
                                   "Table 5 parameters at -0.0018, -0.18, -59.5, -820 1/s) and "
                                   "write every output into a fresh folder.")
    _add_fit_options(p, demo=True)
    p.set_defaults(func=cmd_demo)

    p = sub.add_parser("simulate", parents=[common], help="stress-strain curves of a material",
                       description="Stress of a material along constant-rate ramps or measured "
                                   "histories, as CSV.")
    p.add_argument("--results", metavar="RESULTS.json", help="material from a results file")
    p.add_argument("--model", help="hyperelastic model (with --param)")
    p.add_argument("--param", action="append", metavar="NAME=VALUE[,NAME=VALUE...]",
                   help="a constant (repeatable): C10=0.1, G1=1, tau1=0.01 ...; overrides "
                        "--results")
    p.add_argument("--rate", type=_float("--rate"), action="append", metavar="R",
                   help="constant engineering strain rate in 1/s (repeatable)")
    p.add_argument("--strain-max", type=_float("--strain-max"), metavar="E",
                   help="final engineering strain of the ramps (default -0.5 or 0.5, the "
                        "rate's sign)")
    p.add_argument("--points", type=_ramp_points, default=50, metavar="N",
                   help="points per ramp, from rest (default 50)")
    p.add_argument("--history", action="append", metavar="FILE.csv",
                   help="a strain history with time (s) and strain columns (repeatable)")
    p.add_argument("--measure", choices=("engineering", "true"), default="engineering",
                   help="stress measure (default engineering)")
    p.add_argument("--out", metavar="FILE.csv", help="output CSV (default: standard output)")
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("export", parents=[common], help="solver card of a results file",
                       description="Write the material card of a results file for an FE "
                                   "solver.")
    p.add_argument("results", metavar="RESULTS.json")
    p.add_argument("--to", required=True, choices=SOLVERS + ("json",),
                   help="abaqus, lsdyna, ansys or json")
    p.add_argument("--name", help="material name in the card")
    p.add_argument("--out", metavar="FILE", help="output file (default: standard output)")
    p.set_defaults(func=cmd_export)

    p = sub.add_parser("models", parents=[common],
                       help="registered hyperelastic models and tau strategies",
                       description="List the hyperelastic models (built-in and plug-ins of "
                                   f"the '{PLUGIN_GROUP}' entry-point group) and tau "
                                   "strategies.")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=cmd_models)
    return parser


# ====================================================================== main
def _glue_windows(argv: list[str]) -> list[str]:
    """``--trim-strain -0.3:`` -> ``--trim-strain=-0.3:`` (argparse takes -0.3: for a flag)."""
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        if a in ("--trim-strain", "--trim-time") and i + 1 < len(argv):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
        else:
            out.append(a)
            i += 1
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``vhfit`` command line; returns the exit code.

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments without the program name (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 success, 1 fit failed or interrupted, 2 bad input.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    try:
        parser = build_parser()
        args = parser.parse_args(_glue_windows(argv))
        if args.command is None:
            parser.print_help()
            return EXIT_USAGE
        args._argv = argv
        with warnings.catch_warnings():
            warnings.showwarning = _show_warning  # one line, no source excerpt
            return int(args.func(args))
    except UsageError as exc:
        if debug:
            raise
        _error(_one_line(exc))
        return EXIT_USAGE
    except FitFailed as exc:
        if debug:
            raise
        _error(_one_line(exc))
        return EXIT_FAILED
    except KeyboardInterrupt:
        if debug:
            raise
        _error("interrupted")
        return EXIT_FAILED
    except (ValueError, OSError) as exc:  # DataError is a ValueError: bad input
        if debug:
            raise
        _error(_one_line(exc))
        return EXIT_USAGE
    except Exception as exc:
        if debug:
            raise
        _error(f"{type(exc).__name__}: {_one_line(exc)} (unexpected: rerun with --debug "
               "for the traceback, and please report it)")
        return EXIT_FAILED


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    if issubclass(category, UserWarning):
        msg = message if isinstance(message, Warning) else Warning(message)
        text = f"warning: {_one_line(msg)}"
        try:
            (file or sys.stderr).write(text + "\n")
        except (OSError, ValueError):
            pass


def _error(msg: str) -> None:
    try:
        sys.stderr.write(f"vhfit: error: {msg}\n")
        sys.stderr.flush()
    except (OSError, ValueError):
        pass

