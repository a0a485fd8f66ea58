"""The HTML report of a calibration: one self-contained file that opens in any browser.

``vhfit fit`` writes it as ``report.html``; in Python :meth:`Calibration.report` (or
:func:`write_report`) does. It reads from the top: the verdict (error, worst curve,
the warnings that change how the result may be used, each solver card's check), then
the fit per test mode, stress against time for histories with holds or unloading, the
residuals, the constants with intervals and units, the error per curve, the order
scan, stability, the frequency sweeps and shift factors, the card check, the cards
themselves, every warning, and the command and versions that produced it.

Figures are PNGs inlined as ``data:`` URIs; there is no script and no reference to
anything outside the file. Without matplotlib the report is still written, with a
one-line note in place of the figures. In Jupyter a :class:`Calibration` shows the
verdict and its main plot (``_repr_html_``).
"""

from __future__ import annotations

import platform
import shlex
import time
import warnings
from collections.abc import Sequence
from pathlib import Path

from vhfit import plot
from vhfit._io import atomic_write
from vhfit.calibration import interrupted_in, set_html_report
from vhfit.data import is_moduli
from vhfit.report import _figures, _html
from vhfit.report._figures import residual_figure  # noqa: F401 - the drawer's copy draws it

__all__ = ["build_report", "write_report", "draw_figures", "verdict", "repr_html", "versions"]

#: the solvers whose cards a report made in Python carries


def versions() -> dict[str, str]:
    """Versions of vhfit and the libraries that produced a result.

    Returns
    -------
    dict
        Package -> version (vhfit, numpy, scipy, numba, matplotlib when installed,
        python, platform).

    Examples
    --------
    >>> {"vhfit", "numpy", "scipy", "numba", "python"} <= set(versions())
    True
    """
    import numpy

    from vhfit._version import __version__, package_version

    # numba and matplotlib are not imported for their version: a fit may need neither
    out = {"vhfit": __version__, "numpy": numpy.__version__,
           "scipy": package_version("scipy"), "numba": package_version("numba")}
    if plot.have_matplotlib():
        out["matplotlib"] = package_version("matplotlib")
    out.update(python=platform.python_version(), platform=platform.platform())
    return out


def verdict(cal, *, interrupted: bool = False) -> str:
    """The report's first line: the error, a plain verdict and the worst curve.

    Parameters
    ----------
    cal : Calibration
    interrupted : bool
        The search was interrupted: the line says so first.

    Returns
    -------
    str

    Examples
    --------
    >>> verdict(cal)  # doctest: +SKIP
    'RMSAPE 1.2 %: good fit; worst curve fast (2.1 %)'
    """
    return _html.headline(cal, interrupted)


def _checks(card_check) -> dict:
    """solver -> the check as a dict (``CardCheck.to_dict()`` or ``{"error": ...}``)."""
    return {s: c if isinstance(c, dict) else c.to_dict() for s, c in (card_check or {}).items()}


def _python_cards(cal, curves) -> tuple[dict, dict, dict]:
    """Cards and their check for a report made in Python (not by ``vhfit fit``)."""
    from vhfit.export import export, solvers, supported_laws
    from vhfit.export.check import check_cards

    cards, notes = {}, {}
    for s in solvers():  # every registered solver's card
        if cal.model.hyperelastic.name not in supported_laws(s):
            cards[s], notes[s] = None, [f"no {s} card: the solver has no card for this law"]
            continue
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                cards[s] = export(cal, to=s, notes=list(cal.headlines))
        except Exception as exc:  # a solver that cannot take the model is noted
            cards[s], notes[s] = None, [f"no {s} card: {' '.join(str(exc).split())}"]
    check = {}
    if curves:
        texts = {s: t for s, t in cards.items() if t is not None}
        try:
            check = check_cards(texts, curves, fits=cal)
        except Exception as exc:  # the check reports, it never stops the report
            check = {s: {"error": " ".join(str(exc).split())} for s in texts}
    return cards, notes, check


