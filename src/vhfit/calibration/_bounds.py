"""Search bounds: τ ranges from the strain rates (Eq. 22; the frequencies and times of
small-strain tests) and moduli that can reach the data."""

from __future__ import annotations

import math

import numpy as np

from vhfit._words import setting, worded
from vhfit.data import is_moduli
from vhfit.model import ViscoHyperelastic
from vhfit.modes import get_deformation, long_term_stress
from vhfit.viscous import ParamLayout

__all__ = ["auto_bounds", "search_bounds", "SEARCH_RANGES", "bound_hits", "widen_bounds",
           "bound_hit_headlines", "pinned_headlines", "tau_bound_headlines", "enforced_bounds",
           "stable_box",
           "HIT_MARGIN", "WIDEN", "MAX_EXPONENT_LOG", "STABLE_SAMPLES", "STABLE_PROBES"]

#: Search ranges of the built-in laws' nonlinear constants where their physical bounds
#: are open-ended: λm > 1 (Arruda–Boyce: λm → ∞ is neo-Hooke, 10 is within 1 % of it),
#: λm > √3 (Van der Waals), Jm > 0 (Gent: I1 − 3 must stay below Jm; rubbers ~10–100,
#: soft tissues ~1), a ≥ 0. Any other unbounded dimensionless constant gets [-10, 10].
SEARCH_RANGES: dict[str, dict[str, tuple[float, float]]] = {
    "arruda_boyce": {"lambda_m": (1.01, 10.0)},
    "gent": {"Jm": (0.1, 100.0)},
    "van_der_waals": {"lambda_m": (1.75, 10.0), "a": (0.0, 2.0)},
}


def _linear_rates(c) -> list[float]:
    """The rates a small-strain test stands for in Eq. 22: the angular frequencies ω of a
    sweep, 1/t of a relaxation test (its times after the step)."""
    h = c.history
    x = h.x if h.kind == "frequency" else 1.0 / h.x[h.x > 0]
    return [float(x.min()), float(x.max())] if x.size else []


def rates(curves) -> np.ndarray:
    """Nominal |rates| of the rate and time curves (equilibrium curves have none), and
    ω or 1/t of the small-strain tests."""
    linear = [r for c in curves if is_moduli(c) for r in _linear_rates(c)]
    rated = [c for c in curves if not c.is_equilibrium and not is_moduli(c)]
    if not rated and not linear:
        files = sorted({str(c.source) for c in curves if getattr(c, "source", None)})
        shown = (" (" + ", ".join(files[:3]) + (", ..." if len(files) > 3 else "") + ")"
                 if files else "")
        raise worded(ValueError,
            f"{setting('n_prony > 0', 'Prony terms')} need curves with a strain rate or a "
            f"time column: the equilibrium (rate-free) curves{shown} carry no viscous "
            "response; fit "
            + setting("n_prony=0", "--prony 0")
        )
    r = np.array([abs(float(c.strain_rate or np.nan)) for c in rated]
                 + linear)
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
    return np.asarray(b, dtype=np.float64).reshape(n, 2)  # TauBounds: an (n, 2) array


def _true_target(c) -> np.ndarray:
    """|true stress| of a curve's targets (nominal ones times the loaded stretch)."""
    y = np.abs(np.asarray(c.target_stress, dtype=np.float64))
    if c.measure == "engineering":
        y = y * c.history.out_loaded_stretch
    return y


def _long_term_true(hm, params, h) -> np.ndarray:
    """True stress of the long-term law at a history's outputs, in its mode and direction."""
    x1, x2 = h.out_stretch, h.stretch2_at(h.out_time)
    s = long_term_stress(hm, params, h.deformation, x1, x2, 1)
    if (h.out_direction == 2).any():
        s = np.where(h.out_direction == 2,
                     long_term_stress(hm, params, h.deformation, x1, x2, 2), s)
    return s


def _is_uniaxial(c) -> bool:
    """Whether a curve is of the paper's test, whose long-term stress is the law's own."""
    return get_deformation(c.deformation).uniaxial


