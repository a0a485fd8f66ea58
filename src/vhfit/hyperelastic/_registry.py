"""The :class:`Hyperelastic` law and the registry of laws by name (``@register``)."""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from vhfit._derivatives import central, invariant_gradient, outside_domain, stretch_gradient
from vhfit._fixed import remembered

__all__ = ["Hyperelastic", "register", "get", "available", "unregister", "invariants"]

_INVARIANT_ARGS = ("I1", "I2")
_STRETCH_ARGS = (("l1", "l2", "l3"), ("lambda1", "lambda2", "lambda3"), ("λ1", "λ2", "λ3"))


def _lateral(lam: np.ndarray) -> np.ndarray:
    """λ^(−1/2), the lateral stretches of uniaxial tension; for a ``lam`` that cannot
    change (a batch's samples) the same read-only array every time (:mod:`vhfit._fixed`), so
    that what a law derives from its stretches is remembered too."""
    def lateral():
        l2 = lam**-0.5
        l2.flags.writeable = False
        return l2

    return remembered("lateral", (lam,), lateral)


def invariants(stretch) -> tuple[np.ndarray, np.ndarray]:
    """I1 = λ² + 2/λ and I2 = 2λ + 1/λ² on the incompressible uniaxial path.

    Examples
    --------
    >>> I1, I2 = invariants([1.0, 2.0])
    >>> I1.tolist(), I2.tolist()
    ([3.0, 5.0], [3.0, 4.25])
    """
    lam = np.asarray(stretch, dtype=np.float64)
    return lam**2 + 2.0 / lam, 2.0 * lam + 1.0 / lam**2


