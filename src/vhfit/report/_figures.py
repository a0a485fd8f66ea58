"""The report's figures, each drawn in memory and inlined as a base64 PNG.

The fit, stress–time, moduli, shift-factor, order-scan and history figures are
:mod:`vhfit.plot`'s; the residuals are drawn here. Every figure is drawn on a bare Agg
:class:`matplotlib.figure.Figure` (no display, no pyplot state); one that fails leaves
a one-line note in its place, never a failed report.
"""

from __future__ import annotations

import base64
import dataclasses
import io
import warnings
from collections.abc import Callable
from types import SimpleNamespace

import numpy as np

from vhfit import plot
from vhfit.data import is_moduli
from vhfit.modes import get_deformation

#: dots per inch of the figures drawn here (vhfit.plot's own are at 120)
DPI = 100


@dataclasses.dataclass
class Figure:
    """One figure of the report: its title, a caption, and the ``<img>`` data URI or a note."""

    key: str
    title: str
    caption: str = ""
    uri: str | None = None
    note: str | None = None


def _draw(key: str, title: str, caption: str, make: Callable[[io.BytesIO], object]) -> Figure:
    """Run a plot function into memory; a failure becomes the figure's note."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # nothing from matplotlib leaks to stderr
            buf = io.BytesIO()
            make(buf)  # each draws its figure into buf, once
            uri = "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")
    except Exception as exc:  # a figure never stops the report
        text = " ".join(str(exc).split()) or type(exc).__name__
        return Figure(key, title, caption, note=f"figure not drawn: {text}")
    return Figure(key, title, caption, uri=uri)


def from_file(key: str, title: str, caption: str, path) -> Figure:
    """A figure already drawn into a PNG file (``vhfit fit``'s own plots), inlined."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as exc:
        return Figure(key, title, caption, note=f"figure not read: {exc.strerror}")
    return Figure(key, title, caption,
                  uri="data:image/png;base64," + base64.b64encode(data).decode("ascii"))


def _save(fig, buf) -> None:
    fig.savefig(buf, format="png", dpi=DPI)  # constrained layout: no second, tight pass


def _bare(nrows: int, ncols: int, size: tuple[float, float]):
    from matplotlib.figure import Figure as MplFigure

    fig = MplFigure(figsize=size, layout="constrained")
    return fig, fig.subplots(nrows, ncols, squeeze=False)


def mode_name(mode: str) -> str:
    """The test's name for a figure title, from its record ('planar (pure shear)')."""
    return get_deformation(mode).description.split(":")[0]


def modes_of(curves) -> dict[str, list[int]]:
    """Deformation mode -> indices of the stress–strain curves in it (data order)."""
    out: dict[str, list[int]] = {}
    for i, c in enumerate(curves):
        if not is_moduli(c):
            out.setdefault(str(c.deformation), []).append(i)
    return out


def _subset(cal, idx: list[int]):
    """The calibration with the per-curve errors of the curves ``idx`` (for plot_fit)."""
    errs = list(cal.per_curve_rmsape or [])
    return dataclasses.replace(cal, per_curve_rmsape=[errs[i] if i < len(errs) else np.nan
                                                      for i in idx])


def fit_figures(cal, curves, fits: list, drawn=None) -> list[Figure]:
    """Data against model, one figure per deformation mode; then stress against time.

    ``drawn``: a PNG file of :func:`vhfit.plot.plot_fit` of all the curves (``vhfit
    fit``'s ``fit.png``), used as the one fit figure (drawing the curves again would
    double the time): its panels hold each mode's curves, each curve labelled with its
    test, and the stress–time panels.
    """
    out = []
    groups = modes_of(curves)
    timed = [c for c in curves if not is_moduli(c) and plot.has_holds_or_unloading(c)]
    if drawn is not None and groups:
        cap = "curves whose stresses differ by more than 10x are on separate panels"
        if len(groups) > 1:
            cap += "; shear tests and principal tests on panels of their own"
        if timed:
            cap += "; below, stress against time of the histories with holds or unloading"
        names = ", ".join(mode_name(m) for m in groups)
        out.append(from_file("fit-" + "-".join(groups), f"{names}: data (markers) "
                             "and model (lines)", cap, drawn))
        return out
    for mode, idx in groups.items():
        name = mode_name(mode)
        sub, cs = _subset(cal, idx), [curves[i] for i in idx]
        title = f"{name}: data (markers) and model (lines)"
        out.append(_draw(f"fit-{mode}", title,
                         "curves whose stresses differ by more than 10x are on separate panels",
                         lambda buf, sub=sub, cs=cs, t=title: plot.plot_fit(
                             sub, cs, buf, title=t, time_panels=False)))
    if timed:
        more = len(timed) > plot.MAX_TIME_PANELS
        cap = ("the model along each history (its breakpoints, the data's own points and "
               "points inside each ramp and hold); "
               + ("the first ones shown, the others named" if more
                  else "every such history shown"))
        out.append(_draw("stress-time", "stress against time (histories with holds or "
                         "unloading)", cap, lambda buf: plot.plot_stress_time(cal, curves, buf)))
    return out


def residual_figure(cal, curves, fits: list) -> Figure:
    """Model minus data in percent of each curve's peak stress, a panel per mode."""
    def make(buf):
        groups = modes_of(curves)
        fig, axes = _bare(1, len(groups), (4.6 * len(groups), 3.3))
        for ax, (mode, idx) in zip(axes[0], groups.items()):
            for k, i in enumerate(idx):
                f = fits[i]
                peak = max(float(np.max(np.abs(f["stress"]))), 1e-300)
                ax.plot(f["strain"], 100.0 * (f["model"] - f["stress"]) / peak, "o", ms=2.5,
                        color=f"C{k % 10}", label=str(curves[i].name)[:40])
            ax.axhline(0.0, color="0.4", lw=0.8)
            ax.set_xlabel(get_deformation(mode).strain_label)
            ax.set_ylabel("model − data (% of the curve's peak)")
            ax.set_title(mode_name(mode), fontsize=9)
            ax.grid(True, alpha=0.3)
            if len(idx) <= 10:
                plot.legend_beside(ax, 6)
        _save(fig, buf)
        return fig

    return _draw("residuals", "residuals", "model − data at the objective points, in percent "
                 "of each curve's largest |stress|", make)


def moduli_figure(cal, curves) -> Figure:
    return _draw("moduli", "frequency sweeps and relaxation tests",
                 "E-type moduli, markers data, lines model"
                 + (" (at the reference temperature)" if cal.shift_table else ""),
                 lambda buf: plot.plot_moduli_fit(cal, curves, buf))


def shift_figure(cal) -> Figure:
    """log10 a_T of each temperature, and the calibration's law as a line."""
    def make(buf):
        T = sorted(cal.shift_table)
        table = SimpleNamespace(temperatures=np.array(T, dtype=np.float64),
                                log_aT=np.array([cal.shift_table[t] for t in T],
                                                dtype=np.float64), law=cal.shift)
        return plot.plot_shift_factors(table, buf, label="applied to the tests")

    return _draw("shift", "time–temperature shift factors", "", make)


def scan_figure(cal) -> Figure:
    return _draw("order-scan", "error against the number of Prony terms", "",
                 lambda buf: plot.plot_order_scan(cal, buf))


def history_figure(cal) -> Figure:
    return _draw("history", "error against generation", "best and population mean",
                 lambda buf: plot.plot_history(cal, buf))