def auto_bounds(model: ViscoHyperelastic, curves, tau_b=None) -> dict[str, tuple[float, float]]:
    """Upper search limits (docs/theory.md §11): one term alone reaches every target stress.

    For each linear hyperelastic constant (``linear_params``, or a constant in MPa) and
    each G_i, the smallest value that makes that term alone (the other linear constants
    zero, the nonlinear ones at the law's example values; a Prony term at the shortest τ
    of its bounds ``tau_b``, log10 s, where its response is weakest) reach
    |σ| ≥ |σ_target| at every objective point. Lower limits are 0, or −upper where the
    law allows either sign (the admissible set of docs/theory.md §11 then bounds them).
    Nonlinear constants
    (e.g. Ogden α, λm, Jm) get their physical bounds, narrowed by :data:`SEARCH_RANGES`
    where those are open-ended, or [-10, 10] if unbounded.
    """
    hm = model.hyperelastic
    moduli = np.concatenate([np.abs(c.target_stress) for c in curves if is_moduli(c)]
                            + [np.zeros(0)])
    curves_ss = [c for c in curves if not is_moduli(c)]
    uni = [c for c in curves_ss if _is_uniaxial(c)]
    other = [c for c in curves_ss if not _is_uniaxial(c)]
    lam = np.concatenate([c.history.out_stretch for c in uni] + [np.zeros(0)])
    y = np.concatenate([np.asarray(c.target_stress, dtype=np.float64) for c in uni]
                       + [np.zeros(0)])
    meas = np.concatenate([np.full(np.size(c.target_stress), c.measure)
                           for c in uni] + [np.zeros(0, dtype=str)])
    y_true = np.abs(np.where(meas == "engineering", y * lam, y))
    keep = np.abs(lam - 1) > 1e-9
    lam, y_true = lam[keep], y_true[keep]
    y_other = [_true_target(c) for c in other]
    out: dict[str, tuple[float, float]] = {}
    ex = np.array(hm.example, dtype=np.float64)
    amp = [k in hm.linear_index or u == "MPa" for k, u in enumerate(hm.units)]
    ranges = SEARCH_RANGES.get(hm.name, {})
    for k, name in enumerate(hm.param_names):
        lo_p, hi_p = hm.bounds[k]
        if amp[k]:
            # this constant alone; the nonlinear ones keep their example values
            unit = np.where(amp, np.where(np.arange(hm.n_params) == k, 1.0, 0.0), ex)
            with np.errstate(all="ignore"):
                s = np.abs(hm.stress(lam, unit))
                ratio = y_true / np.where(s > 0, s, np.nan)
                for c, yo in zip(other, y_other):
                    so = np.abs(_long_term_true(hm, unit, c.history))
                    ratio = np.concatenate([ratio, yo / np.where(
                        np.isfinite(so) & (so > 0), so, np.nan)])
                e_unit = 3.0 * float(hm.initial_shear_modulus(unit))  # its E∞ (moduli)
                ratio = np.concatenate([ratio, moduli / (e_unit if e_unit > 0 else np.nan)])
            ys = np.concatenate([y_true, *y_other, moduli])
            hi = float(np.nanmax(ratio)) if np.isfinite(ratio).any() else float(np.max(ys))
            # either sign where the law allows it: the admissible set decides
            out[name] = (-hi if lo_p < 0 else max(0.0, lo_p), hi)
        elif name in ranges:
            out[name] = (max(lo_p, ranges[name][0]), min(hi_p, ranges[name][1]))
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
            out[model.layout.amplitude_name(i)] = (0.0, gmax)
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
            term = ParamLayout.parse(k)
            if term is not None and term.role == ParamLayout.TIME and term.index < n_prony:
                lo, hi = map(float, v)
                if not 0 < lo <= hi:
                    raise ValueError(f"bounds[{k!r}] = {v!r}: need 0 < low <= high (s)")
                tau_b[term.index] = np.log10([lo, hi])
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


