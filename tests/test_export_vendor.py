"""FE cards pinned to the solvers' documented layouts, not to vhfit's own parser.

``tests/test_export.py`` round-trips every card through vhfit's parsers, which share the
writers' ordering tables, so an ordering slip made in both directions passes there. Here
every card is read with string splitting written in this file and compared field by
field with values worked out by hand from the documented card layout; the parsers are
then tested separately on hand-written card text.

Sources of each layout (searched, excerpts read; no vendor manual was read in full):

[ABQ-KW]   Abaqus Keywords Reference, *HYPERELASTIC: parameters MOONEY-RIVLIN, NEO HOOKE,
           OGDEN, POLYNOMIAL (N), YEOH, MODULI=LONG TERM | INSTANTANEOUS
           (abaqus-docs.mit.edu/2017/English/SIMACAEKEYRefMap/simakey-r-hyperelastic.htm).
           Its data-line lists did not survive in the copies found.
[CCX]      CalculiX's Abaqus-compatible *HYPERELASTIC documentation (calculix/cae,
           doc/HYPERELASTIC.html), data lines: MOONEY-RIVLIN C10, C01, D1; NEO HOOKE C10, D1;
           OGDEN N=1 mu1, alpha1, D1; N=2 mu1, alpha1, mu2, alpha2, D1, D2; N=3 first line
           mu1, alpha1, mu2, alpha2, mu3, alpha3, D1, D2, second line D3; POLYNOMIAL N=2
           C10, C01, C20, C11, C02, D1, D2; N=3 first line C10, C01, C20, C11, C02, C30,
           C21, C12, second line C03, D1, D2, D3; YEOH C10, C20, C30, D1, D2, D3 (then the
           temperature, which vhfit does not write).
[ABQ-VE]   Abaqus Keywords Reference, *VISCOELASTIC, TIME=PRONY (abaqus-docs.mit.edu 2017
           simakey-r-viscoelastic.htm) and the Abaqus 6.5 keywords guide copy
           (classes.engineering.wustl.edu .../key/ch21abk04.html): the Prony parameters are
           given directly; the data line g_i, k_i, tau_i is corroborated by PolymerFEM
           (polymerfem.com, "Linear viscoelasticity part 4 - Prony spectrum").
[DYNA-H]   LS-DYNA MAT_077_H field layout as generated from the LS-DYNA manual in Ansys
           PyDyna (ansys/pydyna, keyword_classes/auto/mat/mat_077_h.py): card 1 MID RO PR N
           NV G SIGF REF; with N = 0 the card C10 C01 C11 C20 C02 C30 THERML; then optional
           cards GI BETAI (GJ SIGFJ VFLAG); 10-character fields.
[DYNA-O]   LS-DYNA MAT_077_O (Altair's LS-DYNA-input reference, help.altair.com
           .../mat_077_o_ogden_rubber_lsdyna_r.htm): card MU1..MU8, card ALPHA1..ALPHA8,
           then cards Gi ("shear modulus for relaxation", stress) and beta_i ("decay
           constant for relaxation", 1/time).
[DYNA-LONG] Long format: a "+" after the keyword gives 20-character fields (Oasys PRIMER
           manual, "Long keyword format"); not found in LSTC's own text.
[ANS-GUIDE] Ansys Mechanical APDL Structural Analysis Guide §8.4.1.2 example listings
           (copy at issuhub.com/view/index/5341, pages 228-230): NEO "TBDATA,1 mu shear
           modulus, TBDATA,2 incompressibility parameter (as 2/K)"; OGDEN with 2 terms
           "TBDATA 1 mu1, 2 alpha1, 3 mu2, 4 alpha2, 5 d1 (second d2 is zero)";
           POLY "TB,HYPER,1,,3,POLY" takes the order N in NPTS. TBDATA,STLOC,C1..C6: at
           most six values a command starting at STLOC (Ansys 18.2 command reference,
           Hlp_C_TBDATA).
[ANS-PRONY] TB,PRONY,mat,,npts,SHEAR with TBDATA a1, t1, a2, t2, ... (relative modulus
           then relaxation time) — an Ansys-written material file quoted in docs/export.md
           (pyvisco) and hand-written APDL decks found by code search (TBDATA pairs "a_i,
           tau_i" after TB,PRONY,1,1,8,SHEAR).
NOT FOUND  Ansys's constant order for MOONEY (c10, c01, d), YEOH (c10, c20, c30, d1..d3)
           and POLY (c10, c01, c20, c11, c02[, c30, c21, c12, c03], d1..dN): the Material
           Reference pages found list only the option names. These expectations rest on
           docs/export.md (the Abaqus POLYNOMIAL order, which Ansys's polynomial form shares
           as remembered, not verified here).
[VHFIT]    vhfit's own conversions, docs/export.md "Per solver": Abaqus LONG TERM =
           vhfit constants, INSTANTANEOUS = long-term / g_inf; LS-DYNA long-term, Ogden
           MU = 2 mu/alpha, GI = G_i/3, BETAI = 1/tau_i; Ansys instantaneous, NEO mu =
           2 C10, Ogden mu = 2 mu/alpha; g_i = G_i/G0, G0 = E_inf + sum G_i, E_inf = 3 mu0.

Every parameter set below has mu0 = 1.5 MPa (E_inf = 4.5 MPa) and the Prony terms
G1 = 4.5 MPa, tau1 = 0.01 s, G2 = 9 MPa, tau2 = 2 s, so G0 = 18 MPa, g1 = 0.25,
g2 = 0.5, g_inf = 0.25 and instantaneous = 4 x long-term: every expected number is a
short binary fraction that can be checked by eye.
"""

