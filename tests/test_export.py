"""FE export (vhfit.export): round trips, pinned conventions, card formatting, errors.

The round trips write a card, parse it back (the parsers read only the text) and
compare the stresses of the re-imported model with the calibrated one on
constant-rate ramps and a loading-unloading history. A round trip alone cannot see
a convention error made the same way in writer and parser, so the conventions are
also pinned by hand-computed known answers (``test_*_known_answer``).
"""

from __future__ import annotations

import json
import re
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import vhfit
from vhfit import hyperelastic
from vhfit.export import (
    FORMATS,
    export,
    from_abaqus,
    from_ansys,
    from_json,
    from_lsdyna,
    parse,
    to_abaqus,
    to_ansys,
    to_json,
    to_lsdyna,
)

MODELS = [
    "mooney_rivlin", "neo_hooke", "yeoh", "polynomial2", "polynomial3",
    "ogden", "ogden2", "ogden3",
]
WRITERS = {"abaqus": to_abaqus, "lsdyna": to_lsdyna, "ansys": to_ansys, "json": to_json}
READERS = {"abaqus": from_abaqus, "lsdyna": from_lsdyna, "ansys": from_ansys, "json": from_json}

# constant-rate ramps (compression to -50 %, tension to +50 %) and a loading-unloading
_T = np.linspace(0.0, 0.2, 41)
HISTORIES = [
    dict(strain=np.linspace(0.0, -0.5, 26), strain_rate=-1000.0),
    dict(strain=np.linspace(0.0, -0.5, 26), strain_rate=-1.0),
    dict(strain=np.linspace(0.0, 0.5, 26), strain_rate=10.0),
    dict(strain=np.interp(_T, [0.0, 0.1, 0.2], [0.0, -0.4, 0.0]), time=_T),
]


def assert_same_stress(m1, p1, m2, p2, rtol=1e-6):
    """Stresses equal within ``rtol`` of the peak |stress| of each history."""
    assert m2.hyperelastic.name == m1.hyperelastic.name
    assert m2.param_names == m1.param_names
    for h in HISTORIES:
        s1 = m1.stress(p1, **h)
        s2 = m2.stress(p2, **h)
        scale = np.max(np.abs(s1))
        assert np.max(np.abs(s2 - s1)) <= rtol * scale, (h, s1, s2)


