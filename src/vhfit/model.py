"""The visco-hyperelastic model: one hyperelastic law plus N Prony terms (paper Eq. 19).

Stress of the corrected, conditioned Eq. 19 (docs/theory.md §4–5):

    σ(t) = σ_h(λ(t)) + Σ_i G_i h_i(t),

where h_i is the overstress of branch i per unit modulus, evaluated by the recursion
of :mod:`vhfit._kernels` on an internal grid chosen from the requested accuracy. What
h_i is depends on the model's viscoelastic formulation (:mod:`vhfit.formulations`,
docs/theory.md §14): the corrected Eq. 19 by default, or a solver's own law.
Parameters are the hyperelastic constants first, then ``G1, tau1, G2, tau2, ...``: the
model's :attr:`~ViscoHyperelastic.layout` (a :class:`vhfit.viscous.ParamLayout`) says
which value is what.

A model is described by its :class:`ModelSpec` (the law, the viscous part and the
accuracy): :meth:`ViscoHyperelastic.spec` writes it, :func:`model_from_spec` builds the
model from it, and :meth:`ModelSpec.to_dict` / :func:`spec_from_dict` are its one serial
form (results files, material.json).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from vhfit import hyperelastic as _hyper
from vhfit._batch import Batch, check_measure
from vhfit.formulations import get_formulation
from vhfit.history import History
from vhfit.modes import check_deformation, check_direction, get_deformation, refusal_for
from vhfit.viscoelastic import check_prony, prony_g
from vhfit.viscous import ParamLayout

__all__ = ["ViscoHyperelastic", "Batch", "ModelSpec", "Prony", "model_from_spec", "spec_from_dict",
           "SPEC_VERSION"]


def _dlog(rtol: float) -> float:
    """Largest change of ln λ per step for a relative accuracy ``rtol``.

    The cubic interpolation error of a(λ) ~ λ^k over a step of δ in ln λ is about
    (kδ)⁴/2400; k ≈ 10 covers the strain energies in common use. Checked against an
    independent quadrature in tests/test_model.py.
    """
    if not 0 < rtol < 1:
        raise ValueError(f"rtol = {rtol!r} must lie in (0, 1), e.g. 1e-6 (the default)")
    return min(0.1, 0.6 * rtol**0.25)


def _check_law(hyperelastic) -> None:
    if not isinstance(hyperelastic, (str, _hyper.Hyperelastic)):
        raise ValueError(
            f"hyperelastic = {hyperelastic!r} must be a model name such as 'mooney_rivlin' "
            "(see vhfit.hyperelastic.available()) or a registered Hyperelastic"
        )


def _check_terms(n_prony) -> None:
    if isinstance(n_prony, bool) or not isinstance(n_prony, (int, np.integer)) or n_prony < 0:
        raise ValueError(f"n_prony = {n_prony!r} must be a whole number >= 0")


def _check_rtol(rtol) -> None:
    if isinstance(rtol, bool) or not isinstance(rtol, (int, float, np.integer, np.floating)):
        raise ValueError(f"rtol = {rtol!r} must lie in (0, 1): give a number such as 1e-6")
    _dlog(float(rtol))


def _check_arguments(hyperelastic, n_prony, rtol, formulation) -> None:
    """The front door of :class:`ViscoHyperelastic`: one-line errors, nothing computed."""
    _check_law(hyperelastic)
    _check_terms(n_prony)
    _check_rtol(rtol)
    get_formulation(formulation)


# ------------------------------------------------------------------------ the spec
#: Version of the serial form of :meth:`ModelSpec.to_dict` (its ``"version"`` entry).
SPEC_VERSION = 1


def _spec_error(what: str) -> ValueError:
    return ValueError(f"model spec: {what}")


def _exact_keys(d, keys: Sequence[str], what: str) -> None:
    """Refuse a mapping whose keys are not exactly ``keys`` (one line naming them)."""
    if not isinstance(d, Mapping):
        raise _spec_error(f"{what} = {d!r} is not a mapping")
    missing = [k for k in keys if k not in d]
    extra = sorted(str(k) for k in d if k not in keys)
    if missing or extra:
        raise _spec_error(f"{what} has keys {sorted(map(str, d))}: missing {missing}, "
                          f"unexpected {extra}")


@dataclass(frozen=True)
class Prony:
    """The viscous part of a model: N Prony terms acting in a viscoelastic formulation.

    Parameters
    ----------
    n : int
        Number of Prony terms N ≥ 0 (parameters ``G1, tau1, ..., GN, tauN``).
    formulation : str
        How the series acts at finite strain, a name of
        :data:`vhfit.formulations.FORMULATIONS` (default "hereditary", the corrected
        Eq. 19).

    Examples
    --------
    >>> Prony(2).describe(), Prony(2).to_dict()
    ('2 Prony term(s)', {'kind': 'prony', 'n': 2, 'formulation': 'hereditary'})
    """

    n: int = 1
    formulation: str = "hereditary"
    #: The name of this kind of viscous part in the serial form.
    kind: ClassVar[str] = "prony"

    def __post_init__(self) -> None:
        _check_terms(self.n)
        object.__setattr__(self, "n", int(self.n))
        object.__setattr__(self, "formulation", get_formulation(self.formulation).name)

    def describe(self) -> str:
        """``"N Prony term(s)"``: the words of the summaries, headers and titles."""
        return f"{self.n} Prony term(s)"

    def to_dict(self) -> dict[str, Any]:
        """The serial form: ``kind``, ``n`` and ``formulation``."""
        return {"kind": self.kind, "n": self.n, "formulation": self.formulation}

    @classmethod
    def from_dict(cls, d: Mapping) -> Prony:
        """The inverse of :meth:`to_dict` (exactly its keys; one-line errors)."""
        _exact_keys(d, ("kind", "n", "formulation"), "viscous")
        n, form = d["n"], d["formulation"]
        if isinstance(n, bool) or not isinstance(n, int) or n < 0:
            raise _spec_error(f"viscous n = {n!r} is not a whole number >= 0")
        if not isinstance(form, str):
            raise _spec_error(f"viscous formulation = {form!r} is not a name")
        try:
            return cls(n, form)
        except ValueError as exc:
            raise _spec_error(str(exc)) from None


#: Kind -> viscous part of a model spec (the serial form's ``viscous["kind"]``).
_VISCOUS: dict[str, type[Prony]] = {Prony.kind: Prony}


def _registered(law: _hyper.Hyperelastic) -> bool:
    """Whether ``law`` is the law the registry holds under its name."""
    try:
        return _hyper.get(law.name) is law
    except ValueError:
        return False


@dataclass(frozen=True)
class ModelSpec:
    """What a :class:`ViscoHyperelastic` is: its law, its viscous part and its accuracy.

    :meth:`ViscoHyperelastic.spec` writes it and :func:`model_from_spec` builds the model
    from it; a model's variants ("the same with N terms", "in another formulation", "at a
    coarser accuracy", "with another law") are :meth:`replace` of its spec. Its serial
    form is :meth:`to_dict`, read by :func:`spec_from_dict`.

    Parameters
    ----------
    hyperelastic : str or Hyperelastic
        A registered law's name, or a :class:`~vhfit.hyperelastic.Hyperelastic`: a
        registered one is kept by its name, another (a law built by hand) as itself.
    viscous : Prony
        The viscous part (default one Prony term in the "hereditary" formulation).
    rtol : float
        Relative accuracy of the hereditary integral, in (0, 1).

    Examples
    --------
    >>> s = ModelSpec("yeoh", Prony(2, "hereditary"))
    >>> s.describe(), s.n_prony, s.formulation, s.rtol
    ('yeoh + 2 Prony term(s)', 2, 'hereditary', 1e-06)
    >>> s.with_terms(0).describe()
    'yeoh + 0 Prony term(s)'
    >>> spec_from_dict(s.to_dict()) == s
    True
    """

    hyperelastic: str | _hyper.Hyperelastic = "mooney_rivlin"
    viscous: Prony = field(default_factory=Prony)
    rtol: float = 1e-6

    def __post_init__(self) -> None:
        _check_law(self.hyperelastic)
        if type(self.viscous) not in _VISCOUS.values():
            raise ValueError(f"viscous = {self.viscous!r} must be a viscous part such as "
                             "Prony(n=2)")
        _check_rtol(self.rtol)
        law = _hyper.get(self.hyperelastic)  # an unknown name: its one-line error
        object.__setattr__(self, "hyperelastic", law.name if _registered(law) else law)
        object.__setattr__(self, "rtol", float(self.rtol))

    @property
    def law(self) -> _hyper.Hyperelastic:
        """The hyperelastic law."""
        return _hyper.get(self.hyperelastic)

    @property
    def law_name(self) -> str:
        """The law's name (that of a law built by hand, too)."""
        return self.law.name

    @property
    def n_prony(self) -> int:
        """Number of Prony terms."""
        return self.viscous.n

    @property
    def formulation(self) -> str:
        """The viscoelastic formulation of the Prony series."""
        return self.viscous.formulation

    def replace(self, *, hyperelastic=None, viscous: Prony | None = None,
                n_prony: int | None = None, formulation: str | None = None,
                rtol: float | None = None) -> ModelSpec:
        """The same spec but for the parts given (None: unchanged).

        ``n_prony`` and ``formulation`` change those of the viscous part; give them or
        ``viscous``, not both.

        Examples
        --------
        >>> ModelSpec("neo_hooke").replace(n_prony=3, rtol=1e-4).describe()
        'neo_hooke + 3 Prony term(s)'
        """
        if viscous is not None and (n_prony is not None or formulation is not None):
            raise ValueError("give viscous= or n_prony=/formulation=, not both")
        if viscous is None:
            v = self.viscous
            viscous = Prony(v.n if n_prony is None else n_prony,
                            v.formulation if formulation is None else formulation)
        return ModelSpec(self.hyperelastic if hyperelastic is None else hyperelastic, viscous,
                         self.rtol if rtol is None else rtol)

    def with_terms(self, n_prony: int) -> ModelSpec:
        """The same model with ``n_prony`` Prony terms."""
        return self.replace(n_prony=n_prony)

    def describe(self, formulation: bool = False) -> str:
        """``"law + N Prony term(s)"``; with ``formulation``, a formulation other than
        "hereditary" is added (``", 'NAME' formulation"``)."""
        text = f"{self.law_name} + {self.viscous.describe()}"
        if formulation and self.formulation != "hereditary":
            text += f", '{self.formulation}' formulation"
        return text

    def flat_fields(self) -> dict[str, Any]:
        """``hyperelastic``, ``formulation`` and ``n_prony``: the fields files wrote before
        the spec and still write beside it, for their readers (:func:`spec_from_dict`
        reads them where a file has no spec)."""
        return {"hyperelastic": self.law_name, "formulation": self.formulation,
                "n_prony": self.n_prony}

    def to_dict(self) -> dict[str, Any]:
        """The serial form, JSON-ready: ``version``, ``hyperelastic`` (the law's name: a law
        built by hand must be registered where the dict is read), ``viscous``, ``rtol``.

        Examples
        --------
        >>> ModelSpec("neo_hooke", Prony(1)).to_dict()  # doctest: +NORMALIZE_WHITESPACE
        {'version': 1, 'hyperelastic': 'neo_hooke',
         'viscous': {'kind': 'prony', 'n': 1, 'formulation': 'hereditary'}, 'rtol': 1e-06}
        """
        return {"version": SPEC_VERSION, "hyperelastic": self.law_name,
                "viscous": self.viscous.to_dict(), "rtol": self.rtol}


