"""Plots: panel grouping by stress magnitude, the three figures, and life without matplotlib."""

from __future__ import annotations

import sys
import warnings

import numpy as np
import pytest

import vhfit
from vhfit import plot


def test_group_by_magnitude_splits_orders_of_magnitude():
    # the paper's SEBS: slow curves at ~0.1 MPa, fast ones at ~1-2 MPa -> two panels
    assert plot.group_by_magnitude([0.08, 0.11, 0.96, 1.7]) == [[0, 1], [2, 3]]
    assert plot.group_by_magnitude([1.7, 0.08, 0.96, 0.11]) == [[1, 3], [0, 2]]
    assert plot.group_by_magnitude([1.0, 2.0, 9.0]) == [[0, 1, 2]]
    assert plot.group_by_magnitude([1e-3, 1.0, 1e3]) == [[0], [1], [2]]
    assert plot.group_by_magnitude([1.0, 3.0], ratio=2.0) == [[0], [1]]
    with pytest.raises(ValueError):
        plot.group_by_magnitude([1.0], ratio=1.0)


@pytest.fixture(scope="module")
def fitted():
    m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    truth = dict(C10=0.01, C01=0.005, G1=1.0, tau1=0.01)
    eps = np.linspace(0.0, -0.5, 11)
    curves = [vhfit.Curve(strain=eps, strain_rate=r, name=f"rate {r:g}",
                          stress=m.stress(truth, strain=eps, strain_rate=r,
                                          measure="engineering"))
              for r in (-0.01, -1000.0)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", vhfit.CalibrationWarning)
        cal = vhfit.calibrate(curves, n_prony="auto", max_prony=2, seed=0)
    return cal, curves


def test_fitted_curves_match_the_model(fitted):
    cal, curves = fitted
    fits = cal.fitted_curves(curves, points=50)
    assert len(fits) == 2
    for c, f in zip(curves, fits):
        np.testing.assert_allclose(f["stress"], c.target_stress)
        np.testing.assert_allclose(f["model"], cal.predict(c))
        assert f["fine_strain"][0] == 0 and f["fine_model"].shape == (50,)
        np.testing.assert_allclose(f["fine_strain"][-1], c.target_strain[-1])


def test_plots_are_written(fitted, tmp_path):
    pytest.importorskip("matplotlib")
    cal, curves = fitted
    fig = plot.plot_fit(cal, curves, tmp_path / "fit.png")
    assert len(fig.axes) == 2  # 0.02 MPa vs 0.5 MPa curves: two panels
    plot.plot_history(cal, tmp_path / "history.png")
    plot.plot_order_scan(cal, tmp_path / "scan.pdf")
    for f in ("fit.png", "history.png", "scan.pdf"):
        assert (tmp_path / f).stat().st_size > 1000


def test_order_scan_needs_a_scan(fitted):
    cal, _ = fitted

    class NoScan:
        order_scan: list = []

    with pytest.raises(ValueError, match="n_prony='auto'"):
        plot.plot_order_scan(NoScan())
    del cal


def test_without_matplotlib_the_message_says_how_to_install(fitted, monkeypatch, tmp_path):
    cal, curves = fitted
    for name in [m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib -> ImportError
    assert not plot.have_matplotlib()
    with pytest.raises(plot.PlotUnavailable, match=r"pip install 'vhfit\[plot\]'"):
        plot.plot_fit(cal, curves, tmp_path / "fit.png")
    with pytest.raises(ImportError):
        plot.plot_history(cal)
    # everything else still works
    assert len(cal.fitted_curves(curves)) == 2
