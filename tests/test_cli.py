"""The command line: the real console script in subprocesses, plus in-process checks.

Subprocess tests cover what only a real process shows: the installed ``vhfit`` script,
exit codes, one-line errors without tracebacks, SIGINT and ``--resume``, plug-in
discovery through entry points, running without matplotlib. The many variants of
``export`` and ``simulate`` run in-process through :func:`vhfit.cli.main`, the same
code path minus the process start (about a second each on a loaded machine).
"""

from __future__ import annotations

import csv
import hashlib
import importlib.util
import io
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from _folders import listing

import vhfit
from vhfit import cli, datasets
from vhfit.cli._common import prepare_out
from vhfit.cli._simulate import count_prony, parse_params
from vhfit.model import ViscoHyperelastic

ROOT = Path(__file__).resolve().parents[1]


def _script() -> list[str]:
    """The installed console script (next to this Python), else ``python -m vhfit``."""
    exe = Path(sys.executable).parent / ("vhfit.exe" if os.name == "nt" else "vhfit")
    if exe.exists():
        return [str(exe)]
    found = shutil.which("vhfit")
    return [found] if found else [sys.executable, "-m", "vhfit"]


def run(*args, cwd, env=None, timeout=180) -> subprocess.CompletedProcess:
    e = dict(os.environ)
    e.update(env or {})
    return subprocess.run(_script() + [str(a) for a in args], cwd=cwd, env=e,
                          capture_output=True, text=True, timeout=timeout)


def assert_one_line_error(proc, code, *needles):
    assert proc.returncode == code, (proc.returncode, proc.stdout, proc.stderr)
    err = proc.stderr.strip().splitlines()
    assert "Traceback" not in proc.stderr, proc.stderr
    assert len(err) == 1 and err[0].startswith("vhfit: error: "), proc.stderr
    for n in needles:
        assert n in err[0], (n, err[0])


def write_noisy(folder: Path, noise=0.03, seed=1) -> list[Path]:
    """Three compression curves of a known material, with multiplicative noise."""
    m = ViscoHyperelastic("mooney_rivlin", 2)
    p = dict(C10=0.01, C01=0.005, G1=0.5, tau1=0.01, G2=0.2, tau2=1.0)
    rng = np.random.default_rng(seed)
    paths = []
    for r in (-1.0, -10.0, -100.0):
        eps = np.linspace(0, -0.5, 41)
        s = m.stress(p, strain=eps, strain_rate=r, measure="engineering")
        s[1:] *= 1 + noise * rng.standard_normal(40)
        path = folder / f"noisy_{-r:g}.csv"
        path.write_text(f"# strain_rate: {r}\nstrain,stress_MPa\n"
                        + "".join(f"{e:.6g},{v:.8g}\n" for e, v in zip(eps, s)))
        paths.append(path)
    return paths


@pytest.fixture(scope="module")
def noisy(tmp_path_factory) -> list[Path]:
    return write_noisy(tmp_path_factory.mktemp("noisy"))


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    """One real ``vhfit demo --out DIR`` run, shared by the tests that read its outputs,
    and the CPU seconds it took (the work done, which a loaded machine does not stretch
    the way it stretches wall time)."""
    cwd = tmp_path_factory.mktemp("demo")
    t0 = children_cpu_seconds()
    proc = run("demo", "--out", "out", cwd=cwd, timeout=600)
    return proc, cwd / "out", children_cpu_seconds() - t0


def children_cpu_seconds() -> float:
    """CPU seconds of this process's finished children (wall time where unknown)."""
    try:
        import resource
    except ImportError:  # pragma: no cover - not POSIX
        return time.perf_counter()
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


# ===================================================================== demo
def test_demo_end_to_end(demo):
    proc, out, seconds = demo
    assert proc.returncode == 0, proc.stderr
    assert seconds < 60  # CPU seconds (about 3 on an idle machine)
    # the parameter table with intervals and per-curve errors, labelled as synthetic
    for needle in ("95 % interval", "C10", "tau4", "per-curve RMSAPE", "synthetic",
                   "not experimental data", "abaqus.inp"):
        assert needle in proc.stdout, needle
    # plain progress lines on a non-terminal
    assert "generation" in proc.stderr and "\r" not in proc.stderr
    for f in ("results.json", "fitted_curves.csv", "abaqus.inp", "lsdyna.k", "ansys.mac",
              "material.json", "summary.txt"):
        assert (out / f).is_file(), f
    if importlib.util.find_spec("matplotlib"):
        assert (out / "fit.png").stat().st_size > 10_000
        assert (out / "history.png").is_file()
        assert _png_description(out / "fit.png") is None  # complete: not marked
    assert not list(out.glob("checkpoint.json*"))  # finished: no checkpoint left over
    res = json.loads((out / "results.json").read_text())
    assert res["status"] == "complete" and res["interrupted"] is False
    assert res["rmsape"] <= 0.01  # percent
    assert "synthetic" in res["data_label"] and res["data_label"] == datasets.SEBS_LABEL
    assert res["n_prony"] == 4 and res["seed"] == 0
    for k, v in datasets.SEBS_PARAMS.items():
        assert res["params"][k] == pytest.approx(v, rel=1e-3), k
    digest = hashlib.sha256(datasets.sebs_path().read_bytes()).hexdigest()
    assert res["inputs"][0]["sha256"] == digest
    assert {"vhfit", "numpy", "scipy", "numba", "python", "platform"} <= set(res["versions"])
    assert res["command"][:2] == ["vhfit", "demo"]


