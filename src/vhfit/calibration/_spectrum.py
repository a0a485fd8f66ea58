"""Small-strain data alone: the per-decade Prony spectrum instead of a global search.

When every test of a calibration is a frequency sweep or a relaxation test, the model's
outputs are the generalised Maxwell moduli (docs/theory.md §3, §10): for fixed τ they
are linear in (E∞, G_i), and nothing else of the law enters them. The fit is then the
standard linear-viscoelastic identification (:mod:`vhfit.spectrum`, docs/dma.md), done
here on the calibration's own weighted residuals (every test, its weights, the g∞
floor):

1. one τ per decade over the tests' time scales (1/ω of a sweep, t of a relaxation
   test), one decade beyond each end, inside the search's τ bounds;
2. NNLS for (E∞, G_i) on that grid, then backward pruning: the error against N for
   every N from the grid's size down to 1 (:func:`vhfit.spectrum.pruning_path`);
3. at the chosen N, log τ moved freely (Levenberg–Marquardt by variable projection: the
   moduli solved exactly at each step, Kaufman's Jacobian from the closed-form
   τ-derivatives of the columns) from the best of several starts — the pruned grid's
   τ, N values spread evenly in log τ over the data's decades, and the τ pruned from
   grids of 2 and 4 values a decade — then exchanges: the refined τ together with a
   grid of 2 a decade, pruned back to N and refined, kept while the error falls (free
   τ end in one of many local minima, each term holding its decade; an exchange lets a
   term move to another decade). A fit after the first in another formulation (whose
   moduli are the same) starts from the first fit's τ instead.

The refinement converges with the moduli exact, so no polish of every parameter
follows (on the master curves it moved the error by 1e-6 relative at most and cost a
third of the fit).

``n_prony="auto"`` reads N off the pruning path (the smallest N within ``order_tol`` of
the full grid's error, or exact to round-off) over N = 1 .. the grid's size, about one
term per decade of the data, and says so when the chosen N is the largest there.

The law's constants other than its small-strain modulus are not seen by such data: its
shape is the law's example, scaled so that 3 μ0 = E∞ (the report's uncertainty names
what the data cannot identify).

:func:`seed_from_moduli` gives a joint calibration (moduli beside large-strain curves)
the spectrum's τ of its moduli as one member of the search's first population.
"""

from __future__ import annotations

import math

import numpy as np

from vhfit._blas import one_blas_thread
from vhfit._linear import loss_shape, relaxation_shape, storage_shape
from vhfit.calibration._admissible import data_stability_range
from vhfit.calibration._report import finish
from vhfit.calibration._search import Search, _history
from vhfit.calibration._space import Problem, SeparableSpace
from vhfit.calibration._stop import Stop, StopKind
from vhfit.data import is_moduli
from vhfit.spectrum import pruning_path
from vhfit.viscous import ParamLayout

__all__ = ["applies", "tau_grid", "spectrum_fit", "seed_from_moduli", "ROUTE", "cap_message"]

#: Steps of refinement that rank the starts before the best one goes on to the end
SCOUT_NFEV = 25

#: Steps and tolerances (xtol, ftol, gtol) of a whole refinement of log10 τ
MAX_NFEV = 400
REFINE_TOL = 1e-8

#: Relaxation times per decade of the finer grids whose pruned τ are further starts, and
#: of the grid an exchange adds to the refined τ (see :func:`_refined`)
FINE = (2, 4)

#: Exchanges (refined τ plus a finer grid, pruned back to N, refined) at most
EXCHANGES = 3

LN10 = math.log(10.0)

#: Pruning-path errors below this fraction of the one-term error count as an exact fit
EXACT = 1e-10

#: The result's ``stop_reason`` (and ``options["route"]``) of a fit by this route.
ROUTE = Stop.of(StopKind.SPECTRUM).message


def applies(curves, settings) -> bool:
    """Whether a calibration takes this route: only sweeps/relaxation tests, the separable
    method, the default free τ strategy and no τ bound given for a single term."""
    if not curves or not all(is_moduli(c) for c in curves):
        return False
    if not settings.space.separable or settings.tau_strategy != "free":
        return False
    b = settings.bounds
    return not (isinstance(b, dict) and any(ParamLayout.is_time(k) for k in b))


