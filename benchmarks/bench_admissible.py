"""Recoveries that need the admissible search space (docs/theory.md §11), timed.

    PYTHONPATH=src python benchmarks/bench_admissible.py [--repeats 3]

1. Ogden-2 with μ2 < 0 (Abaqus form, Drucker-stable over the data's range), exact data:
   uniaxial, equibiaxial and planar tension at 3 rates, 200 samples a curve, 3 Prony
   terms; default settings (seed 0..repeats-1).
2. Yeoh with C20 < 0 and one Prony term, exact uniaxial compression at two rates.
3. One-term Ogden α = −20 (brain-tissue-like), equilibrium tension and compression
   λ in [0.9, 1.1]: reached by widening the default α range [−10, 10].

Prints RMSAPE, the largest relative error of the constants, wall and CPU times.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import vhfit

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_modes import PRONY, max_rel_error, multimode_curves  # noqa: E402


def timed(curves, law, **kw):
    t0, c0 = time.perf_counter(), time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate(curves, law, uncertainty=False, **kw)
    return cal, time.perf_counter() - t0, time.process_time() - c0


def yeoh_curves(truth):
    m = vhfit.ViscoHyperelastic("yeoh", 1)
    eps = np.linspace(-0.02, -0.5, 25)
    return [vhfit.Curve(strain=eps, stress=m.stress(truth, strain=eps, strain_rate=r,
                                                    measure="engineering"),
                        strain_rate=r, measure="engineering") for r in (-1.0, -100.0)]


def brain_curves(alpha, mu=0.001):
    m = vhfit.ViscoHyperelastic("ogden", 0)
    out = []
    for end in (-0.1, 0.1):
        eps = np.linspace(end / 20, end, 20)
        out.append(vhfit.Curve(strain=eps, stress=m.stress(dict(mu1=mu, alpha1=alpha),
                                                           strain=eps, measure="engineering"),
                               measure="engineering"))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    og = dict(mu1=0.4, alpha1=3.0, mu2=-0.05, alpha2=-2.0, **PRONY)
    yeoh = dict(C10=0.2, C20=-0.01, C30=0.002, G1=1.0, tau1=0.01)
    brain = dict(mu1=0.001, alpha1=-20.0)
    cases = [
        ("ogden2 mu2<0, 3 modes x 3 rates x 200", multimode_curves("ogden2", og), "ogden2",
         og, dict(n_prony=3)),
        ("yeoh C20<0 + 1 Prony term", yeoh_curves(yeoh), "yeoh", yeoh, dict(n_prony=1)),
        ("ogden alpha=-20, equilibrium", brain_curves(-20.0), "ogden", brain,
         dict(n_prony=0)),
    ]
    print(f"{'case':40s} {'seed':>4s} {'RMSAPE %':>10s} {'max rel':>9s} {'wall s':>7s} "
          f"{'cpu s':>6s}  nit")
    for name, curves, law, truth, kw in cases:
        for seed in range(args.repeats):
            cal, wall, cpu = timed(curves, law, seed=seed, **kw)
            err = max_rel_error(cal.params, truth)
            print(f"{name:40s} {seed:4d} {cal.rmsape:10.3g} {err:9.2g} "
                  f"{wall:7.2f} {cpu:6.2f}  {cal.nit}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
