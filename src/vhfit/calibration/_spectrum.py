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
3. at the chosen N, log τ moved freely (bounded Gauss–Newton by variable projection, the
   moduli by NNLS at each step) from the better of two starts — the pruned grid's τ and
   N values spread evenly in log τ over the data's decades — or, for a fit after the
   first in another formulation (whose moduli are the same), from the first fit's τ;
4. the calibration's polish (bounded least squares on every parameter), which never
   raises the error.

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

from vhfit.calibration._admissible import data_stability_range
from vhfit.calibration._polish import polish as polish_fit
from vhfit.calibration._report import finish
from vhfit.calibration._search import Search, _history
from vhfit.calibration._space import Problem, SeparableSpace
from vhfit.data import is_moduli
from vhfit.spectrum import pruning_path

__all__ = ["applies", "tau_grid", "spectrum_fit", "seed_from_moduli", "ROUTE", "cap_message"]

#: Steps of the final polish: it starts at the variable-projection optimum, so a few
#: steps of least squares on every parameter settle what the τ refinement left
POLISH_NFEV = 10

#: Steps of refinement that rank the two starts before the better one goes on to the end
SCOUT_NFEV = 40

#: Pruning-path errors below this fraction of the one-term error count as an exact fit
EXACT = 1e-10

#: The result's ``stop_reason`` (and ``options["route"]``) of a fit by this route.
ROUTE = "per-decade spectrum (NNLS on a tau grid, pruning, free-tau refinement)"


def applies(curves, settings) -> bool:
    """Whether a calibration takes this route: only sweeps/relaxation tests, the separable
    method, the default free τ strategy and no τ bound given for a single term."""
    if not curves or not all(is_moduli(c) for c in curves):
        return False
    if settings.method != "separable" or settings.tau_strategy != "free":
        return False
    b = settings.bounds
    return not (isinstance(b, dict) and any(k.startswith("tau") for k in b))


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

    def matrix(self, tau: np.ndarray) -> np.ndarray:
        """[E∞ column, G_i columns] × scale, (n_points, 1 + N)."""
        base, H = self.prob.batch.shape_columns(self.shape, np.asarray(tau)[None, :])
        self.nfev += 1
        return np.column_stack([base[0], H[0].T]) * self.prob.scale[:, None]

    def solve(self, A: np.ndarray) -> tuple[np.ndarray, float]:
        """(E∞, G_i) ≥ 0 with E∞ ≥ κ ΣG (the g∞ floor), and the residual norm."""
        from scipy.optimize import nnls

        a, rn = nnls(A, self.ys, maxiter=50 * A.shape[1])
        if self.kappa > 0 and a[0] < self.kappa * a[1:].sum():
            g, rn = nnls(A[:, 1:] + self.kappa * A[:, :1], self.ys, maxiter=50 * A.shape[1])
            a = np.concatenate([[self.kappa * g.sum()], g])
        return a, float(rn)

    def refine(self, logtau: np.ndarray, bounds: tuple[float, float],
               max_nfev: int = 400) -> np.ndarray:
        """Free log10 τ (bounded) by variable projection from ``logtau``; sorted."""
        from scipy.optimize import least_squares

        lo, hi = bounds
        z0 = np.clip(np.asarray(logtau, dtype=np.float64), lo, hi)
        if not lo < hi:
            return z0
        h = 1e-6
        cache: dict = {}

        def solve(z):
            key = z.tobytes()
            if key not in cache:
                A = self.matrix(10.0**z)
                a, _ = self.solve(A)
                cache.clear()
                cache[key] = (A, a)
            return cache[key]

        def resid(z):
            A, a = solve(z)
            return A @ a - self.ys

        def jac(z):
            A, a = solve(z)
            g = a[1:]
            # d(A a)/d log10 τ_i at fixed moduli (each column depends on its own τ only)
            D = (self.matrix(10.0 ** (z + h))[:, 1:] - A[:, 1:]) / h * g
            if self.kappa > 0 and a[0] <= self.kappa * g.sum() * (1 + 1e-12) and g.any():
                active = np.concatenate([[False], g > 0])
                Aa = A[:, 1:][:, g > 0] + self.kappa * A[:, :1]
            else:
                active = a > 0
                Aa = A[:, active]
            if active.any():
                Q, _ = np.linalg.qr(Aa)
                D = D - Q @ (Q.T @ D)  # Kaufman's variable-projection Jacobian
            return D

        with np.errstate(all="ignore"):
            sol = least_squares(resid, z0, jac=jac, bounds=(np.full(z0.size, lo),
                                np.full(z0.size, hi)), method="trf", xtol=1e-12,
                                ftol=1e-12, gtol=1e-12, max_nfev=max_nfev)
        return np.sort(sol.x)