def tau_grid(curves, tau_b: np.ndarray) -> np.ndarray:
    """One τ per decade over the tests' time scales, one decade beyond each end, inside
    the τ bounds ``tau_b`` (log10, every row alike)."""
    scales = np.concatenate([np.asarray(c.history.out_time, dtype=np.float64)
                             for c in curves])
    scales = scales[np.isfinite(scales) & (scales > 0)]
    lo, hi = math.log10(scales.min()), math.log10(scales.max())
    k = np.arange(math.floor(lo) - 1, math.ceil(hi) + 2, dtype=np.float64)
    k = k[(k >= tau_b[0, 0]) & (k <= tau_b[0, 1])]
    if k.size == 0:
        k = np.array([0.5 * (tau_b[0, 0] + tau_b[0, 1])])
    return 10.0**k


class _Moduli:
    """The weighted columns of a moduli-only problem and NNLS with the g∞ floor."""

    def __init__(self, prob: Problem, shape: np.ndarray):
        self.prob, self.shape = prob, shape[None, :]
        self.ys = prob.y * prob.scale
        g = prob.g_inf_min
        self.kappa = g / (1.0 - g) if g > 0 else 0.0
        self.nfev = 0
        self._base = None  # (problem, E∞ column × scale) of the closed forms

    def matrix(self, tau: np.ndarray) -> np.ndarray:
        """[E∞ column, G_i columns] × scale, (n_points, 1 + N)."""
        base, H = self.prob.batch.shape_columns(self.shape, np.asarray(tau)[None, :])
        self.nfev += 1
        return np.column_stack([base[0], H[0].T]) * self.prob.scale[:, None]

    def columns(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`matrix` at τ = 10^z and the derivative of each Prony column with
        respect to its own log10 τ, both × scale, by the closed forms of the small-strain
        moduli (docs/dma.md): with s = x²/(1 + x²), l = x/(1 + x²), x = ωτ,
        ds/dln τ = 2 s (1 − s), dl/dln τ = l (1 − 2 s); d e^(−t/τ)/dln τ = (t/τ) e^(−t/τ).
        The columns are those of the batch's own evaluation (every output of a
        moduli-only batch is a sweep's or a relaxation test's)."""
        prob = self.prob
        if self._base is None or self._base[0] is not prob:
            self._base = (prob, self.matrix(np.ones(1))[:, 0].copy())
        tau = 10.0 ** np.asarray(z, dtype=np.float64)
        n = self._base[1].size
        H, D = np.empty((n, tau.size)), np.empty((n, tau.size))
        for load, sl in prob.batch._linear.loads:  # (the batch's small-strain plan)
            with np.errstate(divide="ignore", over="ignore", under="ignore",
                             invalid="ignore"):
                if load.kind == "frequency":
                    m = load.x.size
                    x = load.x[:, None] * tau
                    s = storage_shape(x)
                    loss = loss_shape(x)
                    H[sl.start:sl.start + m], H[sl.start + m:sl.stop] = s, loss
                    D[sl.start:sl.start + m] = 2.0 * s * (1.0 - s)
                    D[sl.start + m:sl.stop] = loss * (1.0 - 2.0 * s)
                else:
                    r = load.x[:, None] / tau
                    e = relaxation_shape(load.x[:, None], tau)
                    H[sl], D[sl] = e, np.where(e > 0, r * e, 0.0)
        self.nfev += 1
        sc = prob.scale[:, None]
        return np.column_stack([self._base[1], H * sc]), D * (LN10 * sc)

    def solve(self, A: np.ndarray) -> tuple[np.ndarray, float]:
        """(E∞, G_i) ≥ 0 with E∞ ≥ κ ΣG (the g∞ floor), and the residual norm."""
        from vhfit._nnls import nnls

        a, rn = nnls(A, self.ys, maxiter=50 * A.shape[1])
        if self.kappa > 0 and a[0] < self.kappa * a[1:].sum():
            g, rn = nnls(A[:, 1:] + self.kappa * A[:, :1], self.ys, maxiter=50 * A.shape[1])
            a = np.concatenate([[self.kappa * g.sum()], g])
        return a, float(rn)

    def error(self, z: np.ndarray) -> float:
        """The objective at log10 τ = ``z``, the moduli solved."""
        return self.solve(self.columns(z)[0])[1]

    def _projected(self, A: np.ndarray, active: np.ndarray | None = None):
        """The moduli at columns ``A``, an orthonormal basis of their active columns and
        the active set. The least squares on ``active`` (default all columns) is the
        constrained optimum when it is feasible (every modulus > 0, the g∞ floor held)
        and no column left out would lower the residual with a positive modulus (the
        optimality conditions of NNLS); else NNLS decides."""
        act = np.ones(A.shape[1], dtype=bool) if active is None else active
        Q, R = np.linalg.qr(A[:, act])
        with np.errstate(all="ignore"):
            sub = np.linalg.solve(R, Q.T @ self.ys) if np.all(np.diag(R) != 0) else None
        if sub is not None and np.all(np.isfinite(sub)) and np.all(sub > 0):
            a = np.zeros(A.shape[1])
            a[act] = sub
            if self.kappa <= 0 or a[0] >= self.kappa * a[1:].sum():
                if act.all() or np.all(A[:, ~act].T @ (A[:, act] @ sub - self.ys)
                                       >= -1e-12 * np.abs(self.ys).sum()):
                    return a, Q, act
        a, _ = self.solve(A)
        g = a[1:]
        if self.kappa > 0 and a[0] <= self.kappa * g.sum() * (1 + 1e-12) and g.any():
            Aa = A[:, 1:][:, g > 0] + self.kappa * A[:, :1]
            act = None  # (the floor ties E∞ to the G_i: no plain active set)
        else:
            act = a > 0
            Aa = A[:, act]
        return a, (np.linalg.qr(Aa)[0] if Aa.shape[1] else None), act

    def refine(self, logtau: np.ndarray, bounds: tuple[float, float],
               max_nfev: int = MAX_NFEV) -> np.ndarray:
        """Free log10 τ (bounded) by variable projection from ``logtau``; sorted.

        The moduli are re-solved at every step and the Jacobian is Kaufman's: the
        closed-form τ-derivatives of the columns, times the moduli, projected off the
        span of the active columns."""
        lo, hi = bounds
        z0 = np.clip(np.asarray(logtau, dtype=np.float64), lo, hi)
        if not lo < hi:
            return z0
        z, active = z0, [None]

        def at(z):
            A, dA = self.columns(z)
            a, Q, active[0] = self._projected(A, active[0])
            return A @ a - self.ys, dA, a, Q

        def jac(dA, a, Q):
            D = dA * a[1:]
            if Q is not None:
                D = D - Q @ (Q.T @ D)  # Kaufman's variable-projection Jacobian
            return D

        with np.errstate(all="ignore"):
            r, dA, a, Q = at(z)
            cost = float(r @ r)
            if not np.isfinite(cost):
                return np.sort(z0)
            J = jac(dA, a, Q)
            lam, nu, nfev = None, 2.0, 1
            while nfev < max_nfev:
                g = J.T @ r
                H = J.T @ J
                d = np.diag(H).copy()
                if lam is None:
                    lam = 1e-3 * float(d.max()) if d.max() > 0 else 1.0
                if not np.abs(g).max() > REFINE_TOL * max(cost, 1e-300):
                    break
                d = np.maximum(d, 1e-12 * max(float(d.max()), 1e-300))
                try:
                    step = -np.linalg.solve(H + lam * np.diag(d), g)
                except np.linalg.LinAlgError:
                    lam, nu = lam * nu, nu * 2.0
                    continue
                z1 = np.clip(z + step, lo, hi)
                step = z1 - z
                pred = -(2.0 * float(g @ step) + float(step @ (H @ step)))
                r1, dA1, a1, Q1 = at(z1)
                nfev += 1
                cost1 = float(r1 @ r1)
                rho = (cost - cost1) / pred if pred > 0 else -1.0
                if np.isfinite(cost1) and cost1 < cost and rho > 0:
                    small = (cost - cost1 <= REFINE_TOL * cost
                             or np.abs(step).max() <= REFINE_TOL * (np.abs(z).max() + REFINE_TOL))
                    z, r, cost = z1, r1, cost1
                    J = jac(dA1, a1, Q1)
                    lam *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
                    nu = 2.0
                    if small:
                        break
                else:
                    lam, nu = lam * nu, nu * 2.0
                    if lam > 1e16 * max(float(d.max()), 1e-300):
                        break
        return np.sort(z)


def _fast_prune(A: np.ndarray, b: np.ndarray, n: int) -> np.ndarray | None:
    """The Prony columns of ``A`` (E∞ first) kept by backward pruning down to ``n``.

    Columns whose NNLS modulus is 0 go first, at no cost. Then each step drops the
    column whose removal raises the least-squares residual least, a_j² / [(AᵀA)⁻¹]_jj
    (the others re-fitted without sign limits: the closed form of removing one column),
    and the others' moduli follow by the same closed form (the inverse Gram matrix
    updated, not re-factored); only when one of them would turn negative are they
    re-solved by NNLS. None when fewer than ``n`` columns carry a modulus."""
    from vhfit._nnls import nnls

    keep = np.arange(A.shape[1] - 1)
    c = None
    while True:
        if c is None:
            B = A[:, np.r_[0, keep + 1]]
            c, _ = nnls(B, b, maxiter=50 * B.shape[1])
            nz = c[1:] > 0
            if nz.sum() < n:
                return None
            keep, c = keep[nz], np.concatenate([c[:1], c[1:][nz]])
            # E∞ in the set (its modulus may be 0: then left out of the closed forms)
            off = int(c[0] > 0)
            B = A[:, np.r_[0, keep + 1]][:, 1 - off:]
            try:
                Ginv = np.linalg.inv(B.T @ B)
            except np.linalg.LinAlgError:
                return None
        if keep.size <= n:
            return keep
        d = np.diag(Ginv)[off:]
        if not np.all(d > 0):
            return None
        j = int(np.argmin(c[1:] ** 2 / d))
        k = j + off
        cc = c[1 - off:] - c[1 + j] * Ginv[:, k] / Ginv[k, k]
        Ginv = Ginv - np.outer(Ginv[:, k], Ginv[k, :]) / Ginv[k, k]
        Ginv = np.delete(np.delete(Ginv, k, axis=0), k, axis=1)
        cc = np.delete(cc, k)
        keep = np.delete(keep, j)
        if np.all(cc > 0):
            c = cc if off else np.concatenate([[0.0], cc])
        else:
            c = None  # a modulus would turn negative: NNLS again


def _shape(prob: Problem) -> np.ndarray:
    """The law's example constants, its nonlinear ones inside their search bounds."""
    hm = prob.hm
    shape = np.asarray(hm.example, dtype=np.float64).copy()
    for k, name in enumerate(hm.param_names):
        if k not in hm.linear_index:
            lo, hi = prob.bounds[name]
            shape[k] = min(max(shape[k], lo), hi)
    return shape