def spec_from_dict(d: Mapping) -> ModelSpec:
    """The :class:`ModelSpec` of a dict: that of :meth:`ModelSpec.to_dict`, or a file's
    entry that holds one, or the flat fields of files written before the spec.

    A dict with ``"version"`` is the serial form and must hold exactly its keys. A dict
    with ``"spec"`` (an entry of a results file, a material.json document) is read by
    its spec, and the flat fields beside it (:meth:`ModelSpec.flat_fields`, and
    ``rtol``) must agree with it. Otherwise the dict is read as the flat fields among a file's other
    entries: ``hyperelastic``, ``n_prony`` (default 0), ``formulation`` (default
    "hereditary") and ``rtol`` (default 1e-6). Other keys are not read.

    Parameters
    ----------
    d : mapping

    Returns
    -------
    ModelSpec

    Raises
    ------
    ValueError
        One line naming the entry that is wrong.

    Examples
    --------
    >>> spec_from_dict({"hyperelastic": "neo_hooke", "n_prony": 2}).describe()
    'neo_hooke + 2 Prony term(s)'
    >>> spec_from_dict({"version": 9})
    Traceback (most recent call last):
    ...
    ValueError: model spec: version 9 is not known (this vhfit reads version 1)
    """
    if not isinstance(d, Mapping):
        raise _spec_error(f"{d!r} is not a mapping")
    if "spec" in d:
        inner = d["spec"]
        if not (isinstance(inner, Mapping) and "version" in inner):
            raise _spec_error(f"spec = {inner!r} is no model spec (it has no 'version')")
        spec = spec_from_dict(inner)
        for k, v in {**spec.flat_fields(), "rtol": spec.rtol}.items():
            if k in d and d[k] != v:
                raise _spec_error(f"{k} = {d[k]!r} does not match the spec's {v!r}")
        return spec
    if "version" not in d:
        return _flat_spec(d)
    v = d["version"]
    if isinstance(v, bool) or v != SPEC_VERSION:
        raise _spec_error(f"version {v!r} is not known (this vhfit reads version "
                          f"{SPEC_VERSION})")
    _exact_keys(d, ("version", "hyperelastic", "viscous", "rtol"), "the spec")
    viscous, rtol = d["viscous"], d["rtol"]
    kind = viscous.get("kind") if isinstance(viscous, Mapping) else None
    if kind not in _VISCOUS:
        raise _spec_error(f"viscous = {viscous!r} is no known viscous part (kinds: "
                          f"{', '.join(_VISCOUS)})")
    if isinstance(rtol, bool) or not isinstance(rtol, (int, float)):
        raise _spec_error(f"rtol = {rtol!r} is not a number")
    return _spec_of(d["hyperelastic"], _VISCOUS[kind].from_dict(viscous), rtol)


