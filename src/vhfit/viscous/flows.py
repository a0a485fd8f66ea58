"""Flow rules of the viscous networks: a registry users can extend (Abaqus's LAW=USER).

A flow gives the equivalent creep strain rate ε̇_cr of a network (the rate of ln λ_cr in
uniaxial tension) from

* ``q``: q̃, the Mises equivalent of the network's deviatoric Kirchhoff stress (MPa, ≥ 0);
* ``lam_cr``: λ_cr = sqrt(tr C_cr / 3), the network's effective creep stretch (≥ 1);
* ``eps_bar``: ε̄_cr = ∫ ε̇_cr dt, the accumulated equivalent creep strain (≥ 0);

and its constants, in the order of Abaqus's data line. A flow is a plain numpy function
of those, registered by name::

    @register("my_linear", params=("eta",), units=("MPa s",), bounds=((0.0, inf),))
    def my_linear(q, lam_cr, eps_bar, eta):
        "ε̇ = q̃ / η: a Newtonian dashpot"
        return q / eta

Built in (Abaqus spellings accepted by :func:`get`, case-insensitive):

* ``bergstrom_boyce`` (``BERGSTROM``, ``BERGSTROM-BOYCE``; ``A, m, C, E``):
  ε̇ = A (λ_cr − 1 + E)^C q̃^m;
* ``strain`` (``STRAIN``; ``A, n, m``): ε̇ = (A q̃^n [(m + 1) ε̄]^m)^(1/(m+1)), strain
  hardening; singular at ε̄ = 0 when m < 0 (the integrator starts it analytically);
* ``power_law`` (``POWER LAW``, ``POWERLAW``; ``q0, n, m, a, eps0``):
  ε̇ = ε̇0 ((q̃/(q0 + a⟨p⟩))^n [(m + 1) ε̄]^m)^(1/(m+1)). The networks are
  incompressible, so their pressure is not tracked: p = 0 here, and the law is STRAIN
  with A = ε̇0^(m+1) q0^(−n);
* ``hyperb`` (``HYPERB``; ``A, B, n``): ε̇ = A (sinh(B q̃))^n.
"""

from __future__ import annotations

import inspect
import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Flow", "register", "get", "available", "unregister"]

_POS = (0.0, math.inf)
_KINEMATICS = 3  # q, lam_cr, eps_bar


@dataclass(frozen=True, eq=False)
class Flow:
    """A registered flow rule (see :func:`register`).

    Attributes
    ----------
    name : str
        Canonical registry name (``"bergstrom_boyce"``).
    param_names : tuple of str
        The constants, in the order of Abaqus's data line.
    units : tuple of str
    bounds : tuple of (float, float)
        Physical range of each constant (inclusive; used to refuse bad input).
    abaqus : str or None
        The word Abaqus writes after ``LAW=`` (None: no Abaqus form, a user flow).
    rate : callable
        ``rate(q, lam_cr, eps_bar, *constants)`` -> ε̇_cr, numpy-vectorised.
    aliases : tuple of str
        Other names :func:`get` accepts.
    validate : callable or None
        ``validate(*constants)`` -> a reason (str) the constants are refused, or None:
        conditions the bounds cannot state (an open end, a combination).
    """

    name: str
    param_names: tuple[str, ...]
    units: tuple[str, ...]
    bounds: tuple[tuple[float, float], ...]
    abaqus: str | None
    rate: Callable
    aliases: tuple[str, ...] = ()
    validate: Callable | None = None
    doc: str = field(default="", repr=False)

    @property
    def n_params(self) -> int:
        return len(self.param_names)

    def __reduce__(self):
        # flows travel to worker processes by name, as the hyperelastic laws do
        return (get, (self.name,))

    def check(self, constants) -> np.ndarray:
        """Validate one set of constants; return it as an array.

        Examples
        --------
        >>> get("strain").check([1e-5, 1.0, -0.5]).tolist()
        [1e-05, 1.0, -0.5]
        >>> get("hyperb").check([1e-5, -0.1, 2.0])
        Traceback (most recent call last):
        ...
        ValueError: B = -0.1 is outside its physical range [0, inf] for flow 'hyperb'
        """
        c = np.asarray(constants, dtype=np.float64)
        if c.shape != (self.n_params,):
            raise ValueError(f"flow {self.name!r} takes {self.n_params} constants "
                             f"{list(self.param_names)}, got {c.size}")
        for name, v, (lo, hi) in zip(self.param_names, c, self.bounds):
            if not np.isfinite(v):
                raise ValueError(f"{name} = {float(v)!r} is not finite (flow {self.name!r})")
            if not lo <= v <= hi:
                raise ValueError(f"{name} = {v:g} is outside its physical range "
                                 f"[{lo:g}, {hi:g}] for flow {self.name!r}")
        reason = self.validate(*c.tolist()) if self.validate is not None else None
        if reason:
            raise ValueError(f"flow {self.name!r}: {reason}")
        return c


