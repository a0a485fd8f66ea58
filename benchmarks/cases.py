"""Synthetic calibration cases of the paper, shared by the benchmarks.

The paper's experimental curves are not public; curves generated from its published
parameters at its rates are stand-ins, labelled as such. The five random materials
follow the paper's recipe (Mooney–Rivlin + 3 Prony terms at -1, -10, -100, -1000 1/s)
with constants drawn in the paper's Table 1 search ranges; log10 τ is drawn over the
whole Eq. 22 range, so two or three τ can share one semifree sub-range.
"""

from __future__ import annotations

import numpy as np

import vhfit

SEBS = dict(C10=0.00491, C01=0.00441, G1=3.49, tau1=10**-4.91, G2=0.0634, tau2=10**-1.99,
            G3=0.0603, tau3=10**0.581, G4=0.103, tau4=10**2.68)
SEBS_RATES = (-0.0018, -0.18, -59.5, -820.0)
GELATIN = dict(C10=0.0, C01=3.56e-4, G1=21.4, tau1=10**-5.76, G2=0.0211, tau2=10**0.871)
GELATIN_RATES = (-0.0107, -2500.0, -3600.0, -5700.0)
RANDOM_RATES = (-1.0, -10.0, -100.0, -1000.0)


def random_material(k: int) -> dict:
    """Random_k (k = 1..5): MR + 3 Prony terms, τ sorted, drawn over Eq. 22's range."""
    rng = np.random.default_rng(1000 + k)
    p = dict(C10=rng.uniform(0, 0.5), C01=rng.uniform(0, 0.5))
    logtau = np.sort(rng.uniform(-5, 1, 3))
    for i, lt in enumerate(logtau, start=1):
        p[f"G{i}"] = rng.uniform(0.1, 10.0)
        p[f"tau{i}"] = 10.0**lt
    return p


def n_prony(params: dict) -> int:
    return sum(1 for k in params if k.startswith("tau"))


def curves_for(params: dict, rates, *, n: int = 10, strain: float = -0.5, noise: float = 0.0,
               seed: int = 0, hyper: str = "mooney_rivlin") -> list:
    """Engineering-stress curves at constant rates, n points evenly spaced in strain.

    ``noise`` multiplies each stress by (1 + U(-noise, noise)), the paper's ±5 % noise.
    """
    m = vhfit.ViscoHyperelastic(hyper, n_prony(params))
    rng = np.random.default_rng(seed)
    out = []
    for r in rates:
        eps = np.linspace(strain / n, strain, n)
        s = m.stress(params, strain=eps, strain_rate=r, measure="engineering")
        if noise:
            s = s * (1.0 + rng.uniform(-noise, noise, s.size))
        out.append(vhfit.Curve(strain=eps, stress=s, strain_rate=r, measure="engineering",
                               name=f"{r:g} 1/s"))
    return out


def rmsape_of(params: dict, curves, hyper: str = "mooney_rivlin") -> float:
    """Eq. 20 of given parameters on given curves (e.g. the noise floor of the truth)."""
    m = vhfit.ViscoHyperelastic(hyper, n_prony(params))
    r = []
    for c in curves:
        y = np.asarray(c.target_stress)
        s = m.stress(params, c.history, measure=c.measure)
        r.append((s - y) / np.mean(np.abs(y)) * 100)
    r = np.concatenate(r)
    return float(np.sqrt(np.mean(r * r)))


CASES = {
    "SEBS (Table 5)": (SEBS, SEBS_RATES),
    "gelatin (Table 6)": (GELATIN, GELATIN_RATES),
    **{f"Random_{k}": (random_material(k), RANDOM_RATES) for k in range(1, 6)},
}
