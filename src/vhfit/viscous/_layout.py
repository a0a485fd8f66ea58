"""The parameter layout of a model with Prony terms: which value of a parameter vector is what.

A parameter vector holds the hyperelastic law's constants first, then one pair per Prony
term, ``G1, tau1, G2, tau2, ...`` (docs/theory.md §3). The moduli G_i are *amplitudes*:
the stress is linear in them, they are >= 0 and a separable search solves them by
non-negative least squares. The relaxation times τ_i are *times*: > 0 s, searched in
log10 τ. :class:`ParamLayout` is the one description of that layout: the names, their
units and roles, where each sits in a vector (:meth:`ParamLayout.split`,
:meth:`ParamLayout.assemble`), the log10 view of the times, and the parse of a Prony
term's name.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

__all__ = ["ParamLayout", "Term", "AMPLITUDE", "TIME", "LAW"]

#: Role of a Prony modulus G_i: linear in the stress, >= 0, solved by NNLS.
AMPLITUDE = "amplitude"
#: Role of a relaxation time τ_i: > 0 s, searched in log10.
TIME = "time"
#: Role of a hyperelastic law's constant.
LAW = "law"

#: A Prony term's parameter name: its role's prefix and its number (1, 2, ..., no 0).
_NAME = re.compile(r"^(G|tau)([1-9][0-9]*)$")
_PREFIX = {AMPLITUDE: "G", TIME: "tau"}
_ROLE = {v: k for k, v in _PREFIX.items()}


@dataclass(frozen=True)
class Term:
    """A Prony term's parameter, as :meth:`ParamLayout.parse` reads its name.

    Attributes
    ----------
    role : str
        :data:`AMPLITUDE` (``G<i>``) or :data:`TIME` (``tau<i>``).
    index : int
        The term's index from 0 (``tau2`` is the time of term 1).
    """

    role: str
    index: int


@dataclass(frozen=True)
class ParamLayout:
    """The layout ``[law constants..., G1, tau1, ..., GN, tauN]`` of a parameter vector.

    Parameters
    ----------
    law_names : sequence of str
        The hyperelastic law's constants, in order.
    law_units : sequence of str
        Their units, one per constant.
    n_terms : int
        Number N >= 0 of Prony terms.

    Examples
    --------
    >>> lay = ParamLayout(("C10", "C01"), ("MPa", "MPa"), 2)
    >>> lay.names
    ('C10', 'C01', 'G1', 'tau1', 'G2', 'tau2')
    >>> law, G, tau = lay.split([0.1, 0.05, 2.0, 1e-3, 1.0, 1.0])
    >>> law.tolist(), G.tolist(), tau.tolist()
    ([0.1, 0.05], [2.0, 1.0], [0.001, 1.0])
    >>> lay.assemble(law, G, tau).tolist()
    [0.1, 0.05, 2.0, 0.001, 1.0, 1.0]
    >>> ParamLayout.parse("tau2"), ParamLayout.parse("C10")
    (Term(role='time', index=1), None)
    """

    law_names: tuple[str, ...]
    law_units: tuple[str, ...]
    n_terms: int = 0

    #: The roles (:data:`AMPLITUDE`, :data:`TIME`, :data:`LAW`), for use by name.
    AMPLITUDE: ClassVar[str] = AMPLITUDE
    TIME: ClassVar[str] = TIME
    LAW: ClassVar[str] = LAW
    #: Units of a Prony modulus and of a relaxation time.
    AMPLITUDE_UNIT: ClassVar[str] = "MPa"
    TIME_UNIT: ClassVar[str] = "s"

    def __post_init__(self):
        object.__setattr__(self, "law_names", tuple(self.law_names))
        object.__setattr__(self, "law_units", tuple(self.law_units))
        n = self.n_terms
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise ValueError(f"n_terms = {n!r} must be a whole number >= 0")
        object.__setattr__(self, "n_terms", int(n))
        if len(self.law_units) != len(self.law_names):
            raise ValueError(f"{len(self.law_names)} law constants {list(self.law_names)} "
                             f"but {len(self.law_units)} units {list(self.law_units)}")

    @classmethod
    def of(cls, law: Any, n_terms: int) -> ParamLayout:
        """The layout of a hyperelastic law (its ``param_names`` and ``units``) with
        ``n_terms`` Prony terms."""
        return cls(tuple(law.param_names), tuple(law.units), n_terms)

    def with_terms(self, n_terms: int) -> ParamLayout:
        """The same law with ``n_terms`` Prony terms."""
        return ParamLayout(self.law_names, self.law_units, n_terms)

    # -------------------------------------------------------------- names, units, roles
    @staticmethod
    def name(role: str, index: int) -> str:
        """The name of term ``index``'s (from 0) parameter of ``role``: ``name(TIME, 1)``
        is ``"tau2"``."""
        return f"{_PREFIX[role]}{index + 1}"

    @staticmethod
    def amplitude_name(index: int) -> str:
        """``"G<index + 1>"``, the modulus of term ``index`` (from 0)."""
        return ParamLayout.name(AMPLITUDE, index)

    @staticmethod
    def time_name(index: int) -> str:
        """``"tau<index + 1>"``, the relaxation time of term ``index`` (from 0)."""
        return ParamLayout.name(TIME, index)

    def term_names(self) -> tuple[str, ...]:
        """The Prony terms' names, ``G1, tau1, ..., GN, tauN``."""
        return tuple(self.name(role, i) for i in range(self.n_terms) for role in (AMPLITUDE, TIME))

    @property
    def names(self) -> tuple[str, ...]:
        """Every parameter's name, in vector order."""
        return self.law_names + self.term_names()

    @property
    def units(self) -> tuple[str, ...]:
        """Every parameter's unit, in vector order."""
        return self.law_units + (self.AMPLITUDE_UNIT, self.TIME_UNIT) * self.n_terms

    @property
    def roles(self) -> tuple[str, ...]:
        """Every parameter's role (:data:`LAW`, :data:`AMPLITUDE`, :data:`TIME`)."""
        return (LAW,) * self.n_law + (AMPLITUDE, TIME) * self.n_terms

    @property
    def n_law(self) -> int:
        """Number of the law's constants (they come first)."""
        return len(self.law_names)

    @property
    def n_params(self) -> int:
        return self.n_law + 2 * self.n_terms

    # ---------------------------------------------------------------------- positions
    @property
    def law(self) -> slice:
        """Where the law's constants sit in a vector (index its last axis with it)."""
        return slice(0, self.n_law)

    @property
    def amplitudes(self) -> slice:
        """Where the moduli G_i sit in a vector (index its last axis with it)."""
        return slice(self.n_law, None, 2)

    @property
    def times(self) -> slice:
        """Where the relaxation times τ_i sit in a vector (index its last axis with it)."""
        return slice(self.n_law + 1, None, 2)

    def amplitude_index(self, index: int) -> int:
        """Position of term ``index``'s (from 0) modulus in a vector."""
        return self.n_law + 2 * index

    def time_index(self, index: int) -> int:
        """Position of term ``index``'s (from 0) relaxation time in a vector."""
        return self.n_law + 2 * index + 1

    def term(self, index: int) -> slice:
        """Where term ``index``'s (from 0) pair (G, τ) sits in a vector."""
        k = self.amplitude_index(index)
        return slice(k, k + 2)

    def split(self, x) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(law constants, G, τ) of parameter array(s) of shape (..., n_params), views.

        The last axis is read by position: a vector of fewer terms (a pruned fit) gives
        the terms it holds.
        """
        x = np.asarray(x, dtype=np.float64)
        return x[..., self.law], x[..., self.amplitudes], x[..., self.times]

    def assemble(self, law, G, tau) -> np.ndarray:
        """Parameter array(s) (..., n_params) from the law's constants (..., n_law), the
        moduli (..., N) and the relaxation times (..., N): the inverse of :meth:`split`.
        """
        law, G, tau = (np.asarray(a, dtype=np.float64) for a in (law, G, tau))
        for what, a, n in (("law constants", law, self.n_law), ("G", G, self.n_terms),
                           ("tau", tau, self.n_terms)):
            if a.shape[-1:] != (n,):
                raise ValueError(f"{what} has shape {a.shape}; expected {n} values on the "
                                 f"last axis ({self!r})")
        lead = np.broadcast_shapes(law.shape[:-1], G.shape[:-1], tau.shape[:-1])
        x = np.empty(lead + (self.n_params,))
        x[..., self.law], x[..., self.amplitudes], x[..., self.times] = law, G, tau
        return x

    def to_log(self, x) -> np.ndarray:
        """A copy of parameter array(s) with log10 τ in place of τ (the search's view)."""
        z = np.array(x, dtype=np.float64, copy=True)
        z[..., self.times] = np.log10(z[..., self.times])
        return z

    def from_log(self, z) -> np.ndarray:
        """A copy of array(s) with log10 τ with τ in its place (the inverse of
        :meth:`to_log`)."""
        x = np.array(z, dtype=np.float64, copy=True)
        x[..., self.times] = 10.0 ** x[..., self.times]
        return x

    # ------------------------------------------------------------------------ parsing
    @staticmethod
    def parse(name: Any) -> Term | None:
        """The Prony term a parameter's name names (``G<i>``, ``tau<i>``, i >= 1), else
        None (a law's constant, or no parameter at all)."""
        m = _NAME.match(str(name))
        return None if m is None else Term(_ROLE[m.group(1)], int(m.group(2)) - 1)

    @staticmethod
    def is_time(name: Any) -> bool:
        """Whether ``name`` is a relaxation time's (``tau1``, ``tau2``, ...)."""
        t = ParamLayout.parse(name)
        return t is not None and t.role == TIME

    @staticmethod
    def count_terms(names: Iterable[Any]) -> int:
        """The number N of Prony terms that parameter names hold: the highest term
        number; every ``G<i>`` and ``tau<i>`` with i <= N must be among them (one-line
        ValueError naming the missing). The law's names are left aside.

        Examples
        --------
        >>> ParamLayout.count_terms(["C10", "G1", "tau1", "G2", "tau2"])
        2
        >>> ParamLayout.count_terms(["G1", "tau1", "G2"])
        Traceback (most recent call last):
        ...
        ValueError: Prony terms need G_i and tau_i for i = 1..2: missing tau2
        """
        names = list(names)
        terms = {t for t in map(ParamLayout.parse, names) if t is not None}
        n = 1 + max((t.index for t in terms), default=-1)
        if n > len(names):  # (G1000000000 alone: a gap too long to list)
            top = next(ParamLayout.name(t.role, t.index) for t in terms if t.index == n - 1)
            raise ValueError(f"{top}: Prony terms need G_i and tau_i for i = 1..{n}, but only "
                             f"{len(names)} parameters are given: check the term numbers")
        missing = [ParamLayout.name(role, i) for i in range(n) for role in (AMPLITUDE, TIME)
                   if Term(role, i) not in terms]
        if missing:
            raise ValueError(f"Prony terms need G_i and tau_i for i = 1..{n}: missing "
                             f"{', '.join(missing)}")
        return n
