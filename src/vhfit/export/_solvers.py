"""The solver registry: one :class:`Solver` record per FE solver vhfit writes cards for.

A record says everything the rest of vhfit needs to know about a solver: its names, the
file its card goes to, the viscoelastic formulation it integrates the Prony series in
(:mod:`vhfit.formulations`), its card writer and reader, how to recognise its card, the
laws its cards hold, whether its card takes a time–temperature shift, a density and a
bulk modulus, and its card variants. :func:`vhfit.export.export`, :func:`vhfit.export.parse`,
the card check (:mod:`vhfit.export.check`), the shift writer (:mod:`vhfit.export.shift`),
:data:`vhfit.formulations.SOLVER_FORMULATIONS` and the command line read only from here.
Each solver module of :mod:`vhfit.export` defines its own record (``RECORD``), which the
package registers when it finds the module.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field

from vhfit.formulations import FORMULATIONS, SOLVER_FORMULATIONS

__all__ = ["Solver", "register_solver", "unregister_solver", "get_solver", "solver_of",
           "solvers", "records", "names", "card_body", "LiveMapping"]


@dataclass(frozen=True)
class Solver:
    """An FE solver vhfit writes material cards for.

    Attributes
    ----------
    name : str
        Registry name, a lower-case word (``--for NAME``, ``export(..., to=NAME)``).
    label : str
        How the solver is written in messages and card comments.
    suffix : str
        File suffix of its card (``vhfit fit`` writes ``NAME + suffix``).
    formulation : str
        The registered formulation the solver integrates the card's Prony series in.
    write : callable
        ``write(model, params, *, name, notes, comments, **fields) -> str``: the card of
        a calibrated model (a :class:`vhfit.ViscoHyperelastic` and its parameters as a
        dict; ``notes``: warning lines first; ``comments``: lines after the header);
        ``fields`` are the keywords below that the record declares (``density``,
        ``poisson`` and ``bulk_modulus``, a variant's keyword).
    read : callable
        ``read(text) -> (ViscoHyperelastic, params)``: the card back in vhfit's convention.
    sniff : callable
        ``sniff(body) -> bool``: whether a card is this solver's, from its body (the
        lines that are not comments, upper case; :func:`card_body`).
    laws : tuple of str
        The hyperelastic laws its cards hold.
    comment : str
        Its comment prefix (comment lines are skipped when recognising any card).
    aliases : tuple of str
        Other names accepted for it (e.g. its name written with a hyphen).
    shift : callable or None
        ``shift(card, law, mat) -> str``: the card with a WLF time–temperature shift
        (:class:`vhfit.tts.WLF`); None: its cards take none.
    density : bool
        Its writer takes ``density=`` (tonne/mm³).
    bulk_modulus : bool
        Its writer takes ``poisson=`` and ``bulk_modulus=``.
    variants : mapping of str to (str, str)
        Writer keyword -> (label, help) of a card variant, written beside the card on
        request (``vhfit fit --NAME-KEYWORD``) to the file ``NAME_KEYWORD + suffix``.
    test_data : callable or None
        ``test_data(curves, law) -> str``: equilibrium curves as the solver's own
        test-data input for its law fitting (``vhfit fit`` writes it to
        ``NAME_test_data + suffix`` when the data hold such curves); None: none.
    networks : bool
        Its writer also takes a network model (:class:`vhfit.viscous.NetworkModel`, with
        ``params`` None) and its reader reads such cards back.
    no_networks : str
        Why its cards hold no network model (when ``networks`` is False): said in the
        one-line refusal.
    """

    name: str
    label: str
    suffix: str
    formulation: str
    write: Callable[..., str]
    read: Callable[[str], tuple]
    sniff: Callable[[str], bool]
    laws: tuple = ()
    comment: str = "#"
    aliases: tuple = ()
    shift: Callable[..., str] | None = None
    density: bool = False
    bulk_modulus: bool = False
    variants: Mapping = field(default_factory=dict)
    test_data: Callable[..., str] | None = None
    networks: bool = False
    no_networks: str = ""

    @property
    def card_file(self) -> str:
        """The file name of its card in a results folder."""
        return f"{self.name}{self.suffix}"

    def options(self, density=None, poisson=None, bulk_modulus=None) -> dict:
        """The writer keywords among density, Poisson's ratio and bulk modulus that this
        solver's card takes (the others are left out)."""
        out = {}
        if self.density:
            out["density"] = density
        if self.bulk_modulus:
            out.update(poisson=poisson, bulk_modulus=bulk_modulus)
        return out


#: name -> record, in registration order.
_SOLVERS: dict[str, Solver] = {}


