"""Time–temperature shift for the solvers: Abaqus ``*TRS``, Ansys ``TB,SHIFT``, LS-DYNA note.

The Prony terms of a card are those at the reference temperature T_ref; the shift
function makes every relaxation time τ_i(T) = a_T τ_i with the WLF law
log10 a_T = −C1 (T − T_ref)/(C2 + T − T_ref) (:class:`vhfit.tts.WLF`). Layouts
(docs/export.md, docs/dma.md):

* Abaqus Keywords Reference, ``*TRS``: ``DEFINITION=WLF`` (the default), one data line
  "reference temperature, C1, C2"; it must follow ``*VISCOELASTIC`` in the material.
  Abaqus writes the WLF law with reduced time dτ/dt = 1/A, log10 A = −C1 (θ − θ0)/
  (C2 + θ − θ0): the same C1, C2 as vhfit's.
* Ansys Mechanical APDL, ``TB,SHIFT,MAT,,,WLF`` with ``TBDATA,1,Tr,C1,C2`` (constants
  1 to 3: reference temperature, C1, C2), beside ``TB,PRONY``.
* LS-DYNA: ``*MAT_HYPERELASTIC_RUBBER`` and ``*MAT_OGDEN_RUBBER`` (the cards vhfit
  writes) have no temperature shift; the card gets comment lines saying so, with the
  law, so that an analysis away from T_ref can scale BETAI = 1/τ_i by 1/a_T itself.

::

    from vhfit.export import export
    card = export(model, params, to="abaqus", shift=law)   # the hook: add_shift(...)
"""

from __future__ import annotations

import math

__all__ = ["SHIFT_TARGETS", "abaqus_trs", "ansys_shift", "lsdyna_shift_note", "add_shift"]

#: Export targets that carry a shift (LS-DYNA gets a note instead).
SHIFT_TARGETS = ("abaqus", "ansys", "lsdyna")


def _wlf(law) -> tuple[float, float, float]:
    """(T_ref, C1, C2) of a WLF law; one-line errors for anything else."""
    if getattr(law, "name", None) != "wlf":
        kind = getattr(law, "name", type(law).__name__)
        raise ValueError(f"shift = {kind!r} law: the solvers' cards take WLF only; fit one "
                         "with vhfit.tts.fit_shift_law(T, log_aT, 'wlf')")
    vals = (float(law.T_ref), float(law.C1), float(law.C2))
    if not all(math.isfinite(v) for v in vals) or not vals[2] > 0:
        raise ValueError(f"shift: WLF T_ref, C1, C2 = {vals}: give finite constants, C2 > 0")
    return vals


def _num(x: float) -> str:
    return repr(float(x))


def abaqus_trs(law) -> list[str]:
    """Abaqus ``*TRS, DEFINITION=WLF`` lines for a WLF law.

    Examples
    --------
    >>> from vhfit.tts import WLF
    >>> abaqus_trs(WLF(C1=17.44, C2=51.6, T_ref=20.0))
    ['*TRS, DEFINITION=WLF', '20.0, 17.44, 51.6']
    """
    T_ref, c1, c2 = _wlf(law)
    return ["*TRS, DEFINITION=WLF", f"{_num(T_ref)}, {_num(c1)}, {_num(c2)}"]


def ansys_shift(law, mat: int = 1) -> list[str]:
    """Ansys ``TB,SHIFT`` (TBOPT = WLF) commands for a WLF law.

    Examples
    --------
    >>> from vhfit.tts import WLF
    >>> ansys_shift(WLF(C1=17.44, C2=51.6, T_ref=20.0))
    ['TB,SHIFT,1,,,WLF', 'TBDATA,1,20.0,17.44,51.6']
    """
    T_ref, c1, c2 = _wlf(law)
    if not (isinstance(mat, int) and mat >= 1):
        raise ValueError(f"mat = {mat!r}: give a material number >= 1")
    return [f"TB,SHIFT,{mat},,,WLF", f"TBDATA,1,{_num(T_ref)},{_num(c1)},{_num(c2)}"]


def lsdyna_shift_note(law) -> list[str]:
    """LS-DYNA comment lines: the card has no shift; the law to apply by hand.

    Examples
    --------
    >>> from vhfit.tts import WLF
    >>> print(lsdyna_shift_note(WLF(C1=17.44, C2=51.6, T_ref=20.0))[0])
    $ NOTE: no time-temperature shift written: this card has no shift field.
    """
    T_ref, c1, c2 = _wlf(law)
    return [
        "$ NOTE: no time-temperature shift written: this card has no shift field.",
        f"$   The Prony terms are at T_ref = {T_ref:g}; at temperature T use",
        f"$   BETAI(T) = BETAI / a_T, log10 a_T = -{c1:g} (T - {T_ref:g}) / ({c2:g} + T - "
        f"{T_ref:g}) (WLF)",
    ]


def add_shift(card: str, law, to: str, *, mat: int = 1) -> str:
    """The card with the shift of ``law`` added in the place its solver expects.

    Abaqus: ``*TRS`` after the material's ``*VISCOELASTIC`` lines (the card's end);
    Ansys: ``TB,SHIFT`` after ``TB,PRONY``; LS-DYNA: the note before ``*END``.

    Examples
    --------
    >>> from vhfit.tts import WLF
    >>> card = "*MATERIAL, NAME=M\\n*VISCOELASTIC, TIME=PRONY\\n0.5, 0.0, 0.1\\n"
    >>> print(add_shift(card, WLF(8.86, 101.6, 25.0), "abaqus"), end="")
    *MATERIAL, NAME=M
    *VISCOELASTIC, TIME=PRONY
    0.5, 0.0, 0.1
    *TRS, DEFINITION=WLF
    25.0, 8.86, 101.6
    """
    key = str(to).strip().lower()
    if key not in SHIFT_TARGETS:
        raise ValueError(f"shift=: a shift goes to {', '.join(SHIFT_TARGETS)} cards, not "
                         f"{to!r}")
    lines = card.rstrip("\n").split("\n")
    upper = [ln.strip().upper() for ln in lines]
    if key == "abaqus":
        if not any(u.startswith("*VISCOELASTIC") for u in upper):
            raise ValueError("shift=: the card has no *VISCOELASTIC (no Prony terms): a "
                             "temperature shift needs n_prony >= 1")
        return "\n".join(lines + abaqus_trs(law)) + "\n"
    if key == "ansys":
        if not any(u.replace(" ", "").startswith("TB,PRONY") for u in upper):
            raise ValueError("shift=: the commands have no TB,PRONY (no Prony terms): a "
                             "temperature shift needs n_prony >= 1")
        return "\n".join(lines + ansys_shift(law, mat)) + "\n"
    note = lsdyna_shift_note(law)
    end = upper.index("*END") if "*END" in upper else len(lines)
    return "\n".join(lines[:end] + note + lines[end:]) + "\n"
