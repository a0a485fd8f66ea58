"""Time–temperature shift in the solver cards: a WLF law added where each solver expects it.

The Prony terms of a card are those at the reference temperature T_ref; the shift
function makes every relaxation time τ_i(T) = a_T τ_i with the WLF law
log10 a_T = −C1 (T − T_ref)/(C2 + T − T_ref) (:class:`vhfit.tts.WLF`). Each solver's
record (:class:`vhfit.export.Solver`) says how its card takes the law (its ``shift``:
the solver's own shift keyword, or comment lines for a card without a shift field); the
layouts and their sources are in the solver modules and docs/export.md, docs/dma.md.

::

    from vhfit.export import export
    card = export(model, params, to=solver, shift=law)   # the hook: add_shift(...)
"""

from __future__ import annotations

import math

from vhfit.export._solvers import get_solver, names

__all__ = ["SHIFT_TARGETS", "wlf_constants", "wlf_number", "add_shift"]

#: The solvers whose records take a shift (a live view of the registry).
SHIFT_TARGETS = names(lambda rec: rec.shift is not None)


def wlf_constants(law) -> tuple[float, float, float]:
    """(T_ref, C1, C2) of a WLF law; one-line errors for anything else.

    Examples
    --------
    >>> from vhfit.tts import WLF
    >>> wlf_constants(WLF(C1=17.44, C2=51.6, T_ref=20.0))
    (20.0, 17.44, 51.6)
    """
    kind = getattr(law, "name", type(law).__name__)  # a user's law may have no name
    if kind != "wlf":
        raise ValueError(f"shift = {kind!r} law: the solvers' cards take WLF only; fit one "
                         "with vhfit.tts.fit_shift_law(T, log_aT, 'wlf')")
    vals = (float(law.T_ref), float(law.C1), float(law.C2))
    if not all(math.isfinite(v) for v in vals) or not vals[2] > 0:
        raise ValueError(f"shift: WLF T_ref, C1, C2 = {vals}: give finite constants, C2 > 0")
    return vals


def wlf_number(x: float) -> str:
    """A shift constant as a card writes it: the shortest text that reads back exactly.

    Examples
    --------
    >>> wlf_number(8.86), wlf_number(25)
    ('8.86', '25.0')
    """
    return repr(float(x))


def add_shift(card: str, law, to: str, *, mat: int = 1) -> str:
    """The card with the shift of ``law`` added in the place its solver expects.

    Where the shift goes is the solver record's ``shift`` (its solver module writes the
    lines: a shift keyword after the Prony terms, or comment lines).

    Examples
    --------
    >>> import vhfit
    >>> from vhfit.export import export
    >>> from vhfit.tts import WLF
    >>> m = vhfit.ViscoHyperelastic("neo_hooke", n_prony=1)
    >>> card = {s: export(m, dict(C10=0.5, G1=1.0, tau1=0.1), to=s) for s in SHIFT_TARGETS}
    >>> law = WLF(8.86, 101.6, 25.0)
    >>> all("101.6" not in card[s] and "101.6" in add_shift(card[s], law, s)
    ...     for s in SHIFT_TARGETS), len(SHIFT_TARGETS) > 0
    (True, True)
    """
    targets = list(SHIFT_TARGETS)
    try:
        rec = get_solver(to)
    except ValueError:
        rec = None
    if rec is None or rec.shift is None:
        raise ValueError(f"shift=: a shift goes to {', '.join(targets)} cards, not {to!r}")
    wlf_constants(law)
    return rec.shift(card, law, mat)
