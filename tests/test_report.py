"""The HTML report (vhfit.report): verdict first, the constants and cards as fitted,
every text from the data escaped, nothing outside the file, written by ``vhfit fit``.

The data are generated here from a known Mooney–Rivlin + Prony material; one curve is
named ``<script>...`` as a hostile data set would be. The checks read the report as
HTML (the standard library's parser), never trusting the report's own helpers for
what they test.
"""

from __future__ import annotations

import dataclasses
import html
import json
import re
import shlex
import warnings
from html.parser import HTMLParser

import numpy as np
import pytest

import vhfit
from vhfit import cli, plot, report
from vhfit.calibration import set_html_report
from vhfit.export import export

P = dict(C10=0.2, C01=0.05, G1=1.5, tau1=0.05)
HOSTILE = '<script>alert("x")</script>'


def curves():
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    eps = np.linspace(0.0, -0.4, 21)
    out = []
    for r, name, noise in ((-0.1, "slow", 0.01), (-10.0, HOSTILE, 0.06)):
        s = m.stress(P, strain=eps, strain_rate=r, measure="engineering")
        s[1:] *= 1 + noise * np.sin(np.arange(20))  # the hostile curve: the worst fitted
        out.append(vhfit.Curve(strain=eps, stress=s, strain_rate=r, name=name))
    return out


@pytest.fixture(scope="module")
def cal():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return vhfit.calibrate(curves(), hyperelastic="mooney_rivlin", n_prony=1, seed=0,
                               maxiter=25)


@pytest.fixture(scope="module")
def page(cal, tmp_path_factory):
    path = tmp_path_factory.mktemp("report") / "report.html"
    cal.report(path)
    return path.read_text(encoding="utf-8")


class Doc(HTMLParser):
    """Tags, URL attributes and table rows of a document."""

    def __init__(self, text: str):
        super().__init__()
        self.tags: list[str] = []
        self.urls: list[str] = []
        self.rows: list[list[str]] = []
        self._cell: list[str] | None = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        self.urls += [v for k, v in attrs if k in ("src", "href", "srcset", "action") and v]
        if tag == "tr":
            self.rows.append([])
        elif tag in ("td", "th"):
            self._cell = []

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self.rows[-1].append("".join(self._cell).strip())
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def external(text: str) -> list[str]:
    urls = Doc(text).urls + re.findall(r"url\(([^)]*)\)", text)
    return [u for u in urls if not (u.startswith("data:") or u.startswith("#"))]


# ---------------------------------------------------------------- the report's content
def test_the_verdict_comes_first_with_the_error_and_the_worst_curve(cal, page):
    errs = cal.per_curve_rmsape
    assert errs[1] > errs[0]  # the hostile curve is the worst: its name is in the verdict
    line = report.verdict(cal)
    assert line.startswith(f"RMSAPE {cal.rmsape:.4g} %: ")
    assert f"worst curve {HOSTILE} ({errs[1]:.4g} %)" in line
    body = page.split("<body>", 1)[1]
    first = re.search(r'<p class="headline">(.*?)</p>', body)
    assert first is not None and html.unescape(first.group(1)) == line
    assert body.index('id="verdict"') < body.index("<figure")  # verdict before the plots


def test_the_grade_words_follow_the_error():
    import vhfit

    def Fake(e):  # noqa: N802 - a result with only an error
        return vhfit.Calibration(model=vhfit.ViscoHyperelastic("neo_hooke", 0),
                                 params=dict(C10=0.5), rmsape=e, per_curve_rmsape=[],
                                 nit=0, nfev=0, wall_time=0.0, stop_reason="converged")

    assert report.verdict(Fake(4.9)).endswith("good fit")
    assert report.verdict(Fake(9.0)).endswith("fits within 10 %")
    assert "poor: the law cannot follow the data" in report.verdict(Fake(40.0))
    assert report.verdict(Fake(9.0)) == Fake(9.0).verdict()  # the summary's first line
    assert "no valid fit" in report.verdict(Fake(float("inf")))
    assert report.verdict(Fake(1.0), interrupted=True).startswith("INTERRUPTED")


