"""Ansys Mechanical APDL commands: ``TB,HYPER`` + ``TB,PRONY,,,,SHEAR``.

Conventions (see docs/export.md for the sources and what is verified):

* Ansys normalises the shear relaxation as G(t)/G0 = a∞ + Σ a_i exp(−t/τ_i) with
  G0 the modulus of the elastic (here hyperelastic) input, so the ``TB,HYPER``
  constants are the INSTANTANEOUS ones: long-term / g∞. The relative moduli are
  a_i = g_i = G_i / G0 (docs/theory.md §3), data order a1, t1, a2, t2, ...
* ``TB,HYPER`` options: MOONEY (2 parameters: c10, c01, d), NEO (μ = 2 C10, d),
  YEOH with N terms (c10, ..., cN0, d1..dN: vhfit's yeoh and reduced_polynomial1..6),
  POLY N=2/3 (c10, c01, c20, c11, c02[, c30, c21, c12, c03], d1..dN), OGDEN N
  (μ1, α1, ..., d1..dN; N ≤ 6 here), BOYCE (μ, λL, d: the same five-term
  Arruda–Boyce series as Abaqus's) and GENT (μ, Jm, d). Ansys's Ogden energy is
  W = Σ μ_p/α_p (λ̄1^α_p + λ̄2^α_p + λ̄3^α_p − 3), so μ_p(Ansys) = 2 μ_p / α_p. Ansys
  has no Van der Waals law.
* d = 0 is incompressible (mixed u-P elements); a Poisson's ratio gives d = 2/K0.
* At most 6 values per ``TBDATA`` command.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

from vhfit.export._common import (
    Material,
    check_compressibility,
    free_number,
    header,
    model_hint,
    no_density_note,
    parse_number,
    resolve,
    unsupported,
)
from vhfit.export._solvers import Solver
from vhfit.export.shift import wlf_constants, wlf_number
from vhfit.model import ViscoHyperelastic

__all__ = ["to_ansys", "from_ansys", "ansys_shift"]

SOLVER = "Ansys"

_OGDEN = ("ogden", "ogden2", "ogden3", "ogden4", "ogden5", "ogden6")

#: vhfit model -> (TBOPT, NPTS, vhfit constants in TBDATA order, number of d)
_CARDS = {
    "mooney_rivlin": ("MOONEY", 2, ("C10", "C01"), 1),
    "neo_hooke": ("NEO", None, ("C10",), 1),
    "yeoh": ("YEOH", 3, ("C10", "C20", "C30"), 3),
    "polynomial2": ("POLY", 2, ("C10", "C01", "C20", "C11", "C02"), 2),
    "polynomial3": (
        "POLY", 3, ("C10", "C01", "C20", "C11", "C02", "C30", "C21", "C12", "C03"), 3,
    ),
    **{name: ("OGDEN", n, tuple(x for p in range(1, n + 1) for x in (f"mu{p}", f"alpha{p}")), n)
       for n, name in enumerate(_OGDEN, 1)},
    # the reduced polynomial is Ansys's Yeoh form with N terms: c10, ..., cN0, d1..dN
    **{f"reduced_polynomial{n}": ("YEOH", n, tuple(f"C{i}0" for i in range(1, n + 1)), n)
       for n in range(1, 7)},
    "arruda_boyce": ("BOYCE", None, ("mu", "lambda_m"), 1),  # mu, lambda_L, d
    "gent": ("GENT", None, ("mu", "Jm"), 1),  # mu, Jm, d
}


def _to_ansys_constants(kind: str, c: dict[str, float]) -> list[float]:
    """vhfit (Abaqus-convention) constants in Ansys's meaning, TBDATA order."""
    order = _CARDS[kind][2]
    if kind == "neo_hooke":
        return [2.0 * c["C10"]]
    if kind.startswith("ogden"):
        out = []
        for k in range(0, len(order), 2):
            mu, alpha = c[order[k]], c[order[k + 1]]
            if alpha == 0.0:
                raise ValueError(f"{order[k + 1]} = 0: an Ogden exponent must be nonzero")
            out += [2.0 * mu / alpha, alpha]
        return out
    return [c[k] for k in order]


def _tbdata(values: list[str], per: int = 6) -> list[str]:
    return [f"TBDATA,{i + 1},{','.join(values[i:i + per])}" for i in range(0, len(values), per)]


