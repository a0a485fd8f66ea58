"""Cards of network models (Abaqus's parallel rheological framework, PRF): writer, reader.

The writer's layout is pinned against the keyword lines as Abaqus's own verification
decks spell them (the reference material of two PRF creep cases, written here by hand):
``*HYPERELASTIC, <law>, MODULI=INSTANTANEOUS`` with the instantaneous constants, then one
``*VISCOELASTIC, NONLINEAR, NETWORKID=k, SRATIO=s_k, LAW=...`` block per network, its data
line in Abaqus's order (STRAIN: A, n, m; BERGSTROM-BOYCE: A, m, C, E; HYPERB: A, B, n;
POWER LAW: q0, n, m, a, eps0). The reader must read Abaqus's spellings back to the same
constants, and refuse in one line what it cannot read. Solvers whose network equations are
not public refuse a network model in one line. The stresses these cards give are checked
against Abaqus's own results in tests/test_cli_simulate_card.py.
"""

from __future__ import annotations

import math

import pytest

from vhfit.export import export, from_abaqus, parse, records, to_abaqus
from vhfit.viscous import Network, NetworkModel, flows

#: The reference material (Abaqus's PRF verification cases), keyword lines as Abaqus reads
#: them: Arruda-Boyce mu = 20, lambda_m = 7 (instantaneous), D = 0.
HYPER = "*HYPERELASTIC, ARRUDA-BOYCE, MODULI=INSTANTANEOUS\n 20., 7.\n"
U1 = HYPER + """*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5, LAW=STRAIN
 1.0E-5, 1., -0.5
*VISCOELASTIC, NONLINEAR, NETWORKID=2, SRATIO=0.3, LAW=BERGSTROM
 2.5E-5, 4, -1.0, 0.01
"""
U2 = HYPER + """*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5, LAW=STRAIN
 1.0E-5, 1., -0.5
*VISCOELASTIC, NONLINEAR, NETWORKID=2, SRATIO=0.3, LAW=HYPERB
 2.5E-5, 0.15, 2.0
"""
#: (flow, SRATIO, constants in the data line's order) of each reference case's networks
U1_NETWORKS = [("strain", 0.5, (1.0e-5, 1.0, -0.5)),
               ("bergstrom_boyce", 0.3, (2.5e-5, 4.0, -1.0, 0.01))]
U2_NETWORKS = [("strain", 0.5, (1.0e-5, 1.0, -0.5)),
               ("hyperb", 0.3, (2.5e-5, 0.15, 2.0))]

#: A set of constants of each built-in flow (data-line order)
FLOW_CONSTANTS = {
    "bergstrom_boyce": (2.5e-5, 4.0, -1.0, 0.01),
    "strain": (1.0e-5, 1.0, -0.5),
    "hyperb": (2.5e-5, 0.15, 2.0),
    "power_law": (1.5, 2.0, -0.25, 0.0, 3.0e-4),
}
#: Laws of the network cards (instantaneous constants)
LAWS = {
    "neo_hooke": (0.5,),
    "mooney_rivlin": (0.3, 0.05),
    "ogden2": (0.4, 2.5, -0.02, -2.0),
    "arruda_boyce": (20.0, 7.0),
    "van_der_waals": (0.5, 8.0, 0.1, 0.5),
}


def _model(law: str, *nets: tuple) -> NetworkModel:
    return NetworkModel(law, LAWS[law], tuple(Network(*n) for n in nets))


def _data_lines(card: str) -> list[str]:
    return [ln for ln in card.splitlines() if ln.strip() and not ln.startswith("**")]


def _one_line_error(call, needle: str) -> str:
    with pytest.raises(ValueError) as err:
        call()
    text = str(err.value)
    assert "\n" not in text and needle in text, text
    return text


