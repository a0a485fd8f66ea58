"""The figures of ``vhfit fit`` drawn by a second process (``cli._outputs.Drawer``).

Each run is a fresh interpreter (a fork is safe there, as for a user's command): the
figures drawn by the second process, drawn here when there is none, and drawn here
after the second process was lost must be the same files; no process is left behind,
also when the fit fails. Which process drew them is recorded by a wrapper of
``draw_figures`` (the same function in both: an event, not a time).
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("matplotlib")

CHILD = r"""
import json, multiprocessing, os, sys, time
from vhfit.cli import _fit, _outputs, main

mode, out, *files = sys.argv[1:]
given = _outputs.draw_figures


def draw(*job, **kw):  # which process draws (the drawer runs the name it finds here)
    with open(out + ".pids", "a") as f:
        f.write(f"{os.getpid()}\n")
    drawn = given(*job, **kw)
    open(out + ".drawn", "w").close()
    return drawn


_outputs.draw_figures = draw
_outputs.usable_cpus = lambda: 2  # a second CPU, as on any machine the test runs on
if mode == "here":
    _outputs.Drawer.start = classmethod(lambda cls, args: None)
elif mode == "lost":
    _outputs._draw_when_asked = lambda jobs, send, callback: os._exit(3)
elif mode == "fails":
    def refuse(*a, **k):
        raise ValueError("refused by the test")
    _fit.calibrate = refuse
elif mode.startswith("later"):  # the fit of the second formulation fails, or is stopped
    real, calls = _fit.calibrate, []

    def later(*a, **k):
        calls.append(1)
        for _ in range(1200 if len(calls) > 1 and not mode.endswith("-here") else 0):
            if os.path.exists(out + ".drawn"):  # the drawer drew the first fit's figures
                break
            time.sleep(0.1)
        if len(calls) > 1 and mode == "later-fails":  # before a result: exit 1
            raise KeyboardInterrupt
        if len(calls) > 1:
            def stop(progress):
                raise KeyboardInterrupt
            k["callback"] = stop
        return real(*a, **k)
    _fit.calibrate = later
    if mode.endswith("-here"):
        _outputs.Drawer.start = classmethod(lambda cls, args: None)
code = main(["fit", *files, "--model", "neo_hooke", "--prony", "1", "--seed", "0",
             "--popsize", "8", "--maxiter", "4", "-q", "--out", out])
print(json.dumps({"code": code, "pid": os.getpid(),
                  "children": len(multiprocessing.active_children())}))
"""


def _files(tmp_path) -> list[str]:
    """Two ramps of a neo-Hooke + one Prony term material, at two rates."""
    import vhfit

    m = vhfit.ViscoHyperelastic("neo_hooke", 1)
    p = {"C10": 0.2, "G1": 0.5, "tau1": 0.1}
    paths = []
    for rate in (0.1, 10.0):
        eps = np.linspace(0.0, 0.5, 30)
        s = m.stress(p, strain=eps, strain_rate=rate, measure="engineering")
        path = tmp_path / f"r{rate:g}.csv"
        path.write_text("strain_rate,strain,stress_MPa\n" + "".join(
            f"{rate:g},{e:.12g},{v:.12g}\n" for e, v in zip(eps, s)))
        paths.append(f"{path}")
    return paths


def _run(tmp_path, mode: str, files: list[str]) -> tuple[dict, list[int], os.PathLike]:
    out = tmp_path / mode
    proc = subprocess.run([sys.executable, "-c", CHILD, mode, str(out), *files],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    child = json.loads(proc.stdout.strip().splitlines()[-1])
    pids_file = tmp_path / f"{mode}.pids"
    pids = [int(v) for v in pids_file.read_text().split()] if pids_file.exists() else []
    return child, pids, out


def _same_text(a: str, b: str) -> str:
    # the times of the run differ: the search's wall time ("0.52 s", "1 s" under load)
    # and the report's stamp
    times = r"\d+(?:\.\d+)?(?:e[+-]?\d+)? s\b|written \d{4}-\d\d-\d\d \d\d:\d\d:\d\d UTC"
    return re.sub(times, "T", a.replace(str(b), "OUT"))


def test_the_figures_of_the_second_process_are_those_drawn_here(tmp_path):
    files = _files(tmp_path)
    runs = {mode: _run(tmp_path, mode, files) for mode in ("second", "here", "lost")}
    for mode, (child, _, _) in runs.items():
        assert child["code"] == 0 and child["children"] == 0, (mode, child)
    # the second process drew them; without one, or once it was lost, this process did
    assert len(runs["second"][1]) == 1 and runs["second"][1][0] != runs["second"][0]["pid"]
    assert runs["here"][1] == [runs["here"][0]["pid"]]
    assert runs["lost"][1] == [runs["lost"][0]["pid"]]
    ref = runs["here"][2]
    pngs = sorted(p.name for p in ref.glob("*.png"))
    assert "fit.png" in pngs and "history.png" in pngs
    for mode in ("second", "lost"):
        out = runs[mode][2]
        assert sorted(p.name for p in out.iterdir()) == sorted(p.name for p in ref.iterdir())
        for name in pngs:
            assert (out / name).read_bytes() == (ref / name).read_bytes(), (mode, name)
        for name in ("report.html", "summary.txt"):
            assert (_same_text((out / name).read_text(encoding="utf-8"), out)
                    == _same_text((ref / name).read_text(encoding="utf-8"), ref)), (mode, name)


def test_a_failed_fit_leaves_no_drawer_behind(tmp_path):
    child, pids, _ = _run(tmp_path, "fails", _files(tmp_path))
    assert child["code"] == 2 and child["children"] == 0 and pids == []


def test_figures_drawn_during_a_later_fit_that_is_interrupted_are_drawn_again_marked(tmp_path):
    # the drawer starts on the first fit's figures while the second formulation's fit
    # runs; that fit is interrupted, so every figure must carry the mark: drawn here, as
    # without a drawer
    files = _files(tmp_path)
    runs = {mode: _run(tmp_path, mode, files)
            for mode in ("later-interrupted", "later-interrupted-here")}
    (child, pids, out), (child_h, pids_h, ref) = runs.values()
    assert child["code"] == child_h["code"] == 1 and child["children"] == 0
    # drawn there first (unmarked), then here again
    assert pids == [pids[0], child["pid"]] and pids[0] != child["pid"]
    assert pids_h == [child_h["pid"]]
    assert sorted(p.name for p in out.iterdir()) == sorted(p.name for p in ref.iterdir())
    pngs = sorted(p.name for p in ref.glob("*.png"))
    assert "fit.png" in pngs
    for name in pngs:
        data = (out / name).read_bytes()
        assert data == (ref / name).read_bytes(), name
        assert b"INTERRUPTED" in data, name  # the PNG's Description


def test_figures_drawn_during_a_later_fit_that_fails_are_not_left_behind(tmp_path):
    # interrupted before its result: exit 1, the checkpoints kept for --resume, and no
    # figure of the first fit (drawn meanwhile) beside them
    child, _, out = _run(tmp_path, "later-fails", _files(tmp_path))
    assert child["code"] == 1 and child["children"] == 0
    left = sorted(p.name for p in out.iterdir())
    assert left and all(n.startswith("checkpoint.json") for n in left), left
