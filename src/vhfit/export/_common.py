"""Shared pieces of the FE exporters: the material in solver-neutral form, numbers, headers.

Every exporter goes through :class:`Material`: the calibrated model reduced to what a
solver card holds — the long-term hyperelastic constants, the dimensionless Prony
weights g_i = G_i / G0 and the relaxation times τ_i (docs/theory.md §3) — and every parser
builds a :class:`Material` back from the card's fields and turns it into vhfit
parameters with :meth:`Material.to_params`. The two directions share no state: a
parser sees only the text.
"""

from __future__ import annotations

import math
import re
import textwrap
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from vhfit import hyperelastic as _hyper
from vhfit.export._solvers import records
from vhfit.model import ModelSpec, Prony, ViscoHyperelastic, model_from_spec, spec_from_dict
from vhfit.viscous import ParamLayout

__all__ = [
    "Material",
    "resolve",
    "free_number",
    "fixed_number",
    "parse_number",
    "generator",
    "header",
    "unsupported",
    "TooManyTerms",
    "model_hint",
    "UNITS",
    "BULK_RATIO",
    "check_compressibility",
    "no_density_note",
    "SAME_LAW",
    "comment_block",
    "is_network_model",
    "no_network_card",
]

#: The consistent unit system every card is written in (the model's own: MPa and s).
UNITS = "N, mm, s, MPa (stress and moduli), tonne/mm^3 (density)"

#: Default bulk modulus of the cards that need one (a solver record's ``bulk_modulus``),
#: as a multiple of the instantaneous shear modulus: the range of unfilled elastomers
#: (K0/μ0 of 1000 to 10000; docs/export.md, "Compressibility").
BULK_RATIO = 1000.0

#: Laws with the same energy under two names (neo-Hooke = reduced polynomial, N = 1)
SAME_LAW = {"neo_hooke": "reduced_polynomial1", "yeoh": "reduced_polynomial3"}
SAME_LAW.update({v: k for k, v in SAME_LAW.items()})


def generator() -> str:
    """``"vhfit <version>"`` for the header lines (no date: cards are reproducible)."""
    try:
        from importlib.metadata import version

        return f"vhfit {version('vhfit')}"
    except Exception:  # pragma: no cover - not installed (running from a source tree)
        return "vhfit"


# ----------------------------------------------------------------------------- input
def check_compressibility(poisson: float | None = None, bulk_modulus: float | None = None,
                          density: float | None = None) -> None:
    """Refuse a Poisson's ratio outside (−1, 0.5), a non-positive bulk modulus or density,
    or both ν and K, in one line naming the argument and the fix.

    Examples
    --------
    >>> check_compressibility(poisson=0.5)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: poisson = 0.5 must lie in (-1, 0.5): 0.5 is incompressible ...
    """
    if poisson is not None and bulk_modulus is not None:
        raise ValueError("give poisson or bulk_modulus, not both: each fixes the bulk modulus")
    if poisson is not None and not (math.isfinite(poisson) and -1.0 < poisson < 0.5):
        raise ValueError(
            f"poisson = {poisson!r} must lie in (-1, 0.5): 0.5 is incompressible (infinite "
            "bulk modulus); give e.g. 0.4995, or leave it out for the default bulk modulus")
    if bulk_modulus is not None and not (math.isfinite(bulk_modulus) and bulk_modulus > 0):
        raise ValueError(f"bulk_modulus = {bulk_modulus!r} must be > 0 (MPa), e.g. 1000 times "
                         "the instantaneous shear modulus, or leave it out for that default")
    if density is not None and not (math.isfinite(density) and density > 0):
        raise ValueError(f"density = {density!r} must be > 0 (tonne/mm^3, e.g. 1e-9 for "
                         "1000 kg/m^3)")


def is_network_model(model) -> bool:
    """Whether ``model`` is a network (parallel rheological) model of :mod:`vhfit.viscous`."""
    from vhfit.viscous import NetworkModel

    return isinstance(model, NetworkModel)