@dataclass(frozen=True, eq=False)
class Hyperelastic:
    """A registered hyperelastic model (see :func:`register`).

    Attributes
    ----------
    name : str
    param_names : tuple of str
    units : tuple of str
    bounds : tuple of (float, float)
        Physical bounds of each constant (used to reject bad input, not to fit).
    kind : {"invariant", "stretch"}
    energy : callable
        W(I1, I2, *c) or W(l1, l2, l3, *c).
    derivatives : callable or None
        Closed form of the derivatives: for invariant models (I1, I2, *c) ->
        (∂W/∂I1, ∂W/∂I2); for stretch models (l1, l2, l3, *c) ->
        (λ1 ∂W/∂λ1, λ2 ∂W/∂λ2, λ3 ∂W/∂λ3). None: the complex step.
    general_derivatives : callable or None
        A stretch model's closed form (as :attr:`derivatives`) for every test but the
        uniaxial stress (:meth:`stress`), when :attr:`derivatives` is None: a law whose
        recorded uniaxial calibrations keep the complex step bit for bit still evaluates
        the other tests, simple shear among them, by its closed form and compiled sums
        (:attr:`kirchhoff_derivatives`).
    linear : bool
        Whether σ_h is linear in all of the constants (``basis`` gives its columns).
    linear_params : tuple of str
        The constants σ_h is linear in when the others are held fixed (all of them for
        the polynomial laws, the μ's of Ogden, μ of Arruda–Boyce and Gent): the
        separable calibration solves these by least squares and searches the rest.
    example : tuple of float
        A typical set of constants (docs, tests, starting points).
    fewer : str or None
        The registered law that is this one with its last term left out (``ogden3`` ->
        ``ogden2``), the suggestion when the data cannot tell terms apart.
    term : int
        Constants per term when W is a sum of like terms, each linear in its first
        constant (Ogden: ``mu_p, alpha_p``); 0 otherwise. Two such terms whose other
        constants coincide act as one term with the sum of the first constants: a fit
        merges them into :attr:`fewer` (docs/theory.md).
    compressible : bool
        The law has a volumetric part and can deform at J ≠ 1. False for every built-in
        law (they are incompressible): tests that change the volume, such as confined
        compression, are refused for them (:func:`vhfit.modes.refusal_for`).
    contains : tuple of (str, dict)
        The registered laws this one contains, each with the map of its constants into
        this law's (:meth:`embed`): ``("neo_hooke", {"C10": "C10"})`` for Yeoh. Each
        value is the smaller law's constant of that name, a number, or a callable of
        the smaller law's constants (a dict); this law's constants the map leaves out
        are 0. A calibration seeds its search with the contained laws' fits
        (docs/optimizer.md, "Nesting").
    """

    name: str
    param_names: tuple[str, ...]
    units: tuple[str, ...]
    bounds: tuple[tuple[float, float], ...]
    kind: str
    energy: Callable
    derivatives: Callable | None = None
    linear: bool = False
    example: tuple[float, ...] = ()
    mu0: Callable | None = None
    doc: str = field(default="", repr=False)
    linear_params: tuple[str, ...] = ()
    fewer: str | None = None
    term: int = 0
    compressible: bool = False
    general_derivatives: Callable | None = None
    contains: tuple[tuple[str, Mapping[str, Any]], ...] = ()

    @property
    def n_params(self) -> int:
        return len(self.param_names)

    @property
    def kirchhoff_derivatives(self) -> Callable | None:
        """The closed form the tests other than uniaxial use (:attr:`derivatives`, else
        :attr:`general_derivatives`); None: the complex step."""
        return self.derivatives if self.derivatives is not None else self.general_derivatives

    @property
    def linear_index(self) -> tuple[int, ...]:
        """Positions of :attr:`linear_params` in :attr:`param_names`."""
        return tuple(self.param_names.index(n) for n in self.linear_params)

    def __reduce__(self):
        # registered models travel to worker processes by name (their functions may be
        # lambdas or closures that do not pickle); the worker's registry resolves them
        return (get, (self.name,))

    # ------------------------------------------------------------------ helpers
    def _columns(self, params) -> tuple[list[np.ndarray], tuple[int, ...]]:
        """Split (..., n_params) constants into columns shaped (..., 1)."""
        p = np.asarray(params, dtype=np.float64)
        if p.ndim == 0 or p.shape[-1] != self.n_params:
            raise ValueError(
                f"model {self.name!r} takes {self.n_params} constants "
                f"{list(self.param_names)}, got shape {p.shape}"
            )
        return [p[..., k, None] for k in range(self.n_params)], p.shape[:-1]

    def _dW_invariant(self, I1, I2, cols):
        return invariant_gradient(self.energy, self.derivatives, I1, I2, cols)

    def _stress_raw(self, lam: np.ndarray, cols) -> np.ndarray:
        if self.kind == "invariant":
            I1, I2 = invariants(lam)
            W1, W2 = self._dW_invariant(I1, I2, cols)
            return 2.0 * (lam**2 - 1.0 / lam) * (W1 + W2 / lam)
        l2 = _lateral(lam)
        # dW1 = λ1 ∂W/∂λ1 and dW2 = λ2 ∂W/∂λ2
        dW1, dW2 = stretch_gradient(self.energy, lam, l2, l2, cols, axes=(0, 1),
                                    closed_form=self.derivatives)
        if self.derivatives is not None:
            return dW1 - dW2
        return np.where(outside_domain(self.energy, lam, l2, l2, *cols), np.nan, dW1 - dW2)

    # ------------------------------------------------------------------- public
    def stress(self, stretch, params) -> np.ndarray:
        """Uniaxial true stress σ_h(λ) in MPa.

        Parameters
        ----------
        stretch : array_like, shape (m,)
            Stretches λ > 0.
        params : array_like, shape (n_params,) or (..., n_params)
            Constants in ``param_names`` order; leading axes are parameter sets.

        Returns
        -------
        ndarray, shape (m,) or (..., m)

        Examples
        --------
        >>> mr = get("mooney_rivlin")
        >>> float(mr.stress([2.0], [0.5, 0.25])[0])   # 2C10(λ²-1/λ) + 2C01(λ-1/λ²)
        4.375
        """
        lam = np.asarray(stretch, dtype=np.float64)
        cols, lead = self._columns(params)
        out = self._stress_raw(lam if lam.ndim == 1 else lam.reshape(-1), cols)
        out = np.broadcast_to(out, lead + (lam.size,))
        return out.reshape(lead + lam.shape)

    def initial_shear_modulus(self, params) -> np.ndarray:
        """μ0 = 2(∂W/∂I1 + ∂W/∂I2) at I1 = I2 = 3 (for stretch models, E∞ / 3).

        Examples
        --------
        >>> float(get("mooney_rivlin").initial_shear_modulus([1.0, 0.5]))
        3.0
        """
        cols, lead = self._columns(params)
        if self.mu0 is not None:
            mu = np.asarray(self.mu0(*cols), dtype=np.float64)
        elif self.kind == "invariant":
            three = np.full((1,), 3.0)
            W1, W2 = self._dW_invariant(three, three, cols)
            mu = 2.0 * (np.asarray(W1) + np.asarray(W2))
        else:
            # E∞ = dσ_h/dλ at λ = 1, by 4th-order central differences (σ_h(1) = 0)
            mu = central(lambda d: self._stress_raw(np.array([1.0 + d]), cols)) / 3.0
        return np.broadcast_to(mu, lead + (1,))[..., 0].copy()

    def check(self, params) -> np.ndarray:
        """Validate one set of constants against the physical bounds; return it as an array.

        Examples
        --------
        >>> get("neo_hooke").check([0.1]).tolist()
        [0.1]
        >>> get("neo_hooke").check([-0.1])
        Traceback (most recent call last):
        ...
        ValueError: C10 = -0.1 is outside its physical range [0, inf] for model 'neo_hooke'
        """
        p = np.asarray(params, dtype=np.float64)
        if p.shape != (self.n_params,):
            raise ValueError(
                f"model {self.name!r} takes {self.n_params} constants "
                f"{list(self.param_names)}, got {p.size}"
            )
        for name, v, (lo, hi) in zip(self.param_names, p, self.bounds):
            if not np.isfinite(v):
                raise ValueError(f"{name} = {float(v)!r} is not finite")
            if not lo <= v <= hi:
                raise ValueError(
                    f"{name} = {v:g} is outside its physical range [{lo:g}, {hi:g}] "
                    f"for model {self.name!r}"
                )
        return p

    def embed(self, smaller: str | Hyperelastic, params) -> np.ndarray:
        """The constants of this law that give the stress of ``smaller`` at ``params``.

        Parameters
        ----------
        smaller : str or Hyperelastic
            A law this one contains (:attr:`contains`).
        params : array_like, shape (n,), or dict
            The smaller law's constants (in its ``param_names`` order, or by name).

        Returns
        -------
        ndarray, shape (n_params,)

        Raises
        ------
        ValueError
            ``smaller`` is not a law this one contains, or ``params`` do not fit it.

        Examples
        --------
        >>> get("ogden").embed("neo_hooke", [0.25]).tolist()   # μ1 = 2 C10, α1 = 2
        [0.5, 2.0]
        >>> get("yeoh").embed("neo_hooke", {"C10": 0.1}).tolist()
        [0.1, 0.0, 0.0]
        """
        small = get(smaller)
        mapping = dict(self.contains).get(small.name)
        if mapping is None:
            held = ", ".join(name for name, _ in self.contains) or "none"
            raise ValueError(f"{self.name!r} does not contain {small.name!r} "
                             f"(it contains: {held})")
        if isinstance(params, Mapping):
            missing = [n for n in small.param_names if n not in params]
            if missing:
                raise ValueError(f"{small.name!r} constants {missing} are missing")
            c = {n: float(params[n]) for n in small.param_names}
        else:
            p = np.asarray(params, dtype=np.float64).reshape(-1)
            if p.size != small.n_params:
                raise ValueError(f"model {small.name!r} takes {small.n_params} constants "
                                 f"{list(small.param_names)}, got {p.size}")
            c = dict(zip(small.param_names, p.tolist()))
        out = np.zeros(self.n_params)
        for name, value in mapping.items():
            k = self.param_names.index(name)
            out[k] = (c[value] if isinstance(value, str) else
                      float(value(c)) if callable(value) else float(value))
        return out

    def basis(self, stretch) -> np.ndarray:
        """For a linear model, the stresses of unit constants: σ_h = params @ basis.

        Returns
        -------
        ndarray, shape (n_params, m)

        Examples
        --------
        >>> get("mooney_rivlin").basis([2.0]).tolist()   # 2(λ² − 1/λ), 2(λ − 1/λ²)
        [[7.0], [3.5]]
        """
        if not self.linear:
            raise ValueError(f"model {self.name!r} is not linear in its constants")
        return self.stress(stretch, np.eye(self.n_params))


