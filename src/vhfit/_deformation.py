"""What a homogeneous test is: the :class:`Deformation` record and the registry of them.

A record says everything vhfit needs to know of a test — its principal stretches, what
it measures, how its history is laid out and what the factors of the pushed-forward
hereditary integral are — so that no other module tests a test's name. The built-in
records and the law's stresses in them are :mod:`vhfit.modes`, which re-exports all
of this; a new test is a subclass registered with :func:`register_deformation`
(docs/architecture.md shows one).
"""

from __future__ import annotations

import re
from collections.abc import Callable

import numpy as np

from vhfit._fixed import cannot_change, remembered
from vhfit._kirchhoff import principal_kirchhoff
from vhfit.hyperelastic import Hyperelastic


class Deformation:
    """A homogeneous incompressible test: its kinematics and what it measures.

    A test in principal axes needs only :meth:`stretches` (and the attributes that
    differ from the defaults); every other method follows from them. A subclass is
    registered with :func:`register_deformation`; ``Curve(deformation=name)``,
    ``History(..., deformation=name)``, ``ViscoHyperelastic.stress(..., deformation=name)``,
    the calibration, the plots, the cards and ``vhfit fit --deformation name`` then
    accept it.

    Attributes
    ----------
    name : str
        Registry name (set by :func:`register_deformation`).
    aliases : tuple of str
        Other names labs write (lower case, words joined by ``_``), e.g. ``"pure_shear"``.
    description : str
        One line for docs, summaries and error messages.
    uniaxial : bool
        The paper's test (λ2 = λ3 = λ1^(−1/2)): the long-term stress is the law's own
        ``Hyperelastic.stress`` and the hereditary formulation runs its dedicated kernel.
    second_stretch : bool
        λ2 is prescribed as well (``strain2``/``stretch2``, the kinematic argument ``x2``).
    shear : bool
        Driven by the amount of shear γ instead of λ1 (``strain`` is γ; the path starts
        at γ = 0), measuring σ12.
    measured : tuple of str
        The measured stress components, one per loaded direction (direction 2 only when
        there are two).
    stress_free : int
        The principal direction c with σ_c = 0 (the pressure follows from it).
    step_power : float
        The largest |d ln λ_k / d ln λ1|: a history's grid steps ln λ1 by at most
        dlog / step_power (one-stretch tests in principal axes).
    signed : bool
        The measured stress has the strain's sign for every sensible law (a sign
        contradiction in data is then an error).
    drucker : bool
        Checked by :func:`vhfit.stability.drucker` (one-stretch principal tests).
    standard_test : str or None
        Which of the standard tests of hyperelastic test data it is (``"uniaxial"``,
        ``"equibiaxial"`` or ``"planar"``), for a solver's own test-data input (a solver
        record's ``test_data``, :class:`vhfit.export.Solver`); None: none of them.
    strain_label, stress_label : str
        What ``strain`` and ``stress`` mean, for files and plots (units included).
    refusal : str or None
        A test that changes the volume (J ≠ 1, e.g. confined compression) and so cannot
        be represented by an incompressible law: one line saying why and what would work,
        the reason every such law refuses it (:func:`refusal_for`). None: an isochoric test.
    mentions : tuple of str
        Words or phrases (lower case) that name this test in free text — a ``#`` comment
        line, a column header — where the test is easy to miss, e.g. ``"confined"``.
        Matched as whole words and not after "not"/"non" (:func:`deformation_mentioned`).
    """

    name: str = ""
    aliases: tuple[str, ...] = ()
    description: str = ""
    uniaxial: bool = False
    second_stretch: bool = False
    shear: bool = False
    measured: tuple[str, ...] = ("σ11",)
    stress_free: int = 3
    step_power: float = 1.0
    signed: bool = False
    drucker: bool = False
    standard_test: str | None = None
    strain_label: str = "engineering strain λ1 − 1"
    stress_label: str = "stress in the loaded direction (MPa)"
    refusal: str | None = None
    mentions: tuple[str, ...] = ()

    def __repr__(self) -> str:
        return f"<deformation {self.name!r}: {self.description}>"

    def __reduce__(self):  # pickled by name: worker processes look it up in the registry
        return (get_deformation, (self.name,))

    @property
    def directions(self) -> int:
        """Number of loaded directions whose stress can be measured (1 or 2)."""
        return len(self.measured)

    # ------------------------------------------------------------ kinematics
    def stretches(self, x1, x2=None):
        """Principal stretches (λ1, λ2, λ3) at λ1 = ``x1`` (γ in shear), λ2 = ``x2``."""
        raise NotImplementedError(f"deformation {self.name!r} defines no stretches")

    def loaded_stretch(self, x1, x2=None, direction: int = 1) -> np.ndarray:
        """λ_a of the loaded direction a (nominal = true / λ_a); 1 in simple shear."""
        return np.asarray(self._stretches(x1, x2)[direction - 1], dtype=np.float64)

    def _stretches(self, x1, x2):
        """:meth:`stretches`; for data that cannot change (an evaluation plan's samples)
        computed once and kept read-only, so that what a law derives from them is kept
        too (:mod:`vhfit._fixed`)."""
        x1 = np.asarray(x1, dtype=np.float64)
        data = (x1,) if x2 is None else (x1, np.asarray(x2, dtype=np.float64))

        def stretches():
            out = tuple(np.asarray(v, dtype=np.float64) for v in self.stretches(*data))
            for v in out:
                v.flags.writeable = False
            return out

        if not all(cannot_change(v) for v in data):
            return self.stretches(x1, x2)
        return remembered(f"stretches of {self.name}", data, stretches)

    # --------------------------------------------------------- its history
    #: The path variable at rest: λ1 = 1 (γ = 0 in shear).
    rest: float = 1.0

    def path(self, strain: np.ndarray) -> np.ndarray:
        """The path variable of a history from the driving strain: λ1 = 1 + ε (γ in shear)."""
        return 1.0 + strain

    def strain(self, path: np.ndarray) -> np.ndarray:
        """The driving strain from the path variable: λ1 − 1 (γ in shear)."""
        return path - 1.0

    def steps(self, a: float, b: float, x1, x2, dlog: float) -> np.ndarray:
        """Inner and end node times of a history's linear piece from t = a to t = b.

        ``x1`` (and ``x2``) are the path's values at both ends. Every principal stretch
        of a one-stretch test is a power of λ1 (λ linear in t along the piece): steps
        uniform in ln λ1, at most dlog in the fastest of them.
        """
        tt = log_uniform(a, b, x1[0], x1[1], dlog / self.step_power)
        return tt if tt.size else np.array([b])

    # ---------------------------------------------------- long-term stress
    def long_term_coefficients(self, x1, x2=None, direction: int = 1):
        """(I1, I2, p, q) with σ = W1 p + W2 q for an invariant law W(I1, I2).

        σ_a = τ_a − τ_c = (λ_a² − λ_c²) (2 W1 + 2 W2 λ_b²), b the third direction.
        """
        a = [lk * lk for lk in self._stretches(x1, x2)]
        I1 = a[0] + a[1] + a[2]
        I2 = a[0] * a[1] + a[1] * a[2] + a[2] * a[0]
        k, c = direction - 1, self.stress_free - 1
        p = 2.0 * (a[k] - a[c])
        return I1, I2, p, p * a[3 - k - c]

    def stretch_law_stress(self, model: Hyperelastic, cols, x1, x2=None, direction: int = 1):
        """σ_a = τ_a − τ_c of a law in principal stretches (constants as columns)."""
        tau = principal_kirchhoff(model, cols, *self._stretches(x1, x2))
        return tau[direction - 1] - tau[self.stress_free - 1]

    # ------------------------------------- factors of the hereditary integral
    def weights(self, x1, x2=None, direction: int = 1) -> np.ndarray:
        """c_k(t) of the factorised pushed-forward kernel, (2, m): (λ_a², −λ_c²)."""
        lam = self._stretches(x1, x2)
        return np.stack([lam[direction - 1] ** 2, -(lam[self.stress_free - 1] ** 2)])

    def invariant_coefficients(self, x1, x2=None, direction: int = 1):
        """(I1, I2, coef) with f_k = (2/E∞)(W1 coef[2k] + W2 coef[2k + 1]) for W(I1, I2).

        With a_k = λ_k², b_k = I1 a_k − a_k² and bars for means over k:
        f_a = (2 W1 (a_a − ā) + 2 W2 (b_a − b̄)) / (E∞ a_a), likewise f_c.
        """
        a = [lk * lk for lk in self._stretches(x1, x2)]
        I1 = a[0] + a[1] + a[2]
        I2 = a[0] * a[1] + a[1] * a[2] + a[2] * a[0]
        b = [I1 * ak - ak * ak for ak in a]
        a_bar, b_bar = I1 / 3.0, (b[0] + b[1] + b[2]) / 3.0
        k, c = direction - 1, self.stress_free - 1
        coef = np.stack([(a[k] - a_bar) / a[k], (b[k] - b_bar) / a[k],
                         (a[c] - a_bar) / a[c], (b[c] - b_bar) / a[c]])
        return I1, I2, coef

    def kirchhoff_factors(self, model: Hyperelastic, cols, E, x1, x2=None,
                          direction: int = 1):
        """f = (d_a/λ_a², d_c/λ_c²)/E∞, d = dev τ, for a law in principal stretches."""
        lam = self._stretches(x1, x2)
        tau = principal_kirchhoff(model, cols, *lam)
        mean = (tau[0] + tau[1] + tau[2]) / 3.0
        a, c = direction - 1, self.stress_free - 1
        return (tau[a] - mean) / (E * lam[a] ** 2), (tau[c] - mean) / (E * lam[c] ** 2)

    def green_factors(self, x1, x2=None, direction: int = 1, deviatoric: bool = False):
        """(2/3) Ê of the loaded and the stress-free direction (Ê = E or dev E), per unit G.

        E_k = (λ_k² − 1)/2, and dev E_k = (λ_k² − I1/3)/2 (docs/theory.md §14).
        """
        lam = self._stretches(x1, x2)
        a = lam[direction - 1] ** 2
        c = lam[self.stress_free - 1] ** 2
        shift = (lam[0] ** 2 + lam[1] ** 2 + lam[2] ** 2) / 3.0 if deviatoric else 1.0
        return (a - shift) / 3.0, (c - shift) / 3.0