def test_demo_writes_every_card_from_its_solvers_own_fit(demo):
    """Each card passes its own check (the card's error within 1.05 x its fit's + 0.01
    point), and the summary's first lines name per solver the file and that error."""
    proc, out, _ = demo
    res = json.loads((out / "results.json").read_text())
    assert res["card_fits"] == {"abaqus": "hereditary", "lsdyna": "lsdyna",
                                "ansys": "hereditary"}
    assert res["fits"]["lsdyna"]["formulation"] == "lsdyna"
    for s, c in res["card_check"].items():
        fit = res["fits"][res["card_fits"][s]]
        assert c["fit_rmsape"] == pytest.approx(fit["rmsape"], rel=1e-9, abs=1e-12)
        assert c["rmsape"] <= 1.05 * c["fit_rmsape"] + 0.01 and not c["exceeds"], s
    lines = (out / "summary.txt").read_text().splitlines()
    assert proc.stdout.splitlines()[:5] == lines[:5]
    # top-down: the verdict, the data, the cards' own fits' warnings, then per solver its
    # card, error and grade
    assert lines[0].startswith(f"RMSAPE {res['rmsape']:.4g} %: good fit; worst curve ")
    assert lines[1].startswith("data: synthetic SEBS")
    own = [f"WARNING: {w}" for w in res["card_fit_warnings"]]
    assert all(w.startswith("LS-DYNA card's own fit ('lsdyna'): ")
               for w in res["card_fit_warnings"])
    k = 2 + len(own)
    assert lines[2:k] == own
    for ln, s in zip(lines[k:k + 3], ("abaqus", "ansys", "lsdyna")):
        assert ln.startswith(f"{s}: {res['cards'][s]}: ") and "will show RMSAPE" in ln
        assert ln.endswith("%): good fit")  # every card within 5 %
    assert lines[k + 3] == ""


def test_demo_refuses_a_non_empty_out(demo):
    proc, out, _ = demo
    again = run("demo", "--out", out, cwd=out.parent)
    assert_one_line_error(again, 2, str(out), "--force")


def test_default_out_is_a_fresh_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "vhfit-demo").mkdir()
    assert prepare_out(None, "vhfit-demo", force=False, resume=False) == Path("vhfit-demo")
    (tmp_path / "vhfit-demo" / "x").write_text("taken")
    assert prepare_out(None, "vhfit-demo", force=False, resume=False) == \
        Path("vhfit-demo-2")


def test_fitted_curves_csv(demo):
    _, out, _ = demo
    rows = list(csv.DictReader(line for line in (out / "fitted_curves.csv").open()
                               if not line.startswith("#")))
    names = {r["curve"] for r in rows}
    assert len(names) == 4
    pts = [r for r in rows if r["kind"] == "point"]
    assert len(pts) == 4 * 25
    for r in pts:
        d, m = float(r["stress_data"]), float(r["stress_model"])
        assert abs(m - d) <= 1e-3 * abs(d) + 1e-9
    assert sum(r["kind"] == "fine" for r in rows) >= 4 * 100


# =================================================================== export
@pytest.mark.parametrize("solver", ["abaqus", "lsdyna", "ansys", "json"])
def test_export_card_reimports_to_the_same_stresses(demo, solver, tmp_path, capsys):
    _, out, _ = demo
    assert cli.main(["export", str(out / "results.json"), "--to", solver]) == 0
    card = capsys.readouterr().out
    assert card.strip()
    from vhfit import export

    res = json.loads((out / "results.json").read_text())
    # each solver's card holds the constants of its own fit (LS-DYNA: the lsdyna fit's)
    fit = res["fits"][res["card_fits"][solver]] if solver in res["card_fits"] else res
    m1 = ViscoHyperelastic(res["hyperelastic"], fit["n_prony"])
    m2, p2 = getattr(export, f"from_{solver}")(card)
    eps = np.linspace(0.0, -0.6, 31)
    for rate in (-0.0018, -820.0):
        s1 = m1.stress(fit["params"], strain=eps, strain_rate=rate)
        s2 = m2.stress(p2, strain=eps, strain_rate=rate)
        assert np.max(np.abs(s2 - s1)) <= 1e-6 * np.max(np.abs(s1)), solver
    # the card written by the demo holds the same data (its comments add the card check)
    if solver != "json":
        def data(text):
            return [ln for ln in text.splitlines() if ln.strip()
                    and not ln.startswith(("**", "$", "!"))]

        assert data((out / cli.CARD_FILES[solver]).read_text()) == data(card)


def test_export_to_a_file(demo, tmp_path):
    _, out, _ = demo
    dest = tmp_path / "card.inp"
    assert cli.main(["export", str(out / "results.json"), "--to", "abaqus", "--out",
                     str(dest), "--name", "SEBS"]) == 0
    assert "NAME=SEBS" in dest.read_text()


