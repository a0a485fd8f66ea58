"""Tests of vhfit.datasets: the bundled synthetic SEBS curves."""

from __future__ import annotations

import numpy as np
import pytest

from vhfit import datasets


def test_sebs_curves_follow_the_published_rates_and_strains():
    curves = datasets.load_sebs()
    assert [c.strain_rate for c in curves] == list(datasets.SEBS_RATES)
    assert datasets.SEBS_MAX_STRAIN == {-0.0018: -0.3, -0.18: -0.3, -59.5: -0.6, -820.0: -0.6}
    for c in curves:
        top = datasets.SEBS_MAX_STRAIN[c.strain_rate]
        # 26 samples evenly spaced from the rest state to the maximum strain; the 25
        # objective points are the samples after the rest point
        np.testing.assert_allclose(c.strain, top * np.arange(26) / 25, rtol=1e-6, atol=0)
        np.testing.assert_allclose(c.target_strain, c.strain[1:], rtol=1e-12)
        assert c.stress[0] == 0.0 and np.all(np.diff(c.stress) < 0)  # compression
        assert "SEBS (synthetic)" in c.name and f"{c.strain_rate:g} 1/s" in c.name
    whole = datasets.load_sebs(n_points=None)
    assert [c.target_strain.size for c in whole] == [26] * 4


def test_sebs_first_samples_match_the_small_strain_closed_form():
    """At the first sample, σ ≈ E∞ r t + Σ G_i r τ_i (1 − e^(−t/τ_i)) (docs/theory.md §4).

    The paper's Table 5 parameters; the linear solution is exact to first order in ε, and
    for Mooney–Rivlin with κ = C01/(C10 + C01) the true stress departs from it by at most
    (2κ + 1)|ε|(1 + 10|ε|) of itself; engineering stress adds |ε|/(1 − |ε|).
    """
    p = datasets.SEBS_PARAMS
    E_inf = 6 * (p["C10"] + p["C01"])
    G = np.array([p[f"G{i}"] for i in range(1, 5)])
    tau = np.array([p[f"tau{i}"] for i in range(1, 5)])
    kappa = p["C01"] / (p["C10"] + p["C01"])
    for c in datasets.load_sebs():
        eps, r = float(c.strain[1]), c.strain_rate
        t = eps / r
        lin = E_inf * eps + np.sum(G * r * tau * -np.expm1(-t / tau))
        e = abs(eps)
        tol = ((2 * kappa + 1) * e * (1 + 10 * e) + e / (1 - e)) * abs(lin)
        assert abs(c.stress[1] - lin) <= tol, (r, c.stress[1], lin)
    assert p["tau1"] == pytest.approx(10**-4.91) and p["G1"] == 3.49  # paper Table 5


def test_sebs_label_says_synthetic():
    assert "synthetic" in datasets.SEBS_LABEL and "not experimental" in datasets.SEBS_LABEL
    assert "Table 5" in datasets.SEBS_LABEL
    text = datasets.sebs_path().read_text()
    assert "SYNTHETIC" in text and "NOT experimental data" in text