def enforced_bounds(prob, box: bool) -> dict[str, tuple[float, float]]:
    """The box the fit held each constant to (``Calibration.bounds``): name -> (low, high).

    * bounds the user gave: as given (within the law's physical limits);
    * the law's nonlinear constants (α, λm, Jm, ...): their search range (after any
      widening), which the search and the polish keep;
    * moduli (the law's constants in MPa, the G_i) without bounds of the user: the law's
      physical limits (G_i >= 0). Their automatic ranges (:func:`auto_bounds`) are where
      the all-parameter search draws them; the separable search solves them by least
      squares and the polish refines them with no upper limit, so only the full method
      without polish holds them to those ranges (``box`` True: its box, the moduli
      non-negative as :class:`vhfit.calibration._space.FullSpace` draws them).

    τ_i: the τ range of the fit (s).
    """
    hm, model, lay = prob.hm, prob.model, prob.model.layout
    out: dict[str, tuple[float, float]] = {}
    for k, name in enumerate(hm.param_names):
        plo, phi = (float(v) for v in hm.bounds[k])
        if name not in prob.bounds:  # (a problem built with some bounds only)
            if hm.units[k] == "MPa" and not box:
                out[name] = (plo, phi)
            continue
        lo, hi = (float(v) for v in prob.bounds[name])
        if name in prob.user_bounds:
            out[name] = (max(lo, plo), min(hi, phi))
        elif hm.units[k] != "MPa":
            out[name] = (lo, hi)
        else:
            out[name] = (max(lo, 0.0), hi) if box else (plo, phi)
    for i in range(model.n_prony):
        g = lay.amplitude_name(i)
        if g in prob.bounds and (g in prob.user_bounds or box):
            lo, hi = (float(v) for v in prob.bounds[g])
            out[g] = (max(lo, 0.0), hi)
        elif not box:
            out[g] = (0.0, math.inf)
        out[lay.time_name(i)] = tuple(float(10.0 ** v) for v in prob.tau_b[i])
    return out


#: A searched constant within this fraction of its search range from a bound "sits on" it.
HIT_MARGIN = 1e-3

#: A bound that was hit moves outward by this many widths of the search range.
WIDEN = 2.0

#: Exponents (Ogden α) are widened at most to |α| ln λ ≤ this over the stability range,
#: so that λ^α stays far inside float64 (e^300 ≈ 1e130).
MAX_EXPONENT_LOG = 300.0


def _searched_shape(prob) -> list[int]:
    """The law's dimensionless nonlinear constants (α, λm, Jm, ...): searched by DE."""
    hm = prob.hm
    return [k for k in range(hm.n_params) if k not in hm.linear_index and hm.units[k] != "MPa"]


def bound_hits(prob, x: np.ndarray) -> dict[str, str]:
    """Searched nonlinear constants of ``x`` within :data:`HIT_MARGIN` of a search bound
    that is not the law's physical limit: name -> "low" or "high"."""
    hm, out = prob.hm, {}
    for k in _searched_shape(prob):
        name = hm.param_names[k]
        lo, hi = (float(v) for v in prob.bounds[name])
        plo, phi = (float(v) for v in hm.bounds[k])
        margin = HIT_MARGIN * (hi - lo)
        if not hi > lo:
            continue
        if x[k] - lo <= margin and lo > plo:
            out[name] = "low"
        elif hi - x[k] <= margin and hi < phi:
            out[name] = "high"
    return out


