"""Nesting: the search of a law never ends worse than the fits of the laws it contains.

A law that contains another (:attr:`vhfit.hyperelastic.Hyperelastic.contains`: Yeoh
holds neo-Hooke at C20 = C30 = 0, Ogden-2 holds Ogden-1 at μ2 = 0, ...) can represent
every stress the smaller one can, so its best fit is at least as good. A global search
need not find it (issue: Yeoh at 48 % where neo-Hooke fits 8 %). The calibration of a
law with N Prony terms therefore first fits each law it contains with the same data,
N and settings (each of those seeded the same way, down the chain), puts the embedded
optimum (:meth:`~vhfit.hyperelastic.Hyperelastic.embed`, the Prony terms as they are)
into the first population of its own search, and at the end keeps the embedded point
if it is lower (*accept if lower*). The fits are remembered by (law, N, data,
settings), so that ``compare`` and ``--model all``, which fit the smaller laws anyway,
search each one once. docs/optimizer.md, "Nesting".

N Prony terms contain N − 1 (the missing term at G = 0: :func:`padded`), by the same
mechanism, a :class:`Nested` record of the same law with ``n_prony = N − 1``
(:func:`fewer_terms`), and no extra fit: the order scan hands each N the fit of N − 1
it has made (where that fit is done when N's begins; an N fitted beside N − 1 is fitted
again from it if it ended higher, :mod:`._scan`). A call with a fixed N is not seeded by
N − 1 (no fit is made for it), and a fit seeded by N − 1 is not remembered: a
remembered fit is then the same whatever the process fitted before, so that the same
call gives the same result in any process.

The guarantee holds for the same settings: bounds given on the law's own constants (no
such setting of the smaller law), a start population of the caller's own, or a
``max_time`` (a search cut short promises nothing) leave a fit unseeded by smaller
laws; the last two leave it unseeded by N − 1 too.
"""

from __future__ import annotations

import hashlib
import pickle
import time
import warnings
from collections import OrderedDict
from dataclasses import dataclass, fields, replace

import numpy as np

from vhfit.calibration._bounds import widen_bounds
from vhfit.calibration._polish import polish as polish_fit
from vhfit.calibration._settings import CalibrationSettings
from vhfit.calibration._space import search_vector
from vhfit.hyperelastic import get as get_law

__all__ = ["Nested", "nested_fits", "fewer_terms", "seed_rows", "accept_if_lower",
           "clear_cache", "CACHE_SIZE", "remember", "FLOOR_RTOL", "snapshot",
           "added_since", "keep", "containing_box"]

#: Fits remembered for the seeds of later ones (the least recently used dropped first),
#: each as (its RMSAPE, its constants).
CACHE_SIZE = 32
_CACHE: OrderedDict = OrderedDict()
#: A fit of N terms above its fit of N − 1 by more than this (relative) misses the floor:
#: the rounding of two models' integrations of the same stress and the terms pruned
#: below ``prune_tol`` stay within it.
FLOOR_RTOL = 1e-6
#: Settings that do not change a fit at a given N (the scan's, the process layout's and
#: those of the checkpoint and the user's callback, which a seeding fit runs without).
_NOT_THE_FIT = {"hyperelastic", "n_prony", "max_prony", "order_tol", "callback",
                "checkpoint", "checkpoint_every", "resume", "workers", "scan_workers",
                "check_rates", "uncertainty"}


@dataclass(frozen=True)
class Nested:
    """The fit of a contained law, as a point of the containing law's model."""

    law: str  # the contained law
    rmsape: float  # its fit's error
    x: np.ndarray  # its constants embedded in the containing law (its Prony terms kept)
    n_prony: int | None = None  # N − 1: the same law's fit with fewer terms; None: N's

    @property
    def label(self) -> str:
        """Its name in the result's ``options["nested"]``: the law, "law N=k" for k
        Prony terms."""
        return self.law if self.n_prony is None else f"{self.law} N={self.n_prony}"


def clear_cache() -> None:
    """Forget the remembered fits."""
    _CACHE.clear()


def _seedable(s: CalibrationSettings) -> bool:
    """Whether a fit with these settings takes seeds (see the module)."""
    opts = s.de_options or {}
    return s.max_time is None and "init" not in opts and "x0" not in opts


