"""LS-DYNA cards: ``*MAT_HYPERELASTIC_RUBBER`` (MAT_077_H) and ``*MAT_OGDEN_RUBBER`` (MAT_077_O).

Conventions (see docs/export.md for the sources and what is verified):

* The polynomial constants C10, C01, C11, C20, C02, C30 of MAT_077_H are the Abaqus /
  vhfit Cij. Only these six exist, so polynomial3 is exported only when its C21, C12
  and C03 are zero, and reduced_polynomial4..6 only when their C40.. are zero.
* Ogden laws (up to 6 terms; MAT_077_O holds 8) go to MAT_077_O. Arruda–Boyce, Gent
  and Van der Waals have no exact LS-DYNA card: MAT_127 (Arruda–Boyce) takes the
  number of chain links N = λm² as an integer.
* MAT_077_O's Ogden energy is W = Σ μ_p/α_p (λ̄1^α_p + λ̄2^α_p + λ̄3^α_p − 3), not
  Abaqus's 2μ_p/α_p²: MU_p = 2 μ_p / α_p (vhfit μ_p).
* The hyperelastic constants are the LONG-TERM ones: the Prony stress is added on top
  of the stress from the strain energy. Each optional card carries GI, a SHEAR
  relaxation modulus in stress units, and BETAI, a decay constant in 1/time:
  GI = G_i / 3 (vhfit's G_i is uniaxial; uniaxial = 3 × shear for an incompressible
  solid at small strain) and BETAI = 1 / τ_i.
* PR is the Poisson's ratio LS-DYNA builds the bulk modulus from, with the LONG-TERM
  shear modulus: K = 2 G (1 + PR) / (3 (1 − 2 PR)), G = μ0. vhfit writes the PR that
  gives the intended K — 1000 × the instantaneous shear modulus by default, or from a
  Poisson's ratio of the instantaneous response, or given — with enough digits that
  K read back from the printed PR is within 0.1 % of it (:func:`lsdyna_pr`; the long
  format gives ~1e-9).
* Fields are fixed width, 8 to a card. Default is the long format (20-character
  fields, keyword suffix ``+``), which keeps 13 significant digits; the standard
  10-character format keeps only 4-6 and is offered for old readers.
"""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Sequence

import numpy as np

from vhfit import hyperelastic as _hyper
from vhfit.export._common import (
    BULK_RATIO,
    Material,
    TooManyTerms,
    check_compressibility,
    fixed_number,
    header,
    no_density_note,
    parse_number,
    resolve,
    unsupported,
)
from vhfit.export._solvers import Solver
from vhfit.export.shift import wlf_constants
from vhfit.model import ViscoHyperelastic

__all__ = ["to_lsdyna", "from_lsdyna", "lsdyna_pr", "lsdyna_bulk_modulus", "lsdyna_shift_note"]

SOLVER = "LS-DYNA"

_POLY = ("C10", "C01", "C11", "C20", "C02", "C30")  # MAT_077_H card order
_POLY_MODELS = ("neo_hooke", "mooney_rivlin", "yeoh", "polynomial2", "polynomial3",
                *(f"reduced_polynomial{n}" for n in range(1, 7)))
_OGDEN_MODELS = ("ogden", "ogden2", "ogden3", "ogden4", "ogden5", "ogden6")
SUPPORTED = (*_POLY_MODELS, *_OGDEN_MODELS)
#: Why the other built-in laws have no LS-DYNA card here
_WHY = {
    "arruda_boyce": "MAT_127 takes the number of chain links N = lambda_m^2 as a whole "
                    "number, so a fitted lambda_m cannot be written exactly",
    "gent": "no LS-DYNA material has Gent's energy",
    "van_der_waals": "no LS-DYNA material has the Van der Waals energy",
}
#: Largest relative error of the bulk modulus that LS-DYNA computes from the printed PR.
PR_RTOL = 1e-3
#: Optional viscoelastic cards read by each keyword (LS-DYNA manual, via PyDyna's docs).
MAX_PRONY = {"HYPERELASTIC_RUBBER": 6, "OGDEN_RUBBER": 12}