# ------------------------------------------------------------------------- writer
def test_card_of_the_reference_material_has_abaqus_layout():
    """The card of the PRF-U1 constants is Abaqus's own deck, keyword by keyword."""
    m = NetworkModel("arruda_boyce", (20.0, 7.0), tuple(Network(*n) for n in U1_NETWORKS))
    card = to_abaqus(m, name="PRF_U1")
    assert _data_lines(card) == [
        "*MATERIAL, NAME=PRF_U1",
        "*HYPERELASTIC, ARRUDA-BOYCE, MODULI=INSTANTANEOUS",
        "20.0, 7.0, 0.0",
        "*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5, LAW=STRAIN",
        "1e-05, 1.0, -0.5",
        "*VISCOELASTIC, NONLINEAR, NETWORKID=2, SRATIO=0.3, LAW=BERGSTROM-BOYCE",
        "2.5e-05, 4.0, -1.0, 0.01",
    ]
    comments = " ".join(ln[2:].strip() for ln in card.splitlines() if ln.startswith("**"))
    assert "*VISCO" in comments and "never in *STATIC" in comments


@pytest.mark.parametrize("flow, word", [("strain", "STRAIN"), ("bergstrom_boyce",
                                         "BERGSTROM-BOYCE"), ("hyperb", "HYPERB"),
                                        ("power_law", "POWER LAW")])
def test_each_flow_writes_its_abaqus_law_and_data_line(flow, word):
    c = FLOW_CONSTANTS[flow]
    card = to_abaqus(_model("neo_hooke", (flow, 0.4, c)))
    lines = _data_lines(card)
    assert lines[3] == f"*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.4, LAW={word}"
    assert [float(v) for v in lines[4].split(",")] == list(c)


def test_compressible_card_d1_from_the_instantaneous_modulus():
    """D1 = 2/K with K = 2 mu0 (1 + nu) / (3 (1 - 2 nu)) and mu0 the instantaneous initial
    shear modulus of Abaqus's five-term Arruda-Boyce series:
    mu0 = mu (1 + 3/(5 lm^2) + 99/(175 lm^4) + 513/(875 lm^6) + 42039/(67375 lm^8))."""
    mu, lm, nu = 20.0, 7.0, 0.49
    m = NetworkModel("arruda_boyce", (mu, lm), tuple(Network(*n) for n in U1_NETWORKS))
    mu0 = mu * (1 + 3 / (5 * lm**2) + 99 / (175 * lm**4) + 513 / (875 * lm**6)
                + 42039 / (67375 * lm**8))
    K = 2 * mu0 * (1 + nu) / (3 * (1 - 2 * nu))
    d1 = float(_data_lines(to_abaqus(m, poisson=nu))[2].split(",")[2])
    assert d1 == pytest.approx(2.0 / K, rel=1e-12)
    assert float(_data_lines(to_abaqus(m, bulk_modulus=400.0))[2].split(",")[2]) == 2.0 / 400.0


def test_a_flow_without_an_abaqus_law_is_refused_in_one_line():
    @flows.register("test_dashpot_noabaqus", params=("eta",), bounds=((0.0, math.inf),))
    def _dashpot(q, lam_cr, eps_bar, eta):
        return q / eta

    try:
        m = NetworkModel("neo_hooke", (0.5,), (Network("test_dashpot_noabaqus", 0.5, (2.0,)),))
        _one_line_error(lambda: to_abaqus(m), "no Abaqus LAW")
    finally:
        flows.unregister("test_dashpot_noabaqus")


def test_a_law_abaqus_lacks_is_refused_in_one_line():
    m = NetworkModel("gent", (0.5, 50.0), (Network("strain", 0.5, (1e-5, 1.0, -0.5)),))
    _one_line_error(lambda: to_abaqus(m), "Abaqus export does not support")


# ------------------------------------------------------------------------- reader
@pytest.mark.parametrize("card, nets", [(U1, U1_NETWORKS), (U2, U2_NETWORKS)],
                         ids=["PRF-U1", "PRF-U2"])
def test_the_reference_blocks_read_to_the_reference_constants(card, nets):
    model, named = from_abaqus(card)
    assert isinstance(model, NetworkModel)
    assert model.law == "arruda_boyce" and model.law_params == (20.0, 7.0)
    assert [(n.flow, n.ratio, n.constants) for n in model.networks] == nets
    assert named["mu"] == 20.0 and named["network2_sratio"] == 0.3
    assert parse(card)[0] == model  # the format is told from the text


