"""Calibrate a visco-hyperelastic model to stress-strain curves read from CSV files.

Writes three small CSV files (synthetic compression tests of a known material at
three strain rates, with 2 % noise) to a temporary folder, reads them back with
``vhfit.read_csv`` as a user would read their own tests, calibrates Mooney-Rivlin +
2 Prony terms, and prints the parameter table. Runs in a few seconds.

    python examples/calibrate_from_csv.py
"""

import tempfile
from pathlib import Path

import numpy as np

import vhfit

# 1. The "laboratory": a known material and three constant-rate compression tests.
truth = dict(C10=0.02, C01=0.01, G1=1.0, tau1=0.005, G2=0.3, tau2=0.5)
lab = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=2)
rng = np.random.default_rng(42)
folder = Path(tempfile.mkdtemp(prefix="vhfit-example-"))
for rate in (-1.0, -10.0, -100.0):
    strain = np.linspace(0.0, -0.5, 41)
    stress = lab.stress(truth, strain=strain, strain_rate=rate, measure="engineering")
    stress[1:] *= 1 + 0.02 * rng.standard_normal(40)  # 2 % measurement noise
    lines = [f"# strain_rate: {rate}", "strain,stress_MPa"]
    lines += [f"{e:.6g},{s:.8g}" for e, s in zip(strain, stress)]
    (folder / f"compression_{-rate:g}_per_s.csv").write_text("\n".join(lines) + "\n")
print(f"test files in {folder}: {sorted(p.name for p in folder.glob('*.csv'))}")

# 2. Read the tests: one curve per file, the rate from the '# strain_rate:' line,
#    10 objective points per curve (the paper's choice), evenly spaced in strain.
curves = vhfit.read_csv(sorted(folder.glob("*.csv")))
for c in curves:
    print(c)

# 3. Calibrate and report.
cal = vhfit.calibrate(curves, hyperelastic="mooney_rivlin", n_prony=2, seed=0)
print()
print(cal.summary())

# 4. The noise-free truth is recovered to within the noise.
assert cal.rmsape < 5.0, cal.rmsape
cal.to_json(folder / "results.json")
print(f"\nresults written to {folder / 'results.json'}")