def no_network_card(solver) -> ValueError:
    """The one-line refusal of a solver record whose cards hold no network model: what
    is missing (the record's ``no_networks``) and the solvers whose cards do hold one."""
    others = [r.label for r in records() if r.networks]
    where = (f"write it for {' or '.join(others)}" if others
             else "no solver card vhfit writes holds one")
    why = f": {solver.no_networks}" if solver.no_networks else ""
    return ValueError(f"{solver.label} export has no card for a network (parallel "
                      f"rheological) model{why}; {where}, or fit a Prony model for "
                      f"{solver.label}")


def resolve(model, params=None, *, solver=None) -> tuple[ViscoHyperelastic, dict[str, float]]:
    """The (model, params) pair behind the exporters' flexible first arguments.

    Accepts ``(ViscoHyperelastic, dict | array)``; a results-like object with
    ``.model`` and ``.params`` attributes (``params`` omitted); or a mapping with
    ``"params"`` and a model: its ``"spec"`` (:meth:`vhfit.model.ModelSpec.to_dict`, as
    material.json and the results files write it), or ``"model"`` (a
    :class:`ViscoHyperelastic` or a model name) or ``"hyperelastic"`` (a model name),
    with ``"n_prony"`` optional (else counted from the ``G1, tau1, ...`` keys),
    ``"formulation"`` optional (default ``"hereditary"``) and ``"rtol"`` optional (the
    model's accuracy). A network model (:mod:`vhfit.viscous`) is refused in one line:
    ``solver`` (a :class:`~vhfit.export.Solver`) names the card that cannot hold it.
    """
    if is_network_model(model):
        if solver is None:
            raise ValueError("a network (parallel rheological) model has no Prony "
                             "parameters: write its card with a solver that holds networks")
        raise no_network_card(solver)
    if params is None:
        if isinstance(model, ViscoHyperelastic):
            raise TypeError("give the parameters: to_X(model, params)")
        if isinstance(model, Mapping):
            if "params" not in model:
                raise TypeError(
                    "a mapping passed as the model needs 'params' and 'model' or 'hyperelastic' "
                    f"keys; got {sorted(model)}"
                )
            params = model["params"]
            model = _model_of(model, params)
        elif hasattr(model, "params") and hasattr(model, "model"):
            params, model = model.params, _model_of({"model": model.model}, model.params)
        else:
            raise TypeError(
                f"cannot export {type(model).__name__}: give (model, params), an object with "
                ".model and .params, or a mapping with 'params' and 'model'/'hyperelastic'"
            )
    if not isinstance(model, ViscoHyperelastic):
        raise TypeError(f"expected a vhfit.ViscoHyperelastic, got {type(model).__name__}")
    x = model.check(params)
    return model, model.as_dict(x)


def _model_of(doc: Mapping, params) -> ViscoHyperelastic:
    """The model a mapping of :func:`resolve` names (see there)."""
    if "spec" in doc:
        return model_from_spec(spec_from_dict(doc))
    law = doc.get("model", doc.get("hyperelastic"))
    n_prony = doc.get("n_prony")
    if isinstance(law, Mapping):  # e.g. {"hyperelastic": "yeoh", "n_prony": 2}
        n_prony = law.get("n_prony", n_prony)
        law = law.get("hyperelastic", law.get("name"))
    if isinstance(law, ViscoHyperelastic):
        return law
    if law is None:
        raise TypeError("the mapping names no model: add 'model' or 'hyperelastic'")
    if n_prony is None:
        if not isinstance(params, Mapping):
            raise TypeError("give 'n_prony' when the parameters are an array")
        n_prony = ParamLayout.count_terms(params)
    accuracy = {"rtol": float(doc["rtol"])} if "rtol" in doc else {}
    viscous = Prony(int(n_prony), str(doc.get("formulation", "hereditary")))
    return model_from_spec(ModelSpec(law, viscous, **accuracy))


