"""What ``vhfit fit`` writes beside ``results.json``: the summary, the fitted curves, the
solver cards (through ``_cards``), the plots and ``report.html`` (through ``_report``).

The figures (the PNG plots and the report's own) are drawn by a second process where
two CPUs are free (:class:`Drawer`): it loads matplotlib while the fit runs, and draws
while the cards are written and checked here. They are the figures drawn here
otherwise, by the same function (:func:`draw_figures`).
"""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import io
import multiprocessing
import os
import shutil
import warnings
from pathlib import Path

from vhfit import plot, report
from vhfit._io import atomic_write
from vhfit._pools import ChildLost, ForkedCall, fork_is_safe, forked, usable_cpus
from vhfit.calibration import (
    Calibration,
)
from vhfit.cli import _moduli
from vhfit.cli._cards import (
    unfinished,
    write_cards,
)
from vhfit.cli._common import (
    one_line,
)
from vhfit.cli._report import write_fit_report
from vhfit.data import is_moduli
from vhfit.modes import get_deformation
from vhfit.report import residual_figure

__all__ = ["write_outputs", "Drawer", "draw_figures", "figure_job", "send_early"]

RESULTS = "results.json"
#: Where the drawer puts the figures it draws before the outputs are written.
STAGING = ".figures.partial"


# ================================================================== outputs
def write_outputs(fits: dict, plan: dict, curves, inputs, args, out: Path, *, label, command,
                   interrupted, demo, at_ref=None, comparison=None,
                   drawer: Drawer | None = None) -> dict[str, str]:
    """results JSON, fitted curves CSV, solver cards, plots and summary into ``out``; the
    first fit of ``plan`` is the results' own, the others are listed under ``fits``
    (``at_ref``: the tests at the reference temperature, if shifted; ``comparison``: the
    laws compared by ``--model a,b``, whose table heads the summary; ``drawer``: the
    process that draws the figures meanwhile, else they are drawn here)."""
    cal = next(iter(fits.values()))
    raw, curves = curves, at_ref or curves  # tests at T_ref
    written: dict[str, str] = {}
    status = "INTERRUPTED (best so far, not converged)" if interrupted else "complete"
    # top-down: the verdict, the data, the warnings, then the cards and the constants
    verdict = [cal.verdict(interrupted=interrupted)]
    head = [f"data: {label}"] if label else []
    note = unfinished(cal, interrupted)  # the cards' first line, on every figure too
    mark = note and note.split(";")[0]
    job = None if drawer is None else drawer.sent  # sent after the first fit (send_early)
    if job is not None and not (job[0] is cal and job[1] is curves and job[6] == mark):
        drawer.close()  # drawn for another state of the run (a later fit interrupted)
        drawer = job = None
    drawing = job is not None
    if job is None:
        job = figure_job(cal, curves, out, args, demo=demo, raw=raw, mark=mark,
                         lines=drawer is not None)
        drawing = drawer is not None and drawer.send(job)  # drawn there while the cards are
    fitted = job[-1]

    atomic_write(out / "fitted_curves.csv", _fitted_csv(cal, curves, fitted, label, interrupted))
    written["fitted_curves.csv"] = "data and model stress per curve"
    moduli = [(c, f) for c, f in zip(curves, fitted) if _moduli.is_moduli_fit(f)]
    if moduli:  # frequency sweeps and relaxation tests
        atomic_write(out / _moduli.FILE, _moduli.fitted_moduli_csv(*zip(*moduli), interrupted))
        written[_moduli.FILE] = "data and model moduli per sweep or relaxation test"

    cards = write_cards(fits, plan, curves, out, args, interrupted=interrupted)
    written.update({f: f"{solver} card" for solver, f in cards.files.items()})
    drawn = drawer.result() if drawing else None
    plots, plot_note, figures = drawn if drawn is not None else draw_figures(*job)
    written.update({p: "plot" for p in plots.values()})
    page, no_page = write_fit_report(cal, curves, out, cards, plots, args, command=command,
                                     label=label, inputs=inputs, interrupted=interrupted,
                                     comparison=comparison, drawn=figures)
    written.update(page)
    plot_note = "; ".join(n for n in (plot_note, no_page) if n) or None

    compared = [] if comparison is None else comparison.table().splitlines() + [
        f"the other laws' results: laws/LAW/ ({RESULTS}, summary.txt)", ""]
    lines = (verdict + head
             + [f"WARNING: {w}" for w in cards.warnings + cards.fit_warnings]
             + ([""] + compared if compared else [])
             + cards.headline  # + "" when it has lines
             + [f"status: {status}", "", cal.summary(verdict=False)] + cards.fit_lines + [""]
             + cards.summary)
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
        "card_fit_warnings": cards.fit_warnings,
    }
    if len(plan) > 1:
        extra["fits"] = cards.fits_record
    if comparison is not None:
        extra["comparison"] = {**comparison.to_dict(), "others": {
            law: f"laws/{law}/{RESULTS}" for law in comparison.fits if law != comparison.best}}
    cal.save(out / RESULTS, interrupted=interrupted, curves=raw,
             extra=extra)
    written[RESULTS] = "results"
    written["_summary"] = text
    return written


