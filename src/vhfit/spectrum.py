"""Prony spectrum of DMA or relaxation data: one τ per decade, NNLS, then pruning.

The standard linear-viscoelastic identification (docs/dma.md):

1. fix the relaxation times on a grid of ``per_decade`` values per decade spanning the
   data (τ from 1/(2π f_max) to 1/(2π f_min), or from t_min to t_max), one decade
   beyond each end;
2. fit E∞ ≥ 0 and every G_i ≥ 0 by non-negative least squares on the *relative*
   residuals (E′_model − E′)/E′ and (E″_model − E″)/E″ — or (E_model − E)/E in time —
   so that moduli spanning decades count alike;
3. prune: drop, one at a time, the term whose removal raises the error least
   (re-fitting the others), down to one term; this gives the error against N, and the
   smallest N whose error stays within ``1 + tolerance`` times the full spectrum's is
   chosen;
4. optionally (``refine=True``) move the chosen τ_i freely (log τ by Gauss–Newton,
   the moduli by NNLS at each step) for the same N.

Small-strain moduli of the model (docs/theory.md §3): E(t) = E∞ + Σ G_i e^(−t/τ_i),
E′(ω) = E∞ + Σ G_i ω²τ_i²/(1 + ω²τ_i²), E″(ω) = Σ G_i ωτ_i/(1 + ω²τ_i²), ω = 2πf.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from vhfit.viscous import ParamLayout

__all__ = ["PronySpectrum", "prony_spectrum", "design_matrix", "rms_relative_error",
           "pruning_path"]


@dataclass(frozen=True)
class PronySpectrum:
    """A fitted Prony series and its error-against-N table.

    Attributes
    ----------
    E_inf : float
        Long-term modulus E∞, MPa.
    G, tau : ndarray
        Prony moduli G_i (MPa) and relaxation times τ_i (s), τ ascending.
    error : float
        RMS relative error of the fit (of E′ and E″ together, or of E(t)).
    domain : {"frequency", "time"}
    table : ndarray
        Rows (N, RMS relative error) of the pruning path, N descending from the full
        grid to 1.
    tolerance : float
        The accepted relative error increase that chose N.
    """

    E_inf: float
    G: np.ndarray
    tau: np.ndarray
    error: float
    domain: str
    table: np.ndarray = field(repr=False)
    tolerance: float = 0.0

    @property
    def n_prony(self) -> int:
        return int(self.G.size)

    def params(self) -> dict[str, float]:
        """``{"G1": ..., "tau1": ..., ...}`` in vhfit's parameter names."""
        lay = ParamLayout((), (), self.n_prony)
        return dict(zip(lay.names, lay.assemble([], self.G, self.tau).tolist()))

    def summary(self) -> str:
        rows = "\n".join(f"  N = {int(n):3d}   RMS relative error {e:.4%}" for n, e in self.table)
        return (f"Prony spectrum ({self.domain} domain): N = {self.n_prony}, E_inf = "
                f"{self.E_inf:.6g} MPa, RMS relative error {self.error:.4%}\n{rows}")


def _data(item, frequency, storage, loss, time, modulus):
    if item is not None:
        # getattr default: a sweep, a relaxation test or a MasterCurve (storage None: time)
        if getattr(item, "storage", None) is not None:
            frequency, storage, loss = item.frequency, item.storage, item.loss
        else:
            time, modulus = item.time, item.modulus
    if frequency is not None:
        if storage is None or loss is None:
            raise ValueError("frequency data need storage= and loss= (MPa)")
        cols = [np.asarray(v, dtype=np.float64).ravel() for v in (frequency, storage, loss)]
        names = ("frequency", "storage", "loss")
        domain = "frequency"
    elif time is not None and modulus is not None:
        cols = [np.asarray(v, dtype=np.float64).ravel() for v in (time, modulus)]
        names = ("time", "modulus")
        domain = "time"
    else:
        raise ValueError("give an item, or frequency=, storage=, loss=, or time=, modulus=")
    for name, c in zip(names, cols):
        if c.shape != cols[0].shape or c.size < 2:
            raise ValueError(f"{name}: need one value per point and at least 2 points")
        if not (np.isfinite(c).all() and (c > 0).all()):
            raise ValueError(f"{name}: every value must be finite and > 0 (a relative error "
                             "needs a non-zero modulus)")
    return domain, cols