def draw_figures(cal, curves: Sequence, images: dict | None = None, *,
                 fits: list | None = None, given: dict | None = None) -> tuple[list, dict]:
    """The report's figures of a calibration, drawn (:func:`build_report` takes them as
    ``drawn=``, e.g. from another process: they are plain data).

    Parameters
    ----------
    cal : Calibration
    curves : sequence of Curve
        The data it was fitted to (at its reference temperature).
    images : dict, optional
        The PNG files of :mod:`vhfit.plot`'s figures already drawn (``fit``, ``moduli``,
        ``order_scan``, ``history``), inlined instead of drawn again.
    fits : list, optional
        ``cal.fitted_curves(curves)``, computed already (e.g. where the model's kernels
        are loaded); default: computed here.
    given : dict, optional
        Figures drawn already (e.g. by another process), by key: ``residuals``
        (:func:`vhfit.report._figures.residual_figure` of the same calibration, curves
        and fits), used instead of drawing it here.

    Returns
    -------
    tuple
        (the fit figures, the other figures by key).

    Examples
    --------
    >>> main, other = draw_figures(cal, curves)  # doctest: +SKIP
    """
    curves, images = list(curves), dict(images or {})
    if fits is None:
        fits = cal.fitted_curves(curves) if curves else []
    # plot_fit's labels are right only without sweeps among the curves: else redraw
    drawn = None if any(is_moduli(c) for c in curves) else images.get("fit")
    main = _figures.fit_figures(cal, curves, fits, drawn) if curves else []
    other = {}
    if any(not is_moduli(c) for c in curves or []):
        other["residuals"] = ((given or {}).get("residuals")
                              or _figures.residual_figure(cal, curves, fits))
    if any(is_moduli(c) for c in curves or []):
        other["moduli"] = (_figures.from_file("moduli", "frequency sweeps and relaxation "
                                              "tests", "", images["moduli"])
                           if "moduli" in images else _figures.moduli_figure(cal, curves))
    if len(cal.shift_table or {}) >= 2:
        other["shift"] = _figures.shift_figure(cal)
    if cal.order_scan:
        other["scan"] = (_figures.from_file("order-scan", "error against the number of Prony "
                                            "terms", "", images["order_scan"])
                         if "order_scan" in images else _figures.scan_figure(cal))
    if (cal.history or {}).get("nit"):
        other["history"] = (_figures.from_file("history", "error against generation", "",
                                               images["history"])
                            if "history" in images else _figures.history_figure(cal))
    return main, other


