"""Several laws compared: ``vhfit.compare`` and ``vhfit fit --model a,b``.

The errors of the table must be those of separate fits with the same seed (the fits
run in other processes, which must not change a bit); the ranking follows the stated
rule (lowest BIC among stable fits whose cards pass); bad input fits nothing.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import vhfit
from vhfit.cli._fit import model_list
from vhfit.comparison import RULE, Comparison, bic, rank, resolve_laws, table_lines
from vhfit.model import ViscoHyperelastic

TRUE = dict(C10=0.01, C01=0.005, G1=0.5, tau1=0.01)


def _curves():
    m = ViscoHyperelastic("mooney_rivlin", 1)
    eps = np.linspace(-0.02, -0.5, 12)
    return [vhfit.Curve(strain=eps, stress=m.stress(TRUE, strain=eps, strain_rate=r,
                                                   measure="engineering"),
                        strain_rate=r, name=f"r{-r:g}") for r in (-1.0, -100.0)]


@pytest.fixture(scope="module")
def compared():
    curves = _curves()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        comp = vhfit.compare(curves, ["neo_hooke", "mooney_rivlin"], n_prony=1, seed=3,
                             workers=2, maxiter=60)
    return curves, comp


def test_errors_equal_separate_fits_with_the_same_seed(compared):
    curves, comp = compared
    assert isinstance(comp, Comparison)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for law in ("neo_hooke", "mooney_rivlin"):
            alone = vhfit.calibrate(curves, hyperelastic=law, n_prony=1, seed=3, maxiter=60)
            assert comp.fits[law].rmsape == alone.rmsape  # bit for bit
            assert comp.fits[law].params == alone.params
            row = next(r for r in comp.rows if r["law"] == law)
            assert row["rmsape"] == alone.rmsape


def test_the_generating_law_wins_and_the_table_says_why(compared):
    curves, comp = compared
    # the data come from Mooney-Rivlin: it reaches ~0 error, neo-Hooke cannot
    assert comp.best == "mooney_rivlin"
    assert comp.calibration is comp.fits["mooney_rivlin"]
    top = comp.rows[0]
    assert top["rank"] == 1 and top["qualified"] and top["stable"] is True
    n = sum(np.size(c.target_stress) for c in curves)
    assert top["n_points"] == n
    assert top["n_constants"] == 4  # C10, C01, G1, tau1
    e = top["rmsape"] / 100
    assert top["bic"] == pytest.approx(n * math.log(e * e) + 4 * math.log(n), rel=1e-12)
    # one test mode: its error is the fit's (RMS of equal-sized curves' errors)
    assert top["per_mode"]["uniaxial"] == pytest.approx(
        math.sqrt(np.mean(np.square(comp.fits["mooney_rivlin"].per_curve_rmsape))))
    assert top["cards"]["abaqus"]["own"] and not top["cards"]["abaqus"]["exceeds"]
    assert top["cards"]["lsdyna"]["own"] is False  # another formulation: not counted
    text = comp.table()
    assert text.splitlines()[0].endswith("best = mooney_rivlin")
    assert RULE in text and "BIC = n ln((RMSAPE/100)^2) + k ln(n)" in text
    d = json.loads(json.dumps(comp.to_dict(), allow_nan=False))
    assert d["best"] == "mooney_rivlin" and [r["law"] for r in d["rows"]][0] == "mooney_rivlin"


def _row(law, b, *, stable=True, cards=True, error=None):
    return {"law": law, "rmsape": 1.0, "per_mode": {"uniaxial": 1.0}, "n_constants": 2,
            "n_points": 10, "bic": b, "stable": stable, "stability": "", "cards": {},
            "cards_pass": cards, "qualified": error is None and stable and cards is not False,
            "wall_time": 0.1, "n_prony": 1, "error": error}


def test_rank_prefers_stable_fits_with_passing_cards_then_lowest_bic():
    rows = [_row("unstable", -100.0, stable=False), _row("card_fails", -90.0, cards=False),
            _row("failed", math.inf, error="ValueError: x"), _row("ok_high", -10.0),
            _row("ok_low", -20.0)]
    ranked = rank(rows)
    assert [r["law"] for r in ranked] == ["ok_low", "ok_high", "unstable", "card_fails",
                                          "failed"]
    assert [r["rank"] for r in ranked] == [1, 2, 3, 4, 5]
    comp = Comparison(rows=ranked)
    assert comp.best == "ok_low"
    lines = table_lines(comp)
    assert any("failed: ValueError: x" in ln for ln in lines)
    # none qualifies: the lowest BIC of the finite fits
    assert rank([_row("a", -1.0, stable=False), _row("b", -5.0, stable=False)])[0]["law"] == "b"
    assert Comparison(rows=rank([_row("f", math.inf, error="E")])).best is None


def test_bic_pays_for_a_constant_only_with_a_large_enough_error_drop():
    n = 100
    # one more constant costs ln(100) = 4.6: it pays only if n ln(e^2) drops by more
    assert bic(2.0, n, 5) < bic(2.0, n, 4) + math.log(n) + 1e-9
    assert bic(1.99, n, 5) > bic(2.0, n, 4)  # 0.5 % lower error: not worth a constant
    assert bic(1.8, n, 5) < bic(2.0, n, 4)  # 10 % lower: worth it
    assert bic(float("nan"), n, 3) == math.inf and bic(1.0, 0, 3) == math.inf


def test_bad_input_is_refused_before_anything_is_fitted():
    curves = _curves()
    with pytest.raises(ValueError, match="unknown law 'gentt'"):
        vhfit.compare(curves, ["mooney_rivlin", "gentt"])
    with pytest.raises(ValueError, match="hyperelastic: not a keyword of compare"):
        vhfit.compare(curves, ["mooney_rivlin"], hyperelastic="yeoh")
    with pytest.raises(ValueError, match="checkpoint: not a keyword of compare"):
        vhfit.compare(curves, ["mooney_rivlin"], checkpoint="c.json")
    with pytest.raises(ValueError, match="popsize = 3"):
        vhfit.compare(curves, ["mooney_rivlin", "yeoh"], popsize=3)
    with pytest.raises(ValueError, match="workers = 0"):
        vhfit.compare(curves, ["mooney_rivlin"], workers=0)
    with pytest.raises(ValueError, match="unknown solver 'abacus'"):
        vhfit.compare(curves, ["mooney_rivlin"], solvers=["abacus"])
    assert resolve_laws("all") == list(vhfit.hyperelastic.available())
    assert resolve_laws(" yeoh , neo_hooke,yeoh") == ["yeoh", "neo_hooke"]
    with pytest.raises(ValueError, match="empty law name"):
        resolve_laws("yeoh,,neo_hooke")


# ------------------------------------------------------------------ command line
def _vhfit(*args, cwd):
    return subprocess.run([sys.executable, "-m", "vhfit", *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=600, env=dict(os.environ))


def _write(folder: Path) -> list[Path]:
    paths = []
    for c in _curves():
        p = folder / f"{c.name}.csv"
        p.write_text(f"# strain_rate: {float(c.strain_rate)!r}\nstrain,stress_MPa\n"
                     + "".join(f"{float(e)!r},{float(s)!r}\n" for e, s in zip(c.strain, c.stress)))
        paths.append(p)
    return paths


def test_cli_unknown_law_among_several_is_one_line_and_writes_nothing(tmp_path):
    files = _write(tmp_path)
    proc = _vhfit("fit", *files, "--model", "mooney_rivlin,gentt,yeoh", "--out", "o",
                  cwd=tmp_path)
    assert proc.returncode == 2, proc.stderr
    err = proc.stderr.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("vhfit: error: --model: unknown model 'gentt'")
    assert "Traceback" not in proc.stderr and proc.stdout == ""
    assert not (tmp_path / "o").exists()
    assert model_list("all") == list(vhfit.hyperelastic.available())
    assert model_list("yeoh") is None


def test_cli_writes_the_best_as_the_result_and_the_others_beside_it(tmp_path):
    files = _write(tmp_path)
    proc = _vhfit("fit", *files, "--model", "neo_hooke,mooney_rivlin", "--prony", "1",
                  "--seed", "3", "--maxiter", "60", "--no-plot", "--for", "abaqus",
                  "--out", "o", "--quiet", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    out = tmp_path / "o"
    res = json.loads((out / "results.json").read_text())
    assert res["hyperelastic"] == "mooney_rivlin"
    comp = res["comparison"]
    assert comp["best"] == "mooney_rivlin" and comp["rule"] == RULE
    assert comp["others"] == {"neo_hooke": "laws/neo_hooke/results.json"}
    rows = {r["law"]: r for r in comp["rows"]}
    assert rows["mooney_rivlin"]["rmsape"] == res["rmsape"]
    other = vhfit.Calibration.load(out / "laws" / "neo_hooke" / "results.json")
    assert rows["neo_hooke"]["rmsape"] == other.rmsape
    assert (out / "laws" / "neo_hooke" / "summary.txt").is_file()
    assert not (out / "laws" / "mooney_rivlin").exists()
    # the table's errors are those of separate fits with the same seed
    curves = vhfit.read_csv([str(f) for f in files])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for law in ("neo_hooke", "mooney_rivlin"):
            alone = vhfit.calibrate(curves, hyperelastic=law, n_prony=1, seed=3, maxiter=60)
            assert rows[law]["rmsape"] == alone.rmsape
    summary = (out / "summary.txt").read_text()
    assert "best = mooney_rivlin" in summary and "laws/LAW/" in summary
    assert summary.splitlines()[0] == vhfit.Calibration.load(out / "results.json").verdict()
    page = (out / "report.html").read_text()
    assert '<section id="laws"><h2>laws compared</h2>' in page
    assert "best: <b>mooney_rivlin</b>" in page and "<td>neo_hooke</td>" in page


# --------------------------------------------------------- interrupts (--model a,b)
def _compare_argv(files, out) -> list[str]:
    return ["fit", *map(str, files), "--model", "neo_hooke,mooney_rivlin", "--prony", "1",
            "--seed", "3", "--maxiter", "40", "--no-plot", "--for", "abaqus", "--out",
            str(out), "--quiet"]


def test_cli_compare_interrupted_while_fitting_leaves_the_folder_as_it_was(
        tmp_path, monkeypatch, capsys):
    """Ctrl-C during the laws' fits: exit 1, one line, and nothing written — a new folder
    is removed again, a --force'd one keeps exactly its files."""
    from vhfit import cli

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli._fit, "compare", interrupted)
    files = _write(tmp_path)
    assert cli.main(_compare_argv(files, tmp_path / "new")) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "interrupted while the laws were fitted" in err[0]
    assert "nothing written" in err[0] and "rerun" in err[0]
    assert not (tmp_path / "new").exists()
    old = tmp_path / "old"
    (old / "laws" / "yeoh").mkdir(parents=True)
    (old / "keep.txt").write_text("mine")
    (old / "laws" / "yeoh" / "results.json").write_text("{}")
    assert cli.main([*_compare_argv(files, old), "--force"]) == 1
    assert sorted(p.relative_to(old).as_posix() for p in old.rglob("*")) == [
        "keep.txt", "laws", "laws/yeoh", "laws/yeoh/results.json"]