def _card(fields: list, width: int) -> str:
    """One fixed-width card; ``None`` leaves a field blank (LS-DYNA default)."""
    out = []
    for f in fields:
        if f is None:
            out.append(" " * width)
        elif isinstance(f, int):
            out.append(str(f).rjust(width))
        else:
            out.append(fixed_number(f, width))
    return "".join(out).rstrip()


def _names(width: int, names: list[str]) -> str:
    """The '$#' column-title comment above a card."""
    cells = [n.rjust(width) for n in names]
    return "$#" + "".join(cells)[2:]


def lsdyna_pr(K: float, G: float) -> float:
    """The PR from which LS-DYNA's K = 2 G (1 + PR) / (3 (1 − 2 PR)) gives ``K``.

    Parameters
    ----------
    K : float
        The intended bulk modulus, MPa.
    G : float
        The shear modulus LS-DYNA pairs with PR: the long-term μ0 of the card's constants.

    Returns
    -------
    float
        PR = (3K − 2G) / (6K + 2G).

    Examples
    --------
    >>> pr = lsdyna_pr(K=1000.0, G=1.0)
    >>> round(pr, 10), round(lsdyna_bulk_modulus(pr, G=1.0), 6)
    (0.4995001666, 1000.0)
    """
    return (3.0 * K - 2.0 * G) / (6.0 * K + 2.0 * G)


def lsdyna_bulk_modulus(pr: float, G: float) -> float:
    """LS-DYNA's bulk modulus K = 2 G (1 + PR) / (3 (1 − 2 PR)) of a PR (see :func:`lsdyna_pr`)."""
    return 2.0 * G * (1.0 + pr) / (3.0 * (1.0 - 2.0 * pr))


def _check_card(mat, mid, name) -> None:
    """Refuse what MAT_077_H/O cannot hold, one line each."""
    kind = mat.hyperelastic
    if kind not in SUPPORTED:
        raise unsupported(SOLVER, kind, SUPPORTED, _WHY.get(kind, ""))
    if kind in _POLY_MODELS:
        extra = {k: v for k, v in mat.constants.items() if k not in _POLY and v != 0.0}
        if extra:
            raise unsupported(
                SOLVER, kind, SUPPORTED,
                f"MAT_077_H holds only {', '.join(_POLY)}; this parameter set has {extra}",
            )
    if not (isinstance(mid, int) and 0 < mid < 10**8):
        raise ValueError(f"mid = {mid!r} must be a positive integer")
    if not name or len(name) > 80 or "\n" in name:
        raise ValueError(f"material title {name!r}: 1-80 characters on one line")
    keyword = "OGDEN_RUBBER" if kind in _OGDEN_MODELS else "HYPERELASTIC_RUBBER"
    if mat.n_prony > MAX_PRONY[keyword]:
        raise TooManyTerms(f"{SOLVER} *MAT_{keyword} reads at most {MAX_PRONY[keyword]} "
                           f"Prony terms; this model has {mat.n_prony}", MAX_PRONY[keyword])


