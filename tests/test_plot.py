"""Plots: panel grouping by stress magnitude, the three figures, and life without matplotlib."""

from __future__ import annotations

import io
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


# ------------------------------------------------- plots that follow each test's record
# The model is neo-Hooke (C10) with one Prony term: its long-term stresses have closed
# forms, written here from the stretches (not from vhfit): uniaxial nominal
# P = 2 C10 (λ − λ⁻²), biaxial true σ_a = 2 C10 (λ_a² − λ3²) with λ3 = 1/(λ1 λ2),
# simple shear σ12 = 2 C10 γ.
C10 = 0.5
NH = dict(C10=C10, G1=2.0, tau1=1.0)


class _Cal:
    """What the plots read of a calibration: the model and its constants."""

    model = vhfit.ViscoHyperelastic("neo_hooke", n_prony=1)
    params = NH
    per_curve_rmsape: list = []
    rmsape = None
    shift_table: dict = {}
    shift = None

    def fitted_curves(self, items):
        return [c.fitted_curve(self.model, self.params) for c in items]


def _model_lines(ax):
    return [ln for ln in ax.get_lines() if ln.get_linestyle() in ("-", "--")
            and len(ln.get_xdata()) > 2]


def _ramp_hold():
    t = np.concatenate([np.linspace(0.0, 1.0, 6), np.linspace(2.0, 1800.0, 30)])
    eps = np.minimum(0.3 * t, 0.3)
    s = _Cal.model.stress(NH, strain=eps, time=t, measure="engineering")
    return vhfit.Curve(time=t, strain=eps, stress=s, name="ramp-hold")


@pytest.mark.filterwarnings("error")
def test_a_ramp_before_a_long_hold_is_drawn_through_and_its_time_view_relaxes(capfd):
    """A 1 s ramp before an 1800 s hold: the model line has points all along the ramp
    (a uniform grid of 200 over the test would put none inside it), ends at the
    long-term closed form, and a stress–time panel shows the same line in time."""
    pytest.importorskip("matplotlib")
    curve = _ramp_hold()
    assert plot.has_holds_or_unloading(curve)
    fig = plot.plot_fit(_Cal(), [curve], io.BytesIO())
    strain_ax, time_ax = [ax for ax in fig.axes if ax.get_visible()]
    (line,) = _model_lines(strain_ax)
    x, y = line.get_xdata(), line.get_ydata()
    inside = (x > 0.0) & (x < 0.3)
    assert inside.sum() >= 30 and np.all(np.diff(x[x < 0.3]) > 0)
    lam = 1.3
    assert y[-1] == pytest.approx(2 * C10 * (lam - lam**-2), rel=1e-9)
    assert strain_ax.get_xlabel() == "engineering strain λ1 − 1"  # tension only: no note
    assert strain_ax.get_ylabel() == "engineering stress (MPa)"
    (tline,) = _model_lines(time_ax)
    assert time_ax.get_xlabel() == "time (s)"
    np.testing.assert_array_equal(tline.get_ydata(), y)
    assert tline.get_xdata()[-1] == 1800.0 and (tline.get_xdata() < 1.0).sum() >= 30
    markers = [ln for ln in time_ax.get_lines() if ln.get_linestyle() == "None"]
    np.testing.assert_array_equal(markers[0].get_xdata(), curve.time)
    np.testing.assert_array_equal(markers[0].get_ydata(), curve.stress)
    ramp = plot.plot_fit(_Cal(), [vhfit.Curve(strain=[0.1, 0.2, 0.3], stress=[1, 2, 3],
                                              strain_rate=0.1)], io.BytesIO())
    assert len(ramp.axes) == 1  # a monotone ramp: no time view
    assert capfd.readouterr().err == ""


def _biaxial():
    """Two series of Kawabata's kind: λ1 held at 1.2 and at 1.6, λ2 from 0.9 up."""
    l1 = np.repeat([1.2, 1.6], 5)
    l2 = np.tile(np.linspace(0.9, 1.5, 5), 2)
    l3 = 1.0 / (l1 * l2)
    P1 = 2 * C10 * (l1**2 - l3**2) / l1
    P2 = 2 * C10 * (l2**2 - l3**2) / l2
    return vhfit.Curve(stretch=l1, stretch2=l2, stress=P1, stress2=P2,
                       deformation="biaxial", name="kawabata-like")