def send_early(drawer: Drawer | None, fits: dict, curves, args, out: Path, *, demo: bool,
               at_ref=None) -> None:
    """Hand the first fit's figures to the drawer now, while the fits of the other
    formulations run (they draw the first fit only), into a folder of their own
    (:meth:`Drawer.send` ``staged``): a run that fails before its outputs leaves no
    figure behind. :func:`write_outputs` takes them if they are still the run's (no
    later fit was interrupted: its mark is on every figure), else draws them anew."""
    if drawer is None or drawer.sent is not None:
        return
    cal = next(iter(fits.values()))
    note = unfinished(cal, False)
    drawer.send(figure_job(cal, at_ref or curves, out, args, demo=demo,
                           raw=curves, mark=note and note.split(";")[0], lines=True),
                staged=True)


def figure_job(cal: Calibration, curves, out: Path, args, *, demo: bool, raw, mark,
               lines: bool) -> tuple:
    """The arguments of :func:`draw_figures` for the fit ``cal`` of ``curves`` (at the
    reference temperature; ``raw`` as measured), with the fitted curves (the last item,
    also the CSV's) and, if ``lines``, the fit plot's model lines, computed here."""
    return (cal, curves, out, args.no_plot, demo, raw, mark,
            _lines(cal, curves, args.no_plot) if lines else None, cal.fitted_curves(curves))


# ================================================================== figures
def draw_figures(cal: Calibration, curves, out: Path, skip: bool, demo: bool, raw,
                 mark: str | None, lines: list | None = None, fits: list | None = None,
                 shared: bool = False) -> tuple[dict[str, str], str | None, tuple | None]:
    """The plots into ``out`` ({kind: file}, a note on those not drawn) and the report's
    figures (:func:`vhfit.report.draw_figures`; None without figures), every one marked
    with ``mark`` (an unfinished search's line, or None).

    ``lines`` (:func:`vhfit.plot.model_lines`) and ``fits`` (``cal.fitted_curves``) of
    ``curves``: the model's values, computed already (None: computed here). The drawer
    gets them from the process of the fit, whose compiled kernels are loaded: loading
    them again there would cost it half a second before its first figure. ``shared``:
    the small figures are drawn by a copy of this process meanwhile (:func:`_shared`).
    """
    with plot.marked(mark) if mark else contextlib.nullcontext():
        if shared and not skip and plot.have_matplotlib():
            drawn = _shared(cal, curves, out, demo, raw, lines, fits)
            if drawn is not None:
                return drawn
        plots, plot_note = _draw_plots(cal, curves, out, skip=skip, demo=demo, raw=raw,
                                       lines=lines)
        figures = None
        if not skip and plot.have_matplotlib():
            figures = report.draw_figures(cal, curves, {k: out / f for k, f in plots.items()},
                                          fits=fits)
    return plots, plot_note, figures


