"""``vhfit simulate --card FILE``: any card vhfit reads, strain-controlled or in creep.

The reference: Abaqus's own results of two of its verification problems for the parallel
rheological framework (one C3D8H element, Cauchy stress 2.0 held in uniaxial tension: a
``*STATIC`` step ramps the load on elastically, a ``*VISCO`` step of 1000 s creeps). Abaqus
reports E11 = ln λ at its step times; its t = 1 (end of the elastic step) is t = 0 here.
Abaqus integrates with its own automatic time stepping (CETOL = 1e-2), so its figures carry
an integration error of the order of 1e-4 relative: the tolerance is 1e-3 relative on E11.

The other checks use closed forms of neo-Hooke (instantaneous constant C10, so that the
instantaneous uniaxial true stress is 2 C10 (λ² − 1/λ)): with a flow too slow to move in
the test (A → 0) a network card gives the instantaneous law; with a flow much faster than
the test (a linear dashpot, relaxation time far below the times asked) the equilibrium
law, (1 − Σ s_k) times the instantaneous one.
"""

from __future__ import annotations

import csv
import io

import numpy as np
import pytest
from scipy.optimize import brentq

from vhfit import cli
from vhfit.export import to_abaqus
from vhfit.viscous import Network, NetworkModel

HYPER = "*HYPERELASTIC, ARRUDA-BOYCE, MODULI=INSTANTANEOUS\n 20., 7.\n"
STRAIN_NET = "*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO=0.5, LAW=STRAIN\n 1.0E-5, 1., -0.5\n"
CASES = {
    # Abaqus's material blocks, as Abaqus's decks spell them, and its E11 at its step times
    "PRF-U1": (HYPER + STRAIN_NET
               + "*VISCOELASTIC, NONLINEAR, NETWORKID=2, SRATIO=0.3, LAW=BERGSTROM\n"
                 " 2.5E-5, 4, -1.0, 0.01\n",
               {1.0: 0.032380641, 483.31073: 0.040189974, 983.31073: 0.041543677,
                1001.0: 0.041575786}),
    "PRF-U2": (HYPER + STRAIN_NET
               + "*VISCOELASTIC, NONLINEAR, NETWORKID=2, SRATIO=0.3, LAW=HYPERB\n"
                 " 2.5E-5, 0.15, 2.0\n",
               {1.0: 0.032380641, 501.0: 0.032633230, 1001.0: 0.032755878}),
}
CONSTANTS = {  # the same materials as constants
    "PRF-U1": (Network("strain", 0.5, (1e-5, 1.0, -0.5)),
               Network("bergstrom_boyce", 0.3, (2.5e-5, 4.0, -1.0, 0.01))),
    "PRF-U2": (Network("strain", 0.5, (1e-5, 1.0, -0.5)),
               Network("hyperb", 0.3, (2.5e-5, 0.15, 2.0))),
}
#: Abaqus's step times -> --time (its t = 1 is t = 0 here), written as the issue writes them
TIMES = {"PRF-U1": "0,482.31073,982.31073,1000", "PRF-U2": "0,500,1000"}


def _creep_csv(text: str) -> dict[str, np.ndarray]:
    rows = list(csv.DictReader(ln for ln in io.StringIO(text) if not ln.startswith("#")))
    return {k: np.array([float(r[k]) for r in rows]) for k in ("time", "stretch", "strain",
                                                               "stress")}


def _run(capsys, *argv: str) -> dict[str, np.ndarray]:
    assert cli.main(["simulate", *argv]) == 0
    return _creep_csv(capsys.readouterr().out)


def _check_against_abaqus(out: dict[str, np.ndarray], case: str) -> None:
    expected = np.array(list(CASES[case][1].values()))
    np.testing.assert_allclose(out["time"], np.array(list(CASES[case][1])) - 1.0, atol=1e-9)
    np.testing.assert_allclose(np.log(out["stretch"]), expected, rtol=1e-3)
    np.testing.assert_allclose(out["strain"], out["stretch"] - 1.0, rtol=1e-9)
    assert (out["stress"] == 2.0).all()


