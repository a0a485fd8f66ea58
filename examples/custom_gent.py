"""Register your own strain energy (Gent) and calibrate a visco-hyperelastic model with it.

vhfit has Gent built in (``"gent"``); this example writes it again as a user law named
``"my_gent"`` to show how any energy is registered. Gent's energy
W = -mu Jm / 2 ln(1 - (I1 - 3) / Jm) stiffens sharply as I1 - 3 approaches the locking
limit Jm. It is written once, as the formula; vhfit derives
the uniaxial stress from it (by complex-step differentiation) and the calibration
searches Jm (dimensionless, nonlinear) while solving mu (declared linear with
``linear_params``) and the Prony moduli exactly at every step. Runs in a few seconds.

    python examples/custom_gent.py
"""

import numpy as np

import vhfit


@vhfit.hyperelastic.register(
    "my_gent", units=("MPa", "-"), bounds=((0.0, np.inf), (0.5, 100.0)), example=(0.1, 10.0),
    linear_params=("mu",), overwrite=True,
)
def my_gent(I1, I2, mu, Jm):
    """Gent: W = -mu Jm / 2 ln(1 - (I1 - 3) / Jm)."""
    return -mu * Jm / 2 * np.log(1 - (I1 - 3) / Jm)


model = vhfit.ViscoHyperelastic("my_gent", n_prony=1)
print(model.param_names)  # ['mu', 'Jm', 'G1', 'tau1']

# Synthetic tests of a Gent material in tension at two rates (up to 80 % strain).
truth = dict(mu=0.05, Jm=3.0, G1=0.4, tau1=0.05)
strain = np.linspace(0.0, 0.8, 21)
curves = [
    vhfit.Curve(strain=strain, stress=model.stress(truth, strain=strain, strain_rate=r,
                                                   measure="engineering"),
                strain_rate=r, name=f"Gent tension {r:g}/s")
    for r in (0.1, 10.0)
]

# Jm's search range is given explicitly; the Drucker stability check is limited to
# stretches where every mode (uniaxial, equibiaxial, planar) stays below Gent's locking
# limit I1 - 3 < Jm, where the energy is defined.
cal = vhfit.calibrate(curves, hyperelastic="my_gent", n_prony=1, seed=0,
                      bounds={"Jm": (0.5, 20.0)}, stability_range=(0.7, 1.6))
print(cal.summary())
for k, v in truth.items():
    print(f"{k:>5}: true {v:<8g} fitted {cal.params[k]:.6g}")
assert abs(cal.params["Jm"] / truth["Jm"] - 1) < 1e-3, cal.params
