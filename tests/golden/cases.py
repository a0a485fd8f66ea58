"""Golden calibrations: the outputs a refactoring of the house must leave unchanged, bit for bit.

Each case runs a calibration (or the command line) through the public API only and
returns a JSON-ready record of everything that must not change: constants, errors,
generations, evaluations, stop reason, the generation history (best and mean; wall
time and the order scan's process count excluded), warnings, intervals; for the command
line, results.json, the summary, the fitted-curve CSV and the solver cards, with wall
times, timestamps and temporary paths masked.

Record with ``python tests/golden/record.py`` (only when a change of results is
intended and has its own evidence); ``tests/test_golden.py`` compares against the file.
"""

from __future__ import annotations

import contextlib
import io
import json
import re
import warnings
from pathlib import Path

import numpy as np

import vhfit

A_PARAMS = dict(C10=0.2, C01=0.1, G1=1.0, tau1=1e-3, G2=2.0, tau2=1e-1)
RATES = (-1.0, -10.0, -100.0, -1000.0)


def _rate_curves(params, rates=RATES, *, hyper="mooney_rivlin", n=10, noise=0.0, seed=0,
                 n_points=10):
    n_prony = sum(1 for k in params if k.startswith("tau"))
    m = vhfit.ViscoHyperelastic(hyper, n_prony)
    rng = np.random.default_rng(seed)
    out = []
    for r in rates:
        eps = np.linspace(-0.05, -0.5, n)
        s = m.stress(params, strain=eps, strain_rate=r, measure="engineering")
        if noise:
            s = s * (1 + rng.uniform(-noise, noise, s.size))
        out.append(vhfit.Curve(strain=eps, stress=s, strain_rate=r, measure="engineering",
                               n_points=n_points))
    return out


def _history_curves(noise=0.02, seed=4):
    """A loading-unloading history through (t, eps) beside a constant-rate ramp."""
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    rng = np.random.default_rng(seed)
    t = np.array([0.0, 0.004, 0.008, 0.012, 0.016])
    e = np.array([0.0, -0.2, -0.4, -0.2, -0.05])
    tt = np.linspace(0.0, 0.016, 33)
    ee = np.interp(tt, t, e)
    s = m.stress(A_PARAMS, strain=ee, time=tt, measure="engineering")[1:]
    tt, ee = tt[1:], ee[1:]
    s = s * (1 + rng.uniform(-noise, noise, s.size))
    cyc = vhfit.Curve(strain=ee, stress=s, time=tt, measure="engineering", n_points=10)
    return [cyc] + _rate_curves(A_PARAMS, (-1.0, -100.0), noise=noise, seed=seed + 1)


def _record(cal) -> dict:
    d = cal.to_dict()
    d.pop("wall_time", None)
    # how the order scan ran (one process or two, as this process could fork) is, like the
    # wall time, not a result: the results are the same to the bit either way
    d.get("options", {}).pop("scan_processes", None)
    d["history"] = {k: list(v) for k, v in cal.history.items() if k != "time"}
    return d


def _quiet(fn, *a, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*a, **kw)


def _cal(curves, **kw):
    return _record(_quiet(vhfit.calibrate, curves, **kw))


def case_sep_free_n2_exact():
    return _cal(_rate_curves(A_PARAMS), n_prony=2, tau_strategy="free", seed=0)


def case_sep_semifree_n3_noisy_nopolish():
    return _cal(_rate_curves(A_PARAMS, noise=0.03, seed=1), n_prony=3, tau_strategy="semifree",
                seed=1, polish=False)


def case_sep_fixed_n4_noisy():
    return _cal(_rate_curves(A_PARAMS, noise=0.03, seed=2), n_prony=4, tau_strategy="fixed",
                seed=2)


def case_sep_free_n1_history():
    return _cal(_history_curves(), n_prony=1, seed=3)


def case_sep_free_n5_noisy_capped():
    return _cal(_rate_curves(A_PARAMS, noise=0.03, seed=5), n_prony=5, seed=5, maxiter=40)


def case_sep_auto_order():
    return _cal(_rate_curves(A_PARAMS, noise=0.02, seed=6), n_prony="auto", max_prony=3,
                seed=6)


def case_full_semifree_n2():
    return _cal(_rate_curves(A_PARAMS), n_prony=2, method="full", tau_strategy="semifree",
                seed=7, maxiter=30)


def case_full_free_n1_history_nopolish():
    return _cal(_history_curves(), n_prony=1, method="full", seed=8, maxiter=30, polish=False)