def test_cli_compare_aborted_while_writing_the_laws_writes_nothing(tmp_path, monkeypatch,
                                                                    capsys):
    """An abort that comes through while the other laws' results are written (a third
    Ctrl-C): the half-written laws are removed, nothing else was written, exit 1."""
    from vhfit import cli

    real = vhfit.Calibration.save

    def save(self, path, *a, **k):
        real(self, path, *a, **k)
        if cli._fit.LAWS_PARTIAL in str(path):  # the first law's results are on disk
            raise KeyboardInterrupt

    monkeypatch.setattr(vhfit.Calibration, "save", save)
    files = _write(tmp_path)
    assert cli.main(_compare_argv(files, tmp_path / "o")) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "interrupted while the laws' results were written" in err[0]
    assert not (tmp_path / "o").exists()


def test_cli_compare_defers_ctrl_c_while_writing_the_laws(tmp_path, monkeypatch, capsys):
    """One Ctrl-C while the other laws' results are written is deferred, as while fit
    writes its outputs: laws/ is complete, no partial folder is left, and the run ends
    with every output (one formulation: no search left to stop)."""
    import signal

    from vhfit import cli

    real = vhfit.Calibration.save

    def save(self, path, *a, **k):
        if cli._fit.LAWS_PARTIAL in str(path):
            os.kill(os.getpid(), signal.SIGINT)  # handled at once, in this thread
        real(self, path, *a, **k)

    monkeypatch.setattr(vhfit.Calibration, "save", save)
    files = _write(tmp_path)
    out = tmp_path / "o"
    assert cli.main(_compare_argv(files, out)) == 0
    assert "finishing the output files" in capsys.readouterr().err
    assert not (out / cli._fit.LAWS_PARTIAL).exists()
    other = vhfit.Calibration.load(out / "laws" / "neo_hooke" / "results.json")
    assert other.model.hyperelastic.name == "neo_hooke"
    assert (out / "laws" / "neo_hooke" / "summary.txt").is_file()
    assert (out / "results.json").is_file() and (out / "abaqus.inp").is_file()