from __future__ import annotations

import pytest

import vhfit
from vhfit.export import from_abaqus, from_ansys, from_lsdyna, to_abaqus, to_ansys, to_lsdyna

PRONY = dict(G1=4.5, tau1=0.01, G2=9.0, tau2=2.0)
G_INF = 0.25  # 1 - 0.25 - 0.5
INST = 1.0 / G_INF  # instantaneous / long-term

# Distinct binary fractions, so any swap of two constants changes the card.
HYPER = {
    "mooney_rivlin": dict(C10=0.5, C01=0.25),
    "neo_hooke": dict(C10=0.75),
    "yeoh": dict(C10=0.75, C20=0.125, C30=0.03125),
    "polynomial2": dict(C10=0.5, C01=0.25, C20=0.125, C11=0.0625, C02=0.03125),
    "polynomial3": dict(C10=0.5, C01=0.25, C20=0.125, C11=0.0625, C02=0.03125,
                        C30=0.015625, C21=0.0078125, C12=0.00390625, C03=0.001953125),
    "ogden": dict(mu1=1.5, alpha1=2.5),
    "ogden2": dict(mu1=1.0, alpha1=4.0, mu2=0.5, alpha2=-2.0),
    "ogden3": dict(mu1=1.0, alpha1=4.0, mu2=0.75, alpha2=-2.0, mu3=-0.25, alpha3=8.0),
}
# MAT_077_H has no C21, C12, C03 [DYNA-H]: its polynomial3 card needs them zero.
HYPER_DYNA = {**HYPER, "polynomial3": dict(HYPER["polynomial3"], C21=0.0, C12=0.0, C03=0.0)}
LAWS = list(HYPER)


def model_params(law: str, constants: dict | None = None):
    return vhfit.ViscoHyperelastic(law, n_prony=2), {**(constants or HYPER[law]), **PRONY}


def test_every_parameter_set_has_the_stated_moduli():
    """The hand values below assume mu0 = 1.5 MPa and g = (0.25, 0.5) for every law."""
    for table in (HYPER, HYPER_DYNA):
        for law, c in table.items():
            m, p = model_params(law, c)
            x = m.as_array(p)
            assert m.long_term_modulus(x) == pytest.approx(4.5, rel=1e-15), law
            g, _ = m.prony_g(x)
            assert list(g) == pytest.approx([0.25, 0.5], rel=1e-15), law


