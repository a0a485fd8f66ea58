"""Joint calibration: a DMA master curve and large-strain rate curves of one material.

Run::

    python benchmarks/bench_dma_joint.py            # 5 repeats per case
    python benchmarks/bench_dma_joint.py --quick    # 2 repeats

A Mooney–Rivlin + 3-term Prony material (C10 = 0.2, C01 = 0.05 MPa; G = 3, 1, 0.5 MPa at
τ = 1e-3, 0.1, 10 s) gives a storage/loss master curve (31 frequencies, 1e-3..1e3 Hz, from
the closed forms of the generalised Maxwell model written here) and three uniaxial
compression curves at −0.1, −10 and −1000 1/s to 50 % strain (200 samples each, from the
model's own kernel). ``vhfit.calibrate`` with its defaults fits all four together (and,
for comparison, the master curve with a relaxation test instead of the rate curves'
slowest). Goal: every constant back to 1e-6 relative in ≤ 3 s a fit (median wall time,
printed with the machine's cores; other work running there slows it).

:func:`joint_case` and :func:`measure` are importable (e.g. by another benchmark).
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time
import warnings

import numpy as np

import vhfit
from vhfit.calibration import CalibrationWarning

TRUE = dict(C10=0.2, C01=0.05, G1=3.0, tau1=1e-3, G2=1.0, tau2=0.1, G3=0.5, tau3=10.0)
RATES = (-0.1, -10.0, -1000.0)


def maxwell(omega, E_inf, G, tau):
    """(E′, E″) from the complex modulus E* = E∞ + Σ G_i iωτ_i / (1 + iωτ_i)."""
    w = np.asarray(omega, dtype=np.float64)[:, None]
    Es = E_inf + np.sum(np.asarray(G) * (1j * w * tau) / (1.0 + 1j * w * tau), axis=1)
    return Es.real, Es.imag


def joint_case(params: dict | None = None, *, relaxation: bool = False) -> list:
    """The master curve and the rate curves (or a relaxation test for the slowest)."""
    p = dict(TRUE if params is None else params)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 3)
    x = m.as_array(p)
    e_inf = float(m.long_term_modulus(x))
    G, tau = x[2::2], x[3::2]
    f = np.logspace(-3, 3, 31)
    e1, e2 = maxwell(2 * np.pi * f, e_inf, G, tau)
    items: list = [vhfit.FrequencySweep(frequency=f, storage=e1, loss=e2, name="master curve")]
    eps = np.linspace(0.0, -0.5, 201)[1:]
    rates = RATES[1:] if relaxation else RATES
    for r in rates:
        s = m.stress(p, strain=eps, strain_rate=r, measure="engineering")
        items.append(vhfit.Curve(strain=eps, stress=s, strain_rate=r, name=f"{r:g} 1/s"))
    if relaxation:
        t = np.r_[0.0, np.logspace(-4, 2, 40)]
        e_t = e_inf + np.sum(G * np.exp(-t[:, None] / tau), axis=1)
        items.append(vhfit.Relaxation(time=t, modulus=e_t, name="relaxation"))
    return items


def measure(repeats: int = 5, *, relaxation: bool = False, **kw) -> dict:
    """Median wall time of ``repeats`` fits of :func:`joint_case` and the worst relative
    error of the constants (the last fit's)."""
    items = joint_case(relaxation=relaxation)
    times, cal = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", CalibrationWarning)
            cal = vhfit.calibrate(items, hyperelastic="mooney_rivlin", n_prony=3,
                                  **{"seed": 0, **kw})
        times.append(time.perf_counter() - t0)
    err = max(abs(cal.params[k] - v) / v for k, v in TRUE.items())
    return {"median_s": statistics.median(times), "min_s": min(times), "max_rel_error": err,
            "rmsape": cal.rmsape, "generations": cal.nit, "repeats": repeats}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="2 repeats instead of 5")
    args = ap.parse_args()
    repeats = 2 if args.quick else 5
    load = f", load average {os.getloadavg()[0]:.1f}" if hasattr(os, "getloadavg") else ""
    print(f"vhfit {vhfit.__version__}, {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} cores{load}")
    vhfit.calibrate(joint_case()[:2], n_prony=1, seed=0, maxiter=2)  # compile the kernels
    print(f"{'case':<44}{'median s':>10}{'min s':>8}{'max rel err':>13}{'RMSAPE %':>11}"
          f"{'gen':>6}  goal")
    for label, rel in (("master curve + 3 rate curves", False),
                       ("master curve + relaxation + 2 rate curves", True)):
        r = measure(repeats, relaxation=rel)
        ok = r["median_s"] <= 3.0 and r["max_rel_error"] <= 1e-6
        print(f"{label:<44}{r['median_s']:>10.2f}{r['min_s']:>8.2f}{r['max_rel_error']:>13.1e}"
              f"{r['rmsape']:>11.1e}{r['generations']:>6}  {'met' if ok else 'MISSED'}")


if __name__ == "__main__":
    main()