def widen_bounds(prob, hits: dict[str, str], bounds: dict | None = None
                 ) -> dict[str, tuple[float, float]]:
    """The search bounds (``bounds``, default ``prob.bounds``) with each hit bound moved
    :data:`WIDEN` widths outward, inside the law's physical limits (an open one approached
    to 1 % of the remaining gap) and, for an exponent α, inside |α| ≤
    :data:`MAX_EXPONENT_LOG` / max |ln λ| of the stability range. Bounds the user gave
    are kept (not in the result's changes)."""
    bounds = prob.bounds if bounds is None else bounds
    hm, out = prob.hm, dict(bounds)
    ell = max(-math.log(prob.stability_range[0]), math.log(prob.stability_range[1]))
    for name, side in hits.items():
        if name in prob.user_bounds:
            continue
        k = hm.param_names.index(name)
        lo, hi = (float(v) for v in bounds[name])
        plo, phi = (float(v) for v in hm.bounds[k])
        if name.startswith("alpha"):
            cap = MAX_EXPONENT_LOG / ell
            plo, phi = max(plo, -cap), min(phi, cap)
        w = WIDEN * (hi - lo)
        if side == "low":
            new = lo - w
            lo = new if new > plo else plo + 0.01 * (lo - plo)
        else:
            new = hi + w
            hi = new if new < phi else phi - 0.01 * (phi - hi)
        out[name] = (lo, hi)
    return out


def _on_bound(name: str, value: float, side: str, bound: float, how: str,
              sug: tuple[float, float], unit: str = "") -> str:
    """The sentence naming a constant on a search bound: which, where, how to move it."""
    u = f" {unit}" if unit else ""
    return (f"{name} = {value:.6g}{u} ended on its search bound {name} "
            f"{'>=' if side == 'low' else '<='} {bound:g}{u} ({how}): the best fit may lie "
            f"beyond it; widen it with the bounds= keyword, e.g. "
            f"bounds={{'{name}': ({sug[0]:g}, {sug[1]:g})}} (command line: --bounds "
            f"{name}={sug[0]:g}:{sug[1]:g})")


def bound_hit_headlines(prob, x: np.ndarray, hits: dict[str, str], widened: dict) -> list[str]:
    """One sentence per constant still on a search bound: which, where, how to move it."""
    out = []
    for name, side in hits.items():
        k = prob.hm.param_names.index(name)
        lo, hi = (float(v) for v in prob.bounds[name])
        how = ("given in bounds=" if name in prob.user_bounds else
               "after one automatic widening" if name in widened else
               "of the automatic search range")
        out.append(_on_bound(name, float(x[k]), side, lo if side == "low" else hi, how,
                             _suggest(name, lo, hi, side, log=False)))
    return out


#: Laws of the search box tried for a Drucker-stable one (with the law's example, the
#: corners of the box).
STABLE_SAMPLES = 256

#: Doublings beyond a bound tried for a stable law (2^12: a Jm bound of 100 up to 4e5).
STABLE_PROBES = 12


