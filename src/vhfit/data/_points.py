"""Objective points of a curve: where along the measured curve the model is compared.

By default the measured samples themselves, or above a cap the means of bins of
consecutive samples; on request ``n`` points evenly spaced in strain (the paper's choice:
10 points a curve), in time, in arc length along the (strain, stress) curve, or per
segment of a history (loading legs and holds); see :class:`vhfit.data.Curve` for the
rules. Also the point weights.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from vhfit._words import setting
from vhfit.data._errors import DataError, _Where
from vhfit.data._paths import _arclength, _place

#: Objective points per curve when none are asked for: ``None``, the measured samples
#: (bin means of consecutive samples above ``vhfit.data.MAX_POINTS``). The paper's scheme
#: (§2.2) is ``n_points=10``.
DEFAULT_N_POINTS = None

_BYS = ("strain", "time", "arclength", "segments")


def _check_points_args(n_points: Any, by: Any, where: _Where
                       ) -> tuple[int | str | None, str | None]:
    """``n_points`` (an int, None, or ``"all"``: every sample, no bins) and ``by``, checked."""
    if isinstance(n_points, str) and n_points == "all":
        pass
    elif n_points is not None:
        try:
            ok = int(n_points) == n_points and int(n_points) >= 1
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise DataError(
                f"{where()}: {setting(f'n_points={n_points!r}', f'--points {n_points}')}: give "
                "a whole number >= 1, "
                + setting("None", "nothing") + " for the measured samples, or 'all' for every "
                "sample without binning"
            )
        n_points = int(n_points)
    if by is not None and by not in _BYS:
        raise DataError(f"{where()}: {setting(f'by={by!r}', 'the resampling')}: use one of "
                        f"{', '.join(map(repr, _BYS))}")
    return n_points, by


def _compared_mask(
    eps: np.ndarray,
    ts: np.ndarray,
    window: np.ndarray | None,
    constant_rate: bool,
    n_req: int | None,
    window_desc: tuple[str, ...],
    where: _Where,
) -> np.ndarray:
    """The samples inside the compared window (a constant-rate ramp starts at t = 0)."""
    mask = np.ones(eps.size, dtype=bool) if window is None else window.copy()
    if constant_rate:
        mask &= ts >= 0.0  # noise of the wrong sign near strain 0
    if mask.sum() < 1 or (isinstance(n_req, int) and mask.sum() < 2):
        raise DataError(
            f"{where()}: the compared window {' '.join(window_desc) or ''} keeps "
            f"{int(mask.sum())} sample(s): widen it (strain runs "
            f"{eps.min():g} to {eps.max():g}, time 0 to {ts.max():g} s)"
        )
    return mask


def _sample_points(
    cols: tuple[np.ndarray, ...], mask: np.ndarray, bounds: np.ndarray, cap: int
) -> tuple[tuple[np.ndarray, ...], str]:
    """Columns (strain, time, stress, ...) at the compared samples, or bin means above ``cap``.

    Bins are runs of consecutive compared samples, never straddling a gap of the window
    or a segment bound (so turning points and hold ends stay sharp), with about ``cap``
    bins in all, shared among the runs in proportion to their samples. Means, not
    interpolation: noise averages out instead of being picked at chosen places.
    """
    k = np.flatnonzero(mask)
    if k.size <= cap:
        return tuple(v[k] for v in cols), "samples"
    seg = np.searchsorted(bounds[1:-1], k, side="left")  # a bound ends its segment
    brk = (np.diff(seg) != 0) | (np.diff(k) > 1)
    starts = np.flatnonzero(np.concatenate([[True], brk]))
    sizes = np.diff(np.append(starts, k.size))
    nb = np.clip(cap * sizes // k.size, 1, sizes)
    first = np.concatenate([[0], np.cumsum(nb)[:-1]])
    pos = np.arange(k.size) - np.repeat(starts, sizes)
    b = np.repeat(first, sizes) + pos * np.repeat(nb, sizes) // np.repeat(sizes, sizes)
    cnt = np.bincount(b)
    return tuple(np.bincount(b, weights=v[k]) / cnt for v in cols), "bins"


def _objective_indices(
    eps: np.ndarray,
    sig: np.ndarray,
    ts: np.ndarray,
    mask: np.ndarray,
    bounds: np.ndarray,
    n_req: int | None,
    by_req: str | None,
    monotone: bool,
    tol: float,
    window_desc: tuple[str, ...],
    where: _Where,
) -> tuple[np.ndarray | None, str]:
    """Fractional sample indices of the objective points, and how they are spaced.

    None for the measured samples (``n_req`` None: see :func:`_sample_points`).
    ``bounds`` are the sample indices bounding the segments of the history; ``tol`` is
    the strain below which a sample counts as the rest point.
    """
    by = by_req
    if by is None:
        by = "strain" if monotone else "segments"
    if by == "strain" and not monotone:
        raise DataError(
            f"{where()}: cannot resample by strain: the strain is not monotonic (it "
            "unloads or holds): use "
            + setting("by='segments', by='arclength' or by='time'", "--points N alone")
        )
    if n_req is None or n_req == "all":
        return None, "samples"
    if by == "strain":
        c = eps * np.sign(eps[-1] - eps[0])
    elif by == "time":
        c = ts
    else:
        c = _arclength(eps, sig)
    if by == "segments":
        parts = []
        k = np.arange(eps.size)
        for a, b in zip(bounds[:-1], bounds[1:]):
            part = _place(c, mask & (k >= a) & (k <= b), n_req, True)
            if part is not None:
                parts.append(part)
        idx = np.concatenate(parts) if parts else None
    else:
        i0 = int(np.flatnonzero(mask)[0])
        rest = abs(eps[i0]) <= tol
        idx = _place(c, mask, n_req, rest)
    if idx is None:
        raise DataError(
            f"{where()}: the compared window {' '.join(window_desc)} has no "
            f"extent in {by}: widen it"
        )
    return idx, by


def _points_of(
    cols: tuple[np.ndarray, ...],
    rate: float | None,
    window: np.ndarray | None,
    bounds: np.ndarray,
    n_req: int | None,
    by_req: str | None,
    monotone: bool,
    tol: float,
    window_desc: tuple[str, ...],
    cap: int,
    where: _Where,
) -> tuple[tuple[np.ndarray, ...], str]:
    """The columns (strain, stress, time, any more) of a curve at its objective points,
    and how the points are spaced.

    ``rate`` is the constant rate of a curve without time column (None otherwise): its
    point times are ``strain / rate``.
    """
    eps, sig, ts = cols[:3]
    mask = _compared_mask(eps, ts, window, rate is not None, n_req, window_desc, where)
    idx, by = _objective_indices(eps, sig, ts, mask, bounds, n_req, by_req, monotone, tol,
                                 window_desc, where)
    if idx is None:
        out, by = _sample_points(cols, mask, bounds, mask.size if n_req == "all" else cap)
    else:
        k = np.arange(eps.size, dtype=np.float64)
        out = tuple(np.interp(idx, k, v) for v in cols)
    if rate is not None:
        out = (out[0], out[1], out[0] / rate, *out[3:])
    return out, by


def _point_weights(
    weights: Any, e_obj: np.ndarray, t_obj: np.ndarray, s_obj: np.ndarray, where: _Where
) -> tuple[np.ndarray, Any]:
    """The weight of each objective point, and the weights to keep for later points.

    ``weights``: None (all 1), a function of (strain, time, stress), or an array, dropped
    (None is kept) when it does not fit the points any more.
    """
    if weights is None:
        w_obj = np.ones(e_obj.size)
    elif callable(weights):
        w_obj = np.broadcast_to(
            np.asarray(weights(e_obj, t_obj, s_obj), dtype=np.float64), e_obj.shape
        ).copy()
    else:
        w_obj = np.asarray(weights, dtype=np.float64)
        if w_obj.shape != e_obj.shape:
            w_obj = np.ones(e_obj.size)  # stale weights of other points: reset
            weights = None
    if not (np.isfinite(w_obj).all() and (w_obj >= 0).all() and w_obj.sum() > 0):
        raise DataError(
            f"{where()}: point weights must be finite, >= 0 and not all 0"
        )
    return w_obj, weights