#: The plots a copy of the drawer draws (:func:`_shared`), beside the report's residuals.
SMALL_PLOTS = ("history", "order_scan")


def _shared(cal: Calibration, curves, out: Path, demo: bool, raw, lines, fits
            ) -> tuple[dict[str, str], None, tuple] | None:
    """:func:`draw_figures` on two CPUs: a forked copy of this process (matplotlib
    loaded) draws the small plots and the report's residuals while this one draws the
    fit and moduli plots; then the report's figures are made with those residuals.

    None if either part failed or the copy could not run: then everything is drawn
    again, one figure after the other, and fails as it does alone.
    """
    curves = list(curves)
    fits = cal.fitted_curves(curves) if fits is None else fits

    def small():
        with warnings.catch_warnings(record=True) as caught:  # raised again here
            plots, note = _draw_plots(cal, curves, out, skip=False, demo=demo, raw=raw,
                                      only=SMALL_PLOTS)
            residuals = (None if note is not None or all(is_moduli(c) for c in curves)
                         else residual_figure(cal, curves, fits))
        return plots, note, residuals, [(str(w.message), w.category) for w in caught]

    answer = forked(small)
    mine, note = _draw_plots(cal, curves, out, skip=False, demo=demo, raw=raw, lines=lines,
                             only=tuple(k for k in PLOT_FILES if k not in SMALL_PLOTS))
    theirs = answer()
    if note is not None or theirs is None or theirs[1] is not None:
        return None
    for message, category in theirs[3]:  # after this part's own: the order drawn alone
        warnings.warn(message, category, stacklevel=2)
    plots = {k: f for k in PLOT_FILES for d in (mine, theirs[0]) if k in d for f in [d[k]]}
    given = {} if theirs[2] is None else {"residuals": theirs[2]}
    return plots, None, report.draw_figures(cal, curves, {k: out / f for k, f in plots.items()},
                                            fits=fits, given=given)


def _lines(cal: Calibration, curves, skip: bool) -> list | None:
    """The model lines of ``fit.png`` (:func:`vhfit.plot.model_lines`), for the drawer;
    None without that plot, or where they fail (the drawer then meets the failure and
    says it, as when it draws alone)."""
    if skip or all(is_moduli(c) for c in curves):
        return None
    try:
        return plot.model_lines(cal, curves)
    except Exception:  # noqa: BLE001 - reported by the plot that needs them
        return None


