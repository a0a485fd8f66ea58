"""The admissible set of a fit: Drucker-stable laws with a positive initial modulus.

A hyperelastic law is admissible when its tangent d(σ1 − σ3)/d ln λ is positive in
every homogeneous test of the stability check, in tension and compression, over a
stretch range (:mod:`vhfit.stability`, its ``modes_checked()``), and its initial shear
modulus μ0 is positive (docs/theory.md §11, "The admissible set"). Both conditions are
linear in the law's linear constants (``Hyperelastic.linear_params``) for fixed nonlinear ones, and
invariant under a positive scale of them. Here they are checked on a grid of stretches:

* :func:`admissible` — which shapes of a batch are admissible (the filter of the searches
  and of the polish);
* :meth:`Admissible.rows` — the grid's inequalities G c ≥ 0 on the linear constants c;
* :func:`lsi` — least squares under such inequalities (Lawson and Hanson's LSI by
  their LDP and NNLS), the exact solve of the linear constants without Prony terms;
* :func:`arcs` — the arc of admissible directions of a law with two linear constants,
  for its nonlinear ones (:func:`angle_range`: a law without any), searched as one
  angle.
"""

from __future__ import annotations

import math

import numpy as np

from vhfit.data import is_moduli
from vhfit.modes import get_deformation, principal_stretches
from vhfit.stability import mode_range, modes_checked, principal_difference

__all__ = ["Admissible", "data_stability_range", "admissible", "defined", "lsi",
           "angle_range", "arcs", "STABILITY_MARGIN", "GRID_POINTS"]

#: The default stretch range reaches this factor beyond the data's smallest and largest
#: principal stretch (and at least 1/MIN_STRETCH_RANGE..MIN_STRETCH_RANGE).
STABILITY_MARGIN = 1.1

#: Smallest default range: λ in [1/1.1, 1.1] at least.
MIN_STRETCH_RANGE = 1.1

#: Stretches of the grid per mode (log-spaced over the range).
GRID_POINTS = 41

#: Radians kept off each end of the admissible arc of two linear constants.
ANGLE_MARGIN = 1e-6

#: Half step (in ln λ) of the central difference of the tangent, as vhfit.stability.
_D = 1e-4


def data_stability_range(curves) -> tuple[float, float]:
    """Default stretch range of the Drucker condition: the data's deformation, with margin.

    The smallest and the largest principal stretch the curves reach (in their own modes;
    small-strain tests reach none), each :data:`STABILITY_MARGIN` further from 1 (and at
    least 1/1.1 and 1.1), give [λ_lo, λ_hi], a bound on every principal stretch of the
    states checked: each mode is checked over the loaded stretches whose principal
    stretches all stay inside it (:func:`vhfit.stability.mode_range`), so no checked
    state stretches any direction further than the data do, with the margin. A uniaxial
    tension to λ = 17 reaches 17 and 17^(-1/2) = 0.243, so [0.22, 18.7]: uniaxial from
    0.22 to 18.7, equibiaxial from 18.7^(-1/2) = 0.23 to 0.22^(-1/2) = 2.13.

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> c = vhfit.Curve(strain=np.linspace(-0.1, -0.5, 5), stress=-np.linspace(.1, 1, 5))
    >>> lo, hi = data_stability_range([c])
    >>> round(lo, 4), round(hi, 4)   # 0.5 / 1.1 and 0.5^(-1/2) · 1.1
    (0.4545, 1.5556)
    """
    lo, hi = 1.0, 1.0
    for c in curves:
        if is_moduli(c):
            continue
        h = c.history
        lam = principal_stretches(h.deformation, h.out_stretch, h.stretch2_at(h.out_time))
        for v in lam:
            v = np.asarray(v, dtype=np.float64)
            v = v[np.isfinite(v) & (v > 0)]
            if v.size:
                lo, hi = min(lo, float(np.min(v))), max(hi, float(np.max(v)))
    return (min(lo / STABILITY_MARGIN, 1.0 / MIN_STRETCH_RANGE),
            max(hi * STABILITY_MARGIN, MIN_STRETCH_RANGE))