# --------------------------------------------------------------------- Abaqus itself
@pytest.mark.parametrize("case", sorted(CASES))
def test_abaqus_reference_cases_through_the_card(case, tmp_path, capsys):
    card = tmp_path / "case.inp"
    card.write_text(CASES[case][0])
    out = _run(capsys, "--card", str(card), "--creep", "2.0", "--measure", "true",
               "--deformation", "uniaxial", "--time", TIMES[case])
    _check_against_abaqus(out, case)


@pytest.mark.parametrize("case", sorted(CASES))
def test_abaqus_reference_cases_after_writing_the_card(case, tmp_path, capsys):
    """The card vhfit writes from the constants, read back by the same command."""
    card = tmp_path / "written.inp"
    card.write_text(to_abaqus(NetworkModel("arruda_boyce", (20.0, 7.0), CONSTANTS[case])))
    out = _run(capsys, "--card", str(card), "--creep", "2.0", "--measure", "true",
               "--deformation", "uniaxial", "--time", TIMES[case])
    _check_against_abaqus(out, case)


# ------------------------------------------------------------------- closed forms
C10 = 0.5  # neo-Hooke, instantaneous
#: instantaneous true stress of neo-Hooke in each test, per unit 2 C10 (incompressible)
TRUE = {"uniaxial": lambda x: x**2 - 1 / x, "equibiaxial": lambda x: x**2 - x**-4,
        "planar": lambda x: x**2 - x**-2}


def _neo_hooke_card(tmp_path, flow_line: str, data: str, ratio: float = 0.4) -> str:
    path = tmp_path / "neo.inp"
    path.write_text(f"*HYPERELASTIC, NEO HOOKE, MODULI=INSTANTANEOUS\n {C10}, 0.\n"
                    f"*VISCOELASTIC, NONLINEAR, NETWORKID=1, SRATIO={ratio}, LAW={flow_line}\n"
                    f" {data}\n")
    return str(path)


def _stretch_under(S: float, deformation: str, measure: str, scale: float = 1.0) -> float:
    """λ1 with scale · 2 C10 f(λ1) = S (true) or S · λ1 (engineering: S = σ / λ1)."""
    f = TRUE[deformation]
    target = (lambda x: S) if measure == "true" else (lambda x: S * x)
    return brentq(lambda x: scale * 2 * C10 * f(x) - target(x), 1.0 + 1e-12, 10.0,
                  xtol=1e-15, rtol=1e-15)


@pytest.mark.parametrize("deformation", sorted(TRUE))
@pytest.mark.parametrize("measure", ["true", "engineering"])
def test_creep_with_a_frozen_flow_is_the_instantaneous_law(deformation, measure, tmp_path,
                                                           capsys):
    """A → 0 (BB, A = 1e-30 1/(s MPa^m)): the stretch stays the instantaneous one."""
    card = _neo_hooke_card(tmp_path, "BERGSTROM", "1e-30, 1., 0., 0.01")
    out = _run(capsys, "--card", card, "--creep", "0.3", "--measure", measure,
               "--deformation", deformation, "--time", "0,10,100")
    np.testing.assert_allclose(out["stretch"], _stretch_under(0.3, deformation, measure),
                               rtol=1e-9)


@pytest.mark.parametrize("deformation", sorted(TRUE))
def test_creep_with_a_fast_flow_ends_on_the_equilibrium_law(deformation, tmp_path, capsys):
    """A linear dashpot (BB with m = 1, C = 0: ε̇ = A q̃, A = 0.1 1/(s MPa)) relaxes with a
    time of ~1/(3 A s 2 C10) ≈ 8 s: at 500 s and 1000 s (e^-60) the equilibrium network
    alone carries the load, (1 − s) times the instantaneous law."""
    from vhfit.export import parse

    card = _neo_hooke_card(tmp_path, "BERGSTROM", "0.1, 1., 0., 0.01", ratio=0.4)
    # the model itself first: the command line would turn its error into exit code 1
    with open(card) as f:
        parse(f.read())[0].creep(0.3, [0.0, 500.0, 1000.0], deformation=deformation)
    out = _run(capsys, "--card", card, "--creep", "0.3", "--measure", "true",
               "--deformation", deformation, "--time", "0,500,1000")
    assert out["stretch"][0] == pytest.approx(_stretch_under(0.3, deformation, "true"),
                                              rel=1e-9)
    np.testing.assert_allclose(out["stretch"][1:],
                               _stretch_under(0.3, deformation, "true", scale=0.6), rtol=1e-6)


