"""The solver cards of ``vhfit fit``: which fit each solver gets, the cards, their check.

``--for`` picks the solvers; each is served by a fit in the formulation it integrates
(its record's ``formulation``, :class:`vhfit.export.Solver`; every solver, card file,
label and variant here comes from the records), so one fit may serve several solvers
and several fits may be run. Every written card is then parsed back and re-simulated in
its solver's formulation on the data (:mod:`vhfit.export.check`); a card whose error
exceeds its fit's by more than the margin gets a warning, in the card and the summary.
Each card is graded on its own error, as the main fit is (the summary's first lines), and
the warnings of a card's own fit head the summary beside the main fit's.
"""

from __future__ import annotations

import json
import textwrap
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from vhfit._io import atomic_write
from vhfit.calibration import StopKind, grade_word
from vhfit.cli._common import UsageError, one_line
from vhfit.export import LiveMapping, TooManyTerms, export, get_solver, supported_laws
from vhfit.export import solvers as solver_names
from vhfit.export.check import (
    MARGIN_ABSOLUTE,
    MARGIN_RELATIVE,
    check_cards,
    check_words,
    own_fit_warnings,
)
from vhfit.modes import get_deformation
from vhfit.tts import fit_shift_law

__all__ = ["CARD_FILES", "Cards", "plan_fits", "check_targets",
           "card_options", "card_shift", "card_jobs", "label", "solver_of", "write_cards",
           "check_table", "unfinished", "mark", "json_marked", "UNCONVERGED", "fit_record",
           "other_fits", "refusal"]

JSON_FILE = "material.json"


class _CardFiles(LiveMapping):
    """Card key -> file name in a results folder: each registered solver's card
    (``NAME + suffix``), its variants (``NAME_VARIANT + suffix``) and ``json``."""

    def _now(self) -> dict[str, str]:
        out: dict[str, str] = {}
        for s in solver_names():
            rec = get_solver(s)
            out[s] = rec.card_file
            out.update({f"{s}_{v}": f"{s}_{v}{rec.suffix}" for v in rec.variants})
        out["json"] = JSON_FILE
        return out


#: Card key -> file name (read from the solver records at each use).
CARD_FILES: Mapping[str, str] = _CardFiles()


def _solver(key: str):
    """The record of a card key (a solver's name, or ``NAME_VARIANT``)."""
    try:
        return get_solver(key)
    except ValueError:
        pass
    for name in solver_names():
        rec = get_solver(name)
        if any(key == f"{name}_{v}" for v in rec.variants):
            return rec
    raise ValueError(f"card {key!r}: not a registered solver's card")


def solver_of(key: str) -> str:
    """The solver of a card key (a variant's ``NAME_VARIANT`` -> ``NAME``)."""
    return _solver(key).name


def label(key: str) -> str:
    """How a card key is written in messages: the solver's label, or its variant's."""
    rec = _solver(key)
    variant = key[len(rec.name) + 1:] if key != rec.name else ""
    return rec.variants[variant][0] if variant in rec.variants else rec.label


def card_jobs(solver: str, args) -> list[tuple[str, dict]]:
    """(card key, writer keywords) of a solver's card and of the variants asked for
    (``--NAME-VARIANT``)."""
    rec = get_solver(solver)
    return [(solver, {})] + [(f"{solver}_{v}", {v: True}) for v in rec.variants
                             if getattr(args, f"{solver}_{v}")]


def plan_fits(targets, formulation: str | None = None) -> dict[str, list[str]]:
    """Formulation -> the solvers its fit serves (``"hereditary"`` first).

    Every chosen solver (``--for``; without it, every registered solver) is served by a
    fit in the formulation its record names, so each card reproduces the data in its
    own solver. A ``formulation`` (``--formulation``) makes one fit in it serve every
    chosen solver instead; the card check then shows what each solver makes of it.
    """
    every = solver_names()
    chosen = [s for s in every if s in targets] if targets else list(every)
    if formulation is not None:
        return {formulation: chosen}
    own = {s: get_solver(s).formulation for s in chosen}
    plan: dict[str, list[str]] = {}
    for s in sorted(chosen, key=lambda s: own[s] != "hereditary"):
        plan.setdefault(own[s], []).append(s)
    return {f: [s for s in every if s in v] for f, v in plan.items()}


