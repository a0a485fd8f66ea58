"""``vhfit fit`` and ``vhfit demo``: calibrate, then write every output into one folder.

The two commands share the whole workflow (:func:`run_fit`): they differ only in where
the curves come from. ``results.json`` is written by :meth:`Calibration.save`; the
files that only the command line writes (``fitted_curves.csv``, ``summary.txt``, the
solver cards, the plots and ``report.html``, through ``_report``) are written here.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import sys
import warnings
from collections.abc import Iterator, Sequence
from contextlib import closing, contextmanager, nullcontext
from dataclasses import replace
from pathlib import Path

import numpy as np

from vhfit import datasets, hyperelastic
from vhfit._io import atomic_write
from vhfit.calibration import (
    Calibration,
    CalibrationError,
    CalibrationSettings,
    CalibrationWarning,
    calibrate,
    default_n_prony,
    refuse_unrepresentable,
    same_fit,
    start_options,
)
from vhfit.cli._cards import (
    CARD_FILES,
    check_targets,
    plan_fits,
)
from vhfit.cli._common import (
    DEMO_PRONY,
    EXIT_FAILED,
    EXIT_OK,
    FitFailed,
    Progress,
    Signals,
    UsageError,
    one_line,
    prepare_out,
)
from vhfit.cli._inputs import read_curves, sha256
from vhfit.cli._outputs import Drawer, send_early, write_outputs
from vhfit.cli._plugins import load_plugins, resolve_model_name, tau_strategies
from vhfit.cli._settings import check_shift, cli_bounds, fit_settings
from vhfit.comparison import compare
from vhfit.data import is_moduli
from vhfit.formulations import FORMULATIONS

__all__ = ["cmd_fit", "cmd_demo", "run_fit", "run_compare", "model_list", "group_by_file",
           "read_curves",
           "CARD_FILES", "DEMO_PRONY"]

RESULTS = "results.json"
CHECKPOINT = "checkpoint.json"
DEMO_STRATEGY = "semifree"


# ================================================================== commands
def cmd_fit(args, argv: Sequence[str] = ()) -> int:
    """``vhfit fit CURVES...`` (``argv``: the command line, for the results and the resume
    hint)."""
    if args.force and args.resume:
        raise UsageError("--force and --resume contradict each other: give one")
    laws = model_list(args.model)  # several laws: every name known, else nothing fitted
    if laws is not None and args.resume:
        raise UsageError("--resume: several --model laws are fitted without checkpoints; "
                         "resume one law's fit (--model LAW), or drop --resume")
    _check_fit_flags(args)
    _check_card_flags(args, laws)
    if args.bounds:  # checked with each law before anything is read or written
        for law in laws or [resolve_model_name(args.model)]:
            cli_bounds(args, law)
    if getattr(args, "each", None):
        from vhfit.cli._each import run_each

        return run_each(args, lambda a: _fit_data(a, argv, laws))
    return _fit_data(args, argv, laws)


def _fit_data(args, argv: Sequence[str], laws: list[str] | None) -> int:
    """Read the data of ``args``, then fit them into ``--out`` (one material)."""
    with warnings.catch_warnings(record=True) as caught:  # what the readers assumed
        warnings.simplefilter("always")
        curves, inputs = read_curves(args.curves, args)  # bad data: nothing written
    _show_warnings(caught, [], _file_names(inputs))
    # temperatures without shift information: nothing written
    shift_law, at_ref = check_shift(curves, args)
    with _out_folder(args, "vhfit-results") as out:
        if laws is not None:
            return run_compare(curves, inputs, args, out, laws, command=list(argv),
                               shift_law=shift_law, at_ref=at_ref)
        return run_fit(curves, inputs, args, out, label=None, command=list(argv),
                       shift_law=shift_law, at_ref=at_ref)


# ------------------------------------------------- several laws: --model a,b or all
def model_list(given: str) -> list[str] | None:
    """The laws of ``--model a,b,c`` or ``--model all`` (None for one law); an unknown
    law is a usage error naming it, before anything is read or fitted."""
    if given.strip() == "all":
        return list(hyperelastic.available())
    if "," not in given:
        return None
    names = [s.strip() for s in given.split(",")]
    if any(not s for s in names):
        raise UsageError(f"--model {given}: an empty law name; give names separated by "
                         "commas (mooney_rivlin,yeoh) or 'all'")
    for s in names:
        if s not in hyperelastic.available():
            try:
                resolve_model_name(s)
            except UsageError as exc:
                raise UsageError(f"--model: {exc}") from None
    return list(dict.fromkeys(names))


def run_compare(curves, inputs, args, out: Path, laws: list[str], *, command: list[str],
                shift_law=None, at_ref=None) -> int:
    """Fit every law of ``laws`` side by side (:func:`vhfit.compare`), write each law's
    results under ``laws/LAW/`` and the best's as the folder's result (:func:`run_fit`
    with its fit given), with the ranked table first in the summary."""
    strategy = args.strategy
    if strategy not in tau_strategies():
        raise UsageError(
            f"--strategy {strategy!r}: choose one of {', '.join(tau_strategies())}")
    plan = plan_fits(args.targets, args.formulation)
    kw = fit_settings(args, model=laws[0], strategy=strategy, shift_law=shift_law).keywords()
    for k in ("hyperelastic", "n_prony", "callback", "checkpoint", "resume", "workers"):
        kw.pop(k)
    kw["formulation"] = next(iter(plan))
    solvers = [s for group in plan.values() for s in group]
    if not args.quiet:
        print(f"comparing {len(laws)} laws ({', '.join(laws)}), each with "
              f"{args.prony if args.prony is not None else 'the default number of'} Prony "
              f"term(s), seed {args.seed}, side by side on up to {os.cpu_count() or 1} "
              f"processes; outputs in {out}/", file=sys.stderr, flush=True)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            comp = compare(curves, laws, n_prony=args.prony, solvers=solvers, **kw)
    except ValueError as exc:
        raise UsageError(one_line(exc)) from None
    except KeyboardInterrupt:  # no result yet: the folder is left as it was
        raise CompareInterrupted(
            f"interrupted while the laws were fitted: nothing written to {out}; rerun the "
            "command to compare them") from None
    sigs = Signals()  # one for the laws' files and the best's fit: a deferred signal
    with sigs:        # written into laws/ stops the best's next search
        _write_laws(comp, curves, out, sigs, extra={
            "command": ["vhfit", *command], "seed": args.seed, "inputs": inputs})
        if comp.best is None:
            print(comp.table())
            print("vhfit: error: no law found a valid parameter set (RMSAPE is not finite); "
                  "check the data and the laws", file=sys.stderr)
            return EXIT_FAILED
        args.model = comp.best
        return run_fit(curves, inputs, args, out, label=None, command=command,
                       shift_law=shift_law, at_ref=at_ref, given=comp.calibration,
                       comparison=comp, signals=sigs)


class CompareInterrupted(FitFailed):
    """A comparison interrupted before its results were written: exit 1, and the
    ``--out`` folder is left as it was (:func:`_out_folder`)."""


#: Where the other laws' results are written before they are moved to ``laws/`` whole.
LAWS_PARTIAL = ".laws.partial"


def _write_laws(comp, curves, out: Path, sigs: Signals, *, extra: dict) -> None:
    """Each law of the comparison but the best into ``laws/LAW/`` (results and summary).

    The files are written into a hidden sibling folder, which then replaces ``laws/``
    whole: an interrupt never leaves a ``laws/`` of some laws only. Signals are deferred
    meanwhile, as while ``vhfit fit`` writes its outputs; an abort that comes through
    anyway (a third signal) removes what was written and leaves the folder as it was.
    """
    others = [law for law in comp.fits if law != comp.best]
    if not others:
        return
    partial, final = out / LAWS_PARTIAL, out / "laws"
    rows = comp.to_dict()["rows"]
    try:
        shutil.rmtree(partial, ignore_errors=True)
        sigs.writing = True
        for law in others:
            cal = comp.fits[law]
            folder = partial / law
            folder.mkdir(parents=True, exist_ok=True)
            row = next(r for r in comp.rows if r["law"] == law)
            atomic_write(folder / "summary.txt", cal.summary() + "\n")
            cal.save(folder / RESULTS, curves=curves,
                     extra={**extra, "comparison_row": rows[row["rank"] - 1]})
        if final.is_dir():  # an earlier run's (--force)
            shutil.rmtree(final)
        partial.rename(final)
    except KeyboardInterrupt:
        shutil.rmtree(partial, ignore_errors=True)
        raise CompareInterrupted(
            f"interrupted while the laws' results were written: nothing written to {out}; "
            "rerun the command to compare them") from None
    except BaseException:
        shutil.rmtree(partial, ignore_errors=True)
        raise
    finally:
        sigs.writing = False


def cmd_demo(args, argv: Sequence[str] = ()) -> int:
    """``vhfit demo``: the bundled synthetic SEBS set, end to end."""
    if args.force and args.resume:
        raise UsageError("--force and --resume contradict each other: give one")
    args.model = "mooney_rivlin"
    _check_fit_flags(args)
    _check_card_flags(args)
    with _out_folder(args, "vhfit-demo") as out:
        return _run_demo(args, out, list(argv))


def _run_demo(args, out: Path, command: list[str]) -> int:
    path = datasets.sebs_path()
    curves = datasets.load_sebs()
    inputs = [{"path": str(path), "sha256": sha256(path), "bundled": "vhfit.datasets.sebs"}]
    if args.out is None:
        command = command + ["--out", str(out)]
    args.model, args.prony, args.strategy = "mooney_rivlin", args.prony, DEMO_STRATEGY
    if not args.quiet:
        print(
            f"vhfit demo: {len(curves)} synthetic SEBS curves (rates "
            f"{', '.join(f'{r:g}' for r in datasets.SEBS_RATES)} 1/s) generated from the paper's "
            f"Table 5 parameters; calibrating Mooney-Rivlin + {args.prony} Prony terms",
            file=sys.stderr,
        )
    code = run_fit(curves, inputs, args, out, label=datasets.SEBS_LABEL, command=command,
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
    fit refuses), and when a comparison of laws (``--model a,b``) is interrupted before
    its results are written, the files the run added are removed, the checkpoints it changed are
    restored and a folder it created is removed again: a rerun finds the folder as the
    user left it. Interrupts and failed fits (exit 1) keep their checkpoints for
    ``--resume``.
    """
    existed = _existing_out(args.out, default)
    out = prepare_out(args.out, default, force=args.force, resume=args.resume)
    existed = out.resolve() in existed
    names = set(os.listdir(out)) if existed else set()
    saved = {n: (out / n).read_bytes() for n in names  # (bytes: a damaged one too)
             if n.startswith(CHECKPOINT) and (out / n).is_file()}
    try:
        yield out
    except (UsageError, ValueError, OSError, CompareInterrupted):  # exit 2, or a
        # comparison interrupted before its results: as it was
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