def to_ansys(
    model,
    params=None,
    *,
    name: str = "VHFIT_MATERIAL",
    mat: int = 1,
    density: float | None = None,
    poisson: float | None = None,
    bulk_modulus: float | None = None,
    notes: Sequence[str] = (),
    comments: Sequence[str] = (),
) -> str:
    """Ansys APDL material commands of a calibrated visco-hyperelastic model.

    The commands belong inside ``/PREP7`` (or a Mechanical command snippet).

    Parameters
    ----------
    model : ViscoHyperelastic or results-like
        See :func:`vhfit.export.to_abaqus`.
    params : dict or array_like, optional
        The calibrated vhfit parameters.
    name : str
        Material name, written in the comments only.
    mat : int
        Material reference number.
    density : float, optional
        ``MP,DENS`` in tonne/mm³; without it the card's head says so.
    poisson : float, optional
        Poisson's ratio of the instantaneous response (−1 < ν < 0.5) for a compressible
        d1 = 2/K0 (K0 from the instantaneous shear modulus, see
        :meth:`Material.bulk_modulus`).
    bulk_modulus : float, optional
        K0 in MPa instead of ``poisson``. With neither, d = 0 (incompressible, mixed u-P
        elements).
    notes : sequence of str, optional
        Warnings written at the head of the card's comments (``vhfit fit`` passes the
        calibration's headlines, e.g. a g∞ at its floor).
    comments : sequence of str, optional
        Further comment lines after the units (``vhfit fit`` says which fit the
        constants come from).

    Returns
    -------
    str
        The commands, comment lines first.

    Examples
    --------
    >>> import vhfit
    >>> from vhfit.export import to_ansys
    >>> m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    >>> cmds = to_ansys(m, dict(C10=0.0, C01=5.0, G1=30.0, tau1=1e-4))
    >>> print("\\n".join(line for line in cmds.splitlines() if not line.startswith("!")))
    TB,HYPER,1,,2,MOONEY
    TBDATA,1,0.0,10.0,0.0
    TB,PRONY,1,,1,SHEAR
    TBDATA,1,0.5,0.0001
    """
    model, params = resolve(model, params, solver=RECORD)
    m = Material.from_model(model, params)
    if m.hyperelastic not in _CARDS:
        raise unsupported(SOLVER, m.hyperelastic, list(_CARDS))
    if not (isinstance(mat, int) and mat > 0):
        raise ValueError(f"mat = {mat!r} must be a positive integer")
    check_compressibility(poisson, bulk_modulus, density)
    tbopt, npts, _, n_d = _CARDS[m.hyperelastic]
    inst = m.scaled(1.0 / m.g_inf)
    values = [free_number(v) for v in _to_ansys_constants(m.hyperelastic, inst)]
    K = m.bulk_modulus(poisson, bulk_modulus)
    values += [free_number(m.d1(poisson, bulk_modulus))] + [free_number(0.0)] * (n_d - 1)

    conventions = [
        f"Material: {name}, MAT = {mat}; read inside /PREP7",
        "Shear relaxation G(t)/G0 = a_inf + sum a_i exp(-t/tau_i), G0 from TB,HYPER: "
        "a_i = g_i = G_i/G0 (G0 = E_inf + sum G_i), tau_i in s; no bulk relaxation",
        "TB,HYPER NEO: mu = 2 C10; OGDEN: W = sum mu_p/alpha_p (l1b^a+l2b^a+l3b^a-3), "
        "mu_p(Ansys) = 2 mu_p/alpha_p; Cij as vhfit (Abaqus) Cij",
        "d = 0: incompressible (mixed u-P formulation)" if K is None
        else f"d1 = 2/K0, K0 = {K:.9g} MPa "
             + (f"from Poisson's ratio {poisson!r} with the instantaneous shear modulus"
                if poisson is not None else "as given")
             + f" (K0/mu_inst = {K / m.mu_inst:.6g})",
    ]
    if density is None:
        notes = [*notes, no_density_note(SOLVER, "MP,DENS")]
    which = ("INSTANTANEOUS = vhfit long-term constants / g_inf (Ansys has no long-term "
             "option)" if m.n_prony else "long-term = instantaneous (no Prony terms)")
    lines = header("!", solver=SOLVER, notes=notes, comments=comments, mat=m, moduli=which,
                   conventions=conventions)
    if density is not None:
        lines.append(f"MP,DENS,{mat},{free_number(density)}")
    lines.append(f"TB,HYPER,{mat},,{'' if npts is None else npts},{tbopt}")
    lines += _tbdata(values)
    if m.n_prony:
        lines.append(f"TB,PRONY,{mat},,{m.n_prony},SHEAR")
        pairs = [v for g, t in zip(m.g, m.tau) for v in (free_number(g), free_number(t))]
        lines += _tbdata(pairs)
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------------- parsing
def _commands(text: str):
    for raw in text.splitlines():
        line = raw.split("!", 1)[0]
        for cmd in line.split("$"):  # APDL's command separator
            cmd = cmd.strip()
            if cmd and not cmd.startswith("/"):
                yield [t.strip() for t in cmd.split(",")]