class Drawer:
    """A second process that draws the figures of a fit.

    Forked before the fit, it loads matplotlib and draws a figure nobody sees (the first
    figure of a process pays for the fonts and the canvas) on the other CPU, then waits.
    :func:`write_outputs` hands it the fit (:meth:`send`; :func:`send_early` as soon as
    the first fit ends, when fits in other formulations follow) and writes the cards
    while it draws (:func:`draw_figures`, on two CPUs: :func:`_shared`); :meth:`result`
    is what it drew, or None if it was lost (then they are drawn here). :meth:`close`
    ends it, used or not.

    Start one with :meth:`start`, which gives None where it does not pay (no figures
    asked, no matplotlib, one usable CPU) or a fork is not safe.
    """

    def __init__(self):
        jobs, self._send = multiprocessing.get_context("fork").Pipe(duplex=False)
        self._call = ForkedCall(_draw_when_asked, jobs, self._send)
        jobs.close()
        #: the job sent (:func:`draw_figures`' arguments), or None
        self.sent: tuple | None = None
        self._staged: Path | None = None  # the results folder of a staged job

    @classmethod
    def start(cls, args) -> Drawer | None:
        """A drawer for the fit of ``args``, or None (see the class)."""
        if (args.no_plot or not plot.have_matplotlib() or usable_cpus() < 2
                or not fork_is_safe()):
            return None
        return cls()

    def send(self, job: tuple, staged: bool = False) -> bool:
        """Hand over :func:`draw_figures`' arguments; False if they cannot go (drawn here).

        ``staged``: the figures are drawn into a folder ``STAGING`` of the job's results
        folder, and :meth:`result` moves the plots into it (:func:`send_early`). The
        calibration goes without its settings' callback (the command line's progress
        closure, which does not pickle and draws nothing).
        """
        cal, curves, out, *rest = job
        if cal.settings is not None and cal.settings.callback is not None:
            cal = dataclasses.replace(cal, settings=dataclasses.replace(cal.settings,
                                                                        callback=None))
        try:
            if staged:
                self._staged = out
                shutil.rmtree(out / STAGING, ignore_errors=True)  # a killed run's
                (out / STAGING).mkdir()
                out = out / STAGING
            self._send.send((cal, curves, out, *rest))
        except Exception:  # noqa: BLE001 - e.g. not picklable: the figures are drawn here
            self.close()
            return False
        self.sent = job
        return True

    def result(self) -> tuple | None:
        """What :func:`draw_figures` returned there (its plots in the results folder), or
        None if the process was lost."""
        try:
            drawn = self._call.result()
            if drawn is not None and self._staged is not None:
                for name in drawn[0].values():
                    os.replace(self._staged / STAGING / name, self._staged / name)
            return drawn
        except (ChildLost, OSError):  # lost, or its plots not moved: drawn here
            return None
        finally:
            self.close()

    def close(self) -> None:
        """End the process if it still runs (its figures not wanted, or already read),
        and remove what it staged."""
        if not self._send.closed:
            self._send.close()  # a drawer still waiting reads the end of its jobs
        if self._call.process.is_alive():
            self._call.cancel()
        if self._staged is not None:
            shutil.rmtree(self._staged / STAGING, ignore_errors=True)
            self._staged = None


def _draw_when_asked(jobs, send, callback) -> tuple | None:
    """The drawer's process: warm matplotlib, then draw the figures it is sent."""
    send.close()  # the parent's end alone keeps the pipe open: its end is ours
    try:
        from matplotlib.figure import Figure

        # what the figures use first: text, markers, a legend beside, a log axis
        fig = Figure(figsize=(3, 2), layout="constrained")
        ax, log = fig.subplots(1, 2)
        ax.plot([0.0, 1.0], [-1.0, 1.0], "o-", label="λ σ γ ε")
        ax.set_xlabel("strain")
        ax.set_title("stress")
        plot.legend_beside(ax)
        log.semilogy([1.0, 2.0, 3.0], [1e-3, 1.0, 1e2])
        log.grid(True, which="both")
        fig.savefig(io.BytesIO(), format="png", dpi=100)
    except Exception:  # noqa: BLE001 - the real figures report their own failures
        pass
    try:
        job = jobs.recv()
    except EOFError:  # the fit ended without outputs
        return None
    return draw_figures(*job, shared=True)


#: The plots of ``vhfit fit``, kind -> file, in the order they are drawn.
PLOT_FILES = {"fit": "fit.png", "moduli": "moduli.png", "history": "history.png",
              "order_scan": "order_scan.png"}


