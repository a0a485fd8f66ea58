"""Path geometry of measured histories: the strain path e(t) of a time curve.

Rate estimation, arc length along (strain, stress), turning points and holds (the
segments of a history), evenly spaced placement of points over runs of samples, bin
means of noisy records and Douglas–Peucker simplification of the path. Private helpers
of :class:`vhfit.data.Curve`, which passes them the breakpoint cap
``vhfit.data.MAX_BREAKPOINTS`` (the user's knob) at call time.
"""

from __future__ import annotations

import numpy as np

#: A long time record's rate is estimated from this many bin means of its samples.
_RATE_BINS = 200
#: Resampling by arc length smooths the curve into this many bins first, so that sensor
#: noise does not count as length.
_ARC_BINS = 200
#: The strain must reverse by more than this fraction of its range to start a new loading
#: leg (smaller wiggles are noise or machine overshoot).
LEG_RTOL = 0.05
#: A hold: the strain stays within this fraction of its range ...
HOLD_RTOL = 0.002
#: ... for at least this fraction of the test's duration.
HOLD_MIN_DURATION = 0.05


def _estimate_rate(t, eps, sgn, tol) -> float:
    if t.size > 2 * _RATE_BINS:
        # sample-to-sample differences of a long record measure its noise, not its rate
        t, eps = _bin_means(t, eps, _RATE_BINS)
    dt = np.diff(t)
    de = np.diff(eps)
    ok = (dt > 0) & (de != 0)
    if not ok.any():
        return float("nan")
    r = np.abs(de[ok] / dt[ok])
    w = np.abs(de[ok])
    order = np.argsort(r)
    cw = np.cumsum(w[order])
    med = float(r[order][np.searchsorted(cw, 0.5 * cw[-1])])
    if sgn is None:  # mixed: the sign of the first loading
        k = int(np.flatnonzero(np.abs(eps) > tol)[0])
        sgn = float(np.sign(eps[k]))
    return sgn * med


def _arclength(eps: np.ndarray, sig: np.ndarray) -> np.ndarray:
    """Strictly increasing arc length along (strain, stress), both scaled to unit range."""
    n = eps.size
    x = eps / (np.ptp(eps) or 1.0)
    y = sig / (np.ptp(sig) or 1.0)
    k = np.arange(n, dtype=np.float64)
    if n > 4 * _ARC_BINS:  # average into bins so that noise does not add length
        edges = np.linspace(0, n, _ARC_BINS + 1).astype(np.intp)
        cnt = np.diff(edges)
        xs = np.add.reduceat(x, edges[:-1]) / cnt
        ys = np.add.reduceat(y, edges[:-1]) / cnt
        ks = np.add.reduceat(k, edges[:-1]) / cnt
        xs = np.concatenate([[x[0]], xs, [x[-1]]])
        ys = np.concatenate([[y[0]], ys, [y[-1]]])
        ks = np.concatenate([[0.0], ks, [n - 1.0]])
    else:
        xs, ys, ks = x, y, k
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(xs), np.diff(ys)))])
    s = np.interp(k, ks, s)
    total = s[-1] if s[-1] > 0 else 1.0
    return s + 1e-9 * total * k / max(n - 1, 1)


def _turning_points(e: np.ndarray, h: float) -> np.ndarray:
    """Sample indices ``[0, turns..., n-1]`` where the strain reverses by more than ``h``.

    A zigzag filter with hysteresis ``h``, run on the per-bin extremes of long series
    (the extremes of a leg are among them), so its Python loop stays short.
    """
    n = e.size
    if n > 8192:
        edges = np.linspace(0, n, 2049).astype(np.intp)
        lo = [a + int(np.argmin(e[a:b])) for a, b in zip(edges[:-1], edges[1:])]
        hi = [a + int(np.argmax(e[a:b])) for a, b in zip(edges[:-1], edges[1:])]
        cand = np.unique(np.concatenate([[0, n - 1], lo, hi]))
    else:
        cand = np.arange(n)
    v = e[cand]
    turns = []
    direction = 0
    lo_i = hi_i = ext = 0
    for i in range(1, v.size):
        x = v[i]
        if direction == 0:
            if x > v[hi_i]:
                hi_i = i
            if x < v[lo_i]:
                lo_i = i
            if v[hi_i] - v[lo_i] > h:
                direction = 1 if hi_i > lo_i else -1
                ext = hi_i if direction == 1 else lo_i
                first = lo_i if direction == 1 else hi_i
                if first != 0 and abs(v[first] - v[0]) > h:  # it went the other way first
                    turns.append(first)
        elif direction == 1:
            if x > v[ext]:
                ext = i
            elif v[ext] - x > h:
                turns.append(ext)
                direction, ext = -1, i
        else:
            if x < v[ext]:
                ext = i
            elif x - v[ext] > h:
                turns.append(ext)
                direction, ext = 1, i
    return np.array([0, *[int(cand[i]) for i in turns], n - 1], dtype=np.intp)