def case_sep_workers2():
    return _cal(_rate_curves(A_PARAMS, noise=0.03, seed=9), n_prony=2, seed=9, workers=2,
                maxiter=60)


def case_full_workers2():
    return _cal(_rate_curves(A_PARAMS, noise=0.03, seed=10), n_prony=2, method="full",
                seed=10, workers=2, maxiter=20)


def case_sep_yeoh_rmse_weighted():
    curves = _rate_curves(dict(C10=0.3, C20=-0.02, C30=0.01, G1=1.0, tau1=1e-2), hyper="yeoh",
                          noise=0.02, seed=11)
    curves = [c.replace(weight=w) for c, w in zip(curves, (1.0, 2.0, 0.5, 1.0))]
    return _cal(curves, hyperelastic="yeoh", n_prony=1, objective="rmse", seed=11)


def case_sep_ogden_floor():
    # no long-term stiffness in the data's reach: the g_inf floor must act
    curves = _rate_curves(dict(mu1=0.05, alpha1=2.0, G1=3.0, tau1=1e3), hyper="ogden",
                          noise=0.01, seed=12)
    return _cal(curves, hyperelastic="ogden", n_prony=1, seed=12, g_inf_min=0.05)


def case_sep_samples_default():
    # the default objective: every one of the 40 noisy samples a curve
    curves = _rate_curves(A_PARAMS, n=40, noise=0.02, seed=15, n_points=None)
    return _cal(curves, n_prony=2, seed=15)


def case_checkpoint_resume(tmp: Path):
    curves = _rate_curves(A_PARAMS, noise=0.05, seed=13)
    ck = tmp / "ck.json"

    def interrupt(state):
        if state["generation"] == 5:
            raise KeyboardInterrupt
        return False

    cut = _cal(curves, n_prony=2, seed=13, checkpoint=ck, checkpoint_every=0.0,
               callback=interrupt)
    res = _cal(curves, n_prony=2, seed=13, checkpoint=ck, resume=True)
    return {"cut": cut, "resumed": res}


def _mask(text: str, tmp: Path) -> str:
    text = text.replace(str(tmp), "<tmp>")
    text = re.sub(r"wall \d+\.\d+ s", "wall <t> s", text)
    return text


def case_cli_fit(tmp: Path):
    from vhfit.cli import main

    curves = _rate_curves(A_PARAMS, noise=0.02, seed=14)
    files = []
    for i, c in enumerate(curves):
        p = tmp / f"rate{i}.csv"
        rows = "\n".join(f"{float(e)!r},{float(s)!r}" for e, s in zip(c.strain, c.stress))
        p.write_text(f"# strain_rate: {float(c.strain_rate)!r}\nstrain,stress_MPa\n{rows}\n")
        files.append(str(p))
    out = tmp / "out"
    buf_o, buf_e = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(buf_o), contextlib.redirect_stderr(buf_e):
        code = _quiet(main, ["fit", *files, "--prony", "2", "--seed", "14", "--no-plot",
                             "--out", str(out), "--quiet"])
    res = json.loads((out / "results.json").read_text())
    # the settings record came after these results were pinned (tests/test_results_file.py
    # checks it): the results themselves are compared
    for entry in [res, *(res.get("fits") or {}).values()]:  # each solver's fit too
        for k in ("timestamp", "versions", "wall_time", "settings"):
            entry.pop(k, None)
        entry.get("history", {}).pop("time", None)
    # --scan-workers came after the recording too (an option of how, not what, is fitted)
    res.get("cli_options", {}).pop("scan_workers", None)
    res = json.loads(_mask(json.dumps(res), tmp))
    cards = {p.name: _mask(p.read_text(), tmp) for p in sorted(out.iterdir())
             if p.suffix in (".inp", ".k", ".mac", ".txt", ".csv") or p.name.endswith(".json")
             and p.name != "results.json"}
    return {"exit": code, "results": res, "files": cards,
            "stdout": _mask(buf_o.getvalue(), tmp)}


CASES = {name[5:]: fn for name, fn in sorted(globals().items()) if name.startswith("case_")}
NEEDS_TMP = {"checkpoint_resume", "cli_fit"}


def run(name: str, tmp: Path):
    from vhfit.calibration import _nesting

    _nesting.clear_cache()  # each case as in a fresh process: no earlier case's fit seeds it
    fn = CASES[name]
    return fn(tmp) if name in NEEDS_TMP else fn()