def _grid(stretch_range, points: int = GRID_POINTS
          ) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Per test of the Drucker check (:func:`vhfit.stability.modes_checked`), over the
    loaded stretches whose principal stretches stay within ``stretch_range``
    (:func:`vhfit.stability.mode_range`): its principal stretches half a step above each
    grid stretch, then half a step below (one array each: one evaluation of the law per
    test)."""
    out = []
    for m in modes_checked():
        lo, hi = mode_range(m, stretch_range)  # every principal stretch within the range
        lam = np.exp(np.linspace(math.log(lo), math.log(hi), points))
        both = np.concatenate([lam * math.exp(_D), lam * math.exp(-_D)])
        arrays = []
        for v in get_deformation(m).stretches(both, None):
            v = np.array(v, dtype=np.float64)  # its own data, read-only: a law may
            v.flags.writeable = False  # remember what it derives from it
            arrays.append(v)
        out.append(tuple(arrays))
    return out


class Admissible:
    """The admissible set of one law over one stretch range (grid built once)."""

    def __init__(self, hm, stretch_range, points: int = GRID_POINTS):
        self.hm = hm
        self.stretch_range = (float(stretch_range[0]), float(stretch_range[1]))
        # points = the final check's (vhfit.stability.drucker's n): the same stretches
        self.grid = _grid(self.stretch_range, points)
        self.amp = list(hm.linear_index)

    def tangents(self, X: np.ndarray) -> np.ndarray:
        """d(σ1 − σ3)/d ln λ of laws X (..., n_h) on the grid of every mode (..., 3 n)."""
        out = [np.zeros(np.shape(X)[:-1] + (0,))]
        with np.errstate(all="ignore"):
            for l1, l2, l3 in self.grid:
                d = principal_difference(self.hm, X, l1, l2, l3)
                n = d.shape[-1] // 2
                out.append((d[..., :n] - d[..., n:]) / (2 * _D))
        return np.concatenate(out, axis=-1)

    def __call__(self, X: np.ndarray) -> np.ndarray:
        """Whether each law of X (P, n_h) is admissible (bool, P)."""
        X = np.atleast_2d(np.asarray(X, dtype=np.float64))
        with np.errstate(all="ignore"):
            mu0 = np.asarray(self.hm.initial_shear_modulus(X), dtype=np.float64).reshape(-1)
            t = self.tangents(X)
        # a law undefined within the range (past a locking stretch: Gent, Van der Waals)
        # has no positive tangent there: not admissible, as the final check says
        return (mu0 > 0) & np.all(t > 0, axis=-1)

    def rows(self, X: np.ndarray) -> np.ndarray:
        """The inequalities on the linear constants of laws X (P, n_h), their nonlinear
        constants as given: (P, 3 n + 1, m), tangent rows then the μ0 row (each ≥ 0);
        NaN rows where the law is undefined (no admissible law: :func:`defined`)."""
        X = np.atleast_2d(np.asarray(X, dtype=np.float64))
        P, m = X.shape[0], len(self.amp)
        U = np.repeat(X[:, None, :], m, axis=1)
        U[:, :, self.amp] = 0.0
        U[:, np.arange(m), self.amp] = 1.0
        with np.errstate(all="ignore"):
            # as one population of P m laws: the laws' population kernels take 2-D sets
            T = self.tangents(U.reshape(P * m, -1)).reshape(P, m, -1)  # (P, m, 3n)
            Z = U[:, :1].copy()
            Z[:, :, self.amp] = 0.0
            mu = (np.asarray(self.hm.initial_shear_modulus(U), dtype=np.float64).reshape(P, m)
                  - np.asarray(self.hm.initial_shear_modulus(Z), dtype=np.float64).reshape(P, 1))
        return np.concatenate([T.transpose(0, 2, 1), mu[:, None, :]], axis=1)


def defined(G: np.ndarray) -> np.ndarray:
    """Whether the inequality rows G (P, rows, m) of :meth:`Admissible.rows` are all finite:
    a law undefined somewhere in the stability range has no admissible linear constants."""
    return np.all(np.isfinite(G), axis=(1, 2))


def admissible(adm: Admissible | None, X: np.ndarray) -> np.ndarray:
    """``adm(X)``, or all True without an admissible set."""
    X = np.atleast_2d(X)
    return np.ones(X.shape[0], bool) if adm is None else adm(X)


def lsi(A: np.ndarray, y: np.ndarray, G: np.ndarray, h: np.ndarray
        ) -> tuple[np.ndarray, float]:
    """min ||A c − y|| subject to G c ≥ h (Lawson and Hanson, Ch. 20–23).

    The unconstrained least squares solution when it satisfies the inequalities;
    otherwise A = Q R turns the problem into least distance (min ||z|| s.t.
    G R⁻¹ z ≥ h − G R⁻¹ Qᵀ y), solved by NNLS on its dual. A rank-deficient A gets a
    ridge of 1e-12 of its largest singular value. Returns (c, residual norm); NaNs and
    inf when the inequalities have no solution.

    Examples
    --------
    >>> c, r = lsi(np.eye(2), np.array([1.0, -1.0]), np.array([[0.0, 1.0]]), np.zeros(1))
    >>> [round(float(v), 12) + 0.0 for v in c], round(r, 12)
    ([1.0, 0.0], 1.0)
    """
    from vhfit._nnls import nnls

    m = A.shape[1]
    c, *_ = np.linalg.lstsq(A, y, rcond=None)
    if np.all(G @ c >= h):
        return c, float(np.linalg.norm(A @ c - y))
    s = np.linalg.svd(A, compute_uv=False)
    if s.size < m or s[-1] <= 1e-12 * s[0]:
        A = np.vstack([A, 1e-12 * max(s[0], 1e-300) * np.eye(m)])
        y = np.concatenate([y, np.zeros(m)])
    Q, R = np.linalg.qr(A)
    Ri = np.linalg.inv(R)
    qy = Q.T @ y
    E = G @ Ri
    f = h - E @ qy
    norm = np.linalg.norm(E, axis=1)
    keep = norm > 0
    if np.any(~keep & (f > 0)):
        return np.full(m, np.nan), math.inf
    E, f = E[keep] / norm[keep, None], f[keep] / norm[keep]
    M = np.vstack([E.T, f[None, :]])
    d = np.zeros(m + 1)
    d[-1] = 1.0
    u, _ = nnls(M, d, maxiter=50 * M.shape[1])
    r = M @ u - d
    if not abs(r[-1]) > 1e-12:
        return np.full(m, np.nan), math.inf  # incompatible inequalities
    z = -r[:m] / r[-1]
    c = Ri @ (z + qy)
    res = A @ c - y
    return c, float(np.linalg.norm(res))


def arcs(adm: Admissible, X: np.ndarray, nonneg=(False, False), nonpos=(False, False)
         ) -> tuple[np.ndarray, np.ndarray]:
    """The arcs [θ_lo, θ_hi] (P each) of directions (cos θ, sin θ) of two linear
    constants that are admissible on the grid, for the nonlinear constants of each law
    of X (P, n_h; its linear constants are ignored), within the half-plane μ0 > 0;
    ``nonneg`` (``nonpos``) says which of the two must be ≥ 0 (≤ 0) as well.

    Every inequality g · (cos θ, sin θ) ≥ 0 is an arc of length π; their intersection is
    one arc, measured from the direction of the μ0 row (the same for every law: μ0 is
    linear in the linear constants alone), kept :data:`ANGLE_MARGIN` inside its ends (a
    direction on an end has a zero tangent somewhere). Empty (also where the law is
    undefined somewhere in the range): NaN at both ends.
    """
    X = np.atleast_2d(np.asarray(X, dtype=np.float64))
    G = adm.rows(X)  # (P, 3n + 1, 2), the μ0 row last
    theta0 = math.atan2(G[0, -1, 1], G[0, -1, 0])
    signs = ([np.eye(2)[k] for k in range(2) if nonneg[k]]
             + [-np.eye(2)[k] for k in range(2) if nonpos[k]])
    if signs:
        G = np.concatenate([G, np.broadcast_to(np.array(signs), (len(X), len(signs), 2))],
                           axis=1)
    with np.errstate(invalid="ignore"):
        c = np.arctan2(G[..., 1], G[..., 0]) - theta0
        c = (c + math.pi) % (2 * math.pi) - math.pi
        # vanishing rows bound nothing (a law undefined anywhere: no arc, below)
        bind = np.isfinite(c) & (np.hypot(G[..., 0], G[..., 1]) > 0)
        lo = np.max(np.where(bind, c - math.pi / 2, -math.pi / 2), axis=1) + ANGLE_MARGIN
        hi = np.min(np.where(bind, c + math.pi / 2, math.pi / 2), axis=1) - ANGLE_MARGIN
    empty = ~(lo < hi) | ~defined(G)
    lo[empty], hi[empty] = np.nan, np.nan
    return theta0 + lo, theta0 + hi


def angle_range(adm: Admissible, nonneg, nonpos=(False, False)) -> tuple[float, float]:
    """The arc [θ_lo, θ_hi] of admissible directions (:func:`arcs`) of a law without
    nonlinear constants (empty: (nan, nan))."""
    lo, hi = arcs(adm, np.array([adm.hm.example], dtype=np.float64), nonneg, nonpos)
    return float(lo[0]), float(hi[0])