# ---------------------------------------------------------------------- registry
_REGISTRY: dict[str, Hyperelastic] = {}


def _infer_kind(fn: Callable) -> tuple[str, tuple[str, ...]]:
    names = list(inspect.signature(fn).parameters)
    if tuple(names[:2]) == _INVARIANT_ARGS:
        return "invariant", tuple(names[2:])
    for args in _STRETCH_ARGS:
        if tuple(names[:3]) == args:
            return "stretch", tuple(names[3:])
    raise ValueError(
        f"cannot tell the kinematics of {fn.__name__}{inspect.signature(fn)}: its first "
        "arguments must be (I1, I2, ...) for an invariant model or (l1, l2, l3, ...) for a "
        "principal-stretch model"
    )


def register(
    name: str,
    *,
    units: Sequence[str] | None = None,
    bounds: Sequence[tuple[float, float]] | None = None,
    derivatives: Callable | None = None,
    linear: bool = False,
    example: Sequence[float] | None = None,
    mu0: Callable | None = None,
    overwrite: bool = False,
    linear_params: Sequence[str] | None = None,
    fewer: str | None = None,
    term: int = 0,
    general_derivatives: Callable | None = None,
    contains: Sequence[tuple[str, Mapping[str, Any]]] = (),
) -> Callable[[Callable], Callable]:
    """Register a strain energy W by name (decorator).

    Parameters
    ----------
    name : str
        Registry name, used as ``ViscoHyperelastic(name, ...)``.
    units : sequence of str, optional
        Units of the constants (default "MPa" for each).
    bounds : sequence of (lo, hi), optional
        Physical bounds of the constants (default (-inf, inf)).
    derivatives : callable, optional
        Closed-form (∂W/∂I1, ∂W/∂I2) for invariant models, (λa ∂W/∂λa for a = 1, 2, 3)
        for stretch models; else the complex step.
    linear : bool
        Declare σ_h linear in all the constants (checked numerically at registration).
    example : sequence of float, optional
        Typical constants; default 0.1 each.
    mu0 : callable, optional
        Closed-form initial shear modulus ``mu0(*constants)``; else from the derivatives.
    overwrite : bool
        Allow replacing an existing name.
    linear_params : sequence of str, optional
        The constants σ_h is linear in when the others are fixed (checked numerically
        at registration). Default: all of them with ``linear=True``; otherwise the
        constants in MPa if σ_h is linear in them at the example constants, else none.
    fewer : str, optional
        The registered name of this law with its last term left out.
    term : int
        Constants per term when W is a sum of like terms, each linear in its first
        constant (needs ``fewer``); two terms whose other constants coincide are then
        merged into one by a fit.
    general_derivatives : callable, optional
        A stretch model's closed form (λa ∂W/∂λa) for the tests other than uniaxial
        only, when ``derivatives`` is not given (see :class:`Hyperelastic`).
    contains : sequence of (str, dict)
        The laws this one contains, each with the map of its constants into this
        law's: ``{name of this law's constant: the smaller law's constant's name, a
        number, or a callable of the smaller law's constants (a dict)}``, the constants
        left out 0 (:meth:`Hyperelastic.embed`). The calibration's search of this law
        starts from their fits and never ends worse than them.

    Returns
    -------
    decorator
        Returns the function unchanged, registered as a :class:`Hyperelastic`.

    Examples
    --------
    >>> import numpy as np
    >>> @register("my_neo_hooke", overwrite=True)
    ... def my_neo_hooke(I1, I2, C10):
    ...     return C10 * (I1 - 3)
    >>> float(get("my_neo_hooke").stress([2.0], [0.5])[0])  # 2 C10 (λ² - 1/λ)
    3.5
    """

    def decorator(fn: Callable) -> Callable:
        if not isinstance(name, str) or not name:
            raise ValueError("model name must be a non-empty string")
        if name in _REGISTRY and not overwrite:
            raise ValueError(
                f"a hyperelastic model named {name!r} is already registered; "
                "pass overwrite=True to replace it"
            )
        kind, params = _infer_kind(fn)
        n = len(params)
        if n == 0:
            raise ValueError(f"{fn.__name__} has no material constants after its kinematics")
        u = tuple(units) if units is not None else ("MPa",) * n
        b = tuple(tuple(map(float, x)) for x in bounds) if bounds is not None else (
            (-math.inf, math.inf),
        ) * n
        ex = tuple(float(x) for x in example) if example is not None else (0.1,) * n
        if len(u) != n or len(b) != n or len(ex) != n:
            raise ValueError(
                f"{name!r}: units, bounds and example need one entry per constant {list(params)}"
            )
        lp = _linear_names(name, params, u, linear, linear_params)
        if general_derivatives is not None and kind != "stretch":
            raise ValueError(f"{name!r}: general_derivatives is a principal-stretch law's "
                             "closed form; an invariant law gives derivatives= instead")
        if term and (isinstance(term, bool) or not isinstance(term, int) or term < 1
                     or n % term or n == term or fewer is None):
            raise ValueError(f"{name!r}: term = {term!r} must divide its {n} constants into "
                             "two or more like terms, and fewer= must name the law with one "
                             "term less")
        held = _contains(name, params, contains)
        model = Hyperelastic(
            name=name, param_names=params, units=u, bounds=b, kind=kind, energy=fn,
            derivatives=derivatives, example=ex,
            linear=bool(linear) or (linear_params is not None and lp == params),
            mu0=mu0, doc=inspect.getdoc(fn) or "", linear_params=lp,
            fewer=fewer, term=int(term), general_derivatives=general_derivatives,
            contains=held,
        )
        declared = bool(linear) or linear_params is not None
        if name not in _UNCHECKED and not _validate(model, strict=example is not None,
                                                    declared=declared):
            model = replace(model, linear_params=())
        _REGISTRY[name] = model
        return fn

    return decorator