def _segment_bounds(t: np.ndarray, e: np.ndarray, max_breakpoints: int) -> np.ndarray:
    """Sample indices bounding the segments of a history: turning points and holds.

    Holds are looked for in the simplified path; past ``max_breakpoints`` breakpoints
    (a noisy record), in its bin means.
    """
    n = e.size
    rng = float(np.ptp(e))
    turns = _turning_points(e, LEG_RTOL * rng)
    tol = 0.5 * HOLD_RTOL * rng
    pts = _simplify_idx(t, e, tol, limit=max_breakpoints)
    if pts is None:  # noisy: look for holds in bin means (a sample index each)
        tb, eb = _bin_means(t, e, max_breakpoints)
        k = tb.size - 2
        centre = np.concatenate([[0], (np.arange(k) + 0.5) * n // k, [n - 1]]).astype(np.intp)
        sub = _simplify_idx(tb, eb, tol)
        tt, ee, si = tb[sub], eb[sub], centre[sub]
    else:
        tt, ee, si = t[pts], e[pts], pts
    band = 2 * HOLD_RTOL * rng
    min_dur = HOLD_MIN_DURATION * (t[-1] - t[0])
    holds = []  # (start sample, end sample) of runs of the path within a narrow band
    start = lo = hi = None
    for a in range(tt.size - 1):
        b = a + 1
        flat = abs(ee[b] - ee[a]) <= HOLD_RTOL * rng
        if flat and start is not None and max(hi, ee[b]) - min(lo, ee[b]) <= band:
            lo, hi = min(lo, ee[b]), max(hi, ee[b])
            end = b
            continue
        if start is not None and tt[end] - tt[start] >= min_dur:
            holds.append((int(si[start]), int(si[end])))
        start = lo = hi = None
        if flat:
            start, end, lo, hi = a, b, min(ee[a], ee[b]), max(ee[a], ee[b])
    if start is not None and tt[end] - tt[start] >= min_dur:
        holds.append((int(si[start]), int(si[end])))
    bounds = set(int(i) for i in turns)
    for a, b in holds:
        bounds = {i for i in bounds if not a < i < b} | {a, b}
    return np.array(sorted(bounds | {0, n - 1}), dtype=np.intp)


def _place(c: np.ndarray, mask: np.ndarray, n: int, rest: bool) -> np.ndarray | None:
    """Fractional sample indices of ``n`` points evenly spaced in coordinate ``c`` over the
    kept runs of ``mask`` (``c`` strictly increasing); None if the runs have no length."""
    m = np.concatenate([[False], mask, [False]])
    starts = np.flatnonzero(~m[:-1] & m[1:])
    ends = np.flatnonzero(m[:-1] & ~m[1:]) - 1
    lengths = c[ends] - c[starts]
    total = float(lengths.sum())
    if not total > 0:
        return None
    if n == 1:
        pos = np.array([total])
    elif rest:
        pos = total * np.arange(1, n + 1) / n
    else:
        pos = np.linspace(0.0, total, n)
    cum = np.concatenate([[0.0], np.cumsum(lengths)])
    run = np.clip(np.searchsorted(cum[1:], pos, side="left"), 0, starts.size - 1)
    out = np.empty(n)
    for r in np.unique(run):
        a, b = starts[r], ends[r]
        sel = run == r
        cv = np.clip(c[a] + (pos[sel] - cum[r]), c[a], c[b])
        out[sel] = np.interp(cv, c[a : b + 1], np.arange(a, b + 1, dtype=np.float64))
    return out


def _bin_means(t: np.ndarray, e: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    """The path averaged over ``k`` bins of consecutive samples, spanning t[0] to t[-1].

    The ends are extended linearly from the two outer bin means, so the path still
    covers every sample time (the objective's output times among them).
    """
    n = t.size
    k = max(2, min(k, n // 2))
    b = np.arange(n) * k // n
    cnt = np.bincount(b, minlength=k)
    tb = np.bincount(b, weights=t, minlength=k) / cnt
    eb = np.bincount(b, weights=e, minlength=k) / cnt

    def at(x, i, j):
        return eb[i] + (eb[j] - eb[i]) * (x - tb[i]) / (tb[j] - tb[i])

    return (np.concatenate([[t[0]], tb, [t[-1]]]),
            np.concatenate([[at(t[0], 0, 1)], eb, [at(t[-1], k - 2, k - 1)]]))


def _simplify_idx(t: np.ndarray, e: np.ndarray, tol: float,
                  limit: int | None = None) -> np.ndarray | None:
    """Indices of the breakpoints of a piecewise-linear path e(t) to keep so that dropping
    the others moves it by at most ``tol``.

    Douglas–Peucker on the vertical distance; segments shorter than 32 samples that need
    splitting are kept whole, which bounds the work on noisy data. With ``limit``,
    returns None as soon as more than ``limit`` breakpoints would be kept.
    """
    n = t.size
    if n <= 2 or not tol > 0:
        return None if limit is not None and n > limit else np.arange(n)
    keep = np.zeros(n, dtype=bool)
    keep[0] = keep[-1] = True
    kept = 2
    stack = [(0, n - 1)]
    while stack:
        a, b = stack.pop()
        if b - a < 2:
            continue
        tt = t[a : b + 1]
        line = e[a] + (e[b] - e[a]) * (tt - t[a]) / (t[b] - t[a])
        dev = np.abs(e[a : b + 1] - line)
        k = int(np.argmax(dev))
        if dev[k] <= tol:
            continue
        if b - a < 32:
            kept += b - a - 1
            keep[a : b + 1] = True
        else:
            kept += 1
            keep[a + k] = True
            stack.append((a, a + k))
            stack.append((a + k, b))
        if limit is not None and kept > limit:
            return None
    return np.flatnonzero(keep)
