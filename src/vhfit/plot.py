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
one at 2 MPa on a common axis.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
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
    """Whether matplotlib can be imported."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return False
    return True


def _figure(path, nrows: int = 1, ncols: int = 1, **kw) -> tuple[Any, Any]:
    """A figure and its axes: bare Agg figure when saving, pyplot figure otherwise."""
    try:
        if path is not None:
            from matplotlib.figure import Figure

            fig = Figure(**kw)
            axes = fig.subplots(nrows, ncols, squeeze=False)
        else:
            import matplotlib.pyplot as plt

            fig, axes = plt.subplots(nrows, ncols, squeeze=False, **kw)
    except ImportError:
        raise PlotUnavailable(INSTALL_HINT) from None
    return fig, axes


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
    elif path is not None:
        fig.savefig(os.fspath(path), dpi=120, bbox_inches="tight", metadata=meta)
    return fig


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
def _label(curve, i: int) -> str:
    name, rate = curve.name, curve.strain_rate
    text = str(name) if name else f"curve {i + 1}"
    if rate is not None and np.isfinite(rate) and f"{rate:g}" not in text:
        text += f" ({rate:g} 1/s)"
    return text


def _data_points(curve) -> tuple[np.ndarray, np.ndarray]:
    """Strain and stress of a curve's data as given (or its objective points)."""
    eps, sig = curve.strain, curve.stress
    if np.shape(eps) != np.shape(sig):
        eps, sig = curve.history.out_strain, curve.target_stress
    return np.asarray(eps, dtype=np.float64), np.asarray(sig, dtype=np.float64)


def _strain_label(curves) -> str:
    """The x label of stress-strain panels: what the curves' records call their strain."""
    tests = {get_deformation(c.deformation) for c in curves}
    own = sorted(f"{t.name}: {t.strain_label}" for t in tests if t.shear)
    if own and all(t.shear for t in tests):
        return "; ".join(sorted({t.strain_label for t in tests}))
    return "; ".join(["engineering strain (compression < 0)", *own])


def plot_fit(cal, curves: Sequence, path=None, *, ratio: float = 10.0, title: str | None = None):
    """Data against the calibrated model, one colour per curve, panels by magnitude.

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

    Returns
    -------
    matplotlib.figure.Figure
    """
    curves = [c for c in curves if not is_moduli(c)]
    if not curves:
        raise ValueError("no stress-strain curves to plot: draw frequency sweeps and "
                         "relaxation tests with plot_moduli_fit")
    fits = cal.fitted_curves(curves)
    peaks = [
        max(np.max(np.abs(_data_points(c)[1])), np.max(np.abs(f["fine_model"])))
        for c, f in zip(curves, fits)
    ]
    groups = group_by_magnitude(peaks, ratio)
    fig, axes = _figure(path, 1, len(groups), figsize=(5.2 * len(groups), 4.2),
                        layout="constrained")
    errs = list(cal.per_curve_rmsape)
    measures = {c.measure for c in curves}
    ylabel = (f"{measures.pop()} stress (MPa)" if len(measures) == 1
              else "stress (MPa, each curve's measure)")
    from matplotlib import colormaps

    cmap = colormaps["viridis"]
    colours = [cmap(0.9 * i / max(len(curves) - 1, 1)) for i in range(len(curves))]
    for ax, group in zip(axes[0], groups):
        for i in group:
            eps, sig = _data_points(curves[i])
            f = fits[i]
            lab = _label(curves[i], i)
            if i < len(errs):
                lab += f", RMSAPE {errs[i]:.3g} %"
            ax.plot(eps, sig, "o", ms=4, mfc="none", color=colours[i], label=lab)
            ax.plot(f["fine_strain"], f["fine_model"], "-", lw=1.5, color=colours[i])
        ax.plot([], [], "o", ms=4, mfc="none", color="0.4", label="markers: data")
        ax.plot([], [], "-", color="0.4", label="lines: model")
        ax.set_xlabel(_strain_label([curves[i] for i in group]))
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.axhline(0, color="0.6", lw=0.6)
        ax.legend(fontsize=7, loc="best")
    if title is None:
        hm = cal.model.hyperelastic.name
        title = f"{hm} + {cal.model.n_prony} Prony term(s)"
        if cal.rmsape is not None:
            title += f": RMSAPE {cal.rmsape:.3g} %"
    fig.suptitle(title, fontsize=10)
    return _finish(fig, path)


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
    fits = cal.fitted_curves(items)
    sweeps = [i for i, f in enumerate(fits) if "storage" in f]
    relax = [i for i, f in enumerate(fits) if "storage" not in f]
    panels = [p for p in (sweeps, relax) if p]
    fig, axes = _figure(path, 1, len(panels), figsize=(5.4 * len(panels), 4.2),
                        layout="constrained")
    colours = _colours(len(items))
    for ax, panel in zip(axes[0], panels):
        for i in panel:
            f, c, lab = fits[i], colours[i], _label(items[i], i)
            if "storage" in f:
                ax.plot(f["frequency"], f["storage"], "o", ms=3, mfc="none", color=c,
                        label=f"{lab}: E'")
                ax.plot(f["frequency"], f["loss"], "s", ms=3, mfc="none", color=c,
                        label=f"{lab}: E''")
                ax.plot(f["fine_frequency"], f["fine_storage"], "-", lw=1.2, color=c)
                ax.plot(f["fine_frequency"], f["fine_loss"], "--", lw=1.2, color=c)
            else:
                ax.plot(f["time"], f["modulus"], "o", ms=3, mfc="none", color=c, label=lab)
                ax.plot(f["fine_time"], f["fine_model"], "-", lw=1.2, color=c)
        # items shifted to T_ref by the calibration sit at reduced frequency (time)
        _moduli_axes(ax, "storage" in fits[panel[0]], bool(cal.shift_table))
        ax.legend(fontsize=7, loc="best")
    fig.suptitle("markers: data, lines: model", fontsize=10)
    return _finish(fig, path)


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
        ax.legend(fontsize=8)
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
        ax.legend(fontsize=8)
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


def plot_sweeps(master, path=None, *, shifted: bool = False):
    """The sweeps of a master curve, one colour per temperature (blue cold, red hot).

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
    fig, ax, freq = _dma_figure(path, master, (6.0, 4.4))
    sets = list(master.sets)
    for c, s in zip(_colours(len(sets)), sets):
        a = 10.0 ** s["log_aT"] if shifted else 1.0
        x = s["x"] * a if freq else s["x"] / a
        lab = f"{s['temperature']:.4g}"
        ax.plot(x, s["y1"], "o-", ms=3, lw=0.8, color=c, label=lab)
        if s["y2"] is not None:
            ax.plot(x, s["y2"], "s--", ms=3, lw=0.8, color=c, mfc="none")
    _moduli_axes(ax, freq, shifted)
    ax.legend(fontsize=6, ncol=2, title="T", title_fontsize=7, loc="best")
    kind = "storage (o) and loss (s) moduli" if freq else "relaxation modulus"
    ax.set_title(f"{'shifted' if shifted else 'measured'} {kind}", fontsize=10)
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
    ax.legend(fontsize=8)
    ax.set_title(f"master curve at T_ref = {master.T_ref:g}", fontsize=10)
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
    ax.set_xlabel("temperature")
    ax.set_ylabel("log10 a_T")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
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
    ax.legend(fontsize=8)
    ax.set_title(f"residuals: RMS {spectrum.error:.3g}, N = {spectrum.n_prony}", fontsize=10)
    return _finish(fig, path)