@pytest.mark.parametrize("law", sorted(LAWS))
@pytest.mark.parametrize("flow", sorted(FLOW_CONSTANTS))
def test_write_then_read_gives_the_same_constants(law, flow):
    m = _model(law, (flow, 0.35, FLOW_CONSTANTS[flow]), ("strain", 0.2, (1e-3, 1.5, -0.3)))
    assert from_abaqus(to_abaqus(m))[0] == m
    assert parse(export(m, to="abaqus"))[0] == m


@pytest.mark.parametrize("word, flow", [
    ("BERGSTROM", "bergstrom_boyce"), ("BERGSTROM-BOYCE", "bergstrom_boyce"),
    ("bergstrom-boyce", "bergstrom_boyce"), ("POWER LAW", "power_law"),
    ("POWERLAW", "power_law"), ("power law", "power_law"), ("STRAIN", "strain"),
    ("HYPERB", "hyperb"),
])
def test_abaqus_spellings_of_the_laws(word, flow):
    c = FLOW_CONSTANTS[flow]
    card = (f"*Hyperelastic, Neo Hooke, Moduli=Instantaneous\n0.5, 0.\n"
            f"*Viscoelastic, Nonlinear, Networkid=1, Sratio=0.25, Law={word}\n"
            + ", ".join(repr(v) for v in c) + "\n")
    (net,) = from_abaqus(card)[0].networks
    assert (net.flow, net.ratio, net.constants) == (flow, 0.25, c)


def test_any_parameter_order_comments_and_blanks():
    card = """** a deck written by hand
*Material, name=GEL
*Hyperelastic, moduli=INSTANTANEOUS, arruda-boyce
** the instantaneous constants
 20.D0 ,  7.
*Viscoelastic, law=BERGSTROM, sratio=0.3, nonlinear, networkid=2
** A, m, C, E
 2.5-5, 4, -1.0, 0.01
*VISCOELASTIC,NONLINEAR,LAW=STRAIN,NETWORKID=1,SRATIO=0.5
 1.0E-5, 1., -0.5,
*Material, name=OTHER
*Hyperelastic, neo hooke
 1.0, 0.
"""
    model, _ = from_abaqus(card)
    assert model.law_params == (20.0, 7.0)
    assert [(n.flow, n.ratio, n.constants) for n in model.networks] == U1_NETWORKS


def test_a_blank_field_reads_as_zero():
    """POWER LAW with its pressure factor a left blank (Abaqus reads a blank field as 0)."""
    card = (HYPER + "*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5, LAW=POWER LAW\n"
            " 1.5, 2., -0.25, , 3e-4\n")
    assert from_abaqus(card)[0].networks[0].constants == (1.5, 2.0, -0.25, 0.0, 3e-4)


def test_a_user_flow_registered_as_abaqus_user_reads_and_writes():
    @flows.register("test_dashpot_user", params=("eta",), bounds=((0.0, math.inf),),
                    abaqus="USER")
    def _dashpot(q, lam_cr, eps_bar, eta):
        return q / eta

    try:
        card = HYPER + "*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5, LAW=USER\n 3.0\n"
        model = from_abaqus(card)[0]
        assert model.networks[0].flow == "test_dashpot_user"
        assert from_abaqus(to_abaqus(model))[0] == model
    finally:
        flows.unregister("test_dashpot_user")


NL1 = "*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5, LAW=STRAIN\n 1.0E-5, 1., -0.5\n"