def _pr_field(mat: Material, poisson, bulk_modulus, width: int) -> tuple[str, list[str]]:
    """The PR field as printed and the header lines that explain it.

    The printed PR must give back the intended K to :data:`PR_RTOL` (in double precision)
    and lie in
    [0, 0.5): LS-DYNA reads a negative PR as the flag of an extra card.
    """
    K = mat.bulk_modulus(poisson, bulk_modulus)
    if poisson is not None:
        why = f"from Poisson's ratio {poisson!r} of the instantaneous response"
    elif bulk_modulus is not None:
        why = "as given"
    else:
        K, why = mat.default_bulk_modulus(), f"{BULK_RATIO:g} x mu_inst, the default"
    G, mu_inst = mat.mu0, mat.mu_inst
    pr = lsdyna_pr(K, G)
    if pr < 0:
        raise ValueError(
            f"bulk modulus {K:.6g} MPa is below 2/3 of the long-term shear modulus "
            f"({G:.6g} MPa): LS-DYNA's PR would be negative ({pr:.4g}), which MAT_077 reads "
            "as a flag: give a larger bulk_modulus or poisson")
    text = fixed_number(pr, width).strip()
    pr_back = parse_number(text)
    if pr_back >= 0.5:
        raise ValueError(f"PR = {pr!r} (for K = {K:.6g} MPa) rounds to 0.5 in {width}-character "
                         "fields (infinite bulk modulus): use long_format=True or a smaller "
                         "bulk modulus")
    K_back = lsdyna_bulk_modulus(pr_back, G)
    rounding = []
    if not abs(K_back - K) <= PR_RTOL * K:
        msg = (f"PR = {pr!r} (for K = {K:.6g} MPa) needs more digits than {width}-character "
               f"fields hold: {text} gives K = {K_back:.6g} MPa; use long_format=True")
        rounding.append("WARNING: " + msg)
        warnings.warn(msg, stacklevel=3)
    pr32 = float(np.float32(pr_back))
    K32 = lsdyna_bulk_modulus(pr32, G) if pr32 < 0.5 else math.inf
    lines = [
        f"PR = {text}: LS-DYNA's K = 2 G (1+PR)/(3 (1-2 PR)) with G = long-term mu0 = "
        f"{G:.9g} MPa gives K = {K_back:.9g} MPa ({why}); instantaneous shear modulus "
        f"mu_inst = {mu_inst:.9g} MPa, K/mu_inst = {K_back / mu_inst:.6g}",
        *rounding,
    ]
    off = abs(K32 - K) / K
    if off > 0.01:
        lines.append(
            f"WARNING: a single-precision LS-DYNA stores PR as {pr32!r}, i.e. K = {K32:.4g} "
            f"MPa ({100 * off:.3g} % off): run double precision, or give a smaller bulk "
            "modulus")
    if K < 100.0 * mu_inst:
        msg = (f"PR = {text} gives K = {K / mu_inst:.3g} x the instantaneous shear "
               f"modulus: nearly compressible at high rates (g_inf = {mat.g_inf:.3g}); "
               f"the default bulk modulus is {BULK_RATIO:g} mu_inst")
        lines.append("WARNING: " + msg)
        warnings.warn(msg, stacklevel=3)
    return text, lines


