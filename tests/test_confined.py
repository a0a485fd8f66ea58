"""Tests that change the volume are named and refused, never fitted as uniaxial.

A foam in a confining cup (lateral stretches held at 1, J = λ: uniaxial strain) or a
volumetric test (J = λ³) cannot be deformed by an incompressible law at all. The files
here are synthetic: the stress is that of a linear elastic solid in uniaxial strain,
σ = (K + 4G/3) ε, which no incompressible law can produce. The reader must recognise the
test from a ``#`` comment line, a ``deformation``/``mode`` value or a header word;
``calibrate``, a model's stress and ``vhfit fit`` must refuse it in one line that says
why and what would work. Ordinary uniaxial files with comments stay uniaxial.
"""

from __future__ import annotations

import io

import numpy as np
import pytest

import vhfit
from vhfit import cli, modes
from vhfit.calibration import CalibrationError

M_OED = 2.0  # MPa: the constrained modulus K + 4G/3 of the synthetic foam
EPS = np.linspace(0.0, -0.3, 7)
WHY = ("an incompressible law cannot deform in confined compression (J = λ); fit the "
       "unconfined test, or wait for a volumetric law")


def _rows(extra: str = "") -> str:
    return "\n".join(f"{extra}{float(e)!r},{float(M_OED * e)!r}" for e in EPS) + "\n"


COMMENT = ("# CONFINED compression: foam in a steel cup, lateral stretches held at 1, "
           "J = lambda. NOT an incompressible uniaxial test\n# strain_rate: -0.01\n"
           "strain,stress_MPa\n" + _rows())
MODE_VALUE = "mode,strain_rate,strain,stress_MPa\n" + _rows("Confined compression,-0.01,")
DEFORMATION_VALUE = "deformation,strain_rate,strain,stress_MPa\n" + _rows("uniaxial strain,-0.01,")
HEADER_WORD = "# strain_rate: -0.01\nconfined_strain,stress_MPa\n" + _rows()
MODE_LINE = "# mode: confined compression\n# strain_rate: -0.01\nstrain,stress_MPa\n" + _rows()


@pytest.mark.parametrize("text", [COMMENT, MODE_VALUE, DEFORMATION_VALUE, HEADER_WORD,
                                  MODE_LINE],
                         ids=["comment line", "mode value", "deformation value",
                              "header word", "mode line"])
def test_the_reader_recognises_confined_compression(text):
    (c,) = vhfit.read_csv(io.StringIO(text))
    assert c.deformation == "confined_compression"
    np.testing.assert_allclose(c.strain, EPS)
    np.testing.assert_allclose(c.stress, M_OED * EPS)


@pytest.mark.parametrize("text, mode", [
    ("# hydrostatic compression test of a foam block\n# strain_rate: -0.01\n"
     "strain,stress_MPa\n" + _rows(), "volumetric"),
    ("deformation,strain_rate,strain,stress_MPa\n" + _rows("volumetric,-0.01,"),
     "volumetric"),
])
def test_the_reader_recognises_a_volumetric_test(text, mode):
    (c,) = vhfit.read_csv(io.StringIO(text))
    assert c.deformation == mode


@pytest.mark.parametrize("comment", [
    "# unconfined compression between lubricated plates",
    "# uniaxial compression, not confined (free lateral surface)",
    "# volumetric strain not measured; bulk modulus assumed 2000 MPa",
    "# uniaxial strain ramp, incompressible rubber",
    "# test: compression\n# mode: compression",
])
def test_ordinary_uniaxial_files_with_comments_stay_uniaxial(comment):
    text = f"{comment}\n# strain_rate: -0.01\nstrain,stress_MPa\n" + _rows()
    (c,) = vhfit.read_csv(io.StringIO(text))
    assert c.deformation == "uniaxial"


def test_a_mode_column_of_tension_and_compression_is_still_no_test_name():
    text = "mode,strain_rate,strain,stress_MPa\n" + _rows("compression,-0.01,")
    (c,) = vhfit.read_csv(io.StringIO(text))
    assert c.deformation == "uniaxial"


def test_what_names_the_test_beats_a_mention():
    # the '# deformation:' line and deformation= are what the user said: a mention in a
    # comment does not override them
    text = "# deformation: uniaxial\n" + COMMENT
    assert vhfit.read_csv(io.StringIO(text))[0].deformation == "uniaxial"
    assert vhfit.read_csv(io.StringIO(COMMENT), deformation="uniaxial")[0].deformation \
        == "uniaxial"


def test_the_records_kinematics_change_the_volume():
    lam = np.array([0.7, 0.9, 1.2])
    l1, l2, l3 = modes.principal_stretches("confined_compression", lam)
    np.testing.assert_allclose(l1 * l2 * l3, lam)  # J = λ
    l1, l2, l3 = modes.principal_stretches("volumetric", lam)
    np.testing.assert_allclose(l1 * l2 * l3, lam**3)  # J = λ³
    # the tests a law is evaluated in are the isochoric ones only
    assert "confined_compression" not in modes.DEFORMATIONS
    assert "confined_compression" in modes.registered_deformations()


