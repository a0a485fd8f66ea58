"""What is fitted (model, targets, weighted residuals) and the two ways to search it.

Both search spaces follow one protocol — ``bounds()``, ``errors(Z)`` for a batch of
search vectors, ``to_params(z)`` for the full parameter vector, ``layout`` (what a search
vector means) and ``angles()`` (the coordinates the polishes work in) — plus the defaults
of their differential evolution (``popsize``, ``maxiter``, ``de_options``):

* :class:`SeparableSpace`: for fixed relaxation times and a fixed shape of the
  hyperelastic law the stress of the corrected Eq. 19 is linear in the long-term
  modulus E∞ and the Prony moduli G_i (docs/theory.md §10). The search covers only
  the law's shape (ratios of its linear constants, and its nonlinear constants such
  as Ogden's α, λm, Jm) and log10 τ_i; each evaluation solves the moduli exactly by
  non-negative least squares (variable projection). Without Prony terms every linear
  constant is solved by least squares under the Drucker inequalities and only the
  nonlinear ones are searched. Both cover the admissible set (docs/theory.md §11).
* :class:`FullSpace`: the paper's all-parameter search (hyperelastic constants, G_i,
  log10 τ_i).
"""

from __future__ import annotations

import copy
import math

import numpy as np

from vhfit._nnls import nnls
from vhfit.calibration._admissible import (
    Admissible,
    admissible,
    angle_range,
    arcs,
    defined,
    lsi,
)
from vhfit.model import ViscoHyperelastic
from vhfit.objective import Objective

__all__ = ["Problem", "SeparableSpace", "FullSpace", "SPACES", "STRICT", "search_vector"]

#: Relative margin by which the exact solve of the linear constants keeps each Drucker
#: inequality strict (the tangent at least this fraction of its row's norm times the
#: constants' scale).
STRICT = 1e-9


class Problem:
    """Model, targets and the weighted residuals whose norm is the objective (Eq. 20)."""

    def __init__(self, model: ViscoHyperelastic, curves, tau_b, bounds, g_inf_min,
                 objective="rmsape", stability_range=None, user_bounds=(),
                 constrained: bool = True, grid_points: int | None = None):
        self.model = model
        self.hm = model.hyperelastic
        self.batch = model.batch(curves)
        self.objective = Objective(curves, objective)
        self.objective_spec = objective
        self.y = self.objective.target
        # residual weights r = (σ − y) * scale with ||r|| = the objective (Eq. 20)
        w = self.objective.weights
        self.scale = np.sqrt(w / w.sum()) / self.objective.scale
        self.tau_b = tau_b  # (N, 2) log10 τ
        self.bounds = bounds  # name -> (lo, hi) for hyperelastic constants and G
        self.g_inf_min = float(g_inf_min)
        # the admissible set (Drucker-stable over this range, μ0 > 0); None: no check.
        # constrained=False: the range is stated (the final check), but no law of the
        # bounds is stable there and the search is not confined to the admissible set
        self.stability_range = stability_range
        self.constrained = bool(constrained)
        # grid_points: stretches of the admissible grid per mode (None: its default)
        self.adm = (None if stability_range is None or not constrained
                    else Admissible(self.hm, stability_range,
                                    *(() if grid_points is None else (grid_points,))))
        self.user_bounds = frozenset(user_bounds)  # names whose bounds the user gave
        self.coarse = False  # a search's coarser model (and fewer points of long records)

    def admissible(self, X: np.ndarray) -> np.ndarray:
        """Whether the law of each parameter set X (P, n_params) is admissible."""
        X = np.atleast_2d(X)
        return admissible(self.adm, X[:, : self.hm.n_params])

    def errors(self, X: np.ndarray) -> np.ndarray:
        """Objective of parameter sets X (P, n_params); inf where invalid or inadmissible
        (the model is evaluated only for the admissible ones)."""
        X = np.atleast_2d(X)
        ok = self.admissible(X)
        e = np.full(X.shape[0], np.inf)
        if not ok.any():
            return e
        r = self.residuals(X if ok.all() else X[ok])
        with np.errstate(all="ignore", over="ignore"):
            e[ok] = np.sqrt(np.sum(r * r, axis=1))
        e[~np.isfinite(e)] = np.inf
        return e

    def residuals(self, X: np.ndarray) -> np.ndarray:
        """Weighted residuals (P, n_points) of parameter sets X."""
        return (self.batch(np.atleast_2d(X)) - self.y) * self.scale