#: Names being registered by :func:`register_builtin` (their check is not run)
_UNCHECKED: set[str] = set()


def register_builtin(name: str, **kwargs: Any) -> Callable[[Callable], Callable]:
    """:func:`register` for the package's own laws, without the registration check.

    The check (:func:`_validate`: a finite stress at the example constants, the stress
    linear in the constants declared linear) evaluates each law's stress; for the Ogden
    laws that loads their compiled kernel, a quarter of a second at every import that
    a fit with another law never uses. The built-in laws are fixed code: the test suite
    runs the same check on every one of them (``tests/test_laws.py``), where a law that
    failed it would be refused here.

    Parameters
    ----------
    name : str
        Registry name.
    **kwargs
        The keywords of :func:`register`.

    Returns
    -------
    decorator

    Examples
    --------
    >>> @register_builtin("_doc_unchecked", linear=True, overwrite=True)
    ... def _doc_unchecked(I1, I2, C10):
    ...     return C10 * (I1 - 3)
    >>> get("_doc_unchecked").linear_params
    ('C10',)
    >>> unregister("_doc_unchecked")
    """
    def decorator(fn: Callable) -> Callable:
        _UNCHECKED.add(name)
        try:
            return register(name, **kwargs)(fn)
        finally:
            _UNCHECKED.discard(name)

    return decorator