def _flat_spec(d: Mapping) -> ModelSpec:
    """The spec of the flat fields (see :func:`spec_from_dict`)."""
    n, form = d.get("n_prony", 0), d.get("formulation", "hereditary")
    if isinstance(n, bool) or not isinstance(n, int):
        raise _spec_error(f"n_prony = {n!r} is not a whole number")
    if not isinstance(form, str):
        raise _spec_error(f"formulation = {form!r} is not a name")
    try:
        viscous = Prony(n, form)
    except ValueError as exc:
        raise _spec_error(str(exc)) from None
    return _spec_of(d.get("hyperelastic"), viscous, d.get("rtol", 1e-6))


def _spec_of(law, viscous: Prony, rtol) -> ModelSpec:
    """A spec read from a dict: the law must be a name (one-line errors)."""
    if not isinstance(law, str):
        raise _spec_error(f"hyperelastic = {law!r} is not a law's name")
    try:
        return ModelSpec(law, viscous, rtol)
    except ValueError as exc:
        raise _spec_error(str(exc)) from None


def model_from_spec(spec: ModelSpec) -> ViscoHyperelastic:
    """The model a :class:`ModelSpec` describes (the inverse of
    :meth:`ViscoHyperelastic.spec`).

    Examples
    --------
    >>> m = model_from_spec(ModelSpec("mooney_rivlin", Prony(2), rtol=1e-5))
    >>> m
    ViscoHyperelastic('mooney_rivlin', n_prony=2, rtol=1e-05)
    >>> model_from_spec(m.spec()).spec() == m.spec()
    True
    """
    if not isinstance(spec, ModelSpec):
        raise TypeError(f"expected a ModelSpec, got {type(spec).__name__}: build one with "
                        "ModelSpec(...) or spec_from_dict(...)")
    return ViscoHyperelastic(spec.hyperelastic, spec.n_prony, rtol=spec.rtol,
                             formulation=spec.formulation)