def _hyper_layout(tbopt: str, npts: int | None) -> tuple[str, list[str], int]:
    """vhfit model, vhfit constant names in TBDATA order, number of d values."""
    opt = tbopt[:4]
    if opt == "MOON":
        layouts = {
            2: ("mooney_rivlin", ["C10", "C01"]),
            3: ("polynomial2", ["C10", "C01", "C11"]),
            5: ("polynomial2", ["C10", "C01", "C20", "C11", "C02"]),
            9: ("polynomial3", ["C10", "C01", "C20", "C11", "C02", "C30", "C21", "C12", "C03"]),
        }
        n = npts or 2
        if n not in layouts:
            raise unsupported(SOLVER, f"MOONEY with {n} parameters", list(_CARDS))
        return (*layouts[n], 1)
    if opt == "NEO":
        return "neo_hooke", ["mu"], 1
    if opt == "YEOH":
        n = npts or 1
        if not 1 <= n <= 6:
            raise unsupported(SOLVER, f"YEOH order {n}", list(_CARDS))
        kind = "yeoh" if n == 3 else f"reduced_polynomial{n}"
        return kind, list(_CARDS[kind][2]), n
    if opt == "POLY":
        n = npts or 1
        layouts = {1: "mooney_rivlin", 2: "polynomial2", 3: "polynomial3"}
        if n not in layouts:
            raise unsupported(SOLVER, f"POLY order {n}", list(_CARDS))
        return layouts[n], list(_CARDS[layouts[n]][2]), n
    if opt == "OGDE":
        n = npts or 1
        if not 1 <= n <= len(_OGDEN):
            raise unsupported(SOLVER, f"OGDEN with {n} terms", list(_CARDS))
        return _OGDEN[n - 1], list(_CARDS[_OGDEN[n - 1]][2]), n
    if opt in ("BOYC", "GENT"):
        kind = "arruda_boyce" if opt == "BOYC" else "gent"
        return kind, list(_CARDS[kind][2]), 1
    raise unsupported(SOLVER, f"TB,HYPER,,,,{tbopt}", list(_CARDS))