def _settings_for(settings: CalibrationSettings, smaller: str) -> CalibrationSettings | None:
    """The settings of the fit of ``smaller`` (a contained law, or the law itself with
    other N), or None where the guarantee does not apply (see the module)."""
    s = settings
    law = get_law(s.hyperelastic)
    if not _seedable(s):
        return None
    if (smaller != law.name and isinstance(s.bounds, dict)
            and set(s.bounds) & set(law.param_names)):
        return None
    # (no intervals: the seed needs the constants only)
    return replace(s, hyperelastic=smaller, callback=None, checkpoint=None, resume=False,
                   uncertainty=False)


def _key(curves, settings: CalibrationSettings, n_prony: int):
    """(law, N, digest of the data and the settings that make the fit), or None when
    they cannot be digested (no remembering then)."""
    law = get_law(settings.hyperelastic)
    what = tuple((f.name, getattr(settings, f.name)) for f in fields(settings)
                 if f.name not in _NOT_THE_FIT)
    try:
        data = pickle.dumps((list(curves), what), protocol=4)
    except Exception:  # a callable or object that does not pickle: fit every time
        return None
    return law.name, id(law), int(n_prony), hashlib.sha256(data).hexdigest()


def nested_fits(curves, settings: CalibrationSettings, n_prony: int,
                calibrate_n) -> list[Nested]:
    """The fits of the laws that the settings' law contains, each embedded in it.

    Parameters
    ----------
    curves : list
        The calibration's curves.
    settings : CalibrationSettings
        Its settings (the contained law's fit uses them with its own law).
    n_prony : int
        Prony terms of this fit.
    calibrate_n : callable
        The calibration at one N (``_calibrate_n`` of the workflow), which seeds the
        contained law's own search the same way.
    Returns
    -------
    list of Nested
        Empty for a law that contains none, or settings the guarantee does not cover.
    """
    law = get_law(settings.hyperelastic)
    if (settings.space.separable and n_prony == 0
            and len(law.linear_params) == law.n_params):
        # no search at all: least squares under the stability inequalities solves every
        # constant, a convex problem whose optimum is no higher than any stable point of
        # the law, the contained laws' fits among them
        return []
    out = []
    for smaller, _ in law.contains:
        s2 = _settings_for(settings, smaller)
        if s2 is None:
            continue
        key = _key(curves, s2, n_prony)
        fit = _CACHE.get(key) if key is not None else None
        if fit is None:
            with warnings.catch_warnings():  # its warnings are about another fit
                warnings.simplefilter("ignore")
                cal = calibrate_n(curves, s2, n_prony, checkpoint=None, max_time=None,
                                  t0=time.perf_counter(), prior=None)
            fit = _record(cal)
            if key is not None:
                _store(key, fit)
        else:
            _CACHE.move_to_end(key)
        small = get_law(smaller)
        rmsape, x = fit
        hyper = law.embed(small, x[: small.n_params])
        out.append(Nested(small.name, rmsape, np.concatenate([hyper, x[small.n_params:]])))
    return out


def fewer_terms(curves, settings: CalibrationSettings, n_prony: int,
                prior=None) -> list[Nested]:
    """The fit of the same law with N − 1 Prony terms, a point of this fit's space.

    Parameters
    ----------
    curves : list
        The calibration's curves.
    settings : CalibrationSettings
        Its settings.
    n_prony : int
        Prony terms of this fit (N).
    prior : Calibration or None
        The fit of N − 1 (the order scan's); None: none.

    Returns
    -------
    list of Nested
        One record (``n_prony = N − 1``), or none.
    """
    if n_prony < 1 or prior is None or not _seedable(settings):
        return []
    law = get_law(settings.hyperelastic)
    fit = _record(prior)
    return [Nested(law.name, fit[0], fit[1], n_prony - 1)]


def _record(cal) -> tuple[float, np.ndarray]:
    """What a fit's seeds need of it: (its RMSAPE, its constants)."""
    return float(cal.rmsape), np.array(cal.x, dtype=np.float64)


def remember(curves, settings: CalibrationSettings, n_prony: int, cal) -> None:
    """Keep a fit made for the user (its law's own calibration) for the seeds of later
    fits that contain its law (``compare`` fitting neo-Hooke, then Yeoh)."""
    s2 = _settings_for(settings, get_law(settings.hyperelastic).name)
    key = None if s2 is None else _key(curves, s2, n_prony)
    if key is not None:
        _store(key, _record(cal))


