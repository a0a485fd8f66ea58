"""Cards of the laws added for multi-mode fits, pinned to the solvers' documented layouts.

Read with the string splitting of ``tests/test_export_vendor.py`` and compared with
values worked out by hand. Layouts (sources in docs/export.md and docs/theory.md §2):

[ABQ-KW]  Abaqus *HYPERELASTIC: ARRUDA-BOYCE data line μ, λm, D; VAN DER WAALS μ, λm, a,
          β, D; REDUCED POLYNOMIAL, N: C10, C20, ..., CN0, D1..DN; OGDEN, N (N ≤ 6): μ1, α1,
          ..., μN, αN, D1..DN; at most 8 values a line; Abaqus has no Gent law.
[ANS]     Ansys TB,HYPER options BOYCE (μ, λL, d), GENT (μ, Jm, d), YEOH with N terms
          (c10..cN0, d1..dN), OGDEN with N terms (μ1, α1, ..., d1..dN; Ansys μ = 2μ/α);
          instantaneous constants = long-term / g∞; at most 6 values a TBDATA.
[DYNA]    LS-DYNA MAT_077_H card C10 C01 C11 C20 C02 C30; MAT_077_O cards MU1..MU8,
          ALPHA1..ALPHA8 with MU = 2μ/α; GI = G_i/3, BETAI = 1/τ_i; Arruda–Boyce (MAT_127
          takes N = λm² as an integer), Gent and Van der Waals have no exact card.

Every parameter set gets the Prony terms G1 = E∞ (τ1 = 0.01 s), G2 = 2 E∞ (τ2 = 2 s),
so g = (0.25, 0.5), g∞ = 0.25 and instantaneous = 4 × long-term exactly.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_export import assert_same_stress
from test_export_vendor import (
    abaqus_blocks,
    ansys_tables,
    field_values,
    floats,
    lsdyna_cards,
)

import vhfit
from vhfit.export import from_abaqus, from_ansys, from_lsdyna, to_abaqus, to_ansys, to_lsdyna

AB_MU0 = 0.5 * (1 + 3 / (5 * 2.5**2) + 99 / (175 * 2.5**4) + 513 / (875 * 2.5**6)
                + 42039 / (67375 * 2.5**8))  # μ0 of μ = 0.5, λm = 2.5 (docs/theory.md §2)
RP = [0.5, 0.125, 0.03125, 0.0078125, 0.001953125, 0.00048828125]
OG = [(1.0, 4.0), (0.25, -2.0), (0.5, 8.0), (0.125, 1.0), (0.0625, 0.5), (0.03125, -4.0)]

# law -> (constants, μ0 worked by hand)
LAWS = {
    "arruda_boyce": (dict(mu=0.5, lambda_m=2.5), AB_MU0),
    "gent": (dict(mu=0.5, Jm=8.0), 0.5),
    "van_der_waals": (dict(mu=0.5, lambda_m=4.0, a=0.25, beta=0.125), 0.5),
    **{f"reduced_polynomial{n}": ({f"C{i}0": RP[i - 1] for i in range(1, n + 1)}, 2 * RP[0])
       for n in range(1, 7)},
    **{f"ogden{n}": ({k: v for p in range(n) for k, v in
                      ((f"mu{p + 1}", OG[p][0]), (f"alpha{p + 1}", OG[p][1]))},
                     sum(mu for mu, _ in OG[:n])) for n in (4, 5, 6)},
}
TAU = [0.01, 2.0]


def model_params(law: str, constants: dict | None = None):
    c, mu0 = LAWS[law]
    E = 3 * mu0
    p = {**(constants or c), "G1": E, "tau1": TAU[0], "G2": 2 * E, "tau2": TAU[1]}
    return vhfit.ViscoHyperelastic(law, n_prony=2), p


# ---------------------------------------------------------------------------- Abaqus
ABAQUS = {  # [ABQ-KW] keyword parameters and data lines, long-term constants, D = 0
    "arruda_boyce": ("ARRUDA-BOYCE", [[0.5, 2.5, 0.0]]),
    "van_der_waals": ("VAN DER WAALS", [[0.5, 4.0, 0.25, 0.125, 0.0]]),
    "reduced_polynomial1": ("REDUCED POLYNOMIAL, N=1", [[0.5, 0.0]]),
    "reduced_polynomial2": ("REDUCED POLYNOMIAL, N=2", [[0.5, 0.125, 0.0, 0.0]]),
    "reduced_polynomial4": ("REDUCED POLYNOMIAL, N=4", [RP[:4] + [0.0] * 4]),
    "reduced_polynomial6": ("REDUCED POLYNOMIAL, N=6", [RP + [0.0, 0.0], [0.0] * 4]),
    "ogden4": ("OGDEN, N=4", [[1.0, 4.0, 0.25, -2.0, 0.5, 8.0, 0.125, 1.0], [0.0] * 4]),
    "ogden5": ("OGDEN, N=5", [[1.0, 4.0, 0.25, -2.0, 0.5, 8.0, 0.125, 1.0],
                              [0.0625, 0.5] + [0.0] * 5]),
    "ogden6": ("OGDEN, N=6", [[1.0, 4.0, 0.25, -2.0, 0.5, 8.0, 0.125, 1.0],
                              [0.0625, 0.5, 0.03125, -4.0, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0]]),
}


@pytest.mark.parametrize("law", sorted(ABAQUS))
def test_abaqus_cards_of_the_new_laws(law):
    m, p = model_params(law)
    blocks = abaqus_blocks(to_abaqus(m, p))
    assert [kw for kw, _ in blocks] == [
        "*MATERIAL, NAME=VHFIT_MATERIAL",
        f"*HYPERELASTIC, {ABAQUS[law][0]}, MODULI=LONG TERM",
        "*VISCOELASTIC, TIME=PRONY",
    ]
    assert [floats(row) for row in blocks[1][1]] == ABAQUS[law][1]
    rows = [floats(r) for r in blocks[2][1]]
    assert np.allclose(rows, [[0.25, 0.0, 0.01], [0.5, 0.0, 2.0]], rtol=1e-14, atol=0)


def test_abaqus_instantaneous_arruda_boyce_scales_mu_only():
    m, p = model_params("arruda_boyce")
    blocks = abaqus_blocks(to_abaqus(m, p, moduli="instantaneous"))
    assert blocks[1][0] == "*HYPERELASTIC, ARRUDA-BOYCE, MODULI=INSTANTANEOUS"
    assert floats(blocks[1][1][0]) == pytest.approx([2.0, 2.5, 0.0], rel=1e-14)


# ----------------------------------------------------------------------------- Ansys
ANSYS = {  # [ANS] TB,HYPER,mat,,NPTS,TBOPT; instantaneous = 4 × long-term
    "arruda_boyce": ("", "BOYCE", [2.0, 2.5, 0.0]),
    "gent": ("", "GENT", [2.0, 8.0, 0.0]),
    "reduced_polynomial2": ("2", "YEOH", [2.0, 0.5, 0.0, 0.0]),
    "reduced_polynomial6": ("6", "YEOH", [4 * c for c in RP] + [0.0] * 6),
    # μ(Ansys) = 2μ/α × 4: 8 × (1/4, 0.25/−2, 0.5/8, 0.125/1, 0.0625/0.5, 0.03125/−4)
    "ogden4": ("4", "OGDEN", [2.0, 4.0, -1.0, -2.0, 0.5, 8.0, 1.0, 1.0] + [0.0] * 4),
    "ogden6": ("6", "OGDEN", [2.0, 4.0, -1.0, -2.0, 0.5, 8.0, 1.0, 1.0, 1.0, 0.5,
                              -0.0625, -4.0] + [0.0] * 6),
}


@pytest.mark.parametrize("law", sorted(ANSYS))
def test_ansys_commands_of_the_new_laws(law):
    m, p = model_params(law)
    (tb_h, hyper, counts_h), (tb_p, prony, _) = ansys_tables(to_ansys(m, p))
    npts, opt, values = ANSYS[law]
    assert tb_h == ["TB", "HYPER", "1", "", npts, opt]
    assert [hyper[k] for k in sorted(hyper)] == pytest.approx(values, rel=1e-14)
    assert max(counts_h) <= 6
    assert tb_p == ["TB", "PRONY", "1", "", "2", "SHEAR"]
    assert [prony[k] for k in sorted(prony)] == pytest.approx([0.25, 0.01, 0.5, 2.0], rel=1e-14)


# --------------------------------------------------------------------------- LS-DYNA
DYNA_POLY = {  # [DYNA] C10 C01 C11 C20 C02 C30
    "reduced_polynomial2": [0.5, 0.0, 0.0, 0.125, 0.0, 0.0],
    "reduced_polynomial3": [0.5, 0.0, 0.0, 0.125, 0.0, 0.03125],
}


@pytest.mark.filterwarnings("ignore:PR = .* nearly compressible")
@pytest.mark.parametrize("law", [*sorted(DYNA_POLY), "ogden6"])
def test_lsdyna_cards_of_the_new_laws(law):
    m, p = model_params(law)
    cards = lsdyna_cards(to_lsdyna(m, p, long_format=True))
    ogden = law.startswith("ogden")
    assert cards[1] == ("*MAT_OGDEN_RUBBER_TITLE+" if ogden else
                        "*MAT_HYPERELASTIC_RUBBER_TITLE+")
    body = cards[4:-1]
    if ogden:  # MU = 2μ/α (long-term), then the α's
        mus = [0.5, -0.25, 0.125, 0.25, 0.25, -0.015625]
        assert field_values(body[0], 20) == pytest.approx(mus, rel=1e-14)
        assert field_values(body[1], 20) == [4.0, -2.0, 8.0, 1.0, 0.5, -4.0]
        prony = body[2:]
    else:
        assert field_values(body[0], 20) == DYNA_POLY[law]
        prony = body[1:]
    mu0 = LAWS[law][1]  # GI = G_i/3 = (1, 2) × μ0, BETAI = 1/τ
    rows = [field_values(c, 20) for c in prony]
    assert np.allclose(rows, [[mu0, 100.0], [2 * mu0, 0.5]], rtol=1e-13, atol=0)


# ------------------------------------------------------------ refusals and parsers
@pytest.mark.parametrize("writer, law, others", [
    (to_abaqus, "gent", "Ansys"),
    (to_ansys, "van_der_waals", "Abaqus"),
    (to_lsdyna, "van_der_waals", "Abaqus"),
    (to_lsdyna, "gent", "Ansys"),
    (to_lsdyna, "arruda_boyce", "Abaqus or Ansys"),
])
def test_a_law_a_solver_lacks_is_refused_naming_the_solvers_that_have_it(writer, law, others):
    m, p = model_params(law)
    with pytest.raises(ValueError) as err:
        writer(m, p)
    msg = str(err.value)
    assert "\n" not in msg and repr(law) in msg and f"export it to {others} instead" in msg


def test_lsdyna_holds_a_reduced_polynomial_only_up_to_c30():
    m, p = model_params("reduced_polynomial4")
    with pytest.raises(ValueError, match=r"C40.*export it to Abaqus or Ansys"):
        to_lsdyna(m, p)
    cards = lsdyna_cards(to_lsdyna(m, {**p, "C40": 0.0}, long_format=True))
    assert field_values(cards[4], 20) == [0.5, 0.0, 0.0, 0.125, 0.0, 0.03125]


def test_parsers_read_hand_written_cards_of_the_new_laws():
    m, p = from_abaqus("*Material, name=R\n*Hyperelastic, Arruda-Boyce\n0.5, 2.5, 0.\n")
    assert m.hyperelastic.name == "arruda_boyce" and p == dict(mu=0.5, lambda_m=2.5)
    m, p = from_abaqus("*HYPERELASTIC, VAN DER WAALS\n0.5, 4.0, 0.25, 0.125, 0.0\n")
    assert p == dict(mu=0.5, lambda_m=4.0, a=0.25, beta=0.125)
    m, p = from_abaqus("*HYPERELASTIC, REDUCED POLYNOMIAL, N=5\n"
                       "0.5, 0.125, 0.03125, 0.0078125, 0.001953125, 0., 0., 0.,\n0., 0.\n")
    assert m.hyperelastic.name == "reduced_polynomial5" and p["C50"] == 0.001953125
    m, p = from_ansys("TB,HYPE,1,,,GENT\nTBDATA,1,2.0,8.0,0.0\n"
                      "TB,PRON,1,,1,SHEA\nTBDATA,1,0.75,0.1\n")
    # instantaneous μ = 2 → long-term 0.5; G1 = g1 G0 = 0.75 × 3 μ0 / 0.25
    assert m.hyperelastic.name == "gent" and p == pytest.approx(
        dict(mu=0.5, Jm=8.0, G1=4.5, tau1=0.1))
    m, p = from_ansys("TB,HYPER,1,,,BOYCE\nTBDATA,1,0.5,2.5,0.0\n")
    assert p == dict(mu=0.5, lambda_m=2.5)
    with pytest.raises(ValueError, match="Ogden with 7 terms"):
        from_lsdyna("*MAT_OGDEN_RUBBER\n1,1e-9,0.4995,0\n" + ",".join(["0.1"] * 7) + "\n"
                    + ",".join(["2.0"] * 7) + "\n")


ROUND_TRIP = [(w, r, law) for w, r, laws in [
    (to_abaqus, from_abaqus, ["arruda_boyce", "van_der_waals", "reduced_polynomial1",
                              "reduced_polynomial3", "reduced_polynomial6", "ogden5"]),
    (to_ansys, from_ansys, ["arruda_boyce", "gent", "reduced_polynomial1",
                            "reduced_polynomial3", "reduced_polynomial5", "ogden6"]),
    (to_lsdyna, from_lsdyna, ["reduced_polynomial1", "reduced_polynomial2",
                              "reduced_polynomial3", "ogden4"]),
] for law in laws]


@pytest.mark.filterwarnings("ignore:PR = .* nearly compressible")
@pytest.mark.parametrize("writer, reader, law", ROUND_TRIP)
def test_round_trip_keeps_the_law_and_its_stress(writer, reader, law):
    m, p = model_params(law)
    if law.startswith("reduced") and writer is to_lsdyna:
        p = {k: (0.0 if k in ("C40", "C50", "C60") else v) for k, v in p.items()}
    m2, p2 = reader(writer(m, p))
    assert m2.hyperelastic.name == law  # reduced_polynomial3 stays itself, not yeoh
    assert_same_stress(m, p, m2, p2, rtol=1e-12)
    assert np.allclose(m2.as_array(p2), m.as_array(p), rtol=1e-13, atol=0.0)