def _restore(out: Path, existed: bool, names: set[str], saved: dict[str, bytes]) -> None:
    """Undo a run's writes into ``out`` (see :func:`_out_folder`)."""
    try:
        for p in out.iterdir():
            if p.name not in names and p.is_file():
                p.unlink()
        for n, data in saved.items():
            p = out / n
            if not p.is_file() or p.read_bytes() != data:
                atomic_write(p, data)
        if not existed and not any(out.iterdir()):
            out.rmdir()
    except OSError:  # the error being reported matters more than the cleanup
        pass


def _check_card_flags(args, laws: list[str] | None = None) -> None:
    """``--for`` a solver that lacks the law (any of ``laws``, when several), or an
    unknown ``--formulation``: refused before anything is fitted or written."""
    form = args.formulation
    if form is not None and form not in FORMULATIONS:
        load_plugins()  # a plug-in may register it
        if form not in FORMULATIONS:
            raise UsageError(f"--formulation {form}: unknown; choose one of "
                             f"{', '.join(FORMULATIONS)} (or register one in a plug-in)")
    given = args.targets
    if given:  # --for a,b --for c: one list, each solver once
        args.targets = list(dict.fromkeys(s for group in given for s in group))
        for law in laws or [resolve_model_name(args.model)]:
            check_targets(args.targets, law)


