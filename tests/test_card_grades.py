"""Every card graded as its own fit: the summary's card lines, the card check's words,
the report's verdict and ``vhfit check``; the warnings of a card's own fit beside the
main fit's; a solver without a card listed with its reason and a flag that works.

Known answers: the grade thresholds are the fit's verdict (5 %, 10 %, 25 %:
``vhfit.calibration.GOOD_FIT``, ``WITHIN_FIT``, ``ROUGH_FIT``), so a card of 2 % is a
"good fit", of 7 % "fits within 10 %", of 17 % or 23.6 % a "rough fit", of 30 % "poor".
The data are synthetic: noise-free ramps of Mooney-Rivlin + 1 Prony term (G1 = 1.8 MPa,
tau1 = 0.01 s at rates 1 to 1000 1/s, so the glassy stress is twice the relaxed one),
which an elastic neo-Hooke law misses by far more than 25 %; and a frequency sweep of
11 Maxwell terms, one a decade, which the per-decade spectrum fits with 11 terms,
more than LS-DYNA's MAT_077_H takes (6).
"""

from __future__ import annotations

import dataclasses
import json
import re
import shlex
from pathlib import Path

import numpy as np
import pytest

import vhfit
from vhfit import cli
from vhfit.calibration import (
    GOOD_FIT,
    GRADES,
    ROUGH_FIT,
    WITHIN_FIT,
    Calibration,
    grade,
    grade_word,
    worst_grade,
)
from vhfit.cli import _cards
from vhfit.export import TooManyTerms, export
from vhfit.export.check import FAILS, PASSES, CardCheck, check_words, own_fit_warnings
from vhfit.model import ViscoHyperelastic
from vhfit.report import _html, build_report

P = dict(C10=0.2, C01=0.1, G1=1.8, tau1=0.01)


def _cal(rmsape: float, headlines=(), formulation="hereditary", n_prony=0) -> Calibration:
    """A result with the given error and headlines (no fit: the verdict reads only them)."""
    model = ViscoHyperelastic("neo_hooke", n_prony, formulation=formulation)
    params = dict(C10=0.5, **{k: v for i in range(1, n_prony + 1)
                              for k, v in ((f"G{i}", 1.0), (f"tau{i}", 10.0 ** -i))})
    return Calibration(model=model, params=params, rmsape=rmsape,
                       per_curve_rmsape=[rmsape], nit=1, nfev=1, wall_time=0.0,
                       stop_reason="converged", headlines=list(headlines),
                       warnings=list(headlines), curve_names=["a"])


def _check(solver: str, rmsape: float, fit_rmsape: float, formulation="hereditary") -> dict:
    return CardCheck(solver=solver, formulation=formulation, rmsape=rmsape,
                     per_curve=[rmsape], fit_formulation=formulation,
                     fit_rmsape=fit_rmsape).to_dict()


# ======================================================== the words themselves
@pytest.mark.parametrize("e, word, level", [
    (2.0, "good fit", "good"), (GOOD_FIT, "good fit", "good"),
    (7.0, "fits within 10 %", "fair"), (WITHIN_FIT, "fits within 10 %", "fair"),
    (17.0, "rough fit", "fair"), (23.6, "rough fit", "fair"), (ROUGH_FIT, "rough fit", "fair"),
    (30.0, "poor", "poor"), (float("nan"), "no valid fit", "poor"),
])
def test_a_cards_grade_word_uses_the_fits_thresholds(e, word, level):
    assert grade_word(e) == word
    assert grade(e)[0] == level and grade(e)[1].startswith(word)


def test_the_worst_grade_is_the_worst_level():
    assert GRADES == ("good", "fair", "poor")
    assert worst_grade(["good", "fair"]) == "fair"
    assert worst_grade(["fair", "poor", "good"]) == "poor"
    assert worst_grade([]) == "good"


def test_ok_says_that_the_card_reproduces_its_fit_then_grades_the_card():
    assert PASSES == "ok (card = its fit)" and FAILS == "EXCEEDS its fit"
    assert check_words(23.6, False) == "ok (card = its fit); rough fit"
    assert check_words(2.0, False) == "ok (card = its fit); good fit"
    assert check_words(30.0, True) == "EXCEEDS its fit; poor"


