"""Objective functions: RMSAPE (paper Eq. 20) and alternatives, batched over a population.

Every objective here is a *scaled, weighted root mean square* of the point residuals

.. math::

    F = \\sqrt{\\frac{\\sum_p w_p \\, r_p^2}{\\sum_p w_p}}, \\qquad
    r_p = \\frac{\\sigma_{\\mathrm{model},p} - \\sigma_{\\mathrm{obj},p}}{s_p},

over all objective points ``p`` of all curves; the objectives differ only in the scale
``s_p``:

``"rmsape"`` (paper Eq. 20, percent)
    ``s_p = mean_k |σ_obj,ik| / 100`` for a point of curve ``i``: each curve's residuals
    are taken relative to that curve's mean stress, so slow and fast curves count alike.
    An item with a ``target_scale`` array (a frequency sweep, a relaxation test: moduli
    spanning decades) is measured point by point instead, ``s_p = target_scale_p / 100``
    (``|E′|``, ``|E″|``, ``|E(t)|``): the relative error of each modulus, in percent.
``"rmse"`` (MPa)
    ``s_p = 1``.
``"relative_l2"`` (percent)
    ``s_p = sqrt(Σ w σ_obj² / Σ w) / 100``, one scale for all curves: ``F`` is then
    ``100 ‖σ_model − σ_obj‖_w / ‖σ_obj‖_w`` and high-stress curves dominate.

The weight of a point is its curve's weight times its own point weight (both 1 by
default); with equal weights and ``n`` points on each of ``m`` curves, ``"rmsape"`` is
exactly Eq. 20. With unequal point counts it is the RMS over all points.

Model stresses come as an array of shape ``(..., N)`` with the curves' points
concatenated in order (``N = Σ n_i``); a population of ``P`` individuals is ``(P, N)``
and gives ``P`` errors in one vectorised step. A non-finite model stress anywhere in an
individual gives that individual an error of ``+inf`` (never NaN), so an optimiser simply
rejects it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from vhfit._words import setting, worded
from vhfit.data import TestItem

__all__ = [
    "OBJECTIVES",
    "Objective",
    "per_curve_rmsape",
    "register_objective",
    "relative_l2",
    "rmsape",
    "rmse",
]

#: A scale function: ``scale(target, curve, weights) -> s`` gives the residual scale of
#: every point (shape ``(N,)``) from the concatenated targets, the curve index of each
#: point and the point weights.
ScaleFunction = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]

#: Registered objectives: name -> scale function (see the module docstring).
OBJECTIVES: dict[str, ScaleFunction] = {}


def register_objective(name: str) -> Callable[[ScaleFunction], ScaleFunction]:
    """Register a scale function under ``name`` (a decorator).

    Parameters
    ----------
    name : str
        The name that :class:`Objective` and the calibrator accept as ``kind``.

    Examples
    --------
    >>> @register_objective("rmse_kpa")
    ... def _kpa(target, curve, weights):
    ...     return np.full(target.shape, 1e-3)       # residuals in kPa
    >>> Objective([[1.0, 2.0]], "rmse_kpa")([1.0, 2.001])
    0.7071...
    >>> del OBJECTIVES["rmse_kpa"]
    """

    def deco(func: ScaleFunction) -> ScaleFunction:
        OBJECTIVES[name] = func
        return func

    return deco


def _curve_mean_abs(target: np.ndarray, curve: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Point-weighted mean of |target| over each curve (unweighted when weights are equal)."""
    m = int(curve.max()) + 1
    # a curve whose points all have weight 0 still needs a scale: fall back to the plain mean
    wsum = np.bincount(curve, weights=weights, minlength=m)
    num = np.bincount(curve, weights=weights * np.abs(target), minlength=m)
    plain = np.bincount(curve, weights=np.abs(target), minlength=m) / np.bincount(
        curve, minlength=m
    )
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(wsum > 0, num / np.where(wsum > 0, wsum, 1.0), plain)
    return mean


