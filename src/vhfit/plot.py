"""Plots of a calibration: data against fit, error against generation and against N.

matplotlib is an optional dependency (``pip install 'vhfit[plot]'``); it is imported
only when a plot is drawn, so everything else in vhfit works without it. With a
``path`` the figure is drawn on a bare :class:`matplotlib.figure.Figure` (Agg
canvas, no display needed) and saved; without one it is made with pyplot so that it
shows in a notebook or an interactive session.

The DMA plots (docs/dma.md) take a :class:`vhfit.tts.MasterCurve`: the raw sweeps
coloured by temperature, the master curve (with a fitted Prony spectrum), the shift
factors with the fitted law, and the relative residuals of the spectrum.

The data-against-fit plot puts curves whose stress magnitudes differ by more than a
factor ``ratio`` (default 10) on separate panels, as the paper did for SEBS and
gelatin (its Figs. 10 and 11): a slow curve at 0.1 MPa is invisible next to a fast
one at 2 MPa on a common axis. Each test is drawn as its deformation record
(:mod:`vhfit.modes`) describes it: the axes are labelled from the record (γ and the
shear stress in simple shear; the tension/compression note only as the data have
it), both loaded directions are shown, a general biaxial test is drawn per series of
held stretch, and the model follows each curve's own history (:func:`model_line`);
histories with holds or unloading get stress–time panels (:func:`plot_stress_time`).
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import sys
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np

from vhfit.data import is_moduli
from vhfit.modes import get_deformation
from vhfit.spectrum import design_matrix

__all__ = [
    "PlotUnavailable",
    "have_matplotlib",
    "group_by_magnitude",
    "plot_fit",
    "plot_moduli_fit",
    "plot_stress_time",
    "model_line",
    "model_lines",
    "has_holds_or_unloading",
    "plot_history",
    "plot_order_scan",
    "plot_sweeps",
    "plot_master_curve",
    "plot_shift_factors",
    "plot_spectrum_residuals",
    "marked",
]

INSTALL_HINT = "plots need matplotlib: pip install 'vhfit[plot]' (or pip install matplotlib)"


class PlotUnavailable(ImportError):
    """matplotlib is not installed; the message says how to get it."""


def have_matplotlib() -> bool:
    """Whether matplotlib is installed (found on the path, not imported: its import
    takes a tenth of a second that a run without figures need not pay)."""
    if "matplotlib" in sys.modules:  # loaded (or set to None: an import that fails)
        return sys.modules["matplotlib"] is not None
    from importlib.util import find_spec

    return find_spec("matplotlib") is not None


def _figure(path, nrows: int = 1, ncols: int = 1, **kw) -> tuple[Any, Any]:
    """A figure and its axes (none for ``nrows == 0``): bare Agg figure when saving,
    pyplot figure otherwise."""
    try:
        if path is not None:
            from matplotlib.figure import Figure

            fig = Figure(**kw)
        else:
            import matplotlib.pyplot as plt

            fig = plt.figure(**kw)
    except ImportError:
        raise PlotUnavailable(INSTALL_HINT) from None
    return fig, (fig.subplots(nrows, ncols, squeeze=False) if nrows else None)


#: The mark of the figures drawn inside :func:`marked` (None: no mark).
_MARK: contextvars.ContextVar[str | None] = contextvars.ContextVar("vhfit_plot_mark",
                                                                   default=None)


@contextlib.contextmanager
def marked(text: str) -> Iterator[None]:
    """Mark every figure drawn inside the block with ``text``: a red line above the
    figure, and the PNG's ``Description`` (what an interrupted fit's plots say).

    Parameters
    ----------
    text : str
        The mark, e.g. ``"INTERRUPTED: best parameters so far, not converged"``.

    Returns
    -------
    context manager
        Figures drawn by this module's functions inside it carry the mark.

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> from vhfit.plot import marked, plot_fit
    >>> m = vhfit.ViscoHyperelastic("neo_hooke", 0)
    >>> eps = np.linspace(0.0, -0.3, 8)
    >>> c = vhfit.Curve(strain=eps, stress=m.stress({"C10": 0.1}, strain=eps,
    ...                 strain_rate=-1.0, measure="engineering"), strain_rate=-1.0)
    >>> cal = vhfit.calibrate([c], hyperelastic="neo_hooke", n_prony=0, seed=0)
    >>> import io
    >>> with marked("INTERRUPTED"):
    ...     fig = plot_fit(cal, [c], io.BytesIO())
    >>> fig.texts[-1].get_text()  # above the title
    'INTERRUPTED'
    """
    token = _MARK.set(str(text))
    try:
        yield
    finally:
        _MARK.reset(token)


def _finish(fig, path):
    mark = _MARK.get()
    meta = {}
    if mark is not None:
        fig.text(0.5, 1.0, mark, ha="center", va="bottom", color="red", fontsize=11,
                 fontweight="bold")
        meta = {"Description": mark}
    if hasattr(path, "write"):  # a file object (the HTML report draws in memory): a PNG,
        fig.savefig(path, dpi=100, format="png", metadata=meta,  # laid out by the figure
                    bbox_inches="tight" if mark else None)  # (the mark is above it)
    elif path is not None:  # laid out by the figure too: one drawing, not a tight second
        fig.savefig(os.fspath(path), dpi=120, metadata=meta,
                    bbox_inches="tight" if mark else None)
    return fig


def legend_beside(ax, fontsize: float = 7):
    """The axes' legend beside them, at their top right, outside: a legend inside the
    axes can cover a curve wherever it is put; constrained layout makes room for it.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    fontsize : float

    Returns
    -------
    matplotlib.legend.Legend
    """
    return ax.legend(fontsize=fontsize, loc="upper left", bbox_to_anchor=(1.02, 1.0),
                     borderaxespad=0.0)


# ------------------------------------------------------------------- grouping
def group_by_magnitude(peaks: Sequence[float], ratio: float = 10.0) -> list[list[int]]:
    """Indices of curves grouped into panels of comparable stress magnitude.

    Curves are sorted by their peak |stress|; a new group starts whenever a curve's
    peak exceeds ``ratio`` times the smallest peak of the current group. Within each
    group the original order is kept.

    Parameters
    ----------
    peaks : sequence of float
        Peak |stress| of each curve.
    ratio : float
        Largest spread of peaks within one panel.

    Returns
    -------
    list of list of int

    Examples
    --------
    >>> group_by_magnitude([0.08, 0.11, 0.96, 1.7])
    [[0, 1], [2, 3]]
    >>> group_by_magnitude([1.0, 2.0, 3.0])
    [[0, 1, 2]]
    """
    if not ratio > 1:
        raise ValueError(f"ratio = {ratio!r} must be > 1")
    p = np.abs(np.asarray(peaks, dtype=np.float64))
    order = np.argsort(p, kind="stable")
    groups: list[list[int]] = []
    low = None
    for i in order:
        if low is None or p[i] > ratio * max(low, 1e-300):
            groups.append([])
            low = p[i]
        groups[-1].append(int(i))
    return [sorted(g) for g in groups]


# --------------------------------------------------------------------- curves
#: most data markers drawn per curve: a long record is thinned evenly for the eye (the
#: model line is evaluated at every objective point regardless)
MAX_MARKERS = 300
#: at most this many histories get a stress–time panel in :func:`plot_fit`
MAX_TIME_PANELS = 6
#: model points inside a linear piece of a history that travels the whole strain range
#: (fewer for a shorter piece), and inside a piece that lasts the whole test (spaced
#: geometrically from its start, where a hold relaxes fastest)
RAMP_POINTS = 60
HOLD_POINTS = 40
#: most items named in a legend of plot_moduli_fit (more: coloured without names)
MAX_LEGEND_ITEMS = 8
#: temperatures closer than this are one temperature of a calibration's shift table
SAME_TEMPERATURE = 1.0
#: most points of one model line
MAX_LINE_POINTS = 6000
#: points of the model line of an equilibrium curve (uniform in its strain)
EQUILIBRIUM_POINTS = 200


def _label(curve, i: int) -> str:
    name, rate = curve.name, curve.strain_rate
    text = str(name) if name else f"curve {i + 1}"
    if rate is not None and np.isfinite(rate) and f"{rate:.3g}" not in text:
        text += f" ({rate:.3g} 1/s)"
    return text


def _thin(n: int, most: int = MAX_MARKERS) -> np.ndarray:
    """Indices of at most ``most`` of ``n`` samples, evenly spread, both ends kept."""
    if n <= most:
        return np.arange(n)
    return np.unique(np.round(np.linspace(0, n - 1, most)).astype(np.int64))


def _data_points(curve) -> dict[str, Any]:
    """The curve's samples as given (or its objective points): time (None without one),
    strain, stress, and strain2, stress2 of a second direction (None without)."""
    eps, sig = curve.strain, curve.stress
    t = curve.time
    e2, s2 = curve.strain2, curve.stress2
    if np.shape(eps) != np.shape(sig):  # a curve built from its points alone
        eps, sig, t = curve.history.out_strain, curve.target_stress, None
        e2 = s2 = None
    def f64(a):
        return None if a is None else np.asarray(a, dtype=np.float64)

    if s2 is not None and np.shape(s2) != np.shape(sig):
        s2 = None
    return {"time": f64(t), "strain": f64(eps), "stress": f64(sig), "strain2": f64(e2),
            "stress2": f64(s2)}


def _line_times(h, t_obj: np.ndarray) -> np.ndarray:
    """Times of a model line along a history: its breakpoints, the objective points,
    and points inside each linear piece (a ramp by its strain travel, a hold by its
    duration, geometrically from its start)."""
    tb = np.asarray(h.time, dtype=np.float64)
    strain = get_deformation(h.deformation).strain(np.asarray(h.stretch, dtype=np.float64))
    span = max(float(np.ptp(strain)), 1e-300)
    dur = np.diff(tb)
    n_ramp = np.ceil(RAMP_POINTS * np.abs(np.diff(strain)) / span)
    n_hold = np.ceil(HOLD_POINTS * dur / max(float(tb[-1] - tb[0]), 1e-300))
    n = np.maximum(n_ramp, n_hold)
    scale = min(1.0, MAX_LINE_POINTS / max(float(n.sum()), 1.0))
    n = np.ceil(n * scale).astype(np.int64)
    parts = [tb, np.asarray(t_obj, dtype=np.float64)]
    for k in np.flatnonzero(n > 1):
        u = (np.geomspace(1e-3, 1.0, n[k]) if n_hold[k] > n_ramp[k]
             else np.linspace(0.0, 1.0, n[k] + 1)[1:])
        parts.append(tb[k] + u[:-1] * dur[k])
    t = np.unique(np.concatenate(parts))
    return t[(t >= tb[0]) & (t <= tb[-1])]


def model_line(cal, curve) -> dict[str, np.ndarray]:
    """The calibrated model along a curve's own history, for drawing.

    A history in time (a ramp, a ramp–hold, a loading–unloading record) is evaluated
    at its breakpoints, at its objective points (the data's own samples, or their bin
    means for a long record) and at points inside each ramp and hold, so that a short
    ramp before a long hold is drawn as finely as the hold. An equilibrium curve is
    drawn on a grid uniform in its strain.

    Parameters
    ----------
    cal : Calibration
        Or any object with ``model`` and ``params``.
    curve : Curve
        A stress–strain curve (one of the data it was fitted to).

    Returns
    -------
    dict
        ``time`` (s; NaN for an equilibrium curve), ``strain`` (λ1 − 1, or γ in simple
        shear) and ``model`` (MPa, the curve's measure, direction 1); ``model2``, the
        stress of the second loaded direction, when the curve gives one.

    Examples
    --------
    >>> import vhfit
    >>> m = vhfit.ViscoHyperelastic("neo_hooke", n_prony=1)
    >>> p = dict(C10=0.5, G1=1.0, tau1=10.0)
    >>> c = vhfit.Curve(time=[0, 1, 100], strain=[0, 0.2, 0.2], stress=[0, 0.4, 0.2])
    >>> class Cal: model, params = m, p
    >>> line = model_line(Cal, c)            # a 1 s ramp, then a 99 s hold
    >>> int((line["time"] < 1.0).sum()), line["time"].size
    (60, 101)
    """
    h = curve.history
    test = get_deformation(h.deformation)
    two = test.directions == 2 and curve.stress2 is not None
    if h.is_equilibrium:
        if h.stretch2 is not None:
            raise ValueError("a curve with a second prescribed stretch is drawn as series "
                             "(plot_fit), not as one line")
        e = np.asarray(h.out_strain, dtype=np.float64)
        fine = np.linspace(float(e.min()), float(e.max()), EQUILIBRIUM_POINTS)
        h = type(h).equilibrium(fine, deformation=h.deformation)
        t = np.arange(fine.size, dtype=np.float64)
    else:
        t = _line_times(h, curve.target_time)
    n = t.size
    hist = (h.with_outputs(np.concatenate([t, t]), np.repeat([1, 2], n)) if two
            else h.with_outputs(t))
    stress = np.asarray(cal.model.stress(cal.params, hist, measure=curve.measure),
                        dtype=np.float64)
    out = {"time": np.full(n, np.nan) if h.is_equilibrium else t,
           "strain": np.asarray(hist.out_strain[:n], dtype=np.float64),
           "model": stress[:n]}
    if two:
        out["model2"] = stress[n:]
    return out


def model_lines(cal, curves: Sequence) -> list[dict[str, np.ndarray] | None]:
    """The model line (:func:`model_line`) of each stress–strain curve among ``curves``,
    as :func:`plot_fit` draws them: None for an equilibrium test with a second prescribed
    stretch (drawn as series of held stretch, not as one line).

    They can be computed where the model is at hand and drawn elsewhere (``plot_fit``'s
    ``lines=``): ``vhfit fit`` evaluates them beside its fit, whose compiled kernels are
    loaded, and draws them in a process that has loaded matplotlib.

    Parameters
    ----------
    cal : Calibration
        Or any object with ``model`` and ``params``.
    curves : sequence of Curve
        Frequency sweeps and relaxation tests among them are skipped.

    Returns
    -------
    list
        One entry per stress–strain curve, in order.

    Examples
    --------
    >>> import vhfit
    >>> m = vhfit.ViscoHyperelastic("neo_hooke", n_prony=0)
    >>> c = vhfit.Curve(strain=[0.0, 0.1, 0.2], stress=[0.0, 0.1, 0.2], strain_rate=None)
    >>> class Cal: model, params = m, {"C10": 0.5}
    >>> [sorted(line) for line in model_lines(Cal, [c])]
    [['model', 'strain', 'time']]
    """
    curves = [c for c in curves if not is_moduli(c)]
    return [None if get_deformation(c.deformation).second_stretch and c.history.is_equilibrium
            else model_line(cal, c) for c in curves]


def _series(e1: np.ndarray, e2: np.ndarray) -> tuple[list[np.ndarray], int]:
    """Runs of consecutive samples of a two-stretch test in which one strain is held:
    (the runs, the direction whose strain varies within them: 1 or 2)."""
    def runs(held):
        d = np.abs(np.diff(held)) > 1e-9 * max(float(np.max(np.abs(held))), 1e-300)
        return np.split(np.arange(held.size), np.flatnonzero(d) + 1)

    r1, r2 = runs(e1), runs(e2)
    return (r1, 2) if len(r1) <= len(r2) else (r2, 1)


def _sign_note(modes: set) -> str:
    """What the strain's sign means, from the curves' loading modes."""
    if "mixed" in modes or {"tension", "compression"} <= modes:
        return " (tension > 0, compression < 0)"
    return " (compression < 0)" if "compression" in modes else ""


def _axis_labels(curves) -> tuple[str, str]:
    """(x, y) labels of a stress–strain panel, from the curves' deformation records."""
    tests = [get_deformation(c.deformation) for c in curves]
    xs = sorted({t.strain_label for t in tests})
    x = "; ".join(xs)
    if not any(t.shear for t in tests):
        x += _sign_note({c.mode for c in curves})
    measures = sorted({c.measure for c in curves if not get_deformation(c.deformation).shear})
    ys = {t.stress_label for t in tests if t.shear}  # the same in both measures
    if measures:
        ys.add(f"{measures[0]} stress (MPa)" if len(measures) == 1
               else "stress (MPa, each curve's measure)")
    return x, "; ".join(sorted(ys))


def has_holds_or_unloading(curve) -> bool:
    """Whether a curve's history in time holds its strain or reverses it.

    Parameters
    ----------
    curve : Curve

    Returns
    -------
    bool
        False for a monotone ramp and for an equilibrium curve.

    Examples
    --------
    >>> import vhfit
    >>> has_holds_or_unloading(vhfit.Curve(time=[0, 1, 2], strain=[0, 0.2, 0.2],
    ...                                    stress=[0, 1, 0.8]))
    True
    >>> has_holds_or_unloading(vhfit.Curve(strain=[0.1, 0.2], stress=[1, 2],
    ...                                    strain_rate=0.1))
    False
    """
    h = curve.history
    if h.is_equilibrium or np.size(h.time) < 3:
        return bool(not h.is_equilibrium and curve.time is not None
                    and np.size(curve.time) >= 3 and _holds(curve.time, curve.strain))
    return _holds(h.time, get_deformation(h.deformation).strain(np.asarray(h.stretch)))


def _holds(t, e) -> bool:
    e = np.asarray(e, dtype=np.float64)
    d = np.diff(e)
    scale = max(float(np.max(np.abs(e))), 1e-300)
    held = (np.abs(d) <= 1e-6 * scale) & (np.diff(np.asarray(t, dtype=np.float64)) > 0)
    return bool(held.any() or ((d > 1e-6 * scale).any() and (d < -1e-6 * scale).any()))


def _panels(curves, peaks, ratio: float) -> list[tuple[str, list[int]]]:
    """Stress–strain panels: (kind, curve indices). Shear curves and principal tests
    get panels of their own, split by stress magnitude; an equilibrium test with a
    second prescribed stretch gets two panels (one per direction) per curve, drawn by
    series of held stretch."""
    kinds: dict[str, list[int]] = {}
    for i, c in enumerate(curves):
        t = get_deformation(c.deformation)
        series = t.second_stretch and c.history.is_equilibrium  # a history in time: a line
        kinds.setdefault("second" if series else "shear" if t.shear
                         else "principal", []).append(i)
    out = []
    for kind in ("principal", "shear"):
        idx = kinds.get(kind, [])
        if idx:
            for g in group_by_magnitude([peaks[i] for i in idx], ratio):
                out.append((kind, [idx[k] for k in g]))
    for i in kinds.get("second", []):
        out.append(("second-1", [i]))
        if curves[i].stress2 is not None:
            out.append(("second-2", [i]))
    return out


def plot_fit(cal, curves: Sequence, path=None, *, ratio: float = 10.0,
             title: str | None = None, time_panels: bool = True,
             lines: Sequence | None = None):
    """Data against the calibrated model, one colour per curve, panels by magnitude.

    Each test is drawn as its deformation record describes it: the axes name its strain
    and stress (γ and the shear stress in simple shear; the sign note only when the
    data have compression), a test with two loaded directions shows both (squares and
    dashed lines for direction 2), and a test with a second prescribed stretch
    (general biaxial) is drawn per series of held stretch, one panel per direction,
    coloured by the held stretch. The model is evaluated along each curve's own history
    (:func:`model_line`). Histories that hold or unload get stress–time panels too.

    Parameters
    ----------
    cal : Calibration
        The calibration (``.model``, ``.params``, optional ``.per_curve_rmsape``).
    curves : sequence of Curve
        The data it was fitted to.
    path : path-like or binary file object, optional
        Save the figure there (PNG, PDF, SVG... by extension; a file object gets a PNG)
        without needing a display.
    ratio : float
        Curves whose peak stresses differ by more than this factor go on separate
        panels (see :func:`group_by_magnitude`).
    title : str, optional
        Figure title; default names the model and the overall RMSAPE.
    time_panels : bool
        Add stress against time for the histories with holds or unloading (at most
        ``MAX_TIME_PANELS``, the others named in the last panel's title).
    lines : sequence, optional
        The model lines of these curves (:func:`model_lines` of the same calibration and
        curves), computed already; default: computed here.

    Returns
    -------
    matplotlib.figure.Figure
    """
    lines = model_lines(cal, curves) if lines is None else list(lines)
    curves = [c for c in curves if not is_moduli(c)]
    if not curves:
        raise ValueError("no stress-strain curves to plot: draw frequency sweeps and "
                         "relaxation tests with plot_moduli_fit")
    data = [_data_points(c) for c in curves]
    peaks = [max(np.max(np.abs(d["stress"])),
                 0.0 if ln is None else np.max(np.abs(ln["model"])))
             for d, ln in zip(data, lines)]
    panels = _panels(curves, peaks, ratio)
    timed = ([i for i, c in enumerate(curves) if lines[i] is not None
              and has_holds_or_unloading(c)] if time_panels else [])
    shown = timed[:MAX_TIME_PANELS]
    top_cols = min(len(panels), 3)
    top_rows = -(-len(panels) // top_cols)
    bot_cols = min(len(shown), 3)
    bot_rows = -(-len(shown) // bot_cols) if shown else 0
    width = max(6.0, 5.0 * max(top_cols, bot_cols))
    fig, subs = _subfigures(path, [4.2 * top_rows, 3.2 * bot_rows], (width, 0.0))
    axes = subs[0].subplots(top_rows, top_cols, squeeze=False).ravel()
    errs = list(cal.per_curve_rmsape or [])
    colours = _curve_colours(len(curves))
    for ax, (kind, group) in zip(axes, panels):
        if kind.startswith("second"):
            _draw_series(subs[0], ax, cal, curves[group[0]], data[group[0]],
                         int(kind[-1]), group[0], errs)
            continue
        cs = [curves[i] for i in group]
        several = len({c.deformation for c in cs}) > 1
        for i in group:
            d, ln, c = data[i], lines[i], curves[i]
            lab = _label(c, i)
            test = get_deformation(c.deformation)
            if several and not any(a in lab.lower() for a in (test.name, *test.aliases)):
                lab += f", {test.name}"
            if i < len(errs) and np.isfinite(errs[i]):
                lab += f", RMSAPE {errs[i]:.3g} %"
            k = _thin(d["strain"].size)
            ax.plot(d["strain"][k], d["stress"][k], "o", ms=3.5, mfc="none",
                    color=colours[i], label=lab)
            ax.plot(ln["strain"], ln["model"], "-", lw=1.4, color=colours[i])
            if "model2" in ln:
                ax.plot(d["strain"][k], d["stress2"][k], "s", ms=3.5, mfc="none",
                        color=colours[i])
                ax.plot(ln["strain"], ln["model2"], "--", lw=1.4, color=colours[i])
        xl, yl = _axis_labels(cs)
        if any("model2" in lines[i] for i in group):
            yl += "; direction 2: squares, dashed"
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.locator_params(axis="x", nbins=6)  # ticks such as -0.075 stay apart
        ax.grid(True, alpha=0.3)
        ax.axhline(0, color="0.6", lw=0.6)
        legend_beside(ax, 7)
    for ax in axes[len(panels):]:
        ax.set_visible(False)
    if shown:
        _time_panels(subs[1], cal, curves, data, lines, shown, timed[len(shown):], colours)
    if title is None:
        title = cal.model.spec().describe()
        if cal.rmsape is not None:
            title += f": RMSAPE {cal.rmsape:.3g} %"
    if "markers" not in title:  # the report's titles say it already
        title += "\nmarkers: data, lines: model"
    fig.suptitle(title, fontsize=10)
    return _finish(fig, path)


def plot_stress_time(cal, curves: Sequence, path=None):
    """Stress against time of the histories that hold or unload: data and model.

    One panel per history (at most ``MAX_TIME_PANELS``; the others are named in the
    title), the model along the history as :func:`model_line` evaluates it.

    Parameters
    ----------
    cal : Calibration
    curves : sequence of Curve
        The data it was fitted to; curves without holds or unloading are skipped.
    path : path-like or binary file object, optional

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        No curve holds or unloads.
    """
    curves = [c for c in curves if not is_moduli(c)]
    timed = [i for i, c in enumerate(curves) if has_holds_or_unloading(c)]
    if not timed:
        raise ValueError("no history holds or unloads: plot_fit shows the ramps")
    shown = timed[:MAX_TIME_PANELS]
    data = {i: _data_points(curves[i]) for i in shown}
    lines = {i: model_line(cal, curves[i]) for i in shown}
    cols = min(len(shown), 3)
    fig, subs = _subfigures(path, [3.2 * -(-len(shown) // cols)], (5.0 * cols, 0.0))
    more = timed[len(shown):]
    _time_panels(subs[0], cal, curves, data, lines, shown, more,
                 _curve_colours(len(curves)), heading=False)
    head = "stress against time; markers: data, lines: model"
    if more:
        head += f"\nnot shown: {', '.join(str(curves[i].name) for i in more)}"
    fig.suptitle(head, fontsize=10)
    return _finish(fig, path)


def mode_name(deformation) -> str:
    """The test's short name from its record (``'planar (pure shear)'``)."""
    return get_deformation(deformation).description.split(":")[0]


def _curve_colours(n: int) -> list:
    from matplotlib import colormaps

    cmap = colormaps["viridis"]
    return [cmap(0.9 * i / max(n - 1, 1)) for i in range(n)]


def _subfigures(path, heights: list[float], size: tuple[float, float]):
    """A figure of stacked sub-figures of the given heights (those > 0)."""
    fig, _ = _figure(path, 0, 0, figsize=(size[0], sum(heights) + 0.5),
                     layout="constrained")
    used = [h for h in heights if h > 0]
    subs = fig.subfigures(len(used), 1, height_ratios=used, squeeze=False).ravel()
    return fig, list(subs)


def _time_panels(sub, cal, curves, data, lines, shown, more, colours,
                 heading: bool = True) -> None:
    """Stress against time: one panel per history, data markers and the model line."""
    cols = min(len(shown), 3)
    rows = -(-len(shown) // cols)
    axes = sub.subplots(rows, cols, squeeze=False).ravel()
    for ax, i in zip(axes, shown):
        d, ln, c = data[i], lines[i], curves[i]
        tt = d["time"] if d["time"] is not None else c.target_time
        ss = d["stress"] if d["time"] is not None else c.target_stress
        k = _thin(np.size(tt))
        ax.plot(np.asarray(tt)[k], np.asarray(ss)[k], "o", ms=3, mfc="none",
                color=colours[i])
        ax.plot(ln["time"], ln["model"], "-", lw=1.3, color=colours[i])
        if "model2" in ln and d["time"] is not None:
            ax.plot(d["time"][k], d["stress2"][k], "s", ms=3, mfc="none", color=colours[i])
            ax.plot(ln["time"], ln["model2"], "--", lw=1.3, color=colours[i])
        ax.set_title(_label(c, i), fontsize=9)
        ax.set_xlabel("time (s)")
        ax.set_ylabel(_axis_labels([c])[1])
        ax.locator_params(axis="x", nbins=6)
        ax.grid(True, alpha=0.3)
        ax.axhline(0, color="0.6", lw=0.6)
    for ax in axes[len(shown):]:
        ax.set_visible(False)
    if heading:
        head = "stress against time"
        if more:
            head += f" (not shown: {', '.join(str(curves[i].name) for i in more)})"
        sub.suptitle(head, fontsize=9)


def _draw_series(sub, ax, cal, curve, d, direction: int, i: int, errs) -> None:
    """A two-stretch test (general biaxial) per series of held stretch: the stress of
    ``direction`` against the varying strain, coloured by the held one."""
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    e1, e2 = d["strain"], d["strain2"]
    runs, varying = _series(e1, e2)
    x, held = (e2, e1) if varying == 2 else (e1, e2)
    sig = d["stress"] if direction == 1 else d["stress2"]
    heldv = [float(np.mean(held[r])) for r in runs]
    norm = Normalize(min(heldv), max(heldv) if max(heldv) > min(heldv) else min(heldv) + 1)
    cmap = colormaps["viridis"]
    test = get_deformation(curve.deformation)
    for r, hv in zip(runs, heldv):
        colour = cmap(norm(hv))
        ax.plot(x[r], sig[r], "o", ms=3.5, mfc="none", color=colour)
        lo, hi = float(x[r].min()), float(x[r].max())
        fine = np.linspace(lo, hi, 40) if hi > lo else x[r][:1]
        fixed = np.full(fine.size, hv)
        s1, s2 = (fixed, fine) if varying == 2 else (fine, fixed)
        h = type(curve.history).equilibrium(s1, deformation=curve.deformation, strain2=s2)
        h = h.with_outputs(np.arange(fine.size, dtype=np.float64),
                           np.full(fine.size, direction))
        m = cal.model.stress(cal.params, h, measure=curve.measure)
        ax.plot(fine, m, "-", lw=1.3, color=colour)
    other = 3 - varying
    ax.set_xlabel(f"engineering strain λ{varying} − 1 (λ{other} held in each series)")
    ax.set_ylabel(f"{curve.measure} stress {test.measured[direction - 1]} (MPa)")
    lab = _label(curve, i)
    if i < len(errs) and np.isfinite(errs[i]):
        lab += f", RMSAPE {errs[i]:.3g} %"
    ax.set_title(f"{lab}: direction {direction}", fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.axhline(0, color="0.6", lw=0.6)
    sub.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=ax,
                 label=f"held strain λ{other} − 1")


def plot_moduli_fit(cal, items: Sequence, path=None):
    """Frequency sweeps and relaxation tests against the calibrated model, log–log.

    Storage (circles) and loss (squares) moduli over frequency on one panel, relaxation
    moduli over time on another; markers are data, lines the model (E-type moduli).

    Parameters
    ----------
    cal : Calibration
    items : sequence
        The data it was fitted to; stress–strain curves among them are skipped.
    path : path-like, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    items = [c for c in items if is_moduli(c)]
    if not items:
        raise ValueError("no frequency sweeps or relaxation tests to plot")
    temps = [c.temperature for c in items]
    items = [_at_reference(cal, c, T) for c, T in zip(items, temps)]
    fits = cal.fitted_curves(items)
    sweeps = [i for i, f in enumerate(fits) if "storage" in f]
    relax = [i for i, f in enumerate(fits) if "storage" not in f]
    panels = [p for p in (sweeps, relax) if p]
    fig, axes = _figure(path, 1, len(panels), figsize=(5.6 * len(panels), 4.2),
                        layout="constrained")
    by_temp = all(T is not None for T in temps) and len(set(temps)) > 1
    for ax, panel in zip(axes[0], panels):
        # many items: coloured by temperature (a colour bar) or by order, no long legend
        named = not by_temp and len(panel) <= MAX_LEGEND_ITEMS
        colours = (_temperature_colours(fig, ax, [temps[i] for i in panel]) if by_temp
                   else _colours(len(panel)) if named
                   else _order_colours(fig, ax, len(panel)))
        for c, i in zip(colours, panel):
            f, lab = fits[i], _label(items[i], i)
            if "storage" in f:
                ax.plot(f["frequency"], f["storage"], "o", ms=3, mfc="none", color=c,
                        label=f"{lab}: E'" if named else None)
                ax.plot(f["frequency"], f["loss"], "s", ms=3, mfc="none", color=c,
                        label=f"{lab}: E''" if named else None)
                ax.plot(f["fine_frequency"], f["fine_storage"], "-", lw=1.2, color=c)
                ax.plot(f["fine_frequency"], f["fine_loss"], "--", lw=1.2, color=c)
            else:
                ax.plot(f["time"], f["modulus"], "o", ms=3, mfc="none", color=c,
                        label=lab if named else None)
                ax.plot(f["fine_time"], f["fine_model"], "-", lw=1.2, color=c)
        # items shifted to T_ref by the calibration sit at reduced frequency (time)
        sweep = "storage" in fits[panel[0]]
        _moduli_axes(ax, sweep, bool(cal.shift_table))
        _data_ylim(ax, [fits[i][k] for i in panel for k in ("storage", "loss", "modulus")
                        if k in fits[i]])
        if named:
            legend_beside(ax, 7)
        what = ("E' (o, solid) and E'' (s, dashed)" if sweep else "E(t)")
        noun = "sweep" if sweep else "relaxation test"
        ax.set_title(f"{len(panel)} {noun}{'s' if len(panel) > 1 else ''}: {what}",
                     fontsize=9)
    fig.suptitle("markers: data, lines: model", fontsize=10)
    return _finish(fig, path)


def _at_reference(cal, item, T):
    """A sweep or relaxation test at its measured temperature ``T``, shifted to the
    calibration's reference as the fit shifted it (its table of log10 a_T, else its
    law); an item without a temperature is taken as shifted already."""
    table = dict(cal.shift_table or {})
    law = cal.shift
    if T is None or not (table or law is not None):
        return item
    near = [k for k in table if abs(k - T) <= SAME_TEMPERATURE]
    if near:
        log_aT = table[min(near, key=lambda k: abs(k - T))]
    elif law is not None:
        log_aT = float(law.log_aT(np.asarray([T], dtype=np.float64))[0])
    else:
        return item
    return item.shifted(10.0 ** log_aT)


def plot_history(cal, path=None):
    """Best and mean error of each generation of the global search (log scale).

    Parameters
    ----------
    cal : Calibration
        With ``.history`` (lists ``nit``, ``best``, ``mean``).
    path : path-like, optional
        Save the figure there.

    Returns
    -------
    matplotlib.figure.Figure
    """
    h = cal.history or {}
    fig, axes = _figure(path, 1, 1, figsize=(5.5, 3.8), layout="constrained")
    ax = axes[0, 0]
    nit = np.asarray(h.get("nit", []), dtype=np.float64)
    if nit.size:
        best = np.asarray(h["best"], dtype=np.float64)
        mean = np.asarray(h["mean"], dtype=np.float64)
        pos = best > 0
        ax.semilogy(nit[pos], best[pos], label="best")
        okm = np.isfinite(mean) & (mean > 0)
        ax.semilogy(nit[okm], mean[okm], label="population mean", alpha=0.8)
        legend_beside(ax, 8)
    else:
        ax.text(0.5, 0.5, "no generations recorded", ha="center", va="center",
                transform=ax.transAxes)
    ax.set_xlabel("generation")
    ax.set_ylabel("RMSAPE (%)")
    ax.grid(True, which="both", alpha=0.3)
    ax.set_title("error against generation", fontsize=10)
    return _finish(fig, path)


def plot_order_scan(cal, path=None):
    """Error against the number of Prony terms (from ``n_prony="auto"``).

    Parameters
    ----------
    cal : Calibration
        With ``.order_scan``: a list of dicts with ``n_prony`` and ``rmsape``.
    path : path-like, optional
        Save the figure there.

    Returns
    -------
    matplotlib.figure.Figure
    """
    scan = list(cal.order_scan or [])
    if not scan:
        raise ValueError("this calibration has no order scan: calibrate with n_prony='auto'")
    fig, axes = _figure(path, 1, 1, figsize=(5.0, 3.6), layout="constrained")
    ax = axes[0, 0]
    n = [int(r["n_prony"]) for r in scan]
    e = [float(r["rmsape"]) for r in scan]
    ax.semilogy(n, e, "o-")
    chosen = (cal.options or {}).get("n_prony_chosen")
    if chosen in n:
        k = n.index(chosen)
        ax.semilogy([n[k]], [e[k]], "s", ms=11, mfc="none", color="C3",
                    label=f"chosen N = {chosen}")
        legend_beside(ax, 8)
    ax.set_xticks(n)
    ax.set_xlabel("number of Prony terms N")
    ax.set_ylabel("RMSAPE (%)")
    ax.grid(True, which="both", alpha=0.3)
    ax.set_title("error against number of Prony terms", fontsize=10)
    return _finish(fig, path)


# ------------------------------------------------------------------------ DMA
def _colours(n: int) -> list:
    from matplotlib import colormaps

    cmap = colormaps["coolwarm"]
    return [cmap(i / max(n - 1, 1)) for i in range(n)]


def _dma_figure(path, master, size: tuple[float, float]):
    """One-panel figure for a master curve: (figure, axes, is it frequency data)."""
    fig, axes = _figure(path, 1, 1, figsize=size, layout="constrained")
    return fig, axes[0, 0], master.domain == "frequency"


def _moduli_axes(ax, frequency: bool, reduced: bool) -> None:
    what = ("reduced frequency f a_T (Hz)" if reduced else "frequency (Hz)") if frequency \
        else ("reduced time t / a_T (s)" if reduced else "time (s)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(what)
    ax.set_ylabel("modulus (MPa)")
    ax.grid(True, which="both", alpha=0.3)


#: Axis and colour-bar label of temperatures: vhfit keeps a test's temperature in the
#: unit its file writes it in (°C, K or °F), so the label names that unit as the data's.
TEMPERATURE_LABEL = "temperature (unit of the data: °C, K or °F)"


def _temperature_colours(fig, ax, temps: Sequence[float]) -> list:
    """Colours of items at ``temps`` (blue cold, red hot) and a colour bar beside ``ax``."""
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    lo, hi = float(min(temps)), float(max(temps))
    norm = Normalize(lo, hi if hi > lo else lo + 1.0)
    cmap = colormaps["coolwarm"]
    fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=ax, label=TEMPERATURE_LABEL)
    return [cmap(norm(T)) for T in temps]


def _order_colours(fig, ax, n: int) -> list:
    """Colours of ``n`` items in data order and a colour bar numbering them."""
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    norm = Normalize(1, max(n, 2))
    cmap = colormaps["coolwarm"]
    from matplotlib.ticker import MaxNLocator

    bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=ax, label="item (data order)")
    bar.locator = MaxNLocator(integer=True)
    bar.update_ticks()
    return [cmap(norm(k + 1)) for k in range(n)]


def _data_ylim(ax, arrays) -> None:
    """Log y limits a decade beyond the data: a model line far outside them leaves the
    panel instead of squeezing the data into a strip."""
    y = np.concatenate([np.asarray(a, dtype=np.float64).ravel() for a in arrays])
    y = y[np.isfinite(y) & (y > 0)]
    if y.size:
        lo, hi = ax.get_ylim()
        ax.set_ylim(max(lo, float(y.min()) / 10.0), min(hi, float(y.max()) * 10.0))


def plot_sweeps(master, path=None, *, shifted: bool = False):
    """The sweeps of a master curve, coloured by temperature with a colour bar.

    Storage moduli are circles on solid lines, loss moduli squares on dashed lines
    (relaxation moduli: circles); blue is cold, red hot.

    Parameters
    ----------
    master : MasterCurve
        From :func:`vhfit.tts.master_curve`.
    path : path-like, optional
        Save the figure there.
    shifted : bool
        Plot them at their reduced frequency (time): the master curve by temperature.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax, freq = _dma_figure(path, master, (6.4, 4.4))
    sets = list(master.sets)
    colours = _temperature_colours(fig, ax, [s["temperature"] for s in sets])
    for c, s in zip(colours, sets):
        a = 10.0 ** s["log_aT"] if shifted else 1.0
        x = s["x"] * a if freq else s["x"] / a
        ax.plot(x, s["y1"], "o-", ms=3, lw=0.8, color=c)
        if s["y2"] is not None:
            ax.plot(x, s["y2"], "s--", ms=3, lw=0.8, color=c, mfc="none")
    _moduli_axes(ax, freq, shifted)
    kind = ("storage (o, solid) and loss (s, dashed) moduli" if freq
            else "relaxation modulus")
    ax.set_title(f"{'shifted' if shifted else 'measured'} {kind}, {len(sets)} temperatures",
                 fontsize=10)
    return _finish(fig, path)


def _spectrum_moduli(spectrum, x, frequency: bool):
    """E′ and E″ (or E(t) and None) of a Prony spectrum at ``x``."""
    domain = "frequency" if frequency else "time"
    A = design_matrix(domain, np.asarray(x, dtype=np.float64), spectrum.tau)
    m = A @ np.concatenate([[spectrum.E_inf], spectrum.G])
    return (m[: x.size], m[x.size:]) if frequency else (m, None)


def plot_master_curve(master, spectrum=None, path=None):
    """The master curve at T_ref, with a fitted Prony spectrum's moduli as lines.

    Parameters
    ----------
    master : MasterCurve
    spectrum : PronySpectrum, optional
        From :func:`vhfit.spectrum.prony_spectrum`.
    path : path-like, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax, freq = _dma_figure(path, master, (6.0, 4.4))
    if freq:
        ax.plot(master.x, master.storage, "o", ms=3, mfc="none", color="C0", label="E' data")
        ax.plot(master.x, master.loss, "s", ms=3, mfc="none", color="C3", label="E'' data")
    else:
        ax.plot(master.x, master.modulus, "o", ms=3, mfc="none", color="C0", label="E(t) data")
    if spectrum is not None:
        fine = np.logspace(np.log10(master.x.min()), np.log10(master.x.max()), 400)
        m1, m2 = _spectrum_moduli(spectrum, fine, freq)
        ax.plot(fine, m1, "-", color="C0", label=f"Prony, N = {spectrum.n_prony}")
        if m2 is not None:
            ax.plot(fine, m2, "-", color="C3")
    _moduli_axes(ax, freq, True)
    legend_beside(ax, 8)
    ax.set_title(f"master curve at T_ref = {master.T_ref:.4g}", fontsize=10)
    return _finish(fig, path)


def plot_shift_factors(master, path=None, *, law=None, label: str = "from the sweeps"):
    """log10 a_T of each temperature with the fitted (or given) law as a line.

    Parameters
    ----------
    master : MasterCurve
        Or any object with ``temperatures``, ``log_aT`` and ``law`` (e.g. a calibration's
        shift table and law).
    path : path-like or file object, optional
    law : WLF, Arrhenius or PolynomialShift, optional
        Default the master curve's own ``law``.
    label : str
        Legend of the points: where the factors come from.

    Returns
    -------
    matplotlib.figure.Figure
    """
    law = law if law is not None else master.law
    fig, axes = _figure(path, 1, 1, figsize=(5.5, 4.0), layout="constrained")
    ax = axes[0, 0]
    T = np.asarray(master.temperatures)
    ax.plot(T, master.log_aT, "o", color="k", mfc="none", label=label)
    if law is not None:
        fine = np.linspace(T.min(), T.max(), 200)
        consts = ", ".join(f"{k} = {v:.4g}" for k, v in law.constants().items())
        ax.plot(fine, law.log_aT(fine), "-", color="C1", label=f"{law.name}: {consts}")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel(TEMPERATURE_LABEL)
    ax.set_ylabel("log10 a_T")
    ax.grid(True, alpha=0.3)
    legend_beside(ax, 7)
    ax.set_title("shift factors", fontsize=10)
    return _finish(fig, path)


def plot_spectrum_residuals(master, spectrum, path=None):
    """Relative residuals (model − data)/data of a Prony spectrum on the master curve.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax, freq = _dma_figure(path, master, (6.0, 3.6))
    m1, m2 = _spectrum_moduli(spectrum, master.x, freq)
    first = master.storage if freq else master.modulus
    ax.semilogx(master.x, (m1 - first) / first, "o", ms=3, color="C0",
                label="E'" if freq else "E(t)")
    if freq:
        ax.semilogx(master.x, (m2 - master.loss) / master.loss, "s", ms=3, color="C3",
                    label="E''")
    ax.axhline(0.0, color="0.4", lw=0.8)
    ax.set_xlabel("reduced frequency f a_T (Hz)" if freq else "reduced time t / a_T (s)")
    ax.set_ylabel("relative residual")
    ax.grid(True, which="both", alpha=0.3)
    legend_beside(ax, 8)
    ax.set_title(f"residuals: RMS {spectrum.error:.3g}, N = {spectrum.n_prony}", fontsize=10)
    return _finish(fig, path)
