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

import numpy as np

from vhfit.calibration._polish import ROUNDING_TOL, forward_jacobian, g_inf_ok

__all__ = ["varpro_polish", "VARPRO_NFEV"]

#: Residual evaluations of one variable-projection polish (its Jacobian rows included).
VARPRO_NFEV = 200


def varpro_polish(space, z0: np.ndarray, max_nfev: int = VARPRO_NFEV,
                  tol: float = ROUNDING_TOL):
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
        return space.fit_of(Z)[1]

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