def _fine_start(mod: _Moduli, ends: tuple[float, float], per_decade: int, n: int,
                with_z: np.ndarray | None = None) -> np.ndarray | None:
    """log10 τ of N terms pruned (:func:`_fast_prune`) from a grid of ``per_decade``
    values a decade over ``ends`` (log10), plus ``with_z`` if given; None if the grid's
    NNLS keeps fewer than N."""
    g = np.arange(ends[0], ends[1] + 0.5 / per_decade, 1.0 / per_decade)
    if with_z is not None:
        g = np.sort(np.concatenate([g, with_z]))
    keep = _fast_prune(mod.columns(g)[0], mod.ys, n)
    return None if keep is None else g[keep]


def _refined(mod: _Moduli, grid: np.ndarray, keep: np.ndarray | None, n: int, bounds,
             given: np.ndarray | None = None, thorough: bool = True):
    """The refinement at N.

    From ``given`` log10 τ if any. Otherwise the starts are the pruned grid's τ
    (``keep``; pruned here when None), N values spread evenly in log τ over the data's
    decades and, when ``thorough``, the τ pruned from grids of :data:`FINE` values a
    decade: each is refined :data:`SCOUT_NFEV` steps and the best one goes on to the
    end. Free τ end in one of many local minima (each term holds its decade), so then,
    when ``thorough``, up to :data:`EXCHANGES` exchanges: the refined τ together with a
    grid of ``FINE[0]`` values a decade, pruned back to N and refined, kept while the
    error falls — a term can move to another decade, past the others."""
    if given is not None:
        z = mod.refine(np.sort(np.asarray(given, dtype=np.float64)), bounds)
        a, rn = mod.solve(mod.columns(z)[0])
        return z, a, rn
    lg = np.log10(grid)
    if keep is None:
        keep = _fast_prune(mod.columns(lg)[0], mod.ys, n)
        if keep is None:  # fewer terms carry a modulus than asked: the evenly spread
            keep = np.round(np.linspace(0, grid.size - 1, n)).astype(int)
    starts = [lg[keep]]
    ends = lg[[1, -2]] if grid.size > 3 else lg[[0, -1]]
    starts.append(np.linspace(ends[0], ends[1], n) if n > 1 else np.array([ends.mean()]))
    span = (float(lg[0]), float(lg[-1]))
    if thorough:
        starts += [z for z in (_fine_start(mod, span, k, n) for k in FINE) if z is not None]
    scouts = []
    for z0 in starts:
        z = mod.refine(z0, bounds, SCOUT_NFEV)
        scouts.append((mod.error(z), z))
    z = mod.refine(min(scouts, key=lambda sz: sz[0])[1], bounds)
    err = mod.error(z)
    for _ in range(EXCHANGES if thorough else 0):
        z0 = _fine_start(mod, span, FINE[0], n, with_z=z)
        if z0 is None:
            break
        z1 = mod.refine(z0, bounds, SCOUT_NFEV)
        if not mod.error(z1) < err:
            break
        z1 = mod.refine(z1, bounds)
        e1 = mod.error(z1)
        if not e1 < err * (1 - 1e-9):
            break
        z, err = z1, e1
    a, rn = mod.solve(mod.columns(z)[0])
    return z, a, rn


