"""Simple shear beside uniaxial tension of the same size: evaluation and fit times.

Run::

    python benchmarks/bench_shear.py              # 5 repeats
    python benchmarks/bench_shear.py --repeats 3

A synthetic staircase relaxation test, generated from a known material (one-term Ogden,
N = 3 Prony terms) with 0.5 % seeded noise: 4 rates from 0.01 to 1 1/s, each curve four
ramps of equal size and a hold after each, about 385 samples a curve (1540 in all). The
same staircase is written once as simple shear (amount of shear γ up to 1) and once as
uniaxial tension (strain up to 1), at the same times. Printed, medians of the repeats
measured side by side in this one run:

* the cost of one evaluation: a population of 64 parameter sets evaluated by the
  model's batch, divided by 64;
* ``calibrate(..., n_prony=3)`` and ``calibrate(..., n_prony="auto")`` wall times;
* the ratios shear / uniaxial.

Goals (issue 34): per-evaluation cost of simple shear ≤ 2 × uniaxial;
``n_prony="auto"`` on simple shear ≤ 2 s.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
import warnings

import numpy as np

import vhfit
from vhfit.calibration import CalibrationWarning

LAW = "ogden"
TRUTH = dict(mu1=0.2, alpha1=2.5, G1=0.4, tau1=0.5, G2=0.2, tau2=5.0, G3=0.1, tau3=50.0)
RATES = (0.01, 0.1 ** (4 / 3), 0.1 ** (2 / 3), 1.0)
STEPS = 4  # ramps of the staircase
TOP = 1.0  # γ (shear) or ε (uniaxial) at the end of the last ramp
RAMP_SAMPLES, HOLD_SAMPLES = 40, 56  # 4 × (40 + 56) + 1 = 385 samples a curve
HOLD = 100.0  # s, every hold
POP = 64


def staircase(rate: float) -> tuple[np.ndarray, np.ndarray]:
    """(time, strain): ramps of TOP/STEPS at ``rate``, each followed by a hold."""
    t, x = [0.0], [0.0]
    ramp = TOP / STEPS / rate
    for _ in range(STEPS):
        t0, x0 = t[-1], x[-1]
        u = np.arange(1, RAMP_SAMPLES + 1) / RAMP_SAMPLES
        t += list(t0 + ramp * u)
        x += list(x0 + TOP / STEPS * u)
        u = np.arange(1, HOLD_SAMPLES + 1) / HOLD_SAMPLES
        t += list(t[-1] + HOLD * u)
        x += [x[-1]] * HOLD_SAMPLES
    return np.array(t), np.array(x)


def curves(deformation: str) -> list:
    model = vhfit.ViscoHyperelastic(LAW, 3)
    rng = np.random.default_rng(0)
    out = []
    for r in RATES:
        t, x = staircase(r)
        s = model.stress(TRUTH, strain=x, time=t, deformation=deformation,
                         measure="engineering")
        s = s * (1.0 + 0.005 * rng.standard_normal(s.size))
        out.append(vhfit.Curve(strain=x, stress=s, time=t, deformation=deformation,
                               name=f"{deformation} {r:.3g} 1/s"))
    return out


def population(model, seed: int = 1) -> np.ndarray:
    """POP parameter sets scattered around the truth (the search's kind of population)."""
    x = model.as_array(TRUTH)
    rng = np.random.default_rng(seed)
    return x * np.exp(0.3 * rng.standard_normal((POP, x.size)))


def eval_ms(batch, X, calls: int = 20) -> float:
    """Milliseconds per parameter set of one population evaluation."""
    batch(X)  # warm
    t0 = time.perf_counter()
    for _ in range(calls):
        batch(X)
    return (time.perf_counter() - t0) / calls / X.shape[0] * 1e3


def fit_s(data, n_prony) -> tuple[float, float]:
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CalibrationWarning)
        cal = vhfit.calibrate(data, hyperelastic=LAW, n_prony=n_prony, seed=0,
                              uncertainty=False)
    return time.perf_counter() - t0, cal.rmsape


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    data = {d: curves(d) for d in ("uniaxial", "simple_shear")}
    model = vhfit.ViscoHyperelastic(LAW, 3)
    X = population(model)
    batches = {d: model.batch(c) for d, c in data.items()}
    n = sum(c.strain.size for c in data["simple_shear"])
    print(f"staircase: {len(RATES)} rates, {n} samples in all; law {LAW}, N = 3; "
          f"{os.cpu_count()} cores; medians of {args.repeats} repeats, side by side")
    for d in data:  # warm: compile and cache outside the timings
        fit_s(data[d], 1)
    rows: dict = {d: {"eval": [], "n3": [], "auto": [], "err3": None, "errauto": None}
                  for d in data}
    for _ in range(args.repeats):
        for d in data:  # interleaved: a busy moment of the machine hits both
            rows[d]["eval"].append(eval_ms(batches[d], X))
            t, rows[d]["err3"] = fit_s(data[d], 3)
            rows[d]["n3"].append(t)
            t, rows[d]["errauto"] = fit_s(data[d], "auto")
            rows[d]["auto"].append(t)
    med = {d: {k: statistics.median(v) for k, v in r.items() if isinstance(v, list)}
           for d, r in rows.items()}
    print(f"{'':<14}{'ms/eval':>10}{'N=3 s':>9}{'auto s':>9}{'RMSAPE N=3':>12}"
          f"{'RMSAPE auto':>13}")
    for d in data:
        m = med[d]
        print(f"{d:<14}{m['eval']:>10.4f}{m['n3']:>9.2f}{m['auto']:>9.2f}"
              f"{rows[d]['err3']:>12.4f}{rows[d]['errauto']:>13.4f}")
    u, s = med["uniaxial"], med["simple_shear"]
    print(f"{'shear/uniax':<14}{s['eval'] / u['eval']:>10.2f}{s['n3'] / u['n3']:>9.2f}"
          f"{s['auto'] / u['auto']:>9.2f}")
    ok_eval, ok_auto = s["eval"] <= 2.0 * u["eval"], s["auto"] <= 2.0
    print(f"goal per-eval shear <= 2 x uniaxial: {'yes' if ok_eval else 'NO'}; "
          f"goal shear auto <= 2 s: {'yes' if ok_auto else 'NO'}")


if __name__ == "__main__":
    main()