# --------------------------------------------------------------------------- material
def _card_spec(hyperelastic: str, n_prony: int) -> ModelSpec:
    """The spec of a card's model: a law and its Prony terms, every other part default."""
    return ModelSpec(hyperelastic, Prony(n_prony))


@dataclass(frozen=True)
class Material:
    """A visco-hyperelastic material in the form FE cards hold it.

    Attributes
    ----------
    hyperelastic : str
        Registered vhfit model name.
    constants : dict of str to float
        Hyperelastic constants, vhfit's convention (docs/theory.md §2), LONG-TERM values.
    g : tuple of float
        Dimensionless Prony weights g_i = G_i / G0 (docs/theory.md §3).
    tau : tuple of float
        Relaxation times τ_i, s.
    """

    hyperelastic: str
    constants: dict
    g: tuple = ()
    tau: tuple = ()

    # ---------------------------------------------------------------- from vhfit
    @classmethod
    def from_model(cls, model: ViscoHyperelastic, params) -> Material:
        """The card form of one vhfit parameter set (validated)."""
        x = model.check(params)
        hyper, G, tau = model.split(x)
        g, _ = model.prony_g(x)
        if not 1.0 - math.fsum(g) > 0:  # sum(G_i) > 1e16 E_inf: g_inf rounds to 0
            raise ValueError(
                f"Prony moduli {', '.join(f'{v:g}' for v in G)} MPa against a "
                f"long-term modulus of {model.long_term_modulus(x):g} MPa leave g_inf = 0 in "
                "float64, which no card can hold: check the constants (a G_i of 1e16 x E_inf "
                "or more)")
        names = model.hyperelastic.param_names
        return cls(
            hyperelastic=model.hyperelastic.name,
            constants={n: float(v) for n, v in zip(names, hyper)},
            g=tuple(float(v) for v in g),
            tau=tuple(float(v) for v in tau),
        )

    @property
    def n_prony(self) -> int:
        return len(self.g)

    def spec(self) -> ModelSpec:
        """The model of the card: its law and Prony terms (in the default formulation and
        accuracy: a card holds no more)."""
        return _card_spec(self.hyperelastic, self.n_prony)

    @property
    def g_inf(self) -> float:
        """g∞ = 1 − Σ g_i."""
        return 1.0 - math.fsum(self.g)

    @property
    def mu0(self) -> float:
        """Long-term initial shear modulus μ0 = E∞ / 3 of the constants, MPa."""
        h = _hyper.get(self.hyperelastic)
        c = np.array([self.constants[n] for n in h.param_names])
        return float(h.initial_shear_modulus(c))

    @property
    def mu_inst(self) -> float:
        """Instantaneous shear modulus μ0 / g∞ (= (E∞ + Σ G_i) / 3), MPa."""
        return self.mu0 / self.g_inf

    def bulk_modulus(self, poisson: float | None = None,
                     bulk_modulus: float | None = None) -> float | None:
        """The bulk modulus K the cards describe, MPa (None: incompressible).

        ``bulk_modulus`` is taken as given; a Poisson's ratio ν gives
        K = 2 μ_inst (1 + ν) / (3 (1 − 2ν)) with the INSTANTANEOUS shear modulus
        μ_inst = μ0 / g∞: the bulk response does not relax (k_i = 0), so ν describes the
        material at the rates where the Prony terms are active. Each card writes K in
        its solver's own terms (a compressibility D1 = 2/K, :meth:`d1`, or a Poisson's
        ratio that gives this K; docs/export.md).
        """
        check_compressibility(poisson, bulk_modulus)
        if bulk_modulus is not None:
            return float(bulk_modulus)
        if poisson is None:
            return None
        mu_inst = self.mu_inst
        K = 2.0 * mu_inst * (1.0 + poisson) / (3.0 * (1.0 - 2.0 * poisson))
        return K

    def default_bulk_modulus(self) -> float:
        """K = :data:`BULK_RATIO` × μ_inst: nearly incompressible at every rate, MPa."""
        return BULK_RATIO * self.mu_inst

    def d1(self, poisson: float | None = None, bulk_modulus: float | None = None) -> float:
        """Compressibility D1 = 2 / K (the cards' D1 or d1 field); 0 (incompressible) when
        neither ν nor K is given (see :meth:`bulk_modulus`)."""
        K = self.bulk_modulus(poisson, bulk_modulus)
        return 0.0 if K is None else 2.0 / K

    def scaled(self, factor: float) -> dict[str, float]:
        """The constants with every stress-like (MPa) constant multiplied by ``factor``.

        σ_h is linear in the MPa constants of every built-in model, so ``factor = 1/g∞``
        gives the instantaneous constants (docs/theory.md §3: σ0 = σ_h / g∞).
        """
        h = _hyper.get(self.hyperelastic)
        units = dict(zip(h.param_names, h.units))
        return {
            k: (v * factor if units.get(k, "MPa") == "MPa" else v)
            for k, v in self.constants.items()
        }

    # ------------------------------------------------------------------ to vhfit
    @classmethod
    def from_card(
        cls, hyperelastic: str, constants: Mapping[str, float], g: Sequence[float],
        tau: Sequence[float], *, instantaneous: bool, solver: str,
    ) -> Material:
        """Build from values read off a card; ``instantaneous`` constants are converted."""
        g = tuple(float(v) for v in g)
        tau = tuple(float(v) for v in tau)
        for i, (gi, ti) in enumerate(zip(g, tau), start=1):
            if not (math.isfinite(gi) and gi >= 0):
                raise ValueError(f"{solver} card: Prony weight {i} = {gi!r} must be >= 0")
            if not (math.isfinite(ti) and ti > 0):
                raise ValueError(f"{solver} card: relaxation time {i} = {ti!r} must be > 0")
        mat = cls(hyperelastic, {k: float(v) for k, v in constants.items()}, g, tau)
        if not mat.g_inf > 0:
            raise ValueError(
                f"{solver} card: the Prony weights sum to {math.fsum(g)!r} >= 1, so the "
                "long-term modulus g_inf = 1 - sum(g_i) is not positive"
            )
        if instantaneous:
            mat = cls(hyperelastic, mat.scaled(mat.g_inf), g, tau)
        return mat

    def to_params(self) -> tuple[ViscoHyperelastic, dict[str, float]]:
        """The vhfit model and parameters: G_i = g_i G0 with G0 = E∞ / g∞."""
        model = model_from_spec(self.spec())
        hyper = [self.constants[n] for n in model.hyperelastic.param_names]
        E_inf = float(3.0 * model.hyperelastic.initial_shear_modulus(np.array(hyper)))
        if not E_inf > 0:
            raise ValueError(
                f"the card's hyperelastic constants {self.constants} give no long-term "
                f"stiffness (E_inf = {E_inf:g} MPa)"
            )
        G0 = E_inf / self.g_inf
        x = model.layout.assemble(hyper, [gi * G0 for gi in self.g], self.tau)
        return model, model.as_dict(model.check(x))

    @staticmethod
    def params_from_moduli(
        hyperelastic: str, constants: Mapping[str, float], G: Sequence[float],
        tau: Sequence[float], *, solver: str,
    ) -> tuple[ViscoHyperelastic, dict[str, float]]:
        """vhfit (model, params) from long-term constants and uniaxial Prony moduli G_i."""
        if len(G) != len(tau):
            raise ValueError(f"{solver} card: {len(G)} Prony moduli but {len(tau)} times")
        model = model_from_spec(_card_spec(hyperelastic, len(G)))
        law = [float(constants.get(n, 0.0)) for n in model.hyperelastic.param_names]
        values = model.layout.assemble(law, [float(v) for v in G], [float(v) for v in tau])
        try:
            x = model.check(values)
        except ValueError as err:
            raise ValueError(f"{solver} card: {err}") from None
        return model, model.as_dict(x)

    def summary(self) -> str:
        """One line of the vhfit parameters, for the card header."""
        _, p = self.to_params()
        return ", ".join(f"{k}={v:.6g}" for k, v in p.items())