def to_lsdyna(
    model,
    params=None,
    *,
    name: str = "VHFIT_MATERIAL",
    mid: int = 1,
    density: float | None = None,
    poisson: float | None = None,
    bulk_modulus: float | None = None,
    long_format: bool = True,
    notes: Sequence[str] = (),
    comments: Sequence[str] = (),
) -> str:
    """LS-DYNA keyword deck (``*KEYWORD`` ... ``*END``) of a calibrated model.

    Mooney-Rivlin, neo-Hooke, Yeoh and polynomial models go to
    ``*MAT_HYPERELASTIC_RUBBER`` (MAT_077_H), Ogden models to ``*MAT_OGDEN_RUBBER``
    (MAT_077_O); the Prony terms go on their optional GI, BETAI cards.

    Parameters
    ----------
    model : ViscoHyperelastic or results-like
        See :func:`vhfit.export.to_abaqus`.
    params : dict or array_like, optional
        The calibrated vhfit parameters.
    name : str
        Material title (``_TITLE`` option, at most 80 characters).
    mid : int
        Material id.
    density : float, optional
        RO in tonne/mm³; left blank (and flagged in a warning comment) when not given.
    poisson : float, optional
        Poisson's ratio of the instantaneous response, −1 < ν < 0.5: the bulk modulus is
        K = 2 μ_inst (1 + ν) / (3 (1 − 2ν)). This is not the PR field: LS-DYNA pairs PR
        with the long-term shear modulus, so the card's PR is the one giving this K.
    bulk_modulus : float, optional
        K in MPa instead of ``poisson``. With neither, K = 1000 μ_inst.
    notes : sequence of str, optional
        Warnings written at the head of the card's comments (``vhfit fit`` passes the
        calibration's headlines, e.g. a g∞ at its floor).
    comments : sequence of str, optional
        Further comment lines after the units (``vhfit fit`` says which fit the
        constants come from).
    long_format : bool
        20-character fields (keyword suffix ``+``, 13 significant digits) when True;
        the classic 10-character fields (4-6 significant digits) when False.

    Returns
    -------
    str
        The deck.

    Examples
    --------
    >>> import vhfit
    >>> from vhfit.export import to_lsdyna
    >>> m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    >>> deck = to_lsdyna(m, dict(C10=0.0, C01=5.0, G1=30.0, tau1=1e-4), density=1e-9,
    ...                  long_format=False)
    >>> print("\\n".join(l for l in deck.splitlines() if not l.startswith("$")))
    *KEYWORD
    *MAT_HYPERELASTIC_RUBBER_TITLE
    VHFIT_MATERIAL
             1    1.0e-9   0.49975         0
           0.0       5.0       0.0       0.0       0.0       0.0
          10.0     1.0e4
    *END
    """
    model, params = resolve(model, params, solver=RECORD)
    mat = Material.from_model(model, params)
    _check_card(mat, mid, name)
    check_compressibility(poisson, bulk_modulus, density)
    kind = mat.hyperelastic
    ogden = kind in _OGDEN_MODELS
    keyword = "OGDEN_RUBBER" if ogden else "HYPERELASTIC_RUBBER"
    w = 20 if long_format else 10
    pr_text, pr_lines = _pr_field(mat, poisson, bulk_modulus, w)
    conventions = [
        ("Ogden MAT_077_O: W = sum MU_p/ALPHA_p (l1b^a + l2b^a + l3b^a - 3); "
         "MU_p = 2 mu_p/alpha_p from vhfit's (Abaqus) mu_p")
        if ogden else
        "MAT_077_H: W = sum Cpq (I1b-3)^p (I2b-3)^q, C10 C01 C11 C20 C02 C30 = vhfit Cij",
        "Prony cards: GI = shear relaxation modulus = G_i/3 (vhfit G_i is uniaxial), "
        "BETAI = 1/tau_i (1/s); added to the long-term hyperelastic stress",
        *pr_lines,
        ("Long format: 20-character fields (keyword suffix +)" if long_format else
         "Standard 10-character fields: values rounded to 4-6 significant digits"),
    ]
    if density is None:
        notes = [*notes, no_density_note(SOLVER, "RO")]
    lines = ["*KEYWORD"]
    lines += header("$", solver=SOLVER, mat=mat, conventions=conventions, width=80, notes=notes,
                    comments=comments, moduli="LONG-TERM (LS-DYNA adds the Prony stress to them)")
    lines.append(f"*MAT_{keyword}_TITLE" + ("+" if long_format else ""))
    lines.append(name)
    lines.append(_names(w, ["mid", "ro", "pr", "n", "nv", "g", "sigf", "ref"]))
    lines.append(_card([mid, density, None, 0], w))
    lines[-1] = lines[-1][:2 * w] + pr_text.rjust(w) + lines[-1][3 * w:]
    c = mat.constants
    if ogden:
        n = int(kind[-1]) if kind[-1].isdigit() else 1
        mus, alphas = [], []
        for p in range(1, n + 1):
            mu, alpha = c[f"mu{p}"], c[f"alpha{p}"]
            if alpha == 0.0:
                raise ValueError(f"alpha{p} = 0: an Ogden exponent must be nonzero")
            mus.append(2.0 * mu / alpha)
            alphas.append(alpha)
        lines.append(_names(w, [f"mu{p}" for p in range(1, 9)]))
        lines.append(_card(mus, w))
        lines.append(_names(w, [f"alpha{p}" for p in range(1, 9)]))
        lines.append(_card(alphas, w))
    else:
        lines.append(_names(w, [k.lower() for k in _POLY] + ["therml"]))
        lines.append(_card([c.get(k, 0.0) for k in _POLY], w))
    if mat.n_prony:
        lines.append(_names(w, ["gi", "betai"]))
        for i in range(1, mat.n_prony + 1):
            lines.append(_card([params[f"G{i}"] / 3.0, 1.0 / params[f"tau{i}"]], w))
    lines.append("*END")
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------------- parsing
_KEY = re.compile(
    r"^\*MAT_(HYPERELASTIC_RUBBER|077_H|OGDEN_RUBBER|077_O)(_TITLE)?\s*([+\-%]?)\s*$",
    re.IGNORECASE,
)


def _fields(line: str, width: int) -> list[str]:
    if "," in line:  # LS-DYNA also reads comma-separated (free) format
        return [t.strip() for t in line.split(",")]
    return [line[i:i + width] for i in range(0, max(len(line), 8 * width), width)][:8]


