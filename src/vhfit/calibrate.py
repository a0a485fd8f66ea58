"""Calibration: multi-rate curves in, a visco-hyperelastic material out.

Two global searches are available:

* ``method="separable"`` (default): for fixed relaxation times and a fixed shape of
  the hyperelastic law, the stress of the corrected Eq. 19 is linear in the long-term
  modulus E∞ and the Prony moduli G_i (SPEC §4). Differential evolution searches only
  the nonlinear parameters (log10 τ_i and the law's shape); every evaluation solves
  the linear ones exactly by non-negative least squares (variable projection).
* ``method="full"``: the paper's all-parameter differential evolution.

Either is followed by a bounded least-squares polish of all parameters (τ in log10)
that can only keep or lower the error, then by a model-order, stability and
uncertainty report.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from datetime import datetime, timezone

import numpy as np

from vhfit._io import atomic_write, dumps
from vhfit.model import ViscoHyperelastic
from vhfit.objective import Objective
from vhfit.stability import StabilityReport, drucker
from vhfit.viscoelastic import prony_g

__all__ = ["calibrate", "Calibration", "auto_bounds"]

DEFAULT_TAU_STRATEGY = "free"
DEFAULT_DECADES_BELOW = 3  # one decade of margin below Eq. 22: real τ_1 can sit just under it
DEFAULT_DECADES_ABOVE = 1
_DEFAULT_TOL = 1e-6


RESULTS_FORMAT = "vhfit-results-1"


def _versions() -> dict[str, str]:
    import platform

    import numba
    import scipy

    from vhfit import __version__

    return {
        "vhfit": __version__,
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "numba": numba.__version__,
        "python": platform.python_version(),
        "platform": platform.platform(),
    }


def _curve_info(c) -> dict:
    return {
        "name": str(getattr(c, "name", "")),
        "strain_rate": float(getattr(c, "strain_rate", float("nan"))),
        "measure": getattr(c, "measure", "true"),
        "n_points": int(np.size(c.target_stress)),
        "source": getattr(c, "source", None),
    }


class CalibrationWarning(UserWarning):
    """Something about a calibration the user should know (floor active, unidentifiable τ…)."""


# ----------------------------------------------------------------------- helpers
def _as_curves(curves) -> list:
    """A list of curves from Curve objects, file paths (read with read_csv), or a mix."""
    if hasattr(curves, "history") or isinstance(curves, (str, os.PathLike)):
        curves = [curves]
    try:
        items = list(curves)
    except TypeError:
        raise ValueError(
            f"curves must be Curve objects or CSV paths, got {type(curves).__name__}"
        ) from None
    out = []
    for i, c in enumerate(items):
        if isinstance(c, (str, os.PathLike)):
            from vhfit.data import read_csv

            out += read_csv(c)
        elif hasattr(c, "history") and hasattr(c, "target_stress"):
            out.append(c)
        else:
            raise ValueError(
                f"curves[{i}] is a {type(c).__name__}: give vhfit.Curve objects "
                "(vhfit.Curve(strain=..., stress=..., strain_rate=...)) or CSV paths"
            )
    if not out:
        raise ValueError("calibrate needs at least one curve")
    return out


def _rates(curves) -> np.ndarray:
    r = np.array([abs(float(getattr(c, "strain_rate", np.nan) or np.nan)) for c in curves])
    if not np.all(np.isfinite(r) & (r > 0)):
        raise ValueError(
            "every curve needs a nominal strain rate to set the τ bounds (Eq. 22): "
            "give strain_rate= to the Curve, or bounds for every tau"
        )
    return r


def _tau_bounds(rates, n, strategy, below, above) -> np.ndarray:
    """Per-term log10 τ bounds (Eq. 22 and the strategy) from vhfit.optimize.tau_bounds."""
    from vhfit.optimize import tau_bounds  # lazy: the optimizer imports scipy.optimize

    b = tau_bounds(rates, n, strategy=strategy, decades_above=above, decades_below=below)
    return np.asarray(getattr(b, "bounds", b), dtype=np.float64).reshape(n, 2)


def auto_bounds(model: ViscoHyperelastic, curves, tau_b=None) -> dict[str, tuple[float, float]]:
    """Upper limits of SPEC §5: one term alone puts every model stress over the targets.

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