def test_a_network_card_along_a_ramp_with_a_frozen_flow(tmp_path, capsys):
    """Strain control from a card: A → 0 gives the instantaneous law on a ramp."""
    card = _neo_hooke_card(tmp_path, "STRAIN", "1e-30, 1., 0.")
    assert cli.main(["simulate", "--card", card, "--rate", "0.1", "--strain-max", "0.5",
                     "--points", "6", "--measure", "true"]) == 0
    rows = list(csv.DictReader(ln for ln in io.StringIO(capsys.readouterr().out)
                               if not ln.startswith("#")))
    lam = 1.0 + np.array([float(r["strain"]) for r in rows])
    stress = np.array([float(r["stress"]) for r in rows])
    # the file prints 9 significant digits
    np.testing.assert_allclose(stress, 2 * C10 * TRUE["uniaxial"](lam), rtol=1e-8, atol=1e-14)


def test_a_prony_card_runs_as_its_model(tmp_path, capsys):
    """A Prony card through --card: the same stress as the model with the card's constants
    (Abaqus's MODULI=LONG TERM: C10 long-term, g1 = G1/G0, G0 = 6 C10 / g_inf)."""
    import vhfit

    path = tmp_path / "prony.inp"
    path.write_text("*HYPERELASTIC, NEO HOOKE, MODULI=LONG TERM\n 0.5, 0.\n"
                    "*VISCOELASTIC, TIME=PRONY\n 0.5, 0., 0.1\n")
    assert cli.main(["simulate", "--card", str(path), "--rate", "1", "--strain-max", "0.4",
                     "--points", "5"]) == 0
    rows = list(csv.DictReader(ln for ln in io.StringIO(capsys.readouterr().out)
                               if not ln.startswith("#")))
    e = np.array([float(r["strain"]) for r in rows])
    m = vhfit.ViscoHyperelastic("neo_hooke", 1)
    ref = m.stress(dict(C10=0.5, G1=3.0, tau1=0.1), strain=e, strain_rate=1.0,
                   measure="engineering")
    np.testing.assert_allclose([float(r["stress"]) for r in rows], ref, rtol=1e-8, atol=1e-14)


# ------------------------------------------------------------------------ bad input
def _bad(capsys, argv, needle):
    assert cli.main(["simulate", *argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0], err


def test_bad_input_is_one_line(tmp_path, capsys):
    net = tmp_path / "net.inp"
    net.write_text(CASES["PRF-U1"][0])
    prony = tmp_path / "prony.inp"
    prony.write_text("*HYPERELASTIC, NEO HOOKE\n 0.5, 0.\n*VISCOELASTIC, TIME=PRONY\n"
                     " 0.5, 0., 0.1\n")
    bad = tmp_path / "bad.inp"
    bad.write_text("*HYPERELASTIC, ARRUDA-BOYCE, MODULI=LONG TERM\n 20., 7.\n" + STRAIN_NET)
    cases = [
        (["--card", str(tmp_path / "none.inp"), "--creep", "2", "--time", "0,1"], "none.inp"),
        (["--card", str(bad), "--creep", "2", "--time", "0,1"], f"--card {bad}: "),
        (["--card", str(net), "--model", "neo_hooke", "--rate", "1"], "drop --results"),
        (["--card", str(net), "--time", "0,1", "--rate", "1"], "add --creep"),
        (["--card", str(net), "--creep", "2"], "--time t1,t2"),
        (["--card", str(net), "--creep", "2", "--time", "0,5,1"], "--time '0,5,1'"),
        (["--card", str(net), "--creep", "2", "--time=-1,1"], "times >= 0"),
        (["--card", str(net), "--creep", "2", "--time", "0,1", "--rate", "1"], "drop --rate"),
        (["--card", str(net), "--creep", "x", "--time", "0,1"], "--creep 'x'"),
        (["--card", str(prony), "--creep", "2", "--time", "0,1"], "no creep solver"),
        (["--model", "neo_hooke", "--param", "C10=0.5", "--creep", "2", "--time", "0,1"],
         "no creep solver"),
        (["--card", str(net), "--creep", "2", "--time", "0,1", "--deformation",
          "simple_shear"], "--deformation simple_shear"),
    ]
    for argv, needle in cases:
        _bad(capsys, argv, needle)