# ---------------------------------------------------------------- parameter strategies
def _f(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


_ALPHA = st.one_of(_f(-8.0, -0.5), _f(0.5, 8.0))


def _constants(kind: str, *, lsdyna: bool = False):
    if kind == "mooney_rivlin":
        return st.tuples(_f(0.0, 10.0), _f(0.0, 10.0)).filter(lambda c: c[0] + c[1] > 1e-3)
    if kind == "neo_hooke":
        return st.tuples(_f(1e-3, 10.0))
    if kind == "yeoh":
        return st.tuples(_f(1e-3, 10.0), _f(-0.01, 1.0), _f(-1e-3, 0.1))
    if kind == "polynomial2":
        return st.tuples(_f(1e-3, 5.0), _f(0.0, 5.0), *[_f(-0.1, 0.1)] * 3)
    if kind == "polynomial3":
        higher = [_f(-0.01, 0.01)] + [st.just(0.0) if lsdyna else _f(-0.01, 0.01)] * 3
        return st.tuples(_f(1e-3, 5.0), _f(0.0, 5.0), *[_f(-0.1, 0.1)] * 3, *higher)
    n = {"ogden": 1, "ogden2": 2, "ogden3": 3}[kind]
    return st.tuples(*[x for _ in range(n) for x in (_f(1e-3, 5.0), _ALPHA)])


@st.composite
def parameter_sets(draw, kind: str, lsdyna: bool = False, max_prony: int = 3):
    n = draw(st.integers(0, max_prony))
    hyper = list(draw(_constants(kind, lsdyna=lsdyna)))
    prony = [v for _ in range(n) for v in (draw(_f(0.0, 100.0)), 10.0 ** draw(_f(-5.0, 2.0)))]
    m = vhfit.ViscoHyperelastic(kind, n_prony=n)
    return m, m.as_dict(hyper + prony)


def _examples():
    return settings(max_examples=min(settings.default.max_examples, 12))


# ---------------------------------------------------------------------- round trips
@pytest.mark.filterwarnings("ignore:PR = .* nearly compressible")
@pytest.mark.parametrize("kind", MODELS)
@pytest.mark.parametrize("solver", ["abaqus", "lsdyna", "ansys", "json"])
def test_round_trip_reproduces_stress(solver, kind):
    @_examples()
    @given(parameter_sets(kind, lsdyna=solver == "lsdyna"))
    def check(mp):
        m, p = mp
        text = WRITERS[solver](m, p)
        m2, p2 = READERS[solver](text)
        assert_same_stress(m, p, m2, p2)
        for k in p:  # and the parameters themselves, to rounding
            assert p2[k] == pytest.approx(p[k], rel=1e-9, abs=1e-12 * (abs(p[k]) + 1.0))

    check()


@pytest.mark.parametrize("kind", ["mooney_rivlin", "yeoh", "ogden2"])
def test_abaqus_instantaneous_moduli_round_trip(kind):
    @_examples()
    @given(parameter_sets(kind))
    def check(mp):
        m, p = mp
        text = to_abaqus(m, p, moduli="instantaneous")
        m2, p2 = from_abaqus(text)
        assert_same_stress(m, p, m2, p2)

    check()


@pytest.mark.filterwarnings("ignore:PR = .* nearly compressible")
@pytest.mark.filterwarnings("ignore:PR = .* needs more digits")
@pytest.mark.parametrize("kind", ["mooney_rivlin", "polynomial2", "ogden"])
def test_lsdyna_standard_format_round_trip_to_its_precision(kind):
    """10-character fields keep 4-6 digits: the round trip holds to ~1e-4, not 1e-6."""
    @_examples()
    @given(parameter_sets(kind, lsdyna=True))
    def check(mp):
        m, p = mp
        text = to_lsdyna(m, p, long_format=False)
        m2, p2 = from_lsdyna(text)
        assert_same_stress(m, p, m2, p2, rtol=2e-4)

    check()


@pytest.mark.parametrize("solver", ["abaqus", "lsdyna", "ansys", "json"])
def test_model_without_prony_terms(solver):
    m = vhfit.ViscoHyperelastic("yeoh", n_prony=0)
    p = dict(C10=0.3, C20=-0.01, C30=0.002)
    text = WRITERS[solver](m, p)
    body = [ln.upper() for ln in text.splitlines() if not ln.startswith(("**", "$", "!"))]
    words = ("PRONY", "VISCOELASTIC", "MODULI")
    assert solver == "json" or not any(w in ln for w in words for ln in body)
    m2, p2 = READERS[solver](text)
    assert m2.n_prony == 0 and p2 == pytest.approx(p, rel=1e-12)
    assert_same_stress(m, p, m2, p2)


def test_gelatin_round_trip_with_tiny_g_inf():
    """Paper Table 6 (g_inf ~ 1e-4): instantaneous constants 1e4 x long-term."""
    m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=2)
    p = dict(C10=0.0, C01=3.56e-4, G1=21.4, tau1=10**-5.76, G2=0.0211, tau2=10**0.871)
    for solver in ("abaqus", "ansys"):
        m2, p2 = READERS[solver](WRITERS[solver](m, p))
        assert_same_stress(m, p, m2, p2)
    # LS-DYNA builds K from PR and the LONG-TERM shear modulus mu0 = 2 C01: the default
    # PR must give K = 1000 mu_inst, mu_inst = (E_inf + G1 + G2) / 3, although K/mu0 ~ 1e7
    mu0 = 2 * 3.56e-4
    mu_inst = (3 * mu0 + 21.4 + 0.0211) / 3
    text = to_lsdyna(m, p)
    pr = float(_data(text, "$")[3].split()[1])
    assert 2 * mu0 * (1 + pr) / (3 * (1 - 2 * pr)) == pytest.approx(1000 * mu_inst, rel=1e-6)
    assert "WARNING: PR" not in text
    m2, p2 = from_lsdyna(text)
    assert_same_stress(m, p, m2, p2)
    # a small bulk modulus is written, with a warning in the card and to the caller
    with pytest.warns(UserWarning, match="nearly compressible"):
        text = to_lsdyna(m, p, bulk_modulus=10 * mu_inst)
    assert "$ WARNING: PR = " in text
    # 10-character fields cannot hold this PR: K would be far off, and the card says so
    with pytest.warns(UserWarning, match="needs more digits"):
        to_lsdyna(m, p, bulk_modulus=100 * mu_inst, long_format=False)
    with pytest.raises(ValueError, match="rounds to 0.5"):
        to_lsdyna(m, p, bulk_modulus=1e9 * mu_inst, long_format=False)