def test_export_bad_inputs(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    other = tmp_path / "other.json"
    other.write_text('{"a": 1}')
    for argv, needle in [
        (["export", str(tmp_path / "missing.json"), "--to", "abaqus"], "missing.json"),
        (["export", str(bad), "--to", "abaqus"], "not valid JSON"),
        (["export", str(other), "--to", "abaqus"], "not a vhfit results file"),
        (["export", str(other), "--to", "nastran"], "invalid choice"),
    ]:
        assert cli.main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and needle in err[0], err


# ================================================================= simulate
def _read_sim(text: str) -> dict[str, np.ndarray]:
    rows = list(csv.DictReader(line for line in io.StringIO(text) if not line.startswith("#")))
    out: dict[str, list] = {}
    for r in rows:
        out.setdefault(r["curve"], []).append([float(r["time"]), float(r["strain"]),
                                               float(r["stress"])])
    return {k: np.array(v) for k, v in out.items()}


def test_simulate_from_results(demo, tmp_path):
    _, out, _ = demo
    dest = tmp_path / "sim.csv"
    assert cli.main(["simulate", "--results", str(out / "results.json"), "--rate", "-100",
                     "--rate", "-1000", "--strain-max", "-0.5", "--points", "11",
                     "--out", str(dest)]) == 0
    sims = _read_sim(dest.read_text())
    res = json.loads((out / "results.json").read_text())
    m = ViscoHyperelastic(res["hyperelastic"], res["n_prony"])
    for rate in (-100.0, -1000.0):
        t, e, s = sims[f"rate {rate:g} 1/s"].T
        assert e[0] == 0 and e[-1] == pytest.approx(-0.5) and len(e) == 11
        ref = m.stress(res["params"], strain=e, strain_rate=rate, measure="engineering")
        np.testing.assert_allclose(s, ref, rtol=1e-8, atol=1e-14)


def test_simulate_from_parameters_and_history(tmp_path, capsys):
    hist = tmp_path / "cycle.csv"
    hist.write_text("time_s,strain\n0,0\n1,-0.3\n2,0\n")
    assert cli.main(["simulate", "--model", "mooney_rivlin", "--param", "C10=0.1,C01=0.05",
                     "--param", "G1=1", "--param", "tau1=0.5", "--rate", "-10",
                     "--history", str(hist), "--measure", "true"]) == 0
    sims = _read_sim(capsys.readouterr().out)
    m = ViscoHyperelastic("mooney_rivlin", 1)
    p = dict(C10=0.1, C01=0.05, G1=1.0, tau1=0.5)
    t, e, s = sims["rate -10 1/s"].T
    np.testing.assert_allclose(s, m.stress(p, strain=e, strain_rate=-10.0), rtol=1e-8)
    t, e, s = sims["cycle.csv"].T
    np.testing.assert_allclose(t, [0, 1, 2])
    np.testing.assert_allclose(s, m.stress(p, strain=[0, -0.3, 0], time=[0, 1, 2]),
                               rtol=1e-8, atol=1e-12)


@pytest.mark.parametrize("argv, needle", [
    (["simulate", "--rate", "-1"], "needs a material"),
    (["simulate", "--model", "mooney_rivlin", "--param", "C10=0.1,C01=0", "--param", "G1=1",
      "--rate", "-1"], "tau1"),
    (["simulate", "--model", "mooney_rivlin", "--param", "C10=0.1,C01=0"], "give the loading"),
    (["simulate", "--model", "mooney_rivlin", "--param", "C10=0.1,C01=0", "--rate", "-1",
      "--strain-max", "0.5"], "opposite signs"),
    (["simulate", "--model", "mooney_rivlin", "--param", "C10=0.1,C01=0", "--rate", "-1",
      "--strain-max", "0"], "opposite signs"),  # a ramp to ε = 0 has no strain to simulate
    (["simulate", "--model", "mooney_rivlin", "--param", "C10=abc", "--rate", "-1"],
     "not a number"),
    (["simulate", "--model", "nosuchmodel", "--param", "a=1", "--rate", "-1"], "unknown model"),
    (["simulate", "--model", "mooney_rivlin", "--param", "C10=0.1", "--rate", "-1"],
     "missing C01 (give --param C01=VALUE)"),
    (["simulate", "--model", "neo_hooke", "--param", "C10=0.1,D1=3", "--rate", "-1"],
     "D1 is not among them (drop --param D1)"),
])
def test_simulate_bad_input(argv, needle, capsys):
    assert cli.main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0], err


# ====================================================== fit: bad input (real script)
@pytest.mark.parametrize("case", ["missing", "garbage", "bad-prony", "unknown-model"])
def test_fit_bad_input_is_one_line_and_exit_2(case, tmp_path, noisy):
    garbage = tmp_path / "garbage.csv"
    garbage.write_text("strain,stress\n0,0\n-0.1,abc\n")
    argv, needles = {
        "missing": (["fit", tmp_path / "nope.csv"], ["nope.csv"]),
        "garbage": (["fit", garbage, "--rate", "-1"], ["garbage.csv"]),
        "bad-prony": (["fit", noisy[0], "--prony", "x"], ["--prony", "auto"]),
        "unknown-model": (["fit", noisy[0], "--model", "nosuch", "--out", tmp_path / "o"],
                          ["nosuch", "mooney_rivlin"]),
    }[case]
    assert_one_line_error(run(*argv, cwd=tmp_path), 2, *needles)


