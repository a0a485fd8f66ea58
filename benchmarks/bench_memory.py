"""Memory benchmark: peak RSS for 10⁶-point curves and 10 000-individual populations.

Run:  python benchmarks/bench_memory.py [--points 1000000] [--population 10000]

Each scenario runs in a fresh Python process so that its peak resident set size
(``resource.getrusage(...).ru_maxrss``, a high-water mark) is its own; the figure
after ``import vhfit`` and numba's kernels is printed as the baseline.

Scenarios:

* ``csv-rate``   — write a 10⁶-row constant-rate CSV, ``read_csv`` it, calibrate
  (the objective uses 10 points a curve; the curve keeps every sample);
* ``time-smooth`` — a 10⁶-sample measured loading–unloading curve with a time
  column and a smooth strain signal: the stretch history is simplified to a few
  breakpoints, then calibrate;
* ``time-noisy`` — the same with 0.1 % noise on the measured strain: the history is
  capped at ``vhfit.data.MAX_BREAKPOINTS`` breakpoints per curve (with a DataWarning
  giving the tolerance it then follows), then calibrate;
* ``population`` — one evaluation of a 10 000-individual population on four
  paper-size curves, then a calibration with ``popsize=10000`` for 3 generations.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np

TRUTH = dict(C10=0.2, C01=0.1, G1=1.0, tau1=1e-3, G2=2.0, tau2=1e-1)
RATES = (-1.0, -100.0)


def rss_mb() -> float:
    """Peak resident set size of this process so far, MB (Linux: ru_maxrss in KB)."""
    r = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return r / 1024 if sys.platform != "darwin" else r / 2**20


def _warm():
    import vhfit

    m = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    eps = np.linspace(-0.05, -0.5, 10)
    c = [vhfit.Curve(strain=eps, stress=eps, strain_rate=r) for r in (-1.0, -10.0)]
    m.batch(c)(np.tile([0.1, 0.1, 1, 1e-3, 1, 1e-2], (32, 1)))
    return vhfit, m


def scenario_csv_rate(n: int, report: dict) -> None:
    vhfit, m = _warm()
    report["baseline_mb"] = rss_mb()
    with tempfile.TemporaryDirectory() as d:
        paths = []
        for r in RATES:
            eps = np.linspace(-0.5 / n, -0.5, n)
            knots = np.linspace(-0.5 / n, -0.5, 2001)
            s = m.stress(TRUTH, strain=knots, strain_rate=r, measure="engineering")
            sig = np.interp(eps, knots[::-1], s[::-1])
            p = os.path.join(d, f"rate{-r:g}.csv")
            with open(p, "w") as f:
                f.write(f"# strain_rate: {r!r}\nstrain,stress_MPa\n")
                np.savetxt(f, np.column_stack([eps, sig]), delimiter=",", fmt="%.17g")
            paths.append(p)
        report["file_mb"] = sum(os.path.getsize(p) for p in paths) / 1e6
        t0 = time.perf_counter()
        curves = vhfit.read_csv(paths)
        report["read_s"] = time.perf_counter() - t0
        report["after_read_mb"] = rss_mb()
    t0 = time.perf_counter()
    cal = vhfit.calibrate(curves, n_prony=2, seed=0)
    report["calibrate_s"] = time.perf_counter() - t0
    report["rmsape_%"] = cal.rmsape
    report["samples_kept"] = [int(c.strain.size) for c in curves]
    report["objective_points"] = [int(c.target_stress.size) for c in curves]
    report["peak_mb"] = rss_mb()


def _lu_curves(vhfit, m, n: int, noise: float):
    """Loading to -0.5 then unloading to -0.1 at |rate|, n samples, measured time."""
    rng = np.random.default_rng(0)
    out = []
    for r in RATES:
        t_turn = 0.5 / abs(r)
        t = np.linspace(0.0, 1.8 * t_turn, n)
        eps = np.where(t <= t_turn, r * t, r * t_turn - r * (t - t_turn))
        knots_t = np.linspace(0.0, t[-1], 4001)  # the model on a fine grid, interpolated
        e_end = r * t_turn - r * (t[-1] - t_turn)
        hist = vhfit.History.piecewise_linear(np.array([0.0, t_turn, t[-1]]),
                                              np.array([0.0, r * t_turn, e_end]),
                                              out_time=knots_t)
        s = m.stress(TRUTH, hist, measure="engineering")
        sig = np.interp(t, knots_t, s)
        e_meas = eps * (1 + noise * rng.standard_normal(n)) if noise else eps
        out.append(vhfit.Curve(strain=e_meas[1:], stress=sig[1:], time=t[1:]))
    return out


def scenario_time(n: int, report: dict, noise: float) -> None:
    vhfit, m = _warm()
    report["baseline_mb"] = rss_mb()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.perf_counter()
        curves = _lu_curves(vhfit, m, n, noise)
        report["curves_s"] = time.perf_counter() - t0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        t0 = time.perf_counter()
        report["history_breakpoints"] = [int(c.history.time.size) for c in curves]
        report["history_s"] = time.perf_counter() - t0
    report["history_warnings"] = sorted({str(w.message)[:160] for w in caught})
    report["after_curves_mb"] = rss_mb()
    b = m.batch(curves)
    report["internal_samples"] = int(b.sample_stretch.size)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.perf_counter()
        cal = vhfit.calibrate(curves, n_prony=2, seed=0)
        report["calibrate_s"] = time.perf_counter() - t0
    report["rmsape_%"] = cal.rmsape
    report["samples_kept"] = [int(c.strain.size) for c in curves]
    report["peak_mb"] = rss_mb()


def scenario_population(P: int, report: dict) -> None:
    vhfit, _ = _warm()
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import cases

    curves = cases.curves_for(cases.random_material(3), cases.RANDOM_RATES, noise=0.05)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 3)
    b = m.batch(curves)
    report["baseline_mb"] = rss_mb()
    rng = np.random.default_rng(0)
    X = np.column_stack([rng.uniform(0, 1, (P, 2))] + [
        np.column_stack([rng.uniform(0, 5, P), 10 ** rng.uniform(-5, 2, P)]) for _ in range(3)])
    t0 = time.perf_counter()
    S = b(X)
    report["eval_s"] = time.perf_counter() - t0
    report["finite"] = bool(np.isfinite(S).all())
    report["after_eval_mb"] = rss_mb()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.perf_counter()
        cal = vhfit.calibrate(curves, n_prony=3, seed=0, popsize=P, maxiter=3,
                              uncertainty=False)
        report["calibrate_3_generations_s"] = time.perf_counter() - t0
    report["rmsape_%"] = cal.rmsape
    report["peak_mb"] = rss_mb()


SCENARIOS = ("csv-rate", "time-smooth", "time-noisy", "population")


def run_one(name: str, args) -> dict:
    report: dict = {"scenario": name}
    if name == "csv-rate":
        scenario_csv_rate(args.points, report)
    elif name == "time-smooth":
        scenario_time(args.points, report, 0.0)
    elif name == "time-noisy":
        scenario_time(args.points, report, 1e-3)
    else:
        scenario_population(args.population, report)
    return report


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=10**6)
    ap.add_argument("--population", type=int, default=10_000)
    ap.add_argument("--scenario", choices=SCENARIOS, help="run one scenario here (internal)")
    args = ap.parse_args()
    if args.scenario:
        print(json.dumps(run_one(args.scenario, args)))
        return
    print(f"python {sys.version.split()[0]}, {os.cpu_count()} CPUs, "
          f"load {os.getloadavg()[0]:.1f}; points {args.points}, population {args.population}")
    for name in SCENARIOS:
        cmd = [sys.executable, __file__, "--scenario", name, "--points", str(args.points),
               "--population", str(args.population)]
        t0 = time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        if p.returncode != 0:
            print(f"\n## {name}: FAILED ({wall:.1f} s)\n{p.stderr[-2000:]}")
            continue
        rep = json.loads(p.stdout.strip().splitlines()[-1])
        print(f"\n## {name} ({wall:.1f} s in all)")
        for k, v in rep.items():
            if k == "scenario":
                continue
            v = f"{v:.4g}" if isinstance(v, float) else v
            print(f"  {k:<30} {v}")


if __name__ == "__main__":
    main()