def build_report(cal, curves: Sequence | None = None, *, cards: dict | None = None,
                 card_check: dict | None = None, card_notes: dict | None = None,
                 card_warnings: Sequence[str] = (), fit_warnings: Sequence[str] | None = None,
                 command: str | None = None,
                 interrupted: bool | None = None, title: str | None = None, inputs=None,
                 figures: bool = True, images: dict | None = None,
                 comparison=None, drawn: tuple[list, dict] | None = None) -> str:
    """The report as one HTML document (see the module's description).

    Parameters
    ----------
    cal : Calibration
    curves : sequence of Curve, optional
        The data it was fitted to (at its reference temperature); default
        ``cal.curves``. Without data there are no fit figures.
    cards : dict, optional
        Solver -> card text (None: no card). Default: every registered solver's card
        written from ``cal`` (:func:`vhfit.export.solvers`), checked against the data.
    card_check : dict, optional
        Solver -> :class:`vhfit.export.check.CardCheck` or its ``to_dict()``.
    card_notes : dict, optional
        Solver -> notes on its card (why there is none, writer warnings).
    card_warnings : sequence of str
        Headline warnings of the card check (shown in the verdict).
    fit_warnings : sequence of str, optional
        The warnings of the cards' own fits (the fits after the first,
        :func:`vhfit.export.check.own_fit_warnings`), shown in the verdict; default: those
        a results file read back recorded (``card_fit_warnings``).
    command : str, optional
        The command that produced the result.
    interrupted : bool, optional
        The search was interrupted (the report says so first); default what a results
        file read back recorded, else False.
    title : str, optional
        The data's label.
    inputs : list of dict, optional
        Input files (``path``, ``sha256``).

        A result read back from a results file (``Calibration.load``) brings its own
        ``context``: the command, interruption, label, inputs, versions and card check that
        ``vhfit fit`` recorded stand in for the arguments not given.
    figures : bool
        Draw the figures (needs matplotlib; without it a note stands in their place).
    images : dict, optional
        Kind -> PNG file of a :mod:`vhfit.plot` figure already drawn (``fit`` of all
        the curves, ``moduli``, ``order_scan``, ``history``): inlined, not drawn again.
    comparison : vhfit.Comparison, optional
        The laws compared when this fit was chosen among several: its ranked table
        follows the verdict.
    drawn : tuple, optional
        The figures already drawn by :func:`draw_figures` (of the same calibration,
        curves and ``images``): used instead of drawing them here.

    Returns
    -------
    str

    Examples
    --------
    >>> text = build_report(cal)  # doctest: +SKIP
    """
    curves = list(curves if curves is not None else cal.curves)
    ctx = cal.context  # a results file read back: what fit recorded
    if command is None and ctx.get("command"):
        command = shlex.join(str(a) for a in ctx["command"])
    if interrupted is None:
        interrupted = interrupted_in(ctx)
    title = title if title is not None else ctx.get("data_label")
    inputs = inputs if inputs is not None else ctx.get("inputs")
    if card_check is None and not curves and ctx.get("card_check"):
        card_check = ctx["card_check"]
        card_warnings = card_warnings or ctx.get("card_check_warnings") or ()
    if cards is None:
        cards, py_notes, py_check = _python_cards(cal, curves)
        card_notes = {**py_notes, **(card_notes or {})}
        card_check = card_check if card_check is not None else py_check
    check = _checks(card_check)
    card_warnings = list(card_warnings) or [
        _exceeds_text(s, c, (card_check or {})[s]) for s, c in check.items() if c.get("exceeds")]
    note = None
    if not figures:
        note = "figures not drawn (asked for none)"
    elif not plot.have_matplotlib():
        note = f"figures not drawn: {plot.INSTALL_HINT}"
    main, other = ([], {}) if note is not None else (
        drawn if drawn is not None else draw_figures(cal, curves, images))
    if note is None and not curves:
        note = "no fit figures: the data are not at hand (give curves= to Calibration.report)"
    name = cal.model.spec().describe()
    body = [f"<h1>vhfit report: {_html.esc(name)}</h1>"]
    if title:
        body.append(f"<p>data: {_html.esc(title)}</p>")
    if interrupted:
        body.append('<p class="interrupted">INTERRUPTED: the best parameters found so far, '
                    "not converged; resume the fit to finish it</p>")
    if fit_warnings is None:
        fit_warnings = ctx.get("card_fit_warnings") or ()
    no_cards = {s: "; ".join((card_notes or {}).get(s, [])) or "no card"
                for s, text in cards.items() if text is None}
    body.append(_html.verdict_html(cal, interrupted, check, [*card_warnings, *fit_warnings],
                                   no_cards))
    if comparison is not None:
        body.append(_html.section("laws", "laws compared", [_html.comparison_html(comparison)]))
    body.append(_nav(cal, check, cards))
    body += _sections(cal, curves, main, other, note, check, cards, card_notes or {},
                      command, inputs, ctx.get("versions"))
    return _html.page(f"vhfit report: {name}", body)


def _exceeds_text(solver: str, c: dict, given) -> str:
    """The headline of a card that fails its check: its own (with the remedy) if it has
    one, else the numbers."""
    if hasattr(given, "warning"):
        return given.warning()
    return (f"{solver} card: RMSAPE {_html.num(c['rmsape'])} % on the data, allowed "
            f"{_html.num(c.get('allowed'))} %")


