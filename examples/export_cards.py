"""Export a calibrated material to Abaqus, LS-DYNA, Ansys and JSON, and read each back.

Calibrates the bundled synthetic SEBS curves (generated from the paper's Table 5
parameters: not experimental data), writes one card per solver, re-imports every card
and checks that it gives the same stresses. Runs in a few seconds.

    python examples/export_cards.py
"""

import tempfile
from pathlib import Path

import numpy as np

import vhfit
from vhfit import datasets, export

curves = datasets.load_sebs()
cal = vhfit.calibrate(curves, n_prony=4, tau_strategy="semifree", seed=0)
print(f"calibrated: RMSAPE {cal.rmsape:.2g} % on {len(curves)} synthetic SEBS curves")

folder = Path(tempfile.mkdtemp(prefix="vhfit-cards-"))
files = {"abaqus": "sebs.inp", "lsdyna": "sebs.k", "ansys": "sebs.mac", "json": "sebs.json"}
strain = np.linspace(0.0, -0.6, 31)
reference = cal.model.stress(cal.params, strain=strain, strain_rate=-820.0)
for solver, name in files.items():
    card = getattr(export, f"to_{solver}")(cal.model, cal.params, name="SEBS_SYNTHETIC")
    (folder / name).write_text(card)
    # read the card back: the same material, hence the same stresses
    model, params = getattr(export, f"from_{solver}")(card)
    again = model.stress(params, strain=strain, strain_rate=-820.0)
    err = np.max(np.abs(again - reference)) / np.max(np.abs(reference))
    print(f"{solver:>7}: {folder / name}  ({len(card.splitlines())} lines), "
          f"re-imported stress error {err:.1e}")
    assert err < 1e-6

print()
print((folder / "sebs.inp").read_text())
