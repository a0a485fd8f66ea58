"""The loading history of a curve: the :class:`vhfit.History` its model follows.

Every call of the :class:`~vhfit.history.History` builders made by the data package is
here: a constant-rate ramp, a measured (time, strain) path — simplified to the
breakpoints that matter, or followed through bin means when it is too noisy to follow
sample by sample — or an equilibrium (rate-free) set of states; in any deformation, with
the outputs at the objective points and, for a curve that measured both in-plane
stresses, the direction of each output. The path tolerances are passed in by
:class:`vhfit.data.Curve`, which owns them (``vhfit.data.PATH_RTOL``,
``vhfit.data.MAX_BREAKPOINTS``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vhfit.data._errors import DataError, _warn, _Where
from vhfit.data._paths import _bin_means, _simplify_idx
from vhfit.history import History, from_rest


@dataclass(frozen=True)
class _Path:
    """What a curve's history is made of: its samples and its objective points."""

    deformation: str
    rate: float | None  # constant-rate ramp; None for time paths and equilibrium
    time: np.ndarray | None  # sample times (None: constant rate or equilibrium)
    strain: np.ndarray  # λ1 − 1 (γ in simple shear) of the samples
    strain2: np.ndarray | None  # λ2 − 1 of the samples (a second prescribed stretch)
    e_obj: np.ndarray  # driving strain at the objective points (one direction)
    e2_obj: np.ndarray | None
    t_obj: np.ndarray  # their times (sample numbers at equilibrium)
    two: bool  # outputs in both loaded directions (stress2 measured)


def _build_history(p: _Path, path_rtol: float, max_breakpoints: int, where: _Where) -> History:
    """The history of path ``p`` with outputs at its objective points (both directions
    when ``p.two``); a History refusal becomes a DataError naming the curve."""
    try:
        return _history(p, path_rtol, max_breakpoints, where)
    except ValueError as exc:
        if isinstance(exc, DataError):
            raise
        raise DataError(f"{where()}: {exc}") from None


def _history(p: _Path, path_rtol: float, max_breakpoints: int, where: _Where) -> History:
    kw = {"deformation": p.deformation}
    if p.strain2 is not None:
        kw["strain2"] = p.e2_obj if p.time is None else None
    if p.time is None and p.rate is None:
        h = History.equilibrium(p.e_obj, **kw)
    elif p.time is None:
        h = History.constant_rate(p.e_obj, p.rate, **kw)
    else:
        h = _measured_path(p, kw, path_rtol, max_breakpoints, where)
    if not p.two:
        return h
    n = p.t_obj.size
    return h.with_outputs(np.concatenate([h.out_time, h.out_time]),
                          np.repeat(np.array([1, 2]), n))


def _measured_path(p: _Path, kw: dict, path_rtol: float, max_breakpoints: int,
                   where: _Where) -> History:
    """Through the measured samples, breakpoints dropped where that moves the path(s) by
    less than ``path_rtol`` of the range; through bin means when that keeps too many."""
    t, e = from_rest(p.time, p.strain)
    paths = [e] if p.strain2 is None else [e, from_rest(p.time, p.strain2)[1]]
    scale = max(max(float(np.ptp(x)), float(np.abs(x).max())) for x in paths)
    tol = path_rtol * scale
    idx = _union_idx(t, paths, tol, max_breakpoints)
    if idx is None:
        return _smoothed(p, kw, path_rtol, scale, max_breakpoints, where)
    if p.strain2 is not None:
        kw["strain2"] = paths[1][idx]
    return History.piecewise_linear(t[idx], e[idx], out_time=p.t_obj, **kw)


def _union_idx(t, paths, tol, limit):
    """Breakpoints that every path needs (None past ``limit`` of them)."""
    keep = None
    for x in paths:
        idx = _simplify_idx(t, x, tol, limit=limit)
        if idx is None:
            return None
        keep = idx if keep is None else np.union1d(keep, idx)
    if limit is not None and keep.size > limit:
        return None
    return keep


def _smoothed(p: _Path, kw: dict, path_rtol: float, scale: float, limit: int,
              where: _Where) -> History:
    # Following every noisy sample would keep ~all of them as breakpoints and turn
    # the noise into strain-rate spikes of noise/Δt; follow bin means instead.
    raws = [p.strain] if p.strain2 is None else [p.strain, p.strain2]
    binned = [from_rest(*_bin_means(p.time, x, limit)) for x in raws]
    t, xs = binned[0][0], [b[1] for b in binned]
    tol = path_rtol * scale
    idx = None
    while idx is None:
        idx = _union_idx(t, xs, tol, limit)
        tol *= 2.0
    t, xs = t[idx], [x[idx] for x in xs]
    dev = np.interp(p.time, t, xs[0]) - p.strain
    rms = float(np.sqrt(np.mean(dev * dev)))
    _warn(
        f"{where()}: the measured strain path is noisy or too detailed to follow "
        f"sample by sample (more than {limit} breakpoints within "
        f"{path_rtol:g} of its range, and noise would become strain-rate spikes): the "
        f"simulated history follows a {limit}-bin average of it with "
        f"{idx.size} breakpoints (RMS deviation from the samples {rms:.3g} strain, "
        f"{rms / scale:.2g} of the range); smooth the strain signal yourself, or raise "
        f"vhfit.data.MAX_BREAKPOINTS, to choose differently", 6
    )
    if p.strain2 is not None:
        kw["strain2"] = xs[1]
    return History.piecewise_linear(t, xs[0], out_time=p.t_obj, **kw)
