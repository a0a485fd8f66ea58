"""The report's HTML: the page, the verdict and each section, every text escaped.

Everything here is plain HTML with an inline style sheet: no script, no font, no link
to anything outside the file (figures are ``data:`` URIs). Every text that comes from
the data, a file name, the command line or a warning goes through :func:`esc`.
"""

from __future__ import annotations

import html
import json
import math

from vhfit.calibration import grade as calibration_grade
from vhfit.calibration import worst_grade
from vhfit.export.check import check_words

STYLE = """
body{font-family:system-ui,-apple-system,"Segoe UI",Helvetica,Arial,sans-serif;margin:0 auto;
max-width:1100px;padding:1em 1.5em;color:#1d1d1f;line-height:1.4}
h1{font-size:1.45em;margin:.2em 0}h2{font-size:1.15em;border-bottom:1px solid #ccc;
padding-bottom:.2em;margin-top:1.6em}h3{font-size:1em;margin:1em 0 .3em}
.verdict{border-left:6px solid #888;background:#f5f5f7;padding:.6em 1em;margin:.8em 0}
.verdict.good{border-color:#2e7d32}.verdict.fair{border-color:#f9a825}
.verdict.poor{border-color:#c62828}.headline{font-size:1.2em;font-weight:600;margin:.2em 0}
.warn{color:#8a1c1c}.ok{color:#2e7d32}li.warn{color:#9a6700}.bad{color:#c62828;font-weight:600}
.interrupted{background:#fff3cd;border:1px solid #e0b000;padding:.4em .8em}
table{border-collapse:collapse;margin:.4em 0;font-size:.92em}
th,td{border:1px solid #ddd;padding:.2em .6em;text-align:left}td.n{text-align:right;
font-variant-numeric:tabular-nums}th{background:#f0f0f2}
figure{margin:1em 0}figure img{max-width:100%;height:auto;border:1px solid #eee}
figcaption{font-size:.85em;color:#555}
pre{background:#f6f8fa;border:1px solid #ddd;padding:.6em;overflow-x:auto;font-size:.82em;
user-select:all}nav{font-size:.85em;color:#555}nav a{margin-right:.7em}
.note{color:#555;font-style:italic}
"""


def esc(text) -> str:
    """``text`` as HTML text (quotes too: safe inside attributes)."""
    return html.escape(str(text), quote=True)


def num(v, digits: int = 4) -> str:
    """A number rounded for reading (plain text: escaped where it is put)."""
    try:
        x = float(v)
    except (TypeError, ValueError):
        return str(v)
    return f"{x:.{digits}g}" if math.isfinite(x) else str(x)


def table(head: list[str], rows: list[list], numeric: set[int] = frozenset()) -> str:
    """An HTML table; cells are escaped unless given as ``(html,)`` one-tuples."""
    def cell(k, v):
        body = v[0] if isinstance(v, tuple) else esc(v)
        return f'<td class="n">{body}</td>' if k in numeric else f"<td>{body}</td>"

    out = ["<table><tr>" + "".join(f"<th>{esc(h)}</th>" for h in head) + "</tr>"]
    out += ["<tr>" + "".join(cell(k, v) for k, v in enumerate(r)) + "</tr>" for r in rows]
    return "\n".join(out) + "</table>"


def page(title: str, body: list[str]) -> str:
    """The whole document around the sections."""
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<title>{esc(title)}</title><style>{STYLE}</style></head><body>\n"
            + "\n".join(body) + "\n</body></html>\n")


def section(key: str, title: str, parts: list[str]) -> str:
    return f'<section id="{esc(key)}"><h2>{esc(title)}</h2>\n' + "\n".join(parts) + "</section>"


def figure_html(fig) -> str:
    """A report figure as ``<figure>``, or its note when it was not drawn."""
    cap = esc(fig.title) + (f" — {esc(fig.caption)}" if fig.caption else "")
    if fig.uri is None:
        return f'<p class="note">{esc(fig.title)}: {esc(fig.note)}</p>'
    return (f'<figure id="fig-{esc(fig.key)}"><img alt="{esc(fig.title)}" src="{fig.uri}">'
            f"<figcaption>{cap}</figcaption></figure>")


# ----------------------------------------------------------------------- verdict
def grade(rmsape: float) -> tuple[str, str]:
    """(css class, plain words) of an overall RMSAPE in percent: the calibration's own
    verdict (:func:`vhfit.calibration.grade`), so the report and the summary agree."""
    return calibration_grade(rmsape)


def worst_curve(cal) -> tuple[str, float] | None:
    """Name and RMSAPE of the curve with the largest error (None with one curve)."""
    return cal.worst_curve()


def headline(cal, interrupted: bool = False) -> str:
    """The report's first line: error, plain words, worst curve (plain text)."""
    return cal.verdict(interrupted=interrupted)