@pytest.mark.parametrize("law", ["neo_hooke", "mooney_rivlin", "ogden2"])
def test_calibrate_refuses_confined_compression_in_one_line(law):
    curves = vhfit.read_csv(io.StringIO(COMMENT))
    with pytest.raises(CalibrationError) as exc:
        vhfit.calibrate(curves, hyperelastic=law, n_prony=0, seed=0)
    msg = str(exc.value)
    assert "\n" not in msg and WHY in msg and law in msg


def test_calibrate_refuses_a_volumetric_curve_among_good_ones():
    m = vhfit.ViscoHyperelastic("neo_hooke", 0)
    eps = np.linspace(0.0, -0.3, 7)
    good = vhfit.Curve(eps, m.stress([0.1], strain=eps, measure="engineering"),
                       name="unconfined")
    bad = vhfit.Curve(eps, M_OED * eps, deformation="hydrostatic", name="cup")
    with pytest.raises(CalibrationError, match=r"curve 'cup': an incompressible law cannot "
                                               r"deform in a volumetric test \(J = λ³\)"):
        vhfit.calibrate([good, bad], hyperelastic="neo_hooke", n_prony=0)


def test_a_model_has_no_stress_in_confined_compression():
    m = vhfit.ViscoHyperelastic("neo_hooke", 1)
    with pytest.raises(ValueError, match=r"^an incompressible law cannot deform in confined"):
        m.stress([0.1, 0.5, 0.01], strain=EPS, strain_rate=-0.01,
                 deformation="confined_compression")


def test_a_compressible_law_would_be_let_through():
    # the refusal is the law's incompressibility, asked of the law's record
    law = vhfit.hyperelastic.get("neo_hooke")
    assert modes.refusal_for(law, "confined_compression") == WHY
    from dataclasses import replace
    assert modes.refusal_for(replace(law, compressible=True), "confined_compression") is None
    assert modes.refusal_for(law, "uniaxial") is None


def test_cli_fit_refuses_with_exit_2_one_line_nothing_written(tmp_path, capsys):
    f = tmp_path / "foam_confined.csv"
    f.write_text(COMMENT)
    out = tmp_path / "out"
    code = cli.main(["fit", str(f), "--prony", "0", "--no-plot", "--out", str(out)])
    cap = capsys.readouterr()
    assert code == 2
    lines = cap.err.strip().splitlines()  # refused before the fit's first line is printed
    assert len(lines) == 1 and lines[0].startswith("vhfit: error: curve 'foam_confined': ")
    assert WHY in lines[0] and not cap.out
    assert not (out / "results.json").exists()
    assert not out.exists() or not any(out.rglob("*"))  # no card, no summary


def test_cli_fit_of_an_ordinary_commented_file_still_fits(tmp_path, capsys):
    m = vhfit.ViscoHyperelastic("neo_hooke", 0)
    eps = np.linspace(0.0, -0.3, 7)
    p = m.stress([0.1], strain=eps, measure="engineering")
    f = tmp_path / "foam_unconfined.csv"
    f.write_text("# unconfined compression between lubricated plates (not confined)\n"
                 "# strain_rate: -0.01\nstrain,stress_MPa\n"
                 + "\n".join(f"{float(e)!r},{float(s)!r}" for e, s in zip(eps, p)) + "\n")
    out = tmp_path / "out"
    code = cli.main(["fit", str(f), "--model", "neo_hooke", "--prony", "0", "--no-plot",
                     "-q", "--out", str(out)])
    capsys.readouterr()
    assert code == 0 and (out / "results.json").exists()


@pytest.mark.parametrize("text, name", [
    ("# Confined compression in a steel cup", "confined_compression"),
    ("foam in a confining ring", "confined_compression"),
    ("oedometer test", "confined_compression"),
    ("confined_strain", "confined_compression"),  # a header: words joined by '_'
    ("# hydrostatic pressure test", "volumetric"),
    ("# unconfined compression", None),
    ("# lubricated, non-confined", None),
    ("# not confined", None),
    ("# volumetric strain computed from the lateral gauge", None),
    ("# uniaxial tension", None),  # the isochoric tests have no mentions: no change
])
def test_which_words_mention_a_test(text, name):
    assert modes.deformation_mentioned(text) == name


def test_compare_refuses_a_test_no_law_can_represent():
    curves = vhfit.read_csv(io.StringIO(COMMENT))
    with pytest.raises(CalibrationError, match=WHY.replace("(", r"\(").replace(")", r"\)")):
        vhfit.compare(curves, ["neo_hooke", "mooney_rivlin"], n_prony=0, workers=1)
    # the check itself, as compare and calibrate ask it
    vhfit.calibration.refuse_unrepresentable(vhfit.read_csv(io.StringIO(
        COMMENT.replace("CONFINED", "UNCONFINED"))), "neo_hooke")  # passes: uniaxial


def test_cli_model_all_refuses_with_exit_2_not_a_table_of_failures(tmp_path, capsys):
    f = tmp_path / "foam.csv"
    f.write_text(MODE_VALUE)
    code = cli.main(["fit", str(f), "--model", "all", "--prony", "0", "--no-plot", "-q",
                     "--out", str(tmp_path / "out")])
    cap = capsys.readouterr()
    assert code == 2
    assert WHY in cap.err and "laws compared" not in cap.out