# ---------------------------------------------------------------------- registry
_REGISTRY: dict[str, Flow] = {}
_ALIASES: dict[str, str] = {}  # normalised spelling -> canonical name


def _key(name: str) -> str:
    """Spelling-insensitive key: case, spaces, hyphens and underscores ignored
    (``"POWER LAW"``, ``"power_law"`` and ``"PowerLaw"`` are one name)."""
    return re.sub(r"[\s_\-]+", "", str(name)).casefold()


def register(name: str, *, params: Sequence[str], units: Sequence[str] | None = None,
             bounds: Sequence[tuple[float, float]] | None = None, abaqus: str | None = None,
             aliases: Sequence[str] = (), validate: Callable | None = None,
             overwrite: bool = False) -> Callable[[Callable], Callable]:
    """Register a flow rule ``rate(q, lam_cr, eps_bar, *constants)`` by name (decorator).

    Parameters
    ----------
    name : str
        Registry name.
    params : sequence of str
        Names of the constants, in the order the function takes them after its three
        kinematic arguments (and of the solver's data line).
    units, bounds : optional
        One entry per constant (default: "1" and (-inf, inf)).
    abaqus : str, optional
        The ``LAW=`` word of Abaqus, when Abaqus has this flow built in.
    aliases : sequence of str
        Other spellings :func:`get` accepts (the Abaqus word is one already).
    validate : callable, optional
        ``validate(*constants)`` -> reason (str) to refuse, or None.
    overwrite : bool
        Allow replacing a registered flow.

    Returns
    -------
    decorator
        Returns the function unchanged, registered as a :class:`Flow`.

    Examples
    --------
    >>> @register("newtonian", params=("eta",), units=("MPa s",), bounds=((0.0, math.inf),),
    ...           overwrite=True)
    ... def newtonian(q, lam_cr, eps_bar, eta):
    ...     return q / eta
    >>> float(get("NEWTONIAN").rate(2.0, 1.0, 0.0, 4.0))
    0.5
    >>> unregister("newtonian")
    """

    def decorator(fn: Callable) -> Callable:
        if not isinstance(name, str) or not name:
            raise ValueError("flow name must be a non-empty string")
        p = tuple(params)
        n = len(p)
        args = list(inspect.signature(fn).parameters)
        if len(args) != _KINEMATICS + n:
            raise ValueError(f"flow {name!r}: the rate function takes (q, lam_cr, eps_bar, "
                             f"*constants) with {n} constants {list(p)}, "
                             f"its signature has {len(args)} arguments")
        u = tuple(units) if units is not None else ("1",) * n
        b = (tuple(tuple(map(float, x)) for x in bounds) if bounds is not None
             else ((-math.inf, math.inf),) * n)
        if len(u) != n or len(b) != n:
            raise ValueError(f"flow {name!r}: units and bounds need one entry per "
                             f"constant {list(p)}")
        spellings = [name, *aliases] + ([abaqus] if abaqus else [])
        for s in spellings:
            owner = _ALIASES.get(_key(s))
            if owner is not None and owner != name and not overwrite:
                raise ValueError(f"the flow name {s!r} is taken by {owner!r}; "
                                 "pass overwrite=True to replace it")
        if name in _REGISTRY and not overwrite:
            raise ValueError(f"a flow named {name!r} is already registered; "
                             "pass overwrite=True to replace it")
        if name in _REGISTRY:
            unregister(name)
        _REGISTRY[name] = Flow(name=name, param_names=p, units=u, bounds=b, abaqus=abaqus,
                               rate=fn, aliases=tuple(aliases), validate=validate,
                               doc=inspect.getdoc(fn) or "")
        for s in spellings:
            _ALIASES[_key(s)] = name
        return fn

    return decorator


