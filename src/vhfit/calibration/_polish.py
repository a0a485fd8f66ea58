"""The polish: bounded least squares on all parameters after the global search."""

from __future__ import annotations

import numpy as np

from vhfit.calibration._space import Problem

__all__ = ["polish", "g_inf_ok", "forward_jacobian", "ROUNDING_TOL"]

#: Tolerances (xtol, ftol, gtol) of a polish run to rounding.
ROUNDING_TOL = 1e-15


def polish(prob: Problem, x0: np.ndarray, max_nfev: int = 200):
    """Bounded least squares on all parameters (τ in log10); never raises the error.

    Bounds the user gave hold exactly (the law's constants and the G_i); the automatic
    search ranges bound a nonlinear constant only on the side the result is within, a
    modulus not at all (the law's limits only: the admissible set keeps the law stable;
    :func:`vhfit.calibration._bounds.enforced_bounds` is the resulting box).
    """
    model, lay = prob.model, prob.model.layout
    lo = np.empty(model.n_params)
    hi = np.empty(model.n_params)
    for k, name in enumerate(prob.hm.param_names):
        plo, phi = prob.hm.bounds[k]
        blo, bhi = prob.bounds[name]
        if name in prob.user_bounds:
            lo[k], hi[k] = max(plo, blo), min(phi, bhi)
            continue
        if prob.hm.units[k] == "MPa":  # a modulus: the law's limits (enforced_bounds)
            lo[k], hi[k] = plo, phi
            continue
        lo[k], hi[k] = max(plo, min(blo, x0[k])), max(bhi, x0[k])
    lo[lay.amplitudes], hi[lay.amplitudes] = 0.0, np.inf
    for i in range(lay.n_terms):
        if lay.amplitude_name(i) in prob.user_bounds:
            blo, bhi = prob.bounds[lay.amplitude_name(i)]
            lo[lay.amplitude_index(i)], hi[lay.amplitude_index(i)] = max(0.0, blo), bhi
    lo[lay.times] = prob.tau_b[:, 0]
    hi[lay.times] = prob.tau_b[:, 1]
    fixed = lo >= hi
    free = ~fixed

    def expand(z):
        x = np.array(z0_full, dtype=np.float64, copy=True)
        x[free] = z
        return lay.from_log(x)

    z0_full = lay.to_log(x0)
    z0_full = np.clip(z0_full, lo, np.where(fixed, lo, hi))
    counter = {"n": 0}

    def resid_batch(Z):
        X = np.array([expand(z) for z in Z])
        counter["n"] += len(Z)
        return prob.residuals(X)

    last = [None, None]  # the last point fun evaluated, and its residuals

    def fun(z):
        r = resid_batch(z[None, :])[0]
        last[:] = z.copy(), r
        return r

    def jac(z):
        return forward_jacobian(resid_batch, z, hi[free], last)

    e0 = float(np.sqrt(np.sum(fun(z0_full[free]) ** 2)))
    if not np.isfinite(e0) or not free.any():
        return x0, e0, counter["n"]
    try:
        with np.errstate(all="ignore"):
            from scipy.optimize import least_squares

            res = least_squares(
                fun, z0_full[free], jac=jac, bounds=(lo[free], hi[free]), method="trf",
                x_scale="jac", max_nfev=max_nfev, xtol=ROUNDING_TOL, ftol=ROUNDING_TOL,
                gtol=ROUNDING_TOL,
            )
        x1 = expand(res.x)
        e1 = float(np.sqrt(2 * res.cost))
    except (ValueError, np.linalg.LinAlgError):
        return x0, e0, counter["n"]
    if np.isfinite(e1) and e1 < e0 and g_inf_ok(prob, x1) and prob.admissible(x1)[0]:
        return x1, e1, counter["n"]
    return x0, e0, counter["n"]


def forward_jacobian(resid, z: np.ndarray, hi: np.ndarray, last: list) -> np.ndarray:
    """Forward differences of the residuals ``resid`` (a batch of points -> rows) at
    ``z``, all steps in one batch; backwards where forwards would pass ``hi``. ``last``
    ([point, residuals] of the polish's last evaluation): least squares asks for the
    Jacobian where it has just evaluated, and those residuals are reused."""
    h = 1e-7 * np.maximum(np.abs(z), 1e-3)
    steps = z + np.diag(h)
    over = steps > hi
    steps[over] = (z - np.diag(h))[over]
    if last[0] is not None and np.array_equal(last[0], z):
        r0, R = last[1], resid(steps)
    else:
        R = resid(np.vstack([z, steps]))
        r0, R = R[0], R[1:]
    sgn = np.where(over.any(axis=1), -1.0, 1.0)
    return ((R - r0) / (h * sgn)[:, None]).T


def g_inf_ok(prob: Problem, x: np.ndarray) -> bool:
    if prob.g_inf_min <= 0 or prob.model.n_prony == 0:
        return True
    E = prob.model.long_term_modulus(x)
    G = prob.model.split(x)[1]
    return E > 0 and E / (E + G.sum()) >= prob.g_inf_min * (1 - 1e-9)