def check_targets(targets, law: str) -> None:
    """``--for`` solvers whose cards cannot hold the law: a usage error, before fitting."""
    for s in targets or ():
        if law not in supported_laws(s):
            others = [o for o in solver_names() if law in supported_laws(o)]
            fix = (f"drop --for {s} (the law's cards: {', '.join(others)})" if others
                   else "no solver card holds this law")
            raise UsageError(
                f"--for {s}: {label(s)} has no card for the hyperelastic law {law!r}; {fix}, "
                f"or choose a --model among {', '.join(supported_laws(s))}")


#: RMS misfit (decades of a_T, i.e. 2.3 % in time) within which a WLF law fitted to the
#: shift table stands for a law the cards cannot take
CARD_SHIFT_DECADES = 0.01


def card_shift(cal) -> tuple[object, str | None]:
    """The fit's time–temperature shift for the cards: (WLF law or None, note or None).

    A WLF law goes into the cards (each solver record's ``shift``: a shift keyword, or a
    note in a card without one). Another law
    (the one the data chose where the WLF fit degenerates, or a given one) has no card
    form: the cards then carry the WLF law fitted to the fit's shift table when it
    reproduces the table as well (RMS within 10 % of the law's, or within
    :data:`CARD_SHIFT_DECADES`) — for a straight
    line in T, the WLF limit of large C1, C2 — and the note says so and where it holds;
    otherwise no shift, and the note says that.
    """
    law = cal.shift
    if law is None:
        return None, None
    if law.name == "wlf":
        return law, None
    table = dict(cal.shift_table or {})
    if len(table) >= 2:
        T = np.array(list(table), dtype=np.float64)
        y = np.array(list(table.values()), dtype=np.float64)
        T_ref = cal.T_ref if cal.T_ref is not None else law.T_ref
        wlf = fit_shift_law(T, y, "wlf", T_ref=T_ref)
        rms_w = float(np.sqrt(np.mean((wlf.log_aT(T) - y) ** 2)))
        rms_l = float(np.sqrt(np.mean((law.log_aT(T) - y) ** 2)))
        if rms_w <= max(1.1 * rms_l, CARD_SHIFT_DECADES):
            return wlf, (f"time-temperature shift in the card: WLF C1 = {wlf.C1:.6g}, C2 = "
                         f"{wlf.C2:.6g} fitted to the shift table (the form the cards take; "
                         f"the fit's {law.name} law has none), RMS {rms_w:.3g} decades "
                         f"against its {rms_l:.3g}; it holds only for T = {T.min():g}.."
                         f"{T.max():g}")
    return None, (f"no time-temperature shift in the card: the fit's {law.name} law has no "
                  "card form (the cards take WLF); fit with --shift wlf:C1,C2, or without "
                  "--shift to have WLF fitted to the sweeps' shift factors")


def card_options(args, solver: str) -> dict:
    """The keyword arguments of ``solver``'s writer from ``--density``, ``--poisson``,
    ``--bulk-modulus`` (those its record declares)."""
    return get_solver(solver).options(
        **{k: getattr(args, k) for k in ("density", "poisson", "bulk_modulus")})


@dataclass
class Cards:
    """What :func:`write_cards` wrote and found."""

    files: dict = field(default_factory=dict)  # solver -> file name
    errors: dict = field(default_factory=dict)  # solver -> why no card
    notes: dict = field(default_factory=dict)  # solver -> writer warnings
    fits: dict = field(default_factory=dict)  # solver -> formulation of its fit
    check: dict = field(default_factory=dict)  # solver -> CardCheck, or {"error": ...}
    warnings: list = field(default_factory=list)  # headline warnings of the check
    fit_warnings: list = field(default_factory=list)  # those of the cards' own fits
    summary: list = field(default_factory=list)  # lines for summary.txt
    headline: list = field(default_factory=list)  # the summary's first lines, per solver
    fit_lines: list = field(default_factory=list)  # the summaries of the fits after the first
    fits_record: dict = field(default_factory=dict)  # results.json "fits": every fit

    def check_dict(self) -> dict:
        """The ``card_check`` entry of results.json."""
        return {s: c if isinstance(c, dict) else c.to_dict() for s, c in self.check.items()}