@pytest.mark.filterwarnings("error")
def test_a_biaxial_test_shows_both_directions_per_held_stretch_series():
    pytest.importorskip("matplotlib")
    curve = _biaxial()
    fig = plot.plot_fit(_Cal(), [curve], io.BytesIO())
    panels = [ax for ax in fig.axes if ax.get_xlabel()]
    assert len(panels) == 2  # direction 1 and direction 2
    bars = [ax for ax in fig.axes if ax.get_ylabel().startswith("held strain λ1")]
    assert len(bars) == 2  # the series are coloured by the held stretch
    for ax, direction in zip(panels, (1, 2)):
        assert ax.get_xlabel().startswith("engineering strain λ2 − 1")
        assert f"σ{direction}{direction}" in ax.get_ylabel()
        lines = _model_lines(ax)
        assert len(lines) == 2  # one per series, none back to the origin
        for ln, held in zip(lines, (1.2, 1.6)):
            e2 = ln.get_xdata()
            assert np.all(np.diff(e2) > 0)
            l2 = 1.0 + e2
            l3 = 1.0 / (held * l2)
            la = held if direction == 1 else l2
            np.testing.assert_allclose(ln.get_ydata(), 2 * C10 * (la**2 - l3**2) / la,
                                       rtol=1e-10)
        data = [ln for ln in ax.get_lines() if ln.get_linestyle() == "None"]
        want = curve.stress if direction == 1 else curve.stress2
        np.testing.assert_array_equal(np.concatenate([d.get_ydata() for d in data]), want)


@pytest.mark.filterwarnings("error")
def test_shear_is_labelled_gamma_and_the_sign_note_follows_the_data():
    pytest.importorskip("matplotlib")
    g = np.linspace(-0.4, 0.4, 9)
    shear = vhfit.Curve(strain=g, stress=2 * C10 * g, deformation="simple_shear",
                        name="shear")
    eps = np.linspace(0.05, 0.3, 6)
    lam = 1 + eps
    tension = vhfit.Curve(strain=eps, stress=2 * C10 * (lam - lam**-2), name="tension")
    comp = vhfit.Curve(strain=-eps, stress=2 * C10 * ((1 - eps) - (1 - eps) ** -2),
                       name="compression")
    fig = plot.plot_fit(_Cal(), [shear, tension, comp], io.BytesIO(), ratio=1e6)
    principal, gamma = fig.axes
    assert gamma.get_xlabel() == "amount of shear γ"
    assert gamma.get_ylabel() == "shear stress σ12 (MPa)"
    (ln,) = _model_lines(gamma)
    np.testing.assert_allclose(ln.get_ydata(), 2 * C10 * ln.get_xdata(), rtol=1e-10)
    assert principal.get_xlabel() == "engineering strain λ1 − 1 (tension > 0, compression < 0)"
    assert [t.get_text() for t in principal.get_legend().get_texts()] == [
        "tension", "compression"]
    only = plot.plot_fit(_Cal(), [comp], io.BytesIO()).axes[0]
    assert only.get_xlabel() == "engineering strain λ1 − 1 (compression < 0)"
    only = plot.plot_fit(_Cal(), [tension], io.BytesIO()).axes[0]
    assert "compression" not in only.get_xlabel()


@pytest.mark.filterwarnings("error")
def test_stress_time_figure_draws_the_model_line_of_each_history_that_holds():
    """plot_stress_time: one panel per history with holds or unloading (a monotone ramp
    is left out), its line model_line's; none to draw is a clear error."""
    pytest.importorskip("matplotlib")
    hold = _ramp_hold()
    ramp = vhfit.Curve(strain=[0.1, 0.2, 0.3], stress=[1, 2, 3], strain_rate=0.1)
    fig = plot.plot_stress_time(_Cal(), [ramp, hold], io.BytesIO())
    (ax,) = [a for a in fig.axes if a.get_visible()]
    assert ax.get_title() == "ramp-hold (0.3 1/s)" and ax.get_xlabel() == "time (s)"
    (ln,) = _model_lines(ax)
    want = plot.model_line(_Cal(), hold)
    np.testing.assert_array_equal(ln.get_xdata(), want["time"])
    np.testing.assert_array_equal(ln.get_ydata(), want["model"])
    with pytest.raises(ValueError, match="no history holds or unloads"):
        plot.plot_stress_time(_Cal(), [ramp])


