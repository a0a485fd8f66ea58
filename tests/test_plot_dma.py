"""DMA plots: raw sweeps, master curve with a spectrum, shift factors, residuals."""

from __future__ import annotations

import io

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from vhfit import plot, tts  # noqa: E402
from vhfit.spectrum import prony_spectrum  # noqa: E402

LAW = tts.WLF(C1=9.0, C2=110.0, T_ref=20.0)

#: temperatures carry the data's own unit, named on every axis and colour bar
T_LABEL = "temperature (unit of the data: °C, K or °F)"


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
    assert figs["shift.png"].axes[0].get_xlabel() == T_LABEL
    res = figs["resid.png"].axes[0].lines[0].get_ydata()
    assert np.sqrt(np.mean(res**2)) <= spec.error * np.sqrt(2) + 1e-12


def test_moduli_fit_draws_the_data_and_the_model_of_each_item(tmp_path):
    """plot_moduli_fit: the sweep's E′ and E″ and the relaxation test's E(t) appear as
    the data given, and the model lines are the Maxwell moduli of the fitted constants
    (written here from the complex modulus, not from vhfit); stress–strain curves are
    left to plot_fit."""
    import vhfit  # noqa: PLC0415

    params = dict(C10=0.2, C01=0.05, G1=3.0, tau1=1e-2, G2=1.0, tau2=1.0)
    E_inf, G, tau = 1.5, np.array([3.0, 1.0]), np.array([1e-2, 1.0])
    f = np.logspace(-2, 2, 9)
    Es = E_inf + (G * (2j * np.pi * f[:, None] * tau) / (1 + 2j * np.pi * f[:, None] * tau)).sum(1)
    t = np.logspace(-3, 1, 7)
    sweep = vhfit.FrequencySweep(frequency=f, storage=Es.real, loss=Es.imag, name="dma")
    relax = vhfit.Relaxation(time=t, modulus=E_inf + (G * np.exp(-t[:, None] / tau)).sum(1))

    class Cal:  # what plot_moduli_fit reads of a Calibration
        model = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
        shift_table: dict = {}  # no time-temperature shift
        shift = None

        def fitted_curves(self, items):
            return [c.fitted_curve(self.model, params) for c in items]

    assert vhfit.data.is_moduli(sweep) and vhfit.data.is_moduli(relax)
    curve = vhfit.Curve(strain=[-0.1, -0.2], stress=[-0.1, -0.2], strain_rate=-1.0)
    assert not vhfit.data.is_moduli(curve)
    fig = plot.plot_moduli_fit(Cal(), [sweep, curve, relax], tmp_path / "m.png")
    assert (tmp_path / "m.png").stat().st_size > 0
    lines = [ln for ax in fig.axes for ln in ax.get_lines() if len(ln.get_xdata())]
    storage = next(ln for ln in lines if ln.get_label() == "dma: E'")
    np.testing.assert_allclose(storage.get_ydata(), Es.real, rtol=1e-15)
    fine = [ln for ln in lines if ln.get_linestyle() == "-" and len(ln.get_xdata()) == 200]
    x = fine[0].get_xdata()
    ref = E_inf + (G * (2j * np.pi * x[:, None] * tau) / (1 + 2j * np.pi * x[:, None] * tau)).sum(1)
    np.testing.assert_allclose(fine[0].get_ydata(), ref.real, rtol=1e-12)
    assert fig.axes[0].get_xlabel() == "frequency (Hz)"
    Cal.shift_table = {40.0: -2.0}  # a calibration that shifted tests to T_ref
    fig = plot.plot_moduli_fit(Cal(), [sweep])
    assert fig.axes[0].get_xlabel().startswith("reduced frequency")
    with pytest.raises(ValueError, match="no frequency sweeps"):
        plot.plot_moduli_fit(Cal(), [])


def _sweeps_at(temps):
    """Sweeps of one Prony material at each temperature, shifted by LAW (E' and E'' from
    the complex modulus written here)."""
    import vhfit  # noqa: PLC0415

    f = np.logspace(-1, 2, 6)
    tau, G = 10.0 ** np.arange(-5.0, 0.0), np.array([5.0, 8.0, 6.0, 3.0, 1.0])
    out = []
    for T in temps:
        wt = 2j * np.pi * (f * LAW.aT(T))[:, None] * tau
        E = 1 + (G * wt / (1 + wt)).sum(1)
        out.append(vhfit.FrequencySweep(frequency=f, storage=E.real, loss=E.imag,
                                        temperature=T, name=f"dma [T = {T:g}]"))
    return out


@pytest.mark.filterwarnings("error")
def test_sweeps_at_21_temperatures_get_a_colour_bar_not_a_legend(capfd):
    """Raw sweeps at 21 temperatures: coloured blue (cold) to red (hot) with a colour
    bar labelled temperature, no legend (it had 42 entries and squeezed the axes, with
    a layout warning on stderr); plot_moduli_fit draws them at f a_T, a_T from the
    calibration's table, and the same for plot_sweeps of a master curve."""
    import vhfit  # noqa: PLC0415

    temps = np.linspace(-50.0, 100.0, 21)
    items = _sweeps_at(temps)

    class Cal:
        model = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
        params = dict(C10=0.2, C01=0.05, G1=1.0, tau1=1e-2)
        shift_table = {float(T): float(LAW.log_aT(T)) for T in temps}
        shift = LAW

        def fitted_curves(self, its):
            return [c.fitted_curve(self.model, self.params) for c in its]

    fig = plot.plot_moduli_fit(Cal(), items, io.BytesIO())
    ax, bar = fig.axes
    assert ax.get_legend() is None and bar.get_ylabel() == T_LABEL
    assert bar.get_ylim() == pytest.approx((-50.0, 100.0))
    data = [ln for ln in ax.get_lines() if ln.get_marker() == "o"]
    assert len(data) == 21
    for ln, T in zip(data, temps):
        np.testing.assert_allclose(ln.get_xdata(), np.logspace(-1, 2, 6) * LAW.aT(T),
                                   rtol=1e-12)
    cold, hot = data[0].get_color(), data[-1].get_color()
    assert cold[2] > cold[0] and hot[0] > hot[2]  # blue cold, red hot
    sweeps = tts.sweeps_from_columns(
        np.repeat(temps, 6), frequency=np.tile(np.logspace(-1, 2, 6), 21),
        storage=np.concatenate([s.storage for s in items]),
        loss=np.concatenate([s.loss for s in items]))
    mc = tts.master_curve(sweeps, T_ref=20.0, shift_factors=LAW)
    fig = plot.plot_sweeps(mc, io.BytesIO())
    ax, bar = fig.axes
    assert ax.get_legend() is None and bar.get_ylabel() == T_LABEL
    assert len(ax.get_lines()) == 42
    assert capfd.readouterr().err == ""
