"""Curves of every homogeneous test: deformation=, stretches, both stresses, equilibrium.

Expectations are written by hand or from closed forms (neo-Hooke: the nominal stress of
direction a is P_a = 2 C10 (λ_a − λ_a⁻¹ λ3²) with λ3 = 1/(λ1 λ2), docs/theory.md).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import vhfit
from vhfit.data import Curve, DataError

LAM = np.array([1.0, 1.2, 1.5, 2.0])
C10 = 0.25


def neo_hooke_nominal(l1, l2):
    """(P1, P2) of an incompressible neo-Hooke solid, direction 3 stress-free."""
    l3 = 1.0 / (l1 * l2)
    return 2 * C10 * (l1 - l3**2 / l1), 2 * C10 * (l2 - l3**2 / l2)


def raises(*parts):
    return pytest.raises(DataError, match=".*".join(map(_re, parts)))


def _re(s):
    import re

    return re.escape(s)


# ------------------------------------------------------------ unchanged calls
def test_positional_uniaxial_calls_are_unchanged():
    eps = np.linspace(0.0, -0.4, 5)
    c = Curve(eps, 2 * eps, -10.0)
    assert c.deformation == "uniaxial" and not c.is_equilibrium and c.is_constant_rate
    assert c.strain_rate == -10.0 and c.name == "-10 1/s"
    assert c.strain2 is None and c.stress2 is None and c.target_strain2 is None
    np.testing.assert_array_equal(c.target_direction, np.ones(5))


def test_stretch_is_one_plus_strain():
    c = Curve(stretch=LAM, stress=LAM - 1.0, strain_rate=0.1)
    np.testing.assert_allclose(c.strain, LAM - 1.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(c.stretch, LAM, rtol=1e-15)


# ---------------------------------------------------------------- equilibrium
def test_a_curve_without_rate_or_time_is_at_equilibrium_in_any_order():
    lam = np.array([1.5, 1.1, 2.0, 1.1, 0.8])  # unsorted, a repeated state, both signs
    sig = np.array([0.9, 0.2, 1.5, 0.25, -0.4])
    c = Curve(stretch=lam, stress=sig)
    assert c.is_equilibrium and not c.is_constant_rate and c.strain_rate is None
    assert c.mode == "mixed" and c.name == "uniaxial (equilibrium)"
    assert c.n_points == 5 and c.by == "samples"  # nothing merged or reordered
    np.testing.assert_allclose(c.target_strain, lam - 1.0, atol=1e-15)
    np.testing.assert_array_equal(c.target_stress, sig)
    h = c.history
    assert h.is_equilibrium
    np.testing.assert_allclose(h.out_strain, lam - 1.0, atol=1e-15)
    assert "equilibrium" in repr(c)


def test_an_equilibrium_curve_has_no_time_to_trim():
    c = Curve(stretch=LAM, stress=LAM - 1.0)
    with raises("equilibrium curve has no time", "strain"):
        c.trim(time=(0.0, 1.0))
    assert c.trim(strain=(0.1, None)).n_points == 3


def test_equilibrium_curves_compare_the_long_term_law():
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 0)
    for dfm, (p1, _) in [("equibiaxial", neo_hooke_nominal(LAM, LAM)),
                         ("planar", neo_hooke_nominal(LAM, np.ones(4)))]:
        c = Curve(stretch=LAM, stress=p1, deformation=dfm)
        got = m.stress(dict(C10=C10, C01=0.0), c.history, measure=c.measure)
        np.testing.assert_allclose(got, p1, rtol=1e-12, atol=1e-15)


# ------------------------------------------------------------- biaxial tests
def test_a_biaxial_curve_compares_both_stresses_direction_by_direction():
    l1 = np.full(5, 1.5)  # λ1 held, λ2 varied: one biaxial curve as labs report it
    l2 = np.array([0.9, 1.0, 1.2, 1.4, 1.6])
    p1, p2 = neo_hooke_nominal(l1, l2)
    c = Curve(stretch=l1, stretch2=l2, stress=p1, stress2=p2, deformation="biaxial")
    assert c.n_points == 10 and c.name == "biaxial (equilibrium)"
    np.testing.assert_array_equal(c.target_direction, [1] * 5 + [2] * 5)
    np.testing.assert_array_equal(c.target_stress, np.concatenate([p1, p2]))
    np.testing.assert_allclose(c.target_strain2, np.tile(l2 - 1, 2), atol=1e-15)
    h = c.history
    np.testing.assert_array_equal(h.out_direction, c.target_direction)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 0)
    got = m.stress(dict(C10=C10, C01=0.0), h, measure="engineering")
    np.testing.assert_allclose(got, np.concatenate([p1, p2]), rtol=1e-12, atol=1e-15)


def test_an_equibiaxial_curve_may_give_its_second_stress():
    p1, _ = neo_hooke_nominal(LAM, LAM)
    c = Curve(stretch=LAM, stress=p1, stress2=1.01 * p1, deformation="equibiaxial")
    assert c.n_points == 8
    np.testing.assert_array_equal(c.target_stress[4:], 1.01 * p1)
    t = c.with_measure("true")  # σ2 = P2 λ2 and λ2 = λ1
    np.testing.assert_allclose(t.stress2, 1.01 * p1 * LAM, rtol=1e-15)


def test_a_biaxial_curve_converts_each_stress_with_its_own_stretch():
    l1, l2 = np.array([1.0, 1.2, 1.4]), np.array([1.0, 1.1, 1.3])
    c = Curve(stretch=l1, stretch2=l2, stress=[0, 1, 2], stress2=[0, 3, 4],
              deformation="biaxial")
    t = c.with_measure("true")
    np.testing.assert_allclose(t.stress, [0, 1.2, 2.8], rtol=1e-15)
    np.testing.assert_allclose(t.stress2, [0, 3.3, 5.2], rtol=1e-15)


def test_a_biaxial_time_history_follows_both_stretches():
    t = np.linspace(0.0, 4.0, 9)
    l1 = 1 + 0.1 * t
    l2 = 1 + 0.2 * np.minimum(t, 2.0)  # λ2 stops at t = 2 while λ1 goes on
    c = Curve(stretch=l1, stretch2=l2, stress=t, time=t, deformation="biaxial")
    h = c.history
    np.testing.assert_allclose(h.stretch_at(t), l1, rtol=1e-14)
    np.testing.assert_allclose(np.interp(t, h.time, h.stretch2), l2, rtol=1e-14)


def test_a_biaxial_curve_whose_first_stretch_stays_at_one_is_still_deformed():
    c = Curve(strain=np.zeros(3), strain2=[0.0, 0.1, 0.2], stress=[0.0, 0.1, 0.2],
              deformation="biaxial")
    assert c.n_points == 3


# --------------------------------------------------------------- simple shear
def test_simple_shear_takes_the_amount_of_shear_of_any_size():
    g = np.array([0.0, -0.5, -1.5, -2.5])  # γ below -1 is no stretch <= 0
    t = np.arange(4.0)
    c = Curve(strain=g, stress=[0.0, -0.2, -0.5, -0.9], time=t, deformation="simple shear")
    assert c.deformation == "simple_shear" and c.mode == "compression"
    assert "γ < 0" in repr(c)
    assert c.with_measure("true").stress is not None
    np.testing.assert_array_equal(c.with_measure("true").stress, c.stress)  # σ12 = P12


# ----------------------------------------------------------------------- names
@pytest.mark.parametrize("label, name", [
    ("pure shear", "planar"), ("Equibiaxial tension", "equibiaxial"),
    ("uniaxial_tension_compression", "uniaxial"), ("planar-tension", "planar"),
    ("SIMPLE_SHEAR", "simple_shear"), ("general biaxial", "biaxial"),
])
def test_lab_names_of_the_tests_are_understood(label, name):
    more = {"strain2": LAM - 1.0} if name == "biaxial" else {}
    c = Curve(strain=LAM - 1.0, stress=LAM - 1.0, deformation=label, **more)
    assert c.deformation == name


# ---------------------------------------------------------------------- errors
@pytest.mark.parametrize("kwargs, parts", [
    (dict(stretch=LAM, stress=LAM - 1, deformation="torsion"),
     ["'torsion'", "'uniaxial', 'equibiaxial', 'planar', 'biaxial', 'simple_shear'"]),
    (dict(stretch=LAM, stress=LAM - 1, deformation="biaxial"),
     ["biaxial curve needs its second stretch", "stretch2="]),
    (dict(stretch=LAM, stress=LAM - 1, deformation="simple_shear"),
     ["simple shear", "give strain=γ", "not stretch="]),
    (dict(stretch=LAM, strain2=LAM - 1, stress=LAM - 1, deformation="planar"),
     ["strain2= is only for deformation='biaxial'", "'planar'"]),
    (dict(stretch=LAM, stress=LAM - 1, stress2=LAM, deformation="planar"),
     ["stress2=", "'equibiaxial' and 'biaxial'"]),
    (dict(stretch=LAM, strain=LAM - 1, stress=LAM - 1), ["both strain= and stretch="]),
    (dict(stress=LAM - 1), ["no strain= or stretch="]),
    (dict(stretch=LAM), ["no stress="]),
    (dict(stretch=[1.0, 0.0, 2.0], stress=[0, 1, 2]), ["row 1", "stretch = 0", "> 0"]),
    (dict(stretch=LAM, stretch2=[1, 1, -1, 1], stress=LAM - 1, deformation="biaxial"),
     ["row 2", "stretch2"]),
    (dict(stretch=LAM, stretch2=LAM[:3], stress=LAM - 1, deformation="biaxial"),
     ["stretch2 has 3 values", "4"]),
])
def test_bad_mode_arguments_raise_one_line_errors(kwargs, parts):
    with raises(*parts) as info:
        Curve(**kwargs)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("deformation, stretch, stress", [
    ("equibiaxial", [1.0, 0.9, 0.8], [0.0, 0.1, 0.3]),  # stretch < 1 but tensile
    ("planar", [1.0, 1.2, 1.5], [0.0, -0.1, -0.3]),  # stretch > 1 but compressive
])
def test_a_sheet_stress_against_its_stretch_is_an_error_not_a_flip(deformation, stretch,
                                                                    stress):
    with raises(f"curve '{deformation} (equilibrium)' (row 2)", "wrong sign",
                deformation, "thickness stretch"):
        Curve(stretch=stretch, stress=stress, deformation=deformation)


def test_a_shear_stress_against_its_shear_is_an_error():
    with raises("row 2", "wrong sign for simple_shear", "same sign"):
        Curve(strain=[0.0, 0.5, 1.0], stress=[0.0, -0.2, -0.5], strain_rate=1.0,
              deformation="simple_shear")


def test_compression_given_positive_negates_both_directions():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c = Curve(strain=[0.0, 0.1], strain2=[0.0, 0.05], stress=[0.0, 1.0],
                  stress2=[0.0, 0.5], deformation="biaxial", compression_positive=True)
    np.testing.assert_array_equal(c.strain2, [0.0, -0.05])
    np.testing.assert_array_equal(c.stress2, [0.0, -0.5])


# ------------------------------------------------------------------- read_csv
def write(tmp_path, text, name="test.csv"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def test_a_biaxial_file_gives_one_curve_with_both_stresses(tmp_path):
    text = ("lambda1,lambda2,nominal_stress_1,nominal_stress_2\n"
            "1.04,0.98,0.0434,0.0\n1.04,1.00,0.0583,0.0284\n1.04,1.10,0.0900,0.1500\n")
    [c] = vhfit.read_csv(write(tmp_path, text, "kawabata.csv"))
    assert c.deformation == "biaxial" and c.is_equilibrium and c.name == "kawabata"
    np.testing.assert_allclose(c.strain, [0.04] * 3, rtol=1e-12)
    np.testing.assert_allclose(c.strain2, [-0.02, 0.0, 0.1], atol=1e-12)
    np.testing.assert_array_equal(c.stress2, [0.0, 0.0284, 0.15])
    np.testing.assert_array_equal(c.target_stress, [0.0434, 0.0583, 0.09, 0.0, 0.0284, 0.15])
    assert c.metadata["columns"]["strain2"] == "lambda2"


def test_a_deformation_column_splits_the_tests(tmp_path):
    text = ("test_type,stretch,stress_kPa\n"
            "uniaxial tension,1.0,0\nuniaxial tension,1.5,300\n"
            "equibiaxial,1.0,0\nequibiaxial,1.5,600\n"
            "pure shear,1.0,0\npure shear,1.5,400\n")
    cs = vhfit.read_csv(write(tmp_path, text, "rubber.csv"))
    assert [c.deformation for c in cs] == ["uniaxial", "equibiaxial", "planar"]
    assert [c.name for c in cs] == ["rubber [uniaxial tension]", "rubber [equibiaxial]",
                                    "rubber [pure shear]"]
    assert all(c.is_equilibrium for c in cs)
    np.testing.assert_allclose(cs[1].stress, [0.0, 0.6])
    np.testing.assert_allclose(cs[2].strain, [0.0, 0.5])


def test_the_test_of_a_file_from_its_line_or_the_argument(tmp_path):
    p = write(tmp_path, "# deformation: pure shear\nstretch,stress\n1,0\n1.2,0.1\n")
    assert vhfit.read_csv(p)[0].deformation == "planar"
    q = write(tmp_path, "stretch,stress\n1,0\n1.2,0.1\n", "q.csv")
    cs = vhfit.read_csv([p, q], deformation=["equibiaxial", "planar"])
    assert [c.deformation for c in cs] == ["equibiaxial", "planar"]  # the argument wins
    with raises("2 deformations for 3 files"):
        vhfit.read_csv([p, q, q], deformation=["equibiaxial", "planar"])


def test_a_shear_file_is_simple_shear_driven_by_gamma(tmp_path):
    text = "time_s,gamma,shear_stress_kPa\n0,0,0\n1,0.1,20\n2,0.2,35\n"
    [c] = vhfit.read_csv(write(tmp_path, text))
    assert c.deformation == "simple_shear" and c.strain_rate == pytest.approx(0.1)
    np.testing.assert_allclose(c.strain, [0.0, 0.1, 0.2])
    np.testing.assert_allclose(c.stress, [0.0, 0.02, 0.035])


def test_a_stretch_or_shear_column_is_gamma_on_shear_rows(tmp_path):
    text = ("region,mode,stretch_or_shear_amount,nominal_stress_kPa\n"
            "cortex,uniaxial_tension_compression,0.9,-1.1\n"
            "cortex,uniaxial_tension_compression,1.1,0.9\n"
            "cortex,simple_shear,-0.2,-0.3\ncortex,simple_shear,0.2,0.3\n")
    uni, shear = vhfit.read_csv(write(tmp_path, text, "brain.csv"))
    assert (uni.deformation, shear.deformation) == ("uniaxial", "simple_shear")
    np.testing.assert_allclose(uni.strain, [-0.1, 0.1], atol=1e-12)
    np.testing.assert_allclose(shear.strain, [-0.2, 0.2])  # γ as written
    np.testing.assert_allclose(shear.stress, [-3e-4, 3e-4])


def test_a_file_without_rate_or_time_is_at_equilibrium(tmp_path):
    [c] = vhfit.read_csv(write(tmp_path, "strain,stress\n0.2,1\n0,0\n0.1,0.4\n"))
    assert c.is_equilibrium and c.strain_rate is None
    np.testing.assert_array_equal(c.strain, [0.2, 0.0, 0.1])  # the file's order kept


@pytest.mark.parametrize("text, kwargs, parts", [
    ("stretch,stress\n1,0\n1.2,0.1\n", dict(deformation="simple_shear"),
     ["test.csv", "column 'stretch'", "amount of shear", "'gamma'"]),
    ("deformation,stretch,stress\nuniaxial,1,0\ntorsion,1.2,0.1\n", {},
     ["test.csv, line 3, column 'deformation'", "'torsion'", "'simple_shear'"]),
    ("deformation,stretch,stress\nplanar,1,0\nplanar,1.2,0.1\n",
     dict(deformation="equibiaxial"), ["says 'planar'", "deformation='equibiaxial'"]),
    ("stretch,stress\n1,0\n0.8,0.1\n", dict(deformation="equibiaxial"),
     ["test.csv, line 3", "wrong sign for equibiaxial"]),
    ("stretch,stress\n1,0\n1.2,0.1\n", dict(deformation="biaxial"),
     ["test.csv", "second stretch"]),
    ("stretch,stress\n1,0\n1.2,0.1\n", dict(deformation="cone"), ["test.csv", "'cone'"]),
])
def test_bad_mode_files_raise_one_line_errors_naming_the_file(tmp_path, text, kwargs, parts):
    with raises(*parts) as info:
        vhfit.read_csv(write(tmp_path, text), **kwargs)
    assert "\n" not in str(info.value)


def test_arrays_take_the_test_too():
    [c] = vhfit.data.curves_from_arrays({"stretch": LAM, "stress": LAM - 1.0},
                                        deformation="planar")
    assert c.deformation == "planar" and c.is_equilibrium
    c = Curve.from_array({"gamma": [0.0, 0.5], "shear_stress": [0.0, 0.2]}, rate=1.0)
    assert c.deformation == "simple_shear" and c.strain_rate == 1.0


def test_a_constant_rate_biaxial_curve_needs_a_proportional_second_stretch():
    with raises("curve 'biaxial 1 1/s'", "proportional", "time"):
        Curve(strain=[0.0, 0.1, 0.2], strain2=[0.0, 0.1, 0.1], stress=[0.0, 1.0, 2.0],
              strain_rate=1.0, deformation="biaxial")
    c = Curve(strain=[0.0, 0.1, 0.2], strain2=[0.0, 0.05, 0.1], stress=[0.0, 1.0, 2.0],
              strain_rate=1.0, deformation="biaxial")
    np.testing.assert_allclose(c.history.stretch2, [1.0, 1.1])