def card_rows(check: dict) -> list[tuple[str, str, str]]:
    """(solver, css class, plain text) of each card's check: whether the card reproduces
    its fit, then the card's own grade (:func:`vhfit.export.check.check_words`); the
    class is ``ok`` for a card that passes with a good grade, ``bad`` for one that
    exceeds its fit or grades poor, ``warn`` between, ``note`` when not checked."""
    out = []
    for solver, c in check.items():
        if "error" in c:
            out.append((solver, "note", f"{solver}: not checked ({c['error']})"))
            continue
        allowed = c.get("allowed")
        bound = f" (allowed {num(allowed)} %)" if allowed is not None else ""
        level = grade(c["rmsape"])[0]
        cls = ("bad" if c.get("exceeds") or level == "poor" else
               "ok" if level == "good" else "warn")
        out.append((solver, cls,
                     f"{solver}: {check_words(c['rmsape'], bool(c.get('exceeds')))}, card "
                     f"RMSAPE {num(c['rmsape'])} %{bound} in the '{c.get('formulation')}' "
                     "formulation"))
    return out


def card_levels(check: dict) -> list[str]:
    """The grade level of every checked card (its own RMSAPE, as the fit's verdict)."""
    return [grade(c["rmsape"])[0] for c in check.values() if "error" not in c]


def important_warnings(cal, card_warnings: list[str]) -> list[str]:
    """The warnings that change how the result may be used, each once."""
    out = list(cal.headlines or []) + list(card_warnings)
    stab = cal.stability
    if stab is not None and not stab.stable:
        out.append(stab.describe())
    return list(dict.fromkeys(out))


def verdict_html(cal, interrupted: bool, check: dict, card_warnings: list[str],
                 no_cards: dict | None = None) -> str:
    """The verdict box: its colour is the worst grade of the fit and of its cards (a
    warning that matters makes a good one fair); the cards' rows, then the solvers
    without a card (``no_cards``: solver -> why, "no card: ...")."""
    cls = worst_grade([grade(float(cal.rmsape))[0], *card_levels(check)])
    warns = important_warnings(cal, card_warnings)
    if warns and cls == "good":  # a good error with a warning that matters is not green
        cls = "fair"
    if cal.stability is not None and not cal.stability.stable:
        cls = "bad"  # an unstable law is no result to use, whatever its error
    parts = [f'<div class="verdict {cls}" id="verdict">',
             f'<p class="headline">{esc(headline(cal, interrupted))}</p>',
             f"<p>{esc(cal.model.spec().describe())}, "
             f"'{esc(cal.model.formulation)}' formulation; stop: {esc(cal.stop_reason)}; "
             f"{int(cal.nit)} generations, {esc(num(cal.wall_time, 3))} s</p>"]
    if warns:
        parts.append('<ul class="warn">' + "".join(f"<li>WARNING: {esc(w)}</li>" for w in warns)
                     + "</ul>")
    others = [w for w in (cal.warnings or []) if w not in warns]
    if others:
        parts.append(f'<p>{len(others)} further warning(s): <a href="#warnings">below</a></p>')
    items = [f'<li class="{c}">{esc(text)}</li>' for _, c, text in card_rows(check)]
    items += [f'<li class="bad">{esc(s)}: {esc(why)}</li>' for s, why in (no_cards or {}).items()]
    if items:
        parts.append("<p>solver cards (each parsed back and re-simulated; ok: the card "
                     "reproduces its fit, then the card's own grade):</p><ul>"
                     + "".join(items) + "</ul>")
    parts.append("</div>")
    return "\n".join(parts)


# ---------------------------------------------------------------------- sections
def params_html(cal) -> str:
    units = dict(zip(cal.model.param_names, cal.model.units))
    rows = []
    for name, v in cal.params.items():
        ci, b = cal.confidence.get(name), cal.bounds.get(name)
        rows.append([name, f"{float(v):.6g}", units.get(name, ""),
                     f"[{num(ci[0])}, {num(ci[1])}]" if ci else "-",
                     f"[{num(b[0])}, {num(b[1])}]" if b else "-"])
    out = [table(["parameter", "value", "unit", "95 % interval", "search bounds"], rows, {1})]
    if cal.n_prony:
        out.append("<p>g<sub>i</sub> = " + esc(", ".join(f"{float(g):.6g}" for g in cal.g))
                   + f", g<sub>∞</sub> = {float(cal.g_inf):.6g}</p>")
    if cal.options.get("n_prony_reason"):
        out.append(f'<p class="note">{esc(cal.options["n_prony_reason"])}</p>')
    return "\n".join(out)


def curves_html(cal, curves) -> str:
    errs = list(cal.per_curve_rmsape or [])
    rows = []
    names = list(cal.curve_names or [])
    for i in range(max(len(errs), len(curves))):
        c = curves[i] if i < len(curves) else None
        rate = None if c is None else c.strain_rate
        temperature = None if c is None else c.temperature
        rows.append([names[i] if i < len(names) else f"curve {i + 1}" if c is None else c.name,
                     "-" if c is None else c.deformation,
                     "-" if rate is None else f"{float(rate):.4g}",
                     "-" if c is None else c.measure,
                     "-" if temperature is None else num(temperature),
                     num(errs[i]) if i < len(errs) else "-"])
    return table(["curve", "test", "rate (1/s)", "measure", "temperature", "RMSAPE (%)"],
                 rows, {2, 5})