def design_matrix(domain: str, x: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """Columns [1, term_1, ..., term_n] of the moduli at ``x`` (frequency: E′ rows, then
    E″ rows; time: E(t) rows), unweighted."""
    tau = np.asarray(tau, dtype=np.float64)
    if domain == "time":
        return np.column_stack([np.ones_like(x), np.exp(-x[:, None] / tau)])
    wt = 2.0 * math.pi * x[:, None] * tau
    d = 1.0 + wt * wt
    top = np.column_stack([np.ones_like(x), wt * wt / d])
    bottom = np.column_stack([np.zeros_like(x), wt / d])
    return np.vstack([top, bottom])


def rms_relative_error(domain: str, x, targets, E_inf: float, G, tau) -> float:
    """RMS relative error of a Prony series on data (E′ and E″ rows together in frequency).

    Examples
    --------
    >>> import numpy as np
    >>> f = np.array([0.1, 1.0, 10.0])
    >>> w = 2 * np.pi * f
    >>> E1 = 1 + 2 * w**2 / (1 + w**2); E2 = 2 * w / (1 + w**2)
    >>> rms_relative_error("frequency", f, np.concatenate([E1, E2]), 1.0, [2.0], [1.0])
    0.0
    """
    A = design_matrix(domain, np.asarray(x, dtype=np.float64), np.atleast_1d(tau))
    model = A @ np.concatenate([[E_inf], np.atleast_1d(G)])
    t = np.asarray(targets, dtype=np.float64)
    return float(np.sqrt(np.mean(((model - t) / t) ** 2)))


def _nnls(Aw, b):
    from vhfit._nnls import nnls

    coef, rnorm = nnls(Aw, b, maxiter=50 * Aw.shape[1])
    return coef, float(rnorm / math.sqrt(b.size))


def _tau_grid(domain: str, x: np.ndarray, per_decade: int) -> np.ndarray:
    if domain == "frequency":
        lo, hi = 1.0 / (2 * math.pi * x.max()), 1.0 / (2 * math.pi * x.min())
    else:
        lo, hi = x.min(), x.max()
    k0 = math.floor(per_decade * math.log10(lo)) - per_decade
    k1 = math.ceil(per_decade * math.log10(hi)) + per_decade
    return 10.0 ** (np.arange(k0, k1 + 1) / per_decade)


def _prune(Aw, b, keep: np.ndarray):
    """Backward elimination: the (N, error, kept columns, coef) path from all terms to 1.

    A term whose NNLS modulus is 0 leaves the others' solution optimal when dropped
    (the optimality conditions still hold), so such terms go first at no cost; then each
    step drops the term whose removal, after re-fitting the others, raises the error
    least.
    """
    coef, err = _nnls(Aw[:, np.r_[0, keep + 1]], b)
    path = [(keep.size, err, keep, coef)]
    while keep.size > 1:
        zero = np.flatnonzero(coef[1:] == 0.0)
        if zero.size:
            j = zero[0]
            keep, coef = np.delete(keep, j), np.delete(coef, j + 1)
            path.append((keep.size, err, keep, coef))
            continue
        best = None
        for j in range(keep.size):
            trial = np.delete(keep, j)
            c, e = _nnls(Aw[:, np.r_[0, trial + 1]], b)
            if best is None or e < best[1]:
                best = (trial, e, c)
        keep, err, coef = best
        path.append((keep.size, err, keep, coef))
    return path


def pruning_path(A: np.ndarray, b: np.ndarray) -> list[tuple[np.ndarray, np.ndarray, float]]:
    """Backward pruning of the Prony columns of a weighted least-squares problem.

    Parameters
    ----------
    A : ndarray, shape (n, 1 + m)
        Weighted columns: the long-term modulus first, then one per relaxation time.
    b : ndarray, shape (n,)
        Weighted targets.

    Returns
    -------
    list of (kept, coef, residual)
        From all m terms down to 1: the kept Prony columns (indices into the m), the
        non-negative coefficients (long-term modulus first) and the residual norm
        ``||A[:, [0, kept + 1]] coef - b||``.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.logspace(-2, 2, 9)
    >>> A = np.column_stack([np.ones_like(t), np.exp(-t / 0.1), np.exp(-t / 10.0)])
    >>> path = pruning_path(A, 1.0 + 2.0 * np.exp(-t / 10.0))
    >>> [(k.tolist(), round(e, 12)) for k, _, e in path]
    [([0, 1], 0.0), ([1], 0.0)]
    """
    root = math.sqrt(np.asarray(b).size)
    return [(keep, coef, err * root) for _, err, keep, coef in
            _prune(np.asarray(A, dtype=np.float64), np.asarray(b, dtype=np.float64),
                   np.arange(np.shape(A)[1] - 1))]


def _columns_and_slopes(domain: str, x: np.ndarray, tau: np.ndarray):
    """The Prony columns at ``x`` and their derivatives with respect to ln τ."""
    if domain == "time":
        e = np.exp(-x[:, None] / tau)
        return e, (x[:, None] / tau) * e
    wt = 2.0 * math.pi * x[:, None] * tau
    w2 = wt * wt
    d = 1.0 + w2
    cols = np.vstack([w2 / d, wt / d])
    slopes = np.vstack([2.0 * w2 / d**2, wt * (1.0 - w2) / d**2])
    return cols, slopes


def _refine(domain, x, scale, b, tau):
    """Free ln τ for a fixed N by variable projection: the moduli are the NNLS solution
    at each step, and the Jacobian is Kaufman's (the τ-derivative of the columns,
    projected off the span of the active columns)."""
    from scipy.optimize import least_squares

    ones = np.ones(x.size)
    first = np.concatenate([ones, np.zeros(x.size)]) if domain == "frequency" else ones
    cache: dict = {}

    def solve(z):
        key = z.tobytes()
        if key not in cache:
            cols, slopes = _columns_and_slopes(domain, x, np.exp(z))
            A = np.column_stack([first, cols]) * scale[:, None]
            coef, _ = _nnls(A, b)
            cache.clear()
            cache[key] = (A, slopes * scale[:, None], coef)
        return cache[key]

    def resid(z):
        A, _, coef = solve(z)
        return A @ coef - b

    def jac(z):
        A, dA, coef = solve(z)
        D = dA * coef[1:]
        active = coef > 0
        if active.any():
            Q, _ = np.linalg.qr(A[:, active])
            D = D - Q @ (Q.T @ D)
        return D

    sol = least_squares(resid, np.log(tau), jac=jac, method="trf", xtol=1e-8, ftol=1e-8,
                        gtol=1e-8, max_nfev=200)
    return np.sort(np.exp(sol.x))


def prony_spectrum(item=None, *, frequency=None, storage=None, loss=None, time=None,
                   modulus=None, per_decade: int = 1, tolerance: float = 0.05,
                   n_prony: int | None = None, refine: bool = False) -> PronySpectrum:
    """Prony series of a master curve: τ per decade, non-negative moduli, pruning.

    Parameters
    ----------
    item : FrequencySweep, Relaxation or MasterCurve, optional
        The data; or give the arrays: ``frequency`` (Hz), ``storage``, ``loss`` (MPa),
        or ``time`` (s), ``modulus`` (MPa).
    per_decade : int
        Relaxation times per decade of the grid.
    tolerance : float
        Pruning keeps the smallest N whose RMS relative error is at most
        ``(1 + tolerance)`` times that of the full grid.
    n_prony : int, optional
        Take exactly this N from the pruning path instead.
    refine : bool
        Free the chosen τ_i (log τ by least squares, moduli by NNLS) at the chosen N.

    Returns
    -------
    PronySpectrum
        ``.table`` holds the error against N of the pruning path.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.logspace(-3, 3, 61)
    >>> E = 1.0 + 4.0 * np.exp(-t / 0.1) + 2.0 * np.exp(-t / 10.0)
    >>> s = prony_spectrum(time=t, modulus=E, n_prony=2, refine=True)
    >>> np.round(s.tau, 6).tolist(), np.round(s.G, 6).tolist(), round(s.E_inf, 6)
    ([0.1, 10.0], [4.0, 2.0], 1.0)
    """
    if not (isinstance(per_decade, (int, np.integer)) and per_decade >= 1):
        raise ValueError(f"per_decade = {per_decade!r}: give an integer >= 1")
    if not (math.isfinite(tolerance) and tolerance >= 0):
        raise ValueError(f"tolerance = {tolerance!r}: give a relative increase >= 0")
    domain, cols = _data(item, frequency, storage, loss, time, modulus)
    x = cols[0]
    targets = np.concatenate(cols[1:])
    scale = 1.0 / targets
    b = np.ones_like(targets)  # relative residuals: (model - data)/data
    grid = _tau_grid(domain, x, int(per_decade))
    Aw = design_matrix(domain, x, grid) * scale[:, None]
    path = _prune(Aw, b, np.arange(grid.size))
    table = np.array([(n, e) for n, e, _, _ in path])
    if n_prony is not None:
        if not (isinstance(n_prony, (int, np.integer)) and 1 <= n_prony <= grid.size):
            raise ValueError(f"n_prony = {n_prony!r}: give an integer from 1 to {grid.size}")
        chosen = next(p for p in path if p[0] == n_prony)
    else:
        limit = (1.0 + tolerance) * path[0][1]
        chosen = [p for p in path if p[1] <= limit][-1]
    tau = grid[chosen[2]]
    if refine:
        tau = _refine(domain, x, scale, b, tau)
    coef, _ = _nnls(design_matrix(domain, x, tau) * scale[:, None], b)
    err = rms_relative_error(domain, x, targets, coef[0], coef[1:], tau)
    return PronySpectrum(float(coef[0]), coef[1:].copy(), tau.copy(), err, domain, table,
                         float(tolerance))