def cap_message(n: int, what: str, fix: str) -> str:
    """The headline of an automatic N that stopped at the largest N it tried."""
    return (f"n_prony='auto' chose N = {n}, the largest it tried ({what}): more terms may "
            f"fit better; {fix}")


def _given_tau(settings, n: int) -> np.ndarray | None:
    """The log10 τ of N terms that a fit after the first starts from: the last N entries
    of the first row of its ``de_options["init"]``; None when there is none."""
    init = (settings.de_options or {}).get("init")
    if init is not None and np.ndim(init) == 2 and np.shape(init)[1] >= n:
        return np.asarray(init, dtype=np.float64)[0, -n:]
    return None


def spectrum_fit(curves, settings, model_for, n_prony: int | None, t0: float):
    """The calibration of moduli-only data by the per-decade spectrum.

    ``model_for(n)`` builds (model, tau_b, bounds) for N terms; ``n_prony`` None scans
    N automatically. Returns the :class:`Calibration`, the order scan (None for a given
    N), the headlines of the scan and the N it chose. Runs with one BLAS thread
    (:func:`vhfit._blas.one_blas_thread`): its thousands of small QR factorisations
    and products gain nothing from more, and wait for busy cores.
    """
    import scipy.optimize  # noqa: F401  (its BLAS loaded before the threads are set)

    with one_blas_thread():
        return _spectrum_fit(curves, settings, model_for, n_prony, t0)