def floats(tokens) -> list[float]:
    return [float(t) for t in tokens]


# ---------------------------------------------------------------------------- Abaqus
def abaqus_blocks(text: str) -> list[tuple[str, list[list[str]]]]:
    """(keyword line, data lines as comma-split tokens); '**' comments skipped."""
    blocks: list[tuple[str, list[list[str]]]] = []
    for line in text.splitlines():
        if not line.strip() or line.startswith("**"):
            continue
        if line.startswith("*"):
            blocks.append((line, []))
        else:
            blocks[-1][1].append([t.strip() for t in line.rstrip(",").split(",")])
    return blocks


# keyword parameters [ABQ-KW] and data lines [CCX], long-term constants [VHFIT];
# the D values are 0 (incompressible) and the temperature is left out.
ABAQUS_LONG_TERM = {
    "mooney_rivlin": ("MOONEY-RIVLIN", [[0.5, 0.25, 0.0]]),  # C10, C01, D1
    "neo_hooke": ("NEO HOOKE", [[0.75, 0.0]]),  # C10, D1
    "yeoh": ("YEOH", [[0.75, 0.125, 0.03125, 0.0, 0.0, 0.0]]),  # C10, C20, C30, D1-D3
    # C10, C01, C20, C11, C02, D1, D2
    "polynomial2": ("POLYNOMIAL, N=2", [[0.5, 0.25, 0.125, 0.0625, 0.03125, 0.0, 0.0]]),
    # C10, C01, C20, C11, C02, C30, C21, C12 / C03, D1, D2, D3
    "polynomial3": ("POLYNOMIAL, N=3", [
        [0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625, 0.0078125, 0.00390625],
        [0.001953125, 0.0, 0.0, 0.0],
    ]),
    "ogden": ("OGDEN, N=1", [[1.5, 2.5, 0.0]]),  # mu1, alpha1, D1
    "ogden2": ("OGDEN, N=2", [[1.0, 4.0, 0.5, -2.0, 0.0, 0.0]]),  # mu1, a1, mu2, a2, D1, D2
    # mu1, alpha1, mu2, alpha2, mu3, alpha3, D1, D2 / D3
    "ogden3": ("OGDEN, N=3", [[1.0, 4.0, 0.75, -2.0, -0.25, 8.0, 0.0, 0.0], [0.0]]),
}
# [ABQ-VE] one line per term: g_i, k_i (0: no bulk relaxation), tau_i in s
ABAQUS_PRONY = [[0.25, 0.0, 0.01], [0.5, 0.0, 2.0]]


@pytest.mark.parametrize("law", LAWS)
def test_abaqus_card_fields_match_the_documented_layout(law):
    m, p = model_params(law)
    blocks = abaqus_blocks(to_abaqus(m, p, density=1.0e-9))
    assert [kw for kw, _ in blocks] == [
        "*MATERIAL, NAME=VHFIT_MATERIAL",
        "*DENSITY",
        f"*HYPERELASTIC, {ABAQUS_LONG_TERM[law][0]}, MODULI=LONG TERM",
        "*VISCOELASTIC, TIME=PRONY",
    ]
    assert blocks[1][1] == [["1e-09"]]  # tonne/mm^3, written as given
    assert [floats(row) for row in blocks[2][1]] == ABAQUS_LONG_TERM[law][1]
    assert [floats(row) for row in blocks[3][1]] == ABAQUS_PRONY