@pytest.mark.parametrize("card, needle", [
    ("*HYPERELASTIC, ARRUDA-BOYCE, MODULI=LONG TERM\n 20., 7.\n" + NL1,
     "MODULI=LONG TERM with *VISCOELASTIC, NONLINEAR"),
    ("*HYPERELASTIC, ARRUDA-BOYCE\n 20., 7.\n" + NL1, "LONG TERM is Abaqus's default"),
    (HYPER + "*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5, LAW=USER\n 1.\n",
     "LAW=USER (a user subroutine) names no registered flow"),
    (HYPER + "*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5, LAW=TIME\n 1., 1., -.5\n",
     "LAW=TIME names no registered flow"),
    (HYPER + NL1 + "*VISCOELASTIC, TIME=PRONY\n 0.2, 0., 1.\n", "TIME=PRONY beside"),
    (HYPER + "*VISCOELASTIC, NONLINEAR, NETWORKID=1, LAW=STRAIN\n 1.0E-5, 1., -0.5\n",
     "SRATIO= missing"),
    (HYPER + "*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5\n 1.0E-5, 1., -0.5\n",
     "LAW= missing"),
    (HYPER + NL1 + NL1, "NETWORKID=1 is given twice"),
    (HYPER + "*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5, LAW=STRAIN\n"
     " 1.0E-5, 1., -0.5, 20.\n 2.0E-5, 1., -0.5, 40.\n", "temperature-dependent"),
    (HYPER + "*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5, LAW=STRAIN, "
     "DEPENDENCIES=1\n 1.0E-5, 1., -0.5\n", "DEPENDENCIES cannot be read"),
    (HYPER + "*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5, LAW=HYPERB\n"
     " 2.5E-5, -0.15, 2.0\n", "NETWORKID=1, LAW=HYPERB: B = -0.15"),
    (HYPER + NL1 + "*VISCOELASTIC, NONLINEAR, NETWORKID=2, SRATIO=0.6, LAW=STRAIN\n"
     " 1.0E-5, 1., -0.5\n", "ratios sum to 1.1"),
    (HYPER + "*VISCOELASTIC, NONLINEAR, NETWORKID=one, SRATIO=0.5, LAW=STRAIN\n 1.\n",
     "give a whole number"),
])
def test_what_cannot_be_read_is_refused_in_one_line(card, needle):
    _one_line_error(lambda: from_abaqus(card), needle)


# ---------------------------------------------------------------- other solvers
NO_NETWORKS = [r for r in records() if not r.networks]


@pytest.mark.parametrize("rec", NO_NETWORKS, ids=[r.name for r in NO_NETWORKS])
def test_solvers_without_public_network_equations_refuse_in_one_line(rec):
    """Their Bergstrom-Boyce materials' equations and numbering are not public: no card."""
    m = NetworkModel("neo_hooke", (0.5,), (Network("bergstrom_boyce", 0.5,
                                                   FLOW_CONSTANTS["bergstrom_boyce"]),))
    for call in (lambda: rec.write(m, None), lambda: export(m, to=rec.name)):
        text = _one_line_error(call, "publicly documented")
        assert text.startswith(f"{rec.label} export has no card for a network")
        assert "Prony" in text  # what the solver still gets


def test_those_solvers_are_the_ones_the_issue_names():
    """LS-DYNA and Ansys write no network card; Abaqus does."""
    assert {r.name for r in NO_NETWORKS} >= {"lsdyna", "ansys"}
    assert next(r for r in records() if r.name == "abaqus").networks


# ------------------------------------------------------------------- card check
def test_the_card_check_scores_a_network_card_in_its_own_framework():
    """A frozen flow (A → 0) scored against the instantaneous neo-Hooke law's closed form,
    σ = 2 C10 (λ² − 1/λ) (true stress), on ramps at two rates: the card's error is ~0."""
    import numpy as np

    import vhfit
    from vhfit.export.check import NETWORKS, check_card, network_stress

    C10 = 0.5
    m = NetworkModel("neo_hooke", (C10,), (Network("bergstrom_boyce", 0.4,
                                                   (1e-30, 1.0, 0.0, 0.01)),))
    eps = np.linspace(0.05, 0.6, 12)
    lam = 1.0 + eps
    curves = [vhfit.Curve(strain=eps, stress=2 * C10 * (lam**2 - 1 / lam), strain_rate=r,
                          measure="true") for r in (0.01, 1.0)]
    res = check_card(to_abaqus(m), curves, fit=(m, {}))
    assert res.formulation == res.fit_formulation == NETWORKS
    assert res.rmsape < 1e-7 and not res.exceeds
    np.testing.assert_allclose(network_stress(m, curves[0].history, "true"),
                               curves[0].target_stress, rtol=1e-9)
