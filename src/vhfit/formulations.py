"""Viscoelastic formulations: how the Prony series acts at finite strain (docs/theory.md §14).

A formulation says what each Prony branch relaxes. Every formulation here has the
factorised kernel of docs/theory.md §13: along the loaded direction a of a test, the
overstress of branch i per unit modulus G_i is

    h_i(t) = Σ_k c_k(t) [ f_k(0) e^(−t/τ_i) + ∫_0^t e^(−(t−u)/τ_i) f_k'(u) du ],  k = 0, 1,

with weights c_k of the present and factors f_k of the past, so that the recursion of
:func:`vhfit._kernels.overstress_general` evaluates it in O(n·N) work. The stress is
σ = σ_h + Σ_i G_i h_i, σ_h the long-term (hyperelastic) stress, in both built-ins:

* ``"hereditary"`` (default): relaxation of the pushed-forward deviatoric instantaneous
  Kirchhoff stress — the corrected Eq. 19 of the paper, the structure of Abaqus' and
  Ansys' finite-strain Prony viscoelasticity (docs/theory.md §4, §13).
* ``"lsdyna"``: LS-DYNA's ``*MAT_HYPERELASTIC_RUBBER`` / ``*MAT_OGDEN_RUBBER`` — a
  convolution of the Green strain rate gives a second Piola–Kirchhoff stress,
  S = ∫ 2 G(t − s) dE/ds ds with G(t) = Σ GI e^(−BETAI t), GI = G_i/3 and BETAI = 1/τ_i,
  pushed forward with F and added to σ_h. Its factors depend on the kinematics alone.
* ``"lsdyna_deviatoric"``: the same with the deviatoric part of E, the other reading
  the manual leaves open (docs/theory.md §14).

A new formulation is a subclass of :class:`Formulation` registered with
:func:`register_formulation`; ``ViscoHyperelastic(..., formulation=name)`` and
``calibrate(..., formulation=name)`` then accept its name.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from vhfit import modes

__all__ = ["Formulation", "FORMULATIONS", "SOLVER_FORMULATIONS", "register_formulation",
           "get_formulation"]


class Formulation:
    """A viscoelastic formulation: the factors of its factorised kernel (see the module).

    Subclasses override :meth:`factors` (and :meth:`weights` if theirs differ from the
    pushed-forward principal-axis weights c = (λ_a², −λ_c²), or (1, γ) in simple shear).

    Attributes
    ----------
    name : str
        Registry name (set by :func:`register_formulation`).
    kinematic : bool
        True when the factors depend on the kinematics alone, not on the hyperelastic
        constants: they are then computed once per batch, with ``hyperelastic``,
        ``params`` and ``E_inf`` None, and shared by every parameter set.
    uniaxial_kernel : bool
        Whether uniaxial histories run the dedicated kernel of
        :func:`vhfit._kernels.overstress` (the hereditary formulation's own).
    """

    name: str = ""
    kinematic: bool = False
    uniaxial_kernel: bool = False
    #: One line for summaries and error messages.
    description: str = ""

    def weights(self, deformation: str, x1, x2=None, direction: int = 1) -> np.ndarray:
        """c_k(t), shape (2, m), at stretches ``x1`` (γ in simple shear) and ``x2``."""
        return modes.hereditary_weights(deformation, x1, x2, direction)

    def prepare(self, deformation: str, x1, x2=None, direction: int = 1):
        """Anything kinematic that :meth:`factors` can reuse on every call (default None)."""
        return None

    def factors(self, hyperelastic, params, E_inf, deformation: str, x1, x2=None,
                direction: int = 1, prepared=None) -> tuple[np.ndarray, np.ndarray]:
        """f_0, f_1 of the kernel at stretches ``x1`` (and ``x2``), per unit modulus.

        Shape (P, m) for P parameter sets (``params`` (P, n_h), ``E_inf`` (P,)), or (m,)
        for a kinematic formulation. NaN where the law is undefined.
        """
        raise NotImplementedError

    def __repr__(self) -> str:
        return f"<formulation {self.name!r}: {self.description}>"

    def __reduce__(self):  # pickled by name: worker processes look it up in the registry
        return (get_formulation, (self.name,))


#: The registry: name -> :class:`Formulation`.
FORMULATIONS: dict[str, Formulation] = {}

#: The formulation each solver integrates with the Prony cards vhfit writes for it
#: (docs/theory.md §13–14): filled from the solver records of :mod:`vhfit.export` as they
#: are registered (``vhfit.export.register_solver``), never by hand.
SOLVER_FORMULATIONS: dict[str, str] = {}


def register_formulation(name: str) -> Callable:
    """Class decorator: register a :class:`Formulation` subclass under ``name``.

    Examples
    --------
    >>> import numpy as np
    >>> from vhfit import formulations as fm
    >>> @fm.register_formulation("doc_linear")
    ... class Linear(fm.Formulation):
    ...     kinematic = True
    ...     description = "small-strain Boltzmann superposition on λ − 1"
    ...     def factors(self, hyperelastic, params, E_inf, deformation, x1, x2=None,
    ...                 direction=1, prepared=None):
    ...         return np.asarray(x1) - 1.0, np.zeros(np.shape(x1))
    ...     def weights(self, deformation, x1, x2=None, direction=1):
    ...         return np.stack([np.ones(np.shape(x1)), np.zeros(np.shape(x1))])
    >>> "doc_linear" in fm.FORMULATIONS
    True
    >>> del fm.FORMULATIONS["doc_linear"]
    """
    if not isinstance(name, str) or not name.isidentifier():
        raise ValueError(f"formulation name {name!r} must be a word such as 'my_law'")

    def decorate(cls):
        if not (isinstance(cls, type) and issubclass(cls, Formulation)):
            raise TypeError(f"register_formulation({name!r}) decorates a Formulation subclass, "
                            f"got {cls!r}")
        obj = cls()
        obj.name = name
        FORMULATIONS[name] = obj
        return cls

    return decorate


def get_formulation(name) -> Formulation:
    """The registered formulation ``name`` (a Formulation passes through); one-line error.

    Examples
    --------
    >>> get_formulation("lsdyna").kinematic
    True
    >>> get_formulation("abaqus")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: formulation = 'abaqus' is unknown: choose one of hereditary, lsdyna, ...
    """
    if isinstance(name, Formulation):
        return name
    if not isinstance(name, str) or name not in FORMULATIONS:
        raise ValueError(f"formulation = {name!r} is unknown: choose one of "
                         f"{', '.join(FORMULATIONS)}")
    return FORMULATIONS[name]


@register_formulation("hereditary")
class Hereditary(Formulation):
    """Relaxation of the pushed-forward deviatoric instantaneous Kirchhoff stress.

    The corrected Eq. 19 (docs/theory.md §4–5) and its multi-mode form (§13); uniaxial
    histories run the dedicated kernel, so that their results do not change by a bit.
    """

    uniaxial_kernel = True
    description = ("relaxation of the pushed-forward deviatoric instantaneous stress "
                   "(corrected Eq. 19; Abaqus, Ansys)")

    def prepare(self, deformation, x1, x2=None, direction=1):
        return modes.invariant_coefficients(deformation, x1, x2, direction)

    def factors(self, hyperelastic, params, E_inf, deformation, x1, x2=None, direction=1,
                prepared=None):
        return modes.hereditary_factors(hyperelastic, params, E_inf, deformation, x1, x2,
                                        direction, prepared)


def _green_factors(deformation, x1, x2, direction, deviatoric):
    """(2/3) Ê of the loaded and the stress-free direction (Ê = E or dev E), per unit G_i:
    :meth:`vhfit.modes.Deformation.green_factors` of the test (docs/theory.md §14)."""
    return modes.get_deformation(deformation).green_factors(x1, x2, direction, deviatoric)


@register_formulation("lsdyna")
class LsDyna(Formulation):
    """LS-DYNA MAT_077_H / MAT_077_O: Prony convolution of the Green strain rate in PK2.

    S(t) = Σ_i 2 GI_i ∫_0^t e^(−(t−s)/τ_i) dE/ds ds with GI_i = G_i/3, pushed forward
    (σ = F S Fᵀ, J = 1) and added to the long-term stress; the full Green strain E.
    """

    kinematic = True
    deviatoric = False
    description = ("LS-DYNA MAT_077: Prony convolution of the Green strain rate (PK2), "
                   "pushed forward and added to the long-term stress")

    def factors(self, hyperelastic, params, E_inf, deformation, x1, x2=None, direction=1,
                prepared=None):
        return _green_factors(deformation, x1, x2, direction, self.deviatoric)


@register_formulation("lsdyna_deviatoric")
class LsDynaDeviatoric(LsDyna):
    """:class:`LsDyna` with the convolution acting on the deviatoric part of E."""

    deviatoric = True
    description = ("LS-DYNA MAT_077 read with the deviatoric Green strain rate "
                   "(the manual leaves this open)")