# ------------------------------------------------------------------- the result
@dataclass
class Calibration:
    """Result of :func:`calibrate`.

    Attributes
    ----------
    model : ViscoHyperelastic
        The calibrated model (after pruning of negligible Prony terms).
    params : dict
        Name -> value (moduli in MPa, τ in s). Hyperelastic constants are long-term.
    rmsape : float
        Eq. 20 in percent on the objective points.
    per_curve_rmsape : list of float
        Eq. 20 of each curve alone, percent.
    nit, nfev : int
        Generations and model evaluations of the global search (plus polish evaluations).
    wall_time : float
        Seconds.
    stop_reason : str
        Why the global search stopped ("converged", "target reached", "max_time",
        "maxiter", "interrupted", ...).
    g, g_inf : list of float, float
        Dimensionless Prony weights (SPEC §3).
    bounds : dict
        Search bounds used (τ bounds in s).
    history : dict
        Per-generation best and mean error and wall time.
    confidence : dict
        Name -> (low, high) 95 % interval from the Jacobian at the optimum.
    stability : StabilityReport
    order_scan : list of dict
        With ``n_prony="auto"``: error against N.
    warnings : list of str
    """

    model: ViscoHyperelastic
    params: dict
    rmsape: float
    per_curve_rmsape: list
    nit: int
    nfev: int
    wall_time: float
    stop_reason: str
    g: list = field(default_factory=list)
    g_inf: float = 1.0
    bounds: dict = field(default_factory=dict)
    history: dict = field(default_factory=dict)
    confidence: dict = field(default_factory=dict)
    stability: StabilityReport | None = None
    order_scan: list = field(default_factory=list)
    warnings: list = field(default_factory=list)
    options: dict = field(default_factory=dict)
    curve_names: list = field(default_factory=list)

    @property
    def x(self) -> np.ndarray:
        """Parameters as an array in ``model.param_names`` order."""
        return self.model.as_array(self.params)

    @property
    def n_prony(self) -> int:
        return self.model.n_prony

    def predict(self, history=None, **kwargs) -> np.ndarray:
        """Stress of the calibrated material along a history or curve (see ``model.stress``)."""
        if history is not None and not kwargs and hasattr(history, "target_stress"):
            kwargs["measure"] = getattr(history, "measure", "true")
        return self.model.stress(self.params, history, **kwargs)

    def summary(self) -> str:
        """A readable table of constants, intervals, errors and checks."""
        units = dict(zip(self.model.param_names, self.model.units))
        lines = [
            f"vhfit calibration: {self.model.hyperelastic.name} + {self.n_prony} Prony term(s)",
            f"RMSAPE {self.rmsape:.4g} %   generations {self.nit}   evaluations {self.nfev}   "
            f"wall {self.wall_time:.2f} s   stop: {self.stop_reason}",
            "",
            f"{'parameter':<10}{'value':>14}  {'unit':<5}{'95 % interval':>30}",
        ]
        for name, v in self.params.items():
            ci = self.confidence.get(name)
            cis = f"[{ci[0]:.4g}, {ci[1]:.4g}]" if ci else ""
            lines.append(f"{name:<10}{v:>14.6g}  {units[name]:<5}{cis:>30}")
        if self.n_prony:
            lines.append("")
            lines.append("g_i = " + ", ".join(f"{g:.6g}" for g in self.g)
                         + f"   g_inf = {self.g_inf:.6g}")
        lines.append("")
        lines.append("per-curve RMSAPE:")
        for name, e in zip(self.curve_names, self.per_curve_rmsape):
            lines.append(f"  {name:<30} {e:.4g} %")
        if self.order_scan:
            lines.append("")
            lines.append("error against number of Prony terms:")
            for row in self.order_scan:
                mark = "  <- chosen" if row["n_prony"] == self.options.get("n_prony_chosen") else ""
                lines.append(
                    f"  N = {row['n_prony']}: RMSAPE {row['rmsape']:.4g} %  "
                    f"(effective N = {row['effective_n']}){mark}"
                )
        if self.stability is not None:
            lines.append("")
            lines.append("stability: " + self.stability.describe())
        for w in self.warnings:
            lines.append("warning: " + w)
        return "\n".join(lines)

    def to_dict(self) -> dict:
        """JSON-ready dict with everything needed to reproduce and export the result."""
        return {
            "hyperelastic": self.model.hyperelastic.name,
            "n_prony": self.n_prony,
            "param_names": list(self.model.param_names),
            "units": list(self.model.units),
            "params": {k: float(v) for k, v in self.params.items()},
            "g": [float(v) for v in self.g],
            "g_inf": float(self.g_inf),
            "rmsape": float(self.rmsape),
            "per_curve_rmsape": [float(v) for v in self.per_curve_rmsape],
            "curve_names": list(self.curve_names),
            "nit": int(self.nit),
            "nfev": int(self.nfev),
            "wall_time": float(self.wall_time),
            "stop_reason": self.stop_reason,
            "bounds": {k: [float(a), float(b)] for k, (a, b) in self.bounds.items()},
            "confidence": {k: [float(a), float(b)] for k, (a, b) in self.confidence.items()},
            "stability": None if self.stability is None else {
                "stable": self.stability.stable,
                "stretch_range": list(self.stability.stretch_range),
                "unstable": {k: [list(i) for i in v] for k, v in self.stability.unstable.items()},
            },
            "order_scan": self.order_scan,
            "warnings": list(self.warnings),
            "options": self.options,
        }

    def save(self, path, *, status: str = "complete", curves: Sequence | None = None,
             extra: dict | None = None) -> None:
        """Write the results file (JSON) atomically: :meth:`to_dict` plus its context.

        Parameters
        ----------
        path : path-like
            The file to write (``results.json`` of ``vhfit fit``).
        status : {"complete", "interrupted"}
            Whether the search ran to its end.
        curves : sequence of Curve, optional
            The fitted curves, described by name, rate, measure, size and source.
        extra : dict, optional
            Further top-level entries (the command line adds its inputs and options).
        """
        res = self.to_dict()
        res.update({
            "format": RESULTS_FORMAT,
            "status": status,
            "interrupted": status == "interrupted",
            "curves": [_curve_info(c) for c in (curves or [])],
            "versions": _versions(),
            "timestamp": datetime.now(timezone.utc).isoformat(timespec="seconds"),
            "history": self.history,
        })
        res.update(extra or {})
        atomic_write(path, dumps(res, indent=2) + "\n")

    @classmethod
    def load(cls, path) -> Calibration:
        """Read a results file written by :meth:`save` (or by ``vhfit fit``).

        The model and constants, errors, counts, bounds, intervals, warnings and
        history come back; the stability report is recomputed from the constants.
        """
        with open(path, encoding="utf-8") as f:
            res = json.load(f)
        if not isinstance(res, dict) or "params" not in res or "hyperelastic" not in res:
            raise ValueError(f"{path}: not a vhfit results file (no 'hyperelastic' and "
                             "'params'); give the results.json written by vhfit")
        model = ViscoHyperelastic(res["hyperelastic"], int(res.get("n_prony", 0)))
        x = model.check(res["params"])
        lo_hi = res.get("options", {}).get("stability_range")
        stab = drucker(model.hyperelastic, x[: model.hyperelastic.n_params],
                       tuple(lo_hi) if lo_hi else (0.2, 5.0))
        return cls(
            model=model, params=model.as_dict(x), rmsape=float(res["rmsape"]),
            per_curve_rmsape=list(res.get("per_curve_rmsape", [])),
            nit=int(res.get("nit", 0)), nfev=int(res.get("nfev", 0)),
            wall_time=float(res.get("wall_time", 0.0)),
            stop_reason=str(res.get("stop_reason", "")), g=list(res.get("g", [])),
            g_inf=float(res.get("g_inf", 1.0)),
            bounds={k: tuple(v) for k, v in res.get("bounds", {}).items()},
            history=dict(res.get("history", {})),
            confidence={k: tuple(v) for k, v in res.get("confidence", {}).items()},
            stability=stab, order_scan=list(res.get("order_scan", [])),
            warnings=list(res.get("warnings", [])), options=dict(res.get("options", {})),
            curve_names=list(res.get("curve_names", [])),
        )

    def fitted_curves(self, curves: Sequence, points: int = 200) -> list[dict[str, np.ndarray]]:
        """Model stresses along each curve, at its points and on a fine grid.

        Parameters
        ----------
        curves : sequence of Curve
            The curves it was fitted to (each with ``.history`` and ``.measure``).
        points : int
            Size of the fine, uniform-in-time grid along each history.

        Returns
        -------
        list of dict
            Per curve: ``time``, ``strain``, ``stress`` (objective points: data and
            ``model``), and ``fine_time``, ``fine_strain``, ``fine_model``. Stresses are
            in the curve's own measure, MPa.
        """
        out = []
        for c in curves:
            h = c.history
            measure = getattr(c, "measure", "true")
            model = self.model.stress(self.params, h, measure=measure)
            t_fine = np.linspace(0.0, h.duration, int(points))
            fine = self.model.stress(self.params, h.with_outputs(t_fine), measure=measure)
            out.append({
                "time": np.asarray(h.out_time, dtype=np.float64),
                "strain": np.asarray(h.out_strain, dtype=np.float64),
                "stress": np.asarray(c.target_stress, dtype=np.float64),
                "model": np.asarray(model, dtype=np.float64),
                "fine_time": t_fine,
                "fine_strain": h.stretch_at(t_fine) - 1.0,
                "fine_model": np.asarray(fine, dtype=np.float64),
            })
        return out

    def to_json(self, path=None, **kw) -> str:
        """Serialise :meth:`to_dict`; write it atomically to ``path`` if given."""
        text = dumps(self.to_dict(), indent=2, **kw)
        if path is not None:
            atomic_write(path, text)
        return text


