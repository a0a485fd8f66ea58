"""The polish in the separable search's own coordinates (variable projection).

The all-parameter polish (:mod:`vhfit.calibration._polish`) moves the law's constants,
the Prony moduli and log τ together; on a real record with an Ogden law it crawls along
the valley where the moduli and the exponents trade off (hundreds of evaluations for
the last 1e-5 of the error). Here least squares moves only the search vector z of a
:class:`SeparableSpace` (the law's shape, log10 τ) and the linear constants (E∞ and the
G_i) are solved exactly at every step, as in the search: the valley is gone, and the
same minimum is reached in a few tens of evaluations.
"""

from __future__ import annotations

import threading

import numpy as np

from vhfit.calibration._polish import ROUNDING_TOL, forward_jacobian, g_inf_ok

__all__ = ["varpro_polish", "varpro_polish_many", "VARPRO_NFEV"]

#: Residual evaluations of one variable-projection polish (its Jacobian rows included).
VARPRO_NFEV = 200


def varpro_polish(space, z0: np.ndarray, max_nfev: int = VARPRO_NFEV,
                  tol: float = ROUNDING_TOL, residuals=None, on_arc: bool = False):
    """Bounded least squares over the search vector of ``space`` from ``z0``.

    Parameters
    ----------
    space : SeparableSpace
        The search space (its ``prob``, ``bounds()`` and ``to_params``).
    z0 : ndarray
        A search vector (within or on the bounds).
    max_nfev : int
        Least-squares iterations' residual evaluations (``scipy.optimize.least_squares``).
    tol : float
        Its ``xtol``, ``ftol`` and ``gtol`` (default: run to rounding).
    residuals : callable, optional
        Search vectors (k, d) -> their weighted residuals (k, n_points); default
        ``space.fit_of(Z)[1]`` (:func:`varpro_polish_many` batches them).
    on_arc : bool
        For a space whose direction is a place on the admissible arc (Ogden-2 with Prony
        terms): polish the places themselves. By default such a space is polished in
        angles (``space.angles()``), the result converted back (docs/theory.md §11).

    Returns
    -------
    (z, x, err, n)
        The search vector, the full parameter vector, its error, and the parameter sets
        evaluated; never a higher error than at ``z0`` (then ``z0`` itself).

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> from vhfit.calibration._bounds import search_bounds
    >>> from vhfit.calibration._space import Problem, SeparableSpace
    >>> m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    >>> eps = np.linspace(-0.05, -0.5, 10)
    >>> true = dict(C10=0.2, C01=0.1, G1=1.0, tau1=0.01)
    >>> cs = [vhfit.Curve(strain=eps, stress=m.stress(true, strain=eps, strain_rate=r,
    ...       measure="engineering"), strain_rate=r) for r in (-1.0, -100.0)]
    >>> tau_b, auto = search_bounds(m, cs, "free", 3, 1, "auto")
    >>> space = SeparableSpace(Problem(m, cs, tau_b, auto, 1e-6))
    >>> z, x, err, n = varpro_polish(space, np.array([0.5, -1.0]))
    >>> bool(err < 1e-8), np.round(x, 6).tolist()
    (True, [0.2, 0.1, 1.0, 0.01])
    """
    from scipy.optimize import least_squares  # ~0.3 s to import: not at start

    view = space.angles()
    if view is not space and not on_arc:  # in angles, the result in space's coordinates
        za = space.to_angles(z0)[0]
        z, x, e, n = varpro_polish(view, za, max_nfev, tol, residuals)
        return _back(space, z0, za, z), x, e, n
    prob = space.prob
    b = np.asarray(space.bounds(), dtype=np.float64).reshape(-1, 2)
    lo, hi = b[:, 0], b[:, 1]
    z0 = np.clip(np.asarray(z0, dtype=np.float64), lo, hi)
    free = lo < hi
    count = [0]

    def full(z):
        out = z0.copy()
        out[free] = z
        return out

    def resid(Z):
        count[0] += len(Z)
        return space.fit_of(Z)[1] if residuals is None else residuals(Z)

    last = [None, None]  # the last point fun evaluated, and its residuals

    def fun(z):
        r = resid(full(z)[None, :])[0]
        last[:] = z.copy(), r
        return r

    def jac(z):
        return forward_jacobian(lambda Z: resid(np.array([full(v) for v in Z])), z,
                                hi[free], last)

    x0 = space.to_params(z0)
    e0 = float(prob.errors(x0[None, :])[0])
    if not np.isfinite(e0) or not free.any():
        return z0, x0, e0, count[0]
    try:
        with np.errstate(all="ignore"):
            res = least_squares(fun, z0[free], jac=jac, bounds=(lo[free], hi[free]),
                                method="trf", x_scale="jac", max_nfev=max_nfev, xtol=tol,
                                ftol=tol, gtol=tol)
    except (ValueError, np.linalg.LinAlgError):
        return z0, x0, e0, count[0]
    z1 = full(res.x)
    x1 = space.to_params(z1)
    e1 = float(prob.errors(x1[None, :])[0])
    if (np.isfinite(e1) and e1 < e0 and g_inf_ok(prob, x1)
            and bool(prob.admissible(x1[None, :])[0])):
        return z1, x1, e1, count[0]
    return z0, x0, e0, count[0]


