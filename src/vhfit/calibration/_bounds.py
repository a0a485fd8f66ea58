"""Search bounds: τ ranges from the strain rates (Eq. 22) and moduli that can reach the data."""

from __future__ import annotations

import numpy as np

from vhfit.model import ViscoHyperelastic

__all__ = ["auto_bounds", "search_bounds"]

def rates(curves) -> np.ndarray:
    r = np.array([abs(float(getattr(c, "strain_rate", np.nan) or np.nan)) for c in curves])
    if not np.all(np.isfinite(r) & (r > 0)):
        raise ValueError(
            "every curve needs a nominal strain rate to set the τ bounds (Eq. 22): "
            "give strain_rate= to the Curve, or bounds for every tau"
        )
    return r


def tau_bounds_log10(rates, n, strategy, below, above) -> np.ndarray:
    """Per-term log10 τ bounds (Eq. 22 and the strategy) from vhfit.optimize.tau_bounds."""
    from vhfit.optimize import tau_bounds  # lazy: the optimizer imports scipy.optimize

    b = tau_bounds(rates, n, strategy=strategy, decades_above=above, decades_below=below)
    return np.asarray(getattr(b, "bounds", b), dtype=np.float64).reshape(n, 2)


def auto_bounds(model: ViscoHyperelastic, curves, tau_b=None) -> dict[str, tuple[float, float]]:
    """Upper search limits (docs/theory.md §11): one term alone reaches every target stress.

    For each hyperelastic modulus and each G_i, the smallest value that makes that
    term alone (all others zero; a Prony term at the shortest τ of its bounds
    ``tau_b``, log10 s, where its response is weakest) reach |σ| ≥ |σ_target| at every
    objective point. Lower limits are 0. Dimensionless constants (e.g. Ogden α) get
    their physical bounds, or [-10, 10] if unbounded.
    """
    hm = model.hyperelastic
    lam = np.concatenate([c.history.out_stretch for c in curves])
    y = np.concatenate([np.asarray(c.target_stress, dtype=np.float64) for c in curves])
    meas = np.concatenate([np.full(np.size(c.target_stress), getattr(c, "measure", "true"))
                           for c in curves])
    y_true = np.abs(np.where(meas == "engineering", y * lam, y))
    keep = np.abs(lam - 1) > 1e-9
    lam, y_true = lam[keep], y_true[keep]
    out: dict[str, tuple[float, float]] = {}
    ex = np.array(hm.example, dtype=np.float64)
    for k, name in enumerate(hm.param_names):
        lo_p, hi_p = hm.bounds[k]
        if hm.units[k] == "MPa":
            unit = np.where(np.arange(hm.n_params) == k, 1.0, 0.0)
            if hm.kind == "stretch":  # keep dimensionless constants at their example values
                unit = np.where([u == "MPa" for u in hm.units], unit, ex)
            with np.errstate(all="ignore"):
                s = np.abs(hm.stress(lam, unit))
            ratio = y_true / np.where(s > 0, s, np.nan)
            hi = float(np.nanmax(ratio)) if np.isfinite(ratio).any() else float(np.max(y_true))
            out[name] = (max(0.0, lo_p), hi)
        else:
            out[name] = (lo_p if np.isfinite(lo_p) else -10.0, hi_p if np.isfinite(hi_p) else 10.0)
    # a Prony term alone at the bottom of its τ range, where it responds least
    if model.n_prony and tau_b is not None:
        hyper = np.array([hm.example], dtype=np.float64)
        _, H = model.batch(curves).shape_columns(hyper, 10.0 ** tau_b[None, :, 0])
        yy = np.abs(np.concatenate([np.asarray(c.target_stress, dtype=np.float64)
                                    for c in curves]))
        for i in range(model.n_prony):
            h = np.abs(H[0, i])
            ok = h > 0
            gmax = float(np.max(yy[ok] / h[ok])) if ok.any() else float(np.max(yy))
            out[f"G{i + 1}"] = (0.0, gmax)
    return out


def search_bounds(model: ViscoHyperelastic, curves, tau_strategy, decades_below: float,
                  decades_above: float, bounds) -> tuple[np.ndarray, dict]:
    """Per-term log10 τ bounds (N, 2) and name -> (low, high) for the other parameters.

    ``bounds`` is "auto" or a dict overriding the automatic limits per parameter
    (τ in s).
    """
    n_prony = model.n_prony
    if n_prony > 0:
        tau_b = tau_bounds_log10(rates(curves), n_prony, tau_strategy, decades_below,
                                 decades_above)
    else:
        tau_b = np.zeros((0, 2))
    auto = auto_bounds(model, curves, tau_b)
    if isinstance(bounds, dict):
        for k, v in bounds.items():
            if k.startswith("tau") and k[3:].isdigit() and 1 <= int(k[3:]) <= n_prony:
                lo, hi = map(float, v)
                if not 0 < lo <= hi:
                    raise ValueError(f"bounds[{k!r}] = {v!r}: need 0 < low <= high (s)")
                tau_b[int(k[3:]) - 1] = np.log10([lo, hi])
            elif k in auto:
                lo, hi = map(float, v)
                if not lo <= hi:
                    raise ValueError(f"bounds[{k!r}] = {v!r}: low must be <= high")
                auto[k] = (lo, hi)
            else:
                raise ValueError(
                    f"bounds has unknown parameter {k!r}; parameters are {model.param_names}"
                )
    elif bounds != "auto":
        raise ValueError(f"bounds = {bounds!r}: give 'auto' or a dict name -> (low, high)")
    return np.asarray(tau_b, dtype=np.float64), auto