def test_the_parameter_table_holds_the_fitted_constants_with_units(cal, page):
    rows = {r[0]: r for r in Doc(page).rows if r and r[0] in cal.params}
    units = dict(zip(cal.model.param_names, cal.model.units))
    assert set(rows) == set(cal.params)
    for name, v in cal.params.items():
        assert float(rows[name][1]) == pytest.approx(v, rel=1e-5)
        assert rows[name][2] == units[name]


def test_the_cards_are_in_the_report_as_written_by_export(cal, page):
    for solver in ("abaqus", "lsdyna", "ansys"):
        card = export(cal, to=solver, notes=list(cal.headlines))
        pre = re.search(rf'<pre id="card-{solver}">(.*?)</pre>', page, re.S)
        assert pre is not None and html.unescape(pre.group(1)) == card
    assert 'id="card-check"' in page  # checked against the curves it keeps


def test_a_hostile_curve_name_is_escaped_everywhere(page):
    assert "<script" not in page.lower()
    assert "script" not in Doc(page).tags
    assert html.escape(HOSTILE) in page


def test_nothing_outside_the_file_is_referenced(page):
    doc = Doc(page)
    assert doc.urls  # the check below sees the figures and the links
    assert any(u.startswith("data:image/png;base64,") for u in doc.urls)
    assert external(page) == []
    assert "http://" not in page and "https://" not in page


def test_repr_html_shows_the_verdict_and_the_main_plot(cal):
    text = cal._repr_html_()
    assert html.escape(report.verdict(cal)) in text
    assert text.count("<img") == (1 if plot.have_matplotlib() else 0)
    assert external(text) == []


def test_without_matplotlib_the_report_has_a_note_instead_of_figures(cal, tmp_path,
                                                                     monkeypatch):
    monkeypatch.setattr(plot, "have_matplotlib", lambda: False)
    path = tmp_path / "r.html"
    report.write_report(cal, path)
    text = path.read_text(encoding="utf-8")
    assert "<img" not in text and "figures not drawn: plots need matplotlib" in text
    assert html.escape(report.verdict(cal)) in text


def test_a_loaded_result_without_its_data_says_so(cal, tmp_path):
    cal.save(tmp_path / "results.json")
    loaded = vhfit.Calibration.load(tmp_path / "results.json")
    loaded.report(tmp_path / "r.html")
    text = (tmp_path / "r.html").read_text(encoding="utf-8")
    assert "the data are not at hand" in text and "<img" in text  # the history plot
    assert html.escape(report.verdict(cal)) in text


def test_the_report_hook_is_what_calibration_calls(cal, tmp_path):
    seen = []
    set_html_report(lambda c, path, curves=None, **kw: seen.append((c, path)), lambda c: "x")
    try:
        cal.report(tmp_path / "r.html")
        assert seen == [(cal, tmp_path / "r.html")] and cal._repr_html_() == "x"
    finally:
        set_html_report(report.write_report, report.repr_html)


def test_versions_name_every_library_of_the_result():
    v = report.versions()
    assert {"vhfit", "numpy", "scipy", "numba", "python"} <= set(v)
    assert v["numpy"] == np.__version__ and v["vhfit"] == vhfit.__version__


def test_build_report_marks_an_interrupted_fit(cal):
    text = report.build_report(cal, figures=False, cards={}, command="vhfit fit a.csv")
    assert "INTERRUPTED" not in text
    text = report.build_report(cal, figures=False, cards={}, interrupted=True,
                               command="vhfit fit <a>.csv")
    assert 'class="interrupted"' in text and "INTERRUPTED (best so far" in text
    assert "vhfit fit &lt;a&gt;.csv" in text


# ---------------------------------------------------------------- vhfit fit writes it
def test_vhfit_fit_writes_report_html_beside_the_other_outputs(tmp_path, capsys):
    files = []
    for c, fname in zip(curves(), ("slow.csv", "fast<b>.csv")):
        path = tmp_path / fname
        path.write_text(f"# strain_rate: {c.strain_rate}\nstrain,stress_MPa\n" + "".join(
            f"{e:.6g},{s:.8g}\n" for e, s in zip(c.strain, c.stress)))
        files.append(str(path))
    out = tmp_path / "out"
    code = cli.main(["fit", *files, "--prony", "1", "--maxiter", "20", "--seed", "1", "-q",
                     "--out", str(out)])
    assert code == 0
    res = json.loads((out / "results.json").read_text())
    text = (out / "report.html").read_text(encoding="utf-8")
    head = html.unescape(re.search(r'<p class="headline">(.*?)</p>', text).group(1))
    assert head.startswith(f"RMSAPE {res['rmsape']:.4g} %: ")
    assert "report.html" in res["files"] and "report.html" in capsys.readouterr().out
    assert "<b>" not in text and "fast&lt;b&gt;" in text  # the file name, escaped
    assert external(text) == [] and "<img" in text
    lsdyna = re.search(r'<pre id="card-lsdyna">(.*?)</pre>', text, re.S).group(1)
    assert html.unescape(lsdyna) == (out / "lsdyna.k").read_text()
    assert html.escape("vhfit fit") in text and "--maxiter 20" in text  # the command