def stable_box(prob) -> tuple[dict, dict, bool]:
    """Search bounds whose box holds a Drucker-stable law: (bounds, widened, found).

    A law with one linear constant (Gent, Arruda–Boyce, Van der Waals, Ogden-1, ...) is
    admissible or not by its nonlinear constants alone (the admissible set is invariant
    under a positive scale). When no law of a sample of the box (:data:`STABLE_SAMPLES`
    laws, the example and the corners) is admissible over the stability range, each
    automatic bound of a nonlinear constant is moved out by doublings
    (:data:`STABLE_PROBES`, within the law's physical limits), the other constants at
    the example's values: the first that reaches a stable law (Gent's Jm beyond
    I1 − 3 of the range, a λm beyond its largest stretch) is widened to twice that far,
    so that the stable laws fill half of the widened side. ``widened``: name -> the new
    (low, high); ``found`` False: no stable law in reach (the bounds the user gave, or
    none of the law's). Laws with several linear constants are left to the search's arcs
    (``found`` True, nothing widened); so is a fit without an admissible set.
    """
    hm, adm = prob.hm, prob.adm
    bounds = dict(prob.bounds)
    if adm is None or len(hm.linear_index) != 1:
        return bounds, {}, True
    shape = _searched_shape(prob)
    ex = np.array(hm.example, dtype=np.float64)
    box = np.array([[float(v) for v in prob.bounds[hm.param_names[k]]] for k in shape]
                   ).reshape(-1, 2)
    ex[shape] = np.clip(ex[shape], box[:, 0], box[:, 1])
    rng = np.random.default_rng(0)
    X = np.repeat(ex[None, :], STABLE_SAMPLES + 2 ** min(len(shape), 8) + 1, axis=0)
    if shape:
        X[1:STABLE_SAMPLES + 1, shape] = box[:, 0] + rng.random((STABLE_SAMPLES, len(shape))
                                                                 ) * (box[:, 1] - box[:, 0])
        corners = np.array(np.meshgrid(*box[:8], indexing="ij")).reshape(min(len(shape), 8),
                                                                          -1).T
        X[STABLE_SAMPLES + 1:, shape[:8]] = corners
    if adm(X).any():
        return bounds, {}, True
    for j, k in enumerate(shape):
        name = hm.param_names[k]
        if name in prob.user_bounds:
            continue
        lo, hi = box[j]
        plo, phi = (float(v) for v in hm.bounds[k])
        for side in ("high", "low"):
            b = hi if side == "high" else lo
            if side == "high":
                values = (hi * 2.0 ** np.arange(1, STABLE_PROBES + 1) if hi > 0 else
                          hi + max(hi - lo, 1.0) * 2.0 ** np.arange(STABLE_PROBES))
            else:
                values = (lo / 2.0 ** np.arange(1, STABLE_PROBES + 1) if lo > 0 else
                          lo - max(hi - lo, 1.0) * 2.0 ** np.arange(STABLE_PROBES))
            values = values[(values > plo) & (values < phi)]
            P = np.repeat(ex[None, :], values.size, axis=0)
            P[:, k] = values
            ok = np.flatnonzero(adm(P)) if values.size else []
            if len(ok):
                v = float(values[ok[0]])
                far = b + 2.0 * (v - b)  # the stable laws fill half of the new side
                far = far if plo < far < phi else v
                new = (lo, far) if side == "high" else (far, hi)
                bounds[name] = new
                return bounds, {name: [float(new[0]), float(new[1])]}, True
    return bounds, {}, False


def no_stable_headline(prob) -> str:
    """The first warning of a fit that found no Drucker-stable law: why, what to change."""
    hm = prob.hm
    lo, hi = prob.stability_range
    shape = [hm.param_names[k] for k in _searched_shape(prob)]
    given = [n for n in shape if n in prob.user_bounds]
    how = (f"widen the bounds given on {', '.join(given)} (bounds= keyword, command line "
           "--bounds), " if given else "")
    return (f"NO STABLE LAW: no {hm.name} law within the search bounds is Drucker-stable "
            f"over {lo:.3g} <= λ <= {hi:.3g} (every principal stretch): the fit below is "
            f"UNSTABLE; {how}give a narrower stability_range= (command line: "
            "--stability-range LO:HI) if the material is not loaded beyond the data, or "
            "choose another law")


def _suggest(name: str, lo: float, hi: float, side: str, log: bool) -> tuple[float, float]:
    """A wider interval on the side hit: :data:`WIDEN` widths out; for τ (``log``)
    :data:`WIDEN` decades (widths of an automatic range of several decades would reach
    centuries)."""
    if log:
        return ((lo / 10.0 ** WIDEN, hi) if side == "low" else (lo, hi * 10.0 ** WIDEN))
    w = WIDEN * (hi - lo)
    return (lo - w, hi) if side == "low" else (lo, hi + w)