def _nav(cal, check, cards) -> str:
    items = [("figures", "fit"), ("constants", "constants"), ("curves", "per curve")]
    items += [("order-scan", "order scan")] if cal.order_scan else []
    items += [("stability", "stability")]
    items += [("card-check", "card check")] if check else []
    items += [("cards", "cards")] if cards else []
    items += [("warnings", "warnings"), ("provenance", "command and versions")]
    return "<nav>" + "".join(f'<a href="#{k}">{_html.esc(t)}</a>' for k, t in items) + "</nav>"


def _sections(cal, curves, main, other, note, check, cards, card_notes, command, inputs,
              made_with) -> list[str]:
    H = _html
    figs = [H.figure_html(f) for f in main]
    figs += [H.figure_html(other[k]) for k in ("residuals", "moduli", "shift") if k in other]
    if note:
        figs.insert(0, f'<p class="note">{H.esc(note)}</p>')
    out = [H.section("figures", "fit", figs or ['<p class="note">no figures</p>'])]
    out.append(H.section("constants", "constants", [H.params_html(cal)]
                         + ([H.shift_html(cal)] if cal.shift_source is not None else [])))
    out.append(H.section("curves", "error per curve", [H.curves_html(cal, curves)]))
    if cal.order_scan:
        out.append(H.section("order-scan", "number of Prony terms", [H.scan_html(cal)]
                             + ([H.figure_html(other["scan"])] if "scan" in other else [])))
    stab = cal.stability.describe() if cal.stability is not None else "not checked"
    out.append(H.section("stability", "stability", [f"<p>{H.esc(stab)}</p>"]))
    if check:
        out.append(H.section("card-check", "card check",
                             [H.check_html(check, list(cal.curve_names or []))]))
    if cards:
        out.append(H.section("cards", "solver cards", [H.cards_html(cards, card_notes)]))
    warns = list(cal.warnings or [])
    out.append(H.section("warnings", "warnings", [
        "<ul>" + "".join(f"<li>{H.esc(w)}</li>" for w in warns) + "</ul>" if warns
        else "<p>none</p>"]))
    if "history" in other:
        out.append(H.section("search", "the search", [H.figure_html(other["history"])]))
    cmd = command if command is not None else (
        "Python: vhfit.calibrate(...) with the calibration options below")
    out.append(H.section("provenance", "command and versions", [
        H.provenance_html(cmd, made_with or versions(), dict(cal.options or {}), inputs),
        f'<p class="note">written {H.esc(time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()))}'
        "</p>"]))
    return out


def write_report(cal, path, curves: Sequence | None = None, **kw) -> None:
    """Write :func:`build_report` to ``path`` atomically (UTF-8).

    Parameters
    ----------
    cal : Calibration
    path : path-like
    curves : sequence of Curve, optional
    **kw
        Passed to :func:`build_report`.

    Returns
    -------
    None

    Examples
    --------
    >>> write_report(cal, "report.html")  # doctest: +SKIP
    """
    atomic_write(Path(path), build_report(cal, curves, **kw))


def repr_html(cal) -> str:
    """The verdict and the main plot as an HTML fragment (``Calibration._repr_html_``).

    Parameters
    ----------
    cal : Calibration

    Returns
    -------
    str

    Examples
    --------
    >>> html = repr_html(cal)  # doctest: +SKIP
    """
    parts = [_html.verdict_html(cal, False, {}, [])]
    curves = list(cal.curves)
    if curves and plot.have_matplotlib() and any(not is_moduli(c) for c in curves):
        fits = cal.fitted_curves(curves)
        main = _figures.fit_figures(cal, curves, fits)
        if main:
            parts.append(_html.figure_html(main[0]))
    elif curves and plot.have_matplotlib():
        parts.append(_html.figure_html(_figures.moduli_figure(cal, curves)))
    return "<div>" + "\n".join(p for p in parts if p) + "</div>"


set_html_report(write_report, repr_html)