# ------------------------------------------------------------- pinned conventions
# Mooney-Rivlin C10 = 0.2, C01 = 0.05: E_inf = 6 (C10 + C01) = 1.5 MPa;
# G1 = 1.5 MPa, tau1 = 0.01 s: G0 = 3, g1 = 0.5, g_inf = 0.5.
MR = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
MR_P = dict(C10=0.2, C01=0.05, G1=1.5, tau1=0.01)


def _data(text: str, comment: str) -> list[str]:
    return [ln for ln in text.splitlines() if ln.strip() and not ln.startswith(comment)]


def test_abaqus_known_answer():
    assert _data(to_abaqus(MR, MR_P), "**") == [
        "*MATERIAL, NAME=VHFIT_MATERIAL",
        "*HYPERELASTIC, MOONEY-RIVLIN, MODULI=LONG TERM",
        "0.2, 0.05, 0.0",
        "*VISCOELASTIC, TIME=PRONY",
        "0.5, 0.0, 0.01",
    ]
    inst = _data(to_abaqus(MR, MR_P, moduli="instantaneous", density=1e-9), "**")
    assert inst[1:4] == ["*DENSITY", "1e-09,", "*HYPERELASTIC, MOONEY-RIVLIN, MODULI=INSTANTANEOUS"]
    assert inst[4] == "0.4, 0.1, 0.0"  # long-term / g_inf
    # D1 = 2 / K0, K0 = 2 μ_inst (1 + ν) / (3 (1 − 2ν)); μ0 = 2 (C10 + C01) = 0.5,
    # g_inf = 1.5 / 3 = 0.5, μ_inst = 1: ν = 0.4 gives K0 = 2.8 / 0.6 = 14/3, D1 = 3/7
    comp = _data(to_abaqus(MR, MR_P, poisson=0.4), "**")
    assert [float(v) for v in comp[2].split(",")] == pytest.approx([0.2, 0.05, 3 / 7], rel=1e-15)


def test_abaqus_paper_verification_case():
    """The paper's verification material (its §3.2): C10 = 0, C01 = 5 MPa, g1 = 0.5.

    That is G1 = E_inf = 30 MPa.
    """
    p = dict(C10=0.0, C01=5.0, G1=30.0, tau1=1e-6)
    assert "0.5, 0.0, 1e-06" in to_abaqus(MR, p).splitlines()


def test_ansys_known_answer():
    assert _data(to_ansys(MR, MR_P), "!") == [
        "TB,HYPER,1,,2,MOONEY",
        "TBDATA,1,0.4,0.1,0.0",  # instantaneous = long-term / g_inf
        "TB,PRONY,1,,1,SHEAR",
        "TBDATA,1,0.5,0.01",  # a_i = g_i, tau_i
    ]
    neo = vhfit.ViscoHyperelastic("neo_hooke", n_prony=1)
    lines = _data(to_ansys(neo, dict(C10=0.25, G1=1.5, tau1=0.01)), "!")
    assert lines[:2] == ["TB,HYPER,1,,,NEO", "TBDATA,1,1.0,0.0"]  # mu = 2 C10 / g_inf


POLY2 = vhfit.ViscoHyperelastic("polynomial2", n_prony=1)
POLY2_P = dict(C10=0.1, C01=0.02, C20=0.003, C11=0.0004, C02=0.00005, G1=2.0, tau1=0.1)