def get(name: str | Flow) -> Flow:
    """The registered flow of this name or spelling (case, spaces, hyphens ignored).

    Examples
    --------
    >>> get("BERGSTROM").name, get("power law").name, get("POWERLAW").abaqus
    ('bergstrom_boyce', 'power_law', 'POWER LAW')
    """
    if isinstance(name, Flow):
        return name
    canonical = _ALIASES.get(_key(name))
    if canonical is None:
        raise ValueError(f"unknown flow {name!r}; registered: {', '.join(available())}")
    return _REGISTRY[canonical]


def available() -> tuple[str, ...]:
    """Names of the registered flows, in registration order.

    Examples
    --------
    >>> available()[:4]
    ('bergstrom_boyce', 'strain', 'power_law', 'hyperb')
    """
    return tuple(_REGISTRY)


def unregister(name: str) -> None:
    """Remove a flow (and its spellings) from the registry."""
    canonical = get(name).name
    del _REGISTRY[canonical]
    for k in [k for k, v in _ALIASES.items() if v == canonical]:
        del _ALIASES[k]


# ---------------------------------------------------------------------- built-in flows
def _bb_valid(A, m, C, E):
    if E <= 0.0 and C < 0.0:
        return f"E = {E:g} with C = {C:g} < 0 makes the rate infinite at λ_cr = 1 (take E > 0)"
    return None


def _hardening_valid(*c, m_index):
    m = c[m_index]
    return None if m > -1.0 else f"m = {m:g} must be > -1 (the rate has 1/(m + 1))"


@register("bergstrom_boyce", params=("A", "m", "C", "E"),
          units=("1/(s MPa^m)", "1", "1", "1"),
          bounds=(_POS, _POS, (-1.0, 0.0), _POS), abaqus="BERGSTROM-BOYCE",
          aliases=("BERGSTROM",), validate=_bb_valid)
def bergstrom_boyce(q, lam_cr, eps_bar, A, m, C, E):
    """Bergström–Boyce: ε̇ = A (λ_cr − 1 + E)^C q̃^m."""
    return A * (lam_cr - 1.0 + E) ** C * q**m


@register("strain", params=("A", "n", "m"), units=("1/(s MPa^n)", "1", "1"),
          bounds=(_POS, _POS, (-1.0, 0.0)), abaqus="STRAIN",
          validate=lambda A, n, m: _hardening_valid(A, n, m, m_index=2))
def strain(q, lam_cr, eps_bar, A, n, m):
    """Strain hardening: ε̇ = (A q̃^n [(m + 1) ε̄]^m)^(1/(m+1))."""
    return (A * q**n * ((m + 1.0) * eps_bar) ** m) ** (1.0 / (m + 1.0))


@register("power_law", params=("q0", "n", "m", "a", "eps0"),
          units=("MPa", "1", "1", "1", "1/s"),
          bounds=(_POS, _POS, (-1.0, 0.0), _POS, _POS), abaqus="POWER LAW",
          validate=lambda *c: _hardening_valid(*c, m_index=2))
def power_law(q, lam_cr, eps_bar, q0, n, m, a, eps0):
    """Power law: ε̇ = ε̇0 ((q̃/(q0 + a⟨p⟩))^n [(m + 1) ε̄]^m)^(1/(m+1)), p = 0
    (incompressible networks: the pressure is not tracked, so ``a`` has no effect)."""
    return eps0 * ((q / q0) ** n * ((m + 1.0) * eps_bar) ** m) ** (1.0 / (m + 1.0))


@register("hyperb", params=("A", "B", "n"), units=("1/s", "1/MPa", "1"),
          bounds=(_POS, _POS, _POS), abaqus="HYPERB")
def hyperb(q, lam_cr, eps_bar, A, B, n):
    """Hyperbolic sine: ε̇ = A (sinh(B q̃))^n."""
    return A * np.sinh(B * q) ** n
