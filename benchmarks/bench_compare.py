"""vhfit.compare benchmark: 4 laws on the 4 SEBS curves, against the slowest single fit.

Run:  python benchmarks/bench_compare.py [--rounds 3] [--workers 2] [--prony 2]

Each round runs, in this one process,

1. every law alone (``vhfit.calibrate(curves, hyperelastic=law, ...)``, the way one
   ``vhfit fit --model LAW`` fits), timing each; the slowest is T_single;
2. ``vhfit.compare(curves, laws, workers=W, ...)`` with the same keywords and seed,
   timing the whole comparison (process start, fits, card checks): T_compare;

and checks that compare's error of each law equals the single fit's bit for bit. The
rounds alternate the two so that other load on the machine hits both alike; the
medians and the median of the per-round ratios T_compare / T_single are printed.

Target (docs/cli.md): T_compare <= 1.5 x T_single on 2 cores.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
import warnings

import vhfit
from vhfit import datasets

LAWS = ("mooney_rivlin", "yeoh", "ogden2", "arruda_boyce")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--prony", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    curves = datasets.load_sebs()
    kw = dict(n_prony=a.prony, seed=a.seed)
    print(f"{len(LAWS)} laws ({', '.join(LAWS)}) on {len(curves)} SEBS curves, N = {a.prony}, "
          f"seed {a.seed}, {a.workers} processes; cpus {os.cpu_count()}, load "
          f"{os.getloadavg()[0]:.2f}", flush=True)
    warnings.simplefilter("ignore")
    vhfit.calibrate(curves, hyperelastic="neo_hooke", n_prony=1, seed=0)  # compile once
    singles, compares, ratios = [], [], []
    same = True
    for k in range(a.rounds):
        times, errs = {}, {}
        for law in LAWS:
            t0 = time.perf_counter()
            errs[law] = vhfit.calibrate(curves, hyperelastic=law, **kw).rmsape
            times[law] = time.perf_counter() - t0
        t0 = time.perf_counter()
        comp = vhfit.compare(curves, LAWS, workers=a.workers, **kw)
        t_cmp = time.perf_counter() - t0
        t_single = max(times.values())
        for law in LAWS:
            if comp.fits[law].rmsape != errs[law]:
                same = False
                print(f"  DIFFERENT: {law}: compare {comp.fits[law].rmsape!r}, alone "
                      f"{errs[law]!r}")
        singles.append(t_single)
        compares.append(t_cmp)
        ratios.append(t_cmp / t_single)
        print(f"round {k + 1}: single fits " + ", ".join(f"{law} {t:.2f} s" for law, t
                                                          in times.items())
              + f"; slowest {t_single:.2f} s; compare {t_cmp:.2f} s; ratio "
              f"{t_cmp / t_single:.2f}; load {os.getloadavg()[0]:.2f}", flush=True)
    print(comp.table())
    med = statistics.median(ratios)
    print(f"median slowest single fit {statistics.median(singles):.2f} s, median compare "
          f"{statistics.median(compares):.2f} s, median ratio {med:.2f} (target <= 1.5); "
          f"errors equal to the single fits: {'yes' if same else 'NO'}")
    return 0 if same and med <= 1.5 else 1


if __name__ == "__main__":
    raise SystemExit(main())
