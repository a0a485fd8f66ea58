"""Speed of one population evaluation of a network model (vhfit.viscous).

Run::

    python benchmarks/bench_networks_eval.py            # 3 repeats
    python benchmarks/bench_networks_eval.py --quick    # 1 repeat, 10 sets
    python benchmarks/bench_networks_eval.py --repeats 1

Case (the size of issue 36's target): 60 parameter sets × 4 curves × 500 points × 2
Bergström–Boyce networks on Ogden-2, at the integrator's default tolerances. The curves
are VHB-like: loading–unloading to λ = 3 at 0.01, 0.03 and 0.1 1/s, and a relaxation
test (ramp to λ = 2 in 10 s, hold 290 s). The parameter sets are drawn around one set
(log A over four decades, m in [1.5, 6], C in [−1, −0.3], ratios 0.2–0.4 each), seeded.

Printed: the median wall time of one evaluation (all 240 rows in one batched call),
the time per row, and the target (≤ 50 ms) beside it. No number is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from vhfit import hyperelastic
from vhfit.viscous import flows, network_stress

TARGET = 0.050


def curves(points: int = 500) -> tuple[np.ndarray, np.ndarray]:
    """Four curves of ``points`` times each: three load–unload cycles and a relaxation."""
    T, L = [], []
    for rate in (0.01, 0.03, 0.1):
        t_peak = 2.0 / rate
        t = np.linspace(0.0, 2 * t_peak, points)
        T.append(t)
        L.append(1.0 + rate * np.minimum(t, 2 * t_peak - t))
    t = np.concatenate([np.linspace(0.0, 10.0, points // 5),
                        np.linspace(10.0, 300.0, points - points // 5 + 1)[1:]])
    T.append(t)
    L.append(1.0 + 0.1 * np.minimum(t, 10.0))
    return np.stack(T), np.stack(L)


def population(n: int, seed: int = 0):
    rng = np.random.default_rng(seed)
    law = rng.uniform([0.02, 1.5, 0.001, -2.5], [0.04, 2.5, 0.003, -1.5], (n, 4))
    ratios = rng.uniform(0.2, 0.4, (n, 2))
    nets = [np.column_stack([10.0 ** rng.uniform(lo, lo + 4, n), rng.uniform(1.5, 6.0, n),
                             rng.uniform(-1.0, -0.3, n), np.full(n, 0.01)])
            for lo in (-1.0, 1.0)]
    return law, ratios, nets


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--repeats", type=int, default=None)
    args = ap.parse_args()
    n, repeats = (10, 1) if args.quick else (60, 3)
    repeats = args.repeats or repeats
    law = hyperelastic.get("ogden2")
    T, L = curves()
    lp, ratios, nets = population(n)
    bb = [flows.get("bergstrom_boyce")] * 2

    def once():
        return network_stress(law, lp[:, None, :], bb, ratios[:, None, :],
                              [c[:, None, :] for c in nets], T, L)

    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = once()
        times.append(time.perf_counter() - t0)
    med = statistics.median(times)
    rows = n * T.shape[0]
    print(f"population evaluation: {n} sets x {T.shape[0]} curves x {T.shape[1]} points x "
          f"2 networks, output {out.shape}, finite {bool(np.all(np.isfinite(out)))}")
    print(f"median of {repeats}: {med:.3f} s   per row: {1e3 * med / rows:.2f} ms   "
          f"target: {TARGET:.3f} s   ratio to target: {med / TARGET:.0f}x")


if __name__ == "__main__":
    main()
