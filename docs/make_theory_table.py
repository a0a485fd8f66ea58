"""Print the verification table of docs/theory.md (paper §3.2 case against quadrature).

Case (the paper's verification against Abaqus): Mooney–Rivlin C10 = 0, C01 = 5 MPa,
one Prony term with g1 = 0.5 (G1 = E∞ g1 / g∞ = 30 MPa), τ1 ∈ {1e-10, 1e-6, 1e-5,
1e-4, 1} s, constant engineering strain rate −5700 1/s down to λ = 0.45.

The reference integrates the corrected Eq. 19 exactly as stated in docs/theory.md §4,

    σ(t) = σ0(t) − (g1/τ1) ∫_0^t e^(−(t−u)/τ1) σ0(u) [(2/3)(λ(t)/λ(u))² + (1/3) λ(u)/λ(t)] du,

with scipy.integrate.quad (break points at t − kτ1), independently of vhfit. The last
column but one evaluates the paper's misprinted kernel e^(−u/τ1) (absolute time instead
of lag) the same way, to show what the correction is worth. The last column evaluates,
the same way, the similarity form F_t τᴰ F_t⁻¹ of the hereditary integral (no
push-forward: K(u, t) = 1), to show how far the paper's Abaqus agreement (RMS < 0.04 %)
tells the two apart.

Run::

    python docs/make_theory_table.py
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.integrate import quad

import vhfit

C10, C01, G1 = 0.0, 5.0, 30.0
RATE = -5700.0
LAM_END = 0.45
TAUS = (1e-10, 1e-6, 1e-5, 1e-4, 1.0)
N_OUT = 56  # output points, evenly spaced in strain (first one at strain 0 excluded)


def sigma_h(lam: float) -> float:
    return 2 * C10 * (lam * lam - 1 / lam) + 2 * C01 * (lam - 1 / lam**2)


def eq19(t: float, tau: float, misprint: bool = False, similarity: bool = False) -> float:
    E_inf = 6 * (C10 + C01)
    G0 = E_inf + G1
    g1, g_inf = G1 / G0, E_inf / G0
    lt = 1 + RATE * t

    def f(u: float) -> float:
        lu = 1 + RATE * u
        K = 1.0 if similarity else (2 / 3) * (lt / lu) ** 2 + (1 / 3) * lu / lt
        weight = math.exp(-u / tau) if misprint else math.exp(-(t - u) / tau)
        return weight * sigma_h(lu) / g_inf * K / tau

    anchor = 0.0 if misprint else t
    pts = sorted({anchor + sgn * k * tau for k in (1, 4, 16, 64) for sgn in (-1, 1)}
                 - {0.0, t})
    pts = [p for p in pts if 0 < p < t]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        val = quad(f, 0.0, t, points=pts or None, epsabs=1e-13, epsrel=1e-13, limit=1000)[0]
    return sigma_h(lt) / g_inf - g1 * val


def main() -> None:
    eps = np.linspace(0.0, LAM_END - 1.0, N_OUT + 1)[1:]
    t = eps / RATE
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    print("| τ1 (s) | max\\|σ − σ_ref\\| / max\\|σ_ref\\| | RMS pointwise rel. error (%) "
          "| grid steps | misprinted Eq. 19 vs σ_ref (max rel.) "
          "| similarity form vs σ_ref (RMS rel., %) |")
    print("|---:|---:|---:|---:|---:|---:|")
    for tau in TAUS:
        x = [C10, C01, G1, tau]
        h = vhfit.History.constant_rate(eps, RATE)
        b = m.batch([h])
        s = b(np.array([x]))[0]
        ref = np.array([eq19(ti, tau) for ti in t])
        mis = np.array([eq19(ti, tau, misprint=True) for ti in t])
        sim = np.array([eq19(ti, tau, similarity=True) for ti in t])
        err = np.max(np.abs(s - ref)) / np.max(np.abs(ref))
        rms = np.sqrt(np.mean(((s - ref) / ref) ** 2)) * 100
        dev = np.max(np.abs(mis - ref)) / np.max(np.abs(ref))
        sim_rms = np.sqrt(np.mean(((sim - ref) / ref) ** 2)) * 100
        print(f"| {tau:g} | {err:.1e} | {rms:.1e} | {b.step.size} | {dev:.2f} "
              f"| {sim_rms:.3g} |")
    print()
    print(f"{N_OUT} points evenly spaced in strain from 0 to {LAM_END - 1:g} at {RATE:g} 1/s; "
          "default rtol = 1e-6.")


if __name__ == "__main__":
    main()