def _demo_check(out: Path) -> None:
    """Print the fitted constants next to the generating ones."""
    p = Calibration.load(out / RESULTS).params
    true = datasets.SEBS_PARAMS
    rows = ["", "fitted vs generating parameters (paper Table 5):"]
    for k, v in true.items():
        if k in p:
            rows.append(f"  {k:<6} fitted {p[k]:<12.6g} generating {v:<12.6g} "
                        f"rel. diff {abs(p[k] - v) / abs(v):.1e}")
    print("\n".join(rows))


# ================================================================ the fit job
def run_fit(curves, inputs, args, out: Path, *, label: str | None, command: list[str],
            demo: bool = False, shift_law=None, at_ref: list | None = None,
            given: Calibration | None = None, comparison=None,
            signals: Signals | None = None) -> int:
    """Calibrate, then write every output into ``out`` (also when interrupted).

    ``shift_law``: the law of ``--shift`` (None: the tests' own overlap, or one
    temperature); ``at_ref``: the tests at the reference temperature, for the outputs
    (None: ``curves`` are); ``given``: the first formulation's fit, already made (by
    :func:`run_compare`, whose ``comparison`` heads the summary); ``signals``: the
    caller's :class:`Signals`, already installed (a signal it deferred stops the next
    search).
    """
    model = resolve_model_name(args.model)
    strategy = args.strategy
    if strategy not in tau_strategies():
        raise UsageError(
            f"--strategy {strategy!r}: choose one of {', '.join(tau_strategies())}"
        )
    settings = fit_settings(args, model=model, strategy=strategy,
                            checkpoint=str(out / CHECKPOINT), shift_law=shift_law)
    refuse_unrepresentable(curves, settings.hyperelastic)  # before a line is printed
    if args.resume and not any(out.glob(CHECKPOINT + "*")):
        raise UsageError(
            f"--resume: no checkpoint in {out} (the fit ended, or never started there); "
            "drop --resume to fit afresh"
        )
    if not args.quiet and given is None:
        why = None
        if args.prony is None:
            n_txt, why = default_n_prony(curves)
        else:
            n_txt = str(args.prony)
            if args.prony == "auto":
                n_txt = ("auto (N = 1 to one per decade of the data: the per-decade spectrum)"
                         if curves and all(is_moduli(c) for c in curves)
                         else f"auto (N = 1..{args.max_prony})")
        print(f"fitting {model} + {n_txt} Prony term(s), tau strategy {strategy}, seed "
              f"{args.seed}, to {len(curves)} curve(s); outputs in {out}/"
              + (" (resuming)" if args.resume else ""), file=sys.stderr, flush=True)
        if why:
            print(f"no Prony terms: {why} (give --prony N to fit some anyway)",
                  file=sys.stderr, flush=True)
    plan = plan_fits(args.targets, args.formulation)
    sigs = signals if signals is not None else Signals()
    fits: dict[str, Calibration] = {}
    interrupted = False
    drawer = Drawer.start(args)  # loads matplotlib on the other CPU while the fit runs
    with (nullcontext() if signals is not None else sigs), \
            (nullcontext() if drawer is None else closing(drawer)), \
            warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for form in plan:
            if given is not None and not fits:  # fitted by run_compare
                fits[form] = given
                continue
            if fits:  # the figures are the first fit's: drawn while this one runs
                send_early(drawer, fits, curves, args, out, demo=demo, at_ref=at_ref)
            if len(plan) > 1 and not args.quiet:
                print(f"fit in the '{form}' formulation, for {', '.join(plan[form])}",
                      file=sys.stderr, flush=True)
            # a resumed scan starts mid-way: N cannot be counted from the generations then
            progress = Progress(sys.stderr, quiet=args.quiet, scan=args.prony == "auto",
                                first_n=None if args.resume else 1)
            fits[form] = cal = _search(curves, settings, args, out, progress, sigs,
                                       command, form, start=next(iter(fits.values()), None))
            interrupted = cal.interrupted or sigs.stopped_search
            if interrupted:
                break
        cal = next(iter(fits.values()))
        sigs.writing = True
        files = write_outputs(fits, plan, curves, inputs, args, out, label=label,
                               command=command, interrupted=interrupted, demo=demo,
                               at_ref=at_ref, comparison=comparison, drawer=drawer)
    _show_warnings(caught, [w for c in fits.values() for w in c.warnings],
                   _file_names(inputs))
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
    unstable = [c for c in fits.values() if c.stability is not None and not c.stability.stable]
    if unstable:  # written, but not a law to use: the run failed
        print(f"vhfit: error: no Drucker-stable law was found ({unstable[0].stability.describe()}"
              "); give a narrower --stability-range, wider --bounds or another --model",
              file=sys.stderr)
        return EXIT_FAILED
    return EXIT_OK