def unsupported(solver: str, model: str, supported: Sequence[str], why: str = "") -> ValueError:
    """The error every exporter raises for a model its card cannot hold.

    One line: the solver, the model (and why), the solvers whose cards do hold it, and
    the models this solver supports.
    """
    extra = f" ({why})" if why else ""
    others = [r.label for r in records() if r.label != solver and model in r.laws]
    where = (f"export it to {' or '.join(others)} instead" if others
             else "no solver card vhfit writes holds it")
    return ValueError(
        f"{solver} export does not support the hyperelastic model {model!r}{extra}: "
        f"{where}; supported: {', '.join(supported)}"
    )


class TooManyTerms(ValueError):
    """A card that cannot hold the fit's number of Prony terms: the solver's limit in
    ``limit``, the text without a remedy in ``what`` (the command line adds its own flag).
    """

    def __init__(self, what: str, limit: int):
        super().__init__(f"{what}: refit with at most {limit} terms (n_prony={limit})")
        self.what, self.limit = what, int(limit)


def no_density_note(solver: str, keyword: str) -> str:
    """The header warning of a card written without a density."""
    return (f"no density: {keyword} is not written, and {solver} needs it for any dynamic or "
            "explicit analysis: give density= (vhfit fit --density RHO, tonne/mm^3; "
            "1e-9 for 1000 kg/m^3)")