def test_polynomial2_cards_follow_the_documented_constant_order():
    # Abaqus *HYPERELASTIC, POLYNOMIAL, N=2 data line: C10, C01, C20, C11, C02, D1, D2;
    # Ansys TB,HYPER,,,2,POLY: TBDATA c10, c01, c20, c11, c02, d1, d2. Every constant
    # differs, so any other order shows. E_inf = 6 (C10 + C01) = 0.72, G0 = 2.72, and
    # Ansys takes instantaneous constants: long-term / g_inf = long-term * 2.72 / 0.72.
    c = [0.1, 0.02, 0.003, 0.0004, 0.00005]
    lines = _data(to_abaqus(POLY2, POLY2_P), "**")
    i = lines.index("*HYPERELASTIC, POLYNOMIAL, N=2, MODULI=LONG TERM")
    assert [float(v) for v in lines[i + 1].split(",")] == pytest.approx(c + [0.0, 0.0],
                                                                         rel=1e-15)
    lines = _data(to_ansys(POLY2, POLY2_P), "!")
    assert lines[0] == "TB,HYPER,1,,2,POLY"
    tb = [float(v) for v in lines[1].split(",")[2:]] + [float(lines[2].split(",")[2])]
    assert lines[1].split(",")[1] == "1" and lines[2].split(",")[1] == "7"
    assert tb == pytest.approx([v * 2.72 / 0.72 for v in c] + [0.0, 0.0], rel=1e-14)


def test_ogden_mu_conventions_known_answer():
    """Abaqus 2mu/alpha^2 form -> LS-DYNA/Ansys mu/alpha form: MU = 2 mu / alpha."""
    m = vhfit.ViscoHyperelastic("ogden", n_prony=1)
    # mu0 = mu1 = 0.3 -> E_inf = 0.9; G1 = 0.9 -> g1 = 0.5
    p = dict(mu1=0.3, alpha1=2.5, G1=0.9, tau1=0.02)
    assert "0.3, 2.5, 0.0" in to_abaqus(m, p).splitlines()
    ansys = _data(to_ansys(m, p), "!")
    assert ansys[0] == "TB,HYPER,1,,1,OGDEN"
    tbdata = [float(v) for v in ansys[1].split(",")[2:]]
    assert tbdata == pytest.approx([0.48, 2.5, 0.0], rel=1e-14)  # 2*0.3/2.5 / g_inf
    card = _data(to_lsdyna(m, p), "$")
    assert card[1] == "*MAT_OGDEN_RUBBER_TITLE+"
    assert [float(v) for v in card[4].split()] == pytest.approx([0.24])  # 2*0.3/2.5, long-term
    assert [float(v) for v in card[5].split()] == [2.5]
    assert [float(v) for v in card[6].split()] == pytest.approx([0.3, 50.0])  # G1/3, 1/tau1


def test_lsdyna_known_answer():
    card = _data(to_lsdyna(MR, MR_P, density=1e-9), "$")
    assert card[0] == "*KEYWORD" and card[-1] == "*END"
    assert card[1] == "*MAT_HYPERELASTIC_RUBBER_TITLE+"
    assert card[2] == "VHFIT_MATERIAL"
    # MID RO PR N; PR: mu0 = 0.5, G0 = 1.5 + 1.5 = 3, mu_inst = 1, so the default
    # K = 1000 mu_inst = 1000 MPa; LS-DYNA's K = 2 G (1 + PR) / (3 (1 - 2 PR)) with
    # G = mu0 = 0.5 gives it for PR = (3000 - 1) / (6000 + 1)
    assert [float(v) for v in card[3].split()] == pytest.approx([1, 1e-9, 2999 / 6001, 0],
                                                                rel=1e-15)
    assert [float(v) for v in card[4].split()] == [0.2, 0.05, 0, 0, 0, 0]  # long-term Cij
    assert [float(v) for v in card[5].split()] == [0.5, 100.0]  # GI = G1/3, BETAI = 1/tau1


