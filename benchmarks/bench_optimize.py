"""Benchmark of vhfit.optimize: overhead of the extras, and convergence on calibrations.

Run from the repository root::

    python benchmarks/bench_optimize.py            # full run (several minutes)
    python benchmarks/bench_optimize.py --quick    # smaller, for a smoke test

Part 1 - overhead. A cheap vectorized objective (10-D Rastrigin), NP = 60, deferred
updating: plain SciPy (``popsize=6``) and vhfit (``population_size=60`` with
``history=True`` and the paper's four stopping criteria, set so that none fires)
run side by side, interleaved, on the same seeds. Both follow exactly the same
trajectory (checked: identical results), so the time difference is the cost of the
extras. Reported: median time per generation and the ratio.

Part 2 - convergence on calibration-like problems. For 2, 3 and 4 Prony terms and
several seeds, a random Mooney-Rivlin + Prony material in the paper's style
(Random_1..5: rates -1, -10, -100, -1000 1/s, compression to strain -0.5) generates
10 points per curve; each method then fits [C10, C01, G_i, log10 tau_i] (semi-free
tau bounds, Eq. 22; upper limits of docs/theory.md §11) minimising the RMSAPE (Eq. 20, percent)
until RMSAPE < 0.01 % or an evaluation budget. Reported: median generations and
objective evaluations to the target over the seeds (runs that miss the target count
as the budget, so a median is a lower bound when more than half miss), and how many
runs reached it.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings

import numpy as np
import scipy.optimize as so

from vhfit.optimize import (
    LSHADE,
    MaxGenerations,
    TargetValue,
    differential_evolution,
    paper_criteria,
    tau_bounds,
)

RATES = (-1.0, -10.0, -100.0, -1000.0)
STRAIN = np.linspace(-0.05, -0.5, 10)  # 10 points a curve, evenly spaced in strain


# ============================================================================ part 1
def rastrigin_vec(x: np.ndarray) -> np.ndarray:
    """10-D Rastrigin, vectorized: x of shape (N, S) -> (S,)."""
    return 10.0 * x.shape[0] + np.sum(x * x - 10.0 * np.cos(2.0 * np.pi * x), axis=0)


def overhead(generations: int, repeats: int) -> dict:
    bounds = [(-5.12, 5.12)] * 10
    # the paper's four criteria, evaluated every generation but set so that none fires
    # before maxiter (checked below: stop_reason must be 'maxiter'); a zero best-mean
    # gap would mean a collapsed population, when SciPy's tol=0 test stops too
    never = paper_criteria(target=-np.inf, max_generations=10**9, gap_rel=0.0)
    common = dict(vectorized=True, updating="deferred", maxiter=generations, polish=False)
    t_scipy, t_ours, t_hist = [], [], []
    for rep in range(repeats):
        t0 = time.perf_counter()
        a = so.differential_evolution(rastrigin_vec, bounds, popsize=6, tol=0, rng=rep,
                                      **common)
        t1 = time.perf_counter()
        b = differential_evolution(rastrigin_vec, bounds, population_size=60, tol=0,
                                   history=True, stop=never, rng=rep, **common)
        t2 = time.perf_counter()
        c = differential_evolution(rastrigin_vec, bounds, population_size=60, tol=0,
                                   history=True, rng=rep, **common)
        t3 = time.perf_counter()
        assert np.array_equal(a.x, b.x) and a.fun == b.fun and a.nit == b.nit == c.nit
        assert np.array_equal(a.population, b.population), "trajectories differ"
        assert b.stop_reason == "maxiter" and len(b.history) == generations + 1
        t_scipy.append((t1 - t0) / a.nit)
        t_ours.append((t2 - t1) / b.nit)
        t_hist.append((t3 - t2) / c.nit)
    s, o, h = np.median(t_scipy), np.median(t_ours), np.median(t_hist)
    return {"scipy": s, "ours": o, "history_only": h, "ratio": o / s, "ratio_hist": h / s}


# ============================================================================ part 2
class Problem:
    """A calibration-like problem: fit MR + n Prony terms to curves from a known material."""

    def __init__(self, n_terms: int, seed: int) -> None:
        import vhfit
        from vhfit.history import History

        rng = np.random.default_rng([n_terms, seed])
        self.model = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=n_terms)
        self.batch = self.model.batch([History.constant_rate(STRAIN, r) for r in RATES])
        tb = np.asarray(tau_bounds(RATES, n_terms, "semifree"))
        while True:
            c = 10.0 ** rng.uniform(-2.0, 0.0, size=2)  # C10, C01 in MPa
            g = 10.0 ** rng.uniform(-1.0, 1.0, size=n_terms)  # G_i in MPa
            w = tb[:, 1] - tb[:, 0]
            lt = tb[:, 0] + w * rng.uniform(0.1, 0.9, size=n_terms)  # log10 tau_i in its piece
            truth = np.concatenate([c, np.column_stack([g, lt]).ravel()])
            self.target = self.batch(self.to_params(truth[None, :]))[0]
            self.bounds = self._bounds(tb)
            lo, hi = np.array(self.bounds).T
            if np.all((truth > lo) & (truth < hi)):
                break
        self.truth = truth
        self.scale = np.array([np.mean(self.target[k * 10:(k + 1) * 10]) for k in range(4)])
        self.n_eval = 0

    @staticmethod
    def to_params(Z: np.ndarray) -> np.ndarray:
        """Search vectors (rows [C10, C01, G1, log10 tau1, ...]) to model parameters."""
        X = np.array(Z, dtype=np.float64, copy=True)
        X[:, 3::2] = 10.0 ** X[:, 3::2]
        return X

    def _bounds(self, tb: np.ndarray) -> list[tuple[float, float]]:
        """Upper limits of docs/theory.md §11: one term alone puts every stress over the targets."""
        lam = 1.0 + np.tile(STRAIN, len(RATES))
        y = np.abs(self.target)
        c10 = float(np.max(y / np.abs(2 * (lam**2 - 1 / lam))))
        c01 = float(np.max(y / np.abs(2 * (lam - 1 / lam**2))))
        gmax = float(np.max(y / (np.abs(lam**2 - 1 / lam) / 3.0)))  # instantaneous response
        out = [(0.0, c10), (0.0, c01)]
        for lo, hi in tb:
            out += [(0.0, gmax), (float(lo), float(hi))]
        return out

    def rmsape(self, Z: np.ndarray) -> np.ndarray:
        """RMSAPE (Eq. 20, percent) of each row of Z; +inf for invalid parameters."""
        Z = np.atleast_2d(Z)
        self.n_eval += Z.shape[0]
        sig = self.batch(self.to_params(Z))
        err = (sig - self.target).reshape(Z.shape[0], len(RATES), -1) / self.scale[None, :, None]
        with np.errstate(invalid="ignore", over="ignore"):
            f = 100.0 * np.sqrt(np.mean(err.reshape(Z.shape[0], -1) ** 2, axis=1))
        return np.where(np.isfinite(f), f, np.inf)

    def scalar(self, z: np.ndarray) -> float:
        return float(self.rmsape(z[None, :])[0])

    def vectorized(self, Zt: np.ndarray) -> np.ndarray:
        return self.rmsape(Zt.T)


TARGET = 0.01  # RMSAPE, percent


def methods(budget: int) -> dict:
    """name -> (uses vectorized objective, kwargs for differential_evolution)."""
    return {
        "paper preset (rand1bin, NP=60)": (False, dict(preset="paper")),
        "SciPy default (best1bin, 15N)": (False, dict()),
        "jDE (NP=60, deferred)": (True, dict(strategy="jde", population_size=60,
                                             updating="deferred")),
        "SHADE = preset 'recommended'": (True, dict(preset="recommended")),
        "L-SHADE (NP 60->4 over 40k evals)": (True, dict(strategy=LSHADE(max_nfev=40_000),
                                                        population_size=60,
                                                        updating="deferred")),
    }


def run_one(problem: Problem, vectorized: bool, kwargs: dict, budget: int, seed: int) -> dict:
    problem.n_eval = 0

    def over_budget(state):
        return problem.n_eval >= budget and f"budget of {budget} evaluations spent"

    stop = TargetValue(TARGET) | over_budget | MaxGenerations(10**7)
    func = problem.vectorized if vectorized else problem.scalar
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = differential_evolution(func, problem.bounds, vectorized=vectorized, rng=seed,
                                     polish=False, stop=stop, maxiter=10**7, **kwargs)
    return {
        "reached": res.stop_reason == "TargetValue",
        "nit": res.nit,
        "neval": problem.n_eval,
        "time": time.perf_counter() - t0,
        "fun": res.fun,
    }


def convergence(terms: list[int], seeds: list[int], budget: int, out=sys.stdout) -> dict:
    table: dict = {}
    names = list(methods(budget))
    print(f"  {'N':>2s}  {'method':34s} {'reached':>7s} {'med. gen':>9s} {'med. evals':>10s} "
          f"{'paper/this':>10s} {'med. time':>9s}", file=out)
    for n in terms:
        problems = [Problem(n, s) for s in seeds]
        for name, (vec, kw) in methods(budget).items():
            table[(n, name)] = [run_one(p, vec, kw, budget, s) for p, s in zip(problems, seeds)]
        paper = np.median([r["neval"] for r in table[(n, names[0])]])
        for name in names:
            rows = table[(n, name)]
            nev = np.median([r["neval"] for r in rows])
            nit = np.median([r["nit"] for r in rows])
            ok = sum(r["reached"] for r in rows)
            tm = np.median([r["time"] for r in rows])
            print(f"  {n:2d}  {name:34s} {ok:3d}/{len(rows):<3d} {nit:9.0f} {nev:10.0f} "
                  f"{paper / nev:10.1f} {tm:8.1f}s", file=out, flush=True)
    print("  all problems (median over every run):", file=out)
    paper = np.median([r["neval"] for n in terms for r in table[(n, names[0])]])
    for name in names:
        rows = [r for n in terms for r in table[(n, name)]]
        nev = np.median([r["neval"] for r in rows])
        ok = sum(r["reached"] for r in rows)
        print(f"  {'*':>2s}  {name:34s} {ok:3d}/{len(rows):<3d} "
              f"{np.median([r['nit'] for r in rows]):9.0f} {nev:10.0f} {paper / nev:10.1f} "
              f"{np.median([r['time'] for r in rows]):8.1f}s", file=out, flush=True)
    return table


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats/seeds/terms")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--terms", type=int, nargs="*", default=[2, 3, 4])
    ap.add_argument("--budget", type=int, default=400_000)
    ap.add_argument("--skip-overhead", action="store_true")
    ap.add_argument("--skip-convergence", action="store_true")
    args = ap.parse_args(argv)
    if args.quick:
        args.seeds, args.terms, args.budget = 2, [2], 100_000
    if not args.skip_overhead:
        print("Part 1: overhead of the extras (10-D Rastrigin, vectorized, NP=60)")
        gens, reps = (150, 5) if args.quick else (300, 15)
        r = overhead(gens, reps)
        print(f"  plain SciPy              {r['scipy'] * 1e6:8.1f} us/generation")
        print(f"  vhfit history + stop     {r['ours'] * 1e6:8.1f} us/generation  "
              f"ratio {r['ratio']:.3f}")
        print(f"  vhfit history only       {r['history_only'] * 1e6:8.1f} us/generation  "
              f"ratio {r['ratio_hist']:.3f}  (SciPy's tol test kept)")
    if not args.skip_convergence:
        print(f"\nPart 2: evaluations to RMSAPE < {TARGET} % (median over "
              f"{args.seeds} seeds, budget {args.budget} evaluations)")
        convergence(args.terms, list(range(args.seeds)), args.budget)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