def model_hint(text: str, layout: str) -> str:
    """The ``vhfit model:`` header comment of a card, when it names the same law as the
    card's fields (``layout``, e.g. yeoh for reduced_polynomial3); else ``layout``."""
    m = re.search(r"vhfit model:\s*([A-Za-z0-9_]+)", text)
    hint = m.group(1) if m else None
    return hint if hint is not None and SAME_LAW.get(layout) == hint else layout


# ---------------------------------------------------------------------------- numbers
#: Longest number a free-format data line may hold: the free-format input syntax allows
#: 20 characters for a floating-point number (sign, point and exponent included), and
#: CalculiX, which reads the same syntax, silently cuts a longer one at 20 — so that
#: '4.575210514986395e-05' would be read as 4.575 (docs/export.md).
NUMBER_WIDTH = 20


def free_number(x: float, width: int = NUMBER_WIDTH) -> str:
    """Shortest text that reads back as ``x``, in at most ``width`` characters.

    The shortest round-trip text (``repr``) when it fits; else the same digits in the
    shortest exponent form ('4.575210514986395e-5'); else the most significant digits
    that fit (for ``width`` = 20 at least 12, a relative change below 1e-12; 14 where
    the exponent has one or two digits).

    Examples
    --------
    >>> free_number(0.1), free_number(2.0), free_number(-0.0), free_number(1e-5)
    ('0.1', '2.0', '0.0', '1e-05')
    >>> free_number(4.575210514986395e-05), free_number(0.0004465395310138371)
    ('4.575210514986395e-5', '4.465395310138371e-4')
    """
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"cannot write the non-finite value {x!r} into a card")
    if x == 0.0:
        return "0.0"
    text = repr(x)
    if len(text) <= width:
        return text
    digits = len(f"{x:.16e}".partition("e")[0].replace("-", "").replace(".", "").rstrip("0"))
    for p in range(max(digits - 1, 0), -1, -1):
        text = _short_exp(f"{x:.{p}e}")
        if len(text) <= width:
            return text
    raise ValueError(f"cannot write {x!r} in {width} characters")


