"""``vhfit fit --for``, the card flags (--density, --poisson, --bulk-modulus,
--abaqus-explicit), the card check in the outputs, and ``vhfit check`` — in-process.

Hand values: the data are three noise-free compression ramps of Mooney-Rivlin + 1 Prony
term, C10 = 0.2, C01 = 0.1, G1 = 1.8, tau1 = 0.01, fitted (exactly, or to its noise-free
optimum) by a one-term fit: mu0 = 2 (C10 + C01), E_inf = 3 mu0, G0 = E_inf + G1,
mu_inst = G0 / 3. The compressibility numbers are worked out from the fitted constants
with the documented formulas (docs/export.md), not read from the cards.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from vhfit import cli
from vhfit.model import ViscoHyperelastic

P = dict(C10=0.2, C01=0.1, G1=1.8, tau1=0.01)


@pytest.fixture(scope="module")
def data(tmp_path_factory, write_ramps) -> list[str]:
    model = ViscoHyperelastic("mooney_rivlin", 1)
    return write_ramps(tmp_path_factory.mktemp("cards-data"), model, P)


def fit(data, out: Path, *flags) -> dict:
    argv = ["fit", *data, "--prony", "1", "--seed", "0", "--no-plot", "-q", "--out", str(out),
            *flags]
    assert cli.main(argv) == 0
    return json.loads((out / "results.json").read_text())


def moduli(params) -> tuple[float, float]:
    """mu0 (long-term) and mu_inst (instantaneous) of fitted Mooney-Rivlin + 1 term."""
    mu0 = 2 * (params["C10"] + params["C01"])
    return mu0, (3 * mu0 + params["G1"]) / 3


def data_lines(text: str, prefix: str) -> list[str]:
    return [ln for ln in text.splitlines() if ln.strip() and not ln.startswith(prefix)]


# ============================================================ cards that run
@pytest.fixture(scope="module")
def default_run(data, tmp_path_factory):
    out = tmp_path_factory.mktemp("default") / "o"
    return out, fit(data, out, "--density", "1.1e-9", "--abaqus-explicit")


def test_density_reaches_every_card(default_run):
    out, _ = default_run
    abq = data_lines((out / "abaqus.inp").read_text(), "**")
    assert abq[1:3] == ["*DENSITY", "1.1e-09,"]
    dyna = data_lines((out / "lsdyna.k").read_text(), "$")
    assert float(dyna[3][20:40]) == 1.1e-9  # card 1: MID RO PR N, 20-character fields
    ans = data_lines((out / "ansys.mac").read_text(), "!")
    assert ans[0] == "MP,DENS,1,1.1e-09"
    for name in ("abaqus.inp", "lsdyna.k", "ansys.mac"):
        assert "WARNING: no density" not in (out / name).read_text()


def test_default_bulk_modulus_gives_lsdyna_pr_and_explicit_d1(default_run):
    """K = 1000 mu_inst: LS-DYNA's K = 2 mu0 (1 + PR)/(3 (1 - 2 PR)) must give it, and
    the Abaqus/Explicit D1 = 2/K; the Standard card keeps D1 = 0 and says why."""
    out, res = default_run
    mu0, mu_inst = moduli(res["fits"]["lsdyna"]["params"])  # the LS-DYNA card's own fit
    K = 1000 * mu_inst
    pr = float(data_lines((out / "lsdyna.k").read_text(), "$")[3][40:60])
    assert pr == pytest.approx((3 * K - 2 * mu0) / (6 * K + 2 * mu0), rel=1e-14)
    assert 2 * mu0 * (1 + pr) / (3 * (1 - 2 * pr)) == pytest.approx(K, rel=1e-9)
    mu0, mu_inst = moduli(res["params"])  # the Abaqus cards: the hereditary fit
    K = 1000 * mu_inst
    explicit = (out / "abaqus_explicit.inp").read_text()
    row = [float(v) for v in data_lines(explicit, "**")[4].split(",")]
    assert row[:2] == [res["params"]["C10"], res["params"]["C01"]]
    assert row[2] == pytest.approx(2 / K, rel=1e-14)
    assert "Abaqus/Explicit" in explicit.splitlines()[0]
    standard = (out / "abaqus.inp").read_text()
    assert [float(v) for v in data_lines(standard, "**")[4].split(",")][2] == 0.0
    assert "Standard with hybrid elements ONLY" in " ".join(standard.split())
    for name in ("abaqus.inp", "abaqus_explicit.inp", "lsdyna.k", "ansys.mac"):
        assert "Units: N, mm, s, MPa" in (out / name).read_text()


def test_poisson_and_bulk_modulus_set_every_solvers_compressibility(data, tmp_path):
    res = fit(data, tmp_path / "nu", "--poisson", "0.49", "--for", "abaqus,ansys")
    mu0, mu_inst = moduli(res["params"])
    K = 2 * mu_inst * 1.49 / (3 * 0.02)  # nu = 0.49 of the instantaneous response
    abq = data_lines((tmp_path / "nu" / "abaqus.inp").read_text(), "**")
    assert float(abq[2].split(",")[2]) == pytest.approx(2 / K, rel=1e-14)
    ans = data_lines((tmp_path / "nu" / "ansys.mac").read_text(), "!")
    assert float(ans[1].split(",")[4]) == pytest.approx(2 / K, rel=1e-14)  # TBDATA,1,c10,c01,d
    assert not (tmp_path / "nu" / "lsdyna.k").exists()  # not asked for

    fit(data, tmp_path / "k", "--bulk-modulus", "500", "--for", "lsdyna")
    pr = float(data_lines((tmp_path / "k" / "lsdyna.k").read_text(), "$")[3][40:60])
    res = json.loads((tmp_path / "k" / "results.json").read_text())
    mu0, _ = moduli(res["params"])
    assert 2 * mu0 * (1 + pr) / (3 * (1 - 2 * pr)) == pytest.approx(500.0, rel=1e-12)


def test_no_density_is_loud_in_cards_and_summary(data, tmp_path):
    fit(data, tmp_path / "o", "--for", "ansys")
    assert "! WARNING: no density: MP,DENS is not written" in (tmp_path / "o" / "ansys.mac"
                                                              ).read_text()
    assert "note: no --density" in (tmp_path / "o" / "summary.txt").read_text()


# ================================================================ --for and the check
def test_default_fit_serves_every_solver_from_its_own_fit(default_run):
    """Without --for each solver's card comes from a fit in the formulation its solver
    integrates: one hereditary fit (Abaqus, Ansys), one lsdyna fit (LS-DYNA); every card
    passes its own check, and the summary's first lines say per solver which file and
    which error its solver will show."""
    out, res = default_run
    check = res["card_check"]
    assert set(check) == {"abaqus", "abaqus_explicit", "lsdyna", "ansys"}
    assert res["card_fits"] == {"abaqus": "hereditary", "abaqus_explicit": "hereditary",
                                "lsdyna": "lsdyna", "ansys": "hereditary"}
    assert res["fits"]["lsdyna"]["solvers"] == ["lsdyna"]
    assert res["fits"]["lsdyna"]["formulation"] == "lsdyna"
    # the LS-DYNA fit started from the hereditary one: 3/8 of its population, seeded
    assert res["fits"]["lsdyna"]["options"]["popsize"] == res["options"]["popsize"] * 3 // 8
    for s, c in check.items():
        assert c["formulation"] == c["fit_formulation"] == res["card_fits"][s]
        assert c["rmsape"] <= 1.05 * c["fit_rmsape"] + 0.01 and not c["exceeds"], s
    assert check["abaqus"]["fit_rmsape"] == pytest.approx(res["rmsape"], rel=1e-9, abs=1e-12)
    assert check["lsdyna"]["fit_rmsape"] == pytest.approx(res["fits"]["lsdyna"]["rmsape"],
                                                          rel=1e-9, abs=1e-12)
    assert res["card_check_warnings"] == [] and res["card_errors"] == {}
    lines = (out / "summary.txt").read_text().splitlines()
    assert lines[0].startswith(f"RMSAPE {res['rmsape']:.4g} %: ")  # the verdict first
    head = lines[1:lines.index("")]
    # grouped by fit: the hereditary fit's cards, then the lsdyna fit's
    assert [ln.split(":")[0] for ln in head] == ["abaqus", "abaqus_explicit", "ansys", "lsdyna"]
    for ln in head:
        key, file = ln.split(": ")[:2]
        assert file == res["cards"][key] and (out / file).is_file()
        shown = float(ln.split("will show RMSAPE ")[1].split(" %")[0])
        assert shown == pytest.approx(check[key]["rmsape"], rel=1e-3)
    assert "LS-DYNA will show" in head[3] and "'lsdyna'" in head[3]
    card = " ".join(ln.lstrip("$ ") for ln in (out / "lsdyna.k").read_text().splitlines())
    assert "WARNING: LS-DYNA card" not in card
    assert "formulation 'lsdyna' (this fit serves lsdyna; each other solver has its own fit)" \
        in card


@pytest.fixture(scope="module")
def one_fit_run(data, tmp_path_factory):
    """--formulation hereditary: one fit for every card, as asked."""
    out = tmp_path_factory.mktemp("one-fit") / "o"
    return out, fit(data, out, "--formulation", "hereditary")


def test_formulation_makes_one_fit_serve_all_and_flags_lsdyna(one_fit_run):
    """The user's choice of one fit for all: the LS-DYNA card, integrated in LS-DYNA's
    formulation, misses the data by more than the margin at these rates; it is written
    (asked for) with the warning at its head and the summary's."""
    out, res = one_fit_run
    check = res["card_check"]
    for s in ("abaqus", "ansys"):
        assert check[s]["formulation"] == "hereditary"
        assert check[s]["rmsape"] == pytest.approx(res["rmsape"], rel=1e-9, abs=1e-12)
        assert len(check[s]["per_curve"]) == 3 and not check[s]["exceeds"]
    dyna = check["lsdyna"]
    assert dyna["formulation"] == "lsdyna" and dyna["fit_formulation"] == "hereditary"
    assert dyna["exceeds"] and dyna["rmsape"] > 1.05 * res["rmsape"] + 0.01
    assert res["card_fits"] == {"abaqus": "hereditary", "lsdyna": "hereditary",
                                "ansys": "hereditary"}
    summary = (out / "summary.txt").read_text()
    # top-down: the verdict, the card check's warning, then the cards
    first = summary.split("\n\n")[0].splitlines()
    assert first[0].startswith(f"RMSAPE {res['rmsape']:.4g} %: ")
    assert first[1].startswith("WARNING: LS-DYNA card") and "--for lsdyna" in first[1]
    assert first[2].startswith("abaqus: abaqus.inp: Abaqus will show")
    card = (out / "lsdyna.k").read_text()
    assert "$ WARNING: LS-DYNA card" in card
    assert "formulation 'hereditary' (this fit serves abaqus, lsdyna, ansys)" in " ".join(
        ln.lstrip("$ ") for ln in card.splitlines())


