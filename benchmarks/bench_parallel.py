"""calibrate_many benchmark: 40 independent calibrations, serial against a 2-worker pool.

Run:  python benchmarks/bench_parallel.py [--jobs 40] [--workers 2] [--no-dask]

The 40 jobs mix materials (SEBS and gelatin stand-ins, three Random_3 materials with
±5 % noise), model orders, τ strategies and seeds. The script runs them

1. one after another in this process (``calibrate_many(jobs)``), giving the total
   single-job time T (sum of each job's wall time);
2. on a local process pool of ``--workers`` workers (``calibrate_many(jobs, 2)``,
   pool start-up included; the default start method, "fork" where safe, and again
   with "spawn" and with "forkserver"), and checks every job's constants are bit-identical;
   steps 1-2 alternate ``--rounds`` times and the ratios' median is quoted;
3. through a local Dask cluster (2 worker processes × 1 thread) when
   ``distributed`` is installed, again checking the constants.

Target: pool wall time <= 1.3 x T / workers. Other work on the machine slows the pool:
the load average is printed with the figures.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))

import cases  # noqa: E402

import vhfit  # noqa: E402
from vhfit.calibration import CalibrationWarning  # noqa: E402
from vhfit.parallel import calibrate_many  # noqa: E402


def make_jobs(n_jobs: int) -> list[dict]:
    """Materials x N x strategy x seed, cycled up to ``n_jobs``."""
    materials = [
        ("SEBS", cases.curves_for(cases.SEBS, cases.SEBS_RATES), (2, 4)),
        ("gelatin", cases.curves_for(cases.GELATIN, cases.GELATIN_RATES), (2, 3)),
    ] + [
        (f"Random_{k}+5%", cases.curves_for(cases.random_material(k), cases.RANDOM_RATES,
                                            noise=0.05, seed=k), (2, 3))
        for k in (1, 2, 3)
    ]
    jobs = []
    for seed in range(100):
        for strategy in ("free", "semifree"):
            for name, curves, orders in materials:
                for n in orders:
                    jobs.append(dict(name=f"{name} N={n} {strategy} seed {seed}", curves=curves,
                                     n_prony=n, tau_strategy=strategy, seed=seed))
                    if len(jobs) == n_jobs:
                        return jobs
    return jobs


def constants(results) -> dict:
    return {r.name: (r.calibration.params, r.calibration.history["best"]) if r.ok else r.error
            for r in results}


def run(label: str, jobs, executor=None, **kw):
    t0 = time.perf_counter()
    res = list(calibrate_many(jobs, executor, **kw))
    wall = time.perf_counter() - t0
    busy = sum(r.wall_time for r in res)
    cpu = sum(r.cpu_time for r in res)
    first = max(r.wall_time for r in res)
    failed = [r for r in res if not r.ok]
    print(f"{label:<44}{wall:>9.1f}{busy:>12.1f}{cpu:>12.1f}{first:>10.2f}{len(failed):>8}"
          f"   load {os.getloadavg()[0]:.1f}")
    for r in failed:
        print(f"    failed: {r}")
    return res, wall, busy


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=40)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--rounds", type=int, default=3,
                    help="serial and pool runs alternate this many times (medians quoted)")
    ap.add_argument("--no-dask", action="store_true", help="skip the Dask cluster run")
    args = ap.parse_args()
    warnings.simplefilter("ignore", CalibrationWarning)
    import numba
    from numba.np.ufunc import parallel as nb_parallel

    from vhfit._pools import get_context

    print(f"vhfit {vhfit.__version__}, numpy {np.__version__}, numba {numba.__version__}, "
          f"python {platform.python_version()}, {os.cpu_count()} CPUs, "
          f"numba threading layer default threads {numba.config.NUMBA_NUM_THREADS}")
    jobs = make_jobs(args.jobs)
    list(calibrate_many(jobs[:1]))  # warm up: numba kernels loaded in this process
    print(f"\n{len(jobs)} jobs, {args.rounds} rounds")
    print(f"{'run':<44}{'wall s':>9}{'sum job s':>12}{'sum cpu s':>12}{'max job s':>10}"
          f"{'failed':>8}")
    ratios, ratios_spawn, ratios_fs, same = [], [], [], True
    ref = None
    for _ in range(args.rounds):
        serial, _, T = run("serial, in process", jobs)
        ref = ref or constants(serial)
        # the calibrations above never start numba's thread pool, so "auto" forks
        start = get_context("auto").get_start_method()
        pool, t_pool, _ = run(f"process pool, {args.workers} workers ({start})", jobs,
                              args.workers)
        _, t_spawn, _ = run(f"process pool, {args.workers} workers (spawn)", jobs,
                            args.workers, mp_context="spawn")
        _, t_fs, _ = run(f"process pool, {args.workers} workers (forkserver)", jobs,
                         args.workers, mp_context="forkserver")
        ratios_fs.append(t_fs / (T / args.workers))
        ratios.append(t_pool / (T / args.workers))
        ratios_spawn.append(t_spawn / (T / args.workers))
        same = same and constants(serial) == ref and constants(pool) == ref
    print(f"\nnumba thread pool started in this process by the serial runs: "
          f"{nb_parallel._is_initialized is not False}")
    r = float(np.median(ratios))
    print(f"pool wall / (T/{args.workers}), T = sum of single-job times of the same round: "
          f"median {r:.2f} (runs {', '.join(f'{x:.2f}' for x in ratios)}) -> "
          f"{'met' if r <= 1.3 else 'NOT met'} (target <= 1.3)")
    print(f"same with spawn start: median {np.median(ratios_spawn):.2f} "
          f"(runs {', '.join(f'{x:.2f}' for x in ratios_spawn)})")
    print(f"same with forkserver start (what 'auto' uses where fork is unsafe, e.g. "
          f"Jupyter; its server starts in round 1 only): median {np.median(ratios_fs):.2f} "
          f"(runs {', '.join(f'{x:.2f}' for x in ratios_fs)})")
    print(f"constants bit-identical (all serial and pool runs): {same}")

    if args.no_dask:
        return
    try:
        import distributed
    except ImportError:
        print("\nDask: distributed is not installed (pip install 'vhfit[dask]'); skipped")
        return
    t0 = time.perf_counter()
    with distributed.LocalCluster(n_workers=args.workers, threads_per_worker=1,
                                  processes=True, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        t_start = time.perf_counter() - t0
        dask_res, t_dask, _ = run(f"Dask LocalCluster, {args.workers} x 1 thread (submit)",
                                  jobs, client.get_executor())
    print(f"cluster start {t_start:.1f} s; Dask constants identical to serial: "
          f"{constants(dask_res) == ref}")


if __name__ == "__main__":
    main()
