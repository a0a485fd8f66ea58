"""Speed of the constitutive core: one population evaluation, cold start, memory.

Run::

    python benchmarks/bench_model.py            # full run, ~1–2 min
    python benchmarks/bench_model.py --quick    # fewer repeats

Case: Mooney–Rivlin + 4 Prony terms on the paper's four SEBS rates (−0.0018, −0.18,
−59.5, −820 1/s), 10 objective points per curve evenly spaced in strain to −0.5, a
random population of 60 in the paper's SEBS bounds (Table 3: C10 ≤ 0.0308, C01 ≤ 0.0236,
G_i ≤ 31.3 MPa, log10 τ semifree over [−4.91, 3.74]), default accuracy rtol = 1e-6.

Baselines (written here, numpy-vectorised over the whole population at once):

* ``lag-graded trapezoid``: for each output time t, the trapezoid rule on a grid in the
  lag s = t − u that is uniform near 0 and geometric up to t, so that it resolves
  every τ from 1e-5 s to 1e4 s at once (the strongest simple alternative found);
* ``uniform trapezoid``: the textbook version, a uniform time grid per curve. It cannot
  reach 1e-6 within memory for the paper's τ range (the slow curve lasts 278 s and the
  fastest τ is 1.2e-5 s); it is timed on the τ range where it can, found by search.

Grid sizes are chosen by doubling until the error against an independent quadrature
reference (scipy.integrate.quad of the corrected Eq. 19 on a few individuals) is ≤ 1e-6
of each curve's peak stress. vhfit is timed on exactly the same populations.

The same population is also evaluated in the "lsdyna" formulation (LS-DYNA's MAT_077:
a Prony convolution of the Green strain rate added to the long-term stress,
docs/theory.md §14), checked against its own quadrature, and timed side by side with
the default "hereditary" one (goal: at most 1.5× its time per population).
"""

from __future__ import annotations

import argparse
import math
import os
import resource
import subprocess
import sys
import time
import warnings

import numpy as np
from scipy.integrate import quad

import vhfit
from vhfit import History, ViscoHyperelastic, _kernels

SEBS_RATES = (-0.0018, -0.18, -59.5, -820.0)
N_PRONY = 4
POP = 60
N_POINTS = 10
STRAIN_END = -0.5
C10_MAX, C01_MAX, G_MAX = 0.0308, 0.0236, 31.3
LOG_TAU = (-4.91, 3.74)
TARGET_ACC = 1e-6
TARGET_MS = 2.0
TARGET_RATIO = 20.0
TARGET_COLD_S = 2.0
TARGET_LSDYNA_RATIO = 1.5  # "lsdyna" time per population / "hereditary"
MEM_CAP_ELEMENTS = 2**25  # largest (P, N, n) float64 temporary a baseline may build: 256 MB
N_REF = 3  # individuals checked against quadrature


# ------------------------------------------------------------------- set-up
def strains() -> np.ndarray:
    return np.linspace(0.0, STRAIN_END, N_POINTS + 1)[1:]


def population(rng, n=POP, log_tau=LOG_TAU) -> np.ndarray:
    """Random individuals in the paper's SEBS bounds, τ semifree over ``log_tau``."""
    X = np.empty((n, 2 + 2 * N_PRONY))
    X[:, 0] = rng.uniform(0, C10_MAX, n)
    X[:, 1] = rng.uniform(0, C01_MAX, n)
    edges = np.linspace(*log_tau, N_PRONY + 1)
    for i in range(N_PRONY):
        X[:, 2 + 2 * i] = rng.uniform(0, G_MAX, n)
        X[:, 3 + 2 * i] = 10 ** rng.uniform(edges[i], edges[i + 1], n)
    return X


def split(X):
    return X[:, 0], X[:, 1], X[:, 2::2], X[:, 3::2]


def mr_basis(lam):
    """σ_h = C10 φ10 + C01 φ01 (docs/theory.md §2)."""
    return 2 * (lam**2 - 1 / lam), 2 * (lam - 1 / lam**2)