def test_abaqus_instantaneous_moduli_divide_stress_constants_by_g_inf():
    """MODULI=INSTANTANEOUS [ABQ-KW]: long-term / g_inf = 4 x; Ogden alpha unchanged."""
    m, p = model_params("polynomial2")
    blocks = abaqus_blocks(to_abaqus(m, p, moduli="instantaneous"))
    assert blocks[1][0] == "*HYPERELASTIC, POLYNOMIAL, N=2, MODULI=INSTANTANEOUS"
    assert [floats(r) for r in blocks[1][1]] == [[2.0, 1.0, 0.5, 0.25, 0.125, 0.0, 0.0]]
    assert [floats(r) for r in blocks[2][1]] == ABAQUS_PRONY  # g_i do not change
    m, p = model_params("ogden3")
    rows = [floats(r) for r in abaqus_blocks(to_abaqus(m, p, moduli="instantaneous"))[1][1]]
    assert rows == [[4.0, 4.0, 3.0, -2.0, -1.0, 8.0, 0.0, 0.0], [0.0]]


def test_abaqus_d1_from_poisson_uses_the_instantaneous_shear_modulus():
    """D1 = 2/K0, K0 = 2 mu_inst (1 + nu) / (3 (1 - 2 nu)) [VHFIT], mu_inst = 1.5 / 0.25."""
    m, p = model_params("mooney_rivlin")
    K0 = 2 * 6.0 * 1.45 / (3 * 0.1)  # nu = 0.45: 58 MPa
    row = floats(abaqus_blocks(to_abaqus(m, p, poisson=0.45))[1][1][0])
    assert row == pytest.approx([0.5, 0.25, 2 / K0], rel=1e-14)
    m, p = model_params("yeoh")
    row = floats(abaqus_blocks(to_abaqus(m, p, poisson=0.45))[1][1][0])
    assert row == pytest.approx([0.75, 0.125, 0.03125, 2 / K0, 0.0, 0.0], rel=1e-14)


# ---------------------------------------------------------------------------- LS-DYNA
def lsdyna_cards(text: str) -> list[str]:
    """The deck's lines without '$' comments (keywords, title and data cards)."""
    return [ln for ln in text.splitlines() if ln.strip() and not ln.startswith("$")]


def fixed_fields(line: str, width: int) -> list[str]:
    """Fixed-width fields, each checked right-aligned with a blank left of the value."""
    assert len(line) <= 8 * width, line
    fields = [line[k:k + width] for k in range(0, len(line), width)]
    for f in fields:
        if f.strip():
            assert len(f) == width and f[0] == " " and f[-1] != " ", (f, line)
    return fields


def field_values(line: str, width: int) -> list[float | None]:
    return [float(f) if f.strip() else None for f in fixed_fields(line, width)]


# [DYNA-H] card C10 C01 C11 C20 C02 C30: note C11 BEFORE C20 (Abaqus has C20, C11)
DYNA_POLY = {
    "mooney_rivlin": [0.5, 0.25, 0.0, 0.0, 0.0, 0.0],
    "neo_hooke": [0.75, 0.0, 0.0, 0.0, 0.0, 0.0],
    "yeoh": [0.75, 0.0, 0.0, 0.125, 0.0, 0.03125],
    "polynomial2": [0.5, 0.25, 0.0625, 0.125, 0.03125, 0.0],
    "polynomial3": [0.5, 0.25, 0.0625, 0.125, 0.03125, 0.015625],
}
# [DYNA-O] MU card and ALPHA card; MU_p = 2 mu_p / alpha_p of the long-term mu_p [VHFIT]
DYNA_OGDEN = {
    "ogden": ([2 * 1.5 / 2.5], [2.5]),
    "ogden2": ([0.5, -0.5], [4.0, -2.0]),
    "ogden3": ([0.5, -0.75, -0.0625], [4.0, -2.0, 8.0]),
}
# [DYNA-H]/[DYNA-O] one card per term: GI = G_i / 3 (MPa), BETAI = 1 / tau_i (1/s) [VHFIT]
DYNA_PRONY = [[1.5, 100.0], [3.0, 0.5]]