# ------------------------------------------------------------------ registry
_REGISTRY: dict[str, Deformation] = {}


#: Words that say nothing about the kinematics ("uniaxial tension test" is uniaxial).
NOISE_WORDS = frozenset({"tension", "tensile", "compression", "compressive", "test", "tests",
                         "loading", "mode"})


def _key(text) -> str | None:
    """Lower case, words joined by ``_``, without :data:`NOISE_WORDS`: how names and
    aliases are compared."""
    if not isinstance(text, str):
        return None
    words = re.split(r"[\s_\-/]+", text.strip().lower())
    return "_".join(t for t in words if t and t not in NOISE_WORDS)


def register_deformation(name: str, *, aliases=(), overwrite: bool = False) -> Callable:
    """Class decorator: register a :class:`Deformation` subclass under ``name``.

    Parameters
    ----------
    name : str
        Registry name, a word such as ``"my_test"``.
    aliases : sequence of str
        Other names labs write for it (file columns, ``# deformation:`` lines, the CLI).
    overwrite : bool
        Allow replacing an existing name.

    Returns
    -------
    decorator
        Returns the class unchanged; the registry holds one instance of it.

    Examples
    --------
    >>> import numpy as np
    >>> from vhfit import modes
    >>> @modes.register_deformation("doc_planar", aliases=("doc_pure_shear",))
    ... class DocPlanar(modes.Deformation):
    ...     description = "pure shear written again"
    ...     def stretches(self, x1, x2=None):
    ...         x1 = np.asarray(x1, dtype=np.float64)
    ...         return x1, np.ones_like(x1), 1.0 / x1
    >>> modes.deformation_named("doc pure shear")
    'doc_planar'
    >>> [float(v) for v in modes.principal_stretches("doc_planar", 2.0)]
    [2.0, 1.0, 0.5]
    >>> modes.unregister_deformation("doc_planar")
    """
    if not isinstance(name, str) or not name.isidentifier():
        raise ValueError(f"deformation name {name!r} must be a word such as 'my_test'")

    def decorate(cls):
        if not (isinstance(cls, type) and issubclass(cls, Deformation)):
            raise TypeError(f"register_deformation({name!r}) decorates a Deformation "
                            f"subclass, got {cls!r}")
        if name in _REGISTRY and not overwrite:
            raise ValueError(f"a deformation named {name!r} is already registered; pass "
                             "overwrite=True to replace it")
        obj = cls()
        obj.name = name
        obj.aliases = tuple(_key(a) for a in (*cls.aliases, *aliases))
        if not 1 <= obj.directions <= 2 or obj.stress_free not in (1, 2, 3) \
                or obj.stress_free <= obj.directions:
            raise ValueError(f"deformation {name!r}: measured gives one or two components "
                             "(loaded directions 1 and 2) and stress_free is another "
                             "direction, 2 or 3")
        taken = {a: n for n, d in _REGISTRY.items() if n != name
                 for a in (_key(n), *d.aliases)}
        clash = [a for a in (_key(name), *obj.aliases) if a in taken]
        if clash:
            raise ValueError(f"deformation {name!r}: {clash[0]!r} already names "
                             f"{taken[clash[0]]!r}")
        _REGISTRY[name] = obj
        return cls

    return decorate


