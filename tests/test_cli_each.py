"""``vhfit fit --each COLUMN``: one separate fit per value, each equal to the fit of that
value selected alone, and a table side by side."""

from __future__ import annotations

import csv
import json

import pytest

from vhfit import cli

#: Two materials in one file: "soft" has half the stiffness of "stiff"; two ramps each.
ROWS = "".join(
    f"{name},{rate:g},{e:.4f},{k * (3 * e + 4 * e * e):.6f}\n"
    for name, k in (("stiff", 1.0), ("soft", 0.5)) for rate in (0.01, 1.0)
    for e in (0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3))
FILE = "tissue,rate_1/s,strain,stress_MPa\n" + ROWS
FAST = ["--model", "neo_hooke", "--prony", "0", "--no-plot", "-q", "--popsize", "8",
        "--maxiter", "30", "--seed", "1"]


def _results(folder):
    return json.loads((folder / "results.json").read_text())


def test_each_value_is_fitted_alone_as_select_would(tmp_path, capsys):
    data = tmp_path / "two.csv"
    data.write_text(FILE)
    out = tmp_path / "each"
    assert cli.main(["fit", str(data), "--each", "tissue", "--out", str(out), *FAST]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["each.csv", "each.txt", "soft", "stiff"]
    for value in ("stiff", "soft"):
        alone = tmp_path / f"alone-{value}"
        assert cli.main(["fit", str(data), "--select", f"tissue={value}", "--out", str(alone),
                         *FAST]) == 0
        a, b = _results(out / value), _results(alone)
        assert a["params"] == b["params"] and a["rmsape"] == b["rmsape"]
    # neo-Hooke: C10 of the soft material is half that of the stiff (same shape of curve)
    c_stiff = _results(out / "stiff")["params"]["C10"]
    c_soft = _results(out / "soft")["params"]["C10"]
    assert c_soft == pytest.approx(0.5 * c_stiff, rel=1e-6)
    rows = list(csv.DictReader((out / "each.csv").open()))
    assert [r["tissue"] for r in rows] == ["stiff", "soft"]
    assert all(r["law"] == "neo_hooke" and r["exit"] == "0" for r in rows)
    for r in rows:
        assert float(r["rmsape"]) == pytest.approx(_results(out / r["folder"])["rmsape"],
                                                   rel=1e-3)
        summary = (out / r["folder"] / "summary.txt").read_text()
        assert summary.startswith(f"RMSAPE {r['rmsape']} %: {r['grade']}")
    text = (out / "each.txt").read_text()
    assert "stiff" in text and "soft" in text and "RMSAPE %" in text


def test_group_by_and_each_on_one_column_is_refused(tmp_path, capsys):
    data = tmp_path / "two.csv"
    data.write_text(FILE)
    code = cli.main(["fit", str(data), "--each", "tissue", "--group-by", "tissue", "--out",
                     str(tmp_path / "o"), *FAST])
    err = capsys.readouterr().err
    assert code == 2 and "give one" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


def test_a_column_with_one_value_is_refused(tmp_path, capsys):
    data = tmp_path / "one.csv"
    data.write_text("tissue,rate_1/s,strain,stress_MPa\n" + "".join(
        r for r in ROWS.splitlines(keepends=True) if r.startswith("stiff")))
    code = cli.main(["fit", str(data), "--each", "tissue", "--out", str(tmp_path / "o"),
                     *FAST])
    err = capsys.readouterr().err
    assert code == 2 and "1 value(s)" in err and "without --each" in err


def test_a_value_that_is_refused_is_named_and_the_others_are_fitted(tmp_path, capsys):
    # "flat" has zero stress: its fit is refused, the other value is still fitted
    flat = "".join(f"flat,{rate:g},{e:.4f},0\n" for rate in (0.01, 1.0)
                   for e in (0.0, 0.1, 0.2, 0.3))
    data = tmp_path / "mixed.csv"
    data.write_text(FILE + flat)
    out = tmp_path / "each"
    code = cli.main(["fit", str(data), "--each", "tissue", "--out", str(out), *FAST])
    err = capsys.readouterr().err
    assert code == 2
    assert "--each tissue=flat: " in err
    rows = {r["tissue"]: r for r in csv.DictReader((out / "each.csv").open())}
    assert rows["flat"]["exit"] == "2" and rows["flat"]["note"]
    assert rows["stiff"]["exit"] == "0" and float(rows["stiff"]["rmsape"]) >= 0
