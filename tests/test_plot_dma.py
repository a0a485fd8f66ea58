"""DMA plots: raw sweeps, master curve with a spectrum, shift factors, residuals."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from vhfit import plot, tts  # noqa: E402
from vhfit.spectrum import prony_spectrum  # noqa: E402

LAW = tts.WLF(C1=9.0, C2=110.0, T_ref=20.0)


@pytest.fixture(scope="module")
def master():
    f = np.logspace(-1, 2, 8)
    temps = np.array([0.0, 20.0, 40.0])
    tau, G = 10.0 ** np.arange(-5.0, 0.0), np.array([5.0, 8.0, 6.0, 3.0, 1.0])
    rows = []
    for T in temps:
        wt = 2 * np.pi * (f * LAW.aT(T))[:, None] * tau
        rows.append((np.full(f.size, T), f, 1 + (G * wt**2 / (1 + wt**2)).sum(1),
                     (G * wt / (1 + wt**2)).sum(1)))
    cols = [np.concatenate(c) for c in zip(*rows)]
    sweeps = tts.sweeps_from_columns(cols[0], frequency=cols[1], storage=cols[2], loss=cols[3])
    return tts.master_curve(sweeps, T_ref=20.0, law="wlf")


def test_the_four_dma_figures_are_drawn_and_saved(master, tmp_path):
    spec = prony_spectrum(master, n_prony=4)
    figs = {
        "sweeps.png": plot.plot_sweeps(master, tmp_path / "sweeps.png"),
        "shifted.png": plot.plot_sweeps(master, tmp_path / "shifted.png", shifted=True),
        "master.png": plot.plot_master_curve(master, spec, tmp_path / "master.png"),
        "shift.png": plot.plot_shift_factors(master, tmp_path / "shift.png"),
        "resid.png": plot.plot_spectrum_residuals(master, spec, tmp_path / "resid.png"),
    }
    for name in figs:
        assert (tmp_path / name).stat().st_size > 1000
    ax = figs["sweeps.png"].axes[0]
    assert len(ax.lines) == 6  # E' and E'' of each of the 3 temperatures
    # shifted sweeps sit at f a_T: the hot sweep's first point at 0.1 * a_T(40)
    hot = figs["shifted.png"].axes[0].lines[4].get_xdata()
    assert hot[0] == pytest.approx(0.1 * 10 ** master.log_aT[2], rel=1e-12)
    # the law's line passes through 0 at T_ref
    line = figs["shift.png"].axes[0].lines[1]
    x, y = line.get_xdata(), line.get_ydata()
    assert np.interp(20.0, x, y) == pytest.approx(0.0, abs=1e-3)
    res = figs["resid.png"].axes[0].lines[0].get_ydata()
    assert np.sqrt(np.mean(res**2)) <= spec.error * np.sqrt(2) + 1e-12