# ------------------------------------------------------------------ checkpoints
def _fit_key(prob, method, seed, popsize, tol, target, de_options) -> str:
    h = hashlib.sha256()
    for a in (prob.y, prob.scale, prob.batch.sample_stretch, prob.batch.step, prob.tau_b):
        h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
    h.update(repr((prob.model.hyperelastic.name, prob.model.n_prony, method, seed, popsize,
                   tol, target, sorted((de_options or {}).items()),
                   sorted(prob.bounds.items()))).encode())
    return h.hexdigest()


def _snapshot(solver, history, elapsed) -> dict:
    """The search state at a generation boundary (all a bit-identical resume needs)."""
    return {
        "format": "vhfit-checkpoint-1",
        "population": solver.population.tolist(),
        "energies": [float(e) if np.isfinite(e) else "inf" for e in solver.population_energies],
        "rng": solver.random_number_generator.bit_generator.state,
        # SciPy shuffles this array in place to pick donors: it is state too
        "index": solver._random_population_index.tolist(),
        "nfev": int(solver._nfev),
        "history": {k: list(v) for k, v in history.items()},
        "elapsed": elapsed,
    }


def _save_checkpoint(path, key, snap: dict) -> None:
    atomic_write(path, dumps({**snap, "key": key}))


def _load_checkpoint(path, key, solver, history) -> tuple[int, float, str | None]:
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, ValueError) as exc:
        raise ValueError(
            f"checkpoint {path} cannot be read ({exc}); delete it to start afresh"
        ) from None
    if data.get("format") != "vhfit-checkpoint-1" or data.get("key") != key:
        raise ValueError(
            f"checkpoint {path} belongs to a different fit (data, model, seed or options "
            "differ); delete it or drop --resume"
        )
    solver.population = np.array(data["population"], dtype=np.float64)
    solver.population_energies = np.array(
        [np.inf if e == "inf" else e for e in data["energies"]], dtype=np.float64
    )
    solver.random_number_generator.bit_generator.state = data["rng"]
    solver._nfev = int(data["nfev"])
    solver._random_population_index = np.array(data["index"], dtype=np.int64)
    for k in history:
        history[k][:] = data["history"][k]
    return len(history["nit"]), float(data["elapsed"]), data.get("done")