def _search(curves, settings: CalibrationSettings, args, out: Path, progress: Progress,
            sigs: Signals, command: list[str], formulation: str = "hereditary",
            start: Calibration | None = None) -> Calibration:
    """The calibration with progress, signals and a checkpoint in ``out`` (one per
    formulation: ``checkpoint.json`` for the first); a fit after the first starts from
    ``start`` (``start_options``), or is ``start`` in its formulation where that is the
    same fit (``same_fit``: no Prony terms)."""
    def callback(d):
        progress(d)
        sigs.check()  # raises KeyboardInterrupt (caught by calibrate) after a signal
        return False

    settings = replace(settings, formulation=formulation, callback=callback,
                       checkpoint=str(out / _checkpoint(formulation)))
    try:
        kw = settings.keywords()
        same = None if start is None else same_fit(start, curves, **kw)
        if same is not None:  # no Prony terms: the first fit in every formulation
            progress.close()
            return same
        if start is not None:  # the next solver's fit starts from the first
            kw.update(start_options(start, curves, **kw))
        cal = calibrate(curves, **kw)
    except KeyboardInterrupt:
        progress.close()
        raise FitFailed(
            f"interrupted before a result was ready; continue with: {_resume_cmd(command)}"
            if any(out.glob(CHECKPOINT + "*")) else "interrupted before the search started"
        ) from None
    except CalibrationError as exc:  # no finite fit: the data, law or bounds
        progress.close()
        how = ""
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