def _strain_of(name: str, stretch):
    """λ − 1 from a stretch argument, which must be > 0 (one-line error)."""
    lam = np.asarray(stretch, dtype=np.float64)
    bad = ~(lam > 0)
    if bad.any():
        i = int(np.flatnonzero(bad.reshape(-1))[0])
        raise ValueError(f"{name}[{i}] = {float(lam.reshape(-1)[i])!r} must be > 0: stretches are "
                         "positive (λ = 1 + strain)")
    return lam - 1.0


def _history_from(deformation, direction, *, strain, strain_rate, time, stretch, strain2,
                  stretch2) -> History:
    """The History of :meth:`ViscoHyperelastic.stress`'s keywords; one-line errors."""
    check_deformation(deformation)
    check_direction(deformation, direction)
    if strain is not None and stretch is not None:
        raise ValueError("give strain or stretch (= 1 + strain), not both")
    if strain2 is not None and stretch2 is not None:
        raise ValueError("give strain2 or stretch2 (= 1 + strain2), not both")
    if stretch is not None:
        if get_deformation(deformation).shear:
            raise ValueError(f"{deformation} is driven by the amount of shear: give strain=γ, "
                             "not stretch")
        strain = _strain_of("stretch", stretch)
    if stretch2 is not None:
        strain2 = _strain_of("stretch2", stretch2)
    if strain is None:
        raise ValueError("give a history, or strain (or stretch) with strain_rate, time or "
                         "neither (the long-term response)")
    if strain_rate is not None and time is not None:
        raise ValueError("give strain_rate (constant-rate ramp) or time (history), not both; "
                         "neither: the long-term response")
    eps = np.reshape(np.asarray(strain, dtype=np.float64), -1)
    if strain2 is not None:
        strain2 = np.reshape(np.asarray(strain2, dtype=np.float64), -1)
    kw = dict(deformation=deformation, strain2=strain2)
    if strain_rate is not None:
        h = History.constant_rate(eps, strain_rate, **kw)
    elif time is not None:
        h = History.piecewise_linear(time, eps, **kw)
    else:
        h = History.equilibrium(eps, **kw)
    if direction == 2:
        h = h.with_outputs(h.out_time, np.full(h.out_time.size, 2))
    return h