def _back(space, z0: np.ndarray, za: np.ndarray, z: np.ndarray) -> np.ndarray:
    """The end ``z`` of a polish made in angles from ``za`` (``z0`` in ``space``'s own
    coordinates) as a search vector of ``space``: ``z0`` itself where it did not move."""
    return np.asarray(z0, dtype=np.float64) if np.array_equal(z, za) else space.from_angles(z)[0]


class _Batches:
    """Residual requests of several polishes, answered together: one thread per polish,
    one runs at a time (each holds the lock except while it waits for an answer), and
    the caller's thread evaluates the requests once every live polish has made one."""

    def __init__(self, space, n: int):
        self.space = space
        self.cv = threading.Condition()
        self.live = n
        self.asked: dict[int, np.ndarray] = {}
        self.answers: dict[int, np.ndarray] = {}
        self.aborted = False

    def request(self, i: int, Z: np.ndarray) -> np.ndarray:  # a polish's thread, locked
        self.asked[i] = Z
        self.cv.notify_all()
        self.cv.wait_for(lambda: i in self.answers or self.aborted)
        if self.aborted:
            raise _Aborted
        return self.answers.pop(i)

    def leave(self) -> None:  # a polish's thread, locked
        self.live -= 1
        self.cv.notify_all()

    def serve(self) -> None:  # the caller's thread
        with self.cv:
            while True:
                self.cv.wait_for(lambda: self.live == 0 or len(self.asked) == self.live)
                if self.live == 0:
                    return
                order = sorted(self.asked)
                R = self.space.fit_of(np.vstack([self.asked[i] for i in order]))[1]
                k = 0
                for i in order:
                    n = len(self.asked[i])
                    self.answers[i] = R[k:k + n]
                    k += n
                self.asked.clear()
                self.cv.notify_all()


class _Aborted(Exception):
    """The caller stopped waiting (Ctrl-C): the polishes end."""


def varpro_polish_many(space, Z0: np.ndarray, max_nfev: int = VARPRO_NFEV,
                       tol: float = ROUNDING_TOL, on_arc: bool = False) -> list:
    """``[varpro_polish(space, z, max_nfev, tol) for z in Z0]``, the same results, with the
    residuals of all the polishes evaluated as one batch per step (a polish's
    evaluations are rows of their own: the batch does not change them).

    Several short polishes (the other basins' scouts) spend most of their time in the
    per-call cost of small evaluations; here each runs in a thread of its own, one at a
    time, and the caller's thread evaluates what they ask once all of them wait.
    """
    Z0 = np.atleast_2d(np.asarray(Z0, dtype=np.float64))
    if len(Z0) < 2:
        return [varpro_polish(space, z, max_nfev, tol, on_arc=on_arc) for z in Z0]
    view = space.angles()
    if view is not space and not on_arc:  # (as varpro_polish: in angles)
        A = space.to_angles(Z0)
        out = varpro_polish_many(view, A, max_nfev, tol)
        return [(_back(space, z0, za, z), x, e, n) for z0, za, (z, x, e, n) in zip(Z0, A, out)]
    batches = _Batches(space, len(Z0))
    out: list = [None] * len(Z0)

    def run(i: int) -> None:
        with batches.cv:
            try:
                out[i] = varpro_polish(space, Z0[i], max_nfev, tol,
                                       residuals=lambda Z: batches.request(i, Z),
                                       on_arc=on_arc)
            except BaseException as exc:  # noqa: BLE001 - handed to the caller
                out[i] = exc
            finally:
                batches.leave()

    threads = [threading.Thread(target=run, args=(i,), daemon=True) for i in range(len(Z0))]
    for t in threads:
        t.start()
    try:
        batches.serve()
    except BaseException:
        with batches.cv:
            batches.aborted = True
            batches.cv.notify_all()
        raise
    for t in threads:
        t.join()
    for r in out:
        if isinstance(r, BaseException):
            raise r
    return out