def _show_warnings(caught: list, shown: list[str], files: Sequence[str] = ()) -> None:
    """Warnings of the run on stderr, one line each, once each (``shown``: in the table);
    a warning that only the file named in it tells apart from others is printed once with
    the list of its files (:func:`group_by_file`)."""
    seen = set(shown)
    msgs = []
    for w in caught:
        # the table lists the calibration's own warnings; numerical RuntimeWarnings of
        # trial individuals are noise; data warnings (what the reader assumed) are shown
        if issubclass(w.category, CalibrationWarning) or not issubclass(w.category,
                                                                         UserWarning):
            continue
        msg = one_line(w.message)
        if msg not in seen:
            seen.add(msg)
            msgs.append(msg)
    for msg in group_by_file(msgs, files):
        print(f"warning: {msg}", file=sys.stderr)


def _file_names(inputs) -> list[str]:
    """The input files as messages may name them: absolute, and relative to here."""
    out = []
    for i in inputs:
        p = str(i["path"])
        out.append(p)
        try:
            out.append(os.path.relpath(p))
        except ValueError:  # another drive (Windows)
            pass
    return out


#: A number in a message (merged across the files a warning names).
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def group_by_file(messages: Sequence[str], files: Sequence[str]) -> list[str]:
    """``messages`` with those that say the same of several files merged into one line:
    the text once (numbers that differ between the files joined by "/"), then the list
    of the places, each as its message named it (curve and file).

    A message names its place before the first ``": "`` that follows the file's name
    (``curve 'a' (d/a.csv): ...``); messages that name no file, or that alone say what
    they say, are kept as they are.

    Parameters
    ----------
    messages : sequence of str
    files : sequence of str
        The input files as they appear in the messages.

    Returns
    -------
    list of str

    Examples
    --------
    >>> group_by_file(["a.csv: no rate, assumed -1/s", "b.csv: no rate, assumed -10/s",
    ...                "c.csv: bad row"], ["a.csv", "b.csv", "c.csv"])
    ['no rate, assumed -1/-10/s (in 2 files: a.csv; b.csv)', 'c.csv: bad row']
    """
    names = sorted({str(f) for f in files if str(f)}, key=len, reverse=True)
    groups: dict[str, list[tuple[str, str, str]]] = {}
    for m in messages:
        f = next((n for n in names if n in m), None)
        j = -1 if f is None else m.find(": ", m.index(f) + len(f))
        if j < 0:
            groups.setdefault("\0" + m, []).append(("", m, ""))
            continue
        body = m[j + 2:]
        groups.setdefault(_NUMBER.sub("#", body), []).append((m[:j], body, f))
    out = []
    for members in groups.values():
        if len(members) == 1:
            place, body, _ = members[0]
            out.append(f"{place}: {body}" if place else body)
            continue
        n_files = len({f for _, _, f in members})
        places = "; ".join(p for p, _, _ in members)
        out.append(_merged([b for _, b, _ in members])
                   + (f" (in {n_files} files: {places})" if n_files > 1 else f" ({places})"))
    return out


def _merged(bodies: list[str]) -> str:
    """One text for messages equal but for their numbers: each number that differs is
    given as its values joined by "/"."""
    texts = [_NUMBER.split(b) for b in bodies]
    nums = [_NUMBER.findall(b) for b in bodies]
    out = texts[0][0]
    for k in range(len(nums[0])):
        vals = list(dict.fromkeys(n[k] for n in nums))
        out += "/".join(vals) + texts[0][k + 1]
    return out


def _resume_cmd(command: list[str]) -> str:
    cmd = [c for c in command if c not in ("--resume", "--force")]
    return shlex.join(["vhfit"] + cmd + ["--resume"])