def curve_errors(S, ref, n_points=N_POINTS) -> float:
    """max over curves of max|σ − σ_ref| / max|σ_ref| (each curve its own peak)."""
    worst = 0.0
    for c in range(S.shape[-1] // n_points):
        sl = slice(c * n_points, (c + 1) * n_points)
        err = np.max(np.abs(S[..., sl] - ref[..., sl])) / np.max(np.abs(ref[..., sl]))
        worst = max(worst, float(err))
    return worst


# ---------------------------------------------------------------- reference
def reference(x, rates=SEBS_RATES, strain=None) -> np.ndarray:
    """Corrected Eq. 19 (docs/theory.md §5, conditioned form) by adaptive quadrature.

    True stress of Mooney–Rivlin + Prony ``x`` at each strain (default :func:`strains`)
    of a constant-rate ramp at each rate, the rates' results concatenated.
    """
    C10, C01 = x[0], x[1]
    G, tau = x[2::2], x[3::2]
    E = 6 * (C10 + C01)

    def s_hat(lam):
        return (2 * C10 * (lam * lam - 1 / lam) + 2 * C01 * (lam - 1 / lam**2)) / E

    out = []
    for r in rates:
        for eps in strains() if strain is None else strain:
            t = eps / r
            lt = 1 + eps
            st = s_hat(lt)
            total = E * st
            for Gi, ti in zip(G, tau):

                def f(u, ti=ti, t=t, lt=lt, st=st, r=r):
                    lu = 1 + r * u
                    K = (2 / 3) * (lt / lu) ** 2 + (1 / 3) * lu / lt
                    return math.exp(-(t - u) / ti) * (st - s_hat(lu) * K) / ti

                pts = sorted(t - k * ti for k in (1, 4, 16, 64) if 0 < t - k * ti < t)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    val = quad(f, 0, t, points=pts or None, epsabs=1e-14, epsrel=1e-12,
                               limit=1000)[0]
                total += Gi * (st * math.exp(-t / ti) + val)
            out.append(total)
    return np.array(out)


def reference_lsdyna(x, rates=SEBS_RATES) -> np.ndarray:
    """LS-DYNA MAT_077 (docs/theory.md §14) by adaptive quadrature, uniaxial ramps.

    σ = σ_h + λ² S1 − λ⁻¹ S2 with S_k = Σ_i (2 G_i/3) ∫_0^t e^(−(t−u)/τ_i) dE_k/du du,
    E1 = (λ² − 1)/2 and E2 = (λ⁻¹ − 1)/2, so dE1/du = r λ and dE2/du = −r/(2 λ²).
    """
    C10, C01 = x[0], x[1]
    G, tau = x[2::2], x[3::2]
    out = []
    for r in rates:
        for eps in strains():
            t = eps / r
            lt = 1 + eps
            a, b = mr_basis(lt)
            total = C10 * a + C01 * b
            for Gi, ti in zip(G, tau):
                S = []
                for k in (1, 2):
                    def f(u, ti=ti, t=t, r=r, k=k):
                        lu = 1 + r * u
                        rate = r * lu if k == 1 else -r / (2 * lu * lu)  # dE_k/du
                        return math.exp(-(t - u) / ti) * rate

                    pts = sorted(t - k * ti for k in (1, 4, 16, 64) if 0 < t - k * ti < t)
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        S.append(2 * Gi / 3 * quad(f, 0, t, points=pts or None, epsabs=1e-16,
                                                   epsrel=1e-12, limit=1000)[0])
                total += lt * lt * S[0] - S[1] / lt
            out.append(total)
    return np.array(out)


# ---------------------------------------------------------------- baselines
def _hereditary(X, r, t, s, w):
    """σ(t) for the population from lag nodes s (ascending, s[0] = 0) and weights w."""
    C10, C01, G, tau = split(X)
    E = 6 * (C10 + C01)
    lt = 1 + r * t
    lu = 1 + r * (t - s)
    a, b = mr_basis(lu)
    at, bt = mr_basis(np.array(lt))
    st = (C10 * at + C01 * bt) / E                                   # (P,)
    K = (2 / 3) * (lt / lu) ** 2 + (1 / 3) * lu / lt                 # (n,)
    g = st[:, None] - (C10[:, None] * a + C01[:, None] * b) / E[:, None] * K  # (P, n)
    f = np.exp(-s / tau[:, :, None]) * (g[:, None, :] / tau[:, :, None])    # (P, N, n)
    h = st[:, None] * np.exp(-t / tau) + f @ w                       # (P, N)
    return E * st + np.einsum("pi,pi->p", G, h)


def lag_grid(t, n, s_min):
    """Trapezoid nodes/weights on [0, t]: uniform on [0, s_min], geometric above."""
    n0 = max(n // 16, 4)
    if t <= s_min:
        s = np.linspace(0, t, n)
    else:
        s = np.concatenate([np.linspace(0, s_min, n0)[:-1], np.geomspace(s_min, t, n - n0 + 1)])
    w = np.zeros_like(s)
    d = np.diff(s)
    w[:-1] += d / 2
    w[1:] += d / 2
    return s, w


def baseline_lag(X, n, s_min, rates=SEBS_RATES):
    out = []
    for r in rates:
        for eps in strains():
            t = eps / r
            s, w = lag_grid(t, n, s_min)
            out.append(_hereditary(X, r, t, s, w))
    return np.stack(out, axis=1)


def baseline_uniform(X, n_per_curve, rates=SEBS_RATES):
    out = []
    for r, n in zip(rates, n_per_curve):
        T = STRAIN_END / r
        per = n // N_POINTS
        for j in range(1, N_POINTS + 1):
            m = j * per
            t = T * j / N_POINTS
            s = np.linspace(0, t, m + 1)
            w = np.full(m + 1, t / m)
            w[0] = w[-1] = t / (2 * m)
            out.append(_hereditary(X, r, t, s, w))
    return np.stack(out, axis=1)


# ------------------------------------------------------------------ helpers
def median_time(fn, repeats, *, min_time=0.0):
    ts = []
    t_start = time.perf_counter()
    while len(ts) < repeats or time.perf_counter() - t_start < min_time:
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return float(np.median(ts)), float(np.min(ts)), len(ts)


def peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def tune_lag(X_ref, ref, s_min):
    n, err = 256, math.inf
    while True:
        if POP * N_PRONY * n > MEM_CAP_ELEMENTS:
            return None, err
        err = curve_errors(baseline_lag(X_ref, n, s_min), ref)
        if err <= TARGET_ACC:
            return n, err
        n *= 2


def tune_uniform(X_ref, ref):
    """Per-curve grid sizes by doubling; None for a curve that cannot reach the target."""
    sizes, errs = [], []
    for c, r in enumerate(SEBS_RATES):
        sl = slice(c * N_POINTS, (c + 1) * N_POINTS)
        n, err = 10 * 2**4, math.inf
        while True:
            if POP * N_PRONY * n > MEM_CAP_ELEMENTS:
                sizes.append(None)
                errs.append(err)
                break
            S = baseline_uniform_single(X_ref, r, n)
            err = float(np.max(np.abs(S - ref[:, sl])) / np.max(np.abs(ref[:, sl])))
            if err <= TARGET_ACC:
                sizes.append(n)
                errs.append(err)
                break
            n *= 2
    return sizes, errs


def baseline_uniform_single(X, r, n):
    return baseline_uniform(X, [n], rates=(r,))


COLD_CODE = """
import time
t0 = time.perf_counter()
import numpy as np, vhfit
t1 = time.perf_counter()
m = vhfit.ViscoHyperelastic("mooney_rivlin", {n})
hs = [vhfit.History.constant_rate(np.linspace(0, {e}, {k} + 1)[1:], r) for r in {rates}]
X = np.array({x})
S = m.batch(hs)(X)
assert np.isfinite(S).all()
t2 = time.perf_counter()
# VmHWM belongs to this process image (ru_maxrss would include the parent's at fork time)
hwm = [l for l in open("/proc/self/status") if l.startswith("VmHWM")][0].split()[1]
print(t1 - t0, t2 - t1, int(hwm) / 1024)
"""


def cold_start(X, runs):
    code = COLD_CODE.format(n=N_PRONY, e=STRAIN_END, k=N_POINTS, rates=SEBS_RATES,
                            x=X.tolist())
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)  # warm
    walls, imports, firsts, rss = [], [], [], []
    for _ in range(runs):
        t0 = time.perf_counter()
        res = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                             text=True)
        walls.append(time.perf_counter() - t0)
        a, b, c = res.stdout.split()
        imports.append(float(a))
        firsts.append(float(b))
        rss.append(float(c))
    med = [float(np.median(v)) for v in (walls, imports, firsts, rss)]
    return tuple(med)