def pinned_headlines(prob, x: np.ndarray, skip=()) -> list[str]:
    """One sentence per linear constant (a hyperelastic modulus, a G_i) that ends on a
    bound the user gave, beyond those of :func:`bound_hits` (``skip``): no widening moves
    it. A bound at the law's physical limit (G_i >= 0, μ > 0) is no warning. Relaxation
    times are :func:`tau_bound_headlines`' part (after the terms are sorted)."""
    hm, out = prob.hm, []
    for k, name in enumerate(prob.model.param_names):
        if (name in skip or not np.isfinite(x[k]) or name not in prob.user_bounds
                or name not in prob.bounds or ParamLayout.is_time(name)):
            continue  # automatic bounds of the searched shape: bound_hits' part
        lo, hi = (float(v) for v in prob.bounds[name])
        if not hi > lo:
            continue
        plo, phi = ((float(v) for v in hm.bounds[k]) if k < hm.n_params
                    else (0.0, math.inf))  # G_i >= 0
        margin = HIT_MARGIN * (hi - lo)
        side = ("low" if x[k] - lo <= margin and lo > plo else
                "high" if hi - x[k] <= margin and hi < phi else None)
        if side is not None:
            out.append(_on_bound(name, float(x[k]), side, lo if side == "low" else hi,
                                 "given in bounds=", _suggest(name, lo, hi, side, log=False)))
    return out


def tau_bound_headlines(prob, x: np.ndarray, curves, settings, windows: dict[int, str]
                        ) -> dict[int, str]:
    """One sentence per relaxation time on an end of its τ range: term index -> sentence.

    ``x`` and ``prob.tau_b`` are the fit's terms as reported (sorted, merged, pruned). A τ
    within :data:`HIT_MARGIN` of the width of its range (log10) from an end, with G_i > 0,
    is named with the bound and a wider ``bounds=`` for it: a range the user gave
    (``settings.bounds``, told by its ends), or the automatic one (Eq. 22: the data's time
    scales, ``settings.decades_below`` and ``decades_above``), which no widening moves.
    At an end of the whole automatic range a test that identifies it is the other remedy
    (a slower test or a relaxation hold for the upper end, a faster test for the lower);
    at a cut of the range between two terms (the ``semifree`` strategy) the ``free``
    strategy. ``windows`` (term index -> clause,
    :func:`vhfit.calibration._report.time_windows`) adds that τ's time-window fact to its
    sentence, so that one line names each τ. A fixed τ (lower == upper) is never named.
    """
    lay, out = prob.model.layout, {}
    tau_b = np.asarray(prob.tau_b, dtype=np.float64).reshape(-1, 2)
    try:
        whole = tau_bounds_log10(rates(curves), 1, "free", settings.decades_below,
                                 settings.decades_above)[0]
    except ValueError:  # no rates (every τ bounded by the user): no automatic range
        whole = None
    # the ends the user gave, by value: merged and pruned terms are numbered anew, so the
    # term a bound was given to may carry another name now
    given = [math.log10(float(v)) for k, lim in (settings.bounds.items() if isinstance(
        settings.bounds, dict) else ()) if ParamLayout.is_time(k) for v in lim]
    for i in range(tau_b.shape[0]):
        G, tau = float(x[lay.amplitude_index(i)]), float(x[lay.time_index(i)])
        a, b = (float(v) for v in tau_b[i])
        if not (b > a and G > 0 and tau > 0 and np.isfinite(tau)):
            continue
        z, margin = math.log10(tau), HIT_MARGIN * (b - a)
        side = "low" if z - a <= margin else "high" if b - z <= margin else None
        if side is None:
            continue
        name = lay.time_name(i)
        lo, hi = 10.0 ** a, 10.0 ** b
        end = a if side == "low" else b
        outer = whole is not None and abs(end - whole[0 if side == "low" else 1]) <= 1e-9
        if any(abs(end - g) <= 1e-9 for g in given):
            how, then = "given in bounds=", ""
        elif outer:
            how = "the end of the automatic τ range, set by the data's time scales"
            then = ("; or add a slower test or a relaxation hold that identifies it"
                    if side == "high" else "; or add a faster test that identifies it")
        else:
            how = (f"its share of the automatic τ range under the tau strategy "
                   f"{str(settings.tau_strategy)!r}")
            then = ("; or tau_strategy='free' (command line: --strategy free) lets every τ "
                    "span the whole range")
        line = _on_bound(name, tau, side, lo if side == "low" else hi, how,
                         _suggest(name, lo, hi, side, log=True), unit="s")
        out[i] = line + (f"; it {windows[i]}" if i in windows else then)
    return out