def _spectrum_fit(curves, settings, model_for, n_prony: int | None, t0: float):
    """:func:`spectrum_fit` itself."""
    s = settings
    model, tau_b, auto = model_for(1 if n_prony is None else n_prony)
    grid_prob = Problem(model, curves, tau_b, auto, s.g_inf_min, s.objective)
    shape = _shape(grid_prob)
    mod = _Moduli(grid_prob, shape)
    grid = tau_grid(curves, tau_b)
    given = None if n_prony is None else _given_tau(s, n_prony)
    # the pruning path reads an automatic N (and gives its start); a given N's start is
    # pruned by the faster closed-form rule (:func:`_fast_prune`) in the refinement
    path = None if n_prony is not None else pruning_path(mod.matrix(grid), mod.ys)
    scan, heads = None, []
    if n_prony is None:
        # within order_tol of the full grid; an error at round-off level (EXACT times
        # the one-term error) counts as exact whatever the full grid's round-off is
        limit = max((1 + s.order_tol) * min(e for _, _, e in path), EXACT * path[-1][2])
        n = min(k.size for k, _, e in path if e <= limit)
        scan = [{"n_prony": int(k.size), "rmsape": float(e), "effective_n": int(k.size)}
                for k, _, e in reversed(path)]
        if n == grid.size:
            heads.append(cap_message(n, f"N = 1..{grid.size}, one relaxation time per decade "
                                     "of the data and one beyond each end",
                                     "give a larger N (n_prony=, --prony N) to fit more "
                                     "than one per decade"))
        model, tau_b, auto = model_for(n)
        given = _given_tau(s, n)
    else:
        n = n_prony
    bounds = (float(tau_b[0, 0]), float(tau_b[0, 1]))
    prob = Problem(model, curves, tau_b, auto, s.g_inf_min, s.objective)
    mod.prob = prob
    if n > grid.size:  # more terms than decades: N values spread evenly over the grid
        grid, keep = np.geomspace(grid[0], grid[-1], n), np.arange(n)
    elif path is not None:
        keep = next(k for k, _, _ in path if k.size == n)
    else:
        keep = None  # (pruned in the refinement, or it starts from the given τ)
    z, a, _ = _refined(mod, grid, keep, n, bounds, given)
    space = SeparableSpace(prob)
    x = space.assemble(shape, a[0], a[1:], 10.0**z)
    err = float(prob.errors(x[None, :])[0])
    # (no polish of every parameter after it: the refinement has converged in log τ
    # with the moduli exact, and a polish moved the error by 1e-6 relative at most on
    # the master curves while it cost a third of the fit)
    nfev = mod.nfev
    found = Search(np.log10(x[model.layout.times]), 0, nfev,
                   Stop.of(StopKind.SPECTRUM), _history(None), t0)
    options = dict(
        hyperelastic=model.hyperelastic.name, n_prony=n, tau_strategy=str(s.tau_strategy),
        objective=prob.objective.kind, method=s.method, seed=s.seed, popsize=0, maxiter=0,
        tol=s.effective_tol, target=s.target, polish=s.polish, g_inf_min=s.g_inf_min,
        rtol=s.rtol, route=ROUTE,
        stability_range=[float(v) for v in s.stability_range or data_stability_range(curves)],
        tau_grid=[float(v) for v in grid])
    cal = finish(prob, curves, model, x, err, found, nfev, s, options)
    return cal, scan, heads, n


