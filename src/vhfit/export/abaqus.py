"""Abaqus cards: ``*HYPERELASTIC`` + ``*VISCOELASTIC, TIME=PRONY``.

Conventions (see docs/export.md for the sources):

* ``*HYPERELASTIC, <model>, MODULI=LONG TERM`` takes the long-term constants, which
  is what vhfit calibrates; ``MODULI=INSTANTANEOUS`` takes long-term / g∞ (the
  stress-like constants: Cij, μ_p, μ; α, λm, a, β unchanged). The Cij are the Abaqus
  polynomial constants, W = Σ Cij (Ī1 − 3)^i (Ī2 − 3)^j (``REDUCED POLYNOMIAL, N``:
  Ci0 only, N ≤ 6); Ogden μ_p, α_p are Abaqus's, W = Σ 2μ_p/α_p² (λ̄1^α_p + λ̄2^α_p +
  λ̄3^α_p − 3), N ≤ 6; ``ARRUDA-BOYCE`` takes μ, λm and ``VAN DER WAALS`` μ, λm, a, β
  in the forms of docs/theory.md §2. All are vhfit's own conventions, so the constants
  go over unchanged. Abaqus has no Gent law.
* Data lines: the constants, then D1..DN (0 = incompressible, Abaqus/Standard with
  hybrid elements), at most 8 values a line.
* ``*VISCOELASTIC, TIME=PRONY`` data lines ``g_i, k_i, tau_i`` with g_i = G_i / G0 the
  dimensionless shear relaxation modulus (docs/theory.md §3) and k_i = 0 (no bulk relaxation).
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from vhfit import hyperelastic as _hyper
from vhfit.export._common import (
    BULK_RATIO,
    UNITS,
    Material,
    check_compressibility,
    comment_block,
    free_number,
    generator,
    header,
    is_network_model,
    model_hint,
    no_density_note,
    parse_number,
    resolve,
    unsupported,
)
from vhfit.export._solvers import Solver
from vhfit.export.shift import wlf_constants, wlf_number
from vhfit.model import ViscoHyperelastic
from vhfit.modes import get_deformation, registered_deformations

if TYPE_CHECKING:  # the network physics is imported by the functions that use it
    from vhfit.viscous import NetworkModel

__all__ = ["to_abaqus", "from_abaqus", "to_abaqus_test_data", "abaqus_trs"]

SOLVER = "Abaqus"

def _ogden_order(n: int) -> tuple[str, ...]:
    return tuple(x for p in range(1, n + 1) for x in (f"mu{p}", f"alpha{p}"))


#: vhfit model -> (*HYPERELASTIC parameters, constant order on the data line, number of D)
_CARDS = {
    "mooney_rivlin": ("MOONEY-RIVLIN", ("C10", "C01"), 1),
    "neo_hooke": ("NEO HOOKE", ("C10",), 1),
    "yeoh": ("YEOH", ("C10", "C20", "C30"), 3),
    "polynomial2": ("POLYNOMIAL, N=2", ("C10", "C01", "C20", "C11", "C02"), 2),
    "polynomial3": (
        "POLYNOMIAL, N=3",
        ("C10", "C01", "C20", "C11", "C02", "C30", "C21", "C12", "C03"),
        3,
    ),
    **{name: (f"OGDEN, N={n}", _ogden_order(n), n)
       for n, name in enumerate(("ogden", "ogden2", "ogden3", "ogden4", "ogden5", "ogden6"), 1)},
    **{f"reduced_polynomial{n}": (f"REDUCED POLYNOMIAL, N={n}",
                                  tuple(f"C{i}0" for i in range(1, n + 1)), n)
       for n in range(1, 7)},
    # data line mu, lambda_m, D (Abaqus Keywords Reference, *HYPERELASTIC)
    "arruda_boyce": ("ARRUDA-BOYCE", ("mu", "lambda_m"), 1),
    # data line mu, lambda_m, a, beta, D
    "van_der_waals": ("VAN DER WAALS", ("mu", "lambda_m", "a", "beta"), 1),
}

_MODULI = {"long_term": "LONG TERM", "instantaneous": "INSTANTANEOUS"}


def _check_name(name: str) -> None:
    """``*MATERIAL, NAME=``: 1-80 characters, no commas, '*' or newlines."""
    if not name or re.search(r"[,\n\r*]", name) or len(name) > 80:
        raise ValueError(f"material name {name!r}: 1-80 characters, no commas, '*' or newlines")


def _lines_of(values: list[str], per_line: int = 8) -> list[str]:
    """Data lines of at most ``per_line`` values; a continued line ends with a comma."""
    chunks = [values[i:i + per_line] for i in range(0, len(values), per_line)]
    return [", ".join(c) + ("," if k < len(chunks) - 1 else "") for k, c in enumerate(chunks)]


def to_abaqus(
    model,
    params=None,
    *,
    name: str = "VHFIT_MATERIAL",
    moduli: str = "long_term",
    density: float | None = None,
    poisson: float | None = None,
    bulk_modulus: float | None = None,
    explicit: bool = False,
    notes: Sequence[str] = (),
    comments: Sequence[str] = (),
) -> str:
    """Abaqus ``*MATERIAL`` block of a calibrated visco-hyperelastic model.

    Parameters
    ----------
    model : ViscoHyperelastic or results-like
        The model; or an object with ``.model`` and ``.params``, or a mapping with
        ``"params"`` and ``"model"``/``"hyperelastic"`` (then omit ``params``).
    params : dict or array_like, optional
        The calibrated parameters (vhfit convention: long-term hyperelastic constants,
        uniaxial Prony moduli G_i in MPa, τ_i in s).
    name : str
        Material name (``*MATERIAL, NAME=``).
    moduli : {"long_term", "instantaneous"}
        Which hyperelastic constants the card carries (``MODULI=LONG TERM`` is exact
        and preferred; ``INSTANTANEOUS`` writes long-term / g∞).
    density : float, optional
        Mass density in tonne/mm³ (``*DENSITY``; Abaqus/Explicit and dynamic steps need
        one). Without it the card's head says so.
    poisson : float, optional
        Poisson's ratio of the instantaneous response, −1 < ν < 0.5, for a compressible
        D1 = 2/K (see :meth:`Material.bulk_modulus`).
    bulk_modulus : float, optional
        The bulk modulus K in MPa instead of ``poisson``. With neither, D1 = 0
        (incompressible: Abaqus/Standard with hybrid elements only) — or, with
        ``explicit``, K = 1000 μ_inst.
    explicit : bool
        Write the Abaqus/Explicit variant: D1 is never 0 (Abaqus/Explicit cannot impose
        incompressibility, and without D1 it assumes K0/μ0 = 20).
    notes : sequence of str, optional
        Warnings written at the head of the card's comments (``vhfit fit`` passes the
        calibration's headlines, e.g. a g∞ at its floor).
    comments : sequence of str, optional
        Further comment lines after the units (``vhfit fit`` says which fit the
        constants come from).

    Returns
    -------
    str
        The card, comment lines first.

    Examples
    --------
    >>> import vhfit
    >>> from vhfit.export import to_abaqus
    >>> m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    >>> card = to_abaqus(m, dict(C10=0.0, C01=5.0, G1=30.0, tau1=1e-4))
    >>> print("\\n".join(line for line in card.splitlines() if not line.startswith("**")))
    *MATERIAL, NAME=VHFIT_MATERIAL
    *HYPERELASTIC, MOONEY-RIVLIN, MODULI=LONG TERM
    0.0, 5.0, 0.0
    *VISCOELASTIC, TIME=PRONY
    0.5, 0.0, 0.0001
    """
    if is_network_model(model):
        return _network_card(model, name=name, density=density, poisson=poisson,
                             bulk_modulus=bulk_modulus, explicit=explicit, notes=notes,
                             comments=comments)
    model, params = resolve(model, params)
    mat = Material.from_model(model, params)
    if mat.hyperelastic not in _CARDS:
        raise unsupported(SOLVER, mat.hyperelastic, list(_CARDS))
    if moduli not in _MODULI:
        raise ValueError(f"moduli = {moduli!r}; choose 'long_term' or 'instantaneous'")
    _check_name(name)
    check_compressibility(poisson, bulk_modulus, density)
    visco = mat.n_prony > 0
    inst = visco and moduli == "instantaneous"
    constants = mat.scaled(1.0 / mat.g_inf) if inst else mat.constants
    K = _bulk(mat, poisson, bulk_modulus, explicit)

    if not visco:
        which = "long-term = instantaneous (no Prony terms; MODULI not written)"
    elif inst:
        which = "INSTANTANEOUS (MODULI=INSTANTANEOUS): vhfit long-term constants / g_inf"
    else:
        which = "LONG-TERM (MODULI=LONG TERM), exactly vhfit's calibrated constants"
    conventions = [
        "Conventions: W = sum Cij (I1b-3)^i (I2b-3)^j; Ogden W = sum 2 mu_p/alpha_p^2 "
        "(l1b^a_p + l2b^a_p + l3b^a_p - 3) (Abaqus forms = vhfit forms, copied unchanged)",
        "*VISCOELASTIC, TIME=PRONY lines: g_i, k_i, tau_i with g_i = G_i/G0, "
        "G0 = E_inf + sum G_i, k_i = 0 (no bulk relaxation), tau_i in s",
        _compressibility(mat, K, poisson, bulk_modulus, explicit),
    ]
    if density is None:
        notes = [*notes, no_density_note(SOLVER, "*DENSITY")]
    target = "Abaqus/Explicit" if explicit else "Abaqus/Standard"
    lines = header("**", solver=target, notes=notes, comments=comments, mat=mat, moduli=which,
                   conventions=conventions)
    lines.append(f"*MATERIAL, NAME={name}")
    if density is not None:
        lines += ["*DENSITY", f"{free_number(density)},"]
    lines += _hyperelastic(mat.hyperelastic, constants, K, _MODULI[moduli] if visco else None)
    if visco:
        lines.append("*VISCOELASTIC, TIME=PRONY")
        lines += [f"{free_number(g)}, 0.0, {free_number(t)}" for g, t in zip(mat.g, mat.tau)]
    return "\n".join(lines) + "\n"


def _bulk(mat: Material, poisson, bulk_modulus, explicit: bool) -> float | None:
    """The card's bulk modulus (None: incompressible, D1 = 0); the Explicit variant's
    default when neither ν nor K is given."""
    K = mat.bulk_modulus(poisson, bulk_modulus)
    return mat.default_bulk_modulus() if K is None and explicit else K


def _hyperelastic(law: str, constants: dict[str, float], K: float | None,
                  moduli: str | None) -> list[str]:
    """The ``*HYPERELASTIC`` keyword line (``MODULI=`` when given) and its data lines: the
    constants in Abaqus's order, then D1 = 2/K (0: incompressible) and the other D's 0."""
    kind, order, n_d = _CARDS[law]
    d1 = 0.0 if K is None else 2.0 / K
    values = [free_number(constants[k]) for k in order]
    values += [free_number(d1)] + [free_number(0.0)] * (n_d - 1)
    return [f"*HYPERELASTIC, {kind}" + (f", MODULI={moduli}" if moduli else ""),
            *_lines_of(values)]


#: The comment every network card carries: when Abaqus lets the networks flow.
NO_CREEP_IN_STATIC = ("The networks (*VISCOELASTIC, NONLINEAR) creep only in *VISCO steps "
                      "and dynamic steps, never in *STATIC: a *STATIC step gives the "
                      "instantaneous (elastic) response")


def _abaqus_law(flow) -> str:
    """The LAW= word of a registered flow (its record's ``abaqus``), or a one-line refusal."""
    if not flow.abaqus:
        raise ValueError(f"{SOLVER} export: the flow {flow.name!r} has no Abaqus LAW (its "
                         "record's abaqus is None): register it with abaqus='WORD', or "
                         "use a built-in flow")
    return flow.abaqus


def _network_card(model, *, name: str, density: float | None, poisson: float | None,
                  bulk_modulus: float | None, explicit: bool, notes: Sequence[str],
                  comments: Sequence[str]) -> str:
    """The ``*MATERIAL`` block of a network model (Abaqus's parallel rheological framework).

    ``*HYPERELASTIC, <law>, MODULI=INSTANTANEOUS`` with the model's instantaneous
    constants, then one ``*VISCOELASTIC, NONLINEAR, NETWORKID=k, SRATIO=s_k, LAW=...``
    block per network, its data line in the flow record's order (``Flow.param_names``).
    """
    from vhfit.viscous import flows

    if model.law not in _CARDS:
        raise unsupported(SOLVER, model.law, list(_CARDS))
    _check_name(name)
    check_compressibility(poisson, bulk_modulus, density)
    law_names = _hyper.get(model.law).param_names
    constants = {k: float(v) for k, v in zip(law_names, model.law_params)}
    # the instantaneous constants as a law without Prony terms: its moduli are the
    # instantaneous ones, which fix a bulk modulus from a Poisson's ratio
    mat = Material(model.law, constants)
    K = _bulk(mat, poisson, bulk_modulus, explicit)
    records = [(k, net, flows.get(net.flow)) for k, net in enumerate(model.networks, 1)]
    laws = [_abaqus_law(flow) for _, _, flow in records]
    target = "Abaqus/Explicit" if explicit else "Abaqus/Standard"
    if density is None:
        notes = [*notes, no_density_note(SOLVER, "*DENSITY")]
    text = [
        f"Generated by {generator()}: nonlinear visco-hyperelastic material (parallel "
        f"rheological framework) for {target}",
        *(f"WARNING: {n}" for n in notes),
        f"vhfit model: {model.describe()}",
        f"Units: {UNITS}",
        *comments,
        "Conventions: *HYPERELASTIC, MODULI=INSTANTANEOUS holds the instantaneous constants "
        "(Abaqus forms = vhfit forms, copied unchanged); the equilibrium network carries "
        "(1 - sum SRATIO_k) W(F), network k carries SRATIO_k W(F_e,k), F = F_e,k F_cr,k",
        "Each network's creep strain rate is driven by the Mises equivalent of its deviatoric "
        "Kirchhoff stress (MPa), time in s",
        *(f"Network {k}: flow {flow.name} (LAW={word}), data line "
          f"{', '.join(flow.param_names)} = {', '.join(f'{c:.9g}' for c in net.constants)}, "
          f"SRATIO = {net.ratio:.9g}"
          for (k, net, flow), word in zip(records, laws)),
        _compressibility(mat, K, poisson, bulk_modulus, explicit),
        NO_CREEP_IN_STATIC,
    ]
    lines = comment_block("**", text)
    lines.append(f"*MATERIAL, NAME={name}")
    if density is not None:
        lines += ["*DENSITY", f"{free_number(density)},"]
    lines += _hyperelastic(model.law, constants, K, _MODULI["instantaneous"])
    for (k, net, _), word in zip(records, laws):
        lines.append(f"*VISCOELASTIC, NONLINEAR, NETWORKID={k}, "
                     f"SRATIO={free_number(net.ratio)}, LAW={word}")
        lines += _lines_of([free_number(c) for c in net.constants])
    return "\n".join(lines) + "\n"


def _compressibility(mat: Material, K: float | None, poisson, bulk_modulus,
                     explicit: bool) -> str:
    """The header line saying where D1 comes from."""
    if K is None:
        return ("D1 = 0: incompressible, for Abaqus/Standard with hybrid elements ONLY; "
                "Abaqus/Explicit refuses it (without D1 it assumes K0/mu0 = 20): write the "
                "Explicit variant (explicit=True, vhfit fit --abaqus-explicit)")
    if poisson is not None:
        why = f"from Poisson's ratio {poisson!r} and the instantaneous shear modulus"
    elif bulk_modulus is not None:
        why = "as given"
    else:
        why = f"= {BULK_RATIO:g} x the instantaneous shear modulus (default)"
    return (f"D1 = 2/K0 with K0 = {K:.9g} MPa {why} (mu_inst = {mat.mu_inst:.6g} MPa, "
            f"K0/mu_inst = {K / mat.mu_inst:.6g})"
            + ("; Abaqus/Explicit variant" if explicit else ""))


# ------------------------------------------------------------------------- parsing
def _blocks(text: str) -> list[tuple[str, dict[str, str], list[list[str]]]]:
    """(keyword, parameters, data lines as token lists) for every keyword in ``text``."""
    out: list[tuple[str, dict[str, str], list[list[str]]]] = []
    for raw in text.splitlines():
        line = raw.strip()
        if not line or line.startswith("**"):
            continue
        if line.startswith("*"):
            parts = [p.strip() for p in line[1:].split(",")]
            params: dict[str, str] = {}
            for p in parts[1:]:
                if not p:
                    continue
                k, _, v = p.partition("=")
                params[re.sub(r"\s+", " ", k.strip().upper())] = v.strip()
            out.append((re.sub(r"\s+", " ", parts[0].upper()), params, []))
        elif out:
            out[-1][2].append([t.strip() for t in line.rstrip(",").split(",")])
    return out


def _hyper_kind(params: dict[str, str]) -> tuple[str, int]:
    """The vhfit model named by *HYPERELASTIC parameters, and the number of D values."""
    n = int(params.get("N", "1"))
    fixed = {"MOONEY-RIVLIN": "mooney_rivlin", "NEO HOOKE": "neo_hooke", "YEOH": "yeoh",
             "ARRUDA-BOYCE": "arruda_boyce", "VAN DER WAALS": "van_der_waals"}
    for key, kind in fixed.items():
        if key in params:
            return kind, _CARDS[kind][2]
    family = {
        "OGDEN": ("ogden", "ogden2", "ogden3", "ogden4", "ogden5", "ogden6"),
        "REDUCED POLYNOMIAL": ("neo_hooke", "reduced_polynomial2", "yeoh",
                               "reduced_polynomial4", "reduced_polynomial5",
                               "reduced_polynomial6"),
    }
    for key, kinds in family.items():
        if key in params:
            if 1 <= n <= len(kinds):
                return kinds[n - 1], n
            raise unsupported(SOLVER, f"{key}, N={n}", list(_CARDS), "Abaqus allows N <= 6")
    named = [k for k in params if k not in ("N", "MODULI", "POISSON")]
    if named and named != ["POLYNOMIAL"]:
        raise unsupported(SOLVER, ", ".join(named), list(_CARDS))
    if n in (1, 2, 3):  # POLYNOMIAL (the default)
        return ("mooney_rivlin", "polynomial2", "polynomial3")[n - 1], n
    raise unsupported(SOLVER, f"POLYNOMIAL, N={n}", list(_CARDS))


def from_abaqus(text: str, *, name: str | None = None
                ) -> tuple[ViscoHyperelastic | NetworkModel, dict[str, float]]:
    """Read a card written by :func:`to_abaqus` (or by hand) back into vhfit.

    A material with ``*VISCOELASTIC, TIME=PRONY`` (or none) reads as a Prony model; one
    with ``*VISCOELASTIC, NONLINEAR`` networks (Abaqus's parallel rheological framework,
    beside ``*HYPERELASTIC, ..., MODULI=INSTANTANEOUS``) as a network model
    (:class:`vhfit.viscous.NetworkModel`): each block's ``LAW=`` names a registered flow
    (:func:`vhfit.viscous.flows.get`, Abaqus's spellings accepted), its data line its
    constants in the flow record's order. What cannot be read is refused in one line.

    Parameters
    ----------
    text : str
        Abaqus input text holding ``*MATERIAL``, ``*HYPERELASTIC`` (constants given
        directly, no temperature dependence) and optionally ``*VISCOELASTIC,
        TIME=PRONY`` or ``*VISCOELASTIC, NONLINEAR`` blocks.
    name : str, optional
        Which ``*MATERIAL`` to read (default: the first one).

    Returns
    -------
    model : ViscoHyperelastic or NetworkModel
    params : dict
        vhfit parameters (long-term constants, uniaxial G_i, τ_i); for a network model
        its constants by name (the law's, then ``networkK_sratio`` and ``networkK_<name>``
        of each flow constant), for display: the model holds them all.

    Examples
    --------
    >>> from vhfit.export import from_abaqus
    >>> card = '''*MATERIAL, NAME=GEL
    ... *HYPERELASTIC, MOONEY-RIVLIN, MODULI=LONG TERM
    ... 0.0, 5.0, 0.0
    ... *VISCOELASTIC, TIME=PRONY
    ... 0.5, 0.0, 1e-4
    ... '''
    >>> m, p = from_abaqus(card)
    >>> m.param_names, p["G1"]
    (['C10', 'C01', 'G1', 'tau1'], 30.0)
    """
    blocks = _material(_blocks(text), name)
    kind, constants, moduli = _read_hyperelastic(blocks, text)
    visco = [b for b in blocks if b[0] == "VISCOELASTIC"]
    if any("NONLINEAR" in vp for _, vp, _ in visco):
        return _read_networks(kind, constants, moduli, visco)
    g, tau = [], []
    if visco:
        _, vp, vdata = visco[0]
        if vp.get("TIME", "").upper() != "PRONY":
            raise ValueError(f"*VISCOELASTIC {vp}: only TIME=PRONY or NONLINEAR can be read")
        for row in vdata:
            gi, ki, ti = (parse_number(row[j]) if j < len(row) else 0.0 for j in range(3))
            if ki != 0.0:
                warnings.warn(f"*VISCOELASTIC k_i = {ki:g} ignored: vhfit's model is "
                              "incompressible (no bulk relaxation)", stacklevel=2)
            g.append(gi)
            tau.append(ti)
    mat = Material.from_card(kind, constants, g, tau, solver=SOLVER,
                             instantaneous=moduli == "INSTANTANEOUS" and bool(g))
    return mat.to_params()


def _material(blocks: list, name: str | None) -> list:
    """The blocks of the ``*MATERIAL`` named ``name`` (the first one when None; all the
    blocks when the text has no ``*MATERIAL``)."""
    starts = [i for i, b in enumerate(blocks) if b[0] == "MATERIAL"]
    if not starts:
        return blocks
    for k, i in enumerate(starts):
        if name is None or blocks[i][1].get("NAME", "").upper() == name.upper():
            end = starts[k + 1] if k + 1 < len(starts) else len(blocks)
            return blocks[i + 1:end]
    raise ValueError(f"no *MATERIAL, NAME={name} in the Abaqus text")


def _read_hyperelastic(blocks: list, text: str) -> tuple[str, dict[str, float], str]:
    """The law, constants (as written) and ``MODULI`` (upper case; Abaqus's default LONG
    TERM when not given) of the material's ``*HYPERELASTIC``."""
    hyper = [b for b in blocks if b[0] == "HYPERELASTIC"]
    if not hyper:
        raise ValueError("no *HYPERELASTIC keyword in the Abaqus text")
    _, hp, hdata = hyper[0]
    if "TEST DATA INPUT" in hp or "MARLOW" in hp or "USER" in hp:
        raise ValueError("*HYPERELASTIC with test data, MARLOW or USER cannot be read: "
                         "give the constants on the data lines")
    kind, n_d = _hyper_kind(hp)
    kind = model_hint(text, kind)  # e.g. reduced_polynomial3 written as REDUCED POLYNOMIAL, N=3
    order = list(_CARDS[kind][1])
    need = len(order) + n_d + 1  # constants, D's, temperature
    per_record = -(-need // 8)
    if len(hdata) > per_record:
        raise ValueError("temperature-dependent *HYPERELASTIC data is not supported "
                         f"(found {len(hdata)} data lines, one record is {per_record})")
    tokens = [t for line in hdata for t in line]
    if len(tokens) < len(order):
        raise ValueError(f"*HYPERELASTIC {kind}: expected {len(order)} constants "
                         f"{order}, found {len(tokens)} values")
    constants = {k: parse_number(tok) for k, tok in zip(order, tokens)}
    moduli = re.sub(r"\s+", " ", hp.get("MODULI", "LONG TERM").upper())
    if moduli not in ("LONG TERM", "INSTANTANEOUS"):
        raise ValueError(f"*HYPERELASTIC MODULI={moduli}: expected LONG TERM or INSTANTANEOUS")
    return kind, constants, moduli


def _flow_of(law: str, network: int):
    """The registered flow a ``LAW=`` word names (:func:`vhfit.viscous.flows.get` knows
    Abaqus's spellings and each flow's own ``abaqus`` word), or a one-line refusal."""
    from vhfit.viscous import flows

    try:
        return flows.get(law)
    except ValueError:
        where = f"*VISCOELASTIC, NONLINEAR, NETWORKID={network}: LAW={law}"
        if law == "USER":
            raise ValueError(f"{where} (a user subroutine) names no registered flow: register "
                             "one with vhfit.viscous.flows.register(..., abaqus='USER') to "
                             "read it") from None
        raise ValueError(f"{where} names no registered flow (known: "
                         f"{', '.join(flows.available())})") from None


def _read_networks(kind: str, constants: dict[str, float], moduli: str, visco: list
                   ) -> tuple[NetworkModel, dict[str, float]]:
    """A network model from ``*HYPERELASTIC, ..., MODULI=INSTANTANEOUS`` and the material's
    ``*VISCOELASTIC, NONLINEAR`` blocks (see :func:`from_abaqus`)."""
    from vhfit.viscous import Network, NetworkModel

    if moduli != "INSTANTANEOUS":
        raise ValueError(f"*HYPERELASTIC MODULI={moduli} with *VISCOELASTIC, NONLINEAR: the "
                         "parallel rheological framework takes the instantaneous moduli: "
                         "write MODULI=INSTANTANEOUS (LONG TERM is Abaqus's default)")
    if any("NONLINEAR" not in vp for _, vp, _ in visco):
        raise ValueError("*VISCOELASTIC, TIME=PRONY beside *VISCOELASTIC, NONLINEAR networks "
                         "cannot be read: a material is a Prony model or a network model")
    found: dict[int, Network] = {}
    for _, vp, rows in visco:
        where = "*VISCOELASTIC, NONLINEAR"
        unread = sorted(set(vp) - {"NONLINEAR", "NETWORKID", "SRATIO", "LAW"})
        if unread:
            raise ValueError(f"{where}: {', '.join(unread)} cannot be read (temperature or "
                             "field dependence): give one data line of constants")
        missing = [p for p in ("NETWORKID", "SRATIO", "LAW") if not vp.get(p, "").strip()]
        if missing:
            raise ValueError(f"{where}: {'= and '.join(missing)}= missing (each network needs "
                             "NETWORKID=k, SRATIO=s_k and its flow, e.g. LAW=STRAIN)")
        try:
            k = int(vp["NETWORKID"])
            ratio = parse_number(vp["SRATIO"])
        except ValueError:
            raise ValueError(f"{where}: NETWORKID={vp['NETWORKID']}, SRATIO={vp['SRATIO']}: "
                             "give a whole number and a number") from None
        where = f"{where}, NETWORKID={k}"
        if k in found:
            raise ValueError(f"{where} is given twice: each network needs its own NETWORKID")
        flow = _flow_of(re.sub(r"\s+", " ", vp["LAW"].strip().upper()), k)
        n = len(flow.param_names)
        if len(rows) > -(-(n + 1) // 8):  # the constants and a temperature: one record
            raise ValueError(f"{where}: {len(rows)} data lines: temperature-dependent flow "
                             "constants cannot be read (give one line "
                             f"{', '.join(flow.param_names)})")
        tokens = [t for row in rows for t in row][:n]
        tokens += [""] * (n - len(tokens))  # a blank or missing field is 0, as in Abaqus
        try:
            values = tuple(float(v) for v in flow.check([parse_number(t) for t in tokens]))
        except ValueError as exc:
            raise ValueError(f"{where}, LAW={vp['LAW'].strip()}: {exc}") from None
        found[k] = Network(flow=flow.name, ratio=ratio, constants=values)
    law_params = tuple(constants.get(p, 0.0) for p in _hyper.get(kind).param_names)
    try:
        model = NetworkModel(law=kind, law_params=law_params,
                             networks=tuple(found[k] for k in sorted(found)))
    except ValueError as exc:
        raise ValueError(f"{SOLVER} card: {exc}") from None
    return model, _named_constants(model)


def _named_constants(model: NetworkModel) -> dict[str, float]:
    """A network model's constants by name: the law's, then each network's SRATIO and flow
    constants (``networkK_sratio``, ``networkK_<name>``)."""
    from vhfit.viscous import flows

    named = dict(zip(_hyper.get(model.law).param_names, model.law_params))
    for k, net in enumerate(model.networks, 1):
        named[f"network{k}_sratio"] = net.ratio
        named.update({f"network{k}_{p}": v
                      for p, v in zip(flows.get(net.flow).param_names, net.constants)})
    return named


# --------------------------------------------------------------------- test data
def _or(names: list[str]) -> str:
    return " or ".join([", ".join(names[:-1]), names[-1]] if len(names) > 1 else names)


#: Standard test (a deformation record's ``standard_test``) -> its Abaqus test-data
#: keyword (Abaqus' biaxial test is the equibiaxial one).
TEST_DATA_KEYWORDS = {"uniaxial": "*UNIAXIAL TEST DATA", "equibiaxial": "*BIAXIAL TEST DATA",
                      "planar": "*PLANAR TEST DATA"}


def _test_data() -> dict[str, str]:
    """Registered deformation -> its Abaqus test-data keyword (from the ``standard_test``
    of its record; nominal stress, nominal strain lines), for the tests that have one."""
    tests = (get_deformation(n) for n in registered_deformations())
    return {t.name: TEST_DATA_KEYWORDS[t.standard_test] for t in tests
            if t.standard_test in TEST_DATA_KEYWORDS}


def to_abaqus_test_data(curves, hyperelastic: str = "mooney_rivlin", *,
                        name: str = "VHFIT_TEST_DATA") -> str:
    """Abaqus ``*HYPERELASTIC, ..., TEST DATA INPUT`` block of the equilibrium curves.

    Abaqus fits its own constants of the same law to these data (nominal stress,
    nominal strain per line; the keyword of each test follows its record's
    ``standard_test``, e.g. ``*UNIAXIAL TEST DATA`` for ``"uniaxial"``), so its
    evaluation of the law can be compared with vhfit's fit. Only equilibrium (rate-free)
    curves are written: rate curves are not a hyperelastic response. Tests without such a
    keyword in Abaqus (general biaxial, simple shear) are left out with a comment.

    Parameters
    ----------
    curves : sequence of Curve
        The calibration curves; the equilibrium ones are written.
    hyperelastic : str
        The registered law whose Abaqus form Abaqus should fit.
    name : str
        Material name (``*MATERIAL, NAME=``).

    Returns
    -------
    str
        The block, comment lines first.

    Raises
    ------
    ValueError
        When no curve can be written, or Abaqus lacks the law.

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> c = vhfit.Curve(stretch=[1.5, 2.0], stress=[0.4, 0.7], deformation="planar")
    >>> print(to_abaqus_test_data([c], "neo_hooke").split("*MATERIAL")[1])
    , NAME=VHFIT_TEST_DATA
    *HYPERELASTIC, NEO HOOKE, TEST DATA INPUT
    *PLANAR TEST DATA
    0.4, 0.5
    0.7, 1.0
    <BLANKLINE>
    """
    law = hyperelastic if isinstance(hyperelastic, str) else hyperelastic.name
    if law not in _CARDS:
        raise unsupported(SOLVER, law, list(_CARDS))
    _check_name(name)
    keywords = _test_data()
    blocks: dict[str, list[str]] = {}
    skipped = []
    for c in curves:
        if not c.is_equilibrium:
            continue
        kw = keywords.get(c.deformation)
        if kw is None:
            skipped.append(f"{c.name!r} ({c.deformation})")
            continue
        lam = 1.0 + np.asarray(c.strain, dtype=np.float64)
        P = np.asarray(c.stress, dtype=np.float64)
        if c.measure == "true":
            P = P / lam
        blocks.setdefault(kw, []).extend(
            # 12 digits: λ − 1 of a stretch column carries rounding noise in the 17th
            f"{free_number(p)}, {free_number(float(f'{e:.12g}'))}" for p, e in zip(P, lam - 1.0))
    if not blocks:
        raise ValueError(
            f"no equilibrium {_or(list(keywords))} curve to write as Abaqus test "
            "data: give curves with neither strain_rate nor time"
        )
    lines = [
        f"** Generated by {generator()}: equilibrium test data for Abaqus to fit its own "
        f"{_CARDS[law][0]} constants,",
        "** to cross-check vhfit's long-term fit. Units: N, mm, s, MPa. Lines: nominal "
        "stress, nominal strain.",
    ]
    if skipped:
        lines.append("** Not written (no Abaqus test-data keyword): " + ", ".join(skipped))
    lines += [f"*MATERIAL, NAME={name}", f"*HYPERELASTIC, {_CARDS[law][0]}, TEST DATA INPUT"]
    for kw in dict.fromkeys(keywords.values()):
        if kw in blocks:
            lines += [kw] + blocks[kw]
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------- shift, record
def abaqus_trs(law) -> list[str]:
    """Abaqus ``*TRS, DEFINITION=WLF`` lines for a WLF law.

    Abaqus Keywords Reference, ``*TRS``: ``DEFINITION=WLF`` (the default), one data line
    "reference temperature, C1, C2"; it must follow ``*VISCOELASTIC`` in the material.
    Abaqus writes the WLF law with reduced time dτ/dt = 1/A, log10 A = −C1 (θ − θ0)/
    (C2 + θ − θ0): the same C1, C2 as vhfit's.

    Examples
    --------
    >>> from vhfit.tts import WLF
    >>> abaqus_trs(WLF(C1=17.44, C2=51.6, T_ref=20.0))
    ['*TRS, DEFINITION=WLF', '20.0, 17.44, 51.6']
    """
    T_ref, c1, c2 = wlf_constants(law)
    return ["*TRS, DEFINITION=WLF", f"{wlf_number(T_ref)}, {wlf_number(c1)}, {wlf_number(c2)}"]


def _add_trs(card: str, law, mat: int = 1) -> str:
    """``*TRS`` after the material's ``*VISCOELASTIC`` lines (the card's end)."""
    lines = card.rstrip("\n").split("\n")
    if not any(ln.strip().upper().startswith("*VISCOELASTIC") for ln in lines):
        raise ValueError("shift=: the card has no *VISCOELASTIC (no Prony terms): a "
                         "temperature shift needs n_prony >= 1")
    return "\n".join(lines + abaqus_trs(law)) + "\n"


#: Where its cards come in the list of the registered solvers (vhfit.export finds the
#: solver modules and registers their records in this order).
ORDER = 1

#: The solver record (registered by vhfit.export).
RECORD = Solver(
    name="abaqus", label=SOLVER, suffix=".inp", formulation="hereditary",
    write=to_abaqus, read=from_abaqus, sniff=lambda body: "*HYPERELASTIC" in body,
    laws=tuple(_CARDS), comment="**", shift=_add_trs, density=True, bulk_modulus=True,
    variants={"explicit": ("Abaqus/Explicit", "D1 from the bulk modulus, never 0")},
    test_data=to_abaqus_test_data, networks=True)