def _shape(prob: Problem) -> np.ndarray:
    """The law's example constants, its nonlinear ones inside their search bounds."""
    hm = prob.hm
    shape = np.asarray(hm.example, dtype=np.float64).copy()
    for k, name in enumerate(hm.param_names):
        if k not in hm.linear_index:
            lo, hi = prob.bounds[name]
            shape[k] = min(max(shape[k], lo), hi)
    return shape


def _refined(mod: _Moduli, grid: np.ndarray, keep: np.ndarray, n: int, bounds,
             given: np.ndarray | None = None):
    """The refinement at N: from ``given`` log10 τ if any, else from the better of two
    starts — the pruned grid's τ and N values spread evenly in log τ over the data's
    decades — each refined :data:`SCOUT_NFEV` steps, the better one then to the end."""
    if given is not None:
        starts = [np.sort(np.asarray(given, dtype=np.float64))]
    else:
        starts = [np.log10(grid[keep])]
        ends = np.log10(grid[[1, -2]] if grid.size > 3 else grid[[0, -1]])
        starts.append(np.linspace(ends[0], ends[1], n) if n > 1 else np.array([ends.mean()]))
    if len(starts) > 1:
        scouts = []
        for z0 in starts:
            z = mod.refine(z0, bounds, SCOUT_NFEV)
            scouts.append((mod.solve(mod.matrix(10.0**z))[1], z))
        starts = [min(scouts, key=lambda sz: sz[0])[1]]
    z = mod.refine(starts[0], bounds)
    a, rn = mod.solve(mod.matrix(10.0**z))
    return z, a, rn


def _at_shape(prob: Problem, x: np.ndarray, shape: np.ndarray) -> np.ndarray:
    """``x`` with the law's constants put back to ``shape`` scaled to the same initial
    shear modulus: moduli see a law only through μ0, so a polish of all the constants
    drifts freely along the directions they cannot see (Mooney–Rivlin's C10 − C01, to
    C10 = 511 and C01 = −506 MPa on a master curve: a law unstable at once). The moduli,
    and so the error, are unchanged."""
    hm = prob.hm
    nh = hm.n_params
    with np.errstate(all="ignore"):
        mu, mu_s = (float(hm.initial_shear_modulus(v)) for v in (x[:nh], shape))
    if not (np.isfinite(mu) and mu > 0 and mu_s > 0):
        return x
    out = np.array(x, dtype=np.float64, copy=True)
    out[:nh] = shape
    out[list(hm.linear_index)] *= mu / mu_s
    return out


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
    N), the headlines of the scan and the N it chose.
    """
    s = settings
    model, tau_b, auto = model_for(1 if n_prony is None else n_prony)
    grid_prob = Problem(model, curves, tau_b, auto, s.g_inf_min, s.objective)
    shape = _shape(grid_prob)
    mod = _Moduli(grid_prob, shape)
    grid = tau_grid(curves, tau_b)
    given = None if n_prony is None else _given_tau(s, n_prony)
    # the pruning path picks the refinement's start (and an automatic N): not needed
    # for a given N from given τ
    path = None if given is not None else pruning_path(mod.matrix(grid), mod.ys)
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
        keep = None  # (the refinement starts from the given τ)
    z, a, _ = _refined(mod, grid, keep, n, bounds, given)
    space = SeparableSpace(prob)
    x = space.assemble(shape, a[0], a[1:], 10.0**z)
    err = float(prob.errors(x[None, :])[0])
    nfev = mod.nfev
    if s.polish:
        x, err, n_pol = polish_fit(prob, x, POLISH_NFEV)
        nfev += n_pol
        x = _at_shape(prob, x, shape)
        err = float(prob.errors(x[None, :])[0])
    found = Search(np.log10(x[model.hyperelastic.n_params + 1::2]), 0, nfev, ROUTE,
                   _history(None), t0)
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
    z, _, _ = _refined(mod, grid, keep, n, (float(tau_b[0, 0]), float(tau_b[0, 1])))
    b = space.bounds()
    lead = [0.5 * (lo + hi) for lo, hi in b[: len(b) - n]]
    return np.clip(np.concatenate([lead, z]), [lo for lo, _ in b], [hi for _, hi in b])