def unregister_deformation(name: str) -> None:
    """Remove a registered deformation (tests, plug-ins that replace one)."""
    get_deformation(name)
    del _REGISTRY[name]


def registered_deformations() -> tuple[str, ...]:
    """Names of the registered deformations, in registration order.

    Examples
    --------
    >>> registered_deformations()[0], "planar" in registered_deformations()
    ('uniaxial', True)
    """
    return tuple(_REGISTRY)


def get_deformation(name) -> Deformation:
    """The registered deformation ``name`` (a :class:`Deformation` passes through).

    Examples
    --------
    >>> get_deformation("planar").measured
    ('σ11',)
    >>> get_deformation("shear")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: deformation = 'shear' is unknown: choose one of uniaxial, ...
    """
    if isinstance(name, Deformation):
        return name
    try:
        return _REGISTRY[name]
    except (KeyError, TypeError):
        raise ValueError(f"deformation = {name!r} is unknown: choose one of "
                         f"{', '.join(_REGISTRY)}") from None


def deformation_named(text) -> str | None:
    """The registered deformation a lab's label names, or None.

    Names and aliases are compared in lower case with words joined by ``_``, after
    dropping words that say nothing about the kinematics (:data:`NOISE_WORDS`).

    Examples
    --------
    >>> deformation_named("Pure shear"), deformation_named("uniaxial tension")
    ('planar', 'uniaxial')
    >>> deformation_named("torsion") is None
    True
    """
    key = _key(text)
    if not key:
        return None
    for name, rec in _REGISTRY.items():
        if key == _key(name) or key in rec.aliases:
            return name
    return None