# ------------------------------------------------------------- the search space
class _Problem:
    """Model, targets and the two parameterisations of the search."""

    def __init__(self, model: ViscoHyperelastic, curves, tau_b, bounds, g_inf_min,
                 objective="rmsape"):
        self.model = model
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
        hm = model.hyperelastic
        self.hm = hm
        self.amp = [k for k, u in enumerate(hm.units) if u == "MPa"]
        self.other = [k for k, u in enumerate(hm.units) if u != "MPa"]
        lo_amp = [bounds[hm.param_names[k]][0] for k in self.amp]
        # shape of the law: a fraction between two non-negative moduli, or the moduli
        # themselves (redundant scale) when there are more or they may be negative
        self.beta = len(self.amp) == 2 and min(lo_amp) >= 0
        self.n_fixed = sum(1 for lo, hi in tau_b if lo == hi)
        self.free_tau = [i for i, (lo, hi) in enumerate(tau_b) if lo < hi]
        self.nfev = 0  # individuals evaluated by the global search

    # ---- separable: x = [shape..., log10 τ (free ones)]
    def sep_bounds(self) -> list[tuple[float, float]]:
        hm, b = self.hm, []
        if self.beta:
            b.append((0.0, 1.0))
        elif len(self.amp) > 1:
            b += [self.bounds[hm.param_names[k]] for k in self.amp]
        b += [self.bounds[hm.param_names[k]] for k in self.other]
        b += [tuple(self.tau_b[i]) for i in self.free_tau]
        return b

    def sep_decode(self, Z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Shape constants (P, n_h), scale-free, and τ (P, N) from search vectors."""
        P = Z.shape[0]
        hyper = np.zeros((P, self.hm.n_params))
        j = 0
        if self.beta:
            hyper[:, self.amp[0]] = 1.0 - Z[:, 0]
            hyper[:, self.amp[1]] = Z[:, 0]
            j = 1
        elif len(self.amp) > 1:
            hyper[:, self.amp] = Z[:, : len(self.amp)]
            j = len(self.amp)
        else:
            hyper[:, self.amp] = 1.0
        for k in self.other:
            hyper[:, k] = Z[:, j]
            j += 1
        logtau = np.tile(self.tau_b[:, 0], (P, 1))
        logtau[:, self.free_tau] = Z[:, j:]
        return hyper, 10.0**logtau

    def solve_linear(self, hyper, tau):
        """NNLS for (E∞, G_i) of every individual; returns amplitudes (P, 1+N), errors (P,)."""
        base, H = self.batch.shape_columns(hyper, tau)
        P, N = tau.shape
        amps = np.zeros((P, 1 + N))
        err = np.full(P, np.inf)
        from scipy.optimize import nnls  # scipy.optimize costs ~0.3 s to import: not at start

        ys = self.y * self.scale
        kappa = self.g_inf_min / (1.0 - self.g_inf_min) if self.g_inf_min > 0 else 0.0
        for p in range(P):
            A = np.column_stack([base[p]] + [H[p, i] for i in range(N)]) * self.scale[:, None]
            if not np.all(np.isfinite(A)):
                continue
            a, rn = nnls(A, ys)
            if kappa > 0 and a[0] < kappa * a[1:].sum():
                # the g∞ floor is active: E∞ = κ ΣG, a convex problem in G alone
                Ak = A[:, 1:] + kappa * A[:, :1]
                g, rn = nnls(Ak, ys)
                a = np.concatenate([[kappa * g.sum()], g])
            amps[p] = a
            err[p] = rn
        return amps, err

    def sep_errors(self, Z: np.ndarray) -> np.ndarray:
        """Objective of separable search vectors Z (P, d)."""
        hyper, tau = self.sep_decode(Z)
        return self.solve_linear(hyper, tau)[1]

    def full_errors(self, Z: np.ndarray) -> np.ndarray:
        """Objective of full search vectors Z (P, d) (τ in log10)."""
        return self.errors(self.full_to_params(Z, self.hm.n_params))

    def make_objective(self, method: str, mapper=None, chunks: int = 1):
        """The DE objective, vectorised (SciPy passes (d, S)); a map spreads the chunks."""
        errors = self.sep_errors if method == "separable" else self.full_errors

        def objective(Zt: np.ndarray) -> np.ndarray:
            Z = np.atleast_2d(Zt.T) if Zt.ndim > 1 else Zt[None, :]
            self.nfev += Z.shape[0]
            if mapper is None:
                return errors(Z)
            parts = np.array_split(Z, min(chunks, Z.shape[0]))
            out = list(mapper(_chunk_errors, [(self, method, z) for z in parts]))
            return np.concatenate(out)

        return objective

    def sep_to_params(self, z: np.ndarray) -> np.ndarray:
        hyper, tau = self.sep_decode(z[None, :])
        amps, _ = self.solve_linear(hyper, tau)
        return self.assemble(hyper[0], amps[0, 0], amps[0, 1:], tau[0])

    def assemble(self, shape, E_inf, G, tau) -> np.ndarray:
        """Full parameter vector from a law's shape, its E∞, and the Prony terms."""
        hm = self.hm
        shape = np.array(shape, dtype=np.float64)
        with np.errstate(all="ignore"):
            E_shape = 3.0 * float(hm.initial_shear_modulus(shape))
        if E_inf <= 0 or not np.isfinite(E_shape) or E_shape <= 0:
            # no long-term stiffness at all: keep the shape at a vanishing scale
            E_inf = max(E_inf, 1e-12 * max(1.0, float(np.sum(G))))
        shape[self.amp] *= E_inf / E_shape
        x = np.empty(self.model.n_params)
        nh = hm.n_params
        x[:nh] = shape
        x[nh::2] = G
        x[nh + 1::2] = tau
        return x

    # ---- full: x = [hyper constants, (G_i, log10 τ_i)...]
    def full_bounds(self) -> list[tuple[float, float]]:
        b = [self.bounds[n] for n in self.hm.param_names]
        for i in range(self.model.n_prony):
            b.append(self.bounds[f"G{i + 1}"])
            b.append(tuple(self.tau_b[i]))
        return b

    @staticmethod
    def full_to_params(Z: np.ndarray, nh: int) -> np.ndarray:
        X = np.array(Z, dtype=np.float64, copy=True)
        X[..., nh + 1::2] = 10.0 ** X[..., nh + 1::2]
        return X

    def errors(self, X: np.ndarray) -> np.ndarray:
        """RMSAPE (percent) of parameter sets X (P, n_params); inf where invalid."""
        S = self.batch(np.atleast_2d(X))
        r = (S - self.y) * self.scale
        with np.errstate(all="ignore", over="ignore"):
            e = np.sqrt(np.sum(r * r, axis=1))
        e[~np.isfinite(e)] = np.inf
        return e


def _chunk_errors(args) -> np.ndarray:
    prob, method, Z = args
    return prob.sep_errors(Z) if method == "separable" else prob.full_errors(Z)


def _single_thread_worker() -> None:
    # two processes x two numba threads would oversubscribe two cores
    try:
        import numba

        numba.set_num_threads(1)
    except (ImportError, ValueError):
        pass


@contextlib.contextmanager
def _mapper(workers):
    """(map, n_chunks) for ``workers``: 1 -> in process; int -> process pool; map-like."""
    if callable(workers):
        yield workers, 2 * (os.cpu_count() or 2)
    elif isinstance(workers, (int, np.integer)) and not isinstance(workers, bool):
        n = int(workers)
        if n == -1:
            n = os.cpu_count() or 1
        if n < 1:
            raise ValueError(f"workers = {workers!r}: give -1, a whole number >= 1, or a map")
        if n == 1:
            yield None, 1
        else:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            # spawn, not fork: forking after numba's OpenMP threads started is unsafe
            ctx = multiprocessing.get_context("spawn")
            with ProcessPoolExecutor(n, mp_context=ctx, initializer=_single_thread_worker) as ex:
                yield ex.map, n
    else:
        raise ValueError(
            f"workers = {workers!r}: give an int (processes) or a map-like callable"
        )


# ---------------------------------------------------------------------- polish
def _polish(prob: _Problem, x0: np.ndarray, max_nfev: int = 200):
    """Bounded least squares on all parameters (τ in log10); never raises the error."""
    model, nh = prob.model, prob.hm.n_params
    lo = np.empty(model.n_params)
    hi = np.empty(model.n_params)
    for k, name in enumerate(prob.hm.param_names):
        plo, phi = prob.hm.bounds[k]
        blo, bhi = prob.bounds[name]
        lo[k] = max(plo, min(blo, x0[k]))
        hi[k] = phi if prob.hm.units[k] == "MPa" else max(bhi, x0[k])
    lo[nh::2], hi[nh::2] = 0.0, np.inf
    lo[nh + 1::2] = prob.tau_b[:, 0]
    hi[nh + 1::2] = prob.tau_b[:, 1]
    fixed = lo >= hi
    free = ~fixed

    def expand(z):
        x = np.array(z0_full, dtype=np.float64, copy=True)
        x[free] = z
        x[nh + 1::2] = 10.0 ** x[nh + 1::2]
        return x

    z0_full = x0.copy()
    z0_full[nh + 1::2] = np.log10(x0[nh + 1::2])
    z0_full = np.clip(z0_full, lo, np.where(fixed, lo, hi))
    counter = {"n": 0}

    def resid_batch(Z):
        X = np.array([expand(z) for z in Z])
        counter["n"] += len(Z)
        S = prob.batch(X)
        return (S - prob.y) * prob.scale

    def fun(z):
        return resid_batch(z[None, :])[0]

    def jac(z):
        h = 1e-7 * np.maximum(np.abs(z), 1e-3)
        Z = np.vstack([z, z + np.diag(h)])
        # step backwards where forwards would leave the bounds
        over = Z[1:] > hi[free]
        Z[1:][over] = (z - np.diag(h))[over]
        R = resid_batch(Z)
        sgn = np.where(over.any(axis=1), -1.0, 1.0)
        return ((R[1:] - R[0]) / (h * sgn)[:, None]).T

    e0 = float(np.sqrt(np.sum(fun(z0_full[free]) ** 2)))
    if not np.isfinite(e0) or not free.any():
        return x0, e0, counter["n"]
    try:
        with np.errstate(all="ignore"):
            from scipy.optimize import least_squares

            res = least_squares(
                fun, z0_full[free], jac=jac, bounds=(lo[free], hi[free]), method="trf",
                x_scale="jac", max_nfev=max_nfev, xtol=1e-15, ftol=1e-15, gtol=1e-15,
            )
        x1 = expand(res.x)
        e1 = float(np.sqrt(2 * res.cost))
    except (ValueError, np.linalg.LinAlgError):
        return x0, e0, counter["n"]
    if np.isfinite(e1) and e1 < e0 and _g_inf_ok(prob, x1):
        return x1, e1, counter["n"]
    return x0, e0, counter["n"]


def _g_inf_ok(prob: _Problem, x: np.ndarray) -> bool:
    if prob.g_inf_min <= 0 or prob.model.n_prony == 0:
        return True
    E = prob.model.long_term_modulus(x)
    G = prob.model.split(x)[1]
    return E > 0 and E / (E + G.sum()) >= prob.g_inf_min * (1 - 1e-9)


# ----------------------------------------------------------------- uncertainty
def _confidence(prob: _Problem, x: np.ndarray, level: float = 0.95):
    """Intervals from the Jacobian of the weighted residuals (τ intervals via log10 τ)."""
    model, nh = prob.model, prob.hm.n_params
    z = x.copy()
    z[nh + 1::2] = np.log10(x[nh + 1::2])
    n_par = z.size
    h = 1e-6 * np.maximum(np.abs(z), 1e-6)
    Z = np.vstack([z + np.diag(h), z - np.diag(h)])
    X = Z.copy()
    X[:, nh + 1::2] = 10.0 ** X[:, nh + 1::2]
    S = prob.batch(X)
    R = (S - prob.y) * prob.scale
    J = ((R[:n_par] - R[n_par:]) / (2 * h)[:, None]).T
    r0 = (prob.batch(x[None, :])[0] - prob.y) * prob.scale
    n = r0.size
    dof = max(n - n_par, 1)
    s2 = float(r0 @ r0) / dof
    out, unident = {}, []
    if not np.all(np.isfinite(J)):
        return out, unident
    U, sv, Vt = np.linalg.svd(J, full_matrices=False)
    tiny = sv <= sv.max() * 1e-10 if sv.size else np.array([], bool)
    inv = np.where(tiny, 0.0, 1.0 / np.where(tiny, 1.0, sv) ** 2)
    cov = (Vt.T * inv) @ Vt * s2
    from scipy.stats import t as student_t

    tq = float(student_t.ppf(0.5 + level / 2, dof))
    for k, name in enumerate(model.param_names):
        half = tq * math.sqrt(max(cov[k, k], 0.0))
        # a parameter along a (near-)null direction of J cannot be identified
        weak = any(abs(Vt[j, k]) > 0.1 for j in np.flatnonzero(tiny))
        if weak:
            unident.append(name)
        if k >= nh and (k - nh) % 2 == 1:
            with np.errstate(over="ignore"):  # an unidentifiable τ: an interval to inf
                out[name] = (10 ** (z[k] - half), 10 ** (z[k] + half))
        else:
            out[name] = (x[k] - half, x[k] + half)
    return out, unident


def _time_window_warnings(model, x, curves) -> list[str]:
    nh = model.hyperelastic.n_params
    out = []
    durations = [c.history.duration for c in curves]
    firsts = []
    for c in curves:
        t = np.asarray(c.history.out_time)
        firsts.append(float(np.min(t[t > 0])) if np.any(t > 0) else c.history.duration)
    for i in range(model.n_prony):
        G, tau = x[nh + 2 * i], x[nh + 2 * i + 1]
        if G <= 0:
            continue
        if tau > 10 * max(durations):
            out.append(
                f"tau{i + 1} = {tau:.3g} s is longer than 10x every curve's duration "
                f"(longest {max(durations):.3g} s): the data cannot tell it from a stiffer "
                "elastic law; add a slower test or a relaxation hold to identify it"
            )
        elif tau < 0.01 * min(firsts):
            out.append(
                f"tau{i + 1} = {tau:.3g} s relaxes before the first objective point of every "
                f"curve (earliest {min(firsts):.3g} s): its modulus is only seen through "
                "G*tau; faster tests are needed to identify it"
            )
    return out


def _slack_warnings(model_stress, curves) -> list[str]:
    """Curves whose data carry ~no stress where the model (``model_stress``, one array
    per curve at its objective points) pushes the other way.

    A thin sheet (VHB, a membrane) goes slack or buckles on unloading: the measured
    stress stays ~0 while the strain returns, but a solid model predicts stress of the
    opposite sign there, a misfit no constants can remove.
    """
    out = []
    for c, s in zip(curves, model_stress):
        d = np.asarray(c.target_stress)
        top = float(np.max(np.abs(d)))
        if not top > 0:
            continue
        sign = float(np.sign(d[np.argmax(np.abs(d))]))
        bad = (np.abs(d) <= 0.02 * top) & (sign * s < -0.05 * top)
        if np.count_nonzero(bad) < 2:
            continue
        t, e = np.asarray(c.target_time)[bad], np.asarray(c.target_strain)[bad]
        worst = float(s[bad][np.argmax(np.abs(s[bad]))])
        out.append(
            f"curve {c.name!r}: at {int(np.count_nonzero(bad))} objective points (time "
            f"{t.min():.4g}-{t.max():.4g} s, strain {e.min():.4g} to {e.max():.4g}) the measured "
            f"stress is ~0 but the model's reaches {worst:.3g} (opposite sign): the specimen "
            "went slack or buckled there, which the model cannot do; leave that part out, "
            f"e.g. curve.trim(time=(None, {t.min():.4g})), or `vhfit fit --trim-time "
            f":{t.min():.4g}` for its file"
        )
    return out


# --------------------------------------------------------------- the front door
def calibrate(
    curves: Sequence,
    hyperelastic="mooney_rivlin",
    n_prony: int | str = 2,
    *,
    tau_strategy: str | Callable = DEFAULT_TAU_STRATEGY,
    bounds: str | dict = "auto",
    objective: str = "rmsape",
    method: str = "separable",
    seed=None,
    workers=1,
    popsize: int | None = None,
    maxiter: int | None = None,
    tol: float = _DEFAULT_TOL,
    target: float = 1e-4,
    stall: tuple[float, int] = (0.02, 2000),
    polish: bool = True,
    g_inf_min: float = 1e-6,
    max_time: float | None = None,
    max_prony: int = 5,
    order_tol: float = 0.05,
    prune_tol: float = 1e-6,
    decades_below: float = DEFAULT_DECADES_BELOW,
    decades_above: float = DEFAULT_DECADES_ABOVE,
    stability_range: tuple[float, float] = (0.2, 5.0),
    uncertainty: bool = True,
    callback: Callable | None = None,
    rtol: float = 1e-6,
    de_options: dict | None = None,
    checkpoint=None,
    checkpoint_every: float = 5.0,
    resume: bool = False,
    check_rates: bool = True,
) -> Calibration:
    """Calibrate a hyperelastic law + Prony series to curves at several strain rates.

    Parameters
    ----------
    curves : Curve, path, or sequence of them
        Measured curves (``.history``, ``.target_stress``, ``.measure``, ``.strain_rate``,
        optional ``.weight`` and ``.name``; see :class:`vhfit.Curve`), or CSV files read
        with :func:`vhfit.read_csv`.
    hyperelastic : str
        Registered hyperelastic model name.
    n_prony : int or "auto"
        Number of Prony terms; "auto" fits N = 1..``max_prony`` and keeps the smallest
        N whose error is within ``order_tol`` (relative) of the best.
    tau_strategy : {"free", "semifree", "fixed"} or callable
        How the τ bounds are cut from the Eq. 22 range (SPEC §5). Default "free".
    bounds : "auto" or dict
        Search bounds; a dict overrides the automatic ones per parameter
        (``{"tau1": (1e-5, 1e-3), "C10": (0, 1)}``; τ bounds in s).
    objective : {"rmsape", "rmse", "relative_l2"} or callable
        Eq. 20 in percent (default) or an alternative of :mod:`vhfit.objective`; per-curve
        and per-point weights of the curves apply.
    method : {"separable", "full"}
        Variable projection over (shape, log τ) with NNLS for the moduli (default), or
        the paper's all-parameter DE.
    seed : int or None
        Seeds the global search; same seed, same result.
    workers : int or map-like callable
        Passed to the DE (only the full method evaluates in parallel this way).
    popsize : int, optional
        Population size, exactly (default 64 separable, initialised by a Sobol
        sequence, and 60 full, the paper's, by Latin hypercube).
    maxiter : int, optional
        Generation cap (default 1000 separable, 100 000 full).
    tol : float
        Relative best–mean gap of the population that ends the search (default 1e-6;
        1e-5, the paper's 0.001 %, for the full method).
    stall : (float, int)
        The paper's first criterion: stop when the mean error improved by less than
        this fraction over this many generations.
    target : float
        RMSAPE (percent) that ends the search at once.
    polish : bool
        Refine all parameters by bounded least squares afterwards.
    g_inf_min : float
        Floor on g∞ (FE solvers reject g∞ = 0); a warning says when it is active.
    max_time : float, optional
        Seconds after which the search stops with the best result so far.
    stability_range : (float, float)
        Stretch range of the Drucker check.
    uncertainty : bool
        Compute 95 % intervals from the Jacobian.
    callback : callable, optional
        Called each generation with a dict (generation, best, mean, elapsed, n_prony, x);
        returning True stops the search.
    rtol : float
        Accuracy of the model evaluation.
    de_options : dict, optional
        Further keywords of the search's solver,
        :class:`vhfit.optimize.DifferentialEvolutionSolver` (SciPy's, plus ``strategy``
        ``"jde"``, ``"shade"`` or ``"lshade"`` and ``repair``), e.g. ``{"strategy":
        "rand1bin", "mutation": 0.8}``. Settings that calibrate owns (population size,
        generation cap, tolerances, seed, polish, callback, workers) are refused with
        the argument to use instead.
    checkpoint : path, optional
        File where the search state is written atomically every ``checkpoint_every``
        seconds (and at the end); with ``resume=True`` the search continues from it and
        reaches the same result as an uninterrupted run with the same seed.
    checkpoint_every : float
        Seconds between checkpoints.
    resume : bool
        Continue from ``checkpoint`` if it exists (it must belong to the same fit).
    check_rates : bool
        Warn, naming the curves, when the data's rise of stress with strain rate exceeds
        what the model can represent (:func:`vhfit.diagnostics.rate_sensitivity`; the
        paper's gelatin argument).

    Returns
    -------
    Calibration

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    >>> true = dict(C10=0.01, C01=0.005, G1=0.5, tau1=0.01)
    >>> eps = np.linspace(-0.05, -0.5, 10)
    >>> curves = [vhfit.Curve(strain=eps, stress=m.stress(true, strain=eps, strain_rate=r,
    ...           measure="engineering"), strain_rate=r) for r in (-1.0, -100.0)]
    >>> cal = vhfit.calibrate(curves, n_prony=1, seed=0)
    >>> cal.rmsape < 1e-3
    True
    """
    t0 = time.perf_counter()
    curves = _as_curves(curves)
    if method not in ("separable", "full"):
        raise ValueError(f"method = {method!r}; choose 'separable' or 'full'")
    if not 0 <= g_inf_min < 1:
        raise ValueError(f"g_inf_min = {g_inf_min!r} must lie in [0, 1)")
    common = dict(
        tau_strategy=tau_strategy, bounds=bounds, objective=objective, method=method, seed=seed,
        workers=workers,
        popsize=popsize, maxiter=maxiter, tol=tol, target=target, stall=stall, polish=polish,
        g_inf_min=g_inf_min, decades_below=decades_below, decades_above=decades_above,
        stability_range=stability_range, uncertainty=uncertainty, callback=callback,
        rtol=rtol, de_options=de_options, prune_tol=prune_tol,
        checkpoint=checkpoint, checkpoint_every=checkpoint_every, resume=resume,
    )
    if isinstance(n_prony, str) and n_prony != "auto":
        raise ValueError(f"n_prony = {n_prony!r}: give a whole number or 'auto'")
    rate_msgs: list[str] = []
    if check_rates:
        from vhfit.diagnostics import rate_sensitivity

        n_check = max_prony if isinstance(n_prony, str) else int(n_prony)
        rate_msgs = rate_sensitivity(curves, hyperelastic, n_check)
    if isinstance(n_prony, str):
        cal = _order_scan(curves, hyperelastic, max_prony, order_tol, max_time, t0, common)
    else:
        cal = _calibrate_n(curves, hyperelastic, int(n_prony), max_time=max_time, t0=t0,
                           **common)
    for m in rate_msgs:  # the data ask for more rate sensitivity than the model has
        warnings.warn(m, CalibrationWarning, stacklevel=2)
    cal.warnings[:0] = rate_msgs
    return cal


def _order_scan(curves, hyperelastic, max_prony, order_tol, max_time, t0, common):
    results = []
    for n in range(1, max_prony + 1):
        left = None if max_time is None else max(0.0, max_time - (time.perf_counter() - t0))
        if left is not None and left <= 0:
            break
        opts = dict(common)
        if opts.get("checkpoint") is not None:  # one checkpoint per N of the scan
            opts["checkpoint"] = f"{opts['checkpoint']}.N{n}"
        results.append(_calibrate_n(curves, hyperelastic, n, max_time=left, t0=time.perf_counter(),
                                    **opts))
        if results[-1].stop_reason == "interrupted":  # Ctrl-C ends the whole scan
            break
    best = min(r.rmsape for r in results)
    chosen = next(r for r in results if r.rmsape <= best * (1 + order_tol) + 1e-12)
    chosen.order_scan = [
        {"n_prony": n + 1, "rmsape": r.rmsape, "effective_n": r.n_prony}
        for n, r in enumerate(results)
    ]
    chosen.options["n_prony"] = "auto"
    chosen.options["n_prony_chosen"] = results.index(chosen) + 1
    chosen.options["order_rule"] = (
        f"smallest N whose RMSAPE is within {order_tol:.0%} of the best over N = 1..{len(results)}"
    )
    chosen.wall_time = time.perf_counter() - t0
    return chosen


def _calibrate_n(curves, hyperelastic, n_prony, *, tau_strategy, bounds, objective, method, seed,
                 workers,
                 popsize, maxiter, tol, target, stall, polish, g_inf_min, decades_below,
                 decades_above,
                 stability_range, uncertainty, callback, rtol, de_options, prune_tol,
                 checkpoint, checkpoint_every, resume, max_time, t0) -> Calibration:
    model = ViscoHyperelastic(hyperelastic, n_prony, rtol=rtol)
    if n_prony > 0:
        tau_b = _tau_bounds(_rates(curves), n_prony, tau_strategy, decades_below, decades_above)
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
    prob = _Problem(model, curves, np.asarray(tau_b, dtype=np.float64), auto, g_inf_min,
                    objective)

    history = {"nit": [], "best": [], "mean": [], "time": []}
    state = {"best_x": None, "best_f": np.inf, "stop": None, "saved": time.perf_counter()}
    key = _fit_key(prob, method, seed, popsize, tol, target, de_options)
    ckpt = None if checkpoint is None else str(checkpoint)
    if method == "separable":
        dbounds = prob.sep_bounds()
        npop = popsize or 64
        cap = maxiter or 1000
    else:
        dbounds = prob.full_bounds()
        npop = popsize or 60
        cap = maxiter or 100_000
        if tol == _DEFAULT_TOL:
            tol = 1e-5  # the paper's best-mean gap of 0.001 %

    def cb(intermediate_result):
        e = np.asarray(getattr(solver_ref.get("s"), "population_energies", [np.nan]))
        best = float(intermediate_result.fun)
        mean = float(np.mean(e[np.isfinite(e)])) if np.isfinite(e).any() else np.inf
        el = time.perf_counter() - t0
        history["nit"].append(len(history["nit"]) + 1)
        history["best"].append(best)
        history["mean"].append(mean)
        history["time"].append(el)
        if best < state["best_f"]:
            state["best_f"], state["best_x"] = best, np.array(intermediate_result.x)
        if ckpt is not None:
            # a Ctrl-C may land mid-generation: only boundary states are ever written
            state["snap"] = _snapshot(solver_ref["s"], history, el)
            if time.perf_counter() - state["saved"] >= checkpoint_every:
                _save_checkpoint(ckpt, key, state["snap"])
                state["saved"] = time.perf_counter()
        if callback is not None and callback({"generation": len(history["nit"]), "best": best,
                                             "mean": mean, "elapsed": el, "n_prony": n_prony,
                                             "x": np.array(intermediate_result.x)}):
            state["stop"] = "callback"
            return True
        if best <= target:
            state["stop"] = "target reached"
            return True
        if max_time is not None and el > max_time:
            state["stop"] = "max_time"
            return True
        if np.isfinite(mean) and mean - best <= tol * max(best, 1e-300):
            state["stop"] = "converged"
            return True
        rel, window = stall
        if len(history["mean"]) > window:
            old = history["mean"][-window - 1]
            if np.isfinite(old) and old - mean < rel * old:
                state["stop"] = f"mean error improved < {rel:.0%} over {window} generations"
                return True
        return False

    solver_ref: dict = {}
    dim = len(dbounds)
    nfev = 0
    nit = 0
    if dim == 0:  # nothing nonlinear to search (e.g. neo-Hooke with fixed τ)
        z = np.zeros(0)
        stop = "nothing to search"
    else:
        from vhfit.optimize import DifferentialEvolutionSolver

        if method == "separable":
            opts = dict(strategy="best1bin", mutation=(0.5, 1.0), recombination=0.9,
                        init="sobol", updating="deferred")
        else:  # the paper's DE: rand/1/bin, F = 0.8, CR = 0.7, NP = 60; each generation
            # is evaluated as one batch (deferred updating) so that workers = 1 and 2 follow
            # the same trajectory; de_options={"updating": "immediate"} is the paper's exact
            # one-at-a-time variant
            opts = dict(strategy="rand1bin", mutation=0.8, recombination=0.7,
                        init="latinhypercube", updating="deferred")
        opts.update(_check_de_options(de_options, ckpt))
        if workers != 1 and opts["updating"] != "deferred":
            raise ValueError(
                "updating='immediate' evaluates one trial at a time and cannot use workers: "
                "use workers=1 or deferred updating"
            )
        vec = opts["updating"] == "deferred"

        def make_solver(objective):
            with warnings.catch_warnings():
                # any prefix of a scrambled Sobol sequence fills the box well; its
                # "balance" needs a power of two only for quadrature, not for a start
                warnings.filterwarnings("ignore", "The balance properties of Sobol",
                                        UserWarning)
                return DifferentialEvolutionSolver(
                    objective, dbounds, maxiter=cap, population_size=npop, tol=0.0, atol=0.0,
                    rng=np.random.default_rng(seed), polish=False, callback=cb,
                    vectorized=vec, **opts)

        with _mapper(workers) as (mapper, chunks), make_solver(
            prob.make_objective(method, mapper, chunks)
        ) as solver:
            solver_ref["s"] = solver
            finished = None
            if resume and ckpt is not None and os.path.exists(ckpt):
                done, elapsed, finished = _load_checkpoint(ckpt, key, solver, history)
                solver.maxiter = max(cap - done, 0)
                t0 -= elapsed - (time.perf_counter() - t0)
            try:
                if finished:  # the search had ended before the run was cut: don't extend it
                    z, stop = solver.x, finished
                else:
                    res = solver.solve()
                    z = res.x
                    stop = state["stop"] or (
                        "maxiter" if len(history["nit"]) >= cap else res.message)
            except KeyboardInterrupt:
                stop = "interrupted"
                z = state["best_x"] if state["best_x"] is not None else solver.x
            nit = len(history["nit"])
            if ckpt is not None and state.get("snap") is not None:
                snap = state["snap"] if stop == "interrupted" else {**state["snap"], "done": stop}
                _save_checkpoint(ckpt, key, snap)
        nfev = max(prob.nfev, int(getattr(solver, "_nfev", 0)))
    x = prob.sep_to_params(np.asarray(z)) if method == "separable" else \
        prob.full_to_params(np.asarray(z), prob.hm.n_params)
    err = float(prob.errors(x[None, :])[0])
    if polish and stop != "interrupted":
        x, err, n_pol = _polish(prob, x)
        nfev += n_pol
    return _finish(prob, curves, model, x, err, nit, nfev, stop, history, t0, prune_tol,
                   stability_range, uncertainty, dict(
                       hyperelastic=model.hyperelastic.name, n_prony=n_prony,
                       tau_strategy=str(tau_strategy), objective=prob.objective.kind,
                       method=method, seed=seed,
                       popsize=npop, maxiter=cap, tol=tol, target=target, polish=polish,
                       g_inf_min=g_inf_min, rtol=rtol))


#: Solver keywords that calibrate sets itself, and the argument to use instead.
_OWN_DE_KEYS = {
    "popsize": "popsize", "population_size": "popsize", "maxiter": "maxiter",
    "tol": "tol", "atol": "tol", "stop": "tol, target, max_time or callback",
    "rng": "seed", "seed": "seed", "polish": "polish", "callback": "callback",
    "workers": "workers", "vectorized": "workers", "preset": "method",
}


def _check_de_options(de_options, checkpoint) -> dict:
    """The user's solver keywords, refused where calibrate owns the setting."""
    opts = dict(de_options or {})
    for k in opts:
        if k in _OWN_DE_KEYS:
            raise ValueError(
                f"de_options[{k!r}] is set by calibrate: use its {_OWN_DE_KEYS[k]} "
                "argument instead"
            )
    from vhfit.optimize import AdaptiveStrategy, adaptive_strategies

    strategy = opts.get("strategy")
    adaptive = isinstance(strategy, AdaptiveStrategy) or (
        isinstance(strategy, str) and strategy in adaptive_strategies())
    if adaptive and checkpoint is not None:
        raise ValueError(
            f"de_options['strategy'] = {strategy!r} adapts its own state, which checkpoints "
            "do not save: drop checkpoint/resume or use one of SciPy's strategies"
        )
    return opts


def _finish(prob, curves, model, x, err, nit, nfev, stop, history, t0, prune_tol,
            stability_range, uncertainty, options) -> Calibration:
    msgs: list[str] = []
    nh = model.hyperelastic.n_params
    order = np.argsort(x[nh + 1::2], kind="stable")  # present terms from fastest to slowest
    x = np.concatenate([x[:nh]] + [x[nh + 2 * i: nh + 2 * i + 2] for i in order])
    prob.tau_b = prob.tau_b[order]
    # prune Prony terms whose modulus is negligible (SPEC §8: report the effective N)
    G = x[nh::2]
    keep = [i for i in range(model.n_prony) if G[i] > prune_tol * max(G.sum(), 1e-300)]
    if len(keep) < model.n_prony:
        pruned = ViscoHyperelastic(model.hyperelastic, len(keep), rtol=model.rtol)
        x2 = np.concatenate([x[:nh]] + [x[nh + 2 * i: nh + 2 * i + 2] for i in keep])
        msgs.append(
            f"{model.n_prony - len(keep)} Prony term(s) came out negligible and were "
            f"dropped: effective N = {len(keep)}"
        )
        tau_b = prob.tau_b[keep] if len(keep) else np.zeros((0, 2))
        prob = _Problem(pruned, curves, tau_b, prob.bounds, prob.g_inf_min,
                        prob.objective_spec)
        model, x = pruned, x2
        err = float(prob.errors(x[None, :])[0])
    params = model.as_dict(x)
    E_inf = model.long_term_modulus(x)
    if model.n_prony and E_inf > 0:
        g, g_inf = prony_g(E_inf, model.split(x)[1])
    else:
        g, g_inf = np.zeros(model.n_prony), 1.0
    if prob.g_inf_min > 0 and model.n_prony and g_inf <= prob.g_inf_min * (1 + 1e-6):
        msgs.append(
            f"the g_inf floor ({prob.g_inf_min:g}) is active: the best fit wants less long-term "
            "stiffness than FE solvers accept; lower g_inf_min to see what it costs"
        )
    conf: dict = {}
    if uncertainty:
        conf, unident = _confidence(prob, x)
        if unident:
            msgs.append(
                "the data cannot identify " + ", ".join(unident)
                + " (flat directions of the error): treat their values as one of many fits"
            )
    msgs += _time_window_warnings(model, x, curves)
    stress = prob.batch(x[None, :])[0]  # the fit's stresses: per-curve errors, slack check
    msgs += _slack_warnings(prob.objective.split(stress), curves)
    stab = drucker(model.hyperelastic, x[:nh], stability_range)
    if not stab.stable:
        msgs.append(stab.describe())
    for m in msgs:
        warnings.warn(m, CalibrationWarning, stacklevel=3)
    tb = {f"tau{i + 1}": tuple(10.0 ** prob.tau_b[i]) for i in range(model.n_prony)}
    bounds = {**prob.bounds, **tb}
    bounds = {k: v for k, v in bounds.items() if k in model.param_names}
    return Calibration(
        model=model, params=params, rmsape=err,
        per_curve_rmsape=[float(v) for v in prob.objective.per_curve(stress)],
        nit=int(nit), nfev=int(nfev), wall_time=time.perf_counter() - t0, stop_reason=str(stop),
        g=[float(v) for v in g], g_inf=float(g_inf), bounds=bounds, history=history,
        confidence=conf, stability=stab, warnings=msgs, options=options,
        curve_names=[str(getattr(c, "name", f"curve {i}")) for i, c in enumerate(curves)],
    )
