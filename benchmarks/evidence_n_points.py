# ruff: noqa: E501, E402, E401, I001
"""How many objective points per curve? (evidence for vhfit.data.DEFAULT_N_POINTS; not a test)

1. Paper's method (hyperelastic only): fit Mooney-Rivlin (C10, C01 >= 0, NNLS on Eq. 20)
   to n objective points of each real monotone curve, then score the fit with Eq. 20 on
   every measured sample. Report the excess over the fit made on all samples.
2. Resolution of loading-unloading / relaxation curves: piecewise-linear reconstruction of
   the whole measured curve from its objective points (by='segments'), RMS error relative to the
   curve's mean |stress|, for n per leg.
"""
import csv
import glob
import os
import warnings

import numpy as np
from scipy.optimize import nnls

from vhfit.data import Curve, read_csv

warnings.simplefilter("ignore")
D = os.environ.get(
    "VHFIT_DATA", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data")
) + os.sep

if not os.path.isdir(D):
    raise SystemExit(f"no datasets at {os.path.normpath(D)}: set VHFIT_DATA to their directory")

def mr_basis(strain):  # engineering stress of Mooney-Rivlin per unit C10, C01
    lam = 1 + strain
    return np.column_stack([2 * (lam - lam**-2), 2 * (1 - lam**-3)])

def eq20(model, target):
    return 100 * np.sqrt(np.mean(((model - target) / np.mean(np.abs(target))) ** 2))

def fit(c):
    A = mr_basis(c.target_strain) / np.mean(np.abs(c.target_stress))
    b = c.target_stress / np.mean(np.abs(c.target_stress))
    return nnls(A, b)[0]

curves = []
for f in sorted(glob.glob(D + "silicone_tensile_srmd/*.csv")):
    if f.endswith("index.csv"):
        continue
    curves.append(read_csv(f, columns={"time": None}, rate=0.227)[0])
for f in ("treloar1944_uniaxial_tension.csv", "treloar1944_uniaxial_tension_alt_digitization.csv"):
    curves.append(read_csv(D + "treloar1944_kawabata1981/" + f, rate=1e-3)[0])
for region in ("cortex", "corona_radiata", "basal_ganglia", "corpus_callosum"):
    # brain: the compression half (stretch <= 1) as its own monotone curve
    rows = [r for r in csv.DictReader(open(D + "brain_budday2017_quasistatic/budday2017_brain.csv"))
            if r["region"] == region and r["mode"].startswith("uniaxial") and float(r["stretch_or_shear_amount"]) <= 1]
    lam = np.array([float(r["stretch_or_shear_amount"]) for r in rows])[::-1]
    sig = np.array([float(r["nominal_stress_kPa"]) for r in rows])[::-1] * 1e-3
    curves.append(Curve(lam - 1, sig, strain_rate=-1e-3, name=f"brain {region} (compression)"))

ns = [3, 5, 8, 10, 15, 20, 40]
print("Part 1: MR fit on n points, Eq. 20 on all samples; excess over the all-samples fit (%)")
print(f"{'curve':42s} {'all':>7s} " + " ".join(f"n={n:<5d}" for n in ns))
table = []
for c in curves:
    dense = c.resample(None)
    keep = np.abs(dense.target_strain) > 0  # the rest point carries no information
    e_all = eq20(mr_basis(dense.target_strain[keep]) @ fit(dense), dense.target_stress[keep])
    row = []
    for n in ns:
        p = fit(c.resample(n))
        e = eq20(mr_basis(dense.target_strain[keep]) @ p, dense.target_stress[keep])
        row.append(100 * (e / e_all - 1))
    table.append(row)
    print(f"{c.name[:42]:42s} {e_all:7.2f} " + " ".join(f"{v:7.1f}" for v in row))
t = np.array(table)
print(f"{'median excess (%)':42s} {'':7s} " + " ".join(f"{v:7.1f}" for v in np.median(t, 0)))
print(f"{'90th percentile excess (%)':42s} {'':7s} " + " ".join(f"{v:7.1f}" for v in np.percentile(t, 90, 0)))

print("\nPart 2: reconstruction of the measured curve from its objective points (by='segments'),")
print("RMS error / mean|stress| (%), n points per segment")
files = (["vhb4910_zhao_rate_relaxation/loading_unloading/0d01_3d0.csv",
          "vhb4910_zhao_rate_relaxation/loading_unloading/0d05_1d5_1.csv",
          "vhb4910_zhao_rate_relaxation/relaxation/relax_2d0.csv",
          "vhb4910_hossain2012_digitized/loading_unloading_rate_0.03.csv",
          "hnbr50_miehe_goktepe2005/tension_compression_cycles_rate_1.07e-3.csv",
          "hnbr50_miehe_goktepe2005/pure_compression_cycles_rate_7.05e-2.csv",
          "hnbr50_miehe_goktepe2005/multistep_relaxation_tension_compression.csv",
          "muscle_compression_relaxation_digitized/fibre_rate_F_05.csv"])
ns2 = [5, 10, 20, 40]
print(f"{'curve':50s} segs " + " ".join(f"n={n:<5d}" for n in ns2))
for f in files:
    c = read_csv(D + f)[0]
    errs = []
    for n in ns2:
        r = c.resample(n)
        # reconstruct along time (monotone) through the rest point and the objective points
        tt = np.r_[0.0, r.target_time]
        ss = np.r_[0.0 if c.time[0] == 0 else c.stress[0], r.target_stress]
        rec = np.interp(c.time, tt, ss)
        errs.append(100 * np.sqrt(np.mean((rec - c.stress) ** 2)) / np.mean(np.abs(c.stress)))
    print(f"{f.split('/')[-1][:50]:50s} {c.n_segments:4d} " + " ".join(f"{v:7.2f}" for v in errs))
