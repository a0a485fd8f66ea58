"""Temperature shift in the cards (vhfit.export.shift), against the documented layouts:
Abaqus Keywords Reference *TRS (DEFINITION=WLF; data line: reference temperature, C1,
C2), Ansys TB,SHIFT with TBOPT=WLF (TBDATA constants 1-3: Tr, C1, C2)."""

from __future__ import annotations

import pytest

import vhfit
from vhfit.export import export, from_abaqus, from_ansys, from_lsdyna
from vhfit.export.abaqus import abaqus_trs
from vhfit.export.ansys import ansys_shift
from vhfit.export.lsdyna import lsdyna_shift_note
from vhfit.export.shift import SHIFT_TARGETS, add_shift
from vhfit.tts import WLF, Arrhenius

MODEL = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=2)
PARAMS = dict(C10=0.1, C01=0.4, G1=3.0, tau1=0.01, G2=1.0, tau2=1.0)
LAW = WLF(C1=8.86, C2=101.6, T_ref=25.0)


def data_lines(card: str) -> list[str]:
    return [ln for ln in card.splitlines() if ln.strip() and not ln.startswith(("**", "!", "$"))]


def test_abaqus_card_ends_with_trs_after_the_prony_lines():
    card = export(MODEL, PARAMS, to="abaqus", shift=LAW)
    lines = data_lines(card)
    k = lines.index("*VISCOELASTIC, TIME=PRONY")
    assert lines[k + 3:] == ["*TRS, DEFINITION=WLF", "25.0, 8.86, 101.6"]
    fields = [float(v) for v in lines[-1].split(",")]
    assert fields == [LAW.T_ref, LAW.C1, LAW.C2]  # reference temperature, C1, C2
    m, p = from_abaqus(card)  # the Prony terms read back unchanged (at T_ref)
    assert p == pytest.approx(PARAMS, rel=1e-12)


def test_ansys_commands_carry_tb_shift_wlf_after_tb_prony():
    card = export(MODEL, PARAMS, to="ansys", shift=LAW, mat=3)
    lines = data_lines(card)
    k = next(i for i, ln in enumerate(lines) if ln.startswith("TB,PRONY"))
    assert lines[k + 2:] == ["TB,SHIFT,3,,,WLF", "TBDATA,1,25.0,8.86,101.6"]  # 1 TBDATA: 2 terms
    tb = lines[-2].split(",")
    assert tb[0] == "TB" and tb[1] == "SHIFT" and tb[2] == "3" and tb[5] == "WLF"
    assert [float(v) for v in lines[-1].split(",")[2:]] == [25.0, 8.86, 101.6]
    m, p = from_ansys(card)
    assert p == pytest.approx(PARAMS, rel=1e-12)


def test_lsdyna_card_gets_a_note_before_end_and_still_reads_back():
    card = export(MODEL, PARAMS, to="lsdyna", shift=LAW)
    lines = card.splitlines()
    end = lines.index("*END")
    assert lines[end - 3].startswith("$ NOTE: no time-temperature shift")
    assert "BETAI(T) = BETAI / a_T" in lines[end - 1]
    assert "-8.86 (T - 25) / (101.6 + T - 25)" in lines[end - 1]
    m, p = from_lsdyna(card)
    assert p == pytest.approx(PARAMS, rel=1e-10)


def test_the_line_builders_match_the_layouts():
    assert abaqus_trs(LAW) == ["*TRS, DEFINITION=WLF", "25.0, 8.86, 101.6"]
    assert ansys_shift(LAW) == ["TB,SHIFT,1,,,WLF", "TBDATA,1,25.0,8.86,101.6"]
    assert len(lsdyna_shift_note(LAW)) == 3
    assert set(SHIFT_TARGETS) == {"abaqus", "ansys", "lsdyna"}


def test_shift_refusals_are_one_line():
    with pytest.raises(ValueError, match="WLF only"):
        abaqus_trs(Arrhenius(1e5, 25.0))
    elastic = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=0)
    with pytest.raises(ValueError, match="n_prony >= 1"):
        export(elastic, dict(C10=0.1, C01=0.4), to="abaqus", shift=LAW)
    with pytest.raises(ValueError, match="n_prony >= 1"):
        add_shift("TB,HYPER,1,,2,MOONEY\n", LAW, "ansys")
    with pytest.raises(ValueError, match="not 'json'"):
        export(MODEL, PARAMS, to="json", shift=LAW)
    with pytest.raises(ValueError, match="mat"):
        ansys_shift(LAW, mat=0)
