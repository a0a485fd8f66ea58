"""FE-solver export of calibrated visco-hyperelastic models (and the way back).

::

    from vhfit.export import export, parse, solvers
    text = export(model, params, to=solvers()[0])    # any registered solver, or "json"
    model2, params2 = parse(text)                    # read the card back

Each writer takes ``(model, params)`` — or one results-like object with ``.model``
and ``.params`` (or a mapping with ``"params"`` and ``"model"``/``"hyperelastic"``)
— and returns the card as text, comment lines first (generator, model, units,
conventions, long-term or instantaneous moduli). Each parser reads only the card's
fields and converts them back with the documented conventions; the round trip
reproduces the calibrated stresses (tests/test_export.py). Conventions and sources:
docs/export.md.

Each solver is one record (:class:`Solver`: names, card file, formulation, writer,
reader, recognition, laws, shift, density and bulk-modulus fields, variants) in a
registry (:func:`register_solver`). Every public module of this package that defines a
``RECORD`` is a solver module: the package finds them on import (in the order of their
``ORDER``, then of their names), registers each record and re-exports the module's
writers and readers (the names of its ``__all__`` that begin with ``to_`` or ``from_``),
so adding a solver is adding one module. Everything here, the card check and the
command line read from the records.

Units: the model's own consistent set — N, mm, s, MPa; density in tonne/mm³.
"""

from __future__ import annotations

import importlib
import json
import pkgutil
from collections.abc import Mapping

from vhfit.export._common import (
    Material,
    TooManyTerms,
    generator,
    is_network_model,
    resolve,
)
from vhfit.export._solvers import (
    LiveMapping,
    Solver,
    card_body,
    get_solver,
    records,
    register_solver,
    solvers,
    unregister_solver,
)
from vhfit.export.shift import add_shift
from vhfit.model import ViscoHyperelastic

__all__ = [
    "export",
    "parse",
    "to_json",
    "from_json",
    "supported_laws",
    "FORMATS",
    "Solver",
    "register_solver",
    "unregister_solver",
    "get_solver",
    "solvers",
    "TooManyTerms",
]


class _Formats(LiveMapping):
    """Export target -> usual file suffix: every registered solver, and ``json``."""

    def _now(self) -> dict[str, str]:
        return {**{r.name: r.suffix for r in records()}, "json": ".json"}


#: Export target -> usual file suffix (read from the solver records at each use).
FORMATS: Mapping[str, str] = _Formats()

JSON_FORMAT = "vhfit-material"
#: The model's default accuracy: a JSON document says ``rtol`` only when it differs.
_DEFAULT_RTOL = 1e-6


def to_json(model, params=None, *, name: str = "VHFIT_MATERIAL", indent: int = 2) -> str:
    """The calibrated material as JSON: vhfit parameters plus the derived solver values.

    ``spec`` (the model's :meth:`~vhfit.model.ModelSpec.to_dict`: law, number of terms,
    the viscoelastic formulation the constants were fitted in, accuracy) and ``params``
    define the model (this is what :func:`from_json` reads); ``hyperelastic``,
    ``formulation``, ``n_prony`` and ``rtol`` (when not the default) say the same as the
    spec for the readers of documents written before it; ``derived`` holds E∞, G0, g_i,
    g∞ and the instantaneous constants for reference.

    Examples
    --------
    >>> import json, vhfit
    >>> from vhfit.export import to_json
    >>> m = vhfit.ViscoHyperelastic("neo_hooke", n_prony=1)
    >>> d = json.loads(to_json(m, dict(C10=0.5, G1=3.0, tau1=0.1)))
    >>> d["derived"]["g"], d["derived"]["g_inf"]
    ([0.5], 0.5)
    """
    model, params = resolve(model, params)
    mat = Material.from_model(model, params)
    E_inf = 3.0 * mat.mu0
    doc = {
        "format": JSON_FORMAT,
        "generator": generator(),
        "name": name,
        **model.spec().flat_fields(),
        "spec": model.spec().to_dict(),
        "params": params,
        **({} if model.rtol == _DEFAULT_RTOL else {"rtol": model.rtol}),
        "units": {
            "system": "N, mm, s, MPa",
            **dict(zip(model.param_names, model.units)),
        },
        "conventions": (
            "hyperelastic constants long-term (polynomial Cij / Ogden 2mu/alpha^2 forms, "
            "docs/theory.md section 2); "
            "G_i uniaxial Prony moduli: E(t) = E_inf + sum G_i exp(-t/tau_i); "
            "g_i = G_i/G0, G0 = E_inf + sum G_i (docs/theory.md section 3)"
        ),
        "derived": {
            "E_inf": E_inf,
            "G0": E_inf / mat.g_inf,
            "g": list(mat.g),
            "g_inf": mat.g_inf,
            "tau": list(mat.tau),
            "instantaneous_constants": mat.scaled(1.0 / mat.g_inf),
        },
    }
    return json.dumps(doc, indent=indent, allow_nan=False) + "\n"