def from_ansys(text: str, *, mat: int | None = None) -> tuple[ViscoHyperelastic, dict]:
    """Read ``TB,HYPER`` (+ ``TB,PRONY,,,,SHEAR``) commands back into vhfit.

    Parameters
    ----------
    text : str
        APDL text; comments (``!``), ``$``-joined commands and 4-letter
        abbreviations (``TB,PRON,...,SHEA``) are understood.
    mat : int, optional
        Material number to read (default: the first one with ``TB,HYPER``).

    Returns
    -------
    model : ViscoHyperelastic
    params : dict

    Examples
    --------
    >>> from vhfit.export import from_ansys
    >>> m, p = from_ansys("TB,HYPER,1,,2,MOONEY\\nTBDATA,1,0.0,10.0,0.0\\n"
    ...                   "TB,PRONY,1,,1,SHEAR\\nTBDATA,1,0.5,1e-4\\n")
    >>> p
    {'C10': 0.0, 'C01': 5.0, 'G1': 30.0, 'tau1': 0.0001}
    """
    tables: dict[tuple[str, str], dict] = {}
    current = None
    for tok in _commands(text):
        tok = tok + [""] * 8
        cmd = tok[0].upper()
        if cmd == "TB":
            lab = tok[1].upper()[:4]
            matid = tok[2] or "1"
            npts = int(float(tok[4])) if tok[4] else None
            current = {"lab": lab, "mat": matid, "npts": npts, "opt": tok[5].upper(),
                       "data": {}, "next": 1}
            key = (lab if lab != "PRON" else f"PRON-{current['opt'][:4]}", matid)
            tables[key] = current
        elif cmd.startswith("TBDA") and current is not None:
            start = int(float(tok[1])) if tok[1] else current["next"]
            vals = [t for t in tok[2:8]]
            while vals and vals[-1] == "":
                vals.pop()
            for j, v in enumerate(vals):
                current["data"][start + j] = parse_number(v)
            current["next"] = start + len(vals)
        elif cmd in ("TBTEMP", "TBFIELD", "TBFI", "TBTE") and current is not None:
            if current["data"]:
                raise ValueError(f"{SOLVER}: temperature/field-dependent TB data is not supported")
    mats = [k[1] for k in tables if k[0] == "HYPE"]
    if not mats:
        raise ValueError("no TB,HYPER command in the Ansys text")
    matid = str(mat) if mat is not None else mats[0]
    if ("HYPE", matid) not in tables:
        raise ValueError(f"no TB,HYPER for material {matid} in the Ansys text")
    hyp = tables[("HYPE", matid)]
    kind, order, n_d = _hyper_layout(hyp["opt"], hyp["npts"])
    kind = model_hint(text, kind)  # e.g. reduced_polynomial3 written as YEOH with 3 terms
    vals = [hyp["data"].get(i, 0.0) for i in range(1, len(order) + 1)]
    ansys = dict(zip(order, vals))
    if kind == "neo_hooke":
        constants = {"C10": ansys["mu"] / 2.0}
    elif kind.startswith("ogden"):
        constants = {}
        for p in range(1, len(order) // 2 + 1):
            alpha = ansys[f"alpha{p}"]
            constants[f"mu{p}"] = ansys[f"mu{p}"] * alpha / 2.0
            constants[f"alpha{p}"] = alpha
    else:
        constants = {k: ansys.get(k, 0.0) for k in _CARDS[kind][2]}
    g, tau = [], []
    prony = tables.get(("PRON-SHEA", matid))
    if prony is not None:
        n = prony["npts"] or len(prony["data"]) // 2
        for i in range(n):
            g.append(prony["data"].get(2 * i + 1, 0.0))
            tau.append(prony["data"].get(2 * i + 2, 0.0))
    if ("PRON-BULK", matid) in tables:
        warnings.warn("TB,PRONY,,,,BULK ignored: vhfit's model is incompressible",
                      stacklevel=2)
    m = Material.from_card(kind, constants, g, tau, instantaneous=True, solver=SOLVER)
    return m.to_params()


# ------------------------------------------------------------------- shift, record
def ansys_shift(law, mat: int = 1) -> list[str]:
    """Ansys ``TB,SHIFT`` (TBOPT = WLF) commands for a WLF law.

    Ansys Mechanical APDL, ``TB,SHIFT,MAT,,,WLF`` with ``TBDATA,1,Tr,C1,C2`` (constants
    1 to 3: reference temperature, C1, C2), beside ``TB,PRONY``.

    Examples
    --------
    >>> from vhfit.tts import WLF
    >>> ansys_shift(WLF(C1=17.44, C2=51.6, T_ref=20.0))
    ['TB,SHIFT,1,,,WLF', 'TBDATA,1,20.0,17.44,51.6']
    """
    T_ref, c1, c2 = wlf_constants(law)
    if not (isinstance(mat, int) and mat >= 1):
        raise ValueError(f"mat = {mat!r}: give a material number >= 1")
    return [f"TB,SHIFT,{mat},,,WLF",
            f"TBDATA,1,{wlf_number(T_ref)},{wlf_number(c1)},{wlf_number(c2)}"]


def _add_tb_shift(card: str, law, mat: int = 1) -> str:
    """``TB,SHIFT`` after the material's commands (``TB,PRONY`` needed)."""
    lines = card.rstrip("\n").split("\n")
    if not any(ln.strip().upper().replace(" ", "").startswith("TB,PRONY") for ln in lines):
        raise ValueError("shift=: the commands have no TB,PRONY (no Prony terms): a "
                         "temperature shift needs n_prony >= 1")
    return "\n".join(lines + ansys_shift(law, mat)) + "\n"


#: Where its cards come in the list of the registered solvers (vhfit.export finds the
#: solver modules and registers their records in this order).
ORDER = 3

#: The solver record (registered by vhfit.export).
RECORD = Solver(
    name="ansys", label=SOLVER, suffix=".mac", formulation="hereditary",
    write=to_ansys, read=from_ansys, sniff=lambda body: "TB," in body.replace(" ", ""),
    laws=tuple(_CARDS), comment="!", aliases=("apdl", "mapdl"), shift=_add_tb_shift,
    density=True, bulk_modulus=True,
    no_networks=("its Bergstrom-Boyce model (TB,BB) has no publicly "
                 "documented flow equation and TBDATA numbering that vhfit could verify a "
                 "card against"))