def _infer_poly(constants: dict[str, float], hint: str | None) -> str:
    """The smallest built-in model holding the nonzero MAT_077_H constants."""
    nonzero = {k for k, v in constants.items() if v != 0.0}
    order = list(_POLY_MODELS)
    if hint in order:
        order.remove(hint)
        order.insert(0, hint)
    for kind in order:
        h = _hyper.get(kind)
        if not nonzero <= set(h.param_names):
            continue
        try:
            h.check([constants.get(n, 0.0) for n in h.param_names])
        except ValueError:
            continue
        return kind
    raise unsupported(SOLVER, f"MAT_077_H with {sorted(nonzero)}", SUPPORTED)


def from_lsdyna(text: str, *, mid: int | None = None) -> tuple[ViscoHyperelastic, dict]:
    """Read a MAT_077_H / MAT_077_O card back into vhfit.

    The card must give the constants directly (N = 0). For MAT_077_H the model name
    is taken from a ``$ vhfit model: <name>`` comment when it fits the constants,
    else the simplest built-in model holding the nonzero constants is used (the
    stress is the same either way).

    Parameters
    ----------
    text : str
        Keyword text, standard (10), long (20, ``LONG=Y`` or ``+`` suffix) or
        comma-separated fields.
    mid : int, optional
        Which material to read (default: the first MAT_077_H/O).

    Returns
    -------
    model : ViscoHyperelastic
    params : dict

    Examples
    --------
    >>> from vhfit.export import from_lsdyna
    >>> deck = '''*MAT_HYPERELASTIC_RUBBER
    ... 1,1e-9,0.4995,0
    ... 0.0,5.0
    ... 10.0,1e4
    ... '''
    >>> m, p = from_lsdyna(deck)
    >>> m.hyperelastic.name, p["G1"], p["tau1"]
    ('mooney_rivlin', 30.0, 0.0001)
    """
    lines = text.splitlines()
    long_global = any(
        re.match(r"^\*KEYWORD\b.*\bLONG\s*=\s*Y", ln.strip(), re.IGNORECASE) for ln in lines
    )
    m_hint = re.search(r"vhfit model:\s*([A-Za-z0-9_]+)", text)
    hint = m_hint.group(1) if m_hint else None
    k = 0
    while k < len(lines):
        m = _KEY.match(lines[k].strip())
        k += 1
        if not m:
            continue
        width = {"+": 20, "-": 10, "%": 10}.get(m.group(3), 20 if long_global else 10)
        ogden = m.group(1).upper() in ("OGDEN_RUBBER", "077_O")
        data = []
        while k < len(lines) and not lines[k].lstrip().startswith("*"):
            if not lines[k].lstrip().startswith("$"):
                data.append(lines[k].rstrip("\n"))
            k += 1
        if m.group(2):
            data = data[1:]  # title
        cards = [_fields(d, width) for d in data if d.strip()]
        if not cards:
            raise ValueError(f"{SOLVER} *MAT_{m.group(1)} has no data cards")
        head = [parse_number(f) for f in cards[0][:8]] + [0.0] * 8
        if mid is not None and int(head[0]) != mid:
            continue
        return _read(cards, head, ogden, hint)
    raise ValueError(
        "no *MAT_HYPERELASTIC_RUBBER / *MAT_OGDEN_RUBBER (MAT_077_H/O) "
        + (f"with MID {mid} " if mid is not None else "") + "in the LS-DYNA text"
    )