def _contains(name, params, contains) -> tuple[tuple[str, dict], ...]:
    """The ``contains`` declaration checked: (law name, {constant of this law: value})
    pairs, each key one of ``params`` (the smaller laws may be registered later)."""
    out = []
    for entry in contains or ():
        try:
            smaller, mapping = entry
            mapping = dict(mapping)
        except (TypeError, ValueError):
            raise ValueError(f"{name!r}: contains= takes (law name, {{constant: value}}) "
                             f"pairs, got {entry!r}") from None
        bad = [k for k in mapping if k not in params]
        if not isinstance(smaller, str) or smaller == name or bad:
            raise ValueError(f"{name!r}: contains entry {smaller!r} must name another law "
                             f"and map constants of {list(params)} (unknown: {bad})")
        for k, v in mapping.items():
            if not (isinstance(v, str) or callable(v)
                    or isinstance(v, (int, float)) and math.isfinite(v)):
                raise ValueError(f"{name!r}: contains {smaller!r} maps {k} to {v!r}: give "
                                 "a constant's name, a finite number or a callable")
        out.append((smaller, mapping))
    return tuple(out)


def _linear_names(name, params, units, linear, linear_params) -> tuple[str, ...]:
    """The declared linear constants, or the candidates (the MPa constants) to check."""
    if linear_params is None:
        return params if linear else tuple(p for p, u in zip(params, units) if u == "MPa")
    lp = tuple(linear_params)
    unknown = [p for p in lp if p not in params]
    if unknown or len(set(lp)) != len(lp):
        raise ValueError(
            f"{name!r}: linear_params {list(lp)} must name distinct constants of {list(params)}"
        )
    if linear and set(lp) != set(params):
        raise ValueError(f"{name!r}: linear=True means every constant is linear; "
                         f"linear_params {list(lp)} leaves some out")
    return tuple(p for p in params if p in lp)  # in the order of the constants