def _source(form: str, solvers: list[str], several: bool, solver: str) -> list[str]:
    """The card comment saying which fit the constants come from."""
    rec = _solver(solver)
    serves = ", ".join(solvers)
    line = (f"Fit: vhfit formulation '{form}' (this fit serves {serves}"
            + ("; each other solver has its own fit" if several else "") + "); "
            f"{label(solver)} integrates '{rec.formulation}'")
    if rec.formulation != form:
        line += f": see the card check; `vhfit fit --for {rec.name}` fits for it"
    return [line]


def _texts(fits, plan, args) -> tuple[dict, Cards]:
    """Every card's text in memory (solver -> (text, writer kwargs, fit))."""
    out, res = {}, Cards()
    for form, solvers in plan.items():
        cal = fits.get(form)
        if cal is None:  # interrupted before this fit
            for s in solvers:
                res.errors[s] = f"the '{form}' fit was not run (interrupted)"
            continue
        jobs = [job for s in solvers for job in card_jobs(s, args)]
        shift, note = card_shift(cal)
        for solver, extra in jobs:
            name = _solver(solver).name
            kw = dict(notes=list(cal.headlines), **card_options(args, name), **extra,
                      comments=_source(form, solvers, len(plan) > 1, solver))
            if shift is not None:
                kw["shift"] = shift
            if note:
                res.notes.setdefault(solver, []).append(note)
            try:
                with warnings.catch_warnings(record=True) as ws:
                    warnings.simplefilter("always")
                    text = export(cal, to=name, **kw)
            except Exception as exc:  # a solver that cannot take this model is not fatal
                res.errors[solver] = refusal(exc, solver)
                continue
            notes = list(dict.fromkeys(one_line(w.message) for w in ws))
            if notes:
                res.notes[solver] = notes
            out[solver] = (text, kw, cal)
            res.fits[solver] = form
    return out, res


def refusal(exc: Exception, key: str) -> str:
    """Why a writer refused a card, in the command line's words: a card that holds fewer
    Prony terms than the fit names the ``vhfit fit`` flag that makes one it can hold."""
    if isinstance(exc, TooManyTerms):
        return (f"{one_line(exc.what)}: refit (vhfit fit) with --prony {exc.limit} for "
                f"{label(key)} cards")
    return one_line(exc)


#: The stops of a search that ended before converging (docs/cli.md): the card says so.
UNCONVERGED = (StopKind.MAX_TIME, StopKind.MAX_ITER, StopKind.CALLBACK)


def unfinished(cal, interrupted: bool = False) -> str | None:
    """The first comment line of a card from a search that did not finish, or None."""
    stop = cal.stop_reason
    if interrupted or stop.interrupted:
        return ("INTERRUPTED: written by an interrupted vhfit fit (best constants so far, "
                "not converged); continue it with --resume before using this card")
    if stop.kind in UNCONVERGED:
        return (f"NOT CONVERGED: the search stopped at {stop} before it converged; the "
                "constants may be far from the best (fit again with a larger --max-time "
                "or --maxiter)")
    return None


def mark(text: str, prefix: str, line: str, width: int = 100) -> str:
    """``text`` with ``line`` (wrapped, as comments with ``prefix``) before its first
    comment line (at the top if it has none)."""
    rows = text.splitlines(keepends=True)
    at = next((i for i, r in enumerate(rows) if r.startswith(prefix)), 0)
    add = [f"{prefix} {piece}\n" for piece in textwrap.wrap(
        line, width - len(prefix) - 1, subsequent_indent="  ", break_on_hyphens=False)]
    return "".join(rows[:at] + add + rows[at:])


