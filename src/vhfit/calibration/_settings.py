"""The front door of :func:`vhfit.calibrate`: its settings, one frozen object, every
argument checked before any computation (:class:`CalibrationSettings`)."""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import Any

from vhfit._words import setting, worded
from vhfit.formulations import get_formulation
from vhfit.model import ModelSpec, Prony
from vhfit.viscous import ParamLayout

__all__ = ["CalibrationSettings", "check_arguments", "DEFAULT_TOL", "RecordedCallable",
           "bound_problem", "bounds_terms", "bounds_for_terms"]

DEFAULT_TOL = 1e-6
DEFAULT_TAU_STRATEGY = "free"
DEFAULT_DECADES_BELOW = 3  # one decade of margin below Eq. 22: real τ_1 can sit just under it
DEFAULT_DECADES_ABOVE = 1
FULL_TOL = 1e-5  # the paper's best-mean gap of 0.001 %, the full method's default


def _fail(name: str, value: Any, fix: str) -> None:
    raise worded(ValueError, f"{name} = {value!r}: {fix}")


def _is_int(v: Any) -> bool:
    return isinstance(v, numbers.Integral) and not isinstance(v, bool)


def _is_real(v: Any) -> bool:
    return isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v)


def _int(a: dict, name: str, low: int, *, optional: bool = False) -> None:
    v = a[name]
    if optional and v is None:
        return
    if not _is_int(v) or v < low:
        _fail(name, v, f"give a whole number >= {low}" + (" or None" if optional else ""))


def _real(a: dict, name: str, low: float, high: float = math.inf, *, open_low=False,
          open_high=False, optional: bool = False) -> None:
    v = a[name]
    if optional and v is None:
        return
    ok = _is_real(v) and (v > low if open_low else v >= low) and (
        v < high if open_high else v <= high)
    if not ok:
        lo = f"> {low:g}" if open_low else f">= {low:g}"
        hi = "" if high == math.inf else (f" and < {high:g}" if open_high else f" and <= {high:g}")
        _fail(name, v, f"give a finite number {lo}{hi}" + (" or None" if optional else ""))


def _flag(a: dict, name: str) -> None:
    if not isinstance(a[name], (bool, int)) or a[name] not in (0, 1):
        _fail(name, a[name], "give True or False")


def _choices(a: dict) -> None:
    from vhfit.calibration._space import SPACES
    from vhfit.optimize import tau_strategies

    get_formulation(a["formulation"])  # its own one-line error
    if a["method"] not in SPACES:
        _fail("method", a["method"], "choose 'separable' or 'full'")
    n = a["n_prony"]
    if not (n is None or (n == "auto" if isinstance(n, str) else _is_int(n) and n >= 0)):
        _fail("n_prony", n, "give a whole number >= 0, 'auto', or None (the default)")
    ts = a["tau_strategy"]
    if not callable(ts) and ts not in tau_strategies():
        _fail("tau_strategy", ts, f"choose one of {sorted(tau_strategies())} or give a callable")
    if not (a["bounds"] == "auto" if isinstance(a["bounds"], str) else
            isinstance(a["bounds"], dict)):
        _fail("bounds", a["bounds"], "give 'auto' or a dict name -> (low, high)")
    _user_bounds(a)
    w = a["workers"]
    if not (callable(w) or (_is_int(w) and (w >= 1 or w == -1))):
        _fail("workers", w, "give -1, a whole number >= 1, or a map-like callable")
    if a["callback"] is not None and not callable(a["callback"]):
        _fail("callback", a["callback"], "give a callable f(state_dict) or None")
    if a["de_options"] is not None and not isinstance(a["de_options"], dict):
        _fail("de_options", a["de_options"], "give a dict of solver keywords or None")
    ck = a["checkpoint"]
    if ck is not None and not isinstance(ck, (str, os.PathLike)):
        _fail("checkpoint", ck, "give a file path or None")
    if a["resume"] and ck is None:
        _fail("resume", a["resume"], "resuming needs checkpoint=PATH (the file to resume from)")


