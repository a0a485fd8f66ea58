"""Adding a test mode is one record: the uniaxial test written again under another name.

``uniaxial_again`` is registered here and nowhere else (no other module is touched). Its
record repeats uniaxial's kinematics (λ, λ^(−1/2), λ^(−1/2)) and says it is the paper's
test (``uniaxial = True``), so every module takes the same code path for it as for
``"uniaxial"``: stresses, fits (same seed: the same parameters bit for bit), the command
line with its cards and card check, the plots and the Abaqus test data must all come out
identical. The one independent reference is the closed form of neo-Hooke at equilibrium,
σ = 2 C10 (λ² − 1/λ), for the record's own kinematics.
"""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

import vhfit
from vhfit import cli, modes
from vhfit.export import to_abaqus_test_data
from vhfit.history import History

TOY = "uniaxial_again"
P = dict(C10=0.2, C01=0.1, G1=1.8, tau1=0.01)


@pytest.fixture(scope="module", autouse=True)
def toy():
    """Register the toy mode for this module's tests only."""

    @modes.register_deformation(TOY, aliases=("uniaxial twice", "ua"))
    class UniaxialAgain(modes.Deformation):
        description = "uniaxial written again: λ, λ^(−1/2), λ^(−1/2)"
        uniaxial = True  # the law's own uniaxial stress and the dedicated kernel
        standard_test = "uniaxial"

        def stretches(self, x1, x2=None):
            return x1, x1**-0.5, x1**-0.5

    yield modes.get_deformation(TOY)
    modes.unregister_deformation(TOY)
    assert TOY not in modes.registered_deformations()


def _ramps(deformation: str) -> list[vhfit.Curve]:
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    eps = np.linspace(0.0, -0.5, 21)
    return [vhfit.Curve(eps, m.stress(P, strain=eps, strain_rate=r, measure="engineering"),
                        strain_rate=r, deformation=deformation, name=f"ramp {r:g}")
            for r in (-1.0, -30.0, -1000.0)]


# ============================================================== the record
def test_the_toy_is_registered_with_its_aliases(toy):
    assert TOY in modes.registered_deformations()
    assert modes.get_deformation(TOY) is toy and toy.name == TOY
    assert modes.deformation_named("Uniaxial-Twice tension") == TOY
    assert modes.deformation_named("UA") == TOY
    assert toy.directions == 1 and not toy.second_stretch and not toy.shear


def test_a_name_or_alias_cannot_be_taken_twice():
    with pytest.raises(ValueError, match="'ua' already names 'uniaxial_again'"):
        @modes.register_deformation("another_toy", aliases=("ua",))
        class Another(modes.Deformation):
            pass
    with pytest.raises(ValueError, match="already registered"):
        @modes.register_deformation(TOY)
        class Again(modes.Deformation):
            pass
    assert "another_toy" not in modes.registered_deformations()


def test_a_record_that_loads_its_stress_free_direction_is_refused():
    with pytest.raises(ValueError, match="stress_free is another direction"):
        @modes.register_deformation("bad_toy")
        class Bad(modes.Deformation):
            measured = ("σ11", "σ22")
            stress_free = 2
    assert "bad_toy" not in modes.registered_deformations()


def test_aliases_are_compared_without_the_words_that_say_nothing():
    @modes.register_deformation("noisy_toy", aliases=("Noisy Tension Test",))
    class Noisy(modes.Deformation):
        def stretches(self, x1, x2=None):
            return x1, x1**-0.5, x1**-0.5
    try:
        assert modes.deformation_named("noisy") == "noisy_toy"
        assert modes.deformation_named("noisy compression") == "noisy_toy"
    finally:
        modes.unregister_deformation("noisy_toy")


def test_the_toys_equilibrium_stress_is_the_closed_form():
    lam = np.array([0.5, 0.8, 1.0, 1.5, 2.5])
    got = modes.long_term_stress(vhfit.hyperelastic.get("neo_hooke"), [0.3], TOY, lam)
    np.testing.assert_allclose(got, 2 * 0.3 * (lam**2 - 1 / lam), rtol=1e-13, atol=1e-15)


# ============================================================ same stresses
@pytest.mark.parametrize("formulation", ["hereditary", "lsdyna"])
def test_stresses_are_those_of_uniaxial(formulation):
    m = vhfit.ViscoHyperelastic("ogden2", 2, formulation=formulation)
    x = dict(zip(m.param_names, [0.3, 2.0, 0.01, -3.0, 1.2, 0.05, 0.4, 2.0]))
    eps = np.linspace(0.0, 0.8, 17)
    for kw in (dict(strain_rate=5.0), dict(time=np.linspace(0, 2, 17)), {}):
        np.testing.assert_array_equal(
            m.stress(x, strain=eps, deformation=TOY, measure="engineering", **kw),
            m.stress(x, strain=eps, measure="engineering", **kw))
    h_toy = History.piecewise_linear([0, 1, 2], [0, -0.4, 0.1], deformation=TOY)
    h_uni = History.piecewise_linear([0, 1, 2], [0, -0.4, 0.1])
    np.testing.assert_array_equal(m.stress(x, h_toy), m.stress(x, h_uni))
    np.testing.assert_array_equal(h_toy.out_loaded_stretch, h_uni.out_loaded_stretch)


