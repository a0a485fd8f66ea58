"""Several deformation modes and rates in one calibration (synthetic data, known answer).

The material is Ogden's three-term fit to Treloar's natural rubber (Ogden 1972, Proc. R.
Soc. Lond. A 326:565; μ_p = 0.63, 0.0012, −0.01 MPa and α_p = 1.3, 5.0, −2.0 in Ogden's
form W = Σ μ_p/α_p (λ1^α_p + λ2^α_p + λ3^α_p − 3)), written in vhfit's (Abaqus') form
W = Σ 2μ_p/α_p² (...), i.e. μ_p(vhfit) = μ_p α_p / 2, given an illustrative two-term
Prony series. From it we generate what a lab would measure:

* equilibrium (fully relaxed) uniaxial, equibiaxial and pure-shear curves — no rate, no
  time — like Treloar's own data;
* uniaxial tension ramps at 0.1, 10 and 1000 1/s, 100 samples each.

One call fits the long-term law to the equilibrium curves and the Prony series to the
ramps, and recovers the constants. Run: ``python examples/multimode.py``.
"""

from __future__ import annotations

import numpy as np

import vhfit

OGDEN_1972 = [(0.63, 1.3), (0.0012, 5.0), (-0.01, -2.0)]  # (μ_p, α_p), Ogden's form
TRUE = {}
for p, (mu, alpha) in enumerate(OGDEN_1972, start=1):
    TRUE[f"mu{p}"], TRUE[f"alpha{p}"] = mu * alpha / 2.0, alpha
TRUE.update(G1=2.0, tau1=1e-3, G2=0.5, tau2=0.1)


def measured_curves() -> list:
    model = vhfit.ViscoHyperelastic("ogden3", n_prony=2)
    curves = []
    lam = np.linspace(1.1, 4.0, 30)
    for mode in ("uniaxial", "equibiaxial", "planar"):
        P = model.stress(TRUE, stretch=lam, deformation=mode, measure="engineering")
        curves.append(vhfit.Curve(stretch=lam, stress=P, deformation=mode,
                                  name=f"{mode}, equilibrium"))
    eps = np.linspace(0.01, 1.0, 100)
    for rate in (0.1, 10.0, 1000.0):
        P = model.stress(TRUE, strain=eps, strain_rate=rate, measure="engineering")
        curves.append(vhfit.Curve(strain=eps, stress=P, strain_rate=rate,
                                  name=f"uniaxial, {rate:g} 1/s"))
    return curves


def main() -> None:
    curves = measured_curves()
    cal = vhfit.calibrate(curves, hyperelastic="ogden3", n_prony=2, seed=0)
    print(cal.summary())
    print("\nrecovered vs true:")
    for name, v in TRUE.items():
        print(f"  {name:<7} {cal.params[name]:>12.6g}  {v:>12.6g}")


if __name__ == "__main__":
    main()