def test_lsdyna_small_strain_relaxation_modulus_matches():
    """3 x (mu0 + sum GI exp(-beta t)) is vhfit's E(t) = E_inf + sum G_i exp(-t/tau_i)."""
    m = vhfit.ViscoHyperelastic("polynomial2", n_prony=2)
    p = dict(C10=0.2, C01=0.1, C20=0.01, C11=0.0, C02=0.0, G1=4.0, tau1=1e-3, G2=1.0, tau2=2.0)
    rows = _data(to_lsdyna(m, p), "$")
    c = [float(v) for v in rows[4].split()]
    gi_beta = [[float(v) for v in r.split()] for r in rows[5:7]]
    t = np.logspace(-5, 2, 30)
    E_dyna = 3 * (2 * (c[0] + c[1]) + sum(g * np.exp(-b * t) for g, b in gi_beta))
    E_vhfit = vhfit.viscoelastic.relaxation_modulus(t, m.long_term_modulus(m.as_array(p)),
                                                    [4.0, 1.0], [1e-3, 2.0])
    np.testing.assert_allclose(E_dyna, E_vhfit, rtol=1e-12)


# ------------------------------------------------------------------------ formatting
@pytest.mark.filterwarnings("ignore:PR = .* nearly compressible")
@pytest.mark.parametrize("long_format, width", [(True, 20), (False, 10)])
def test_lsdyna_fixed_width_fields_never_overflow(long_format, width):
    m = vhfit.ViscoHyperelastic("polynomial3", n_prony=6)
    p = dict(C10=0.123456789, C01=-1.23456789e-7, C20=12345.6789, C11=-9.87654321e-300,
             C02=1e300, C30=-3.3333333333333e-5, C21=0.0, C12=0.0, C03=0.0)
    for i in range(1, 7):
        p |= {f"G{i}": 10.0 ** (i - 4) / 7, f"tau{i}": 10.0 ** (2 * i - 8) / 3}
    text = to_lsdyna(m, p, long_format=long_format, density=1.1e-9)
    title = False
    for line in text.splitlines():
        if line.startswith("$") or line.startswith("*"):
            title = line.startswith("*MAT_")
            assert len(line) <= 8 * width
            continue
        if title:  # the _TITLE line
            title = False
            continue
        assert len(line) <= 8 * width
        for k in range(0, len(line), width):
            field = line[k:k + width]
            if field.strip():
                assert field[0] == " ", f"field {field!r} touches its neighbour"
                assert re.fullmatch(r"\s*-?\d+(\.\d*)?(e-?\d+)?", field), field
                float(field)


def test_lsdyna_prony_term_limit():
    m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=7)
    p = {"C10": 0.1, "C01": 0.0} | {f"G{i}": 1.0 for i in range(1, 8)}
    p |= {f"tau{i}": 10.0**i for i in range(1, 8)}
    with pytest.raises(ValueError, match="at most 6 Prony terms"):
        to_lsdyna(m, p)


def test_abaqus_data_lines_hold_at_most_eight_values():
    m = vhfit.ViscoHyperelastic("polynomial3", n_prony=0)
    text = to_abaqus(m, dict(zip(m.param_names, [0.1] * 9)), poisson=0.49)
    lines = _data(text, "**")
    i = lines.index("*HYPERELASTIC, POLYNOMIAL, N=3")  # no MODULI without Prony terms
    first, second = lines[i + 1], lines[i + 2]
    assert len(first.rstrip(",").split(",")) == 8 and first.endswith(",")
    assert len(second.split(",")) == 4  # C03, D1, D2, D3
    assert float(second.split(",")[1]) > 0  # D1 from poisson
    assert all(len(ln) <= 256 for ln in text.splitlines())


@given(st.floats(1e-200, 1e200), st.floats(1e-3, 1.0), st.floats(1e-3, 1e3),
       st.floats(1e-200, 1e200))