@pytest.mark.filterwarnings("error")
def test_an_equibiaxial_test_with_both_stresses_shows_the_second_dashed():
    """Equibiaxial with stress2 given: squares and a dashed line for direction 2, both
    on the closed form P = 2 C10 (λ − λ⁻⁵) (λ3 = λ⁻²), equal in both directions."""
    pytest.importorskip("matplotlib")
    lam = np.linspace(1.1, 2.0, 6)
    P = 2 * C10 * (lam - lam**-5)
    curve = vhfit.Curve(stretch=lam, stress=P, stress2=P * 1.01, deformation="equibiaxial",
                        name="eb")
    (ax,) = plot.plot_fit(_Cal(), [curve], io.BytesIO()).axes
    solid, dashed = _model_lines(ax)
    assert solid.get_linestyle() == "-" and dashed.get_linestyle() == "--"
    for ln in (solid, dashed):
        x = ln.get_xdata()
        np.testing.assert_allclose(ln.get_ydata(), 2 * C10 * ((1 + x) - (1 + x) ** -5),
                                   rtol=1e-10)
    squares = [ln for ln in ax.get_lines() if ln.get_marker() == "s"]
    np.testing.assert_array_equal(squares[0].get_ydata(), P * 1.01)
    assert ax.get_ylabel().endswith("direction 2: squares, dashed")


def test_every_legend_is_beside_its_axes_and_inside_the_figure(fitted):
    """A legend never covers a curve: it sits outside the panel's data area (which an
    inside legend overlaps wherever it is placed), and whole within the saved figure
    (the PNG files are saved without a tight second layout pass)."""
    pytest.importorskip("matplotlib")
    cal, curves = fitted
    figs = [plot.plot_fit(cal, curves, io.BytesIO()), plot.plot_history(cal, io.BytesIO()),
            plot.plot_order_scan(cal, io.BytesIO())]
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    n_legends = 0
    for fig in figs:
        canvas = FigureCanvasAgg(fig)  # as savefig draws it (the layout runs)
        canvas.draw()
        renderer = canvas.get_renderer()
        whole = fig.bbox
        for ax in fig.axes:
            leg = ax.get_legend()
            if leg is None or not ax.get_visible():
                continue
            n_legends += 1
            box, area = leg.get_window_extent(renderer), ax.get_window_extent(renderer)
            assert box.x0 >= area.x1 or box.x1 <= area.x0 or box.y0 >= area.y1 \
                or box.y1 <= area.y0, (ax.get_title(), box, area)
            assert whole.x0 - 1 <= box.x0 and box.x1 <= whole.x1 + 1 and \
                whole.y0 - 1 <= box.y0 and box.y1 <= whole.y1 + 1, (box, whole)
    assert n_legends >= 3  # both fit panels' and the history's at least


def test_model_lines_give_the_laws_stress_on_each_stress_strain_curve():
    """Computed where the model is (the fit's process) and drawn elsewhere: the line of a
    neo-Hooke equilibrium curve is σ = 2 C10 (λ² − 1/λ) (true stress, written here)."""
    from vhfit.plot import model_lines

    m = vhfit.ViscoHyperelastic("neo_hooke", n_prony=0)

    class Cal:
        model, params = m, {"C10": 0.5}

    c = vhfit.Curve(strain=[0.0, 0.1, 0.3], stress=[0.0, 0.1, 0.3], measure="true")
    (line,) = model_lines(Cal, [c])
    lam = 1.0 + np.asarray(line["strain"])
    np.testing.assert_allclose(line["model"], 2 * 0.5 * (lam**2 - 1 / lam), rtol=1e-9,
                               atol=1e-12)