def test_an_unconverged_fit_says_so_first_in_every_card_and_material_json(data, tmp_path):
    out = tmp_path / "o"
    res = fit(data, out, "--maxiter", "1", "--for", "abaqus,ansys", "--no-polish")
    assert res["stop_reason"] == "maxiter" and res["status"] == "complete"
    for f, prefix in (("abaqus.inp", "**"), ("ansys.mac", "!")):
        first = next(ln for ln in (out / f).read_text().splitlines() if ln.startswith(prefix))
        assert first.startswith(f"{prefix} NOT CONVERGED: the search stopped at maxiter "
                                "before it converged")
    mat = json.loads((out / "material.json").read_text())
    assert mat["status"] == "not_converged" and "maxiter" in mat["status_note"]
    # vhfit export of these results says so too
    assert cli.main(["export", str(out / "results.json"), "--to", "lsdyna", "--out",
                     str(tmp_path / "x.k")]) == 0
    card = (tmp_path / "x.k").read_text().splitlines()
    assert card[0] == "*KEYWORD" and card[1].startswith("$ NOT CONVERGED: the search stopped")
    assert cli.main(["export", str(out / "results.json"), "--to", "json", "--out",
                     str(tmp_path / "x.json")]) == 0
    assert json.loads((tmp_path / "x.json").read_text())["status"] == "not_converged"
    ok = fit(data, tmp_path / "ok", "--for", "abaqus")
    assert ok["stop_reason"] != "maxiter"
    assert json.loads((tmp_path / "ok" / "material.json").read_text())["status"] == "complete"
    assert "CONVERGED" not in (tmp_path / "ok" / "abaqus.inp").read_text()


