"""ParamLayout: the layout [law constants..., G1, tau1, ..., GN, tauN] of a parameter vector."""

from __future__ import annotations

import numpy as np
import pytest

import vhfit
from vhfit.viscous import ParamLayout

MR = ParamLayout(("C10", "C01"), ("MPa", "MPa"), 2)


def test_names_units_and_roles_follow_the_law_then_the_terms():
    assert MR.names == ("C10", "C01", "G1", "tau1", "G2", "tau2")
    assert MR.units == ("MPa", "MPa", "MPa", "s", "MPa", "s")
    assert MR.roles == ("law", "law", "amplitude", "time", "amplitude", "time")
    assert (MR.n_law, MR.n_terms, MR.n_params) == (2, 2, 6)
    assert MR.term_names() == ("G1", "tau1", "G2", "tau2")
    assert ParamLayout(("C10",), ("MPa",), 0).names == ("C10",)
    assert MR.with_terms(1).names == ("C10", "C01", "G1", "tau1")
    assert [MR.names[MR.amplitude_index(i)] for i in range(2)] == ["G1", "G2"]
    assert [MR.names[MR.time_index(i)] for i in range(2)] == ["tau1", "tau2"]
    assert [MR.amplitude_name(i) for i in range(2)] == ["G1", "G2"]
    assert MR.time_name(9) == "tau10"


def test_the_model_is_described_by_its_layout():
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    assert m.layout == MR
    assert m.param_names == list(MR.names) and m.units == list(MR.units)
    law = vhfit.hyperelastic.get("ogden")
    assert vhfit.ViscoHyperelastic("ogden", 1).layout == ParamLayout.of(law, 1)


def test_split_and_assemble_are_inverse_to_the_bit():
    x = np.array([0.1, 0.05, 2.0, 1e-3, 1.0, 7.0])
    law, G, tau = MR.split(x)
    assert law.tolist() == [0.1, 0.05] and G.tolist() == [2.0, 1.0]
    assert tau.tolist() == [1e-3, 7.0]
    assert np.array_equal(MR.assemble(law, G, tau), x)
    # many sets at once (the last axis), and the pieces broadcast
    X = np.stack([x, 2 * x, 3 * x])
    assert np.array_equal(MR.assemble(*MR.split(X)), X)
    assert np.array_equal(MR.assemble([0.1, 0.05], [[2.0, 1.0]] * 3, [1e-3, 7.0])[2], x)
    # positions index a vector
    assert x[MR.term(1)].tolist() == [1.0, 7.0] and x[MR.law].tolist() == [0.1, 0.05]


def test_the_log_view_changes_the_times_only():
    x = np.array([0.1, 0.05, 2.0, 1e-3, 1.0, 100.0])
    z = MR.to_log(x)
    assert z.tolist() == [0.1, 0.05, 2.0, -3.0, 1.0, 2.0]
    assert x[3] == 1e-3  # a copy
    back = MR.from_log(z)
    assert np.array_equal(back[[0, 1, 2, 4]], x[[0, 1, 2, 4]])
    assert np.allclose(back, x, rtol=4 * np.finfo(float).eps, atol=0)


@pytest.mark.parametrize("name, role, index", [
    ("G1", "amplitude", 0), ("tau1", "time", 0), ("tau12", "time", 11), ("G3", "amplitude", 2)])
def test_parse_reads_a_terms_name(name, role, index):
    t = ParamLayout.parse(name)
    assert (t.role, t.index) == (role, index)
    assert ParamLayout.name(role, index) == name
    assert ParamLayout.is_time(name) == (role == "time")


@pytest.mark.parametrize("name", ["C10", "G0", "tau0", "tau01", "g1", "tau", "G1a", 3, "mu1"])
def test_parse_leaves_other_names(name):
    assert ParamLayout.parse(name) is None and not ParamLayout.is_time(name)


def test_count_terms_from_names():
    assert ParamLayout.count_terms(["C10", "C01"]) == 0
    assert ParamLayout.count_terms({"tau2": 1, "G1": 0, "C10": 1, "G2": 2, "tau1": 3}) == 2
    with pytest.raises(ValueError, match="missing G2, tau2$"):
        ParamLayout.count_terms(["G1", "tau1", "G3", "tau3"])
    huge = r"^tau1000000000: .* i = 1\.\.1000000000, but only 2 parameters"
    with pytest.raises(ValueError, match=huge):
        ParamLayout.count_terms(["C10", "tau1000000000"])


@pytest.mark.parametrize("make, match", [
    (lambda: ParamLayout(("C10",), ("MPa",), -1), "n_terms = -1"),
    (lambda: ParamLayout(("C10",), ("MPa",), True), "n_terms = True"),
    (lambda: ParamLayout(("C10",), ("MPa",), 1.5), "n_terms = 1.5"),
    (lambda: ParamLayout(("C10", "C01"), ("MPa",), 1), "2 law constants"),
    (lambda: MR.assemble([0.1], [1.0, 2.0], [1.0, 2.0]), "law constants has shape"),
    (lambda: MR.assemble([0.1, 0.2], [1.0], [1.0, 2.0]), "G has shape"),
    (lambda: MR.assemble([0.1, 0.2], [1.0, 2.0], [[1.0, 2.0, 3.0]]), "tau has shape"),
    (lambda: ParamLayout.count_terms(["tau2", "C10", "C01"]), "missing G1, tau1, G2$"),
])
def test_errors_are_one_line(make, match):
    with pytest.raises(ValueError, match=match) as err:
        make()
    assert "\n" not in str(err.value)