def batch_bytes(b) -> int:
    arrays = [b.sample_stretch, b.step, b.sample_off, b.step_off, b._gather_node,
              b._gather_sample, b.out_stretch, b._eng]
    return int(sum(a.nbytes for a in arrays))


def yes(ok: bool) -> str:
    return "MET" if ok else "NOT MET"


# --------------------------------------------------------------------- main
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    reps = 50 if args.quick else 300
    base_reps = 3 if args.quick else 5

    print(f"vhfit {vhfit.__version__}, numpy {np.__version__}, python {sys.version.split()[0]}, "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f} at start")
    import numba

    print(f"numba {numba.__version__}, {numba.get_num_threads()} threads")
    rng = np.random.default_rng(args.seed)
    X = population(rng)
    hs = [History.constant_rate(strains(), r) for r in SEBS_RATES]
    model = ViscoHyperelastic("mooney_rivlin", N_PRONY)
    b = model.batch(hs)
    b(X)  # compile / load the cache
    t_med, t_min, n_calls = median_time(lambda: b(X), reps, min_time=1.0)
    rss_core = peak_rss_mb()

    # kernel-only timings, both code paths (the Batch picks one by population size)
    hyper, G, tau = model.split(X)
    s_hat, _, _ = b._s_hat(hyper)
    kargs = (s_hat, b.sample_stretch, b.step, b.sample_off, b.step_off,
             np.ascontiguousarray(G), np.ascontiguousarray(tau), _kernels.DERIV, False)
    par = getattr(_kernels, "_overstress_par", None)
    seq = getattr(_kernels, "_overstress_seq", None)
    kern = {}
    for name, f in (("parallel", par), ("serial", seq)):
        if f is not None:
            f(*kargs)
            kern[name] = median_time(lambda f=f: f(*kargs), reps)[0]
    t_hyper = median_time(lambda: b._s_hat(hyper), reps)[0]
    t_serial = None
    if hasattr(_kernels, "PARALLEL_MIN_JOBS"):  # the same Batch call, forced onto one thread
        saved = _kernels.PARALLEL_MIN_JOBS, _kernels.PARALLEL_MIN_WORK
        _kernels.PARALLEL_MIN_JOBS = _kernels.PARALLEL_MIN_WORK = 1 << 62
        try:
            t_serial, t_serial_min, _ = median_time(lambda: b(X), reps)
        finally:
            _kernels.PARALLEL_MIN_JOBS, _kernels.PARALLEL_MIN_WORK = saved
    c0 = time.process_time()
    t0 = time.perf_counter()
    for _ in range(reps):
        b(X)
    cpu_ratio = (time.process_time() - c0) / (time.perf_counter() - t0)

    # the "lsdyna" formulation on the same population, timed alternately with the
    # hereditary one so that both see the same load on a shared machine
    b_ls = ViscoHyperelastic("mooney_rivlin", N_PRONY, formulation="lsdyna").batch(hs)
    b_ls(X)
    t_here, t_ls = [], []
    for _ in range(5):
        t_here.append(median_time(lambda: b(X), max(reps // 5, 10))[0])
        t_ls.append(median_time(lambda: b_ls(X), max(reps // 5, 10))[0])
    t_here, t_ls = float(np.median(t_here)), float(np.median(t_ls))

    print()
    print("Case: Mooney-Rivlin + 4 Prony, SEBS rates (-0.0018, -0.18, -59.5, -820 1/s), "
          f"{N_POINTS} points/curve to strain {STRAIN_END}, population {POP}, rtol 1e-6")
    print(f"vhfit grid: {b.step.size} steps, {b.sample_stretch.size} samples over 4 curves")

    # ---------------------------------------------------------- cold start
    wall, t_import, t_first, rss_cold = cold_start(X, 3 if args.quick else 5)

    # ----------------------------------------------------------- accuracy
    X_ref = X[:N_REF]
    t0 = time.perf_counter()
    ref = np.stack([reference(x) for x in X_ref])
    t_quad = (time.perf_counter() - t0) / N_REF
    err_vhfit = curve_errors(b(X_ref), ref)
    ref_ls = np.stack([reference_lsdyna(x) for x in X_ref])
    err_ls = curve_errors(b_ls(X_ref), ref_ls)

    # ----------------------------------------------------- lag-graded baseline
    s_min = 10 ** LOG_TAU[0] / 100
    n_lag, err_lag = tune_lag(X_ref, ref, s_min)
    if n_lag is not None:
        t_lag = median_time(lambda: baseline_lag(X, n_lag, s_min), base_reps)[0]
        err_lag_chk = curve_errors(baseline_lag(X_ref, n_lag, s_min), ref)
    rss_lag = peak_rss_mb()

    # ------------------------------------------------------ uniform baseline
    sizes_full, errs_full = tune_uniform(X_ref, ref)
    lo_found = None
    for lo in np.arange(-4.0, 3.0, 1.0):
        Xr = population(np.random.default_rng(args.seed + 1), log_tau=(lo, LOG_TAU[1]))
        ref_r = np.stack([reference(x) for x in Xr[:N_REF]])
        sizes, errs = tune_uniform(Xr[:N_REF], ref_r)
        if all(s is not None for s in sizes):
            lo_found, sizes_r, errs_r = lo, sizes, errs
            break
    if lo_found is not None:
        br = model.batch(hs)
        br(Xr)
        t_vh_r = median_time(lambda: br(Xr), reps)[0]
        t_uni = median_time(lambda: baseline_uniform(Xr, sizes_r), base_reps)[0]
        err_vh_r = curve_errors(br(Xr[:N_REF]), ref_r)
    rss_end = peak_rss_mb()

    # -------------------------------------------------------------- report
    per = t_med / POP
    print()
    print(f"{'method':<34}{'grid':>22}{'error vs quad':>15}{'ms / population':>17}"
          f"{'us / individual':>17}{'ratio':>9}")
    print("-" * 114)
    print(f"{'vhfit Batch (median)':<34}{b.step.size:>16} steps{err_vhfit:>15.2e}"
          f"{t_med * 1e3:>17.3f}{per * 1e6:>17.1f}{1.0:>9.1f}")
    print(f"{'vhfit Batch (best)':<34}{'':>22}{'':>15}{t_min * 1e3:>17.3f}"
          f"{t_min / POP * 1e6:>17.1f}")
    if t_serial is not None:
        print(f"{'vhfit Batch, serial kernel (median)':<34}{'':>22}{'':>15}{t_serial * 1e3:>17.3f}"
              f"{t_serial / POP * 1e6:>17.1f}")
        print(f"{'vhfit Batch, serial kernel (best)':<34}{'':>22}{'':>15}"
              f"{t_serial_min * 1e3:>17.3f}{t_serial_min / POP * 1e6:>17.1f}")
    for name, tk in kern.items():
        print(f"{'  kernel alone, ' + name:<34}{'':>22}{'':>15}{tk * 1e3:>17.3f}"
              f"{tk / POP * 1e6:>17.1f}")
    print(f"{'vhfit Batch, lsdyna (median)':<34}{b_ls._general.step.size:>16} steps"
          f"{err_ls:>15.2e}{t_ls * 1e3:>17.3f}{t_ls / POP * 1e6:>17.1f}{t_ls / t_here:>9.2f}"
          f"  (hereditary alternately: {t_here * 1e3:.3f} ms)")
    print(f"{'  hyperelastic part alone (numpy)':<34}{'':>22}{'':>15}{t_hyper * 1e3:>17.3f}"
          f"{t_hyper / POP * 1e6:>17.1f}")
    if n_lag is not None:
        print(f"{'lag-graded trapezoid (numpy)':<34}{n_lag:>11} nodes/output{err_lag_chk:>15.2e}"
              f"{t_lag * 1e3:>17.1f}{t_lag / POP * 1e6:>17.1f}{t_lag / t_med:>9.0f}")
    else:
        print(f"{'lag-graded trapezoid (numpy)':<34}{'> memory cap':>22}{err_lag:>15.2e}")
    print(f"{'scipy quad (reference)':<34}{'adaptive':>22}{0.0:>15.0e}{t_quad * POP * 1e3:>17.0f}"
          f"{t_quad * 1e6:>17.0f}{t_quad * POP / t_med:>9.0f}")
    print()
    full = ", ".join(f"{r:g}: " + (f"n={s}" if s else f"fails (err {e:.1e} at cap)")
                     for r, s, e in zip(SEBS_RATES, sizes_full, errs_full))
    print(f"uniform trapezoid on the paper's tau range [1e{LOG_TAU[0]}, 1e{LOG_TAU[1]}] s, "
          f"grid cap {MEM_CAP_ELEMENTS // (POP * N_PRONY)} nodes/curve: {full}")
    if lo_found is not None:
        print(f"  reaches {TARGET_ACC:g} only for tau >= 1e{lo_found:g} s (semifree over "
              f"[{lo_found:g}, {LOG_TAU[1]}]); on that population:")
        print(f"{'  vhfit Batch (median)':<34}{'':>22}{err_vh_r:>15.2e}{t_vh_r * 1e3:>17.3f}"
              f"{t_vh_r / POP * 1e6:>17.1f}{1.0:>9.1f}")
        print(f"{'  uniform trapezoid (numpy)':<34}{str(sizes_r):>22}{max(errs_r):>15.2e}"
              f"{t_uni * 1e3:>17.1f}{t_uni / POP * 1e6:>17.1f}{t_uni / t_vh_r:>9.0f}")
    else:
        print("  it does not reach the target for any tau range tried")
    print()
    print(f"cold start, fresh interpreter with the numba cache warm (median of runs): "
          f"{wall:.2f} s wall for the whole `python -c`; inside it, import vhfit "
          f"{t_import:.2f} s, build the batch + first call {t_first:.3f} s")
    print(f"memory: Batch plan arrays {batch_bytes(b) / 1024:.1f} KiB; per-call temporaries "
          f"{(s_hat.nbytes + 8 * POP * (b.step.size + 4)) / 1024:.0f} KiB; peak RSS "
          f"{rss_cold:.0f} MB for a process that only runs vhfit, {rss_core:.0f} MB here "
          f"before the baselines, {max(rss_lag, rss_end):.0f} MB after them")
    print(f"load average {os.getloadavg()[0]:.2f} at end; {n_calls} timed calls; the batch "
          f"used {cpu_ratio:.2f} CPU-seconds per wall second (2 = both cores busy)")
    print()
    print("targets:")
    print(f"  accuracy <= {TARGET_ACC:g} vs quad on {N_REF} individuals: {err_vhfit:.2e} "
          f"{yes(err_vhfit <= TARGET_ACC)}")
    print(f"  lsdyna accuracy <= {TARGET_ACC:g} vs quad on {N_REF} individuals: {err_ls:.2e} "
          f"{yes(err_ls <= TARGET_ACC)}")
    print(f"  lsdyna time per population <= {TARGET_LSDYNA_RATIO:g}x hereditary: "
          f"{t_ls * 1e3:.3f} / {t_here * 1e3:.3f} ms = {t_ls / t_here:.2f}x "
          f"{yes(t_ls / t_here <= TARGET_LSDYNA_RATIO)}")
    print(f"  median batch time <= {TARGET_MS:g} ms: {t_med * 1e3:.3f} ms "
          f"{yes(t_med * 1e3 <= TARGET_MS)}")
    if t_serial is not None:
        print(f"  (with the serial kernel: {t_serial * 1e3:.3f} ms "
              f"{yes(t_serial * 1e3 <= TARGET_MS)})")
    if n_lag is not None:
        ratio = t_lag / t_med
        print(f"  >= {TARGET_RATIO:g}x faster per individual than the strongest simple "
              f"alternative (lag-graded trapezoid): {ratio:.0f}x {yes(ratio >= TARGET_RATIO)}"
              + (f" (serial kernel: {t_lag / t_serial:.0f}x)" if t_serial else ""))
    if lo_found is not None:
        ratio = t_uni / t_vh_r
        print(f"  (uniform trapezoid, restricted tau range: {ratio:.0f}x)")
    cold = t_import + t_first  # the target: import and first call (cache warm)
    print(f"  cold start (import + first call) <= {TARGET_COLD_S:g} s: {cold:.2f} s "
          f"{yes(cold <= TARGET_COLD_S)} (whole interpreter incl. start-up and exit: "
          f"{wall:.2f} s)")


if __name__ == "__main__":
    main()