def _read(cards, head, ogden: bool, hint: str | None):
    pr, n = head[2], int(head[3])
    if n != 0:
        raise ValueError(f"{SOLVER} card has N = {n}: LS-DYNA fits the constants from test "
                         "curves; only N = 0 (constants given) can be read")
    rest = cards[1:]
    if pr < 0:
        rest = rest[1:]  # the extra (hysteresis / Mullins) card
    if ogden:
        if len(rest) < 2:
            raise ValueError(f"{SOLVER} MAT_077_O: missing the MU and ALPHA cards")
        mus = [parse_number(f) for f in rest[0][:8]]
        alphas = [parse_number(f) for f in rest[1][:8]]
        pairs = [(mu, a) for mu, a in zip(mus, alphas) if mu != 0.0 or a != 0.0]
        if not 1 <= len(pairs) <= len(_OGDEN_MODELS):
            raise unsupported(SOLVER, f"Ogden with {len(pairs)} terms", SUPPORTED,
                              f"vhfit has Ogden with 1 to {len(_OGDEN_MODELS)} terms")
        kind = _OGDEN_MODELS[len(pairs) - 1]
        constants = {}
        for p, (mu_d, alpha) in enumerate(pairs, start=1):
            if alpha == 0.0:
                raise ValueError(f"{SOLVER} MAT_077_O: ALPHA{p} = 0 with MU{p} = {mu_d:g}")
            constants[f"mu{p}"] = mu_d * alpha / 2.0
            constants[f"alpha{p}"] = alpha
        visco = rest[2:]
    else:
        if not rest:
            raise ValueError(f"{SOLVER} MAT_077_H: missing the C10 ... C30 card")
        row = rest[0] + [""] * 8
        if parse_number(row[6]) > 0:
            raise ValueError(f"{SOLVER} MAT_077_H: THERML > 0 (temperature curves) "
                             "cannot be read")
        constants = {name: parse_number(f) for name, f in zip(_POLY, row[:6])}
        kind = _infer_poly(constants, hint)
        visco = rest[1:]
    G, tau = [], []
    for row in visco:
        row = row + [""] * 2
        gi, beta = parse_number(row[0]), parse_number(row[1])
        if gi == 0.0 and beta == 0.0:
            continue
        if not beta > 0:
            raise ValueError(f"{SOLVER} Prony card GI = {gi:g}, BETAI = {beta:g}: "
                             "the decay constant must be > 0")
        G.append(3.0 * gi)
        tau.append(1.0 / beta)
    return Material.params_from_moduli(kind, constants, G, tau, solver=SOLVER)


# ------------------------------------------------------------------- shift, record
def lsdyna_shift_note(law) -> list[str]:
    """LS-DYNA comment lines: the card has no shift; the law to apply by hand.

    ``*MAT_HYPERELASTIC_RUBBER`` and ``*MAT_OGDEN_RUBBER`` have no temperature shift; the
    comment lines give the law, so that an analysis away from T_ref can scale
    BETAI = 1/τ_i by 1/a_T itself.

    Examples
    --------
    >>> from vhfit.tts import WLF
    >>> print(lsdyna_shift_note(WLF(C1=17.44, C2=51.6, T_ref=20.0))[0])
    $ NOTE: no time-temperature shift written: this card has no shift field.
    """
    T_ref, c1, c2 = wlf_constants(law)
    return [
        "$ NOTE: no time-temperature shift written: this card has no shift field.",
        f"$   The Prony terms are at T_ref = {T_ref:g}; at temperature T use",
        f"$   BETAI(T) = BETAI / a_T, log10 a_T = -{c1:g} (T - {T_ref:g}) / ({c2:g} + T - "
        f"{T_ref:g}) (WLF)",
    ]


def _add_shift_note(card: str, law, mat: int = 1) -> str:
    """The note of :func:`lsdyna_shift_note` before ``*END``."""
    lines = card.rstrip("\n").split("\n")
    upper = [ln.strip().upper() for ln in lines]
    end = upper.index("*END") if "*END" in upper else len(lines)
    return "\n".join(lines[:end] + lsdyna_shift_note(law) + lines[end:]) + "\n"


#: Where its cards come in the list of the registered solvers (vhfit.export finds the
#: solver modules and registers their records in this order).
ORDER = 2

#: The solver record (registered by vhfit.export).
RECORD = Solver(
    name="lsdyna", label=SOLVER, suffix=".k", formulation="lsdyna",
    write=to_lsdyna, read=from_lsdyna, sniff=lambda body: "*MAT_" in body,
    laws=SUPPORTED, comment="$", aliases=("ls-dyna", "dyna"), shift=_add_shift_note,
    density=True, bulk_modulus=True,
    no_networks=("its Bergstrom-Boyce material (*MAT_BERGSTROM_BOYCE_RUBBER) "
                 "has no publicly documented flow equation and field numbering that vhfit "
                 "could verify a card against"))