def bounds_terms(n_prony: Any, max_prony: int = 5) -> int:
    """The most Prony terms a fit with ``n_prony`` (a number, ``"auto"`` or None) may have:
    the Prony names a ``bounds=`` entry may use (``G1``, ``tau1``, ... up to this index).

    Examples
    --------
    >>> from vhfit.calibration import bounds_terms
    >>> bounds_terms(3), bounds_terms("auto", max_prony=6), bounds_terms(None)
    (3, 6, 2)
    """
    if isinstance(n_prony, str):
        return int(max_prony)
    if n_prony is None:
        from vhfit.calibration._identify import DEFAULT_N_PRONY
        return DEFAULT_N_PRONY
    return int(n_prony)


def bound_problem(name: str, low: float, high: float, hyperelastic: Any,
                  n_terms: int) -> str | None:
    """Why the search limits ``(low, high)`` given for one parameter cannot be used, as
    the fix to make, or None when they can.

    The parameter must be one of the law's constants or a Prony term ``G<i>``/``tau<i>``
    with i <= ``n_terms``; ``low <= high`` (equal limits fix the parameter); the limits
    finite (a linear constant of the law may be unbounded: ±inf) and inside the
    parameter's physical range: the law's own range for its constants (e.g. C10 >= 0 of
    neo-Hooke, λm >= 1 of Arruda–Boyce), G_i >= 0 (a Prony modulus), τ_i > 0 (s).

    Parameters
    ----------
    name : str
        The parameter, as the model names it (``"C10"``, ``"alpha1"``, ``"tau2"``).
    low, high : float
        The limits given.
    hyperelastic : str or Hyperelastic
        The law (an unknown name: only the Prony terms and the numbers are checked).
    n_terms : int
        The most Prony terms of the fit (:func:`bounds_terms`).

    Returns
    -------
    str or None
        What is wrong and how to fix it (one line, without the parameter's name first),
        or None.

    Examples
    --------
    >>> from vhfit.calibration import bound_problem
    >>> bound_problem("alpha1", -40.0, 40.0, "ogden", 1) is None
    True
    >>> bound_problem("C10", -1.0, 1.0, "neo_hooke", 1)
    'outside the physical range of C10 of the neo_hooke law, [0, inf]: give limits within it'
    >>> bound_problem("tau1", 0.0, 1.0, "neo_hooke", 1)
    'a relaxation time is > 0 s: give 0 < low'
    """
    from vhfit import hyperelastic as _hyper

    try:
        law = _hyper.get(hyperelastic)
    except ValueError:
        law = None
    prony = ParamLayout.parse(name)
    if law is None and not prony:
        return None  # a constant of a law not registered (yet): its fit names the law
    names = list(law.param_names) if law is not None else []
    if str(name) not in names and not (prony and prony.index < n_terms):
        terms = list(ParamLayout((), (), n_terms).term_names())
        terms_txt = (f"with up to {n_terms} Prony term(s)" if n_terms else
                     "without Prony terms")
        what = (f"the {law.name} law {terms_txt}" if law is not None
                else f"a fit {terms_txt}")
        more = (f" (more terms: raise {setting('n_prony', '--prony')})" if prony else "")
        return (f"unknown parameter of {what}{more}; give one of "
                f"{', '.join(names + terms) or 'none'}")
    try:
        lo, hi = float(low), float(high)
    except (TypeError, ValueError):
        return "give two numbers (low, high)"
    if math.isnan(lo) or math.isnan(hi):
        return "give two numbers (low, high), not NaN"
    if lo > hi:
        return "the lower limit is above the upper: give low <= high"
    unbounded_ok = law is not None and not prony and names.index(str(name)) in law.linear_index
    if not (math.isfinite(lo) and math.isfinite(hi)) and not unbounded_ok:
        return ("give finite limits (only a constant the law is linear in may be "
                "unbounded)")
    if prony and prony.role == ParamLayout.TIME:
        return None if lo > 0 else "a relaxation time is > 0 s: give 0 < low"
    if prony and prony.role == ParamLayout.AMPLITUDE:
        return None if lo >= 0 else "a Prony modulus G_i is >= 0: give low >= 0"
    plo, phi = law.bounds[names.index(str(name))]
    if lo < plo or hi > phi:
        return (f"outside the physical range of {name} of the {law.name} law, "
                f"[{plo:g}, {phi:g}]: give limits within it")
    return None