def _draw_plots(cal: Calibration, curves, out: Path, *, skip: bool, demo: bool,
                raw=None, lines: list | None = None, only: tuple | None = None
                ) -> tuple[dict[str, str], str | None]:
    """The plots that apply ({kind: file}) and a note on those not drawn (``raw``: the
    tests as measured, whose temperatures colour the moduli plot; it shifts them;
    ``lines``: the fit plot's model lines, computed already; ``only``: these kinds)."""
    if skip:
        return {}, "plots skipped (--no-plot)"
    if not plot.have_matplotlib():
        return {}, f"plots skipped: {plot.INSTALL_HINT}"
    plots: dict[str, str] = {}
    kinds = set(PLOT_FILES if only is None else only)
    try:
        if "fit" in kinds and not all(is_moduli(c) for c in curves):
            plot.plot_fit(cal, curves, out / PLOT_FILES["fit"],
                          title=None if not demo else
                          f"synthetic SEBS (paper Table 5): {cal.model.hyperelastic.name} + "
                          f"{cal.n_prony} Prony terms, RMSAPE {cal.rmsape:.3g} %",
                          lines=lines)
            plots["fit"] = PLOT_FILES["fit"]
        if "moduli" in kinds and any(is_moduli(c) for c in curves):  # sweeps, relaxation
            plot.plot_moduli_fit(cal, raw or curves, out / PLOT_FILES["moduli"])
            plots["moduli"] = PLOT_FILES["moduli"]
        if "history" in kinds and cal.history and cal.history.get("nit"):
            plot.plot_history(cal, out / PLOT_FILES["history"])
            plots["history"] = PLOT_FILES["history"]
        if "order_scan" in kinds and cal.order_scan:
            plot.plot_order_scan(cal, out / PLOT_FILES["order_scan"])
            plots["order_scan"] = PLOT_FILES["order_scan"]
    except Exception as exc:
        return plots, f"plots failed: {one_line(exc)}"
    return plots, None


def _jsonable(d: dict) -> dict:
    out = {k: v for k, v in d.items() if not k.startswith("_") and not callable(v)}
    for later in ("deformation", "formulation", "tref", "shift", "columns", "units",
                  "group_by", "select", "bounds"):
        if out.get(later, "") is None:  # not given: the record is as before the flag
            del out[later]
    return out


def _fitted_csv(cal: Calibration, curves, fits, label, interrupted) -> str:
    buf = io.StringIO()
    buf.write("# vhfit fitted curves: data and calibrated model, per curve\n")
    if label:
        buf.write(f"# data: {label}\n")
    buf.write(f"# model: {cal.model.spec().describe()}; "
              f"RMSAPE {cal.rmsape:.6g} %" + ("; INTERRUPTED" if interrupted else "") + "\n")
    buf.write("# kind=point: objective points (stress_data = data, stress_model = model); "
              "kind=fine: model on a fine time grid (stress_data empty)\n")
    buf.write("# units: s, engineering strain, MPa (in each curve's measure)\n")
    # other tests than the paper's add two columns: the test, and the loaded direction
    tests = {get_deformation(c.deformation) for c in curves}
    modes = not all(t.uniaxial for t in tests)
    if modes:
        strains = "".join(f"; {t.name}: strain = {t.strain_label}"
                          for t in sorted(tests, key=lambda t: t.name) if t.shear)
        buf.write("# deformation: the test; direction: 1, or 2 for the second stress of a "
                  "test with two loaded directions; equilibrium curves: time = sample number, "
                  f"strain_rate empty{strains}\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["curve", "strain_rate", "measure", "kind", "time", "strain", "stress_data",
                "stress_model"] + (["deformation", "direction"] if modes else []))
    for c, f in zip(curves, fits):
        if _moduli.is_moduli_fit(f):  # in fitted_moduli.csv
            continue
        name = str(c.name)
        r = c.strain_rate
        rate = "" if r is None else f"{float(r):g}"
        meas = c.measure
        dfm = [c.deformation] if modes else []
        dirs = c.target_direction
        for t, e, s, m, d in zip(f["time"], f["strain"], f["stress"], f["model"], dirs):
            w.writerow([name, rate, meas, "point", f"{t:.9g}", f"{e:.9g}", f"{s:.9g}", f"{m:.9g}"]
                       + (dfm + [int(d)] if modes else []))
        for t, e, m in zip(f["fine_time"], f["fine_strain"], f["fine_model"]):
            w.writerow([name, rate, meas, "fine", f"{t:.9g}", f"{e:.9g}", "", f"{m:.9g}"]
                       + (dfm + [1] if modes else []))
    return buf.getvalue()