@pytest.mark.parametrize("argv, needle", [
    (["fit", "{f}", "--frobnicate"], "--frobnicate"),
    (["fit", "{f}", "--strategy", "nosuch", "--out", "o"], "semifree"),
    (["fit", "{f}", "--popsize", "0"], "--popsize"),
    (["fit", "{f}", "--rate", "-1", "--rate", "-2", "--out", "o"], "one rate for all files"),
    (["fit", "{f}", "--force", "--resume"], "contradict"),
    (["fit", "{f}", "--trim-time", "5", "--out", "o"], "LOW:HIGH"),
    (["fit", "{f}", "--trim-strain", "-0.1:-0.4", "--out", "o"], "LOW must be below HIGH"),
    (["fit", "{f}", "--trim-time", ":1", "--trim-time", ":2", "--out", "o"],
     "one window for all files"),
    (["fit", "{f}", "--trim-strain", "0.1:", "--out", "o"], "keeps 0 sample(s)"),
    (["fit", "{f}", "--resume", "--out", "nowhere"], "does not exist"),
    (["nosuchcommand"], "invalid choice"),
])
def test_fit_bad_flags_in_process(argv, needle, noisy, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert cli.main([a.format(f=noisy[0]) for a in argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("vhfit: error: ") and needle in err[0], err


def test_fit_refusals_name_the_file_and_the_cli_flag(tmp_path, monkeypatch, capsys):
    """All-zero stress and Prony terms without rates: the file and the flag as typed."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "ok.csv").write_text("strain,stress_MPa\n0,0\n0.1,0.1\n0.2,0.25\n0.3,0.4\n")
    (tmp_path / "flat.csv").write_text("strain,stress_MPa\n0,0\n0.1,0\n0.2,0\n0.3,0\n")
    for argv, needles in (
            (["ok.csv", "flat.csv"], ["'flat'", "leave its file out"]),
            (["ok.csv", "--prony", "1"], ["--prony 0"])):
        assert cli.main(["fit", *argv, "--model", "neo_hooke", "--out", "o", "--force",
                         "--no-plot", "-q"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("vhfit: error: "), err
        for n in needles:
            assert n in err[0], (n, err[0])
        # the only Python keyword left is marked as such
        assert "n_prony=0 (command line" in err[0] or "n_prony=" not in err[0]
        assert "from Python, use objective=" in err[0] or "objective=" not in err[0]


def test_fit_trims_each_file_by_its_own_window(noisy, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    # one window per file, in file order; ':' leaves a file whole
    argv = ["fit", *map(str, noisy), "--trim-strain", "-0.3:", "--trim-strain", ":",
            "--trim-strain", "-0.4:-0.1", "--points", "5", "--prony", "1", "--no-plot",
            "-q", "--out", "o"]
    assert cli.main(argv) == 0
    text = (tmp_path / "o" / "fitted_curves.csv").read_text()
    rows = csv.DictReader(io.StringIO("".join(
        line for line in text.splitlines(keepends=True) if not line.startswith("#"))))
    by: dict[str, list[float]] = {}
    for r in rows:
        if r["kind"] == "point":
            by.setdefault(r["curve"], []).append(float(r["strain"]))
    lo_hi = {name: (min(v), max(v)) for name, v in by.items()}
    assert len(lo_hi) == 3
    a, b, c = (lo_hi[k] for k in sorted(lo_hi, key=lambda k: abs(float(k.split("_")[1]))))
    assert a[0] >= -0.3 - 1e-12  # -0.3: (signed: compression runs to -0.5)
    assert b[0] == pytest.approx(-0.5)  # untrimmed
    assert c[0] >= -0.4 - 1e-12 and c[1] <= -0.1 + 1e-12


def test_debug_shows_the_traceback(tmp_path):
    proc = run("fit", tmp_path / "nope.csv", "--debug", cwd=tmp_path)
    assert proc.returncode != 0 and "Traceback" in proc.stderr


def test_python_m_vhfit(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "vhfit", "--version"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0 and proc.stdout.strip() == f"vhfit {vhfit.__version__}"


PROGRAM = r"""
import atexit, sys
from vhfit.cli import _main, program
atexit.register(print, "registered before the program")
given = _main.main


def main():  # the command registers an exit handler, as multiprocessing's pools do
    atexit.register(print, "registered by the command")  # left in the buffer
    return given(sys.argv[1:])


_main.main = main
program()
"""


def test_the_program_exits_with_the_code_after_the_exit_handlers_of_its_run(tmp_path):
    """``vhfit`` ends without the interpreter's teardown: the exit handlers registered
    during the run still run, the code and every byte written reach the caller; one
    registered before the program started is passed over (the teardown is skipped)."""
    # standard output buffered, as it is in a pipe unless PYTHONUNBUFFERED says otherwise
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    ok = subprocess.run([sys.executable, "-c", PROGRAM, "simulate", "--model", "neo_hooke",
                         "--param", "C10=0.1", "--rate", "0.1", "--points", "3000"],
                        cwd=tmp_path, capture_output=True, text=True, timeout=300, env=env)
    assert ok.returncode == 0, ok.stderr
    lines = ok.stdout.splitlines()
    assert lines[-1] == "registered by the command"
    assert "registered before the program" not in ok.stdout
    # all 3000 rows of the ramp, past any pipe buffer: flushed before the exit
    rows = [ln for ln in lines[:-1] if ln.startswith("rate 0.1 1/s,")]
    assert len(rows) == 3000, len(rows)
    bad = subprocess.run([sys.executable, "-c", PROGRAM, "export", "nope.json", "--to",
                          "json"], cwd=tmp_path, capture_output=True, text=True, timeout=300,
                         env=env)
    assert bad.returncode == 2 and bad.stderr.startswith("vhfit: error: "), bad.stderr
    assert bad.stdout.splitlines() == ["registered by the command"]


# ============================================================ fit in-process
def test_fit_writes_everything(noisy, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    code = cli.main(["fit", *map(str, noisy), "--prony", "2", "--seed", "1", "--quiet",
                     "--no-plot", "--out", "res"])
    assert code == 0
    out = capsys.readouterr().out
    assert "95 % interval" in out and "noisy_100" in out
    res = json.loads((tmp_path / "res" / "results.json").read_text())
    assert [i["sha256"] for i in res["inputs"]] == [
        hashlib.sha256(p.read_bytes()).hexdigest() for p in noisy
    ]
    assert res["options"]["seed"] == 1 and res["status"] == "complete"
    assert res["rmsape"] < 5
    assert (tmp_path / "res" / "abaqus.inp").is_file()
    # "--resume" after a finished fit: nothing to resume
    assert cli.main(["fit", *map(str, noisy), "--out", "res", "--resume", "-q"]) == 2
    assert "no checkpoint" in capsys.readouterr().err


def _png_description(path: Path) -> str | None:
    """The ``Description`` text chunk of a PNG file (None if it has none)."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    i = 8
    while i < len(data):
        n = int.from_bytes(data[i:i + 4], "big")
        kind, body = data[i + 4:i + 8], data[i + 8:i + 8 + n]
        if kind == b"tEXt" and body.startswith(b"Description\x00"):
            return body.split(b"\x00", 1)[1].decode("latin-1")
        i += 12 + n
    return None


@pytest.mark.skipif(not importlib.util.find_spec("matplotlib"), reason="needs matplotlib")
def test_plots_of_an_unfinished_fit_say_so(noisy, tmp_path, ctrl_c_in_fit):
    """Every PNG of a fit cut by Ctrl-C says INTERRUPTED (a red line above the figure and
    the PNG's Description), as its cards do; resumed to a generation cap, NOT CONVERGED."""
    out = tmp_path / "o"
    argv = ["fit", *map(str, noisy), "--prony", "1", "--maxiter", "8", "--target", "0",
            "--for", "abaqus", "--out", str(out), "-q", "--checkpoint-every", "0.001"]
    with ctrl_c_in_fit(3):
        assert cli.main(argv) == 1
    pngs = sorted(out.glob("*.png"))
    assert {p.name for p in pngs} >= {"fit.png", "history.png"}
    card = (out / "abaqus.inp").read_text()
    for p in pngs:
        d = _png_description(p)
        assert d == "INTERRUPTED: written by an interrupted vhfit fit (best constants so far, " \
                    "not converged)", (p.name, d)
        assert d in card.replace("\n** ", " ")  # the card's own words
    assert cli.main(argv + ["--resume"]) == 0
    assert json.loads((out / "results.json").read_text())["stop_reason"] == "maxiter"
    for p in sorted(out.glob("*.png")):
        assert _png_description(p) == ("NOT CONVERGED: the search stopped at maxiter before "
                                       "it converged"), p.name


# ============================================ Ctrl-C and --resume (real script)
@pytest.mark.skipif(os.name == "nt", reason="POSIX signals")
def test_interrupt_writes_outputs_and_resume_matches_an_uninterrupted_run(noisy, tmp_path):
    args = [*noisy, "--prony", "2", "--method", "full", "--maxiter", "600", "--target", "0",
            "--checkpoint-every", "0.2", "--no-plot", "-q"]
    # the reference: uninterrupted, in-process (the same code path)
    assert cli.main(["fit", *map(str, args), "--out", str(tmp_path / "ref")]) == 0
    ref = json.loads((tmp_path / "ref" / "results.json").read_text())

    out = tmp_path / "run"
    proc = subprocess.Popen(_script() + ["fit", *map(str, args), "--out", str(out)],
                            cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    ck = out / "checkpoint.json"

    def generations():  # the checkpoint is replaced atomically: always whole
        return json.loads(ck.read_text())["solver"]["generations"] if ck.exists() else 0

    # interrupt once the search has made progress since its first checkpoint: two
    # checkpoints seen (events, not a sleep), and 600 generations are far from done
    deadline = time.monotonic() + 120
    first = None
    while first is None or generations() <= first:
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline
        if first is None and ck.exists():
            first = generations()
        time.sleep(0.05)
    assert proc.poll() is None, "the fit ended before it could be interrupted"
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 1, stderr
    assert "Traceback" not in stderr
    assert "--resume" in stderr and "interrupted" in stderr
    res = json.loads((out / "results.json").read_text())
    assert res["status"] == "interrupted" and res["interrupted"] is True
    assert res["stop_reason"] == "interrupted" and 0 < res["nit"] < 600
    summary = (out / "summary.txt").read_text()
    assert "INTERRUPTED" in summary
    assert '<p class="interrupted">' in (out / "report.html").read_text(encoding="utf-8")
    # every file says so: the cards in their first comment line, material.json in a field
    for f, prefix in (("abaqus.inp", "**"), ("ansys.mac", "!")):
        first = next(ln for ln in (out / f).read_text().splitlines() if ln.startswith(prefix))
        assert first.startswith(f"{prefix} INTERRUPTED: written by an interrupted vhfit fit")
    mat = json.loads((out / "material.json").read_text())
    assert mat["status"] == "interrupted" and "INTERRUPTED" in mat["status_note"]
    head = [ln for ln in (out / "fitted_curves.csv").read_text().splitlines()
            if ln.startswith("# model:")]
    assert head[0].endswith("; INTERRUPTED")
    # the LS-DYNA fit, after the interrupted one, never ran: no card, and the summary's
    # first lines say so
    assert not (out / "lsdyna.k").exists()
    assert "lsdyna: no card: the 'lsdyna' fit was not run (interrupted)" in summary.split(
        "\n\n")[0]
    assert res["card_errors"]["lsdyna"] == "the 'lsdyna' fit was not run (interrupted)"
    assert set(res["cards"]) == {"abaqus", "ansys", "json"}
    assert cli.main(["export", str(out / "results.json"), "--to", "ansys", "--out",
                     str(tmp_path / "again.mac")]) == 0  # vhfit export says so as well
    assert (tmp_path / "again.mac").read_text().startswith("! INTERRUPTED: written by an "
                                                           "interrupted vhfit fit")
    assert (out / "checkpoint.json").is_file()

    again = run("fit", *args, "--out", out, "--resume", cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    fin = json.loads((out / "results.json").read_text())
    assert fin["status"] == "complete" and fin["nit"] == ref["nit"]
    assert fin["history"]["best"] == ref["history"]["best"]  # the same search, bit for bit
    assert fin["params"] == ref["params"]
    assert fin["fits"]["lsdyna"]["params"] == ref["fits"]["lsdyna"]["params"]
    assert (out / "lsdyna.k").is_file() and "INTERRUPTED" not in (out / "abaqus.inp").read_text()
    # --maxiter 600 and --target 0: the resumed search ends at its generation cap, which
    # every card and material.json say (not converged), no longer "interrupted"
    assert fin["stop_reason"] == "maxiter"
    assert json.loads((out / "material.json").read_text())["status"] == "not_converged"
    assert (out / "abaqus.inp").read_text().startswith("** NOT CONVERGED: the search stopped "
                                                         "at maxiter")
    assert not any(out.glob("checkpoint.json*"))


# ================================================================== models
def test_models_lists_models_and_strategies(capsys):
    assert cli.main(["models"]) == 0
    out = capsys.readouterr().out
    assert "mooney_rivlin" in out and "C10 [MPa]" in out and "ogden" in out
    assert "semifree" in out and "free" in out
    assert cli.main(["models", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert {m["name"] for m in data["models"]} >= {"mooney_rivlin", "neo_hooke", "yeoh"}
    assert data["tau_strategies"][:3] == ["free", "semifree", "fixed"]
    # the formulations and which solver integrates which (abaqus, ansys: hereditary)
    forms = {f["name"]: f["solvers"] for f in data["formulations"]}
    assert forms["hereditary"] == ["abaqus", "ansys"] and forms["lsdyna"] == ["lsdyna"]
    assert forms["lsdyna_deviatoric"] == []


def test_models_discovers_entry_point_plugins(tmp_path):
    site = tmp_path / "site"
    (site / "fakeplug-1.0.dist-info").mkdir(parents=True)
    (site / "fakeplug-1.0.dist-info" / "METADATA").write_text(
        "Metadata-Version: 2.1\nName: fakeplug\nVersion: 1.0\n")
    (site / "fakeplug-1.0.dist-info" / "entry_points.txt").write_text(
        "[vhfit.models]\ngent_plugin = fakeplug_models\nbroken = fakeplug_missing\n")
    (site / "fakeplug_models.py").write_text(textwrap.dedent("""
        import numpy as np
        import vhfit

        @vhfit.hyperelastic.register("gent_plugin", units=("MPa", "-"),
                                     example=(0.1, 10.0))
        def gent_plugin(I1, I2, mu, Jm):
            "Gent: W = -mu Jm / 2 ln(1 - (I1 - 3) / Jm)"
            return -mu * Jm / 2 * np.log(1 - (I1 - 3) / Jm)
    """))
    env = {"PYTHONPATH": os.pathsep.join([str(site), os.environ.get("PYTHONPATH", "")])}
    proc = run("models", cwd=tmp_path, env=env)
    assert proc.returncode == 0, proc.stderr
    assert "gent_plugin" in proc.stdout and "mu [MPa], Jm [-]" in proc.stdout
    assert "broken" in proc.stdout and "error" in proc.stdout  # reported, not fatal
    # a command resolving the model name loads the plug-in too
    proc = run("simulate", "--model", "gent_plugin", "--param", "mu=0.1,Jm=10", "--rate",
               "-1", "--points", "3", cwd=tmp_path, env=env)
    assert proc.returncode == 0, proc.stderr
    assert "gent_plugin" in proc.stdout


# ========================================================= without matplotlib
def test_fit_without_matplotlib_says_how_to_get_plots(noisy, tmp_path):
    fake = tmp_path / "nompl" / "matplotlib"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text("raise ImportError('matplotlib hidden by the test')\n")
    env = {"PYTHONPATH": os.pathsep.join([str(fake.parent), os.environ.get("PYTHONPATH", "")])}
    proc = run("fit", *noisy, "--prony", "1", "--out", tmp_path / "o", "-q", cwd=tmp_path,
               env=env)
    assert proc.returncode == 0, proc.stderr
    assert "pip install 'vhfit[plot]'" in proc.stdout
    assert (tmp_path / "o" / "results.json").is_file()
    assert (tmp_path / "o" / "abaqus.inp").is_file()
    assert not list((tmp_path / "o").glob("*.png"))


# ======================================================= progress, helpers
class _Stream(io.StringIO):
    def __init__(self, tty):
        super().__init__()
        self._tty = tty

    def isatty(self):
        return self._tty


def test_progress_updates_one_line_on_a_terminal():
    s = _Stream(True)
    p = cli.Progress(s)
    for g in range(1, 4):
        p({"generation": g, "best": 1.0 / g, "mean": 2.0 / g, "elapsed": 0.2 * g})
        p.last_print = -1e9  # do not wait between updates
    p.close()
    text = s.getvalue()
    assert text.count("\r") >= 3 and text.count("\n") == 1
    assert "generation     3" in text and "best 0.3333 %" in text and "elapsed" in text


def test_progress_prints_plain_periodic_lines_otherwise():
    s = _Stream(False)
    p = cli.Progress(s, every=3600, scan=True)
    for g in (1, 2, 3, 1, 2):  # the generation count restarts: next N of the scan
        p({"generation": g, "best": 1.0, "mean": 2.0, "elapsed": 0.1})
    p.close()
    lines = s.getvalue().splitlines()
    assert "\r" not in s.getvalue()
    assert lines[0].startswith("N=1  generation     1") and lines[-1].startswith("N=2")
    assert len(lines) == 2


def test_progress_shows_two_n_fitted_side_by_side():
    """An order scan on two processes reports N = 2 and N = 3 in turn: the line shows
    both, in the order of N; once one stops reporting, the other alone."""
    s = _Stream(False)
    p = cli.Progress(s, every=0.0, scan=True)
    for g in (1, 2):
        p({"generation": g, "best": 9.0, "mean": 9.5, "elapsed": 0.1, "n_prony": 3})
        p({"generation": g + 10, "best": 5.0, "mean": 6.0, "elapsed": 0.2, "n_prony": 2})
    lines = s.getvalue().splitlines()
    assert lines[-1] == ("N=2  generation    12  best 5 %  |  N=3  generation     2  best 9 %"
                         "  elapsed 0.2 s")
    p.latest[2] = (time.perf_counter() - 2 * p.RECENT, p.latest[2][1])  # N = 2 ended
    p({"generation": 3, "best": 8.0, "mean": 8.5, "elapsed": 0.3, "n_prony": 3})
    assert s.getvalue().splitlines()[-1].startswith("N=3  generation     3  best 8 %  mean")


def test_parse_helpers():
    assert parse_params("C10=0.1, C01=2e-3") == {"C10": 0.1, "C01": 0.002}
    assert count_prony({"C10": 1, "G1": 1, "tau1": 1, "G2": 2, "tau2": 2}) == 2
    with pytest.raises(cli.UsageError, match="tau2"):
        count_prony({"G1": 1, "tau1": 1, "G2": 2})
    with pytest.raises(cli.UsageError, match="NAME=VALUE"):
        parse_params("C10")


# ================================================= entry points, exit codes, plug-ins
def test_exit_codes_are_the_documented_ones(tmp_path, capsys):
    """docs/cli.md: 0 success, 1 fit failed or interrupted, 2 bad input."""
    assert (cli.EXIT_OK, cli.EXIT_FAILED, cli.EXIT_USAGE) == (0, 1, 2)
    assert cli.main(["models"]) == cli.EXIT_OK
    assert cli.main(["export", str(tmp_path / "none.json"), "--to", "abaqus"]) == cli.EXIT_USAGE
    assert capsys.readouterr().err.startswith("vhfit: error: ")


def test_a_failing_fit_is_exit_1_and_one_line(noisy, tmp_path, monkeypatch, capsys):
    def broken(*args, **kwargs):
        raise RuntimeError("solver exploded\nsecond line")

    monkeypatch.setattr(vhfit.cli._fit, "calibrate", broken)
    argv = ["fit", *map(str, noisy), "--out", str(tmp_path / "out"), "--no-plot", "-q"]
    capsys.readouterr()
    assert cli.main(argv) == cli.EXIT_FAILED
    err = [x for x in capsys.readouterr().err.splitlines() if x.strip()]
    assert len(err) == 1 and err[0].startswith("vhfit: error: the fit failed: solver exploded")
    with pytest.raises(cli.FitFailed, match="the fit failed: solver exploded"):  # --debug
        cli.main(argv + ["--debug", "--force"])


def test_build_parser_reads_the_fit_command():
    args = cli.build_parser().parse_args(
        ["fit", "a.csv", "b.csv", "--prony", "3", "--model", "ogden2", "--seed", "7"])
    assert args.command == "fit" and args.curves == ["a.csv", "b.csv"]
    assert args.prony == 3 and args.model == "ogden2" and args.seed == 7
    assert args.func.__name__ == "cmd_fit"  # resolved to vhfit.cli._fit.cmd_fit when it runs
    export = cli.build_parser().parse_args(["export", "r.json", "--to", "lsdyna"])
    assert (export.command, export.to) == ("export", "lsdyna")
    with pytest.raises((SystemExit, cli.UsageError)):
        cli.build_parser().parse_args(["export", "r.json", "--to", "nastran"])


def test_load_plugins_registers_the_models_of_the_entry_point_group(tmp_path, monkeypatch):
    assert cli.PLUGIN_GROUP == "vhfit.models"  # docs/cli.md: the entry-point group
    dist = tmp_path / "inproc_plug-1.0.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: inproc_plug\nVersion: 1.0\n")
    (dist / "entry_points.txt").write_text(
        f"[{cli.PLUGIN_GROUP}]\nsquare = inproc_plug_models:register_all\n"
        "missing = inproc_plug_nowhere\n[other.group]\nignored = inproc_plug_nowhere\n")
    (tmp_path / "inproc_plug_models.py").write_text(textwrap.dedent("""
        import vhfit

        def register_all():
            @vhfit.hyperelastic.register("_test_inproc_square", example=(1.0,))
            def square(I1, I2, c):
                return c * (I1 - 3) ** 2
    """))
    monkeypatch.syspath_prepend(str(tmp_path))
    try:
        found = {p["name"]: p for p in cli.load_plugins()}
        assert found["square"]["models"] == ["_test_inproc_square"]
        assert found["square"]["error"] is None
        assert found["square"]["distribution"] == "inproc_plug"
        assert "ModuleNotFoundError" in found["missing"]["error"]
        assert "ignored" not in found  # another group
        assert "_test_inproc_square" in vhfit.hyperelastic.available()
        vhfit.hyperelastic.unregister("_test_inproc_square")
        with pytest.raises(ModuleNotFoundError):  # strict: the broken plug-in raises
            cli.load_plugins(strict=True)
    finally:
        if "_test_inproc_square" in vhfit.hyperelastic.available():
            vhfit.hyperelastic.unregister("_test_inproc_square")


# ============================================= bad input leaves --out as it was (exit 2)
def write_locking(folder: Path) -> Path:
    """Uniaxial tension of a neo-Hooke solid to λ = 12 (I1 − 3 = 141): past every Jm of
    Gent's default search range (0.1, 100), so no Gent individual is finite within it when
    it is given (:data:`GENT_BOUNDS`: a user's bounds are not widened, the automatic ones
    are)."""
    eps = np.linspace(0.05, 11.0, 20)
    s = ViscoHyperelastic("neo_hooke", 0).stress(dict(C10=0.005), strain=eps, strain_rate=0.1,
                                                 measure="engineering")
    path = folder / "locking.csv"
    path.write_text("strain,stress_MPa\n" + "".join(f"{float(e)!r},{float(v)!r}\n"
                                                    for e, v in zip(eps, s)))
    return path


#: Gent's default Jm range given as the user's: kept as it is
GENT_BOUNDS = ["--model", "gent", "--bounds", "Jm=0.1:100"]

GENT_LOCKED = (r"the gent fit found no parameter set with a finite error \(\d+ evaluated, "
               r"stop: no finite error in 50 generations\): its search bounds \(Jm <= 100\) "
               r"leave the gent law undefined at the data's deformation everywhere, but "
               r"Jm = 1000 is not; widen them, e\.g\. --bounds Jm=0\.1:1000")


@pytest.mark.parametrize("before", ["absent", "empty", "files"])
@pytest.mark.parametrize("case, extra, pattern", [
    ("typo", ["--model", "mooney_rivlinn"],
     r"unknown model 'mooney_rivlinn': choose one of .*mooney_rivlin.* \(see 'vhfit models'\)"),
    ("max-prony", ["--prony", "auto", "--max-prony", "0"],
     r"--max-prony 0: give a whole number >= 1 \(the largest N that --prony auto tries\)"),
    ("strategy", ["--strategy", "loose"], r"--strategy 'loose': choose one of free, .*"),
    ("bad-file", ["--model", "neo_hooke"], r".*garbage\.csv.*"),
    ("refused-by-calibrate", ["--g-inf-min", "1"], r"g_inf_min = 1\.0: .*"),
    ("gent-locked", GENT_BOUNDS, GENT_LOCKED),
], ids=lambda v: v if isinstance(v, str) and " " not in v and len(v) < 25 else "")
def test_fit_bad_input_leaves_the_out_folder_as_it_was(case, extra, pattern, before, noisy,
                                                       tmp_path, monkeypatch, capsys):
    """Exit 2, one line, and --out exactly as before: not created, or (with --force) its
    files untouched — a checkpoint of another fit included — and none added."""
    monkeypatch.chdir(tmp_path)
    garbage = tmp_path / "garbage.csv"
    garbage.write_text("strain,stress\n0,0\n-0.1,abc\n")
    data = {"bad-file": garbage, "gent-locked": write_locking(tmp_path)}.get(case, noisy[0])
    out = tmp_path / "out"
    force = []
    if before != "absent":
        out.mkdir()
        force = ["--force"]
    if before == "files":
        (out / "notes.txt").write_text("mine\n")
        (out / "checkpoint.json").write_text('{"format": "another fit"}')
    was = listing(out)
    capsys.readouterr()
    code = cli.main(["fit", str(data), "--rate", "0.1", "--out", str(out), "--no-plot",
                     "--checkpoint-every", "0.001", *extra, *force])
    err = [x for x in capsys.readouterr().err.splitlines() if x.startswith("vhfit: error")]
    assert code == 2 and len(err) == 1, err
    assert re.fullmatch(r"vhfit: error: " + pattern, err[0]), err[0]
    assert listing(out) == was


def test_max_prony_0_is_refused_before_anything_is_printed(noisy, tmp_path, monkeypatch,
                                                           capsys):
    """No 'N = 1..0' progress line: the flag is refused first, in one line."""
    monkeypatch.chdir(tmp_path)
    assert cli.main(["fit", str(noisy[0]), "--max-prony", "0", "--out", "o"]) == 2
    err = capsys.readouterr().err
    assert err.strip().splitlines() == [
        "vhfit: error: --max-prony 0: give a whole number >= 1 (the largest N that --prony "
        "auto tries)"]
    assert not (tmp_path / "o").exists()


def test_a_checkpoint_that_resumes_into_a_failure_says_start_fresh(tmp_path, monkeypatch,
                                                                   capsys, ctrl_c_in_fit):
    """A Gent fit cut (Ctrl-C) while every individual is still infinite keeps its
    checkpoint (exit 1: it could have found a finite one); resumed, it ends in the bound
    error, which says to start fresh with --force, and the folder stays as it was."""
    monkeypatch.chdir(tmp_path)
    data, out = write_locking(tmp_path), tmp_path / "out"
    argv = ["fit", str(data), "--rate", "0.1", *GENT_BOUNDS, "--out", str(out),
            "--no-plot", "--checkpoint-every", "0.001"]
    with ctrl_c_in_fit(3):
        assert cli.main(argv) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("vhfit: error: interrupted before a result was ready; continue "
                              "with: vhfit fit ") and err[-1].endswith(" --resume"), err
    assert sorted(os.listdir(out)) == ["checkpoint.json"]
    was = listing(out)
    assert cli.main(argv + ["--resume"]) == 2
    err = [x for x in capsys.readouterr().err.splitlines() if x.startswith("vhfit: error")]
    assert len(err) == 1 and re.fullmatch(
        r"vhfit: error: " + GENT_LOCKED + f"; the checkpoint in {re.escape(str(out))} holds "
        r"this failed search and resumes only into it: start fresh with --force instead of "
        r"--resume", err[0]), err
    assert listing(out) == was


@pytest.mark.parametrize("argv", [
    ["simulate", "--model", "mooney_rivlin", "--param", "C10=0.1,C01=0", "--param", "G1=1",
     "--rate", "-1"],
    ["simulate", "--model", "nosuchmodel", "--param", "a=1", "--rate", "-1"],
    ["export", "missing.json", "--to", "abaqus"],
    ["export", "garbage.json", "--to", "lsdyna"],
])
@pytest.mark.parametrize("before", ["absent", "file"])
def test_simulate_and_export_bad_input_leave_their_out_file_as_it_was(argv, before, tmp_path,
                                                                      monkeypatch, capsys):
    """Exit 2 writes nothing to --out: no new file, an existing one untouched."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "garbage.json").write_text("{not json")
    out = tmp_path / "dest.txt"
    if before == "file":
        out.write_text("kept\n")
    was = listing(tmp_path)
    assert cli.main(argv + ["--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("vhfit: error: "), err
    assert listing(tmp_path) == was