def _validate(model: Hyperelastic, strict: bool, declared: bool = True) -> bool:
    """Refuse an example with a non-finite stress or a false linearity claim.

    Returns whether ``model.linear_params`` holds (an undeclared, inferred candidate
    that fails the check is dropped by the caller instead of refused).
    """
    lam = np.array([0.6, 0.9, 1.3, 2.0])
    with np.errstate(all="ignore"):
        s = model.stress(lam, np.array(model.example))
    if not np.all(np.isfinite(s)):
        if not strict:  # default example constants may lie outside a model's domain
            return declared
        raise ValueError(
            f"model {model.name!r} gives a non-finite stress at its example constants "
            f"{model.example}: check the energy (and pass example= with valid constants)"
        )
    idx = list(model.linear_index)
    if not idx:
        return True
    # σ(a + 2b) = σ(a) + 2σ(b) in the linear constants, the others at their example values
    rng = np.random.default_rng(0)
    a, b = rng.uniform(0.1, 1.0, (2, len(idx)))
    x = np.tile(np.array(model.example), (3, 1))
    x[0, idx], x[1, idx], x[2, idx] = a + 2.0 * b, a, b
    with np.errstate(all="ignore"):
        lhs, sa, sb = model.stress(lam, x)
    rhs = sa + 2.0 * sb
    if np.all(np.isfinite(lhs)) and np.allclose(
        lhs, rhs, rtol=1e-10, atol=1e-12 * np.abs(rhs).max()
    ):
        return True
    if not declared:
        return False
    what = "linear" if model.linear else f"linear in {list(model.linear_params)}"
    raise ValueError(f"model {model.name!r} is declared {what} but its stress is not")


def get(model: str | Hyperelastic) -> Hyperelastic:
    """Look up a registered model by name (a :class:`Hyperelastic` passes through).

    Examples
    --------
    >>> mr = get("mooney_rivlin")
    >>> mr.param_names, mr.kind, mr.linear, mr.linear_params
    (('C10', 'C01'), 'invariant', True, ('C10', 'C01'))
    >>> get(mr) is mr
    True
    """
    if isinstance(model, Hyperelastic):
        return model
    try:
        return _REGISTRY[model]
    except (KeyError, TypeError):
        raise ValueError(
            f"unknown hyperelastic model {model!r}; available: {', '.join(available())} "
            "(register your own with @vhfit.hyperelastic.register)"
        ) from None


def available() -> list[str]:
    """Names of the registered models.

    Examples
    --------
    >>> {"mooney_rivlin", "neo_hooke", "ogden"} <= set(available())
    True
    """
    return sorted(_REGISTRY)


def unregister(name: str) -> None:
    """Remove a model from the registry."""
    _REGISTRY.pop(name, None)