def _mention_re(phrase: str) -> re.Pattern:
    """A phrase as whole words (any separator between them), not after "not"/"non"."""
    words = r"[\s_\-]+".join(map(re.escape, phrase.split()))
    return re.compile(rf"(?<![a-z0-9])(?<!not )(?<!non )(?<!non-){words}(?![a-z0-9])")


def deformation_mentioned(text) -> str | None:
    """The registered test that free text (a comment line, a header) mentions, or None.

    Only the words of a record's :attr:`Deformation.mentions` count: a test that a lab
    describes in prose rather than names in a ``deformation`` column or line.

    Examples
    --------
    >>> deformation_mentioned("# CONFINED compression of foam in a steel cup")
    'confined_compression'
    >>> deformation_mentioned("unconfined compression") is None
    True
    >>> deformation_mentioned("uniaxial compression, not confined") is None
    True
    """
    if not isinstance(text, str):
        return None
    low = text.lower()
    for name, rec in _REGISTRY.items():
        if any(_mention_re(w).search(low) for w in rec.mentions):
            return name
    return None


def refusal_for(law: Hyperelastic, deformation) -> str | None:
    """Why ``law`` cannot represent the test ``deformation``, in one line, or None.

    An incompressible law (every built-in one: :attr:`Hyperelastic.compressible` False)
    cannot deform in a test that changes the volume; the record says why and what would
    work.

    Examples
    --------
    >>> from vhfit import hyperelastic
    >>> refusal_for(hyperelastic.get("neo_hooke"), "confined_compression")[:46]
    'an incompressible law cannot deform in confine'
    >>> refusal_for(hyperelastic.get("neo_hooke"), "uniaxial") is None
    True
    """
    test = get_deformation(deformation)
    return None if law.compressible else test.refusal


def check_deformation(deformation) -> str:
    """The deformation name, or a one-line error listing the valid ones."""
    if not isinstance(deformation, str):
        get_deformation(None)
    return get_deformation(deformation).name


def with_two_directions() -> tuple[str, ...]:
    """The registered tests with a second loaded direction (``direction=2``)."""
    return tuple(n for n, d in _REGISTRY.items() if d.directions == 2)


def with_second_stretch() -> tuple[str, ...]:
    """The registered tests that prescribe λ2 as well (``strain2``, ``stretch2``)."""
    return tuple(n for n, d in _REGISTRY.items() if d.second_stretch)


def check_direction(deformation: str, direction) -> int:
    """1, or 2 for a test with a second loaded direction; else a one-line error."""
    if isinstance(direction, bool) or direction not in (1, 2):
        raise ValueError(f"direction = {direction!r} must be 1 or 2")
    if direction == 2 and get_deformation(deformation).directions < 2:
        raise ValueError(
            f"direction = 2 needs a second loaded direction: {deformation!r} has none "
            f"(only {' and '.join(with_two_directions())} do); use direction = 1"
        )
    return int(direction)


def log_uniform(a: float, b: float, l0: float, l1: float, dlog: float) -> np.ndarray:
    """Times after ``a`` up to ``b`` uniform in ln λ, λ linear in t from l0 to l1, with
    steps of at most dlog; empty if λ does not change."""
    dl = abs(np.log(l1 / l0))
    if dl == 0:
        return np.zeros(0)
    m = max(1, int(np.ceil(dl / dlog)))
    lam = l0 * np.exp(np.log(l1 / l0) * np.linspace(0.0, 1.0, m + 1)[1:])
    tt = a + (lam - l0) / (l1 - l0) * (b - a)
    tt[-1] = b
    return tt
