"""What a fit of sweeps alone loads: only what it uses.

``vhfit fit`` on a frequency sweep takes the per-decade spectrum route (no search, no
compiled kernel, no figures with --no-plot). In a fresh interpreter such a fit must not
import numba (its kernels and the Ogden sums compile on first use), scipy.stats (the
Sobol start of a second formulation's search, which the route does not run) or
matplotlib (asked whether it is installed, not imported): together they are about a
second of a fresh process's time. The fits are still made for both formulations, and
they are the fits of the same data made with those packages loaded.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys

import numpy as np

UNUSED = ("numba", "scipy.stats", "matplotlib")

CHILD = r"""
import contextlib, io, json, sys
from vhfit import cli
with contextlib.redirect_stdout(io.StringIO()):
    code = cli.main(["fit", sys.argv[1], "--model", "neo_hooke", "--prony", "3", "--seed",
                     "0", "--out", sys.argv[2], "--no-plot", "-q"])
print(json.dumps({"code": code, "loaded": [m for m in sys.argv[3:] if m in sys.modules]}))
"""


def _sweep_file(tmp_path):
    """E′, E″ of a three-term Maxwell model (written here from E*), 40 frequencies."""
    f = np.logspace(-3, 3, 40)
    w = 2 * np.pi * f[:, None]
    tau, G = np.array([1e-2, 1.0, 1e2]), np.array([3.0, 2.0, 1.0])
    E = 0.6 + np.sum(G * (1j * w * tau) / (1 + 1j * w * tau), axis=1)
    path = tmp_path / "sweep.csv"
    rows = "\n".join(f"{a:.17g},{b:.17g},{c:.17g}" for a, b, c in zip(f, E.real, E.imag))
    path.write_text("frequency_Hz,E_storage_MPa,E_loss_MPa\n" + rows + "\n", encoding="utf-8")
    return path


def test_a_fit_of_sweeps_alone_imports_no_numba_scipy_stats_or_matplotlib(tmp_path):
    path = _sweep_file(tmp_path)
    out = tmp_path / "out"
    env = dict(os.environ)
    proc = subprocess.run([sys.executable, "-c", CHILD, str(path), str(out), *UNUSED],
                          capture_output=True, text=True, env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    child = json.loads(proc.stdout.strip().splitlines()[-1])
    assert child["code"] == 0
    assert child["loaded"] == []
    res = json.loads((out / "results.json").read_text(encoding="utf-8"))
    assert set(res["fits"]) == {"hereditary", "lsdyna"}
    # the versions it records are those of the packages it did not import
    import numba
    import scipy

    assert res["versions"]["numba"] == numba.__version__
    assert res["versions"]["scipy"] == scipy.__version__
    # the same fit in this process, where numba, scipy.stats and matplotlib may be loaded
    import vhfit

    ref = vhfit.calibrate(vhfit.read_csv(path), hyperelastic="neo_hooke", n_prony=3, seed=0)
    assert res["fits"]["hereditary"]["params"] == ref.params
    # exact data: the route gives back the three terms (an independent check of the fit)
    taus = sorted(res["params"][f"tau{i}"] for i in (1, 2, 3))
    np.testing.assert_allclose(taus, [1e-2, 1.0, 1e2], rtol=1e-4)


QUICK = r"""
import contextlib, io, json, sys
from vhfit import cli
out = io.StringIO()
with contextlib.redirect_stdout(out):
    try:
        code = cli.main(sys.argv[1].split())
    except SystemExit as exc:  # argparse's --version / --help
        code = exc.code
print(json.dumps({"code": code, "text": out.getvalue(),
                  "loaded": [m for m in sys.argv[2:] if m in sys.modules]}))
"""

#: what a fit loads and the quick commands must not: the compiled kernels, the search,
#: the figures, the fit code and the file readers
FIT_ONLY = ("numba", "scipy", "matplotlib", "vhfit.calibration", "vhfit.optimize._de",
            "vhfit.data")


def _quick(argv: str, unused) -> dict:
    """``vhfit ARGV`` in a fresh interpreter: its exit code, output and which of
    ``unused`` it imported."""
    proc = subprocess.run([sys.executable, "-c", QUICK, argv, *unused], capture_output=True,
                          text=True, env=dict(os.environ), timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    child = json.loads(proc.stdout.strip().splitlines()[-1])
    assert child["code"] in (0, None), (argv, child)
    assert child["text"].strip(), argv  # it printed something
    return child


def test_version_and_help_load_no_numpy_nor_any_registry():
    """--version and --help print what the parser holds: argparse and the standard library
    only, not numpy (nor the law, test and solver registries that the commands' flags name,
    which come with it)."""
    unused = ("numpy", *FIT_ONLY, "vhfit.hyperelastic", "vhfit.modes", "vhfit.export")
    for argv in ("--version", "--help"):
        assert _quick(argv, unused)["loaded"] == [], argv


def test_help_lists_every_command_the_full_parser_has():
    """The command line builds only the flags of the command it runs: --help still lists
    every command, with the same line as the parser of every command's flags."""
    from vhfit.cli._parser import build_parser

    text = _quick("--help", ())["text"]
    full = build_parser()
    subs = next(a for a in full._actions if isinstance(a, argparse._SubParsersAction))
    for choice in subs._choices_actions:
        assert re.search(rf"^\s+{choice.dest}\s+{re.escape(choice.help)}$", text, re.M), (
            choice.dest)


def test_the_parser_of_one_command_reads_its_arguments_as_the_full_parser():
    from vhfit.cli._parser import build_parser, command_in, glue_windows

    for argv in (["fit", "a.csv", "b.csv", "--prony", "auto", "--model", "yeoh",
                  "--trim-strain", "-0.3:", "--for", "lsdyna", "--abaqus-explicit", "-q"],
                 ["--debug", "export", "r.json", "--to", "abaqus", "--poisson", "0.49"],
                 ["simulate", "--model", "neo_hooke", "--param", "C10=1", "--rate", "0.1"],
                 ["check", "r.json", "--points", "20"], ["models", "--json"],
                 ["demo", "--prony", "2"]):
        words = glue_windows(argv)
        assert command_in(words) == (argv[1] if argv[0] == "--debug" else argv[0],)
        ns = build_parser(command_in(words)).parse_args(words)
        ref = build_parser().parse_args(words)
        assert {k: v for k, v in vars(ns).items() if k != "func"} == {
            k: v for k, v in vars(ref).items() if k != "func"}
        assert ns.func.__name__ == ref.func.__name__
    assert command_in(["--version"]) == () and command_in([]) == ()


def test_models_loads_no_numba_scipy_matplotlib_fit_code_or_readers():
    """``vhfit models`` reads the registries (the laws' numpy code) and nothing the fit
    needs besides."""
    child = _quick("models", FIT_ONLY)
    assert child["loaded"] == [], child["loaded"]
    # the listing still names the τ strategies, read without the search's scipy
    assert "tau strategies" in child["text"] and "semifree" in child["text"]


def test_models_names_the_solvers_of_each_formulation_from_their_records():
    """The formulations' solvers come from the solver records, which the export package
    registers: the listing loads them itself (the parser no longer does)."""
    from vhfit import export

    listed = json.loads(_quick("models --json", ())["text"])["formulations"]
    for form in listed:
        own = [s for s in export.solvers() if export.get_solver(s).formulation == form["name"]]
        assert form["solvers"] == own, form
    assert sum(len(f["solvers"]) for f in listed) == len(export.solvers()) > 0