class SeparableSpace:
    """Search over (shape of the law, log10 τ); the linear moduli by least squares.

    The law's constants split into the linear ones (``Hyperelastic.linear_params``: σ_h is
    linear in them) and the rest (α, λm, Jm, ...), which are always searched.

    * With Prony terms, DE searches the shape of the linear constants — a direction
      (cos θ, sin θ) of two on their admissible arc (with nonlinear constants, as Ogden-2:
      the place on the arc of the member's own ones, :meth:`directions`), or the
      constants themselves (a redundant scale, signed where the law allows) when there
      are more — and log10 τ; NNLS solves (E∞, G_i) for every individual; inadmissible
      shapes get +inf.
    * Without Prony terms the long-term stress is linear in the linear constants
      themselves: least squares under the Drucker inequalities (and the lower limits
      the law or the user set) solves all of them exactly for every individual, and DE
      searches only the other constants (nothing at all for the polynomial laws).
    """

    method = "separable"
    #: the linear constants solved for each member, not searched (:func:`varpro_polish`
    #: and the gathered-population shortcut apply)
    separable = True
    popsize = 64
    maxiter = 1000
    de_options = dict(strategy="best1bin", mutation=(0.5, 1.0), recombination=0.9,
                      init="sobol", updating="deferred")

    def __init__(self, prob: Problem):
        self.prob = prob
        hm = prob.hm
        self.amp = list(hm.linear_index)
        if not self.amp:
            raise ValueError(
                f"method='separable' needs a law with constants its stress is linear in; "
                f"{hm.name!r} declares none (register it with linear_params=...): "
                "use method='full'"
            )
        self.other = [k for k in range(hm.n_params) if k not in self.amp]
        self.exact = prob.model.n_prony == 0
        # linear constants that must stay >= 0: by the law, or by bounds the user gave
        self.nonneg = [hm.bounds[k][0] >= 0 or (hm.param_names[k] in prob.user_bounds
                                                and prob.bounds[hm.param_names[k]][0] >= 0)
                       for k in self.amp]
        # shape of two linear constants: a direction (cos θ, sin θ) on the admissible arc
        # (docs/theory.md §11); more: the constants themselves (redundant scale), signed
        # where the law allows, the inadmissible ones rejected by Problem.errors
        # bounds the user gave on linear constants (the law's and the G_i): limits of the
        # least squares solves, whatever the search's own ranges
        user = prob.user_bounds
        self.nonpos = [hm.param_names[k] in user and prob.bounds[hm.param_names[k]][1] <= 0
                       for k in self.amp]
        self.limits = [(j, *map(float, prob.bounds[hm.param_names[k]]))
                       for j, k in enumerate(self.amp) if hm.param_names[k] in user]
        lay = prob.model.layout
        self.g_limits = [(i, *map(float, prob.bounds[lay.amplitude_name(i)]))
                         for i in range(lay.n_terms) if lay.amplitude_name(i) in user]
        self.angle = not self.exact and len(self.amp) == 2
        if self.angle:
            self.theta = self._arc()
        # more than two linear constants with Prony terms: each searched coordinate is its
        # constant in units of :meth:`_term_units`, so that every term spans a comparable
        # share of the box (the constants' own search ranges are set by the smallest
        # strains, where (I1 − 3)^k vanishes: Yeoh's C30 would span ±1e6 where good
        # shapes need 1e-5 of C10's scale)
        self.redundant = not self.exact and len(self.amp) > 2
        self.unit = self._term_units() if self.redundant else None
        # with nonlinear constants the admissible arc moves with them: the search's
        # coordinate is the place on the arc of its own shape (see decode)
        self.on_arc = self.angle and bool(self.other) and prob.adm is not None
        self.layout = ("separable, on the arc of each shape" if self.on_arc else
                       "separable, shapes in term units" if self.redundant else self.method)
        self._angles = None  # (the view of angles(), made once)
        self.free_tau = [i for i, (lo, hi) in enumerate(prob.tau_b) if lo < hi]

    def _arc(self) -> tuple[float, float]:
        """The searched arc of directions of two linear constants: the admissible one for
        a law without nonlinear constants, else the half-plane μ0 > 0 (and the signs the
        law requires), the rest left to the filter."""
        prob = self.prob
        adm = prob.adm if not self.other else None
        if adm is None:
            adm = Admissible(prob.hm, (1.0 / 1.01, 1.01))
            adm.grid = []  # the μ0 row alone
        lo, hi = angle_range(adm, self.nonneg, self.nonpos)
        if not lo < hi:
            raise ValueError(
                f"no {prob.hm.name} law is Drucker-stable over the stretch range "
                f"{prob.stability_range}: give a narrower stability_range"
            )
        return lo, hi

    def _term_units(self) -> np.ndarray:
        """Per linear constant, the value at which its term alone has the weighted norm of
        the targets (the law's other constants at their example values): the long-term
        stress of each unit constant, σ(B + e_k) − σ(B) with B all linear constants at 1
        (as in :meth:`solve_constants`), over the objective's points. A term that cannot
        be evaluated there keeps the size of its search range."""
        prob, hm, amp = self.prob, self.prob.hm, self.amp
        m, nh = len(amp), hm.n_params
        X = np.zeros((m + 1, prob.model.n_params))
        X[:, :nh] = np.asarray(hm.example, dtype=np.float64)
        X[:, amp] = 1.0
        X[np.arange(1, m + 1), amp] += 1.0
        X[:, prob.model.layout.times] = 10.0 ** np.mean(prob.tau_b, axis=1)  # G_i = 0: τ idle
        with np.errstate(all="ignore"):
            S = prob.batch(X)
            size = np.linalg.norm((S[1:] - S[:1]) * prob.scale, axis=1)
        target = float(np.linalg.norm(prob.y * prob.scale))
        rng = np.array([max(abs(float(v)) for v in prob.bounds[hm.param_names[k]])
                        for k in amp])
        ok = np.isfinite(size) & (size > 0) & (target > 0)
        return np.where(ok, target / np.where(ok, size, 1.0), np.where(rng > 0, rng, 1.0))

    def shape_coords(self, constants: np.ndarray) -> np.ndarray:
        """Search coordinates of the shape of linear constants ``constants`` (m,) (the
        redundant-scale layout): in term units, scaled into the unit box."""
        z = np.asarray(constants, dtype=np.float64) / self.unit
        top = float(np.max(np.abs(z))) if z.size else 0.0
        return z / top if top > 0 and np.isfinite(top) else z

    #: with a polish after it, the search of a law with several linear constants and a
    #: nonlinear shape polishes its best member when its error first falls below each of
    #: these multiples of the target (see :meth:`finish_levels`)
    FINISH_LEVELS = (1e4, 3e3, 1e3, 3e2, 1e2)

    def finish_levels(self, target: float) -> tuple[float, ...]:
        """Errors below which a polish of the search's best member is tried, largest first.

        For a law with several linear constants and nonlinear shape constants (Ogden
        with 2+ terms) DE's approach crawls along curved valleys in (shape, log τ) that
        the polish — least squares on all parameters — crosses in a few iterations: on
        the multi-mode recovery of an Ogden-2 material a polish from where the error is
        still ~1e4 times the target reaches 1e-12 %; in the signed admissible space the
        search's approach is slower, so the levels are half a decade apart (on the Ogden-2
        recoveries of benchmarks/bench_admissible.py and bench_modes, seeds 0-2, this cut
        the evaluations by a third against levels a decade apart). Each level is tried
        once; a polish that misses the target costs its evaluations and the search goes
        on. Every
        other law: none.
        """
        if self.several_basins():
            return tuple(target * f for f in self.FINISH_LEVELS)
        return ()

    def several_basins(self) -> bool:
        """Whether the space has basins a gathered population may miss: a law with
        several linear constants (of either sign) and nonlinear ones, with Prony terms
        (Ogden-2 and more: terms that trade their signs and exponents)."""
        return bool(self.other) and len(self.amp) > 1 and not self.exact

    #: Band beyond each end of the arc (a share of the arc) that maps onto the end: a law
    #: on the boundary of the admissible set, where the best fit of a record often lies
    #: (a fit pushes the law to its stability limit), is then a region of the search
    #: space instead of a face of it (docs/theory.md §11). On the VHB 4910 record of
    #: benchmarks/bench_real.py (Ogden-2, N = 2) polishes from a first population reach
    #: that boundary optimum from 9 % of its members with 0.3, 5 % with 0.1, 3 % without.
    ARC_BAND = 0.3

    def bounds(self) -> list[tuple[float, float]]:
        hm, pb, b = self.prob.hm, self.prob.bounds, []
        if self.on_arc:
            b.append((-self.ARC_BAND, 1.0 + self.ARC_BAND))
        elif self.angle:
            b.append(self.theta)
        elif self.redundant:  # in term units; the scale is redundant (NNLS sets it)
            b += [(0.0 if nn else -1.0, 0.0 if npos else 1.0)
                  for nn, npos in zip(self.nonneg, self.nonpos)]
        b += [pb[hm.param_names[k]] for k in self.other]
        b += [tuple(self.prob.tau_b[i]) for i in self.free_tau]
        return b

    def decode(self, Z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Shape constants (P, n_h), scale-free, and τ (P, N) from search vectors."""
        P = Z.shape[0]
        hyper = np.zeros((P, self.prob.hm.n_params))
        j = 0
        if self.on_arc:
            j = 1  # the direction follows from the nonlinear constants, below
        elif self.angle:
            hyper[:, self.amp[0]] = np.cos(Z[:, 0])
            hyper[:, self.amp[1]] = np.sin(Z[:, 0])
            j = 1
        elif self.redundant:
            hyper[:, self.amp] = Z[:, : len(self.amp)] * self.unit
            j = len(self.amp)
        else:
            hyper[:, self.amp] = 1.0
        for k in self.other:
            hyper[:, k] = Z[:, j]
            j += 1
        if self.on_arc:
            hyper[:, self.amp] = self.directions(Z[:, 0], hyper)
        logtau = np.tile(self.prob.tau_b[:, 0], (P, 1))
        logtau[:, self.free_tau] = Z[:, j:]
        return hyper, 10.0**logtau

    def arc_of(self, hyper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The admissible arcs [θ_lo, θ_hi] of the nonlinear constants of laws ``hyper``
        (:func:`vhfit.calibration._admissible.arcs`), within the searched half-plane."""
        # a polish's Jacobian rows share the nonlinear constants but for one: each
        # distinct set once
        _, first, back = np.unique(hyper[:, self.other], axis=0, return_index=True,
                                   return_inverse=True)
        if len(first) < len(hyper):
            lo, hi = arcs(self.prob.adm, hyper[first], self.nonneg, self.nonpos)
            lo, hi = lo[back.reshape(-1)], hi[back.reshape(-1)]
        else:
            lo, hi = arcs(self.prob.adm, hyper, self.nonneg, self.nonpos)
        with np.errstate(invalid="ignore"):
            lo, hi = np.maximum(lo, self.theta[0]), np.minimum(hi, self.theta[1])
            empty = ~(lo < hi)
        lo[empty], hi[empty] = np.nan, np.nan
        return lo, hi

    def directions(self, place: np.ndarray, hyper: np.ndarray) -> np.ndarray:
        """(cos θ, sin θ) (P, 2) at ``place`` on the admissible arc of each law's
        nonlinear constants: 0 its lower end, 1 its upper one, the band beyond either
        end (:data:`ARC_BAND`) the end itself; NaN where no direction is admissible."""
        lo, hi = self.arc_of(hyper)
        theta = lo + np.clip(place, 0.0, 1.0) * (hi - lo)
        return np.column_stack([np.cos(theta), np.sin(theta)])

    def angles(self):
        """The same space with the direction searched as the angle θ itself on the
        half-plane μ0 > 0, inadmissible shapes rejected (the polishes' coordinates: on a
        place, the arc's ends move with every exponent, and a polish along a valley where
        one term's modulus vanishes crawls); itself when it has no arc of its own."""
        if not self.on_arc:
            return self
        if self._angles is None:
            twin = copy.copy(self)
            twin.on_arc, twin.layout, twin._angles = False, self.method, None
            self._angles = twin
        return self._angles

    def to_angles(self, Z: np.ndarray) -> np.ndarray:
        """Search vectors Z (P, d) in the coordinates of :meth:`angles`."""
        Z = np.array(np.atleast_2d(Z), dtype=np.float64)
        if self.on_arc:
            hyper, _ = self.decode(Z)
            Z[:, 0] = np.arctan2(hyper[:, self.amp[1]], hyper[:, self.amp[0]])
        return Z

    def from_angles(self, Z: np.ndarray) -> np.ndarray:
        """Search vectors of :meth:`angles` (P, d) in this space's coordinates."""
        Z = np.array(np.atleast_2d(Z), dtype=np.float64)
        if self.on_arc:
            hyper, _ = self.angles().decode(Z)
            Z[:, 0] = self.places(Z[:, 0], hyper)
        return Z

    def places(self, theta: np.ndarray, hyper: np.ndarray) -> np.ndarray:
        """The search coordinates of directions θ (P,) for the nonlinear constants of laws
        ``hyper`` (P, n_h): their places on the arcs (clipped to them; 0.5 where a law
        has no admissible direction)."""
        lo, hi = self.arc_of(np.atleast_2d(hyper))
        with np.errstate(invalid="ignore"):
            place = np.clip((np.asarray(theta, dtype=np.float64) - lo) / (hi - lo), 0.0, 1.0)
        return np.where(lo < hi, place, 0.5)

    def solve_linear(self, hyper, tau, residuals: bool = False):
        """NNLS for (E∞, G_i) of every individual; returns amplitudes (P, 1+N), errors (P,)
        and, with ``residuals``, the weighted residuals (P, n_points) of the solution
        (NaN rows where nothing was solved)."""
        prob = self.prob
        P, N = tau.shape
        amps = np.zeros((P, 1 + N))
        err = np.full(P, np.inf)
        R = np.full((P, prob.y.size), np.nan) if residuals else None
        # inadmissible shapes are rejected before the model is evaluated for them (on
        # the arc of their own shape every direction is admissible, or NaN)
        keep = np.flatnonzero(np.isfinite(hyper).all(axis=1) if self.on_arc
                              else admissible(prob.adm, hyper))
        if keep.size < P:
            if keep.size:
                out = self.solve_linear(hyper[keep], tau[keep], residuals)
                amps[keep], err[keep] = out[0], out[1]
                if residuals:
                    R[keep] = out[2]
            return (amps, err, R) if residuals else (amps, err)
        base, H = prob.batch.shape_columns(hyper, tau)
        ys = prob.y * prob.scale
        kappa = prob.g_inf_min / (1.0 - prob.g_inf_min) if prob.g_inf_min > 0 else 0.0
        # every individual's matrix [σ_h/E∞, h_1..h_N] × scale in one array, built once
        C = np.empty((P, base.shape[1], 1 + N))
        C[:, :, 0] = base
        C[:, :, 1:] = H.transpose(0, 2, 1)
        C *= prob.scale[None, :, None]
        finite = np.isfinite(C).all(axis=(1, 2))  # (every shape here is admissible)
        if self.limits or self.g_limits:  # the user's bounds on linear constants
            with np.errstate(all="ignore"):
                E_shape = 3.0 * np.asarray(prob.hm.initial_shear_modulus(hyper),
                                           dtype=np.float64).reshape(-1)
            finite &= np.isfinite(E_shape) & (E_shape > 0)
        for p in np.flatnonzero(finite):
            A = C[p]
            if self.limits or self.g_limits:
                amps[p], err[p] = self._limited(A, ys, hyper[p] / E_shape[p], kappa)
                if residuals:
                    R[p] = A @ amps[p] - ys
                continue
            a, rn = nnls(A, ys)
            if kappa > 0 and a[0] < kappa * a[1:].sum():
                # the g∞ floor is active: E∞ = κ ΣG, a convex problem in G alone
                Ak = A[:, 1:] + kappa * A[:, :1]
                g, rn = nnls(Ak, ys)
                a = np.concatenate([[kappa * g.sum()], g])
            amps[p] = a
            err[p] = rn
            if residuals:
                R[p] = A @ a - ys
        return (amps, err, R) if residuals else (amps, err)

    def _limited(self, A, ys, unit, kappa) -> tuple[np.ndarray, float]:
        """(E∞, G_i) of one individual by least squares under the user's bounds on linear
        constants: the law's constant k is ``unit[k]`` E∞ (the shape scaled to E∞ = 1),
        so each of its limits is a linear inequality on E∞; with G_i ≥ 0, E∞ ≥ 0 and the
        g∞ floor E∞ ≥ κ ΣG_i (:func:`vhfit.calibration._admissible.lsi`). Returns the
        amplitudes and the residual norm (inf: the limits cannot all hold)."""
        n = A.shape[1]
        rows, h = [np.eye(n)], [np.zeros(n)]
        if kappa > 0:
            rows.append(np.concatenate([[1.0], np.full(n - 1, -kappa)])[None, :])
            h.append(np.zeros(1))
        limits = [(self.amp[j], unit[self.amp[j]] * np.eye(n)[0], lo, hi)
                  for j, lo, hi in self.limits]
        limits += [(None, np.eye(n)[1 + i], lo, hi) for i, lo, hi in self.g_limits]
        for _, g, lo, hi in limits:
            if np.isfinite(lo):
                rows.append(g[None, :])
                h.append(np.array([lo]))
            if np.isfinite(hi):
                rows.append(-g[None, :])
                h.append(np.array([-hi]))
        a, rn = lsi(A, ys, np.vstack(rows), np.concatenate(h))
        if not np.all(np.isfinite(a)):
            return np.zeros(n), np.inf
        # lsi meets each inequality to rounding: no constant a hair outside its bounds
        return np.maximum(a, 0.0), rn

    def solve_constants(self, hyper, constrained: bool = True
                        ) -> tuple[np.ndarray, np.ndarray]:
        """Without Prony terms: the linear constants of every individual by least squares.

        ``hyper`` (P, n_h) holds the other constants. By linearity the stress of each
        unit linear constant is σ(B + e_k) − σ(B), with B all linear constants at 1 (a
        shape with a positive initial modulus, which the batch requires) and σ(B) =
        Σ_k σ(B + e_k)/(m + 1) for m linear constants. The constants minimise the error
        over the admissible set (the Drucker inequalities on the stretch grid and μ0 ≥ 0,
        :func:`vhfit.calibration._admissible.lsi`), each at or above its lower limit
        where the law or the user's bounds set one. Returns the constants (P, n_h) and
        the errors (P,); +inf where the law is invalid or the result has no stiffness.
        A user's upper bound on a linear constant is a limit too. ``constrained=False``:
        without the Drucker inequalities and μ0 > 0 (the best unconstrained fit, reported
        beside the result), the limits kept.
        """
        prob, amp = self.prob, self.amp
        P, m = hyper.shape[0], len(amp)
        X = np.repeat(hyper, m, axis=0).reshape(P, m, -1)
        X[:, :, amp] = 1.0
        X[:, np.arange(m), amp] += 1.0
        S = prob.batch(X.reshape(P * m, -1)).reshape(P, m, -1)  # σ(B + e_k)
        # Σ_k σ(B + e_k) = (m + 1) σ(B): σ(B) needs no evaluation of its own
        with np.errstate(invalid="ignore"):  # inf - inf where the law is undefined
            cols = (S - S.sum(axis=1, keepdims=True) / (m + 1)) * prob.scale  # (P, m, n_pts)
        names = [prob.hm.param_names[k] for k in amp]
        lo = np.array([prob.bounds[n][0] if (n in prob.user_bounds or nn) else -np.inf
                       for n, nn in zip(names, self.nonneg)])
        hi = np.full(m, np.inf)  # upper limits: only the user's
        for j, _, h_j in self.limits:
            hi[j] = h_j
        bounded, capped = np.flatnonzero(np.isfinite(lo)), np.flatnonzero(np.isfinite(hi))
        rows = (np.zeros((P, 0, m)) if prob.adm is None or not constrained
                else prob.adm.rows(hyper))
        ys = prob.y * prob.scale
        out = np.array(hyper, dtype=np.float64, copy=True)
        err = np.full(P, np.inf)
        limit_rows = np.vstack([np.eye(m)[bounded], -np.eye(m)[capped]])
        limit_h = np.concatenate([lo[bounded], -hi[capped]])
        for p in range(P):
            A = cols[p].T
            if not np.all(np.isfinite(A)):
                continue
            if not defined(rows[p:p + 1])[0]:
                continue  # undefined within the stability range: not admissible
            G = rows[p]
            # strictly inside the tangent inequalities, by a hair of the data's scale
            c0, *_ = np.linalg.lstsq(A, ys, rcond=None)
            h = np.concatenate([STRICT * np.linalg.norm(G, axis=1) * np.linalg.norm(c0),
                                limit_h])
            c, rn = lsi(A, ys, np.vstack([G, limit_rows]), h)
            # lsi meets each limit to rounding: no constant a hair outside its bounds
            c = np.clip(c, lo, hi)
            out[p, amp] = c
            err[p] = rn
        with np.errstate(all="ignore"):
            mu0 = prob.hm.initial_shear_modulus(out)
        if constrained:
            err[~(mu0 > 0)] = np.inf
        err[~np.isfinite(err)] = np.inf
        # no least squares solution: no constants either (not decode's placeholder 1)
        out[np.ix_(~np.isfinite(err), amp)] = np.nan
        return out, err

    def errors(self, Z: np.ndarray) -> np.ndarray:
        """Objective of search vectors Z (P, d)."""
        hyper, tau = self.decode(Z)
        if self.exact:
            return self.solve_constants(hyper)[1]
        return self.solve_linear(hyper, tau)[1]

    def to_params(self, z: np.ndarray) -> np.ndarray:
        return self.params_of(z[None, :])[0]

    def params_of(self, Z: np.ndarray) -> np.ndarray:
        """Full parameter vectors (P, n_params) of search vectors Z (P, d), their linear
        constants solved as one batch (a polish's Jacobian rows at once)."""
        return self.fit_of(Z)[0]

    def fit_of(self, Z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Full parameter vectors (P, n_params) of search vectors Z and their weighted
        residuals (P, n_points) (:meth:`Problem.residuals`), from one solve of the
        linear constants: with Prony terms the residuals of the least squares itself
        (the stress is linear in E∞ and the G_i), without the model evaluated again."""
        hyper, tau = self.decode(np.atleast_2d(Z))
        if self.exact:
            X = self.solve_constants(hyper)[0]
            with np.errstate(all="ignore"):
                return X, self.prob.residuals(X)
        amps, _, R = self.solve_linear(hyper, tau, residuals=True)
        X = self.assemble_many(hyper, amps, tau)
        bad = ~np.isfinite(R).all(axis=1)
        if bad.any():  # nothing solved (inadmissible, not finite): the model says what
            with np.errstate(all="ignore"):
                R[bad] = self.prob.residuals(X[bad])
        return X, R

    def assemble(self, shape, E_inf, G, tau) -> np.ndarray:
        """Full parameter vector from a law's shape, its E∞, and the Prony terms.

        A shape without a positive initial modulus (μ0 ≤ 0, e.g. every linear constant
        zero: a search that found nothing finite) cannot be scaled to any E∞: its linear
        constants come back NaN (the error of such a vector is +inf). The linear
        constants the user bounded are kept within those bounds (the least squares met
        them up to rounding).
        """
        amps = np.concatenate([[E_inf], np.atleast_1d(np.asarray(G, dtype=np.float64))])
        return self.assemble_many(np.asarray(shape, dtype=np.float64)[None, :],
                                  amps[None, :], np.asarray(tau, dtype=np.float64)[None, :])[0]

    def assemble_many(self, shapes, amps, tau) -> np.ndarray:
        """:meth:`assemble` of many: shapes (P, n_h), amplitudes (E∞, G_i) (P, 1 + N) and
        τ (P, N); (P, n_params)."""
        hm = self.prob.hm
        P = shapes.shape[0]
        shape = np.array(shapes, dtype=np.float64)
        with np.errstate(all="ignore"):
            E_shape = 3.0 * np.asarray(hm.initial_shear_modulus(shape),
                                       dtype=np.float64).reshape(P)
        stiff = np.isfinite(E_shape) & (E_shape > 0)
        E_inf = amps[:, 0].astype(np.float64)
        G = np.array(amps[:, 1:], dtype=np.float64)
        # no long-term stiffness at all: keep the shape at a vanishing scale
        none = E_inf <= 0
        E_inf[none] = np.maximum(E_inf[none],
                                 1e-12 * np.maximum(1.0, np.sum(G[none], axis=1)))
        with np.errstate(all="ignore"):
            scaled = shape[:, self.amp] * (E_inf / E_shape)[:, None]
        # no stiffness to scale: no constants either
        shape[:, self.amp] = np.where(stiff[:, None], scaled, np.nan)
        for j, lo, hi in self.limits:
            k = self.amp[j]
            shape[stiff, k] = np.minimum(np.maximum(shape[stiff, k], lo), hi)
        for i, lo, hi in self.g_limits:
            G[:, i] = np.minimum(np.maximum(G[:, i], lo), hi)
        return self.prob.model.layout.assemble(shape, G, tau)


class FullSpace:
    """The paper's search: every parameter at once, τ as log10 τ."""

    method = "full"
    separable = False  # every parameter searched
    layout = method  # what a search vector means (a checkpoint's key)

    def angles(self):
        """The polishes' view of the space: the space itself (see SeparableSpace)."""
        return self
    popsize = 60
    maxiter = 100_000
    # the paper's DE: rand/1/bin, F = 0.8, CR = 0.7, NP = 60; each generation is
    # evaluated as one batch (deferred updating) so that workers = 1 and 2 follow the
    # same trajectory; de_options={"updating": "immediate"} is the paper's exact
    # one-at-a-time variant
    de_options = dict(strategy="rand1bin", mutation=0.8, recombination=0.7,
                      init="latinhypercube", updating="deferred")

    def __init__(self, prob: Problem):
        self.prob = prob

    def several_basins(self) -> bool:
        """The paper's search ends by its own criteria only."""
        return False

    def finish_levels(self, target: float) -> tuple[float, ...]:
        """No early polish of the all-parameter search."""
        return ()

    def bounds(self) -> list[tuple[float, float]]:
        # the paper's box: its moduli non-negative unless the user's bounds say otherwise
        # (Problem.errors rejects the inadmissible laws inside it)
        pb, hm, lay = self.prob.bounds, self.prob.hm, self.prob.model.layout
        b = [(max(pb[n][0], 0.0), pb[n][1])
             if hm.units[k] == "MPa" and n not in self.prob.user_bounds else pb[n]
             for k, n in enumerate(hm.param_names)]
        for i in range(lay.n_terms):
            b.append(pb[lay.amplitude_name(i)])
            b.append(tuple(self.prob.tau_b[i]))
        return b

    def errors(self, Z: np.ndarray) -> np.ndarray:
        """Objective of search vectors Z (P, d)."""
        return self.prob.errors(self.to_params(Z))

    def to_params(self, z: np.ndarray) -> np.ndarray:
        return self.prob.model.layout.from_log(z)


SPACES = {"separable": SeparableSpace, "full": FullSpace}


def search_vector(space, x: np.ndarray) -> np.ndarray:
    """The search vector of ``space`` whose parameters are the full vector ``x`` (τ for
    Prony terms that ``x`` lacks: the middle of their range, with a zero modulus).

    A fit with fewer Prony terms (pruned, or of N − 1 terms) is a point of the space of
    N terms: each of its terms goes to the slot whose τ range holds it, else the nearest.
    """
    prob, lay = space.prob, space.prob.model.layout
    n = lay.n_terms
    logtau = np.mean(prob.tau_b, axis=1)
    g = np.zeros(n)
    free = list(range(n))
    hyper, G, tau = lay.split(x)
    for gi, t in zip(G, np.log10(tau)):  # a pruned fit has fewer terms:
        if not free:  # each goes to the slot whose τ range holds it, else the nearest
            break
        lo, hi = prob.tau_b[free, 0], prob.tau_b[free, 1]
        i = free[int(np.argmin(np.maximum(lo - t, 0) + np.maximum(t - hi, 0)))]
        free.remove(i)
        logtau[i], g[i] = t, gi
    if not space.separable:
        return lay.assemble(hyper, g, logtau)
    amp = [x[k] for k in space.amp]
    z = []
    if space.angle:  # the direction of the two linear constants, turned onto the arc
        th, mid = math.atan2(amp[1], amp[0]), 0.5 * sum(space.theta)
        th += 2 * math.pi * round((mid - th) / (2 * math.pi))
        z.append(float(space.places(th, hyper)[0]) if space.on_arc else th)
    elif space.redundant:
        z += list(space.shape_coords(np.asarray(amp)))
    z += [x[k] for k in space.other]
    z += [logtau[i] for i in space.free_tau]
    return np.asarray(z, dtype=np.float64)