@pytest.mark.filterwarnings("ignore:PR = .* nearly compressible")
@pytest.mark.parametrize("long_format, width, suffix", [(True, 20, "+"), (False, 10, "")])
@pytest.mark.parametrize("law", LAWS)
def test_lsdyna_card_fields_match_the_documented_layout(law, long_format, width, suffix):
    m, p = model_params(law, HYPER_DYNA[law])
    cards = lsdyna_cards(to_lsdyna(m, p, density=1.0e-9, mid=7, long_format=long_format))
    ogden = law.startswith("ogden")
    keyword = "*MAT_OGDEN_RUBBER_TITLE" if ogden else "*MAT_HYPERELASTIC_RUBBER_TITLE"
    assert cards[0] == "*KEYWORD" and cards[-1] == "*END"
    assert cards[1] == keyword + suffix  # [DYNA-LONG]: '+' selects 20-character fields
    assert cards[2] == "VHFIT_MATERIAL"  # _TITLE: one title line
    # card 1: MID RO PR N (N = 0: constants given); MID and N are integers
    head = fixed_fields(cards[3], width)
    assert [f.strip() for f in (head[0], head[1], head[3])] == ["7", "1.0e-9", "0"]
    # PR: LS-DYNA's K = 2 G (1 + PR) / (3 (1 - 2 PR)) with G = mu0 = 1.5 must give the
    # default K = 1000 mu_inst = 6000 MPa [VHFIT]: PR = (3K - 2G)/(6K + 2G) = 17997/36003
    assert float(head[2]) == pytest.approx(17997 / 36003, rel=1e-15 if long_format else 3e-8)
    body = cards[4:-1]
    if ogden:
        mus, alphas = DYNA_OGDEN[law]
        assert field_values(body[0], width) == pytest.approx(mus, rel=1e-14)
        assert field_values(body[1], width) == alphas
        prony = body[2:]
    else:
        assert field_values(body[0], width) == DYNA_POLY[law]
        prony = body[1:]
    assert [field_values(c, width) for c in prony] == DYNA_PRONY


def test_lsdyna_standard_format_rounds_to_its_ten_character_fields():
    """Values with more digits than 9 characters hold are rounded, never overflow."""
    m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    p = dict(C10=1 / 3, C01=0.0, G1=2.0, tau1=3.0)  # E_inf = 2, GI = 2/3, BETAI = 1/3
    cards = lsdyna_cards(to_lsdyna(m, p, long_format=False))
    c = field_values(cards[4], 10)
    assert c == pytest.approx([1 / 3, 0.0, 0.0, 0.0, 0.0, 0.0], rel=1e-6)
    assert field_values(cards[5], 10) == pytest.approx([2 / 3, 1 / 3], rel=1e-6)
    long = lsdyna_cards(to_lsdyna(m, p))
    assert field_values(long[4], 20)[0] == pytest.approx(1 / 3, rel=1e-13)
    assert field_values(long[5], 20) == pytest.approx([2 / 3, 1 / 3], rel=1e-13)


# ----------------------------------------------------------------------------- Ansys
def ansys_tables(text: str) -> list[tuple[list[str], dict[int, float], list[int]]]:
    """(TB tokens, table location -> value, values per TBDATA) for every TB command."""
    tables: list[tuple[list[str], dict[int, float], list[int]]] = []
    for line in text.splitlines():
        if not line.strip() or line.startswith("!"):
            continue
        tok = line.split(",")
        if tok[0] == "TB":
            tables.append((tok, {}, []))
        elif tok[0] == "TBDATA":
            data, counts = tables[-1][1], tables[-1][2]
            start = int(tok[1])
            assert start == len(data) + 1, line  # contiguous locations
            for k, v in enumerate(tok[2:]):
                data[start + k] = float(v)
            counts.append(len(tok) - 2)
    return tables