def test_the_check_table_row_grades_each_card():
    rows = _cards.check_table({"abaqus": _check("abaqus", 2.0, 2.0),
                               "lsdyna": _check("lsdyna", 23.6, 23.5, "lsdyna")}, ["a"])
    row = {ln.split()[0]: ln for ln in rows[2:4]}
    assert row["abaqus"].endswith("  ok (card = its fit); good fit")
    assert row["lsdyna"].endswith("  ok (card = its fit); rough fit")
    assert "23.6 %" in row["lsdyna"]


# ======================================================== the summary's head
def test_a_card_whose_own_fit_is_poor_is_called_poor_in_the_head():
    """The main fit good (2 %), the LS-DYNA card from its own fit 30 %: its line says
    poor, the others good."""
    res = _cards.Cards(files={"abaqus": "abaqus.inp", "lsdyna": "lsdyna.k"},
                       fits={"abaqus": "hereditary", "lsdyna": "lsdyna"})
    res.check = {"abaqus": CardCheck("abaqus", "hereditary", 2.0, [2.0], "hereditary", 2.0),
                 "lsdyna": CardCheck("lsdyna", "lsdyna", 30.0, [30.0], "lsdyna", 29.9)}
    lines = _cards._headline(res, {"hereditary": ["abaqus"], "lsdyna": ["lsdyna"]})
    assert lines[0] == ("abaqus: abaqus.inp: Abaqus will show RMSAPE 2 % on the data (its fit, "
                        "in 'hereditary': 2 %): good fit")
    assert lines[1] == ("lsdyna: lsdyna.k: LS-DYNA will show RMSAPE 30 % on the data (its fit, "
                        "in 'lsdyna': 29.9 %): poor")


def test_own_fit_warnings_name_the_cards_and_skip_the_main_fits():
    main = _cal(2.0, ["shared warning"])
    dyna = _cal(13.8, ["shared warning", "constants not determined: mu in [-130, 130]"],
                formulation="lsdyna")
    got = own_fit_warnings({"hereditary": main, "lsdyna": dyna},
                           {"hereditary": ["abaqus", "ansys"], "lsdyna": ["lsdyna"]})
    assert got == ["LS-DYNA card's own fit ('lsdyna'): constants not determined: "
                   "mu in [-130, 130]"]
    assert own_fit_warnings({"hereditary": main}, {"hereditary": ["abaqus"]}) == []
    assert own_fit_warnings({}, {}) == []


# ======================================================== the report's verdict
@pytest.mark.parametrize("cards, colour", [
    ({"abaqus": 2.0}, "good"),
    ({"abaqus": 2.0, "lsdyna": 7.0}, "fair"),
    ({"abaqus": 2.0, "lsdyna": 30.0}, "poor"),
    ({"abaqus": 30.0}, "poor"),
])
def test_the_verdict_colour_is_the_worst_of_the_fit_and_its_cards(cards, colour):
    check = {s: _check(s, e, e) for s, e in cards.items()}
    box = _html.verdict_html(_cal(2.0), "complete", check, [])
    assert box.startswith(f'<div class="verdict {colour}"')
    for s, e in cards.items():
        assert f"{s}: ok (card = its fit); {_html.esc(grade_word(e))}, card RMSAPE" in box
    assert ('<li class="bad">lsdyna: ok (card = its fit); poor' in box) == (
        cards.get("lsdyna") == 30.0)


def test_a_poor_fit_with_good_cards_stays_poor():
    box = _html.verdict_html(_cal(40.0), "complete", {"abaqus": _check("abaqus", 2.0, 2.0)}, [])
    assert box.startswith('<div class="verdict poor"')