def seed_from_moduli(curves, space, settings, n: int) -> np.ndarray | None:
    """A search vector of ``space`` (a :class:`SeparableSpace`) whose τ are the spectrum's
    of the moduli among ``curves`` at N = ``n``, its shape the middle of its bounds; None
    when there are no moduli (or no large-strain curves, or τ to search)."""
    moduli = [c for c in curves if is_moduli(c)]
    if not moduli or len(moduli) == len(curves) or n < 1 or not isinstance(
            space, SeparableSpace) or len(space.free_tau) != n:
        return None
    prob = space.prob
    tau_b = prob.tau_b
    if not np.all(tau_b == tau_b[0]):
        return None
    sub = Problem(prob.model, moduli, tau_b, prob.bounds, settings.g_inf_min,
                  settings.objective)
    mod = _Moduli(sub, _shape(sub))
    grid = tau_grid(moduli, tau_b)
    path = pruning_path(mod.matrix(grid), mod.ys)
    if n <= grid.size:
        keep = next(k for k, _, _ in path if k.size == n)
    else:
        grid, keep = np.geomspace(grid[0], grid[-1], n), np.arange(n)
    z, _, _ = _refined(mod, grid, keep, n, (float(tau_b[0, 0]), float(tau_b[0, 1])),
                       thorough=False)
    b = space.bounds()
    lead = [0.5 * (lo + hi) for lo, hi in b[: len(b) - n]]
    return np.clip(np.concatenate([lead, z]), [lo for lo, _ in b], [hi for _, hi in b])
