"""Wall time of the default fit of each real dataset: this checkout against a baseline
release, side by side in one run.

Run::

    python benchmarks/bench_speed_real.py                        # every dataset, vs main
    python benchmarks/bench_speed_real.py --only hnbr50,vhb_zhao --repeats 3
    python benchmarks/bench_speed_real.py --base-rev 3bc6eb2     # a given release

The datasets and their commands are those of ``benchmarks/bench_real.py`` (read at run
time from ``--data``, default ``../shared/data`` or ``$VHFIT_DATA``). The baseline is
the source tree of ``--base`` (a folder with ``src/vhfit``), or of ``--base-rev`` checked
out once as a detached git worktree in a temporary folder (removed at the end). Each
fit runs in a fresh process (``python`` with ``PYTHONPATH`` set to one side's ``src``)
that reads the data, compiles numba on a small fit, then times ``vhfit.calibrate`` as
``bench_real`` does (``seed=0``; median of ``--repeats`` fits). The two sides alternate
per dataset and repeat (baseline first on even rounds, this checkout first on odd ones)
so that a change of the machine's load falls on both. Both sides' errors are printed
and a fit whose RMSAPE is more than ``--rtol`` (1e-3) relative above the baseline's is
flagged ``WORSE``. CPU time (the process, all threads, and its ended child processes:
an order scan's second one) is printed beside wall time: on a shared machine it is the
steadier figure.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def worker(name: str, data: Path, repeats: int) -> None:
    """Time the default fit of one dataset with the vhfit on the path; print JSON."""
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")  # as bench_real: small matrices
    import numpy as np

    import vhfit

    sys.path.insert(0, str(HERE))
    from bench_modes import _cpu, forget_fits
    from bench_real import DATASETS, read

    ds = next(d for d in DATASETS if d.name == name)
    curves = read(ds, data)
    warm = [vhfit.Curve(strain=np.linspace(0.01, 0.2, 10), stress=np.linspace(0.01, 0.2, 10),
                        strain_rate=r) for r in (0.1, 1.0)]
    walls, cpus, cal = [], [], None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vhfit.calibrate(warm, n_prony=1, maxiter=2, polish=False, uncertainty=False)
        vhfit.calibrate(curves, hyperelastic=ds.law, seed=0, maxiter=1, polish=False,
                        uncertainty=False, **{**ds.fit, "n_prony": 1 if ds.fit else None})
        for _ in range(repeats):
            forget_fits()  # each repeat as a fresh process's fit
            t0, c0 = time.perf_counter(), _cpu()
            cal = vhfit.calibrate(curves, hyperelastic=ds.law, seed=0, **ds.fit)
            walls.append(time.perf_counter() - t0)
            cpus.append(_cpu() - c0)
    print(json.dumps(dict(wall=statistics.median(walls), cpu=statistics.median(cpus),
                          rmsape=cal.rmsape, n=cal.model.n_prony,
                          order=[r["rmsape"] for r in cal.order_scan or []],
                          vhfit=vhfit.__file__)))


def run_side(src: Path, name: str, data: Path, repeats: int) -> dict:
    env = {**os.environ, "PYTHONPATH": str(src)}
    p = subprocess.run([sys.executable, __file__, "--worker", name, "--data", str(data),
                        "--repeats", str(repeats)], env=env, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"{name} with {src}: the fit failed:\n{p.stderr[-2000:]}")
    out = json.loads(p.stdout.strip().splitlines()[-1])
    if not out["vhfit"].startswith(str(src)):
        raise SystemExit(f"{name}: ran {out['vhfit']}, not the vhfit of {src}")
    return out


def main(argv=None) -> int:
    sys.path.insert(0, str(HERE))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=Path, default=Path(os.environ.get(
        "VHFIT_DATA", ROOT.parent.parent / "shared" / "data")),
        help="folder of the datasets (default ../shared/data or $VHFIT_DATA)")
    ap.add_argument("--only", default=None, help="comma list of dataset names (bench_real's)")
    ap.add_argument("--repeats", type=int, default=1, help="fits per process (median)")
    ap.add_argument("--rounds", type=int, default=1,
                    help="processes per side and dataset (median of their medians)")
    ap.add_argument("--base", type=Path, default=None,
                    help="source tree of the baseline (a folder holding src/vhfit)")
    ap.add_argument("--new", type=Path, default=ROOT,
                    help="source tree of the side measured against it (default: this checkout)")
    ap.add_argument("--base-rev", default="main",
                    help="git revision checked out as the baseline when --base is not given")
    ap.add_argument("--rtol", type=float, default=1e-3,
                    help="relative error increase over the baseline flagged WORSE")
    ap.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.worker:
        worker(a.worker, a.data, a.repeats)
        return 0
    if not a.data.is_dir():
        raise SystemExit(f"no datasets at {a.data}: give --data or set VHFIT_DATA")
    from bench_real import DATASETS

    chosen = [d for d in DATASETS if not a.only or d.name in a.only.split(",")]
    tmp = None
    base = a.base
    if base is None:
        tmp = Path(tempfile.mkdtemp(prefix="vhfit-base-"))
        base = tmp / "tree"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(base),
                        a.base_rev], check=True, capture_output=True)
    rev = subprocess.run(["git", "-C", str(base), "rev-parse", "--short", "HEAD"],
                         capture_output=True, text=True).stdout.strip() or str(base)
    head = subprocess.run(["git", "-C", str(a.new), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True).stdout.strip() or str(a.new)
    sides = {"base": base / "src", "new": a.new / "src"}
    print(f"baseline {rev} ({base}) vs {head} ({a.new}); {os.cpu_count()} cores, load "
          f"{os.getloadavg()[0]:.1f}; {a.rounds} process(es) x {a.repeats} fit(s) per side",
          flush=True)
    rows = []
    try:
        for ds in chosen:
            if not all((a.data / ds.folder / f).is_file() for f in ds.files):
                print(f"{ds.name}: skipped, files not found under {a.data / ds.folder}")
                continue
            res = {"base": [], "new": []}
            for r in range(a.rounds):
                order = ("base", "new") if r % 2 == 0 else ("new", "base")
                for side in order:
                    res[side].append(run_side(sides[side], ds.name, a.data, a.repeats))
            b, n = res["base"][-1], res["new"][-1]
            row = dict(name=ds.name, cmd=ds.command(),
                       tb=statistics.median(x["wall"] for x in res["base"]),
                       tn=statistics.median(x["wall"] for x in res["new"]),
                       cb=statistics.median(x["cpu"] for x in res["base"]),
                       cn=statistics.median(x["cpu"] for x in res["new"]),
                       eb=b["rmsape"], en=n["rmsape"], nb=b["n"], nn=n["n"])
            row["worse"] = row["en"] > row["eb"] * (1 + a.rtol)
            rows.append(row)
            print(f"{ds.name}: base {row['tb']:.2f} s (cpu {row['cb']:.2f}) {row['eb']:.6g} % "
                  f"N={row['nb']} {b['order']}\n{'':{len(ds.name)}}  new  {row['tn']:.2f} s "
                  f"(cpu {row['cn']:.2f}) {row['en']:.6g} % N={row['nn']} {n['order']}",
                  flush=True)
    finally:
        if tmp is not None:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force",
                            str(base)], capture_output=True)
            shutil.rmtree(tmp, ignore_errors=True)
    print("\n| dataset | command | wall before s | wall after s | ratio | cpu before s | "
          "cpu after s | error before % | error after % | N before/after |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        flag = " WORSE" if r["worse"] else ""
        print(f"| {r['name']} | `{r['cmd']}` | {r['tb']:.2f} | {r['tn']:.2f} | "
              f"{r['tb'] / r['tn']:.1f}x | {r['cb']:.2f} | {r['cn']:.2f} | {r['eb']:.6g} | "
              f"{r['en']:.6g}{flag} | {r['nb']}/{r['nn']} |")
    if rows:
        mb = statistics.median(r["tb"] for r in rows)
        mn = statistics.median(r["tn"] for r in rows)
        tb, tn = sum(r["tb"] for r in rows), sum(r["tn"] for r in rows)
        cb, cn = sum(r["cb"] for r in rows), sum(r["cn"] for r in rows)
        print(f"\nall fits: wall {tb:.1f} s before, {tn:.1f} s after ({tb / tn:.1f}x); cpu "
              f"{cb:.1f} s before, {cn:.1f} s after ({cb / cn:.1f}x)")
        print(f"median wall per fit: before {mb:.2f} s, after {mn:.2f} s ({mb / mn:.1f}x); "
              f"max after {max(r['tn'] for r in rows):.2f} s; errors worse than "
              f"{a.rtol:g} relative: {sum(r['worse'] for r in rows)}/{len(rows)}; load now "
              f"{os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