class ViscoHyperelastic:
    """Hyperelastic law + N-term Prony series under homogeneous uniaxial loading.

    Parameters
    ----------
    hyperelastic : str or Hyperelastic
        A registered model name (see ``vhfit.hyperelastic.available()``).
    n_prony : int
        Number of Prony terms N ≥ 0.
    rtol : float
        Relative accuracy of the hereditary integral (default 1e-6 of the peak stress).
    formulation : str
        How the Prony series acts at finite strain, a name of
        :data:`vhfit.formulations.FORMULATIONS`: "hereditary" (default; the corrected
        Eq. 19, docs/theory.md §13) or another registered one, such as a solver's own
        (:data:`vhfit.formulations.SOLVER_FORMULATIONS`), docs/theory.md §14. The
        parameters mean the same in every formulation.

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=2)
    >>> m.param_names
    ['C10', 'C01', 'G1', 'tau1', 'G2', 'tau2']
    >>> p = dict(C10=0.0, C01=5.0, G1=30.0, tau1=1e-4, G2=0.0, tau2=1.0)
    >>> s = m.stress(p, strain=np.linspace(0, -0.55, 5), strain_rate=-5700.0)
    >>> s.shape
    (5,)
    """

    def __init__(self, hyperelastic="mooney_rivlin", n_prony: int = 1, *, rtol: float = 1e-6,
                 formulation: str = "hereditary"):
        _check_arguments(hyperelastic, n_prony, rtol, formulation)
        self._spec = spec = ModelSpec(hyperelastic, Prony(n_prony, formulation), rtol)
        self._formulation = get_formulation(spec.formulation)
        #: Name of the viscoelastic formulation (see :mod:`vhfit.formulations`).
        self.formulation: str = spec.formulation
        self.hyperelastic = spec.law
        self.n_prony = spec.n_prony
        self.rtol = spec.rtol
        self._dlog = _dlog(self.rtol)
        #: What each parameter is and where it sits (the law's constants, then G_i, τ_i).
        self.layout: ParamLayout = ParamLayout.of(self.hyperelastic, self.n_prony)
        self.param_names: list[str] = list(self.layout.names)
        self.units: list[str] = list(self.layout.units)

    def __repr__(self) -> str:
        form = "" if self.formulation == "hereditary" else f", formulation={self.formulation!r}"
        return (
            f"ViscoHyperelastic({self.hyperelastic.name!r}, n_prony={self.n_prony}, "
            f"rtol={self.rtol:g}{form})"
        )

    @property
    def n_params(self) -> int:
        return len(self.param_names)

    def spec(self) -> ModelSpec:
        """What this model is (law, viscous part, accuracy): :func:`model_from_spec`
        builds it again; its :meth:`~ModelSpec.replace` makes variants.

        Examples
        --------
        >>> m = ViscoHyperelastic("neo_hooke", 2)
        >>> model_from_spec(m.spec().with_terms(1))
        ViscoHyperelastic('neo_hooke', n_prony=1, rtol=1e-06)
        """
        return self._spec

    # ------------------------------------------------------------- parameters
    def as_array(self, params) -> np.ndarray:
        """Parameters as an array in ``param_names`` order (from a dict or a sequence).

        Examples
        --------
        >>> m = ViscoHyperelastic("mooney_rivlin", 1)
        >>> m.as_array(dict(tau1=0.01, G1=2.0, C01=0.05, C10=0.1)).tolist()
        [0.1, 0.05, 2.0, 0.01]
        """
        if isinstance(params, Mapping):
            missing = [n for n in self.param_names if n not in params]
            extra = [k for k in params if k not in self.param_names]
            if missing or extra:
                raise ValueError(
                    f"params for {self!r}: missing {missing}, unexpected {extra}; "
                    f"expected {self.param_names}"
                )
            return np.array([float(params[n]) for n in self.param_names])
        x = np.asarray(params, dtype=np.float64)
        if x.shape[-1:] != (self.n_params,):
            raise ValueError(
                f"params has shape {x.shape}; expected {self.n_params} values "
                f"{self.param_names} (last axis)"
            )
        return x

    def as_dict(self, x) -> dict[str, float]:
        """Parameters as a dict name -> value.

        Examples
        --------
        >>> ViscoHyperelastic("neo_hooke", 1).as_dict([0.1, 2.0, 0.01])
        {'C10': 0.1, 'G1': 2.0, 'tau1': 0.01}
        """
        return dict(zip(self.param_names, map(float, self.as_array(x))))

    def split(self, x) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(hyperelastic constants, G, tau) from parameter array(s) of shape (..., n_params).

        Examples
        --------
        >>> hyper, G, tau = ViscoHyperelastic("mooney_rivlin", 2).split([0.1, 0.05, 2, 1e-3, 1, 1])
        >>> hyper.tolist(), G.tolist(), tau.tolist()
        ([0.1, 0.05], [2.0, 1.0], [0.001, 1.0])
        """
        return self.layout.split(x)

    def check(self, params) -> np.ndarray:
        """Validate one parameter set; raise ValueError naming the bad parameter.

        Examples
        --------
        >>> m = ViscoHyperelastic("mooney_rivlin", 1)
        >>> m.check([0.1, 0.05, 2.0, 0.01]).tolist()
        [0.1, 0.05, 2.0, 0.01]
        >>> m.check([0.1, 0.05, -2.0, 0.01])
        Traceback (most recent call last):
        ...
        ValueError: G1 = -2.0: Prony moduli must be finite and >= 0 MPa
        """
        x = self.as_array(params)
        if x.ndim != 1:
            raise ValueError(f"expected one parameter set, got shape {x.shape}")
        hyper, G, tau = self.split(x)
        self.hyperelastic.check(hyper)
        check_prony(G, tau)
        E_inf = self.long_term_modulus(x)
        if not E_inf > 0:
            raise ValueError(
                f"the long-term modulus E_inf = 3 mu0 = {E_inf:g} MPa must be > 0: "
                f"the hyperelastic constants {dict(zip(self.hyperelastic.param_names, hyper))} "
                "give no long-term stiffness (e.g. C10 and C01 both 0)"
            )
        return x

    def long_term_modulus(self, x) -> np.ndarray | float:
        """E∞ = 3 μ0 of the hyperelastic law, MPa.

        Examples
        --------
        >>> ViscoHyperelastic("mooney_rivlin", 1).long_term_modulus([0.0, 5.0, 30.0, 1e-4])
        30.0
        """
        hyper = self.split(x)[0]
        E = 3.0 * self.hyperelastic.initial_shear_modulus(hyper)
        return float(E) if np.ndim(E) == 0 else E

    def prony_g(self, params) -> tuple[np.ndarray, float]:
        """Dimensionless (g_i, g∞) of one parameter set (docs/theory.md §3).

        Examples
        --------
        The paper's verification material, C01 = 5 MPa and g1 = 0.5:

        >>> g, g_inf = ViscoHyperelastic("mooney_rivlin", 1).prony_g([0.0, 5.0, 30.0, 1e-4])
        >>> g.tolist(), g_inf
        ([0.5], 0.5)
        """
        x = self.check(params)
        return prony_g(self.long_term_modulus(x), self.split(x)[1])

    # ------------------------------------------------------------------ stress
    def stress(
        self,
        params,
        history=None,
        *,
        strain=None,
        strain_rate: float | None = None,
        time=None,
        measure: str = "true",
        stretch=None,
        strain2=None,
        stretch2=None,
        deformation: str = "uniaxial",
        direction: int = 1,
    ) -> np.ndarray:
        """Stress of the model along a history of any homogeneous test, in its formulation.

        Parameters
        ----------
        params : dict or array_like
            One parameter set: dict name -> value, or values in ``param_names`` order.
        history : History or Curve, optional
            The history to follow; alternatively give ``strain`` (or ``stretch``) with
            ``strain_rate`` (constant-rate ramp from ε = 0), with ``time``
            (piecewise-linear history through ``(time, strain)``, ``time[0] = 0``), or
            with neither (fully relaxed states: the long-term response).
        strain, strain_rate, time : array_like, float, array_like
            See above. Compression is negative. In simple shear ``strain`` is the
            amount of shear γ.
        measure : {"true", "engineering"}
            True (Cauchy) or engineering (nominal, σ/λ_a) stress.
        stretch : array_like, optional
            λ1 instead of ``strain`` (= λ1 − 1); not for simple shear.
        strain2, stretch2 : array_like, optional
            λ2 − 1 or λ2 at each strain: tests with a second prescribed stretch only.
        deformation : str
            A registered test (:func:`vhfit.modes.registered_deformations`; default
            "uniaxial", docs/theory.md §13).
        direction : {1, 2}
            The loaded direction whose stress is returned (2: tests with two).

        Returns
        -------
        ndarray
            Stress in MPa at each strain (or at ``history.out_time``); σ12 in simple
            shear.

        Examples
        --------
        >>> import vhfit
        >>> m = vhfit.ViscoHyperelastic("neo_hooke", n_prony=0)
        >>> float(m.stress([0.5], strain=[1.0], strain_rate=1.0)[0])   # 2 C10 (λ² − 1/λ)
        3.5
        >>> float(m.stress([0.5], strain=[0.4], deformation="simple_shear")[0])   # 2 C10 γ
        0.4
        """
        x = self.check(params)
        given = dict(strain=strain, strain_rate=strain_rate, time=time, stretch=stretch,
                     strain2=strain2, stretch2=stretch2)
        if history is None:
            history = _history_from(deformation, direction, **given)
        elif any(v is not None for v in given.values()) or deformation != "uniaxial" \
                or direction != 1:
            raise ValueError(
                "give either a history or strain/stretch/strain_rate/time/deformation/"
                "direction, not both"
            )
        out = self.batch([history], measure=measure)(x[None, :])[0]
        if not np.all(np.isfinite(out)):
            raise ValueError(
                f"the stress is not finite for params {self.as_dict(x)}: the hyperelastic "
                "energy is undefined on this history (check its constants and the strain range)"
            )
        shape_of = strain if strain is not None else stretch
        if shape_of is not None:
            out = out.reshape(np.shape(shape_of))
        return out

    def creep(self, params, stress: float, time, *, deformation: str = "uniaxial",
              measure: str = "true") -> np.ndarray:
        """Stretch of a creep test: ``stress`` applied at once at t = 0, then held.

        The load is a step: at t = 0 the stretch jumps to the instantaneous response,
        what the recursion gives for a jump from rest (every branch at its instantaneous
        state, h_i = ŝ in the "hereditary" formulation: the law with its instantaneous
        modulus, σ_h/g∞), and then creeps towards the long-term response σ_h(λ) = σ.
        It is found by time-stepping the model's state (the recursion of each Prony
        term) and solving, at each node of a fixed grid, the scalar equation
        σ(λ_(n+1); state_n) = ``stress``; the grid is chosen from ``time`` and
        :attr:`rtol` alone (uniform in ln t, refined towards t = 0 where the creep is
        fastest; docs/theory.md §15), never from the parameters.

        Parameters
        ----------
        params : dict or array_like
            One parameter set.
        stress : float
            The held stress in MPa (negative in compression), in ``measure``.
        time : array_like
            Times in s (>= 0, non-decreasing) at which the stretch is wanted; t = 0 gives
            the instantaneous response.
        deformation : str
            A test driven by λ1 alone in principal axes: "uniaxial" (default),
            "equibiaxial", "planar" (or a registered one of that kind).
        measure : {"true", "engineering"}
            The held stress is true (Cauchy) or engineering (nominal, force per
            undeformed area: a dead load).

        Returns
        -------
        ndarray
            λ1 at each time (same shape as ``time``).

        Raises
        ------
        ValueError
            In one line: a test that is not driven by one stretch (simple shear, biaxial),
            times out of order, or a stress the model cannot carry (at t = 0, or later
            when its long-term law cannot).

        Examples
        --------
        A neo-Hookean model with no Prony term does not creep: 2 C10 (λ² − 1/λ) = σ.

        >>> m = ViscoHyperelastic("neo_hooke", n_prony=0)
        >>> lam = m.creep([0.5], 3.5, [0.0, 1.0])
        >>> [round(float(v), 12) for v in lam]
        [2.0, 2.0]
        """
        from vhfit import _creep  # noqa: PLC0415 (the stepper: only a creep test needs it)

        x = self.check(params)
        check_deformation(deformation)
        test = get_deformation(deformation)
        if test.shear:
            raise ValueError(
                f"creep in {test.name} is refused: a shear creep test must also prescribe "
                "the normal stresses that hold the shear (the Poynting effect), which a "
                "single held stress does not; use uniaxial, equibiaxial or planar tension")
        if test.second_stretch:
            raise ValueError(
                f"creep in {test.name} is refused: two prescribed stretches need two held "
                "stresses; use uniaxial, equibiaxial or planar tension")
        why = refusal_for(self.hyperelastic, test.name)
        if why:
            raise ValueError(why)
        check_measure(measure)
        try:
            s = float(stress)
        except (TypeError, ValueError):
            raise ValueError(f"stress must be a number in MPa, got {stress!r}") from None
        if not np.isfinite(s):
            raise ValueError(f"stress = {stress!r} must be finite (MPa)")
        t = np.asarray(time, dtype=np.float64)
        flat = t.reshape(-1)
        if not flat.size:
            raise ValueError("time is empty: give at least one time (0: the instantaneous "
                             "response)")
        bad = ~np.isfinite(flat) | (flat < 0)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(f"time[{i}] = {flat[i]!r} must be finite and >= 0 s (the load "
                             "is applied at t = 0)")
        back = np.flatnonzero(np.diff(flat) < 0)
        if back.size:
            i = int(back[0]) + 1
            raise ValueError(f"time must not decrease, but time[{i}] = {flat[i]:g} < "
                             f"time[{i - 1}] = {flat[i - 1]:g}: sort the times")
        point = _creep.MaterialPoint(self, x, test.name, measure)
        return _creep.creep(point, s, flat, self.rtol).reshape(t.shape)

    def batch(self, histories: Sequence, *, measure: str | Sequence[str] | None = None) -> Batch:
        """A compiled evaluation plan for many parameter sets on fixed histories.

        Parameters
        ----------
        histories : sequence of History or Curve
        measure : str or sequence of str, optional
            Stress measure per history; default each curve's own ``measure`` (Curves)
            or "true".

        Returns
        -------
        Batch
            ``batch(X)`` with X of shape (P, n_params) gives (P, n_points) stresses.

        Examples
        --------
        >>> import numpy as np
        >>> from vhfit.history import History
        >>> m = ViscoHyperelastic("mooney_rivlin", 1)
        >>> b = m.batch([History.constant_rate(np.linspace(0, -0.3, 4), -1.0)])
        >>> X = [[0.1, 0.05, 2.0, 0.01], [0.1, 0.05, -1.0, 0.01]]   # the second is invalid
        >>> s = b(X)
        >>> s.shape, bool(np.all(s[0, 1:] < 0)), bool(np.all(np.isinf(s[1])))
        ((2, 4), True, True)
        """
        return Batch(self, histories, measure)

    def residual(self, params, curves: Sequence) -> np.ndarray:
        """Model minus measured stress at every objective point of every curve, MPa.

        The curves are Curve objects (``.history``, ``.target_stress``, ``.measure``).

        Examples
        --------
        >>> import numpy as np, vhfit
        >>> m = ViscoHyperelastic("mooney_rivlin", 1)
        >>> p = [0.1, 0.05, 2.0, 0.01]
        >>> eps = np.linspace(-0.05, -0.3, 10)   # the curve's 10 objective points
        >>> c = vhfit.Curve(strain=eps, stress=m.stress(p, strain=eps, strain_rate=-1.0,
        ...                 measure="engineering"), strain_rate=-1.0)
        >>> r = m.residual(p, [c])
        >>> r.shape, bool(np.max(np.abs(r)) < 1e-12)
        ((10,), True)
        """
        x = self.check(params)
        b = self.batch(curves)
        target = np.concatenate([np.asarray(c.target_stress, dtype=np.float64) for c in curves])
        return b(x[None, :])[0] - target