def json_marked(text: str, line: str | None) -> str:
    """material.json with ``status`` (and ``status_note``) of the fit."""
    doc = json.loads(text)
    doc = {"status": "complete" if line is None else line.split(":")[0].lower().replace(
        " ", "_"), **({"status_note": line} if line else {}), **doc}
    return json.dumps(doc, indent=2) + "\n"


def write_cards(fits: dict, plan: dict, curves, out: Path, args,
                interrupted: bool = False) -> Cards:
    """Write the cards of ``plan`` (formulation -> solvers) from ``fits`` (formulation ->
    Calibration), check each against ``curves``, and write material.json and the solvers'
    test-data inputs (records with ``test_data``) of the first fit.

    A card that fails its check is not written (its reason is in ``errors``) unless
    ``--formulation`` chose the fit for every solver: then it is written with the check's
    warning at its head. Every file of an interrupted run (``interrupted``) or of an
    unconverged search starts with a comment saying so (:func:`unfinished`).
    """
    texts, res = _texts(fits, plan, args)
    forced = args.formulation is not None
    for solver, (text, kw, cal) in texts.items():
        try:
            res.check[solver] = check = check_cards({solver: text}, curves, fits=cal)[solver]
        except Exception as exc:  # the check reports, it never stops the outputs
            res.check[solver] = {"error": one_line(exc)}
        else:
            if check.warning() and not forced:  # a card its own solver would get wrong
                res.errors[solver] = f"no card written: {check.warning()}"
                continue
            if check.warning():
                res.warnings.append(check.warning())
                kw = dict(kw, notes=[*kw["notes"], check.warning()])
                text = export(cal, to=_solver(solver).name, **kw)
        status = unfinished(cal, interrupted)
        if status:
            text = mark(text, _solver(solver).comment, status)
        atomic_write(out / CARD_FILES[solver], text)
        res.files[solver] = CARD_FILES[solver]
    first = next(iter(fits.values()))
    status = unfinished(first, interrupted)
    atomic_write(out / CARD_FILES["json"], json_marked(export(first, to="json"), status))
    res.files["json"] = CARD_FILES["json"]
    if any(c.is_equilibrium and get_deformation(c.deformation).standard_test
           for c in curves):  # the solvers' test-data inputs (records with test_data)
        for name in solver_names():
            rec = get_solver(name)
            if rec.test_data is None:
                continue
            key, file = f"{name} test data", f"{name}_test_data{rec.suffix}"
            try:
                text = rec.test_data(curves, first.model.hyperelastic.name)
            except ValueError as exc:
                res.errors[key] = one_line(exc)
            else:
                if status:
                    text = mark(text, rec.comment, f"{status.split(':')[0]}: the fit of this "
                                "folder did not finish; these test data are complete")
                atomic_write(out / file, text)
                res.files[key] = file
    res.fit_warnings = own_fit_warnings(fits, plan)
    res.headline = _headline(res, plan)
    res.fit_lines = other_fits(fits, plan)
    res.fits_record = {f: {"solvers": plan[f], **fit_record(c)} for f, c in fits.items()}
    res.summary = _summary(res, curves, args, fits, plan)
    return res


def _headline(res: Cards, plan: dict) -> list[str]:
    """The summary's first lines: per solver card, its file, the error its solver will
    show on the data and its grade (:func:`vhfit.calibration.grade_word`: the main fit's
    thresholds), or why it has no card."""
    lines = []
    for k in _card_keys(res, plan):
        c = res.check.get(k)
        if k in res.files:
            if isinstance(c, dict) or c is None:
                what = f"not checked: {c['error']}" if c else "not checked"
            else:
                what = (f"{label(k)} will show RMSAPE {c.rmsape:.4g} % on the data (its fit, "
                        f"in '{res.fits[k]}': {c.fit_rmsape:.4g} %): {grade_word(c.rmsape)}")
            lines.append(f"{k}: {res.files[k]}: {what}")
        elif k in res.errors:
            lines.append(f"{k}: no card: {res.errors[k]}")
    return lines + [""] if lines else []