def bounds_for_terms(bounds: Any, n_prony: int) -> Any:
    """``bounds`` of a fit with ``n_prony`` terms: without the entries of Prony terms it
    does not have (an order scan's smaller N); "auto" as it is.

    Parameters
    ----------
    bounds : "auto" or dict
        ``calibrate``'s ``bounds=``.
    n_prony : int
        The fit's number of Prony terms.

    Returns
    -------
    "auto" or dict

    Examples
    --------
    >>> from vhfit.calibration._settings import bounds_for_terms
    >>> bounds_for_terms({"C10": (0, 1), "tau1": (1, 2), "G3": (0, 5)}, 2)
    {'C10': (0, 1), 'tau1': (1, 2)}
    """
    if not isinstance(bounds, dict):
        return bounds
    out = {}
    for k, v in bounds.items():
        term = ParamLayout.parse(k)
        if term is None or term.index < n_prony:
            out[k] = v
    return out


def _user_bounds(a: dict) -> None:
    """Each entry of a ``bounds`` dict: a known parameter, limits in its physical range."""
    b = a["bounds"]
    if not isinstance(b, dict):
        return
    n_terms = bounds_terms(a["n_prony"], a["max_prony"] if _is_int(a["max_prony"]) else 5)
    for name, v in b.items():
        if not isinstance(name, str):
            _fail("bounds", b, f"name the parameters by text, not {name!r}")
        if not (isinstance(v, (tuple, list)) and len(v) == 2):
            _fail(f"bounds[{name!r}]", v, "give a pair (low, high)")
        fix = bound_problem(name, v[0], v[1], a["hyperelastic"], n_terms)
        if fix is not None:
            _fail(f"bounds[{name!r}]", v, fix)


def _pairs(a: dict) -> None:
    stall = a["stall"]
    if not (isinstance(stall, (tuple, list)) and len(stall) == 2 and _is_real(stall[0])
            and stall[0] >= 0 and _is_int(stall[1]) and stall[1] >= 1):
        _fail("stall", stall, "give (fraction >= 0, generations >= 1), e.g. (0.02, 2000)")
    sr = a["stability_range"]
    if sr is not None and not (isinstance(sr, (tuple, list)) and len(sr) == 2
                               and all(_is_real(v) for v in sr) and 0 < sr[0] < 1 < sr[1]):
        _fail("stability_range", sr,
              "give (low, high) stretches with 0 < low < 1 < high, or None (the data's range)")
    t = a["target"]
    if isinstance(t, bool) or not isinstance(t, numbers.Real) or math.isnan(t):
        _fail("target", t, "give a number (the objective value that ends the search)")


def _shift(a: dict) -> None:
    """``shift_factors`` (a law, a dict {T: log10 a_T} or a pair) and ``T_ref``."""
    T_ref, sf = a["T_ref"], a["shift_factors"]
    if T_ref is not None and not _is_real(T_ref):
        _fail("T_ref", T_ref, "give the reference temperature as a finite number, or None")
    if sf is None:
        return
    fix = ("give a law (vhfit.tts.WLF(C1, C2, T_ref), ...), a dict {temperature: log10 a_T} "
           "or a pair (temperatures, log10 a_T)")
    if hasattr(sf, "log_aT"):
        # getattr default: a user's shift law (anything with log_aT) may have no T_ref
        law_T = getattr(sf, "T_ref", None)
        if T_ref is not None and law_T is not None and abs(float(law_T) - T_ref) > 1e-12:
            _fail("T_ref", T_ref, f"the shift law is referred to T_ref = {law_T!r}: drop "
                  "T_ref or give a law at it")
        return
    if isinstance(sf, dict):
        pairs = list(sf.items())
    elif isinstance(sf, (tuple, list)) and len(sf) == 2:
        try:
            tt, ll = (list(map(float, v)) for v in sf)
        except (TypeError, ValueError):
            _fail("shift_factors", sf, fix)
        if len(tt) != len(ll):
            _fail("shift_factors", sf, f"{len(tt)} temperatures and {len(ll)} log10 a_T: "
                  "give one log10 a_T per temperature")
        pairs = list(zip(tt, ll))
    else:
        _fail("shift_factors", sf, fix)
    if not pairs or not all(_is_real(T) and _is_real(L) for T, L in pairs):
        _fail("shift_factors", sf, "give at least one temperature, each with a finite "
              "log10 a_T")