def from_json(text: str) -> tuple[ViscoHyperelastic, dict]:
    """Model and parameters from :func:`to_json` output or a results-like JSON document.

    The document needs ``"params"`` and its model: ``"spec"`` (as :func:`to_json`
    writes it), or ``"hyperelastic"`` (or ``"model"``) — a calibration results file
    reads as well.

    Examples
    --------
    >>> from vhfit.export import from_json
    >>> m, p = from_json('{"hyperelastic": "neo_hooke", "params": {"C10": 0.5}}')
    >>> m.param_names, p
    (['C10'], {'C10': 0.5})
    """
    doc = json.loads(text)
    if not isinstance(doc, dict):
        raise ValueError("the JSON document must be an object with 'params' and 'hyperelastic'")
    return resolve(doc)


def _target(to: str) -> str:
    """The registered solver ``to`` names (or an alias of), or ``"json"``."""
    key = str(to).strip().lower()
    if key == "json":
        return key
    try:
        return get_solver(key).name
    except ValueError:
        raise ValueError(f"unknown export target {to!r}; choose one of "
                         f"{', '.join(FORMATS)}") from None


def supported_laws(solver: str) -> tuple[str, ...]:
    """The built-in hyperelastic laws whose cards ``solver`` holds.

    A solver's writer may refuse some constants of a law it holds (a card with fewer
    fields than the law has constants, unless the others are zero) when writing.

    Examples
    --------
    >>> from vhfit.export import solvers, supported_laws
    >>> all("neo_hooke" in supported_laws(s) for s in solvers())
    True
    """
    key = _target(solver)
    if key == "json":
        raise ValueError("every registered law has a JSON form: give one of "
                         f"{', '.join(solvers())}")
    return tuple(get_solver(key).laws)


def export(model, params=None, *, to: str | None = None, **options) -> str:
    """Write a calibrated model for an FE solver (dispatch to ``to_<solver>``).

    Parameters
    ----------
    model : ViscoHyperelastic, NetworkModel or results-like
        The model with ``params``; or a calibration result (``.model``, ``.params``)
        or a mapping with ``"params"`` and ``"model"``/``"hyperelastic"``; or a network
        model (:class:`vhfit.viscous.NetworkModel`, no ``params``), which only a solver
        whose record holds networks writes (the others refuse it in one line).
    params : dict or array_like, optional
        The calibrated parameters (omit when ``model`` is results-like).
    to : str, optional
        Target format: a registered solver (:func:`solvers`) or one of its aliases, or
        ``"json"``; default the first registered solver.
    **options
        Passed to the writer (``name``, ``density``, the keywords its solver's record
        declares, ...); ``shift=`` a WLF law
        (:class:`vhfit.tts.WLF`) adds the temperature shift (:mod:`vhfit.export.shift`).

    Returns
    -------
    str
        The card text; :data:`FORMATS` gives a file suffix for each target.

    Examples
    --------
    >>> import vhfit
    >>> from vhfit.export import export, parse, solvers
    >>> m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    >>> p = dict(C10=0.0, C01=5.0, G1=30.0, tau1=1e-4)
    >>> cards = {s: export(m, p, to=s) for s in solvers()}
    >>> all(export({"model": m, "params": p}, to=s) == card for s, card in cards.items())
    True
    >>> all(abs(parse(card)[1]["C01"] - 5.0) < 1e-12 for card in cards.values())
    True
    """
    shift = options.pop("shift", None)
    key = _target(solvers()[0] if to is None else to)
    write = to_json if key == "json" else get_solver(key).write
    # a network model goes to the writer as it is: a record that holds networks writes it,
    # any other refuses it in one line (resolve)
    args = (model, None) if is_network_model(model) else resolve(model, params)
    text = write(*args, **options)
    return text if shift is None else add_shift(text, shift, key, mat=options.get("mat", 1))


def parse(text: str, fmt: str | None = None) -> tuple[ViscoHyperelastic, dict]:
    """Read a card of any supported format back (``fmt`` guessed when None).

    Examples
    --------
    >>> from vhfit.export import parse
    >>> parse("*HYPERELASTIC, NEO HOOKE\\n0.5, 0.0\\n")[1]
    {'C10': 0.5}
    """
    if fmt is not None:
        key = _target(fmt)
        return from_json(text) if key == "json" else get_solver(key).read(text)
    body = card_body(text)
    if body.lstrip().startswith("{"):
        return from_json(text)
    for rec in records():
        if rec.sniff(body):
            return rec.read(text)
    raise ValueError(f"cannot tell the card format: give fmt= one of {', '.join(FORMATS)}")


def _solver_modules() -> list:
    """The public modules of this package that define a solver ``RECORD``, in the order of
    their ``ORDER`` (default: after the ordered ones), then of their names."""
    found = []
    for info in pkgutil.iter_modules(__path__):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        if isinstance(getattr(module, "RECORD", None), Solver):
            found.append(module)
    return sorted(found, key=lambda m: (getattr(m, "ORDER", float("inf")), m.__name__))


# each solver module registers its record and lends the package its writers and readers
for _module in _solver_modules():
    register_solver(_module.RECORD)
    for _name in getattr(_module, "__all__", ()):
        if _name.startswith(("to_", "from_")) and _name not in __all__:
            globals()[_name] = getattr(_module, _name)
            __all__.append(_name)
del _module, _name