def _card_keys(res: Cards, plan: dict) -> list[str]:
    """The card keys of the plan's solvers (their variants after each), in plan order."""
    seen = [*res.files, *res.errors, *res.check]
    keys = [k for solvers in plan.values() for s in solvers
            for k in [s, *(v for v in seen if v.startswith(f"{s}_"))]]
    return list(dict.fromkeys(keys))


def fit_record(cal) -> dict:
    """One fit of several in results.json: its constants and errors (no history)."""
    d = cal.to_dict()
    d.pop("history", None)
    if cal.settings is not None:
        d["settings"] = cal.settings.to_dict()
    return d


def other_fits(fits: dict, plan: dict) -> list[str]:
    """The summary's lines of every fit after the first (each solver's own fit)."""
    lines = []
    for form, other in list(fits.items())[1:]:
        lines += ["", f"== the fit in the '{form}' formulation, for "
                      f"{', '.join(plan[form])} ==", other.summary()]
    return lines


def check_table(check: dict, curve_names) -> list[str]:
    """The card check as text lines (solver rows, then per-curve errors)."""
    lines = [
        "card check: each card parsed back and re-simulated in its solver's formulation on "
        "every test history; RMSAPE (Eq. 20) on the data; a card passes (ok: card = its fit) "
        f"when its error <= {1 + MARGIN_RELATIVE:g} x its fit's + {MARGIN_ABSOLUTE:g}; then "
        "its own grade, as the fit's",
        f"  {'card':<16}{'solver law':<13}{'fit (law)':<26}{'card':>12}{'allowed':>12}",
    ]
    rows = {s: c if isinstance(c, dict) else c.to_dict() for s, c in check.items()}
    for s, c in rows.items():
        if "error" in c:
            lines.append(f"  {s:<16}not checked: {c['error']}")
            continue
        fit = (f"{c['fit_rmsape']:.4g} % ({c['fit_formulation']})"
               if c.get("fit_rmsape") is not None else "-")
        allowed = f"{c['allowed']:.4g} %" if c.get("allowed") is not None else "-"
        lines.append(f"  {s:<16}{c['formulation']:<13}{fit:<26}{c['rmsape']:>10.4g} %"
                     f"{allowed:>12}  " + check_words(c["rmsape"], bool(c.get("exceeds"))))
    done = [s for s, c in rows.items() if "error" not in c]
    if done and curve_names:
        lines.append("  per curve (RMSAPE %): " + " | ".join(done))
        for i, name in enumerate(curve_names):
            vals = " | ".join(f"{rows[s]['per_curve'][i]:.4g}" for s in done)
            lines.append(f"    {str(name):<30} {vals}")
    return lines


def _summary(res: Cards, curves, args, fits, plan) -> list[str]:
    lines = []
    if len(plan) > 1 or next(iter(plan)) != "hereditary":
        lines.append("fits: " + "; ".join(
            f"'{f}' for {', '.join(s)}"
            + (f" (RMSAPE {fits[f].rmsape:.4g} %)" if f in fits else " (not run)")
            for f, s in plan.items()))
    if res.files:
        lines.append("solver cards: " + ", ".join(f"{k} -> {v}" for k, v in res.files.items()))
    for k, v in res.notes.items():
        lines += [f"note ({k} card): {n}" for n in v]
    shown = set(_card_keys(res, plan))  # in the headline
    for k, v in res.errors.items():
        if k not in shown:
            lines.append(f"no {k} card: {v}")
    if args.density is None:
        lines.append("note: no --density: the cards carry no density (*DENSITY, RO, MP,DENS) "
                     "and say so; give --density RHO (tonne/mm^3, 1e-9 for 1000 kg/m^3) for "
                     "dynamic or explicit analyses")
    if res.check:
        names = [str(c.name) for c in curves]
        lines += [""] + check_table(res.check, names)
    return lines
