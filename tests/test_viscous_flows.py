"""The flow registry of the viscous networks and the records' validation (vhfit.viscous).

Rates are checked against the formulas evaluated by hand; bad input is refused in one
line.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from vhfit.viscous import Network, NetworkModel, flows


def test_the_four_flows_are_built_in_with_their_data_line_order():
    assert flows.available()[:4] == ("bergstrom_boyce", "strain", "power_law", "hyperb")
    assert flows.get("bergstrom_boyce").param_names == ("A", "m", "C", "E")
    assert flows.get("strain").param_names == ("A", "n", "m")
    assert flows.get("hyperb").param_names == ("A", "B", "n")
    assert flows.get("power_law").param_names == ("q0", "n", "m", "a", "eps0")
    assert [flows.get(n).abaqus for n in flows.available()[:4]] == [
        "BERGSTROM-BOYCE", "STRAIN", "POWER LAW", "HYPERB"]


@pytest.mark.parametrize("spelling, name", [
    ("BERGSTROM", "bergstrom_boyce"), ("BERGSTROM-BOYCE", "bergstrom_boyce"),
    ("Bergstrom_Boyce", "bergstrom_boyce"), ("STRAIN", "strain"), ("HYPERB", "hyperb"),
    ("POWER LAW", "power_law"), ("POWERLAW", "power_law"), ("power_law", "power_law")])
def test_solver_spellings_are_accepted(spelling, name):
    f = flows.get(spelling)
    assert isinstance(f, flows.Flow) and f.name == name and flows.get(f) is f


def test_an_unknown_flow_is_refused_in_one_line():
    with pytest.raises(ValueError, match=r"unknown flow 'TIME'; registered: bergstrom_boyce"):
        flows.get("TIME")
    with pytest.raises(ValueError, match="unknown flow") as e:
        Network("TIME", 0.5, (1.0,))
    assert "\n" not in str(e.value)


def test_rates_are_the_formulas():
    q, lc, eb = 1.7, 1.2, 0.03
    bb = flows.get("bergstrom_boyce").rate(q, lc, eb, 2e-3, 4.0, -1.0, 0.01)
    assert bb == pytest.approx(2e-3 * (0.2 + 0.01) ** -1.0 * 1.7**4, rel=1e-14)
    st = flows.get("strain").rate(q, lc, eb, 1e-5, 1.0, -0.5)
    assert st == pytest.approx((1e-5 * 1.7 * (0.5 * 0.03) ** -0.5) ** 2.0, rel=1e-14)
    hy = flows.get("hyperb").rate(q, lc, eb, 2.5e-5, 0.15, 2.0)
    assert hy == pytest.approx(2.5e-5 * math.sinh(0.15 * 1.7) ** 2, rel=1e-14)


@pytest.mark.parametrize("n, m", [(1.0, -0.5), (3.0, -0.2), (2.0, 0.0)])
def test_power_law_is_strain_with_A_from_q0_and_eps0(n, m):
    """With a = 0 (and p = 0: the networks' pressure is not tracked), POWER LAW is STRAIN
    with A = ε̇0^(m+1) q0^(−n), the identity the solver's own decks use."""
    q0, eps0 = 2.0, 3e-4
    q, eb = np.array([0.3, 1.0, 4.0]), np.array([1e-4, 0.02, 0.5])
    pl = flows.get("power_law").rate(q, 1.0, eb, q0, n, m, 0.7, eps0)
    st = flows.get("strain").rate(q, 1.0, eb, eps0 ** (m + 1) * q0**-n, n, m)
    np.testing.assert_allclose(pl, st, rtol=1e-13)


@pytest.mark.parametrize("flow, constants, match", [
    ("hyperb", (-1.0, 0.1, 2.0), r"A = -1 is outside its physical range"),
    ("strain", (1e-5, 1.0, -1.0), r"m = -1 must be > -1"),
    ("bergstrom_boyce", (1.0, 1.0, -1.0, 0.0), r"E = 0 with C = -1 < 0 makes the rate "
                                                r"infinite"),
    ("bergstrom_boyce", (1.0, 1.0, 0.5, 0.01), r"C = 0.5 is outside"),
    ("bergstrom_boyce", (1.0, 1.0, 0.0), r"takes 4 constants \['A', 'm', 'C', 'E'\], got 3"),
    ("strain", (math.nan, 1.0, -0.5), r"A = nan is not finite"),
])
def test_bad_constants_are_refused_in_one_line(flow, constants, match):
    with pytest.raises(ValueError, match=match) as e:
        Network(flow, 0.3, constants)
    assert "\n" not in str(e.value)


def test_a_user_flow_registers_works_and_unregisters():
    @flows.register("test_newtonian", params=("eta",), units=("MPa s",),
                    bounds=((0.0, math.inf),), aliases=("NEWTON",))
    def newtonian(q, lam_cr, eps_bar, eta):
        return q / eta

    try:
        assert flows.get("newton").name == "test_newtonian"
        assert flows.get("test_newtonian").abaqus is None
        assert flows.get("test_newtonian").rate(3.0, 1.0, 0.0, 2.0) == 1.5
        with pytest.raises(ValueError, match="already registered"):
            flows.register("test_newtonian", params=("eta",))(newtonian)
        with pytest.raises(ValueError, match=r"takes 1 constants \[.eta.\], got 3"):
            Network("NEWTON", 0.3, (1.0, 2.0, 3.0))
        assert Network("NEWTON", 0.3, (2.0,)).flow == "test_newtonian"
    finally:
        flows.unregister("test_newtonian")
    assert "test_newtonian" not in flows.available()
    with pytest.raises(ValueError, match="unknown flow"):
        flows.get("NEWTON")


def test_a_rate_function_must_match_its_constants():
    with pytest.raises(ValueError, match=r"takes \(q, lam_cr, eps_bar, \*constants\) with 2"):
        flows.register("test_bad", params=("a", "b"))(lambda q, lam_cr, eps_bar, a: q)


@pytest.mark.parametrize("ratios, match", [
    ((-0.5,), r"network ratio s = -0.5 must be a positive finite number"),
    ((0.0,), r"network ratio s = 0.0 must be a positive"),
    ((0.6, 0.4), r"network ratios sum to 1, not < 1"),
    ((0.7, 0.5), r"network ratios sum to 1.2, not < 1"),
])
def test_bad_ratios_are_refused_in_one_line(ratios, match):
    with pytest.raises(ValueError, match=match) as e:
        NetworkModel("neo_hooke", (0.5,),
                     tuple(Network("hyperb", s, (1e-3, 1.0, 1.0)) for s in ratios))
    assert "\n" not in str(e.value)


def test_model_records_validate_and_describe():
    n = Network("BERGSTROM", 0.3, [2.5e-5, 4, -1.0, 0.01])
    assert n.constants == (2.5e-5, 4.0, -1.0, 0.01) and n.flow == "bergstrom_boyce"
    m = NetworkModel("arruda_boyce", [20.0, 7.0], [Network("strain", 0.5, (1e-5, 1, -0.5)), n])
    assert m.networks[1] is n and m.law_params == (20.0, 7.0)
    assert m.describe() == "arruda_boyce + 2 networks (strain, bergstrom_boyce)"
    with pytest.raises(ValueError, match="at least one viscous network"):
        NetworkModel("neo_hooke", (0.5,), ())
    with pytest.raises(ValueError, match="outside its physical range"):
        NetworkModel("neo_hooke", (-0.5,), (n,))
    with pytest.raises(ValueError, match="unknown"):
        NetworkModel("no_such_law", (0.5,), (n,))


def test_unsupported_tests_and_measures_are_refused_in_one_line():
    m = NetworkModel("neo_hooke", (0.5,), (Network("hyperb", 0.3, (1e-3, 1.0, 1.0)),))
    t, lam = np.array([0.0, 1.0]), np.array([1.0, 1.1])
    with pytest.raises(ValueError, match=r"simple shear rotates them") as e:
        m.stress(t, lam, deformation="simple_shear")
    assert "\n" not in str(e.value)
    with pytest.raises(ValueError, match="incompressible"):
        m.stress(t, lam, deformation="confined_compression")
    with pytest.raises(ValueError, match=r"measure 'nominal'"):
        m.stress(t, lam, measure="nominal")
    with pytest.raises(ValueError, match="needs stretch2"):
        m.stress(t, lam, deformation="biaxial")
    with pytest.raises(ValueError, match="non-decreasing"):
        m.stress(t[::-1], lam)
    with pytest.raises(ValueError, match="one-stretch test"):
        m.creep(0.1, t, deformation="biaxial")
    with pytest.raises(ValueError, match="non-negative"):
        m.creep(0.1, [-1.0, 1.0])