def register_solver(solver: Solver) -> Solver:
    """Register a solver record (its formulation enters
    :data:`vhfit.formulations.SOLVER_FORMULATIONS`).

    Parameters
    ----------
    solver : Solver
        The record; its name, aliases and variant keys must be new lower-case words.

    Returns
    -------
    Solver
        The record.

    Examples
    --------
    >>> from vhfit.export import Solver, register_solver, unregister_solver, export
    >>> def write(model, params, *, name="M", notes=(), comments=()):
    ...     return f"# {name}\\n" + "".join(f"{k} {v!r}\\n" for k, v in params.items())
    >>> rec = register_solver(Solver(
    ...     name="doc_solver", label="DocSolver", suffix=".txt", formulation="hereditary",
    ...     write=write, read=None, sniff=lambda body: body.startswith("C10"),
    ...     laws=("neo_hooke",)))
    >>> import vhfit
    >>> print(export(vhfit.ViscoHyperelastic("neo_hooke", 0), {"C10": 0.5}, to="doc_solver"))
    # M
    C10 0.5
    <BLANKLINE>
    >>> unregister_solver("doc_solver")
    """
    if not isinstance(solver, Solver):
        raise TypeError(f"register_solver takes a vhfit.export.Solver, got {solver!r}")
    names = [solver.name, *solver.aliases]
    for n in names:
        if not (isinstance(n, str) and n == n.lower() and n.replace("-", "_").isidentifier()):
            raise ValueError(f"solver name {n!r}: give a lower-case word such as 'my_solver'")
        if n == "json" or _lookup(n) is not None:
            raise ValueError(f"solver name {n!r} is taken: choose another name, or "
                             f"unregister_solver({n!r}) first")
    if solver.formulation not in FORMULATIONS:
        raise ValueError(f"solver {solver.name!r}: formulation {solver.formulation!r} is not "
                         f"registered (known: {', '.join(FORMULATIONS)})")
    for part in ("write", "read", "sniff"):
        f = getattr(solver, part)
        if part != "read" and not callable(f):
            raise TypeError(f"solver {solver.name!r}: {part} must be callable")
    _SOLVERS[solver.name] = solver
    SOLVER_FORMULATIONS[solver.name] = solver.formulation
    return solver


def unregister_solver(name: str) -> None:
    """Remove a registered solver (and its entry of SOLVER_FORMULATIONS)."""
    rec = get_solver(name)
    del _SOLVERS[rec.name]
    SOLVER_FORMULATIONS.pop(rec.name, None)


def _lookup(name: str) -> Solver | None:
    key = str(name).strip().lower()
    if key in _SOLVERS:
        return _SOLVERS[key]
    for rec in _SOLVERS.values():
        if key in rec.aliases:
            return rec
    return None


def get_solver(name) -> Solver:
    """The solver registered under ``name`` or one of its aliases (a Solver passes).

    Examples
    --------
    >>> rec = next(records())
    >>> get_solver(rec.name.upper()) is rec, get_solver(rec) is rec
    (True, True)
    >>> all(get_solver(alias) is r for r in records() for alias in r.aliases)
    True
    """
    if isinstance(name, Solver):
        return name
    rec = _lookup(name)
    if rec is None:
        raise ValueError(f"unknown solver {name!r}: choose one of {', '.join(_SOLVERS)}")
    return rec


def solver_of(key: str) -> Solver:
    """The solver of a card key: a solver's name or alias, or ``NAME_VARIANT``.

    Examples
    --------
    >>> rec = next(r for r in records() if r.variants)
    >>> solver_of(f"{rec.name}_{next(iter(rec.variants))}") is rec
    True
    """
    rec = _lookup(key)
    if rec is not None:
        return rec
    k = str(key).strip().lower()
    for rec in _SOLVERS.values():
        if any(k == f"{rec.name}_{v}" for v in rec.variants):
            return rec
    raise ValueError(f"solver {key!r}: choose one of {', '.join(_SOLVERS)}")


def solvers() -> tuple[str, ...]:
    """The registered solvers' names, in registration order.

    Examples
    --------
    >>> solvers() == tuple(rec.name for rec in records()) and len(solvers()) > 0
    True
    """
    return tuple(_SOLVERS)


def records() -> Iterator[Solver]:
    """The registered records, in registration order."""
    return iter(tuple(_SOLVERS.values()))


def card_body(text: str) -> str:
    """A card's lines that are no comment of any registered solver, upper case.

    Examples
    --------
    >>> card_body("** comment\\n*Hyperelastic, neo hooke\\n0.5,\\n")
    '*HYPERELASTIC, NEO HOOKE\\n0.5,'
    """
    prefixes = tuple(r.comment for r in _SOLVERS.values() if r.comment)
    return "\n".join(ln for ln in text.splitlines()
                     if ln.strip() and not ln.lstrip().startswith(prefixes)).upper()


class _Live:
    """A read-only view built anew from the solver registry at each use, so that it
    follows solvers registered later: a subclass gives :meth:`_now`, the view now."""

    def _now(self):
        raise NotImplementedError

    def __getitem__(self, key):
        return self._now()[key]

    def __len__(self) -> int:
        return len(self._now())

    def __repr__(self) -> str:
        return repr(self._now())


class LiveMapping(_Live, Mapping):
    """A read-only mapping that follows the solver registry (:class:`_Live`)."""

    def __iter__(self) -> Iterator:
        return iter(self._now())


class _Names(_Live, Sequence):
    """The names of the registered solvers that ``keep`` accepts, read at each use."""

    def __init__(self, keep: Callable[[Solver], bool]):
        self._keep = keep

    def _now(self) -> tuple[str, ...]:
        return tuple(r.name for r in _SOLVERS.values() if self._keep(r))


def names(keep: Callable[[Solver], bool] | None = None) -> Sequence[str]:
    """A live view of the names of the registered solvers (those ``keep`` accepts).

    Examples
    --------
    >>> view = names(lambda rec: rec.shift is not None)
    >>> list(view) == [rec.name for rec in records() if rec.shift is not None]
    True
    """
    return _Names(keep or (lambda rec: True))