def test_a_card_that_fails_its_check_is_not_written(data, tmp_path, monkeypatch):
    """Without --formulation a card its solver would get wrong is no card: no file, the
    reason in the summary's first lines and in results.json (card_errors)."""
    import vhfit.export.check as chk

    monkeypatch.setattr(chk, "MARGIN_ABSOLUTE", -1.0)  # no card can pass now
    out = tmp_path / "o"
    res = fit(data, out, "--for", "ansys,lsdyna")
    assert not (out / "ansys.mac").exists() and not (out / "lsdyna.k").exists()
    assert res["cards"] == {"json": "material.json"}
    assert set(res["card_errors"]) == {"ansys", "lsdyna"}
    assert all(c["exceeds"] for c in res["card_check"].values())
    lines = (out / "summary.txt").read_text().splitlines()
    assert lines[0].startswith("RMSAPE ")  # the verdict, then each solver's card
    assert lines[1].startswith("ansys: no card: no card written: Ansys card: Ansys will show")
    assert lines[2].startswith("lsdyna: no card: no card written: LS-DYNA card: LS-DYNA will "
                               "show RMSAPE")


def test_for_lsdyna_and_abaqus_runs_two_fits_and_says_which_card_is_whose(data, tmp_path):
    out = tmp_path / "o"
    res = fit(data, out, "--for", "lsdyna", "--for", "abaqus")
    assert res["formulation"] == "hereditary"
    assert sorted(res["fits"]) == ["hereditary", "lsdyna"]
    assert res["fits"]["lsdyna"]["solvers"] == ["lsdyna"]
    assert res["fits"]["lsdyna"]["formulation"] == "lsdyna"
    assert res["card_fits"] == {"abaqus": "hereditary", "lsdyna": "lsdyna"}
    assert sorted(p.name for p in out.iterdir() if p.suffix in (".inp", ".k", ".mac")) == [
        "abaqus.inp", "lsdyna.k"]
    dyna = res["card_check"]["lsdyna"]
    assert dyna["fit_formulation"] == "lsdyna"
    assert dyna["fit_rmsape"] == pytest.approx(res["fits"]["lsdyna"]["rmsape"], rel=1e-6)
    assert dyna["rmsape"] <= 1.05 * dyna["fit_rmsape"] + 0.01 and not dyna["exceeds"]
    summary = (out / "summary.txt").read_text()
    assert "fits: 'hereditary' for abaqus" in summary and "'lsdyna' for lsdyna" in summary
    assert "== the fit in the 'lsdyna' formulation, for lsdyna ==" in summary
    assert "mooney_rivlin + 1 Prony term(s), 'lsdyna' formulation" in summary
    # the LS-DYNA constants are the lsdyna fit's
    cards = data_lines((out / "lsdyna.k").read_text(), "$")
    assert float(cards[4][20:40]) == pytest.approx(res["fits"]["lsdyna"]["params"]["C01"],
                                                     rel=1e-12)