# TB,HYPER,mat,,NPTS,TBOPT and TBDATA values from location 1: INSTANTANEOUS constants
# (long-term / g_inf = 4 x) [VHFIT]; NEO and OGDEN order [ANS-GUIDE]; MOONEY, YEOH and
# POLY order NOT FOUND in Ansys's text (see the module docstring).
ANSYS = {
    "mooney_rivlin": ("2", "MOONEY", [2.0, 1.0, 0.0]),  # c10, c01, d
    "neo_hooke": ("", "NEO", [6.0, 0.0]),  # mu = 2 C10 / g_inf, d
    "yeoh": ("3", "YEOH", [3.0, 0.5, 0.125, 0.0, 0.0, 0.0]),  # c10, c20, c30, d1-d3
    # c10, c01, c20, c11, c02, d1, d2
    "polynomial2": ("2", "POLY", [2.0, 1.0, 0.5, 0.25, 0.125, 0.0, 0.0]),
    # c10, c01, c20, c11, c02, c30, c21, c12, c03, d1, d2, d3
    "polynomial3": ("3", "POLY", [2.0, 1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125,
                                  0.015625, 0.0078125, 0.0, 0.0, 0.0]),
    # mu_p(Ansys) = 2 mu_p / alpha_p / g_inf, alpha_p, then d1..dN
    "ogden": ("1", "OGDEN", [2 * 1.5 / 2.5 * INST, 2.5, 0.0]),
    "ogden2": ("2", "OGDEN", [2.0, 4.0, -2.0, -2.0, 0.0, 0.0]),
    "ogden3": ("3", "OGDEN", [2.0, 4.0, -3.0, -2.0, -0.25, 8.0, 0.0, 0.0, 0.0]),
}
# [ANS-PRONY] a1, t1, a2, t2 with a_i = g_i (relative moduli), t_i in s
ANSYS_PRONY = [0.25, 0.01, 0.5, 2.0]


@pytest.mark.parametrize("law", LAWS)
def test_ansys_commands_match_the_documented_layout(law):
    m, p = model_params(law)
    text = to_ansys(m, p, mat=3, density=1.0e-9)
    assert "MP,DENS,3,1e-09" in text.splitlines()  # tonne/mm^3 as given
    (tb_h, hyper, counts_h), (tb_p, prony, counts_p) = ansys_tables(text)
    npts, opt, values = ANSYS[law]
    assert tb_h == ["TB", "HYPER", "3", "", npts, opt]
    assert [hyper[k] for k in sorted(hyper)] == pytest.approx(values, rel=1e-14)
    assert tb_p == ["TB", "PRONY", "3", "", "2", "SHEAR"]
    assert [prony[k] for k in sorted(prony)] == ANSYS_PRONY
    # [ANS-GUIDE] TBDATA holds six values at most
    assert max(counts_h + counts_p) <= 6 and sum(counts_h) == len(values)


def test_ansys_d1_from_poisson_uses_the_instantaneous_shear_modulus():
    m, p = model_params("polynomial2")
    K0 = 2 * 6.0 * 1.45 / (3 * 0.1)  # as for Abaqus: mu_inst = 6 MPa, nu = 0.45
    (_, hyper, _), _ = ansys_tables(to_ansys(m, p, poisson=0.45))
    assert [hyper[6], hyper[7]] == pytest.approx([2 / K0, 0.0], rel=1e-14)


# ---------------------------------------------------------------- parsers, by hand
EXPECTED_POLY2 = {**HYPER["polynomial2"], **PRONY}


def assert_params(model, params, law, expected):
    assert model.hyperelastic.name == law
    assert model.param_names == list(expected)
    assert params == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize("moduli, scale", [("LONG TERM", 1.0), ("INSTANTANEOUS", INST)])
def test_abaqus_parser_reads_a_hand_written_polynomial_card(moduli, scale):
    c = [v * scale for v in (0.5, 0.25, 0.125, 0.0625, 0.03125)]
    text = (
        "*Material, name=RUBBER\n"
        f"*Hyperelastic, polynomial, N=2, moduli={moduli}\n"
        f"{c[0]}, {c[1]}, {c[2]}, {c[3]}, {c[4]}, 0., 0.\n"
        "*Viscoelastic, time=PRONY\n"
        "0.25, 0., 0.01\n"
        "0.5, 0., 2.\n"
    )
    assert_params(*from_abaqus(text), "polynomial2", EXPECTED_POLY2)