@register_objective("rmsape")
def _scale_rmsape(target: np.ndarray, curve: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Eq. 20: residuals relative to the curve's mean |stress|, in percent."""
    mean = _curve_mean_abs(target, curve, weights)
    bad = ~(mean > 0) | ~np.isfinite(mean)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise _NoScale(i, f"has a mean |stress| of {mean[i]:g} at its objective points: "
                          "RMSAPE (Eq. 20) divides by it; "
                          + setting("drop that curve or use objective='rmse'",
                                    "leave its file out"))
    return mean[curve] / 100.0


class _NoScale(ValueError):
    """A curve whose residual scale is undefined; :class:`Objective` names the curve."""

    def __init__(self, index: int, what: str) -> None:
        super().__init__(f"curve {index} {what}")
        self.index, self.what = index, what


@register_objective("rmse")
def _scale_rmse(target: np.ndarray, curve: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Plain residuals, in the stress unit (MPa)."""
    return np.ones_like(target)


@register_objective("relative_l2")
def _scale_relative_l2(target: np.ndarray, curve: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Residuals relative to the RMS target stress of all curves together, in percent."""
    rms = float(np.sqrt(np.sum(weights * target**2) / np.sum(weights)))
    if not rms > 0:
        raise ValueError(
            "all target stresses are zero: relative_l2 divides by their RMS; use "
            "objective='rmse'"
        )
    return np.full_like(target, rms / 100.0)


def _as_targets(targets: Any) -> list[np.ndarray]:
    """Targets as a list of 1-D float arrays, one per curve."""
    if isinstance(targets, TestItem):  # a single curve, sweep or relaxation test
        targets = [targets]
    if isinstance(targets, np.ndarray) and targets.ndim == 1:
        targets = [targets]
    if isinstance(targets, np.ndarray) and targets.ndim == 2:
        return [np.asarray(row, dtype=np.float64) for row in targets]
    out = []
    for i, t in enumerate(targets):
        arr = np.asarray(t.target_stress if isinstance(t, TestItem) else t, dtype=np.float64)
        if arr.ndim == 0:
            # a flat list of numbers is one curve
            return [np.asarray(targets, dtype=np.float64).reshape(-1)]
        if arr.ndim != 1:
            raise ValueError(f"target of curve {i} must be 1-D, got shape {arr.shape}")
        out.append(arr)
    return out


class Objective:
    """An objective over a fixed set of curves, evaluated for one model or a population.

    Parameters
    ----------
    curves : sequence of Curve or of array_like
        The curves (anything with a ``target_stress`` array, and optionally ``weight``
        and ``target_weights``) or their target stresses directly, one 1-D array per
        curve (a 2-D array: one row per curve).
    kind : str or callable, default "rmsape"
        A name in :data:`OBJECTIVES` (``"rmsape"``, ``"rmse"``, ``"relative_l2"``) or a
        scale function ``scale(target, curve, weights) -> s`` (see the module docstring).
    weights : sequence of float, optional
        Per-curve weights; default: each curve's ``weight`` attribute, else 1.

    Attributes
    ----------
    target : ndarray, shape (N,)
        Concatenated target stresses.
    curve : ndarray of int, shape (N,)
        Curve index of each point.
    slices : list of slice
        Where each curve's points sit in the concatenated vector.
    weights : ndarray, shape (N,)
        Point weights (curve weight times point weight).
    scale : ndarray, shape (N,)
        Residual scale of each point.

    Notes
    -----
    ``residuals(s)`` returns ``r`` with ``objective(s) == sqrt(mean(r**2))``, the form
    :func:`scipy.optimize.least_squares` minimises (it minimises ``sum(r**2) / 2``).

    Examples
    --------
    Two curves of three points; the model is 10 % high on the second point of curve 0:

    >>> obj = Objective([[-1.0, -2.0, -3.0], [-10.0, -20.0, -30.0]])
    >>> model = np.array([[-1.0, -2.2, -3.0, -10.0, -20.0, -30.0],
    ...                   [-1.0, -2.0, -3.0, -10.0, -20.0, -30.0]])
    >>> obj(model)                       # one error per individual
    array([4.0824829, 0.       ])
    >>> obj.per_curve(model[0])
    array([5.77350269, 0.        ])
    """

    def __init__(
        self,
        curves: Sequence[Any] | np.ndarray,
        kind: str | ScaleFunction = "rmsape",
        *,
        weights: Sequence[float] | None = None,
    ) -> None:
        if isinstance(curves, TestItem):
            items: list[Any] | None = [curves]
        elif isinstance(curves, np.ndarray):
            items = None
        else:  # test items (their weights and scales count), or arrays of targets
            items = list(curves)
            if not all(isinstance(c, TestItem) for c in items):
                items = None
        targets = _as_targets(items if items is not None else curves)
        m = len(targets)
        if m == 0:
            raise ValueError("no curves given: an objective needs at least one curve")
        sizes = [t.size for t in targets]
        for i, n in enumerate(sizes):
            if n == 0:
                raise ValueError(f"curve {i} has no objective points")
        for i, t in enumerate(targets):
            if not np.isfinite(t).all():
                j = int(np.flatnonzero(~np.isfinite(t))[0])
                raise ValueError(f"target stress {j} of curve {i} is {t[j]!r}: not finite")
        # weights: curve weight x point weight
        if weights is not None:
            cw = np.asarray(weights, dtype=np.float64).reshape(-1)
            if cw.size != m:
                raise ValueError(f"weights has {cw.size} entries for {m} curves")
        elif items is not None and len(items) == m:
            cw = np.array([float(c.weight) for c in items])
        else:
            cw = np.ones(m)
        pw = []
        for i, n in enumerate(sizes):
            p = None
            if items is not None and len(items) == m:
                p = items[i].target_weights
            p = np.ones(n) if p is None else np.asarray(p, dtype=np.float64).reshape(-1)
            if p.size != n:
                raise ValueError(f"curve {i}: {p.size} point weights for {n} points")
            pw.append(p * cw[i])
        w = np.concatenate(pw)
        if not (np.isfinite(w).all() and (w >= 0).all()):
            raise ValueError("weights must be finite and >= 0")
        if not w.sum() > 0:
            raise ValueError("all weights are zero: give at least one curve a positive weight")

        self.target = np.concatenate(targets)
        self.curve = np.repeat(np.arange(m), sizes)
        bounds = np.concatenate([[0], np.cumsum(sizes)])
        self.slices = [slice(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])]
        self.weights = w
        if callable(kind):
            # getattr default: a callable (functools.partial, an instance) may have no name
            self.kind = getattr(kind, "__name__", "custom")
            scale_fn = kind
        else:
            try:
                scale_fn = OBJECTIVES[kind]
            except KeyError:
                raise ValueError(
                    f"unknown objective {kind!r}: use one of {sorted(OBJECTIVES)} or a "
                    "scale function"
                ) from None
            self.kind = kind
        try:
            scale = np.asarray(scale_fn(self.target, self.curve, self.weights),
                               dtype=np.float64)
        except _NoScale as exc:  # name the curve (its file) when the test items say it
            if items is None or len(items) != m or not getattr(items[exc.index], "name", ""):
                raise
            item = items[exc.index]
            src = getattr(item, "source", None)
            where = f"curve {item.name!r}" + (f" ({src})" if src else "")
            raise worded(ValueError, f"{where} {exc.what}") from None
        scale = np.broadcast_to(scale, self.target.shape).copy()
        if self.kind == "rmsape" and items is not None and len(items) == m:
            _point_scales(items, self.slices, scale)
        if not (np.isfinite(scale).all() and (scale > 0).all()):
            raise ValueError(f"objective {self.kind!r} gave a non-positive or non-finite scale")
        self.scale = scale
        self._wnorm = w / w.sum()
        # residual factor so that sqrt(mean(r**2)) is the weighted RMS
        self._rfactor = np.sqrt(self._wnorm * w.size) / scale

    # ------------------------------------------------------------------ sizes
    @property
    def n_curves(self) -> int:
        """Number of curves ``m``."""
        return len(self.slices)

    @property
    def n_points(self) -> int:
        """Total number of objective points ``N``."""
        return int(self.target.size)

    def __repr__(self) -> str:
        return f"Objective({self.kind!r}, {self.n_curves} curves, {self.n_points} points)"

    # ------------------------------------------------------------- evaluation
    def _check(self, stress: Any) -> np.ndarray:
        if (
            isinstance(stress, (list, tuple))
            and len(stress) == self.n_curves > 1
            and all(
                np.ndim(a) >= 1 and np.shape(a)[-1] == sl.stop - sl.start
                for a, sl in zip(stress, self.slices)
            )
        ):
            stress = self.stack(stress)  # a list of per-curve arrays
        s = np.asarray(stress, dtype=np.float64)
        if s.ndim == 0 or s.shape[-1] != self.n_points:
            raise ValueError(
                f"model stress must have shape (..., {self.n_points}) (all curves' points "
                f"concatenated), got {s.shape}"
            )
        return s

    def stack(self, per_curve: Sequence[Any]) -> np.ndarray:
        """Concatenate per-curve model stresses (each ``(..., n_i)``) to ``(..., N)``."""
        return np.concatenate([np.asarray(a, dtype=np.float64) for a in per_curve], axis=-1)

    def split(self, values: Any) -> list[np.ndarray]:
        """Split a concatenated ``(..., N)`` array into per-curve arrays."""
        v = np.asarray(values)
        return [v[..., sl] for sl in self.slices]

    def residuals(self, stress: Any) -> np.ndarray:
        """Scaled residuals ``r``, shape ``(..., N)``, with ``objective = sqrt(mean(r**2))``.

        Non-finite model stresses give ``inf`` residuals (never NaN).
        """
        s = self._check(stress)
        with np.errstate(over="ignore", invalid="ignore"):
            r = (s - self.target) * self._rfactor
        return np.where(np.isnan(r), np.inf, r)

    def __call__(self, stress: Any) -> np.ndarray | float:
        """Objective value of each individual: shape ``(...)`` for stress ``(..., N)``."""
        s = self._check(stress)
        with np.errstate(over="ignore", invalid="ignore"):
            d = (s - self.target) / self.scale
            f = np.sqrt((d * d) @ self._wnorm)
        f = np.where(np.isfinite(f) & np.isfinite(s).all(axis=-1), f, np.inf)
        return float(f) if f.ndim == 0 else f

    def per_curve(self, stress: Any) -> np.ndarray:
        """Objective of each curve on its own, shape ``(..., m)``.

        For ``"rmsape"`` this is the per-curve RMSAPE (the point-weighted RMS of curve
        ``i``'s relative residuals).
        """
        s = self._check(stress)
        out = []
        with np.errstate(over="ignore", invalid="ignore"):
            d = (s - self.target) / self.scale
            for sl in self.slices:
                w = self.weights[sl]
                wsum = w.sum()
                w = w / wsum if wsum > 0 else np.full(w.shape, 1.0 / w.size)
                f = np.sqrt((d[..., sl] ** 2) @ w)
                ok = np.isfinite(f) & np.isfinite(s[..., sl]).all(axis=-1)
                out.append(np.where(ok, f, np.inf))
        return np.stack(out, axis=-1)


def _point_scales(items: Sequence[Any], slices: list[slice], scale: np.ndarray) -> None:
    """RMSAPE of moduli: each point relative to its own value (``target_scale``), in place."""
    for i, (c, sl) in enumerate(zip(items, slices)):
        ts = c.target_scale
        if ts is None:
            continue
        ts = np.asarray(ts, dtype=np.float64).reshape(-1)
        if ts.size != sl.stop - sl.start:
            raise ValueError(f"curve {i}: {ts.size} point scales for {sl.stop - sl.start} "
                             "points")
        scale[sl] = ts / 100.0


# --------------------------------------------------------------------- functions
def _evaluate(kind: str, model: Any, target: Any, weights: Any, per_curve: bool = False):
    targets = _as_targets(target)
    obj = Objective(targets, kind, weights=weights)
    if isinstance(target, np.ndarray) and target.ndim == 2:
        model = np.asarray(model, dtype=np.float64)
        model = model.reshape(model.shape[:-2] + (-1,)) if model.ndim >= 2 else model
    elif isinstance(model, (list, tuple)) and len(targets) > 1:
        model = obj.stack(model)
    return obj.per_curve(model) if per_curve else obj(model)


def rmsape(model: Any, target: Any, *, weights: Sequence[float] | None = None):
    """Root mean square average percentage error, paper Eq. 20, in percent.

    .. math::

        F = \\sqrt{\\frac{1}{n m}\\sum_{i=1}^{m}\\sum_{j=1}^{n}\\left(
            \\frac{\\sigma_{\\mathrm{obj},ij}-\\sigma_{\\mathrm{model},ij}}
                 {\\frac{1}{n}\\sum_k |\\sigma_{\\mathrm{obj},ik}|}\\,100\\right)^2}

    The curve mean is taken of ``|σ|``: equal to ``|mean σ|`` for a compression-only or
    tension-only curve (the paper's case), and still a meaningful stress level for a
    curve that changes sign (tension-compression cycles), whose signed mean can be ~0.

    Parameters
    ----------
    model : array_like
        Model stresses: shape ``(..., m, n)`` for a 2-D ``target``; otherwise the
        curves' points concatenated, ``(..., N)``, or a list of per-curve arrays.
    target : array_like
        Objective stresses: a 2-D array ``(m, n)`` (one row per curve), a list of 1-D
        arrays (curves of any lengths), or a 1-D array (one curve).
    weights : sequence of float, optional
        Per-curve weights; they multiply the squared terms and are normalised, so equal
        weights give Eq. 20.

    Returns
    -------
    float or ndarray
        The error in percent, one per leading index of ``model``; ``inf`` where the
        model stress is not finite.

    Examples
    --------
    >>> target = np.array([[-1.0, -2.0, -3.0], [-10.0, -20.0, -30.0]])
    >>> rmsape(target * 1.1, target)   # 10 % of 1, 2, 3 relative to their mean 2: 5, 10, 15 %
    10.801234...
    >>> rmsape(np.stack([target, target]), target)   # a population of two
    array([0., 0.])
    """
    return _evaluate("rmsape", model, target, weights)


def per_curve_rmsape(model: Any, target: Any, *, weights: Sequence[float] | None = None):
    """RMSAPE of each curve on its own, shape ``(..., m)``; arguments as :func:`rmsape`.

    Examples
    --------
    >>> target = [np.array([-1.0, -2.0, -3.0]), np.array([-10.0, -30.0])]
    >>> per_curve_rmsape([np.array([-1.0, -2.0, -3.0]), np.array([-12.0, -30.0])], target)
    array([0.        , 7.07106781])
    """
    return _evaluate("rmsape", model, target, weights, per_curve=True)


def rmse(model: Any, target: Any, *, weights: Sequence[float] | None = None):
    """Root mean square error in MPa over all points; arguments as :func:`rmsape`.

    Examples
    --------
    >>> rmse([1.0, 2.0, 4.0], [1.0, 2.0, 3.0])
    0.5773502...
    """
    return _evaluate("rmse", model, target, weights)


def relative_l2(model: Any, target: Any, *, weights: Sequence[float] | None = None):
    """``100 ‖model − target‖ / ‖target‖`` over all points, in percent.

    Unlike :func:`rmsape` the curves are not normalised one by one, so the curves with
    the highest stresses dominate. Arguments as :func:`rmsape`.

    Examples
    --------
    >>> relative_l2([3.0, 4.0], [3.0, 5.0])
    17.149858...
    """
    return _evaluate("relative_l2", model, target, weights)