def test_vhfit_fit_no_plot_still_writes_the_report(tmp_path):
    c = curves()[0]
    path = tmp_path / "one.csv"
    path.write_text(f"# strain_rate: {c.strain_rate}\nstrain,stress_MPa\n" + "".join(
        f"{e:.6g},{s:.8g}\n" for e, s in zip(c.strain, c.stress)))
    out = tmp_path / "out"
    assert cli.main(["fit", str(path), "--prony", "0", "--maxiter", "10", "-q", "--no-plot",
                     "--out", str(out)]) == 0
    text = (out / "report.html").read_text(encoding="utf-8")
    assert "figures not drawn (asked for none)" in text and "<img" not in text


def test_one_fit_figure_per_test_mode_and_the_order_scan(tmp_path):
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    g = np.linspace(0.0, 0.8, 21)
    shear = vhfit.Curve(strain=g, stress=m.stress(P, strain=g, strain_rate=1.0,
                                                  measure="engineering",
                                                  deformation="simple_shear"),
                        strain_rate=1.0, deformation="simple_shear", name="shear")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c = vhfit.calibrate([*curves(), shear], hyperelastic="mooney_rivlin", n_prony="auto",
                            max_prony=2, seed=0, maxiter=10)
    text = report.build_report(c, cards={})
    figs = re.findall(r'<figure id="fig-([^"]+)"', text)
    if plot.have_matplotlib():
        assert figs[:2] == ["fit-uniaxial", "fit-simple_shear"] and "order-scan" in figs
    scan = [r for r in Doc(text).rows if len(r) == 4 and r[0] in ("1", "2")]
    assert [int(r[0]) for r in scan] == [row["n_prony"] for row in c.order_scan]
    for r, row in zip(scan, c.order_scan):
        assert float(r[1]) == pytest.approx(row["rmsape"], rel=1e-3)
    assert [r[3] for r in scan].count("chosen") == 1


@pytest.mark.skipif(not plot.have_matplotlib(), reason="figures need matplotlib")
def test_a_ramp_hold_history_gets_a_stress_time_view_and_a_ramp_does_not(page, tmp_path):
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    t = np.concatenate([np.linspace(0.0, 1.0, 11), np.linspace(1.5, 20.0, 20)])
    eps = np.where(t <= 1.0, -0.3 * t, -0.3)
    hold = vhfit.Curve(strain=eps, stress=m.stress(P, strain=eps, time=t,
                                                   measure="engineering"),
                       time=t, name="ramp-hold")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c = vhfit.calibrate([hold], hyperelastic="mooney_rivlin", n_prony=1, seed=0,
                            maxiter=5)
    figs = re.findall(r'<figure id="fig-([^"]+)"', report.build_report(c, cards={}))
    assert "stress-time" in figs
    assert "stress-time" not in re.findall(r'<figure id="fig-([^"]+)"', page)
    # vhfit fit's own fit.png of one mode holds the stress-time panels: not drawn twice
    import io  # noqa: PLC0415

    fig = plot.plot_fit(c, [hold], io.BytesIO())
    assert [ax.get_xlabel() for ax in fig.axes] == ["engineering strain λ1 − 1 "
                                                    "(compression < 0)", "time (s)"]
    png = tmp_path / "fit.png"
    plot.plot_fit(c, [hold], png)
    text = report.build_report(c, [hold], cards={}, images={"fit": png})
    figs = re.findall(r'<figure id="fig-([^"]+)"', text)
    assert figs[0] == "fit-uniaxial" and "stress-time" not in figs
    assert "below, stress against time" in text