def test_the_report_shows_the_own_fits_warnings_and_the_solvers_without_a_card():
    text = build_report(_cal(2.0), [], cards={"abaqus": "*card", "lsdyna": None},
                        card_check={"abaqus": _check("abaqus", 2.0, 2.0)},
                        card_notes={"lsdyna": ["no card: six terms at most"]},
                        fit_warnings=["LS-DYNA card's own fit ('lsdyna'): g_inf = 0.021"],
                        figures=False)
    box = text[text.index('<div class="verdict'):text.index("</div>")]
    assert box.startswith('<div class="verdict fair"')  # a warning that matters: not green
    assert "<li>WARNING: LS-DYNA card&#x27;s own fit (&#x27;lsdyna&#x27;): g_inf = 0.021</li>" \
        in box
    assert '<li class="bad">lsdyna: no card: six terms at most</li>' in box
    assert "<h3>lsdyna</h3>" in text  # and in the cards' section


def test_a_results_file_read_back_brings_its_own_fits_warnings(tmp_path):
    cal = _cal(2.0)
    loaded = dataclasses.replace(cal, context={"card_fit_warnings": ["LS-DYNA card's own "
                                                                     "fit ('lsdyna'): recorded"]})
    text = build_report(loaded, [], cards={}, figures=False)
    assert "WARNING: LS-DYNA card&#x27;s own fit (&#x27;lsdyna&#x27;): recorded" in text


# ======================================================== through the command line
@pytest.fixture(scope="module")
def ramps(tmp_path_factory, write_ramps) -> list[str]:
    return write_ramps(tmp_path_factory.mktemp("grades-data"),
                       ViscoHyperelastic("mooney_rivlin", 1), P)


def _fit(files, out: Path, *flags) -> dict:
    assert cli.main(["fit", *files, "--seed", "0", "--no-plot", "-q", "--out", str(out),
                     *flags]) == 0
    return json.loads((out / "results.json").read_text())


@pytest.fixture(scope="module")
def poor_run(ramps, tmp_path_factory):
    """An elastic law for rate-dependent data: every card reproduces its fit, and is poor."""
    out = tmp_path_factory.mktemp("poor") / "o"
    return out, _fit(ramps, out, "--model", "neo_hooke", "--prony", "0")


def test_poor_cards_are_called_poor_in_the_summary_and_the_report(poor_run):
    out, res = poor_run
    assert res["rmsape"] > ROUGH_FIT
    lines = (out / "summary.txt").read_text().splitlines()
    head = lines[1:lines.index("")]
    assert [ln.split(":")[0] for ln in head] == ["abaqus", "ansys", "lsdyna"]
    assert all(ln.endswith("%): poor") for ln in head), head
    rows = [ln for ln in lines if ln.startswith("  abaqus ") or ln.startswith("  lsdyna ")]
    assert rows and all(r.endswith("ok (card = its fit); poor") for r in rows)
    page = (out / "report.html").read_text()
    assert '<div class="verdict poor"' in page
    assert '<li class="bad">lsdyna: ok (card = its fit); poor, card RMSAPE' in page


def test_vhfit_check_with_data_grades_each_card(poor_run, ramps, capsys):
    out, res = poor_run
    capsys.readouterr()
    assert cli.main(["check", str(out / "results.json"), "--data", *ramps]) == 0
    text = capsys.readouterr().out
    rows = [ln for ln in text.splitlines() if ln.startswith(("  abaqus ", "  ansys ",
                                                               "  lsdyna "))]
    assert len(rows) == 3 and all(r.endswith("  ok (card = its fit); poor") for r in rows)
    assert not any(r.rstrip().endswith("  ok") for r in rows)