def _short_exp(s: str) -> str:
    """'1.5e-05' -> '1.5e-5' (Fortran reads any exponent width)."""
    mant, _, exp = s.partition("e")
    if not exp:
        return s
    sign = "-" if exp.startswith("-") else ""
    return f"{mant}e{sign}{exp.lstrip('+-').lstrip('0') or '0'}"


def fixed_number(x: float, width: int) -> str:
    """``x`` right-aligned in a ``width``-character field, as precisely as fits.

    At most ``width - 1`` characters are used, so a field never touches its left
    neighbour. Among fixed-point and scientific forms the one closest to ``x`` wins.

    Examples
    --------
    >>> fixed_number(0.4995, 10)
    '    0.4995'
    >>> fixed_number(-1.23456789e-5, 10)
    ' -1.235e-5'
    >>> fixed_number(1e4, 10), fixed_number(5.0, 10)
    ('     1.0e4', '       5.0')
    >>> fixed_number(1 / 3, 10), float(fixed_number(1 / 3, 20)) == 1 / 3
    (' 0.3333333', True)
    """
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"cannot write the non-finite value {x!r} into a card")
    room = width - 1
    if x == 0.0:
        return "0.0".rjust(width)
    best, err = None, None
    for p in range(16, -1, -1):
        # '#' keeps the decimal point ('5.', '1.e4'): with a point, a Fortran E/F edit
        # descriptor cannot shift the value by an implied decimal
        for s in (_short_exp(f"{x:#.{p}e}"), f"{x:#.{p}f}"):
            if len(s) > room:
                continue
            v = float(s)
            if v == 0.0 and x != 0.0:
                continue
            key = (abs(v - x), ".e" in s or s.endswith("."), len(s))
            if best is None or key < err:
                best, err = s, key
    if best is None:
        raise ValueError(f"{x!r} does not fit a {width}-character field")
    return best.rjust(width)


def parse_number(token: str, default: float = 0.0) -> float:
    """A card field as a float (blank -> ``default``; Fortran 'D' exponents accepted)."""
    t = token.strip()
    if not t:
        return default
    t = t.replace("d", "e").replace("D", "E")
    # Fortran also writes '1.5-5' for 1.5e-5
    m = re.fullmatch(r"([+-]?\d*\.?\d*)([+-]\d+)", t)
    if m and m.group(1) not in ("", "+", "-"):
        t = f"{m.group(1)}e{m.group(2)}"
    return float(t)


# ---------------------------------------------------------------------------- headers
def header(
    prefix: str,
    *,
    solver: str,
    mat: Material,
    moduli: str,
    conventions: Sequence[str],
    width: int = 100,
    notes: Sequence[str] = (),
    comments: Sequence[str] = (),
) -> list[str]:
    """The comment block every card starts with (ASCII, wrapped to ``width``).

    Generator, model, units, the solver conventions used and whether the hyperelastic
    moduli are long-term or instantaneous, then the calibrated vhfit parameters. ``notes``
    (e.g. a g∞ at its floor) come right after the first line, as warnings; ``comments``
    (e.g. which fit the constants come from) right after the units.
    """
    lines = [
        f"Generated by {generator()}: visco-hyperelastic material for {solver}",
        *(f"WARNING: {n}" for n in notes),
        f"vhfit model: {mat.spec().describe()}",
        f"Units: {UNITS}",
        *comments,
        *conventions,
        f"Hyperelastic moduli are {moduli}",
        f"g_inf = 1 - sum(g_i) = {mat.g_inf:.9g}",
        f"Calibrated vhfit parameters (paper convention, G_i uniaxial): {mat.summary()}",
    ]
    return comment_block(prefix, lines, width)


def comment_block(prefix: str, lines: Sequence[str], width: int = 100) -> list[str]:
    """``lines`` as comment lines of a card: ``prefix`` first, wrapped to ``width``."""
    out = []
    for line in lines:
        for piece in textwrap.wrap(line, width - len(prefix) - 1,
                                   subsequent_indent="  ", break_on_hyphens=False):
            out.append(f"{prefix} {piece}")
    return out