def test_vhfit_check_reproduces_the_fits_card_check(default_run, data, capsys):
    out, res = default_run
    capsys.readouterr()
    assert cli.main(["check", str(out / "results.json"), "--data", *data, "--json"]) == 0
    got = json.loads(capsys.readouterr().out)["card_check"]
    assert set(got) == set(res["card_check"])
    for k, v in got.items():
        assert v["rmsape"] == pytest.approx(res["card_check"][k]["rmsape"], rel=1e-12)
    assert cli.main(["check", str(out / "results.json"), "--card",
                     str(out / "lsdyna.k")]) == 0
    text = capsys.readouterr().out
    assert "lsdyna.k" in text and "WARNING" not in text  # its own fit: it passes


def test_vhfit_check_flags_a_card_from_another_formulation(one_fit_run, capsys):
    out, _ = one_fit_run
    capsys.readouterr()
    assert cli.main(["check", str(out / "results.json"), "--card",
                     str(out / "lsdyna.k")]) == 0
    text = capsys.readouterr().out
    assert text.startswith("WARNING: LS-DYNA card") and "lsdyna.k" in text


# ================================================================== bad input
@pytest.mark.parametrize("flags, needle", [
    (["--for", "abaqus", "--model", "gent"], "--for abaqus"),
    (["--for", "lsdyna", "--model", "arruda_boyce"], "--for lsdyna"),
    (["--for", "radioss"], "--for 'radioss'"),
    (["--density", "0"], "--density 0"),
    (["--density=-1e-9"], "--density -1e-9"),
    (["--bulk-modulus", "0"], "--bulk-modulus 0"),
    (["--bulk-modulus=-5"], "--bulk-modulus -5"),
    (["--poisson", "0.5"], "--poisson 0.5"),
    (["--poisson=-1"], "--poisson -1"),
    (["--poisson", "0.3", "--bulk-modulus", "10"], "--bulk-modulus"),
    (["--formulation", "radioss"], "--formulation radioss"),
])
def test_bad_card_flags_are_refused_before_fitting(flags, needle, data, tmp_path,
                                                   monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "never"
    assert cli.main(["fit", *data, "--prony", "1", "--out", str(out), "-q", *flags]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("vhfit: error: ") and needle in err[0], err
    assert not out.exists()  # nothing written


def test_export_takes_the_card_flags(default_run, capsys):
    out, res = default_run
    capsys.readouterr()
    assert cli.main(["export", str(out / "results.json"), "--to", "abaqus", "--explicit",
                     "--bulk-modulus", "400", "--density", "1e-9"]) == 0
    rows = data_lines(capsys.readouterr().out, "**")
    assert rows[1:3] == ["*DENSITY", "1e-09,"]
    assert float(rows[4].split(",")[2]) == 2 / 400
    assert cli.main(["export", str(out / "results.json"), "--to", "lsdyna", "--explicit"]) == 2
    assert "--explicit" in capsys.readouterr().err


def test_export_takes_each_solvers_own_fit(data, tmp_path, capsys):
    out = tmp_path / "o"
    res = fit(data, out, "--for", "abaqus,lsdyna")
    capsys.readouterr()
    assert cli.main(["export", str(out / "results.json"), "--to", "lsdyna"]) == 0
    rows = data_lines(capsys.readouterr().out, "$")
    assert float(rows[4][20:40]) == pytest.approx(res["fits"]["lsdyna"]["params"]["C01"],
                                                  rel=1e-12)
    assert cli.main(["export", str(out / "results.json"), "--to", "abaqus"]) == 0
    rows = data_lines(capsys.readouterr().out, "**")
    assert float(rows[2].split(",")[1]) == res["params"]["C01"]


def test_formulation_flag_fits_once_in_that_law_for_every_card(data, tmp_path):
    """--formulation lsdyna: one fit in LS-DYNA's law serves every card; the LS-DYNA card
    reproduces it and the hereditary solvers' cards are flagged (the data are hereditary,
    so the lsdyna fit cannot be exact while a hereditary card of it must miss more)."""
    res = fit(data, tmp_path / "o", "--formulation", "lsdyna")
    assert res["formulation"] == "lsdyna"
    check = res["card_check"]
    assert set(check) == {"abaqus", "lsdyna", "ansys"}
    assert {c["fit_formulation"] for c in check.values()} == {"lsdyna"}
    assert check["lsdyna"]["rmsape"] == pytest.approx(res["rmsape"], rel=1e-3)
    assert not check["lsdyna"]["exceeds"]
    assert check["abaqus"]["exceeds"] and check["ansys"]["exceeds"]
