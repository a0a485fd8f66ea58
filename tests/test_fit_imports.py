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

import json
import os
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
        code = cli.main(sys.argv[1:2])
    except SystemExit as exc:  # argparse's --version / --help
        code = exc.code
heavy = ("numba", "scipy", "matplotlib", "vhfit.calibration", "vhfit.optimize._de")
print(json.dumps({"code": code, "text": out.getvalue(),
                  "loaded": [m for m in heavy if m in sys.modules]}))
"""


def test_version_help_and_models_load_no_numba_scipy_matplotlib_or_fit_code():
    """The quick commands import on demand: none of the fit's packages in a fresh process."""
    for argv in ("--version", "--help", "models"):
        proc = subprocess.run([sys.executable, "-c", QUICK, argv], capture_output=True,
                              text=True, env=dict(os.environ), timeout=300)
        assert proc.returncode == 0, proc.stderr[-2000:]
        child = json.loads(proc.stdout.strip().splitlines()[-1])
        assert child["code"] in (0, None), (argv, child)
        assert child["loaded"] == [], (argv, child["loaded"])
        assert child["text"].strip(), argv  # it printed something
    # the models listing still names the τ strategies, read without the search's scipy
    assert "tau strategies" in child["text"] and "semifree" in child["text"]