def check_arguments(a: dict) -> None:
    """Raise a one-line ValueError naming the first bad argument of ``calibrate`` and the fix."""
    _choices(a)
    _pairs(a)
    _shift(a)
    _int(a, "max_prony", 1)
    if a["scan_workers"] not in ("auto", 1, 2) or isinstance(a["scan_workers"], bool):
        _fail("scan_workers", a["scan_workers"], "give 'auto', 1 (one N after the other) "
              "or 2 (two N side by side)")
    _int(a, "popsize", 5, optional=True)
    _int(a, "maxiter", 1, optional=True)
    _real(a, "tol", 0.0)
    _real(a, "g_inf_min", 0.0, 1.0, open_high=True)
    _real(a, "max_time", 0.0, optional=True)
    _real(a, "order_tol", 0.0)
    _real(a, "prune_tol", 0.0)
    _real(a, "decades_below", 0.0)
    _real(a, "decades_above", 0.0)
    _real(a, "rtol", 0.0, 1.0, open_low=True, open_high=True)
    _real(a, "checkpoint_every", 0.0)
    for name in ("polish", "uncertainty", "resume", "check_rates"):
        _flag(a, name)


@dataclass(frozen=True)
class CalibrationSettings:
    """Everything that decides how :func:`vhfit.calibrate` fits, checked once.

    The fields are :func:`vhfit.calibrate`'s arguments after the curves, with the same
    names, defaults and meaning (see there). Building one checks every field and raises
    a one-line ``ValueError`` naming the first bad one and the fix; a settings object
    that exists is valid. The workflow, the search, the report and the results file read
    it; :meth:`to_dict` is what a results file records under ``"settings"``.

    Examples
    --------
    >>> from vhfit import CalibrationSettings
    >>> s = CalibrationSettings("neo_hooke", n_prony=1, seed=0)
    >>> s.method, s.effective_tol
    ('separable', 1e-06)
    >>> CalibrationSettings.from_dict(s.to_dict()) == s
    True
    >>> CalibrationSettings(popsize=3)
    Traceback (most recent call last):
    ...
    ValueError: popsize = 3: give a whole number >= 5 or None
    """

    hyperelastic: Any = "mooney_rivlin"
    n_prony: int | str | None = None
    tau_strategy: str | Callable = DEFAULT_TAU_STRATEGY
    bounds: str | dict = "auto"
    objective: str | Callable = "rmsape"
    method: str = "separable"
    seed: Any = None
    workers: int | Callable = 1
    scan_workers: int | str = "auto"
    popsize: int | None = None
    maxiter: int | None = None
    tol: float = DEFAULT_TOL
    target: float = 1e-4
    stall: tuple[float, int] = (0.02, 2000)
    polish: bool = True
    g_inf_min: float = 1e-6
    max_time: float | None = None
    max_prony: int = 5
    order_tol: float = 0.05
    prune_tol: float = 1e-6
    decades_below: float = DEFAULT_DECADES_BELOW
    decades_above: float = DEFAULT_DECADES_ABOVE
    stability_range: tuple[float, float] | None = None
    uncertainty: bool = True
    callback: Callable | None = None
    rtol: float = 1e-6
    de_options: dict | None = None
    checkpoint: Any = None
    checkpoint_every: float = 5.0
    resume: bool = False
    check_rates: bool = True
    formulation: str = "hereditary"
    shift_factors: Any = None
    T_ref: float | None = None

    def __post_init__(self) -> None:
        check_arguments(self.keywords())

    def keywords(self) -> dict[str, Any]:
        """The fields as :func:`vhfit.calibrate`'s keywords (``calibrate(curves,
        **settings.keywords())`` fits with these settings).

        Returns
        -------
        dict
            Field name -> value, in calibrate's order.

        Examples
        --------
        >>> from vhfit import CalibrationSettings
        >>> list(CalibrationSettings().keywords())[:3]
        ['hyperelastic', 'n_prony', 'tau_strategy']
        """
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def model_spec(self, n_prony: int) -> ModelSpec:
        """The spec of the model these settings fit with ``n_prony`` terms (the fit's own
        number, or one of an order scan's): the law, formulation and accuracy given.

        Examples
        --------
        >>> from vhfit import CalibrationSettings
        >>> CalibrationSettings("yeoh", n_prony="auto").model_spec(2).describe()
        'yeoh + 2 Prony term(s)'
        """
        return ModelSpec(self.hyperelastic, Prony(n_prony, self.formulation), self.rtol)

    @property
    def space(self) -> type:
        """The search space of ``method`` (``SeparableSpace`` or ``FullSpace``): what
        the method is (``space.separable``) is asked of it."""
        from vhfit.calibration._space import SPACES

        return SPACES[self.method]

    @property
    def effective_tol(self) -> float:
        """The best–mean gap the search stops at: ``tol``, or for the full method left at
        the default, the paper's 1e-5."""
        if not self.space.separable and self.tol == DEFAULT_TOL:
            return FULL_TOL
        return self.tol

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready record of the settings (a results file's ``"settings"``).

        Numbers, strings, None and containers of them are kept; tuples become lists; a
        callable (a ``tau_strategy``, ``objective``, ``workers`` map or ``callback``) is
        recorded by name as ``{"callable": "module.name"}``; a shift law as ``{"law":
        name, "constants": {...}}``; shift factors given as a table as ``{"table":
        [[T, log10 a_T], ...]}``; anything else as ``{"repr": repr(value)}``.

        Returns
        -------
        dict

        Examples
        --------
        >>> from vhfit import CalibrationSettings
        >>> CalibrationSettings(stall=(0.01, 50)).to_dict()["stall"]
        [0.01, 50]
        """
        out = {k: _record(v) for k, v in self.keywords().items()}
        out["shift_factors"] = _record_shift(self.shift_factors)
        law = self.hyperelastic  # a registered name or a Hyperelastic object
        out["hyperelastic"] = law if isinstance(law, str) else str(law.name)
        return out

    @classmethod
    def from_dict(cls, d: dict) -> CalibrationSettings:
        """Settings from :meth:`to_dict` (a results file's ``"settings"`` entry).

        Fields the record lacks take their defaults; unknown entries are ignored (a
        newer vhfit's settings). A callable recorded by name comes back as a
        :class:`RecordedCallable` that says so when called: give the callable again to
        rerun the fit.

        Parameters
        ----------
        d : dict
            What :meth:`to_dict` wrote.

        Returns
        -------
        CalibrationSettings

        Raises
        ------
        ValueError
            A recorded value that is not a valid setting (one line naming it).

        Examples
        --------
        >>> from vhfit import CalibrationSettings
        >>> CalibrationSettings.from_dict({"n_prony": 3, "stall": [0.01, 50]}).stall
        (0.01, 50)
        """
        if not isinstance(d, dict):
            raise TypeError("'settings' is not a mapping of name to value")
        known = {f.name for f in fields(cls)}
        kw = {k: _restore(v) for k, v in d.items() if k in known}
        for k in ("stall", "stability_range"):
            if isinstance(kw.get(k), list):
                kw[k] = tuple(kw[k])
        if isinstance(kw.get("bounds"), dict):
            kw["bounds"] = {k: tuple(v) if isinstance(v, list) else v
                            for k, v in kw["bounds"].items()}
        if "shift_factors" in kw:
            kw["shift_factors"] = _restore_shift(d["shift_factors"])
        return cls(**kw)


class RecordedCallable:
    """A callable of a settings record, known by name only (a results file cannot hold
    the function itself); calling it says so.

    Examples
    --------
    >>> from vhfit.calibration import RecordedCallable
    >>> f = RecordedCallable("mymodule.my_objective")
    >>> f
    RecordedCallable('mymodule.my_objective')
    """

    def __init__(self, name: str):
        self.name = str(name)

    def __call__(self, *args, **kwargs):
        raise TypeError(f"{self.name} was recorded by name only; give the callable itself "
                        "to calibrate with these settings")

    def __repr__(self) -> str:
        return f"RecordedCallable({self.name!r})"

    def __eq__(self, other) -> bool:
        return isinstance(other, RecordedCallable) and other.name == self.name

    def __hash__(self) -> int:
        return hash(self.name)


def _callable_name(f) -> str:
    if isinstance(f, RecordedCallable):
        return f.name
    # getattr defaults: a partial or a callable instance has no __qualname__/__module__
    name = getattr(f, "__qualname__", None) or type(f).__qualname__
    module = getattr(f, "__module__", None) or type(f).__module__
    return f"{module}.{name}"


def _record(v) -> Any:
    """One value as JSON (see :meth:`CalibrationSettings.to_dict`)."""
    if v is None or isinstance(v, (bool, str)):
        return v
    if isinstance(v, numbers.Integral):
        return int(v)
    if isinstance(v, numbers.Real):
        return float(v)
    if isinstance(v, os.PathLike):
        return os.fspath(v)
    if isinstance(v, (tuple, list)):
        return [_record(x) for x in v]
    if isinstance(v, dict) and all(isinstance(k, str) for k in v):
        return {k: _record(x) for k, x in v.items()}
    if callable(v):
        return {"callable": _callable_name(v)}
    return {"repr": repr(v)}


def _restore(v) -> Any:
    """One value of a record back (callables as :class:`RecordedCallable`)."""
    if isinstance(v, dict):
        if set(v) == {"callable"}:
            return RecordedCallable(v["callable"])
        if set(v) == {"repr"}:
            return str(v["repr"])
        return {k: _restore(x) for k, x in v.items()}
    if isinstance(v, list):
        return [_restore(x) for x in v]
    return v


def _record_shift(sf) -> Any:
    """``shift_factors`` as JSON: a law by name and constants, a table by its pairs."""
    if sf is None:
        return None
    if hasattr(sf, "log_aT") and hasattr(sf, "constants"):
        return {"law": sf.name, "constants": {k: float(v) for k, v in sf.constants().items()}}
    if isinstance(sf, dict):
        return {"table": [[float(T), float(L)] for T, L in sf.items()]}
    return {"pair": _record(sf)}


def _restore_shift(d) -> Any:
    if not isinstance(d, dict):
        return d
    if "law" in d:
        return shift_law(d["law"], d.get("constants") or {})
    if "table" in d:
        return {float(T): float(L) for T, L in d["table"]}
    if "pair" in d:
        return tuple(d["pair"])
    return _restore(d)


def shift_law(name, c: dict):
    """A shift law from its name and :meth:`constants` (None for an unknown name)."""
    from vhfit.tts import WLF, Arrhenius, PolynomialShift

    if name == "wlf":
        return WLF(float(c["C1"]), float(c["C2"]), float(c["T_ref"]))
    if name == "arrhenius":
        return Arrhenius(float(c["E_a"]), float(c["T_ref"]),
                         float(c.get("absolute_zero", -273.15)))
    if name == "polynomial":
        coef = [float(c[f"c{k}"]) for k in range(1, len(c))]
        return PolynomialShift(tuple(coef), float(c["T_ref"]))
    return None
