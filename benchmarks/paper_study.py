"""Reproduce and extend the paper's parametric study; write docs/paper-study.md.

Run (full study, by hand, about 10 min on 2 free cores)::

    python benchmarks/paper_study.py

Quick mode (CI, about a minute; writes into a temporary directory unless --out)::

    python benchmarks/paper_study.py --quick

Re-render the document from a saved run without recomputing::

    python benchmarks/paper_study.py --from-json results.json

Items: (1) τ strategies × Prony terms (paper Figs. 6-7), (2) population size
(Figs. 8-9), (3) noise (Table 4), (4) SEBS and gelatin stand-ins (Tables 5-6),
(5) gelatin's rate-stiffening limit, (6) a summary table for the README. Every number
and every verdict in the generated document comes from this run; nothing is typed in.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import math
import os
import platform
import sys
import tempfile
import threading
import time
import warnings
from concurrent.futures import as_completed


def _peek_workers(argv) -> int:
    for i, a in enumerate(argv):
        if a == "--workers" and i + 1 < len(argv):
            return max(1, int(argv[i + 1]))
        if a.startswith("--workers="):
            return max(1, int(a.split("=", 1)[1]))
    return 2


# one numba thread per worker process: the workers already use the cores
os.environ.setdefault(
    "NUMBA_NUM_THREADS", str(max(1, (os.cpu_count() or 1) // _peek_workers(sys.argv)))
)

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import cases  # noqa: E402

# vhfit loads its optimizer lazily: import it here, so that a spawned worker (which
# re-imports this module) loads it as it starts, not inside its first timed calibration
import vhfit  # noqa: E402
import vhfit.optimize  # noqa: E402, F401
from vhfit._pools import process_pool  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
STRATEGIES = ("free", "semifree", "fixed")
NP_LIST = (5, 10, 15, 20, 30, 40, 50, 60, 80, 100)
FLOOR = 1e-8  # RMSAPE plotted at this floor when lower (percent)

# the paper's published figures (its Tables 4-6 and text)
PAPER = {
    "random3": dict(rmsape=0.0491, gens="1303", time="103 min"),
    "noise": dict(rmsape="3.1168-3.1196", gens="543-707", time="29-46 min",
                  rows=[(3.1195, 543, 31), (3.1196, 707, 46), (3.1168, 578, 29),
                        (3.1169, 597, 34), (3.1168, 607, 35)]),
    "sebs": dict(rmsape=7.484, gens="3058", time="132 min", n=4),
    "gelatin": dict(rmsape=19.69, gens="354", time="13 min", n=5),
    "hardware": "two Xeon E5-2650 v2 (16 cores, 2.6 GHz)",
}


# --------------------------------------------------------------------- the cases
def gelatin_reported_curves():
    """Gelatin stand-in with the rate stiffening the paper reports (not measured data).

    The Table 6 model curves at the paper's rates, except that the fast curves follow
    σ_2500(ε) (r / 2500)^p with p = ln 4 / ln(5700/2500): ×4 in stress for ×2.28 in
    rate between 2500 and 5700 1/s, as the paper's discussion quotes for the data.
    """
    cv = _paper_points(cases.curves_for(cases.GELATIN, cases.GELATIN_RATES))
    base = cv[1]
    p = math.log(4.0) / math.log(5700.0 / 2500.0)
    out = [cv[0], base]
    for c in cv[2:]:
        f = (c.strain_rate / base.strain_rate) ** p
        out.append(vhfit.Curve(strain=base.target_strain, stress=np.asarray(base.target_stress) * f,
                               strain_rate=c.strain_rate, measure="engineering", name=c.name,
                               n_points=PAPER_POINTS))
    return out


#: The paper's objective: 10 points a curve, evenly spaced in strain (its §2.2).
PAPER_POINTS = 10


def _paper_points(curves):
    """The curves compared at the paper's 10 points, not at every sample (vhfit's default)."""
    return [c.resample(PAPER_POINTS) for c in curves]


def case_curves(case: str, noise_seed=None):
    """Curves (at the paper's 10 points) and the true parameters of a case name."""
    curves, truth = _case_curves(case, noise_seed)
    return _paper_points(curves), truth


def _case_curves(case: str, noise_seed=None):
    if case.startswith("Random_"):
        truth = cases.random_material(int(case.split("_")[1]))
        if noise_seed is None:
            return cases.curves_for(truth, cases.RANDOM_RATES), truth
        return cases.curves_for(truth, cases.RANDOM_RATES, noise=0.05, seed=noise_seed), truth
    if case == "SEBS":
        return cases.curves_for(cases.SEBS, cases.SEBS_RATES), cases.SEBS
    if case == "gelatin":
        return cases.curves_for(cases.GELATIN, cases.GELATIN_RATES), cases.GELATIN
    if case == "gelatin-reported":
        return gelatin_reported_curves(), None
    raise ValueError(case)


def paper_init(curves, n, strategy, npop, seed):
    """Latin-hypercube initial population of exactly ``npop`` individuals.

    The paper's NP is absolute; SciPy sizes a population as a multiple of the number of
    parameters, so the study passes the initial population explicitly, drawn over the
    same bounds calibrate uses (Eq. 22 τ bounds and the modulus bounds of docs/theory.md §11).
    """
    from scipy.stats import qmc

    from vhfit.calibration import auto_bounds
    from vhfit.optimize import tau_bounds

    rates = [abs(c.strain_rate) for c in curves]
    tb = tau_bounds(rates, n, strategy=strategy, decades_above=1, decades_below=2)
    tb = np.asarray(getattr(tb, "bounds", tb), dtype=np.float64).reshape(n, 2)
    model = vhfit.ViscoHyperelastic("mooney_rivlin", n)
    ab = auto_bounds(model, curves, tb)
    lo = [ab["C10"][0], ab["C01"][0]]
    hi = [ab["C10"][1], ab["C01"][1]]
    for i in range(n):
        lo += [ab[f"G{i + 1}"][0], tb[i, 0]]
        hi += [ab[f"G{i + 1}"][1], tb[i, 1]]
    lo, hi = np.array(lo), np.array(hi)
    u = qmc.LatinHypercube(d=lo.size, rng=np.random.default_rng(10_000 + seed)).random(npop)
    return lo + u * (hi - lo)


def max_rel_error(params, truth):
    """Largest relative error of recovered constants (a pruned term counts as 100 %)."""
    if truth is None:
        return None
    errs = []
    for k, v in truth.items():
        got = params.get(k)
        if got is None:
            errs.append(1.0)
        elif v != 0:
            errs.append(abs(got - v) / abs(v))
        else:
            errs.append(abs(got))
    return float(max(errs))


def staircase(hist):
    """Compact best-so-far history: points where the best fell by >= 1 %, and the last."""
    g, t, b = hist.get("nit", []), hist.get("time", []), hist.get("best", [])
    out, last = [], math.inf
    for i in range(len(b)):
        if b[i] < 0.99 * last or i == len(b) - 1:
            out.append((int(g[i]), float(t[i]), float(b[i])))
            last = b[i]
    return out


def run_job(spec: dict) -> dict:
    """One calibration of the study (runs in a worker process)."""
    warnings.simplefilter("ignore")
    rec = dict(spec)
    cpu0 = time.process_time()
    try:
        curves, truth = case_curves(spec["case"], spec.get("noise_seed"))
        n, seed = spec["n"], spec["seed"]
        kw = dict(n_prony=n, seed=seed, uncertainty=False)
        if spec["method"] in ("paper", "paper-batched"):
            npop = spec.get("np", 50)
            # the paper's DE updates the population one trial at a time (immediate);
            # "paper-batched" is calibrate(method="full")'s default, one batch a generation
            upd = "immediate" if spec["method"] == "paper" else "deferred"
            kw.update(method="full", tau_strategy=spec["strategy"], decades_below=2,
                      decades_above=1, polish=False, maxiter=spec["gens"],
                      max_time=spec.get("max_time"), popsize=npop,
                      de_options={"init": paper_init(curves, n, spec["strategy"], npop, seed),
                                  "updating": upd})
            rec["population"] = npop
        elif spec["method"] == "vhfit":  # our method on the cell's strategy, Eq. 22 bounds
            kw.update(tau_strategy=spec["strategy"], decades_below=spec.get("decades_below", 2))
            rec["population"] = 64
        else:  # "default": every calibrate default (free τ, Eq. 22 minus a decade, ...)
            if spec.get("np"):
                kw["popsize"] = spec["np"]
            rec["population"] = spec.get("np") or 64
        cal = vhfit.calibrate(curves, **kw)
        rec.update(
            rmsape=float(cal.rmsape), nit=int(cal.nit), nfev=int(cal.nfev),
            wall=float(cal.wall_time), stop=str(cal.stop_reason), n_eff=int(cal.n_prony),
            params={k: float(v) for k, v in cal.params.items()},
            per_curve=[float(v) for v in cal.per_curve_rmsape],
            history=staircase(cal.history),
            rel_err=max_rel_error(cal.params, truth) if truth is not None and
            cases.n_prony(truth) == n and spec.get("noise_seed") is None else None,
            noisy_rel_err=max_rel_error(cal.params, truth)
            if spec.get("noise_seed") is not None else None,
        )
        if spec.get("noise_seed") is not None:
            rec["floor"] = float(cases.rmsape_of(truth, curves))
    except Exception as exc:  # keep the study going; failures are reported in the doc
        rec.update(error=f"{type(exc).__name__}: {exc}")
    rec["cpu"] = time.process_time() - cpu0
    return rec


def _worker_init():
    warnings.simplefilter("ignore")


# ----------------------------------------------------------------------- the plan
def plan(args) -> list[dict]:
    q = args.quick
    seeds = range(args.seeds)
    mats = [3] if q else [1, 2, 3, 4, 5]
    ns = [1, 3] if q else [1, 2, 3, 4, 5]
    jobs = []
    # 1. strategies x Prony terms
    for k in mats:
        for n in ns:
            for s in seeds:
                for st in STRATEGIES:
                    jobs.append(dict(item=1, case=f"Random_{k}", n=n, strategy=st, seed=s,
                                     method="paper", gens=args.paper_gens, np=50,
                                     max_time=args.max_paper_time))
                    jobs.append(dict(item=1, case=f"Random_{k}", n=n, strategy=st, seed=s,
                                     method="vhfit"))
                jobs.append(dict(item=1, case=f"Random_{k}", n=n, strategy="default", seed=s,
                                 method="default"))
    # 2. population size (the paper: semifree, 3 terms)
    nps = (10, 60) if q else NP_LIST
    for k in mats:
        for npop in nps:
            for s in seeds:
                jobs.append(dict(item=2, case=f"Random_{k}", n=3, strategy="semifree", seed=s,
                                 method="paper", gens=args.paper_gens, np=npop,
                                 max_time=args.max_paper_time))
                jobs.append(dict(item=2, case=f"Random_{k}", n=3, strategy="default", seed=s,
                                 method="default", np=npop))
    # 3. noise: one noisy Random_3 data set, 5 trials (as the paper: its 5 errors agree to
    # 3e-3 %), the noise-free original, and 5 further noise realisations for our default
    trials = range(2 if q else 5)
    for tr in trials:
        jobs.append(dict(item=3, case="Random_3", n=3, strategy="semifree", seed=tr,
                         method="paper", gens=args.long_gens, np=50, noise_seed=0,
                         max_time=args.max_paper_time))
        jobs.append(dict(item=3, case="Random_3", n=3, strategy="default", seed=tr,
                         method="default", noise_seed=0))
        if not q:
            jobs.append(dict(item=3, case="Random_3", n=3, strategy="default", seed=tr,
                             method="default", noise_seed=100 + tr, tag="realisation"))
    for s in seeds:
        # the paper's standard case run to the paper's own criteria, for each strategy
        # ("1c"; its semifree runs are also the noise-free row of the noise table)
        for st in STRATEGIES:
            for meth in ("paper", "paper-batched"):
                jobs.append(dict(item="1c", case="Random_3", n=3, strategy=st, seed=s,
                                 method=meth, gens=args.long_gens, np=50,
                                 max_time=args.max_paper_time))
        jobs.append(dict(item=3, case="Random_3", n=3, strategy="default", seed=s,
                         method="default", tag="original"))
    # 4. SEBS and gelatin stand-ins
    for case in ("SEBS", "gelatin"):
        for n in ([PAPER["sebs"]["n"] if case == "SEBS" else 2] if q else range(1, 6)):
            for s in seeds:
                jobs.append(dict(item=4, case=case, n=n, strategy="default", seed=s,
                                 method="default"))
                jobs.append(dict(item=4, case=case, n=n, strategy="semifree", seed=s,
                                 method="vhfit", decades_below=3))
        for s in seeds:
            jobs.append(dict(item=4, case=case, n=PAPER["sebs" if case == "SEBS" else
                                                     "gelatin"]["n"],
                             strategy="semifree", seed=s, method="paper", np=60,
                             gens=args.long_gens, max_time=args.max_paper_time))
    # 5. gelatin with the reported rate stiffening
    for n in ([2] if q else range(1, 6)):
        for s in seeds:
            jobs.append(dict(item=5, case="gelatin-reported", n=n, strategy="default", seed=s,
                             method="default"))
            jobs.append(dict(item=5, case="gelatin-reported", n=n, strategy="semifree", seed=s,
                             method="vhfit", decades_below=3))
    for s in seeds:
        jobs.append(dict(item=5, case="gelatin-reported", n=5, strategy="semifree", seed=s,
                         method="paper", np=60, gens=args.long_gens // 4,
                         max_time=args.max_paper_time))
    return jobs


def _cost(job) -> float:
    if job["method"] == "paper":
        return job["gens"] * job.get("np", 50) * 1.4e-4
    if job["method"] == "paper-batched":
        return job["gens"] * job.get("np", 50) * 3e-5
    return 0.3 * job["n"]


class LoadSampler(threading.Thread):
    """Samples the 1-minute load average every few seconds during the run."""

    def __init__(self, every=5.0):
        super().__init__(daemon=True)
        self.every, self.samples, self._stop = every, [], threading.Event()

    def run(self):
        while not self._stop.is_set():
            self.samples.append(os.getloadavg()[0])
            self._stop.wait(self.every)

    def stop(self):
        self._stop.set()
        self.samples.append(os.getloadavg()[0])


def execute(jobs, workers) -> list[dict]:
    jobs = sorted(jobs, key=_cost, reverse=True)  # longest first: better packing
    out, t0 = [], time.perf_counter()
    # spawn: fresh interpreters, each with the NUMBA_NUM_THREADS set at the top
    with process_pool(workers, "spawn", initializer=_worker_init) as ex:
        futs = [ex.submit(run_job, j) for j in jobs]
        for i, f in enumerate(as_completed(futs), 1):
            out.append(f.result())
            if i % 25 == 0 or i == len(futs):
                print(f"  {i}/{len(futs)} calibrations, {time.perf_counter() - t0:.0f} s",
                      file=sys.stderr, flush=True)
    return out


# ------------------------------------------------------------------- statistics
def med(xs):
    xs = [x for x in xs if x is not None and np.isfinite(x)]
    return float(np.median(xs)) if xs else float("nan")


def q(xs, p):
    xs = [x for x in xs if x is not None and np.isfinite(x)]
    return float(np.percentile(xs, p)) if xs else float("nan")


def fmt(x, d=3):
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "–"
    if x == 0:
        return "0"
    if abs(x) < 1e-3 or abs(x) >= 1e5:
        return f"{x:.{max(d - 1, 1)}e}"
    return f"{x:.{d}g}"


def spread(xs):
    return f"{fmt(med(xs))} [{fmt(q(xs, 25), 2)}–{fmt(q(xs, 75), 2)}]"


def select(R, **kw):
    return [r for r in R if all(r.get(k) == v for k, v in kw.items()) and "error" not in r]


def time_to(rec, level):
    """Seconds a run needed to reach RMSAPE <= level (best-so-far history, else its end)."""
    for _, t, b in rec.get("history", []):
        if b <= level:
            return t
    return rec["wall"] if rec["rmsape"] <= level else float("inf")


def best_at(rec, gen):
    """Best RMSAPE of a run after ``gen`` generations (1 % resolution)."""
    v = float("nan")
    for g, _, b in rec.get("history", []):
        if g <= gen:
            v = b
    return v


def table(header, rows, align=None):
    align = align or ["l"] + ["r"] * (len(header) - 1)
    sep = ["---:" if a == "r" else ":---" for a in align]
    lines = ["| " + " | ".join(header) + " |", "| " + " | ".join(sep) + " |"]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def compare(paper_runs, ours_runs, tie=0.01):
    """Cell verdict: our default against the paper's method, medians over seeds.

    win: lower median RMSAPE (by more than ``tie`` relative, or both below 1e-6 %)
    reached in no more time than the paper's method took (median time to reach the
    paper's median final error, against its median wall time); tie: within ``tie``.
    """
    pe, oe = med([r["rmsape"] for r in paper_runs]), med([r["rmsape"] for r in ours_runs])
    pw = med([r["wall"] for r in paper_runs])
    tt = med([time_to(r, pe) for r in ours_runs])
    ow = med([r["wall"] for r in ours_runs])
    if oe < 1e-6 and pe < 1e-6:  # both exact to rounding
        verdict = "tie" if ow <= pw else "tie (slower)"
    elif oe <= pe * (1 - tie):
        verdict = "win" if tt <= pw else "win (slower)"
    elif oe <= pe * (1 + tie):
        verdict = "tie" if ow <= pw else "tie (slower)"
    else:
        verdict = "loss"
    return dict(pe=pe, oe=oe, pw=pw, ow=ow, tt=tt, verdict=verdict)


# ---------------------------------------------------------------------- figures
def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


COLORS = {"free": "tab:blue", "semifree": "tab:orange", "fixed": "tab:green",
          "default": "tab:red"}


def fig_strategies(R, path):
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.3), sharey=True)
    for ax, meth, title in ((axes[0], "paper", "paper's DE (our evaluator)"),
                            (axes[1], "vhfit", "vhfit separable (same τ bounds)")):
        for st in STRATEGIES:
            rs = select(R, item=1, method=meth, strategy=st)
            ax.scatter([r["wall"] for r in rs], [max(r["rmsape"], FLOOR) for r in rs], s=14,
                       alpha=0.7, color=COLORS[st], label=st)
        if meth == "vhfit":
            rs = select(R, item=1, method="default")
            ax.scatter([r["wall"] for r in rs], [max(r["rmsape"], FLOOR) for r in rs], s=14,
                       alpha=0.7, color=COLORS["default"], marker="x", label="vhfit default")
        ax.set(xscale="log", yscale="log", xlabel="wall time (s)", title=title)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_ylabel(f"final RMSAPE (%) (values < {FLOOR:g} drawn at {FLOOR:g})")
    fig.suptitle("Final error against wall time, 5 random materials × N = 1..5 × seeds "
                 "(cf. paper Fig. 6)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def fig_prony(R, path):
    plt = _plt()
    ns = sorted({r["n"] for r in select(R, item=1)})
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.3), sharey=True)
    for ax, meth, title in ((axes[0], "paper", "paper's DE (our evaluator)"),
                            (axes[1], "vhfit", "vhfit separable")):
        sts = STRATEGIES + (("default",) if meth == "vhfit" else ())
        for j, st in enumerate(sts):
            m = "default" if st == "default" else meth
            y, lo, hi = [], [], []
            for n in ns:
                e = [max(r["rmsape"], FLOOR) for r in select(R, item=1, method=m, strategy=st, n=n)]
                y.append(med(e))
                lo.append(q(e, 25))
                hi.append(q(e, 75))
            x = np.array(ns) + (j - 1.5) * 0.06
            ax.errorbar(x, y, yerr=[np.array(y) - lo, np.array(hi) - y], marker="o", capsize=3,
                        color=COLORS[st], label="vhfit default" if st == "default" else st)
        ax.set(yscale="log", xlabel="number of Prony terms N", title=title, xticks=ns)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_ylabel("final RMSAPE (%): median and quartiles")
    fig.suptitle("Final error against N (cf. paper Fig. 7); the materials have 3 true terms",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def fig_population(R, path_hist, path_final):
    plt = _plt()
    nps = sorted({r["np"] for r in select(R, item=2, method="paper")})
    mats = sorted({r["case"] for r in select(R, item=2)})
    cmap = plt.get_cmap("viridis")
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.3), sharey=True)
    case = "Random_4" if "Random_4" in mats else mats[0]
    for ax, meth, title in ((axes[0], "paper", f"paper's DE, {case}, seed 0"),
                            (axes[1], "default", f"vhfit default, {case}, seed 0")):
        for i, npop in enumerate(nps):
            rs = select(R, item=2, method=meth, np=npop, case=case, seed=0)
            if not rs:
                continue
            h = rs[0]["history"]
            t = [p[1] for p in h] + [rs[0]["wall"]]
            b = [max(p[2], FLOOR) for p in h] + [max(rs[0]["rmsape"], FLOOR)]
            ax.step(t, b, where="post", color=cmap(i / max(1, len(nps) - 1)), label=f"NP {npop}")
        ax.set(xscale="log", yscale="log", xlabel="wall time (s)", title=title)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    axes[0].set_ylabel("best RMSAPE (%)")
    fig.suptitle("Best error against time for each population size (cf. paper Fig. 8); "
                 "vhfit's final point includes the polish", fontsize=10)
    fig.tight_layout()
    fig.savefig(path_hist, dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.3), sharey=True)
    for ax, meth, title in ((axes[0], "paper", "paper's DE (semifree, N = 3)"),
                            (axes[1], "default", "vhfit default (N = 3)")):
        for case in mats:
            y = [med([max(r["rmsape"], FLOOR) for r in select(R, item=2, method=meth, np=npop,
                                                             case=case)]) for npop in nps]
            ax.plot(nps, y, marker="o", ms=3, alpha=0.6, label=case)
        y = [med([max(r["rmsape"], FLOOR) for r in select(R, item=2, method=meth, np=npop)])
             for npop in nps]
        ax.plot(nps, y, color="k", lw=2.5, label="median of all")
        ax.set(yscale="log", xlabel="population size NP", title=title)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("final RMSAPE (%), median over seeds")
    fig.suptitle("Final error against population size (cf. paper Fig. 9)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path_final, dpi=110)
    plt.close(fig)


def fig_sebs_gelatin(R, path):
    plt = _plt()
    fig, axes = plt.subplots(1, 3, figsize=(13, 4), sharey=False)
    for ax, case, item in ((axes[0], "SEBS", 4), (axes[1], "gelatin", 4),
                           (axes[2], "gelatin-reported", 5)):
        for meth, st, lab in (("default", "default", "vhfit default (free)"),
                              ("vhfit", "semifree", "vhfit semifree")):
            rs = select(R, item=item, case=case, method=meth)
            ns = sorted({r["n"] for r in rs})
            y = [med([max(r["rmsape"], FLOOR) for r in rs if r["n"] == n]) for n in ns]
            ax.plot(ns, y, marker="o", color=COLORS[st], label=lab)
        rs = select(R, item=item, case=case, method="paper")
        if rs:
            ax.scatter([rs[0]["n"]], [med([max(r["rmsape"], FLOOR) for r in rs])], color="k",
                       marker="s", zorder=5, label="paper's DE (its setting)")
        if case == "gelatin-reported":
            ax.axhline(PAPER["gelatin"]["rmsape"], color="gray", ls="--",
                       label="paper on measured gelatin (19.69 %)")
        ax.set(yscale="log", xlabel="number of Prony terms N", title=case + " stand-in")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("final RMSAPE (%), median over seeds")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def single_term_ratio(strain, k, a_over_eps, law_shape=(0.0, 1.0)):
    """σ(k r)/σ(r) of one Prony term alone (E∞ → 0) at one strain, per a = |r| τ."""
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    r = -1.0
    tau = a_over_eps * abs(strain) / abs(r)
    b = m.batch([vhfit.History.constant_rate([strain], r),
                 vhfit.History.constant_rate([strain], k * r)], measure="true")
    _, H = b.shape_columns(np.array([law_shape]), tau[None, :])
    return H[0, :, 1] / H[0, :, 0]


def fig_gelatin_limit(R, path):
    from vhfit.diagnostics import rate_ratio_bounds

    plt = _plt()
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    ax = axes[0]
    a = np.logspace(-4, 3, 300)
    for eps, ls in ((-0.01, ":"), (-0.25, "--"), (-0.5, "-")):
        ax.plot(a, single_term_ratio(eps, 2.0, a), ls=ls, color="tab:blue",
                label=f"one Prony term, ε = {eps:g}")
    ax.plot(a, 2 * a * -np.expm1(-1 / (2 * a)) / (a * -np.expm1(-1 / a)), color="tab:orange",
            lw=1, label="small-strain closed form")
    ax.axhline(2.0, color="k", lw=0.8)
    ax.set(xscale="log", xlabel="|r| τ / |ε|  (viscous ← → elastic)",
           ylabel="σ(2r) / σ(r) at the same strain", ylim=(0.9, 2.2),
           title="(a) doubling the rate at most doubles the stress")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    # (b) data ratio against the model's bound, gelatin as reported and Table 6
    ax = axes[1]
    rep = gelatin_reported_curves()
    tab6 = case_curves("gelatin")[0]
    eps = np.asarray(rep[1].target_strain)
    for cs, ls, lab in ((rep, "-", "as reported"), (tab6, ":", "Table 6 model")):
        for c, col in ((cs[2], "tab:purple"), (cs[3], "tab:red")):
            ax.plot(-eps, np.asarray(c.target_stress) / np.asarray(cs[1].target_stress), ls=ls,
                    color=col, label=f"{lab}: σ({c.strain_rate:g}) / σ(-2500)")
    for c, col in ((rep[2], "tab:purple"), (rep[3], "tab:red")):
        _, hi = rate_ratio_bounds("mooney_rivlin", eps, -2500.0, c.strain_rate)
        ax.plot(-eps, hi, color=col, lw=3, alpha=0.35,
                label=f"model bound ×{c.strain_rate / -2500:.3g}")
    best = _best_fit(R, "gelatin-reported")
    if best is not None:
        m = vhfit.ViscoHyperelastic("mooney_rivlin", best["n_eff"])
        s1 = m.stress(best["params"], strain=eps, strain_rate=-2500.0)
        for c, col in ((rep[2], "tab:purple"), (rep[3], "tab:red")):
            s = m.stress(best["params"], strain=eps, strain_rate=c.strain_rate)
            ax.plot(-eps, s / s1, ls="--", color=col, lw=1,
                    label=f"best fit (N = {best['n']}): σ({c.strain_rate:g}) / σ(-2500)")
    ax.set(xlabel="|engineering strain|", ylabel="stress ratio at the same strain",
           title="(b) gelatin's rate stiffening against the bound")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6)
    # (c) the best fit to the reported-stiffening stand-in
    ax = axes[2]
    if best is not None:
        m = vhfit.ViscoHyperelastic("mooney_rivlin", best["n_eff"])
        for c, col in zip(rep[1:], ("tab:green", "tab:purple", "tab:red")):
            e = np.asarray(c.target_strain)
            ax.plot(-e, -np.asarray(c.target_stress), "o", color=col, ms=4,
                    label=f"stand-in {c.strain_rate:g} 1/s")
            ee = np.linspace(e[0] / 5, e[-1], 60)
            ax.plot(-ee, -m.stress(best["params"], strain=ee, strain_rate=c.strain_rate,
                                   measure="engineering"), color=col)
        ax.set(xlabel="|engineering strain|", ylabel="|engineering stress| (MPa)",
               title=f"(c) best fit: RMSAPE {best['rmsape']:.3g} % (lines)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _best_fit(R, case):
    rs = [r for r in R if r.get("case") == case and "error" not in r and r["method"] != "paper"]
    return min(rs, key=lambda r: r["rmsape"]) if rs else None


# --------------------------------------------------------------------- the doc
def _cells_item1(R, ours_method):
    out = []
    for st in STRATEGIES:
        for n in sorted({r["n"] for r in select(R, item=1)}):
            for case in sorted({r["case"] for r in select(R, item=1)}):
                p = select(R, item=1, method="paper", strategy=st, n=n, case=case)
                o = (select(R, item=1, method="vhfit", strategy=st, n=n, case=case)
                     if ours_method == "vhfit" else
                     select(R, item=1, method="default", n=n, case=case))
                if p and o:
                    out.append(dict(label=f"{st}, N = {n}, {case}", strategy=st, n=n, case=case,
                                    **compare(p, o)))
    return out


def _cells_other(R):
    out = []
    for npop in sorted({r["np"] for r in select(R, item=2, method="paper")}):
        for case in sorted({r["case"] for r in select(R, item=2)}):
            p = select(R, item=2, method="paper", np=npop, case=case)
            o = select(R, item=2, method="default", np=npop, case=case)
            if p and o:
                out.append(dict(item=2, label=f"NP = {npop}, {case}", **compare(p, o)))
    p = [r for r in select(R, item=3, method="paper") if r.get("noise_seed") == 0]
    o = [r for r in select(R, item=3, method="default") if r.get("noise_seed") == 0]
    if p and o:
        out.append(dict(item=3, label="Random_3 ±5 % noise, 5 trials", **compare(p, o)))
    p = select(R, item="1c", method="paper", strategy="semifree")
    o = select(R, item=3, method="default", tag="original")
    if p and o:
        out.append(dict(item=3, label="Random_3 noise-free (the paper's standard case)",
                        **compare(p, o)))
    for case in ("SEBS", "gelatin"):
        p = select(R, item=4, method="paper", case=case)
        if p:
            o = select(R, item=4, method="default", case=case, n=p[0]["n"])
            if o:
                out.append(dict(item=4, label=f"{case} stand-in, N = {p[0]['n']}",
                                **compare(p, o)))
    p = select(R, item=5, method="paper")
    if p:
        o = select(R, item=5, method="default", n=p[0]["n"])
        if o:
            out.append(dict(item=5, label=f"gelatin (reported stiffening), N = {p[0]['n']}",
                            **compare(p, o)))
    return out


def _count(cells):
    c = {"win": 0, "win (slower)": 0, "tie": 0, "tie (slower)": 0, "loss": 0}
    for x in cells:
        c[x["verdict"]] += 1
    return c


def _cell_row(x):
    return [x["label"], fmt(x["pe"]), fmt(x["pw"], 2), fmt(x["oe"]), fmt(x["ow"], 2),
            fmt(x["tt"], 2), x["verdict"]]


CELL_HEAD = ["cell", "paper's DE RMSAPE %", "its wall s", "vhfit RMSAPE %", "vhfit wall s",
             "vhfit s to paper's error", "verdict"]


def section_setup(meta):
    la = meta["load"]
    rows = [
        ["command", f"`{meta['command']}`"],
        ["date", meta["date"]],
        ["machine", f"{meta['cpu']}, {meta['cores']} cores (shared with other work)"],
        ["load average during the run (1 min)",
         f"min {la[0]:.1f}, median {la[1]:.1f}, max {la[2]:.1f} (2 = both cores busy)"],
        ["software", meta["versions"]],
        ["worker processes", f"{meta['workers']} (NUMBA_NUM_THREADS = {meta['threads']} each)"],
        ["calibrations", f"{meta['n_runs']} ({meta['n_failed']} failed)"],
        ["**total wall time**", f"**{meta['wall'] / 60:.1f} min**"],
    ]
    if meta.get("cpu_total"):
        rows.append(["CPU time of all calibrations",
                     f"{meta['cpu_total'] / 60:.1f} min, i.e. about "
                     f"{meta['cpu_total'] / 60 / meta['workers']:.1f} min of wall time on "
                     f"{meta['workers']} idle cores"])
    return table(["", ""], rows, ["l", "l"])


def section_methods(meta):
    a = meta["args"]
    return f"""\
Three ways of calibrating are compared, on the same evaluator of the corrected Eq. 19:

- **paper's DE** — `calibrate(method="full", tau_strategy=S, decades_below=2,
  polish=False, de_options={{"updating": "immediate", "init": …}})`: all-parameter
  differential evolution, rand/1/bin, F = 0.8, CR = 0.7, immediate updating (each trial
  replaces its parent at once, as in the Rodríguez-Mier code the paper builds on; item 1c
  also shows calibrate's default batched variant, one evaluation batch per generation,
  which is faster per generation), the paper's four stopping criteria, τ bounds of Eq. 22 and the
  modulus bounds of docs/theory.md §11, and an initial Latin-hypercube population of exactly NP
  individuals (NP = 50 for the random materials as in the paper's Table 1, 60 for SEBS
  and gelatin as in its Tables 2-3). **Budget:** it is capped at
  **{a['paper_gens']} generations in items 1-2** and at {a['long_gens']} generations in
  item 1c (the standard case run to the paper's own criteria) and items 3-4
  ({a['long_gens'] // 4} in item 5), with a safety limit of {a['max_paper_time']:g} s per
  run. The paper's standard case needed 1303 generations, so in items 1-2 the paper's DE
  is stopped well before its own criteria would stop it: its errors there are those of a
  budget-limited run, not its converged errors (items 1c, 3 and 4 show runs that end by
  the paper's criteria or near the paper's own generation counts).
- **vhfit** — `calibrate(method="separable", tau_strategy=S, decades_below=2)`: our
  method on exactly the paper's search space for strategy S (variable projection: DE over
  the Mooney–Rivlin shape and log τ, non-negative least squares for the moduli, then a
  least-squares polish).
- **vhfit default** — `calibrate(curves, n_prony=N, seed=s)` with every default: free τ
  over Eq. 22's range widened by one decade below, population 64 (Sobol start), polish.

All runs use `uncertainty=False` (the 95 % intervals are not needed here) and are
repeated over {a['seeds']} seeds per cell unless stated. Errors are Eq. 20 (RMSAPE, %) on
the 10 objective points of each curve. Times are wall-clock seconds of one calibration in
one worker process, on a machine shared with other work (see the load above): they scale
with the load, the generation counts and errors do not. The data are synthetic: the
random materials of `benchmarks/cases.py` (Mooney–Rivlin + 3 Prony terms at −1, −10,
−100, −1000 1/s) and curves generated from the paper's published SEBS and gelatin
parameters at the paper's rates — stand-ins for the unpublished experimental curves,
so a perfect fit exists and error levels cannot be compared with the paper's
experimental 7.48 % and 19.69 %; generations and times can.
"""


def _strategy_medians(R, meth, nmin=2):
    out = {}
    for st in STRATEGIES:
        rs = [r for r in select(R, item=1, method=meth, strategy=st) if r["n"] >= nmin]
        out[st] = med([r["rmsape"] for r in rs])
    return out


def _cell_winners(R, meth, nmin=2):
    """Per (N >= nmin, material): which strategy has the lowest seed-median error."""
    wins = dict.fromkeys(STRATEGIES, 0)
    cases_ = sorted({r["case"] for r in select(R, item=1)})
    for n in sorted({r["n"] for r in select(R, item=1)}):
        if n < nmin:
            continue
        for case in cases_:
            m = {st: med([r["rmsape"] for r in select(R, item=1, method=meth, strategy=st, n=n,
                                                      case=case)]) for st in STRATEGIES}
            if all(np.isfinite(v) for v in m.values()):
                wins[min(m, key=m.get)] += 1
    return wins


def section_item1(R, meta, figs):
    G = meta["args"]["paper_gens"]
    ns = sorted({r["n"] for r in select(R, item=1)})
    rows = []
    for st in STRATEGIES:
        for n in ns:
            p = select(R, item=1, method="paper", strategy=st, n=n)
            o = select(R, item=1, method="vhfit", strategy=st, n=n)
            conv = sum(1 for r in p if r["stop"] != "maxiter")
            rows.append([f"{st}, N = {n}", spread([r["rmsape"] for r in p]),
                         fmt(med([best_at(r, G // 3) for r in p])),
                         fmt(med([r["nit"] for r in p]), 4), f"{conv}/{len(p)}",
                         fmt(med([r["wall"] for r in p]), 2),
                         spread([r["rmsape"] for r in o]), fmt(med([r["wall"] for r in o]), 2)])
    for n in ns:
        o = select(R, item=1, method="default", n=n)
        rows.append([f"vhfit default, N = {n}", "", "", "", "", "",
                     spread([r["rmsape"] for r in o]), fmt(med([r["wall"] for r in o]), 2)])
    t1 = table(["strategy, N", "paper's DE RMSAPE % median [quartiles]",
                f"… after {G // 3} gen.", "gen.", "stopped by its criteria", "wall s",
                "vhfit RMSAPE % median [quartiles]", "vhfit wall s"], rows)

    # the standard case run to the paper's own criteria (1c)
    cv = {st: select(R, item="1c", method="paper", strategy=st) for st in STRATEGIES}
    ov = {st: select(R, item=1, method="vhfit", strategy=st, n=3, case="Random_3")
          for st in STRATEGIES}
    lvl = 1.0
    rows_c = []
    for st in STRATEGIES:
        for meth, lab in (("paper", "immediate (the paper's)"),
                          ("paper-batched", "batched (calibrate's default)")):
            p, o = select(R, item="1c", method=meth, strategy=st), ov[st]
            if not p:
                continue
            tt = [time_to(r, lvl) for r in p]
            e = [r["rmsape"] for r in p]
            ok = [t for t in tt if np.isfinite(t)]
            rows_c.append([f"{st}, {lab}", f"{fmt(med(e))} [{_rng(e, 3)}]",
                           fmt(med([r["nit"] for r in p]), 4),
                           fmt(med([r["wall"] for r in p]), 3),
                           f"{len(ok)}/{len(tt)}, {fmt(med(ok), 2)} s",
                           "; ".join(sorted({r["stop"] for r in p})),
                           fmt(med([r["rmsape"] for r in o])) if meth == "paper" else "",
                           fmt(med([r["wall"] for r in o]), 2) if meth == "paper" else ""])
    t1c = table(["strategy, updating", "paper's DE RMSAPE % median [range]", "gen.", "wall s",
                 f"runs reaching {lvl:g} %, median time", "stopped by",
                 "vhfit RMSAPE % (same bounds)", "vhfit wall s"], rows_c)
    cm = {st: med([r["rmsape"] for r in cv[st]]) for st in STRATEGIES}
    cw = {st: med([r["wall"] for r in cv[st]]) for st in STRATEGIES}
    t1 = {st: [time_to(r, lvl) for r in cv[st]] for st in STRATEGIES}
    t1p = {st: f"{sum(np.isfinite(v))}/{len(v)} runs, median {fmt(float(np.median(v)), 2)} s"
           for st, v in t1.items()}  # median with inf for runs that never got there
    speed = float(np.median(t1["free"]) / np.median(t1["semifree"]))

    # claims
    pm, om = _strategy_medians(R, "paper"), _strategy_medians(R, "vhfit")
    pw, ow = _cell_winners(R, "paper"), _cell_winners(R, "vhfit")
    best_p, best_o = min(pm, key=pm.get), min(om, key=om.get)
    best_c = min(cm, key=cm.get) if all(np.isfinite(v) for v in cm.values()) else None
    n1 = {m: (med([r["rmsape"] for r in select(R, item=1, method=m, strategy="free", n=1)]),
              med([r["rmsape"] for r in select(R, item=1, method=m, strategy="semifree", n=1)]))
          for m in ("paper", "vhfit")}
    nmax = max(ns)
    fixed_nmax = {m: med([r["rmsape"] for r in select(R, item=1, method=m, strategy="fixed",
                                                      n=nmax)]) for m in ("paper", "vhfit")}
    free3 = med([r["rmsape"] for r in select(R, item=1, method="vhfit", strategy="free", n=3)])

    def yes(b):
        return "**reproduced**" if b else "**not reproduced**"

    def lst(d, dd=3):
        return ", ".join(f"{k} {fmt(v, dd)}" for k, v in d.items())

    claims = [
        ["semifree reaches the lowest error (Figs. 6-7)",
         f"capped, N ≥ 2, medians: {lst(pm)} %; lowest in cells: "
         + ", ".join(f"{k} {v}" for k, v in pw.items())
         + f". To its criteria (1c): {lst(cm)} %",
         f"N ≥ 2, medians: {lst(om)} %; lowest in cells: "
         + ", ".join(f"{k} {v}" for k, v in ow.items()),
         f"{yes(best_p == 'semifree')} with the capped paper's DE, "
         f"{yes(best_c == 'semifree')} when it runs to its criteria (1c, best: {best_c}); "
         f"with vhfit the best is **{best_o}**"],
        ["fixed τ needs the shortest times (Fig. 6)",
         f"to its criteria (1c), median wall s: {lst(cw)}",
         "median wall s: " + lst({k: med([r["wall"] for r in select(R, item=1, method="vhfit",
                                                                    strategy=k)])
                                  for k in STRATEGIES}, 2),
         yes(min(cw, key=cw.get) == "fixed")
         + (" (fixed has only the moduli to search)" if min(cw, key=cw.get) == "fixed" else
            f" (fastest: {min(cw, key=cw.get)})")],
        ["semifree converges 10-100× faster than free (Discussion)",
         f"to its criteria (1c): free/semifree wall = {fmt(cw['free'] / cw['semifree'], 3)}; "
         f"time to reach {lvl:g} %: free {t1p['free']}, semifree {t1p['semifree']}; final "
         f"error free/semifree = {fmt(cm['free'] / cm['semifree'], 3)}",
         "", "**partly reproduced**" + f" (×{fmt(speed, 2)} sooner to {lvl:g} %, not 10×)"
         if 1.2 < speed < 10 else
         yes(speed >= 10) + (f" in the sense that most free runs never reach {lvl:g} % "
                             "within the budget; to the generation cap both take the "
                             "same time" if not np.isfinite(speed) else "")],
        ["free and semifree give the same error at N = 1 (Fig. 7)",
         f"free {fmt(n1['paper'][0])} %, semifree {fmt(n1['paper'][1])} %",
         f"free {fmt(n1['vhfit'][0])} %, semifree {fmt(n1['vhfit'][1])} %",
         yes(abs(n1["vhfit"][0] - n1["vhfit"][1]) <= 0.01 * n1["vhfit"][0])
         + " (identical bounds for one term)"],
        ["fixed τ needs more terms for the same error (Discussion)",
         f"fixed at N = {nmax}: {fmt(fixed_nmax['paper'])} %",
         f"fixed at N = {nmax}: {fmt(fixed_nmax['vhfit'])} %; free at N = 3: {fmt(free3)} %",
         yes(fixed_nmax["vhfit"] > 10 * max(free3, 1e-12))],
    ]
    t2 = table(["the paper's claim", "paper's DE here", "vhfit here", "verdict"], claims,
               ["l", "l", "l", "l"])
    cells_a = _cells_item1(R, "vhfit")
    cells_b = _cells_item1(R, "default")
    ca, cb = _count(cells_a), _count(cells_b)
    det = table(CELL_HEAD, [_cell_row(x) for x in cells_a])
    txt = f"""\
## 1. τ strategies × number of Prony terms (paper Figs. 6-7)

{len({r['case'] for r in select(R, item=1)})} random material(s) × three strategies ×
N = {', '.join(map(str, ns))} × {meta['args']['seeds']} seed(s), each with the paper's DE
(NP = 50, capped at {G} generations) and with vhfit on the same τ bounds; plus vhfit's
default (free τ, one more decade below Eq. 22). Medians and quartiles are over
materials × seeds; "stopped by its criteria" counts the paper's-DE runs that ended by the
paper's own criteria before the cap.

{t1}

![final error against time]({figs['fig6']})

![final error against N]({figs['fig7']})

**1c. The standard case run to the paper's own stopping criteria** (Random_3, N = 3,
NP = 50, up to {meta['args']['long_gens']} generations, {meta['args']['seeds']} seeds per
strategy), with the paper's immediate updating and with calibrate's batched default:
under the generation cap above every run of the paper's DE takes about the same time, so
the paper's time claims are tested here, where runs end by the paper's criteria (or near
its 1303 generations). The claims below use the immediate (paper's) rows.

{t1c}

**The paper's claims, tested:**

{t2}


**Cell by cell** (strategy × N × material, medians over seeds; "vhfit s to paper's error" is
the time vhfit's run needed to get below the paper's DE's final error, from its
per-generation history, or its whole wall time if only the polish got it there):
vhfit on the same bounds wins {ca['win']}, wins but later than the capped paper's DE
stopped {ca['win (slower)']}, ties {ca['tie'] + ca['tie (slower)']}, loses {ca['loss']} of
{len(cells_a)} cells; our full default (free τ) against the paper's DE with each strategy:
wins {cb['win']}, later {cb['win (slower)']}, ties {cb['tie'] + cb['tie (slower)']},
loses {cb['loss']} of {len(cells_b)}.

<details><summary>all {len(cells_a)} cells, vhfit on the same bounds</summary>

{det}

</details>
"""
    return txt, dict(pm=pm, om=om, best_p=best_p, best_o=best_o, cells_a=cells_a,
                     cells_b=cells_b, n1=n1, fixed_nmax=fixed_nmax, free3=free3, cm=cm, cw=cw,
                     best_c=best_c)


def _plateau(nps, meds, factor=2.0):
    """Smallest NP from which every larger NP is within ``factor`` of the best median."""
    best = min(meds)
    for i, npop in enumerate(nps):
        if all(m <= factor * max(best, 1e-12) for m in meds[i:]):
            return npop
    return nps[-1]


def section_item2(R, meta, figs):
    G = meta["args"]["paper_gens"]
    nps = sorted({r["np"] for r in select(R, item=2, method="paper")})
    rows = []
    pmed, omed, ogen, owall = [], [], [], []
    for npop in nps:
        p = select(R, item=2, method="paper", np=npop)
        o = select(R, item=2, method="default", np=npop)
        pmed.append(med([r["rmsape"] for r in p]))
        omed.append(med([r["rmsape"] for r in o]))
        rows.append([npop, spread([r["rmsape"] for r in p]), fmt(med([r["nit"] for r in p]), 4),
                     fmt(med([r["wall"] for r in p]), 2), spread([r["rmsape"] for r in o]),
                     fmt(med([r["nit"] for r in o]), 4), fmt(med([r["wall"] for r in o]), 2)])
        ogen.append(med([r["nit"] for r in o]))
        owall.append(med([r["wall"] for r in o]))
    t = table(["NP", "paper's DE RMSAPE % median [quartiles]", "gen.", "wall s",
               "vhfit default RMSAPE %", "gen.", "wall s"], rows)
    mats = sorted({r["case"] for r in select(R, item=2)})
    per = []
    for case in mats:
        pm = [med([r["rmsape"] for r in select(R, item=2, method="paper", np=n, case=case)])
              for n in nps]
        om = [med([r["rmsape"] for r in select(R, item=2, method="default", np=n, case=case)])
              for n in nps]
        per.append([case, _plateau(nps, pm), fmt(min(pm)), _plateau(nps, om), fmt(min(om))])
    t2 = table(["material", "paper's DE: NP from which error is within 2× of its best",
                "its best median %", "vhfit default: same", "its best median %"], per)
    pl_p, pl_o = _plateau(nps, pmed), _plateau(nps, omed)
    hard = max(per, key=lambda r: r[1])
    easy = min(per, key=lambda r: r[1])
    txt = f"""\
## 2. Population size (paper Figs. 8-9)

The paper's standard case (semifree, N = 3) with its DE at NP ∈ {{{', '.join(map(str, nps))}}}
(exact population sizes; capped at {G} generations), and vhfit's default with
`popsize=NP` (also exact), five materials × {meta['args']['seeds']} seeds.

{t}

{t2}

![best error against time per NP]({figs['fig8']})

![final error against NP]({figs['fig9']})

**The paper's claim** — "less than 60 individuals are not enough … at 60 individuals we
find an asymptote; Random_1 achieved good results with only 20 individuals and Random_4
needs at least 60": with the paper's DE here the median error over all materials is within
2× of its best from NP = **{pl_p}** on (best median {fmt(min(pmed))} % at
NP = {nps[int(np.argmin(pmed))]}). Under a fixed generation cap a larger population gets
fewer generations' worth of progress per evaluation, so this measures the paper's DE at
equal generations, as the paper's Fig. 8 does at equal time; the paper ran each NP to its
stopping criteria. Per material, the paper's DE needs the largest population on
{hard[0]} (NP = {hard[1]}) and the smallest on {easy[0]} (NP = {easy[1]}); the paper named
Random_4 as the hardest (60) and Random_1 as the easiest (20). Wall times in this table
also reflect the machine's load at the moment each run ran (runs are scheduled longest
first), so compare generations and errors. With vhfit the population hardly matters:
from NP = **{pl_o}** the median is within 2× of its best ({fmt(min(omed))} %), because DE
only searches the 4 nonlinear parameters (shape and three log τ) and the moduli are
solved exactly. Its smallest population (NP = {nps[0]}) needs {fmt(ogen[0], 3)} generations
and {fmt(owall[0], 2)} s (medians) where NP = {nps[-1]} needs {fmt(ogen[-1], 3)} and
{fmt(owall[-1], 2)} s.
"""
    return txt, dict(pl_p=pl_p, pl_o=pl_o, pmed=pmed, omed=omed, nps=nps)


def section_item3(R, meta):
    ptr = sorted([r for r in select(R, item=3, method="paper") if r.get("noise_seed") == 0],
                 key=lambda r: r["seed"])
    otr = sorted([r for r in select(R, item=3, method="default") if r.get("noise_seed") == 0],
                 key=lambda r: r["seed"])
    po = select(R, item="1c", method="paper", strategy="semifree")
    oo = select(R, item=3, method="default", tag="original")
    floor = otr[0]["floor"] if otr else float("nan")
    pr3 = PAPER["random3"]
    rows = [["Random_3 (original)", f"{pr3['rmsape']} / {pr3['gens']} / {pr3['time']}",
             f"{fmt(med([r['rmsape'] for r in po]))} / {fmt(med([r['nit'] for r in po]), 4)} / "
             f"{fmt(med([r['wall'] for r in po]), 2)} s",
             ", ".join(sorted({r["stop"] for r in po})),
             f"{fmt(med([r['rmsape'] for r in oo]))} / {fmt(med([r['nit'] for r in oo]), 4)} / "
             f"{fmt(med([r['wall'] for r in oo]), 2)} s", "0",
             fmt(med([r["rel_err"] for r in oo]))]]
    for i in range(max(len(ptr), len(otr))):
        pp = PAPER["noise"]["rows"][i] if i < 5 else None
        p = ptr[i] if i < len(ptr) else None
        o = otr[i] if i < len(otr) else None
        rows.append([
            f"±5 % noise, trial {i + 1}",
            f"{pp[0]} / {pp[1]} / {pp[2]} min" if pp else "",
            f"{fmt(p['rmsape'], 5)} / {p['nit']} / {fmt(p['wall'], 2)} s" if p else "",
            p["stop"] if p else "",
            f"{fmt(o['rmsape'], 5)} / {o['nit']} / {fmt(o['wall'], 2)} s" if o else "",
            fmt(floor, 5),
            f"{fmt(o['noisy_rel_err'], 2)} (N_eff {o['n_eff']}); paper's DE "
            f"{fmt(p['noisy_rel_err'], 2)}" if o and p else "",
        ])
    t = table(["run", "paper: RMSAPE % / gen. / time", "paper's DE here: RMSAPE % / gen. / wall",
               "its stop", "vhfit default: RMSAPE % / gen. / wall", "noise floor %",
               "worst relative parameter error"], rows)
    real = sorted(select(R, item=3, tag="realisation"), key=lambda r: r["noise_seed"])
    t2 = ""
    if real:
        rr = [[r["noise_seed"] - 100 + 1, fmt(r["floor"], 4), fmt(r["rmsape"], 4),
               fmt(r["rmsape"] / r["floor"], 3), r["n_eff"], fmt(r["noisy_rel_err"], 2)]
              for r in real]
        t2 = ("Further noise realisations (vhfit default; one seed each):\n\n"
              + table(["realisation", "noise floor %", "vhfit RMSAPE %", "ratio", "N_eff",
                       "worst relative parameter error"], rr))
    pe = med([r["rmsape"] for r in ptr])
    oe = med([r["rmsape"] for r in otr])
    pspread = (max(r["rmsape"] for r in ptr) - min(r["rmsape"] for r in ptr)) if ptr else 0
    same = abs(pe - oe) <= 0.02 * oe
    if oe < floor:
        r1 = (f"the best fits of the noisy data end **below the noise floor** (vhfit median "
              f"{fmt(oe, 4)} %, paper's DE median {fmt(pe, 4)} %, floor {fmt(floor, 4)} %): "
              "the error level of about 3 % is set by the noise itself (uniform ±5 % noise "
              "has an RMS of 5/√3 ≈ 2.9 % of each point; Eq. 20 divides by the curve's mean "
              "stress, which weighs the large-strain points more), so \"noise raises the "
              "error to about 3 %\" is **reproduced**.")
    else:
        r1 = (f"vhfit ends at {fmt(oe, 4)} % against a noise floor of {fmt(floor, 4)} %, the "
              f"paper's DE at {fmt(pe, 4)} %.")
    if same:
        r2 = (f"The paper explains its 3.12 % by runs stopping \"in local minima\". Here the "
              f"paper's DE and vhfit end at the same error (within 2 %; spread of the paper's "
              f"DE over trials {fmt(pspread, 2)} %), at or below the truth's error: every run "
              "found (nearly) the global optimum of the noisy problem. We **disagree** with "
              "the local-minimum explanation: the 3 % is the noise, not the optimizer.")
    else:
        r2 = (f"The paper's DE ends {fmt(pe / oe, 3)}× vhfit's error (spread over trials "
              f"{fmt(pspread, 2)} %): it stops short of the optimum vhfit finds, consistent "
              "with the paper's explanation that its noisy runs stop early (its best-mean "
              "gap criterion ends them).")
    allfit = [r["rmsape"] for r in otr[:1] + real]
    allfloor = [r["floor"] for r in otr[:1] + real]
    if allfit:
        lo_f, hi_f = min(allfit), max(allfit)
        r2 += (f" Over {len(allfit)} noise realisations the best fits span {fmt(lo_f, 3)}–"
               f"{fmt(hi_f, 3)} % (noise floors {fmt(min(allfloor), 3)}–"
               f"{fmt(max(allfloor), 3)} %)"
               + (", a range that contains the paper's 3.117–3.120 %: its Table 4 is what the "
                  "global optimum of a ±5 %-noisy Random_3 looks like."
                  if lo_f <= 3.12 <= hi_f else "."))
    txt = f"""\
## 3. Noise (paper Table 4)

Random_3 with ±5 % uniform multiplicative noise on every point (one noisy data set, five
trials = five seeds, as in the paper, whose five errors agree to 0.003 %), and the
noise-free original (the paper's standard case). The **noise floor** is the RMSAPE of the
true parameters on the same noisy data: a fit below it has fitted part of the noise.
The paper's DE runs here up to {meta['args']['long_gens']} generations, i.e. normally to
its own stopping criteria (column "its stop").

{t}

{t2}

Reading: {r1} {r2} The recovered parameters move by the amount in the last column: with
noise, some of the three Prony terms are no longer identifiable (vhfit prunes a term whose
modulus comes out zero: N_eff).
"""
    return txt, dict(pe=pe, oe=oe, floor=floor, po=po, oo=oo, ptr=ptr, otr=otr)


def _eq22_low(rates, below=2):
    return math.log10(1.0 / max(abs(r) for r in rates)) - below


def _param_rows(truth, runs, paper_runs):
    rows = []
    pbest = min(paper_runs, key=lambda r: r["rmsape"]) if paper_runs else None
    for k, v in truth.items():
        vals = [r["params"].get(k) for r in runs if k in r["params"]]
        m = med(vals) if vals else float("nan")
        e = abs(m - v) / abs(v) if v else abs(m)
        pv = pbest["params"].get(k) if pbest and pbest["n_eff"] == len(truth) // 2 - 1 else None
        pe = (abs(pv - v) / abs(v) if v else abs(pv)) if pv is not None else None
        show = (lambda x: f"10^{math.log10(x):.3f}") if k.startswith("tau") else fmt
        rows.append([k, show(v) if v else "0", show(m) if np.isfinite(m) and m > 0 else fmt(m),
                     fmt(e, 2), show(pv) if pv else "–", fmt(pe, 2) if pe is not None else "–"])
    return rows


def section_item4(R, meta, figs):
    rows = []
    semi_better, compared = {}, {}
    for case in ("SEBS", "gelatin"):
        ns = sorted({r["n"] for r in select(R, item=4, case=case, method="default")})
        semi_better[case] = 0
        for n in ns:
            d = select(R, item=4, case=case, method="default", n=n)
            s = select(R, item=4, case=case, method="vhfit", n=n)
            es, ed = med([r["rmsape"] for r in s]), med([r["rmsape"] for r in d])
            if max(es, ed) > 1e-3:  # below 1e-3 % both are exact fits: no ranking
                semi_better[case] = semi_better.get(case, 0) + (es < 0.99 * ed)
                compared[case] = compared.get(case, 0) + 1
            rows.append([f"{case}, N = {n}", spread([r["rmsape"] for r in d]),
                         fmt(med([r["wall"] for r in d]), 2), fmt(med([r["n_eff"] for r in d]), 2),
                         spread([r["rmsape"] for r in s]), fmt(med([r["wall"] for r in s]), 2),
                         fmt(med([r["n_eff"] for r in s]), 2)])
        p = select(R, item=4, case=case, method="paper")
        if p:
            rows.append([f"{case}, N = {p[0]['n']}, **paper's DE** (semifree, NP = 60)",
                         spread([r["rmsape"] for r in p]), fmt(med([r["wall"] for r in p]), 2),
                         fmt(med([r["n_eff"] for r in p]), 2),
                         f"gen. {fmt(med([r['nit'] for r in p]), 4)}; stop: "
                         + ", ".join(sorted({r["stop"] for r in p})), "", ""])
    t = table(["case, N", "vhfit default RMSAPE %", "wall s", "N_eff", "vhfit semifree RMSAPE %",
               "wall s", "N_eff"], rows)
    ptabs = []
    for case, truth in (("SEBS", cases.SEBS), ("gelatin", cases.GELATIN)):
        n = cases.n_prony(truth)
        runs = select(R, item=4, case=case, method="default", n=n)
        if not runs:
            continue
        pr = select(R, item=4, case=case, method="paper")
        ptabs.append(f"**{case}** (published = the paper's Table {5 if case == 'SEBS' else 6}, "
                     f"N = {n}; vhfit default: median over seeds; paper's DE: its best run, "
                     "where its effective N matches):\n\n"
                     + table(["parameter", "published", "vhfit default", "rel. error",
                              "paper's DE", "rel. error"], _param_rows(truth, runs, pr)))
    lows = {c: _eq22_low(r) for c, r in (("SEBS", cases.SEBS_RATES),
                                          ("gelatin", cases.GELATIN_RATES))}
    t1s = {"SEBS": math.log10(cases.SEBS["tau1"]), "gelatin": math.log10(cases.GELATIN["tau1"])}
    edge = all(abs(t1s[c] - lows[c]) < 0.01 for c in lows)
    gel5 = select(R, item=4, case="gelatin", method="default", n=5)
    txt = f"""\
## 4. SEBS and gelatin (paper Tables 5-6)

Curves generated from the published parameters at the paper's rates (stand-ins for the
unpublished experimental curves: a perfect fit exists), calibrated with N = 1..5 by
vhfit's default (free τ) and by vhfit with semifree τ (default bounds), and by the paper's
DE in the paper's own setting (SEBS: 4 semifree terms; gelatin: 5 semifree terms, which
the paper then pruned to 2), up to {meta['args']['long_gens']} generations.

{t}

![error against N for SEBS and gelatin]({figs['sebs']})

{chr(10).join(p + chr(10) for p in ptabs)}
- The paper found 4 terms best for SEBS and, for gelatin, 5 terms of which 3 came out
  zero. On the stand-ins (which have 4 and 2 true terms) the error falls to rounding level
  from the true N on, and vhfit prunes the surplus terms by itself: gelatin with N = 5
  keeps a median of {fmt(med([r['n_eff'] for r in gel5]), 2)} terms.
- The paper found semifree better than free "for all Prony series numbers" on gelatin.
  With vhfit, counting only the N where either strategy leaves more than 1e-3 % (below
  that both are exact fits), semifree beats free at {semi_better.get('gelatin', 0)} of
  {compared.get('gelatin', 0)} N on the gelatin stand-in and {semi_better.get('SEBS', 0)}
  of {compared.get('SEBS', 0)} on SEBS: with an optimizer that solves the moduli exactly,
  the unconstrained (free) search is at least as good.
- {"Both published τ1 sit exactly on the lower bound of Eq. 22" if edge else
   "The published τ1 are near the lower bound of Eq. 22"} (SEBS: log10 τ1 = {t1s['SEBS']:.2f},
  bound {lows['SEBS']:.2f}; gelatin: {t1s['gelatin']:.2f}, bound {lows['gelatin']:.2f}):
  the paper's search was most likely clipped there, i.e. the best fit wanted a faster
  term. vhfit's default searches one decade further down for this reason.
"""
    return txt, dict(edge=edge, semi_better=semi_better)


def section_item5(R, meta, figs):
    from vhfit.diagnostics import rate_pairs, rate_sensitivity

    sets = [("gelatin, reported stiffening", gelatin_reported_curves()),
            ("gelatin, Table 6 model", case_curves("gelatin")[0]),
            ("SEBS, Table 5 model", case_curves("SEBS")[0])]
    rows = []
    for name, cs in sets:
        for p in rate_pairs(cs, "mooney_rivlin", 5):
            if p.rate_ratio > 20:  # quasi-static against dynamic: far from the bound
                continue
            rows.append([name, f"{p.slow} → {p.fast}", fmt(p.rate_ratio, 3),
                         fmt(p.stress_ratio, 3), f"[{fmt(p.low, 3)}, {fmt(p.high, 3)}]",
                         "**cannot be fitted**" if p.too_steep or p.too_flat else "ok"])
    t = table(["data", "curves", "rate ×", "stress × (measured)", "any MR + Prony model",
               "verdict"], rows)
    msgs = rate_sensitivity(gelatin_reported_curves(), "mooney_rivlin", 5)
    frows = []
    for n in sorted({r["n"] for r in select(R, item=5, method="default")}):
        d = select(R, item=5, method="default", n=n)
        s = select(R, item=5, method="vhfit", n=n)
        b = min(d + s, key=lambda r: r["rmsape"])
        frows.append([n, spread([r["rmsape"] for r in d]), spread([r["rmsape"] for r in s]),
                      ", ".join(fmt(v, 3) for v in b["per_curve"])])
    p = select(R, item=5, method="paper")
    if p:
        frows.append([f"{p[0]['n']}, paper's DE", spread([r["rmsape"] for r in p]), "",
                      f"gen. {fmt(med([r['nit'] for r in p]), 4)}, "
                      f"wall {fmt(med([r['wall'] for r in p]), 2)} s"])
    t2 = table(["N", "vhfit default RMSAPE %", "vhfit semifree RMSAPE %",
                "best run: per-curve RMSAPE % (−0.0107, −2500, −3600, −5700 1/s)"], frows)
    best = _best_fit(R, "gelatin-reported")
    byn = {n: min(r["rmsape"] for r in select(R, item=5, n=n) if r["method"] != "paper")
           for n in sorted({r["n"] for r in select(R, item=5, method="default")})}
    ns5 = sorted(byn)
    flat = len(ns5) >= 2 and byn[ns5[-1]] >= 0.8 * byn[ns5[1 if len(ns5) > 2 else 0]]
    trend = (f"the error stops falling with N (best {fmt(byn[ns5[1]], 3)} % at N = {ns5[1]}, "
             f"{fmt(byn[ns5[-1]], 3)} % at N = {ns5[-1]})" if flat and len(ns5) > 2 else
             "more terms do not remove it" if flat else
             "the error still falls with N here")
    txt = f"""\
## 5. Gelatin's limit: a Prony series cannot stiffen faster than the rate

The paper: between 2500 and 5700 1/s (×2.28 in rate) gelatin's stress rises ×4, while
"the viscoelastic model only allows at most a doubling of stiffness by doubling the strain
rate". Made exact for the model (`vhfit.diagnostics`, derived from Eq. 19): for a
constant-rate ramp from rest, substituting the strain e = r u in the hereditary integral
shows that the rate enters a Prony term only through a = |r| τ, so raising the rate ×k acts
on each term exactly like raising its τ ×k. A term's overstress at strain ε is
φ(a) = ∫ e^(−s/a) w′(ε − s) ds with w = ŝ K the weighted instantaneous stress, and
φ(ka)/φ(a) runs from 1 (elastic limit, a → ∞) to k (viscous limit, a → 0); in the small-
strain limit φ(a) = a (1 − e^(−ε/a)), the closed form of docs/theory.md §4. The total stress at a
strain is a sum of such terms plus the long-term term (ratio 1), and a ratio of sums of
same-sign terms lies between the smallest and the largest term ratio (mediant
inequality). Hence, for **any** E∞, G_i ≥ 0, τ_i and any N,
**1 ≤ σ(k r)/σ(r) ≤ k** in compression — the bound is approached only when the long-term
stiffness vanishes and every τ_i ≪ ε/r. At large strain the module evaluates the same sup
and inf with the model's own recursion instead of assuming them (in compression they are
1 and k to 1e-6 for Mooney–Rivlin, Yeoh and Ogden shapes; in tension a C01 term can
exceed k).

![the rate-stiffening bound and gelatin]({figs['gelatin']})

Panel (a): one Prony term alone, ratio of the stresses at 2r and r at the same strain,
against the term's Deborah-like number |r|τ/|ε|. Panel (b): the stress ratios of the
gelatin stand-in built with the reported stiffening (solid), of the curves generated from
the paper's own Table 6 parameters (dotted — which, being a Prony model, stay below the
bound), the model's bound (thick) and the best fit's ratios (dashed). Panel (c): the best
fit (any N ≤ 5, either strategy) to the reported-stiffening stand-in.

{t}

`calibrate` will warn with these messages (from `vhfit.diagnostics.rate_sensitivity`) on
the reported-stiffening stand-in:

<!-- output: paper-study-rate-warnings -->
```text
{chr(10).join(msgs) if msgs else "(no warning)"}
```

Fits to the reported-stiffening stand-in (the Table 6 curves at −0.0107 and −2500 1/s,
the fast curves raised to ×1.85 and ×4 of the −2500 curve, as the paper quotes for its
data; not measured data):

{t2}

The best error any N reaches is **{fmt(best['rmsape'] if best else float('nan'), 3)} %**
(the paper: 19.69 % on the measured curves), and {trend}, with a search that finds the
exact parameters of every stand-in that a Prony model can represent (items 1-4): the limit
is the model's, not the search's, as the paper argues — **reproduced**, and now detected
before the fit. The fast curves' errors in the last column show the model spreading the
misfit over the three Hopkinson-bar curves, whose stress it cannot separate enough.
"""
    return txt, dict(best=best, msgs=msgs)


def _rng(xs, d=4):
    xs = [x for x in xs if x is not None and np.isfinite(x)]
    if not xs:
        return "–"
    lo, hi = min(xs), max(xs)
    return fmt(lo, d) if fmt(lo, d) == fmt(hi, d) else f"{fmt(lo, d)}–{fmt(hi, d)}"


def section_summary(R, meta, s3):
    def cell(rs, per_gen=True):
        if not rs:
            return "–"
        return (f"{_rng([r['rmsape'] for r in rs])} %, {_rng([r['nit'] for r in rs])} gen., "
                f"{_rng([r['wall'] for r in rs], 2)} s")

    rows = [
        ["Random_3, N = 3, noise-free",
         f"{PAPER['random3']['rmsape']} %, {PAPER['random3']['gens']} gen., "
         f"{PAPER['random3']['time']}", cell(s3["po"]), cell(s3["oo"])],
        [f"Random_3 ±5 % noise, 5 trials (noise floor here {fmt(s3['floor'], 4)} %)",
         f"{PAPER['noise']['rmsape']} %, {PAPER['noise']['gens']} gen., {PAPER['noise']['time']}",
         cell(s3["ptr"]), cell(s3["otr"])],
    ]
    for case, key, n_ours in (("SEBS", "sebs", 4), ("gelatin", "gelatin", 5)):
        p = select(R, item=4, case=case, method="paper")
        o = select(R, item=4, case=case, method="default", n=n_ours)
        rows.append([f"{case} stand-in, N = {n_ours} (the paper: measured curves)",
                     f"{PAPER[key]['rmsape']} %, {PAPER[key]['gens']} gen., {PAPER[key]['time']}",
                     cell(p), cell(o)])
    p = select(R, item=5, method="paper")
    o = select(R, item=5, method="default", n=5)
    rows.append(["gelatin with the reported ×4 stiffening, N = 5", "19.69 % (measured curves)",
                 cell(p), cell(o)])
    rows.append(["the whole parametric study", "~130 calibrations, days",
                 "", f"{meta['n_runs']} calibrations (both methods), "
                 f"{meta['wall'] / 60:.1f} min"])
    hw = (f"| hardware | {PAPER['hardware']} | {meta['cpu']}, {meta['cores']} cores, shared "
          f"(load {meta['load'][1]:.1f}) | same |")
    t = table(["case", "the paper", "the paper's DE on vhfit's evaluator",
               "vhfit default"], rows, ["l", "l", "l", "l"]) + "\n" + hw
    note = ("Errors are Eq. 20 RMSAPE; ranges over seeds/trials. The paper's SEBS and gelatin "
            "errors are on measured curves, ours on curves generated from its published "
            "parameters (a perfect fit exists; the reported-stiffening row imitates the "
            "measured gelatin's rate stiffening). The paper's DE here is capped at "
            f"{meta['args']['long_gens']} generations ({meta['args']['long_gens'] // 4} in "
            "the last case). Generated by `benchmarks/paper_study.py`; details in "
            "[docs/paper-study.md](docs/paper-study.md).")
    return t + "\n\n" + note + "\n"


def section_scorecard(cells1a, cells1b, cells_o):
    groups = [("1a", "1: strategies × N, vhfit on the same τ bounds", cells1a),
              ("1b", "1: strategies × N, vhfit default (free τ)", cells1b)]
    for item, name in ((2, "2: population size (vhfit default, popsize = NP)"),
                       (3, "3: noise and the standard case"), (4, "4: SEBS, gelatin stand-ins"),
                       (5, "5: gelatin, reported stiffening")):
        groups.append((str(item), name, [c for c in cells_o if c["item"] == item]))
    rows = []
    nonwin = []
    for short, name, cs in groups:
        c = _count(cs)
        rows.append([f"{short} — {name.split(': ', 1)[1]}", len(cs), c["win"],
                     c["win (slower)"], c["tie"] + c["tie (slower)"], c["loss"]])
        nonwin += [(short, x) for x in cs if x["verdict"] != "win"]
    t = table(["item", "cells", "wins", "wins, but later than the paper's DE stopped", "ties",
               "losses"], rows)
    t += ("\n\n1a: vhfit with the same τ strategy and bounds as the paper's DE in each cell; "
          "1b: vhfit's default (free τ) against the paper's DE with each strategy.")
    why = []
    for name, x in nonwin:
        if x["verdict"].startswith("tie") and x["oe"] < 1e-6:
            reason = "both exact to rounding"
        elif x["verdict"].startswith("tie") and ("fixed" in x["label"]
                                                 or "N = 1," in x["label"]):
            reason = ("the same optimum: with one term or fixed τ the search is small "
                      "and the paper's DE converges within its budget too")
        elif x["verdict"].startswith("tie") and "noise" in x["label"]:
            reason = "both at the optimum of the noisy data, below the noise floor"
        elif x["verdict"].startswith("tie"):
            reason = "the same optimum (within 1 %)"
        elif x["verdict"] == "win (slower)":
            reason = ("lower error, but the capped paper's DE stopped sooner than vhfit got "
                      "below its error")
        else:
            reason = "the paper's DE ends lower"
        why.append([name, x["label"], fmt(x["pe"]), fmt(x["pw"], 2), fmt(x["oe"]),
                    fmt(x["ow"], 2), fmt(x["tt"], 2), x["verdict"], reason])
    t2 = table(["item", "cell", "paper's DE %", "its wall s", "vhfit %", "vhfit wall s",
                "vhfit s to paper's error", "verdict", "why"], why,
               ["l", "l", "r", "r", "r", "r", "r", "l", "l"]) if why else "(none)"
    return t, t2, nonwin


def _tau_clusters():
    """Random materials whose true τ share one semifree sub-range (N = 3, Eq. 22)."""
    a = _eq22_low(cases.RANDOM_RATES)
    b = math.log10(1.0 / min(abs(r) for r in cases.RANDOM_RATES)) + 1
    edges = np.linspace(a, b, 4)
    out = []
    for k in range(1, 6):
        lt = [math.log10(v) for key, v in cases.random_material(k).items() if key.startswith("tau")]
        bins = np.clip(np.searchsorted(edges, lt) - 1, 0, 2)
        if len(set(bins.tolist())) < 3:
            out.append(f"Random_{k}")
    return out


def section_disagree(meta, s1, s2, s3, s4, s5, nonwin):
    b = []
    G = meta["args"]["paper_gens"]
    clus = _tau_clusters()
    if s1["best_o"] != "semifree":
        b.append(
            f"**Semifree is not the best strategy for the problem, only for the paper's "
            f"optimizer.** With vhfit on the same bounds the lowest median error for N ≥ 2 is "
            f"{s1['best_o']} ({', '.join(f'{k} {fmt(v)} %' for k, v in s1['om'].items())}). "
            "Semifree's search space is a subset of free's, so an optimizer that converges "
            "can only do as well or better with free τ; semifree helps the paper's DE because "
            "it shrinks the space the DE must explore, and it costs accuracy whenever two "
            f"true τ fall into one sub-range — which happens for {len(clus)} of the 5 random "
            f"materials at N = 3 ({', '.join(clus) or 'none'}). This is why vhfit's default "
            "is free τ.")
    pm = ", ".join(f"{k} {fmt(v)} %" for k, v in s1["pm"].items())
    cm = ", ".join(f"{k} {fmt(v)} %" for k, v in s1["cm"].items())
    if s1["best_p"] == "semifree" and s1["best_c"] == "semifree":
        b.append(
            f"With the paper's own DE semifree does give the lowest error, as the paper "
            f"reports: capped at {G} generations, medians for N ≥ 2: {pm}; run to its "
            f"criteria on the standard case (1c): {cm}.")
    else:
        b.append(
            f"**With the paper's own DE**, the lowest error is not always semifree's: capped "
            f"at {G} generations, medians for N ≥ 2: {pm} (best: {s1['best_p']}); run to its "
            f"criteria on the standard case (1c): {cm} (best: {s1['best_c']}).")
    b.append(
        f"**Population size.** With the paper's DE at {G} generations the median error is "
        f"within 2× of its best from NP = {s2['pl_p']} on (the paper: an asymptote at 60). "
        f"vhfit's error is within 2× of its best from NP = {s2['pl_o']}: with the moduli "
        "solved exactly the search has 4 dimensions instead of 8, and the paper's advice of "
        "60-80 individuals does not carry over.")
    if abs(s3["pe"] - s3["oe"]) <= 0.02 * s3["oe"]:
        b.append(
            "**Noise.** The paper attributes its ~3.1 % to runs stopping in local minima; "
            "here both optimizers end at the same error, at or below the noise floor (the "
            "truth's own error on the noisy data): the 3 % is the noise, not a local minimum.")
    if s4["edge"]:
        b.append(
            "**SEBS and gelatin τ1.** Both published fastest relaxation times sit exactly on "
            "the lower Eq. 22 bound: those calibrations were clipped by the search range, so "
            "the published τ1 (and the moduli that compensate for it) are bound-limited "
            "values, not free optima.")
    losses = [x for _, x in nonwin if x["verdict"] == "loss"]
    slower = [x for _, x in nonwin if x["verdict"] == "win (slower)"]
    if losses:
        b.append(f"**Cells where our default loses to the paper's DE: {len(losses)}** — listed "
                 "in the scorecard above with their numbers.")
    else:
        b.append("Our default loses no cell to the paper's DE on final error.")
    if slower:
        b.append(
            f"In {len(slower)} cell(s) our default ends lower but needed more time to get "
            "below the paper's DE's final error than that run took (listed above). There the "
            "paper's DE was stopped by the generation cap (or its own criteria) at a much "
            "higher error; a budget-matched comparison is the 'vhfit s to paper's error' "
            "column.")
    return "\n".join(f"- {x}" for x in b) + "\n"


def render(R, meta, out_dir):
    fig_dir = os.path.join(out_dir, "figures")
    os.makedirs(fig_dir, exist_ok=True)
    names = dict(fig6="paper_study_fig6_strategies.png", fig7="paper_study_fig7_prony.png",
                 fig8="paper_study_fig8_population_history.png",
                 fig9="paper_study_fig9_population.png", sebs="paper_study_sebs_gelatin.png",
                 gelatin="paper_study_gelatin_limit.png")
    figs = {k: f"figures/{v}" for k, v in names.items()}
    P = {k: os.path.join(fig_dir, v) for k, v in names.items()}
    fig_strategies(R, P["fig6"])
    fig_prony(R, P["fig7"])
    fig_population(R, P["fig8"], P["fig9"])
    fig_sebs_gelatin(R, P["sebs"])
    fig_gelatin_limit(R, P["gelatin"])
    t1, s1 = section_item1(R, meta, figs)
    t2, s2 = section_item2(R, meta, figs)
    t3, s3 = section_item3(R, meta)
    t4, s4 = section_item4(R, meta, figs)
    t5, s5 = section_item5(R, meta, figs)
    summary = section_summary(R, meta, s3)
    sc, sc_list, nonwin = section_scorecard(s1["cells_a"], s1["cells_b"], _cells_other(R))
    dis = section_disagree(meta, s1, s2, s3, s4, s5, nonwin)
    failed = [r for r in R if "error" in r]
    fail_txt = ""
    if failed:
        fail_txt = "\n## Failed calibrations\n\n" + table(
            ["item", "case", "method", "strategy", "N", "seed", "error"],
            [[r["item"], r["case"], r["method"], r["strategy"], r["n"], r["seed"], r["error"]]
             for r in failed]) + "\n"
    quick = ("\n> **Quick mode**: a small subset for CI (one material, few N and NP, one "
             "seed); the numbers are not the study's.\n" if meta["args"]["quick"] else "")
    doc = f"""\
# The paper's parametric study, reproduced and extended

*Generated by `benchmarks/paper_study.py` — do not edit by hand; rerun the script.*
{quick}
The paper's conclusions — semifree τ beats free and fixed, about 60 individuals are
needed, 1-5 Prony terms suffice, noise raises the error to about 3 %, and a Prony series
cannot follow gelatin's steep rate stiffening — came from about 130 calibrations that took
days on 16 cores. This page reruns that study with the paper's own optimizer on vhfit's
evaluator and with vhfit's method, extends it (seeds, medians and spreads, the noise
floor, parameter recovery, the rate-stiffening bound), and says where we disagree.

## Setup

{section_setup(meta)}

{section_methods(meta)}

## Summary: the paper's headline figures beside ours

{summary}

## Scorecard: our default against the paper's method, cell by cell

A cell is one setting (strategy × N × material, NP × material, …) with medians over its
seeds. **win**: lower median final RMSAPE (by more than 1 %) *and* vhfit got below the
paper's DE's final error in no more time than the paper's DE took; **win, but later**:
lower final error, but reaching the paper's DE's error took vhfit longer than the capped
paper's DE ran; **tie**: within 1 % (or both below 1e-6 %); **loss**: the paper's DE ends
lower.

{sc}

Every cell that is not a plain win:

{sc_list}

{t1}
{t2}
{t3}
{t4}
{t5}
## Where we disagree with the paper

{dis}
{fail_txt}
## Reproduce

    python benchmarks/paper_study.py

writes this page, `docs/paper-study-summary.md` (also pasted into README.md) and
`docs/figures/paper_study_*.png`; `--quick` runs a one-minute subset into a temporary
directory; `--json FILE` keeps the raw results and `--from-json FILE` re-renders from them.
"""
    with open(os.path.join(out_dir, "paper-study.md"), "w") as f:
        f.write(doc)
    with open(os.path.join(out_dir, "paper-study-summary.md"), "w") as f:
        f.write("<!-- generated by benchmarks/paper_study.py; do not edit by hand -->\n"
                + summary)
    return doc, summary


README_START = "<!-- paper-study-summary: start (written by benchmarks/paper_study.py) -->\n"
README_END = "<!-- paper-study-summary: end -->\n"


def _update_readme(summary: str) -> None:
    """Replace the summary table between the README's markers (a run into docs/ only)."""
    path = os.path.join(ROOT, "README.md")
    with open(path) as f:
        text = f.read()
    a, b = text.find(README_START), text.find(README_END)
    if a < 0 or b < a:
        print("README.md has no paper-study-summary markers: table not updated",
              file=sys.stderr)
        return
    text = text[: a + len(README_START)] + summary.rstrip("\n") + "\n" + text[b:]
    with open(path, "w") as f:
        f.write(text)
    print(f"updated the summary table in {path}", file=sys.stderr)


def _cpu() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small subset for CI (~1 min)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seeds", type=int, default=None, help="seeds per cell (3; quick 1)")
    ap.add_argument("--paper-gens", type=int, default=None,
                    help="generation cap of the paper's DE in items 1-2 (200; quick 40)")
    ap.add_argument("--long-gens", type=int, default=None,
                    help="generation cap of the paper's DE in items 1c, 3, 4 (1500; quick "
                         "150); item 5 gets a quarter")
    ap.add_argument("--max-paper-time", type=float, default=120.0,
                    help="safety limit in s for one run of the paper's DE")
    ap.add_argument("--out", default=None,
                    help="output directory (default docs/; quick: a temporary directory)")
    ap.add_argument("--json", default=None, help="also save the raw results here")
    ap.add_argument("--from-json", default=None, help="re-render from saved raw results")
    args = ap.parse_args(argv)
    q = args.quick
    args.seeds = args.seeds or (1 if q else 3)
    args.paper_gens = args.paper_gens or (40 if q else 200)
    args.long_gens = args.long_gens or (150 if q else 1500)
    out = args.out or (tempfile.mkdtemp(prefix="paper-study-") if q else os.path.join(ROOT, "docs"))
    os.makedirs(out, exist_ok=True)
    warnings.simplefilter("ignore")
    if args.from_json:
        with open(args.from_json) as f:
            data = json.load(f)
        R, meta = data["results"], data["meta"]
    else:
        jobs = plan(args)
        print(f"paper study: {len(jobs)} calibrations on {args.workers} worker(s)", file=sys.stderr)
        sampler = LoadSampler()
        sampler.start()
        t0 = time.perf_counter()
        R = execute(jobs, args.workers)
        wall = time.perf_counter() - t0
        sampler.stop()
        import numba
        import scipy

        loads = sampler.samples
        # file arguments as base names: the document must not carry this machine's paths
        cmd = "python benchmarks/paper_study.py" + ("".join(
            " " + (os.path.basename(a) if os.path.isabs(a) else a)
            for a in (argv if argv is not None else sys.argv[1:])))
        meta = dict(
            command=cmd, date=_dt.datetime.now().strftime("%Y-%m-%d %H:%M"), cpu=_cpu(),
            cores=os.cpu_count(), load=[min(loads), float(np.median(loads)), max(loads)],
            versions=(f"vhfit {vhfit.__version__}, Python {platform.python_version()}, NumPy "
                      f"{np.__version__}, SciPy {scipy.__version__}, Numba {numba.__version__}"),
            workers=args.workers, threads=os.environ.get("NUMBA_NUM_THREADS"),
            n_runs=len(R), n_failed=sum(1 for r in R if "error" in r), wall=wall,
            args=dict(quick=q, seeds=args.seeds, paper_gens=args.paper_gens,
                      long_gens=args.long_gens, max_paper_time=args.max_paper_time),
        )
        path = args.json or os.path.join(tempfile.gettempdir(), "paper_study_results.json")
        with open(path, "w") as f:
            json.dump(dict(meta=meta, results=R), f)
        print(f"raw results: {path}", file=sys.stderr)
    cpu = [r["cpu"] for r in R if "cpu" in r]
    meta["cpu_total"] = float(sum(cpu)) if len(cpu) == len(R) else None
    t = time.perf_counter()
    _, summary = render(R, meta, out)
    if os.path.abspath(out) == os.path.join(ROOT, "docs"):
        _update_readme(summary)
    print(f"study {meta['wall']:.0f} s + rendering {time.perf_counter() - t:.0f} s; "
          f"wrote {os.path.join(out, 'paper-study.md')}", file=sys.stderr)


if __name__ == "__main__":
    main()