def test_abaqus_numbers_fit_in_20_characters_and_read_back(c10, r, q, tau1):
    """Regression: Abaqus' syntax allows 20 characters a number and CalculiX cuts a longer
    one at 20, so a 21-character '4.575210514986395e-05' was read as 4.575. Every number
    of a card fits, and a reader that keeps only the first 20 characters of each field
    gets every constant back to 1e-12 (the digits that fit)."""
    m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    p = dict(C10=c10 / 3.0, C01=c10 * r / 7.0, G1=c10 * q / 11.0, tau1=tau1 / 3.0)
    text = to_abaqus(m, p, bulk_modulus=1e4 * c10 / 3.0)
    lines = _data(text, "**")
    i = lines.index("*HYPERELASTIC, MOONEY-RIVLIN, MODULI=LONG TERM")
    j = lines.index("*VISCOELASTIC, TIME=PRONY")
    fields = [f.strip() for k in (i + 1, j + 1) for f in lines[k].split(",")]
    assert all(len(f) <= 20 for f in fields), fields
    c10_read, c01_read, d1, _, _, tau_read = (float(f[:20]) for f in fields)
    assert c10_read == pytest.approx(p["C10"], rel=1e-12)
    assert c01_read == pytest.approx(p["C01"], rel=1e-12)
    assert d1 == pytest.approx(2.0 / (1e4 * c10 / 3.0), rel=1e-12)
    assert tau_read == pytest.approx(p["tau1"], rel=1e-12)


def test_ansys_tbdata_holds_at_most_six_values():
    m = vhfit.ViscoHyperelastic("polynomial3", n_prony=4)
    p = dict(zip(m.param_names, [0.1] * 9 + [1.0, 1e-3, 2.0, 1e-2, 3.0, 1e-1, 4.0, 1.0]))
    for line in _data(to_ansys(m, p), "!"):
        if line.startswith("TBDATA"):
            assert 1 <= len(line.split(",")) - 2 <= 6


@pytest.mark.parametrize("solver, comment", [("abaqus", "**"), ("lsdyna", "$"), ("ansys", "!")])
def test_cards_start_with_documenting_comments(solver, comment):
    text = WRITERS[solver](MR, MR_P)
    assert text.isascii()
    lines = text.splitlines()
    if solver == "lsdyna":
        lines = lines[1:]  # *KEYWORD
    head = []
    for ln in lines:
        if not ln.startswith(comment):
            break
        head.append(ln)
    block = "\n".join(head)
    assert re.search(r"vhfit \d", block)  # generator and version
    assert "mooney_rivlin" in block and "Units: N, mm, s, MPa" in block
    assert "tonne/mm^3" in block
    assert re.search(r"Hyperelastic moduli are (LONG-TERM|INSTANTANEOUS)", block)


def test_instantaneous_or_long_term_is_stated():
    assert "moduli are LONG-TERM" in to_abaqus(MR, MR_P)
    assert "moduli are INSTANTANEOUS" in to_abaqus(MR, MR_P, moduli="instantaneous")
    assert "moduli are INSTANTANEOUS" in to_ansys(MR, MR_P)
    assert "moduli are LONG-TERM" in to_lsdyna(MR, MR_P)


# -------------------------------------------------------------------------- errors
@pytest.fixture
def custom_model():
    name = "gent_export_test"

    @hyperelastic.register(name, overwrite=True, example=(0.1, 10.0))
    def gent(I1, I2, mu, Jm):
        return -mu * Jm / 2 * np.log(1 - (I1 - 3) / Jm)

    yield vhfit.ViscoHyperelastic(name, n_prony=1), {"mu": 0.1, "Jm": 10.0, "G1": 1.0,
                                                     "tau1": 1.0}
    hyperelastic.unregister(name)


@pytest.mark.parametrize("solver, label", [
    ("abaqus", "Abaqus"), ("lsdyna", "LS-DYNA"), ("ansys", "Ansys")])
def test_unsupported_model_names_solver_model_and_alternatives(custom_model, solver, label):
    m, p = custom_model
    with pytest.raises(ValueError) as err:
        WRITERS[solver](m, p)
    msg = str(err.value)
    assert label in msg and "gent_export_test" in msg and "mooney_rivlin" in msg


def test_lsdyna_rejects_polynomial3_terms_mat077h_cannot_hold():
    m = vhfit.ViscoHyperelastic("polynomial3", n_prony=0)
    p = dict(zip(m.param_names, [0.1, 0.05, 0.0, 0.0, 0.0, 0.0, 0.01, 0.0, 0.0]))
    with pytest.raises(ValueError, match=r"LS-DYNA.*polynomial3.*C21.*supported: "):
        to_lsdyna(m, p)