def test_a_result_read_back_brings_its_recorded_context(cal, tmp_path):
    """What vhfit fit recorded in results.json (``context`` of a loaded result) stands in
    for the arguments not given: command, status, card check, versions."""
    cal.save(tmp_path / "results.json")
    loaded = dataclasses.replace(vhfit.Calibration.load(tmp_path / "results.json"), context={
        "command": ["vhfit", "fit", "<x>.csv"], "status": "interrupted",
        "card_check": {"lsdyna": {"rmsape": 9.0, "per_curve": [8.0, 10.0],
                                  "formulation": "lsdyna", "fit_formulation": "hereditary",
                                  "fit_rmsape": 1.0, "allowed": 1.1, "exceeds": True}},
        "card_check_warnings": ["LS-DYNA card: recorded warning"],
        "versions": {"numpy": "0.0-recorded"}, "data_label": "label <i>",
    })
    text = report.build_report(loaded, figures=False)
    assert html.escape(shlex.join(["vhfit", "fit", "<x>.csv"])) in text
    assert '<p class="interrupted">' in text
    assert "WARNING: LS-DYNA card: recorded warning" in text
    assert "lsdyna: EXCEEDS its fit; fits within 10 %, card RMSAPE 9 % (allowed 1.1 %)" in text
    assert "0.0-recorded" in text and "label &lt;i&gt;" in text


def test_shift_figure_is_the_plot_modules_shift_factor_plot():
    """The report's shift-factor figure is drawn by vhfit.plot (one drawing, two users):
    its points labelled as the factors applied to the tests, with the calibration's law."""
    import io
    from types import SimpleNamespace

    from vhfit import plot, tts
    from vhfit.report import _figures

    law = tts.WLF(C1=8.86, C2=101.6, T_ref=20.0)
    table = SimpleNamespace(temperatures=np.array([10.0, 20.0, 30.0]),
                            log_aT=law.log_aT(np.array([10.0, 20.0, 30.0])), law=law)
    fig = plot.plot_shift_factors(table, io.BytesIO(), label="applied to the tests")
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert texts[0] == "applied to the tests" and texts[1].startswith(law.name)
    cal = SimpleNamespace(shift_table=dict(zip(table.temperatures, table.log_aT)), shift=law)
    drawn = _figures.shift_figure(cal)
    assert drawn.note is None and drawn.uri.startswith("data:image/png;base64,")


@pytest.mark.skipif(not plot.have_matplotlib(), reason="figures need matplotlib")
def test_the_fit_png_of_several_modes_is_the_reports_fit_figure_not_drawn_again(tmp_path):
    """vhfit fit's fit.png (every curve, each labelled with its test) is inlined as the
    one fit figure of a report of several modes: the same bytes, no per-mode redraw."""
    import base64  # noqa: PLC0415

    m = vhfit.ViscoHyperelastic("neo_hooke", 0)
    e = np.linspace(0.0, 0.6, 13)
    tests = [vhfit.Curve(strain=e, stress=m.stress({"C10": 0.2}, strain=e, strain_rate=1.0,
                                                  deformation=d),
                         strain_rate=1.0, deformation=d, name=d)
             for d in ("uniaxial", "simple_shear")]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c = vhfit.calibrate(tests, hyperelastic="neo_hooke", n_prony=0, seed=0, maxiter=5)
    png = tmp_path / "fit.png"
    fig = plot.plot_fit(c, tests, png)
    labels = [t.get_text() for ax in fig.axes if ax.get_legend()
              for t in ax.get_legend().get_texts()]
    assert any("uniaxial" in t for t in labels) and any("simple_shear" in t for t in labels)
    text = report.build_report(c, tests, cards={}, images={"fit": png})
    figs = re.findall(r'<figure id="fig-([^"]+)"', text)
    assert figs[0] == "fit-uniaxial-simple_shear" and not {"fit-uniaxial",
                                                           "fit-simple_shear"} & set(figs)
    assert base64.b64encode(png.read_bytes()).decode("ascii") in text
    # without the file (a report made in Python) each mode is drawn on its own
    figs = re.findall(r'<figure id="fig-([^"]+)"', report.build_report(c, tests, cards={}))
    assert figs[:2] == ["fit-uniaxial", "fit-simple_shear"]