# ============================================================== same fits
def test_a_fit_is_that_of_uniaxial_bit_for_bit():
    opts = dict(n_prony=1, seed=3, maxiter=40, uncertainty=False)
    toy = vhfit.calibrate(_ramps(TOY), **opts)
    uni = vhfit.calibrate(_ramps("uniaxial"), **opts)
    assert toy.params == uni.params
    assert toy.rmsape == uni.rmsape
    for a, b in zip(toy.fitted_curves(_ramps(TOY)), uni.fitted_curves(_ramps("uniaxial"))):
        np.testing.assert_array_equal(a["fine_model"], b["fine_model"])


def test_the_plots_draw_the_toy_as_uniaxial(tmp_path):
    pytest.importorskip("matplotlib")
    from vhfit import plot

    cal = vhfit.calibrate(_ramps("uniaxial"), n_prony=1, seed=0, maxiter=5,
                          uncertainty=False)
    figs = [plot.plot_fit(cal, _ramps(d), tmp_path / f"{d}.png") for d in (TOY, "uniaxial")]
    lines = [[ln.get_xydata() for ax in f.axes for ln in ax.get_lines()] for f in figs]
    assert len(lines[0]) == len(lines[1]) > 0
    for a, b in zip(*lines):
        np.testing.assert_array_equal(a, b)
    assert [ax.get_xlabel() for ax in figs[0].axes] == [ax.get_xlabel() for ax in figs[1].axes]
    assert (tmp_path / f"{TOY}.png").stat().st_size > 0


def test_the_abaqus_test_data_of_the_toy_are_uniaxial_lines():
    lam = np.linspace(1.1, 2.0, 4)
    p = 0.4 * (lam - lam**-2)
    toy, uni = (to_abaqus_test_data([vhfit.Curve(stretch=lam, stress=p, deformation=d)],
                                    "neo_hooke") for d in (TOY, "uniaxial"))
    assert "*UNIAXIAL TEST DATA" in toy and toy == uni


# ========================================================== command line
def _write(folder) -> list[str]:
    paths = []
    for c in _ramps("uniaxial"):
        path = folder / f"ramp_{-c.strain_rate:g}.csv"
        rows = "".join(f"{float(e)!r},{float(s)!r}\n" for e, s in zip(c.strain, c.stress))
        path.write_text(f"# strain_rate: {c.strain_rate}\nstrain,stress_MPa\n{rows}")
        paths.append(str(path))
    return paths


def _card_lines(path) -> list[str]:
    """The lines of a card that solvers read (comments, which name the run, left out)."""
    return [ln for ln in path.read_text().splitlines()
            if ln.strip() and not ln.startswith(("**", "$", "!", "/COM"))]


def _fit(data, out, *flags):
    argv = ["fit", *data, "--prony", "1", "--seed", "0", "--maxiter", "30", "-q",
            "--out", str(out), *flags]
    assert cli.main(argv) == 0
    return json.loads((out / "results.json").read_text())


def test_cli_fit_with_the_toy_mode_gives_the_uniaxial_fit_cards_and_check(tmp_path):
    pytest.importorskip("matplotlib")
    data = _write(tmp_path)
    toy = _fit(data, tmp_path / "toy", "--deformation", "uniaxial twice")
    uni = _fit(data, tmp_path / "uni")
    assert [c["deformation"] for c in toy["curves"]] == [TOY] * 3
    assert toy["params"] == uni["params"]
    assert toy["card_check"] == uni["card_check"]  # each card re-simulated and scored
    assert set(toy["card_check"]) == {"abaqus", "lsdyna", "ansys"}
    assert toy["cards"] == uni["cards"]
    for solver, card in uni["cards"].items():  # the same cards, but for their comments
        if solver != "json":
            assert _card_lines(tmp_path / "toy" / card) == _card_lines(tmp_path / "uni" / card)
    pngs = sorted(p.name for p in (tmp_path / "toy").glob("*.png"))
    assert pngs and pngs == sorted(p.name for p in (tmp_path / "uni").glob("*.png"))
    rows = [list(csv.DictReader(ln for ln in open(tmp_path / d / "fitted_curves.csv")
                                if not ln.startswith("#"))) for d in ("toy", "uni")]
    assert rows[0] and rows[0] == rows[1]