def test_invalid_parameters_and_options_are_refused():
    with pytest.raises(ValueError, match="long-term modulus"):
        to_abaqus(MR, dict(C10=0.0, C01=0.0, G1=1.0, tau1=1.0))
    with pytest.raises(ValueError, match="moduli"):
        to_abaqus(MR, MR_P, moduli="relaxed")
    with pytest.raises(ValueError, match="poisson"):
        to_lsdyna(MR, MR_P, poisson=0.5)
    with pytest.raises(ValueError, match="export target"):
        export(MR, MR_P, to="nastran")
    with pytest.raises(TypeError, match="parameters"):
        to_ansys(MR)


# ------------------------------------------------------------- dispatch and parsing
def test_export_dispatch_accepts_results_like_objects():
    result = SimpleNamespace(model=MR, params=MR_P)
    as_dict = {"hyperelastic": "mooney_rivlin", "params": MR_P}
    for to in ("abaqus", "lsdyna", "ansys", "json"):
        text = export(MR, MR_P, to=to)
        assert export(result, to=to) == text
        assert export(as_dict, to=to) == text
        m2, p2 = parse(text)  # format guessed
        assert p2 == pytest.approx(MR_P, rel=1e-12)
    assert set(FORMATS) == {"abaqus", "lsdyna", "ansys", "json"}


def test_json_document():
    doc = json.loads(to_json(MR, MR_P))
    assert doc["hyperelastic"] == "mooney_rivlin" and doc["n_prony"] == 1
    assert doc["derived"]["g"] == [0.5] and doc["derived"]["g_inf"] == 0.5
    assert doc["derived"]["instantaneous_constants"] == {"C10": 0.4, "C01": 0.1}
    # a results-like document with a nested model description reads too
    m2, p2 = from_json(json.dumps({"model": {"hyperelastic": "mooney_rivlin", "n_prony": 1},
                                   "params": MR_P, "rmsape": 1.0}))
    assert m2.param_names == MR.param_names and p2 == MR_P


def test_parsers_read_hand_written_variants():
    # Abaqus: lower case, no MODULI (LONG TERM is the default), reduced polynomial N=1
    m, p = from_abaqus("*Material, name=A\n*Hyperelastic, reduced polynomial, n=1\n0.25, 0.\n"
                       "*Viscoelastic, time=PRONY\n0.5, 0., 0.01\n")
    assert m.hyperelastic.name == "neo_hooke" and p == pytest.approx(
        dict(C10=0.25, G1=1.5, tau1=0.01))
    # Ansys: abbreviated labels as written by Ansys itself, TBDATA without STLOC
    m, p = from_ansys("TB,HYPE,1,1,2,MOON\nTBDATA,,0.4,0.1,0.\nTB,PRON,1,1,1,SHEA\n"
                      "TBFIELD,TEMP,0.0\nTBDATA,1,0.5,1.e-2\n")
    assert p == pytest.approx(MR_P)
    # LS-DYNA: global long format, comma-separated and fixed cards mixed
    long_card = (
        "*KEYWORD LONG=Y\n*MAT_HYPERELASTIC_RUBBER\n"
        + "".join(f"{v:>20}" for v in ("1", "1e-9", "0.4995", "0")) + "\n"
        + "".join(f"{v:>20}" for v in ("0.2", "0.05")) + "\n0.5,100.0\n*END\n"
    )
    m, p = from_lsdyna(long_card)
    assert m.hyperelastic.name == "mooney_rivlin" and p == pytest.approx(MR_P)


def test_lsdyna_parser_names_the_polynomial_model_from_the_fields():
    m = vhfit.ViscoHyperelastic("yeoh", n_prony=0)
    text = to_lsdyna(m, dict(C10=0.3, C20=0.01, C30=0.0))
    assert from_lsdyna(text)[0].hyperelastic.name == "yeoh"  # from the vhfit comment
    bare = "\n".join(ln for ln in text.splitlines() if not ln.startswith("$"))
    assert from_lsdyna(bare)[0].hyperelastic.name == "yeoh"  # inferred: C10, C20 only
    with pytest.raises(ValueError, match="N = 2"):
        from_lsdyna("*MAT_HYPERELASTIC_RUBBER\n1,1e-9,0.4995,2\n1.,1.,1.,1\n")