def test_abaqus_parser_reads_hand_written_ogden3_and_yeoh_cards():
    text = (
        "*MATERIAL, NAME=O3\n*HYPERELASTIC, OGDEN, N=3\n"
        "1.0, 4.0, 0.75, -2.0, -0.25, 8.0, 0.0, 0.0\n0.0\n"
        "*VISCOELASTIC, TIME=PRONY\n0.25, 0.0, 0.01\n0.5, 0.0, 2.0\n"
    )
    assert_params(*from_abaqus(text), "ogden3", {**HYPER["ogden3"], **PRONY})
    text = ("*HYPERELASTIC, YEOH\n0.75, 0.125, 0.03125, 0.0, 0.0, 0.0\n"
            "*VISCOELASTIC, TIME=PRONY\n0.25, 0.0, 0.01\n0.5, 0.0, 2.0\n")
    assert_params(*from_abaqus(text), "yeoh", {**HYPER["yeoh"], **PRONY})


def _fixed(values, width: int) -> str:
    return "".join(str(v).rjust(width) for v in values)


@pytest.mark.parametrize("width, suffix", [(10, ""), (20, "+")])
def test_lsdyna_parser_reads_a_hand_written_mat077h_card(width, suffix):
    text = "\n".join([
        "*KEYWORD",
        f"*MAT_HYPERELASTIC_RUBBER{suffix}",
        _fixed([1, "1.0e-9", 0.4995, 0], width),
        _fixed([0.5, 0.25, 0.0625, 0.125, 0.03125, 0.0], width),  # C10 C01 C11 C20 C02 C30
        _fixed([1.5, 100.0], width),  # GI = G1/3, BETAI = 1/tau1
        _fixed([3.0, 0.5], width),
        "*END",
    ])
    assert_params(*from_lsdyna(text), "polynomial2", EXPECTED_POLY2)


def test_lsdyna_parser_reads_a_hand_written_mat077o_card():
    text = "\n".join([
        "*MAT_OGDEN_RUBBER_TITLE",
        "hand-written",
        _fixed([1, "1.0e-9", 0.4995, 0], 10),
        _fixed([0.5, -0.5], 10),  # MU_p = 2 mu_p / alpha_p
        _fixed([4.0, -2.0], 10),
        _fixed([1.5, 100.0], 10),
        _fixed([3.0, 0.5], 10),
    ])
    assert_params(*from_lsdyna(text), "ogden2", {**HYPER["ogden2"], **PRONY})


def test_ansys_parser_reads_hand_written_poly_ogden_and_neo_commands():
    prony = "TB,PRONY,1,,2,SHEAR\nTBDATA,1,0.25,0.01,0.5,2.0\n"
    text = "TB,HYPER,1,,2,POLY\nTBDATA,1,2.0,1.0,0.5,0.25,0.125,0.0\nTBDATA,7,0.0\n" + prony
    assert_params(*from_ansys(text), "polynomial2", EXPECTED_POLY2)
    text = "TB,HYPER,1,,2,OGDEN\nTBDATA,1,2.0,4.0,-2.0,-2.0,0.0,0.0\n" + prony
    assert_params(*from_ansys(text), "ogden2", {**HYPER["ogden2"], **PRONY})
    text = "TB,HYPER,1,,,NEO\nTBDATA,1,6.0,0.0\n" + prony
    assert_params(*from_ansys(text), "neo_hooke", {**HYPER["neo_hooke"], **PRONY})
    text = "TB,HYPER,1,,3,YEOH\nTBDATA,1,3.0,0.5,0.125\n" + prony
    assert_params(*from_ansys(text), "yeoh", {**HYPER["yeoh"], **PRONY})