def _store(key, fit) -> None:
    _CACHE[key] = fit
    _CACHE.move_to_end(key)
    while len(_CACHE) > CACHE_SIZE:
        _CACHE.popitem(last=False)


def snapshot() -> set:
    """The keys of the fits remembered now (for :func:`added_since`)."""
    return set(_CACHE)


def added_since(keys: set) -> list:
    """The fits remembered since :func:`snapshot` gave ``keys``: (key, fit) pairs that
    pickle, which :func:`keep` remembers in another process (the order scan's child
    hands its fits to the parent)."""
    return [(k, v) for k, v in _CACHE.items() if k not in keys]


def keep(entries: list) -> None:
    """Remember the fits of :func:`added_since`."""
    for k, v in entries:
        _store(k, v)


def seed_rows(space, nested: list[Nested]) -> list[np.ndarray]:
    """The search vectors of ``space`` of the nested fits, clipped into its bounds."""
    b = np.asarray(space.bounds(), dtype=np.float64).reshape(-1, 2)
    if not len(b):
        return []
    return [np.clip(search_vector(space, n.x), b[:, 0], b[:, 1]) for n in nested]


def padded(prob, x: np.ndarray) -> np.ndarray:
    """The full parameter vector of ``prob``'s model from ``x`` with N or fewer Prony
    terms (the missing ones with G = 0 at the middle of their τ range)."""
    return prob.model.layout.from_log(search_vector(_AsFull(prob), x))


class _AsFull:
    """The all-parameter view of a problem, for :func:`search_vector`'s slotting."""

    separable = False  # every parameter in the vector

    def __init__(self, prob):
        self.prob = prob


def containing_box(prob, nested: list[Nested]) -> dict[str, tuple[float, float]]:
    """The automatic bounds of the law's constants that a nested fit lies outside of,
    widened (:func:`~vhfit.calibration._bounds.widen_bounds`, repeatedly) until each
    nested fit is a point of the box: name -> (low, high); empty where each already is.

    A contained law's fit may end outside this law's automatic box where its own search
    widened a bound it ended on (Ogden-4's α3 past 10); its embedded point is then no
    member of this law's search, and accept-if-lower could not keep it. Bounds the user
    gave are kept (no nested fits are made under them), and so are the Prony terms' τ
    bounds: the same strategy gives the same τ ranges to a contained law's fit, and N's
    range of a term need not hold N − 1's (``semifree``).
    """
    hm = prob.hm
    bounds, out = dict(prob.bounds), {}
    for n in nested:
        x = padded(prob, n.x)
        for _ in range(8):  # each pass moves a bound WIDEN widths out (or to its limit)
            hits = {}
            for k, name in enumerate(hm.param_names):
                lo, hi = (float(v) for v in bounds[name])
                if name not in prob.user_bounds and np.isfinite(x[k]):
                    if x[k] < lo:
                        hits[name] = "low"
                    elif x[k] > hi:
                        hits[name] = "high"
            if not hits:
                break
            wide = widen_bounds(prob, hits, bounds)
            for name in hits:
                bounds[name] = out[name] = wide[name]
    return out


def _in_box(space, x: np.ndarray) -> bool:
    """Whether ``x`` is a point of ``space``'s search box (its search vector unclipped)."""
    b = np.asarray(space.bounds(), dtype=np.float64).reshape(-1, 2)
    z = search_vector(space, x)
    return bool(np.all(np.isfinite(z)) and np.all(z >= b[:, 0]) and np.all(z <= b[:, 1]))


def accept_if_lower(prob, space, nested: list[Nested], x: np.ndarray, err: float,
                    polish: bool) -> tuple[np.ndarray, float, str | None]:
    """The search's result ``(x, err)``, or the lowest nested fit where that is lower
    (polished in this law's space when ``polish``): ``(x, err, label of the fit kept
    or None)``."""
    kept = None
    for n in nested:
        xn = padded(prob, n.x)
        if not _in_box(space, xn):  # outside the box searched: not a point of this fit
            continue
        en = float(prob.errors(xn[None, :])[0])
        if not en < err:
            continue
        if polish:
            xp, ep, _ = polish_fit(prob, xn)
            if ep < en:
                xn, en = xp, ep
        x, err, kept = xn, en, n.label
    return x, err, kept