def test_a_cards_own_fit_warning_reaches_the_head_the_verdict_and_check(ramps, tmp_path,
                                                                      monkeypatch, capsys):
    """The LS-DYNA card's own fit (its formulation's) has a headline the main fit lacks:
    it is a WARNING line at the head of the summary, in the report's verdict (not green),
    in results.json and in ``vhfit check``."""
    real = cli._fit.calibrate
    note = "constants not determined by the data: planted for the test"

    def calibrate(curves, **kw):
        cal = real(curves, **kw)
        if kw.get("formulation") == "lsdyna":
            cal = dataclasses.replace(cal, headlines=[*cal.headlines, note],
                                      warnings=[*cal.warnings, note])
        return cal

    monkeypatch.setattr(cli._fit, "calibrate", calibrate)
    out = tmp_path / "o"
    res = _fit(ramps, out, "--prony", "1", "--for", "abaqus,lsdyna")
    want = f"LS-DYNA card's own fit ('lsdyna'): {note}"
    assert res["card_fit_warnings"] == [want] and note not in res["headlines"]
    lines = (out / "summary.txt").read_text().splitlines()
    head = lines[:lines.index("")]
    assert f"WARNING: {want}" in head
    page = (out / "report.html").read_text()
    box = page[page.index('<div class="verdict'):page.index("</div>")]
    assert "own fit (&#x27;lsdyna&#x27;): constants not determined" in box
    assert not box.startswith('<div class="verdict good"')
    capsys.readouterr()
    assert cli.main(["check", str(out / "results.json"), "--data", *ramps]) == 0
    assert f"WARNING: {want}" in capsys.readouterr().out.splitlines()


# ======================================================== no card: a flag that works
@pytest.fixture(scope="module")
def sweep(tmp_path_factory) -> str:
    """A frequency sweep of E* = 1 + sum of 11 unit terms, tau = 1e-7 .. 1e3 s."""
    f = np.logspace(-4, 6, 41)
    w = 2 * np.pi * f
    tau = np.logspace(-7, 3, 11)
    es = 1.0 + np.sum((1j * w[:, None] * tau) / (1 + 1j * w[:, None] * tau), 1)
    path = tmp_path_factory.mktemp("sweep") / "dma.csv"
    np.savetxt(path, np.column_stack([f, es.real, es.imag]), delimiter=",", comments="",
               header="frequency_Hz,storage_MPa,loss_MPa")
    return str(path)


def test_the_no_card_hint_is_a_flag_that_writes_the_card_when_followed(sweep, tmp_path):
    out = tmp_path / "many"
    res = _fit([sweep], out, "--prony", "auto")
    assert res["n_prony"] > 6 and not (out / "lsdyna.k").exists()
    why = res["card_errors"]["lsdyna"]
    assert why.startswith("LS-DYNA *MAT_HYPERELASTIC_RUBBER reads at most 6 Prony terms; "
                          f"this model has {res['n_prony']}: ")
    assert "n_prony" not in why  # the command line's words, not the API's
    lines = (out / "summary.txt").read_text().splitlines()
    assert f"lsdyna: no card: {why}" in lines[:lines.index("")]
    page = (out / "report.html").read_text()
    assert f'<li class="bad">lsdyna: no card: {_html.esc(why)}</li>' in page
    flag = shlex.split(re.search(r"refit \(vhfit fit\) with (--prony \d+)", why).group(1))
    assert flag == ["--prony", "6"]
    again = tmp_path / "six"
    res6 = _fit([sweep], again, *flag)
    assert res6["n_prony"] == 6 and "lsdyna" not in res6["card_errors"]
    assert (again / "lsdyna.k").is_file() and res6["cards"]["lsdyna"] == "lsdyna.k"


def test_export_of_too_many_terms_names_the_flag(sweep, tmp_path, capsys):
    out = tmp_path / "many"
    _fit([sweep], out, "--prony", "auto")
    capsys.readouterr()
    assert cli.main(["export", str(out / "results.json"), "--to", "lsdyna"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("vhfit: error: --to lsdyna: LS-DYNA *MAT_HYPERELASTIC_RUBBER reads "
                          "at most 6 Prony terms") and "--prony 6" in err and "n_prony" not in err


def test_the_writer_refuses_too_many_terms_with_the_limit():
    m = ViscoHyperelastic("mooney_rivlin", 7)
    p = dict(C10=0.2, C01=0.1, **{k: v for i in range(1, 8)
                                  for k, v in ((f"G{i}", 0.1), (f"tau{i}", 10.0 ** -i))})
    with pytest.raises(TooManyTerms) as err:
        export(m, p, to="lsdyna")
    assert err.value.limit == 6 and isinstance(err.value, ValueError)
    assert str(err.value).endswith("this model has 7: refit with at most 6 terms (n_prony=6)")
    assert vhfit.export.TooManyTerms is TooManyTerms