def scan_html(cal) -> str:
    chosen = cal.options.get("n_prony_chosen")
    rows = [[r["n_prony"], num(r["rmsape"]), r.get("effective_n", "-"),
             "chosen" if r["n_prony"] == chosen else ""] for r in cal.order_scan]
    return table(["N", "RMSAPE (%)", "effective N", ""], rows, {0, 1})


def shift_html(cal) -> str:
    law = cal.shift
    head = ("no law fitted (a given table)" if law is None else
            f"{law.name}: " + ", ".join(f"{k} = {v:.6g}" for k, v in law.constants().items()))
    rows = [[f"{T:g}", f"{L + 0.0:.4g}"] for T, L in sorted(cal.shift_table.items())]
    return (f"<p>{esc(head)} (source: {esc(cal.shift_source)}); the constants are at "
            f"T_ref = {esc(num(cal.T_ref, 6))}</p>"
            + table(["temperature", "log10 a_T"], rows, {0, 1}))


def check_html(check: dict, names: list[str]) -> str:
    rows, per = [], []
    for solver, c in check.items():
        if "error" in c:
            rows.append([solver, "-", "-", "-", "-", f"not checked: {c['error']}"])
            continue
        fit = c.get("fit_rmsape")
        rows.append([solver, c.get("formulation", "-"),
                     "-" if fit is None else f"{num(fit)} ({c.get('fit_formulation')})",
                     num(c["rmsape"]), "-" if c.get("allowed") is None else num(c["allowed"]),
                     check_words(c["rmsape"], bool(c.get("exceeds")))])
        per.append(solver)
    out = ["<p>Each card parsed back and re-simulated in its solver's formulation on every "
           "test history; RMSAPE (%) on the data.</p>",
           table(["card", "solver's formulation", "fit (its formulation)", "card", "allowed",
                  "check"], rows, {3, 4})]
    if per and names:
        prow = [[n] + [num(check[s]["per_curve"][i]) if i < len(check[s].get("per_curve", []))
                       else "-" for s in per] for i, n in enumerate(names)]
        out.append(table(["curve (RMSAPE %)"] + per, prow, set(range(1, len(per) + 1))))
    return "\n".join(out)


def cards_html(cards: dict, notes: dict) -> str:
    out = []
    for solver, text in cards.items():
        out.append(f"<h3>{esc(solver)}</h3>")
        out += [f'<p class="note">{esc(n)}</p>' for n in notes.get(solver, [])]
        if text is None:
            continue
        out.append(f'<pre id="card-{esc(solver)}">{esc(text)}</pre>')
    return "\n".join(out)


def provenance_html(command, versions: dict, options: dict, inputs) -> str:
    out = []
    if command:
        out.append("<h3>command</h3><pre>" + esc(command) + "</pre>")
    out.append("<h3>versions</h3>" + table(["package", "version"],
                                          [[k, v] for k, v in versions.items()]))
    if inputs:
        out.append("<h3>inputs</h3>" + table(
            ["file", "sha256"], [[d.get("path", ""), d.get("sha256", "")] for d in inputs]))
    if options:
        out.append("<h3>calibration options</h3><pre>"
                   + esc(json.dumps(options, indent=1, default=str, sort_keys=True)) + "</pre>")
    return "\n".join(out)


def comparison_html(comp) -> str:
    """The laws compared (``vhfit fit --model a,b``): the ranked table and the rule."""
    rows = comp.rows
    modes = list(dict.fromkeys(m for r in rows for m in r["per_mode"]))
    solvers = list(dict.fromkeys(s for r in rows for s in r["cards"]))
    head = ["rank", "law", "RMSAPE %", *modes, "constants", "BIC", "stable", *solvers,
            "time s"]
    body = []
    for r in rows:
        if r["error"] is not None:
            body.append(["-", r["law"], f"failed: {r['error']}"] + [""] * (len(head) - 3))
            continue
        cards = []
        for s in solvers:
            c = r["cards"].get(s)
            cards.append("-" if c is None or "error" in c else "n/a" if not c["own"]
                         else "EXCEEDS" if c["exceeds"] else "ok")
        body.append([r["rank"], r["law"], num(r["rmsape"]),
                     *(num(r["per_mode"].get(m, math.nan)) for m in modes),
                     r["n_constants"], num(r["bic"], 6),
                     {True: "yes", False: "NO", None: "-"}[r["stable"]], *cards,
                     num(r["wall_time"], 3)])
    n = len(modes)
    return (f"<p>best: <b>{esc(comp.best or 'none')}</b>, ranked by {esc(comp.rule)}; BIC = "
            "n ln((RMSAPE/100)²) + k ln(n), n objective points, k constants; the other "
            "laws' results are in laws/LAW/</p>"
            + table(head, body, {0, 2, *range(3, 3 + n), 3 + n, 4 + n}))
