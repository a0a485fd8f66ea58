"""After the search: order of the terms, pruning, uncertainty, checks, warnings, the result."""

from __future__ import annotations

import math
import re
import time
import warnings

import numpy as np

from vhfit.calibration._admissible import data_stability_range
from vhfit.calibration._bounds import enforced_bounds, tau_bound_headlines
from vhfit.calibration._polish import polish
from vhfit.calibration._result import Calibration, CalibrationWarning
from vhfit.calibration._space import Problem
from vhfit.model import model_from_spec
from vhfit.stability import drucker
from vhfit.viscoelastic import prony_g
from vhfit.viscous import ParamLayout

__all__ = ["finish", "merge_terms", "MERGE_RTOL", "confidence", "covariance",
           "time_windows", "time_window_warnings", "slack_warnings", "degenerate_warnings",
           "CORRELATION_TOL", "NEGLIGIBLE"]


def covariance(prob: Problem, x: np.ndarray):
    """The Jacobian's view of a fit: (z, cov, Vt, tiny, s2, dof).

    ``z`` is ``x`` with log10 τ, ``cov`` the covariance of z *without* the factor s²
    (so that correlations are defined even for an exact fit), ``Vt`` and ``tiny`` the
    right singular vectors of J and which singular values count as zero, ``s2`` the
    residual variance. None when J is not finite.
    """
    lay = prob.model.layout
    z = lay.to_log(x)
    n_par = z.size
    h = 1e-6 * np.maximum(np.abs(z), 1e-6)
    Z = np.vstack([z + np.diag(h), z - np.diag(h)])
    R = prob.residuals(lay.from_log(Z))
    J = ((R[:n_par] - R[n_par:]) / (2 * h)[:, None]).T
    r0 = prob.residuals(x[None, :])[0]
    n = r0.size
    dof = max(n - n_par, 1)
    s2 = float(r0 @ r0) / dof
    if not np.all(np.isfinite(J)):
        return None
    U, sv, Vt = np.linalg.svd(J, full_matrices=False)
    tiny = sv <= sv.max() * 1e-10 if sv.size else np.array([], bool)
    inv = np.where(tiny, 0.0, 1.0 / np.where(tiny, 1.0, sv) ** 2)
    return z, (Vt.T * inv) @ Vt, Vt, tiny, s2, dof


def confidence(prob: Problem, x: np.ndarray, level: float = 0.95, cov=None):
    """Intervals from the Jacobian of the weighted residuals (τ intervals via log10 τ).

    ``cov`` is :func:`covariance` of the same fit when already computed.
    """
    model = prob.model
    out, unident = {}, []
    got = covariance(prob, x) if cov is None else cov
    if got is None:
        return out, unident
    z, cov0, Vt, tiny, s2, dof = got
    cov = cov0 * s2
    # Student's t quantile: scipy.special's stdtrit is what scipy.stats.t.ppf evaluates
    # (identical values), without the seconds scipy.stats takes to import
    from scipy.special import stdtrit

    tq = float(stdtrit(dof, 0.5 + level / 2))
    roles = model.layout.roles
    for k, name in enumerate(model.param_names):
        half = tq * math.sqrt(max(cov[k, k], 0.0))
        # a parameter along a (near-)null direction of J cannot be identified
        weak = any(abs(Vt[j, k]) > 0.1 for j in np.flatnonzero(tiny))
        if weak:
            unident.append(name)
        if roles[k] == ParamLayout.TIME:
            with np.errstate(over="ignore"):  # an unidentifiable τ: an interval to inf
                out[name] = (10 ** (z[k] - half), 10 ** (z[k] + half))
        else:
            out[name] = (x[k] - half, x[k] + half)
    return out, unident


#: Two hyperelastic moduli whose estimates correlate at least this closely (|ρ|, from
#: the Jacobian at the fit) act on the data as one term: only a combination of them is
#: determined, each alone ~1/sqrt(2e-6) ≈ 700 times less certain than if the two were
#: separable (docs/reliability.md, "Degenerate fits").
CORRELATION_TOL = 1.0 - 1e-6

#: A constant below this fraction of the largest of its kind is effectively zero.
NEGLIGIBLE = 1e-12


def _partners(names, units, i: int) -> list[int]:
    """The dimensionless constants of the same term as modulus ``names[i]`` (the α of
    Ogden's μ: the same trailing number)."""
    m = re.fullmatch(r"(\D+)(\d+)", names[i])
    if m is None:
        return []
    return [k for k, n in enumerate(names) if units[k] == "1" and n != names[i]
            and re.fullmatch(r"\D+" + m.group(2), n)]


def _fewer_terms(hm) -> str:
    return hm.fewer or "a law with fewer terms"


def _negligible(model, x, names, units, moduli) -> tuple[list[str], set[int]]:
    """Constants below NEGLIGIBLE of the largest of their kind, one sentence per kind."""
    out, zero = [], set()
    for idx, kind in ((moduli, "hyperelastic modulus"),
                      (list(range(x.size))[model.layout.amplitudes], "Prony modulus G_i")):
        top = max((abs(float(x[k])) for k in idx), default=0.0)
        tiny = [k for k in idx if len(idx) > 1 and abs(float(x[k])) < NEGLIGIBLE * top]
        zero.update(tiny)
        if tiny:
            out.append(
                ", ".join(f"{names[k]} = {x[k]:.3g} {units[k]}" for k in tiny)
                + f" below {NEGLIGIBLE:g} of the largest {kind} ({top:.4g} MPa): effectively "
                "zero, the term is absent from the fit; use a model without it")
    return out, zero


def degenerate_warnings(model, x, conf: dict, cov0=None) -> list[str]:
    """Constants the data do not determine: terms that act as one, constants that are
    effectively zero, intervals wider than their value (docs/reliability.md).

    Parameters
    ----------
    model : ViscoHyperelastic
    x : ndarray
        The fitted parameters.
    conf : dict
        Name -> (low, high) 95 % interval (empty: no interval check).
    cov0 : ndarray, optional
        Covariance of the fit's parameters up to the factor s² (:func:`covariance`;
        None: no correlation check).

    Returns
    -------
    list of str
        One sentence each: what is degenerate, what it means, what to do.

    Examples
    --------
    >>> from vhfit.model import ViscoHyperelastic
    >>> m = ViscoHyperelastic("yeoh", 0)
    >>> degenerate_warnings(m, np.array([0.5, 1.86e-55, 0.01]), {})[0][:48]
    'C20 = 1.86e-55 MPa below 1e-12 of the largest hy'
    """
    hm = model.hyperelastic
    names, units = list(model.param_names), list(model.units)
    moduli = [k for k in range(hm.n_params) if units[k] == "MPa"]
    zero_msgs, zero = _negligible(model, x, names, units, moduli)
    out = []
    if cov0 is not None:
        d = np.sqrt(np.maximum(np.diag(cov0), 0.0))
        live = [k for k in moduli if k not in zero]
        for a, i in enumerate(live):
            for j in live[a + 1:]:
                if not (d[i] > 0 and d[j] > 0):
                    continue
                rho = float(cov0[i, j] / (d[i] * d[j]))
                if not abs(rho) >= CORRELATION_TOL:
                    continue
                pi, pj = _partners(names, units, i), _partners(names, units, j)
                how = f"correlation of {names[i]} and {names[j]} {rho:+.9f}"
                what = (f"{names[pi[0]]} and {names[pj[0]]} ({x[pi[0]]:.4g} vs {x[pj[0]]:.4g})"
                        if pi and pj else f"{names[i]} and {names[j]}")
                out.append(
                    f"{what} cannot be told apart by the data ({how}): the two terms act as "
                    "one, only a combination of them is determined; use "
                    f"{_fewer_terms(hm)}, or add tests (other modes, larger "
                    "strains) that separate them")
    out += zero_msgs
    # half-width of the interval (a τ's is not symmetric in s) wider than |value|; NaN
    # and inf count as wider
    wide = [k for k, name in enumerate(names) if name in conf and k not in zero
            and not (conf[name][1] - conf[name][0]) / 2 <= abs(float(x[k]))]
    if wide:
        out.append(
            "not determined by the data (95 % interval wider than the value): "
            + ", ".join(f"{names[k]} = {x[k]:.4g} {units[k]} in [{conf[names[k]][0]:.3g}, "
                        f"{conf[names[k]][1]:.3g}]" for k in wide)
            + "; do not use these constants one by one: fit fewer terms (a smaller N, a law "
            "with fewer constants) or add tests that exercise them")
    return out


def time_windows(model, x, curves) -> dict[int, str]:
    """The relaxation times (G_i > 0) outside the data's time window: term index -> clause
    (what it does, what would identify it), to follow "tau{i + 1} = ... s ".

    A τ longer than 10x every curve's duration cannot be told from a stiffer elastic law;
    one shorter than 0.01x every curve's first objective time is seen only through G·τ.
    """
    lay = model.layout
    out = {}
    durations = [c.history.duration for c in curves]
    firsts = []
    for c in curves:
        t = np.asarray(c.history.out_time)
        firsts.append(float(np.min(t[t > 0])) if np.any(t > 0) else c.history.duration)
    for i in range(model.n_prony):
        G, tau = x[lay.amplitude_index(i)], x[lay.time_index(i)]
        if G <= 0:
            continue
        if tau > 10 * max(durations):
            out[i] = (
                f"is longer than 10x every curve's duration (longest {max(durations):.3g} "
                "s): the data cannot tell it from a stiffer elastic law; add a slower test "
                "or a relaxation hold to identify it"
            )
        elif tau < 0.01 * min(firsts):
            out[i] = (
                f"relaxes before the first objective point of every curve (earliest "
                f"{min(firsts):.3g} s): its modulus is only seen through G*tau; faster "
                "tests are needed to identify it"
            )
    return out


def time_window_warnings(model, x, curves, named=()) -> list[str]:
    """One sentence per relaxation time of :func:`time_windows`, except the term indices
    ``named`` (a sentence naming that τ on a bound already carries its clause)."""
    lay = model.layout
    return [f"{lay.time_name(i)} = {x[lay.time_index(i)]:.3g} s {clause}"
            for i, clause in time_windows(model, x, curves).items() if i not in named]


def slack_warnings(model_stress, curves) -> list[str]:
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


#: Relaxation times closer than this relative difference are one term (merged).
MERGE_RTOL = 0.01


def merge_terms(G: np.ndarray, tau: np.ndarray, rtol: float = MERGE_RTOL
                ) -> tuple[np.ndarray, np.ndarray, list[tuple[int, ...]]]:
    """Merge neighbouring Prony terms whose relaxation times coincide (sorted τ in, sorted
    τ out; terms in a user's order are merged with their neighbours only).

    Two branches with τ within ``rtol`` of each other act as one of modulus G_a + G_b;
    the merged τ is their modulus-weighted geometric mean, so the change of the
    stress is of second order in the difference.

    Returns
    -------
    G, tau : ndarray
        The merged terms.
    groups : list of tuple of int
        The original indices that each merged term gathers.

    Examples
    --------
    >>> G, tau, groups = merge_terms(np.array([1.0, 3.0, 2.0]), np.array([0.1, 0.1005, 10.0]))
    >>> G.tolist(), groups
    ([4.0, 2.0], [(0, 1), (2,)])
    """
    groups: list[list[int]] = []
    for i in range(tau.size):
        first = tau[groups[-1][0]] if groups else 0.0
        # (the lower end holds for sorted τ; a user's term order may be unsorted)
        if groups and first * (1.0 - rtol) <= tau[i] <= first * (1.0 + rtol):
            groups[-1].append(i)
        else:
            groups.append([i])
    Gm, tm = np.empty(len(groups)), np.empty(len(groups))
    for k, g in enumerate(groups):
        if len(g) == 1:  # untouched, to the bit
            Gm[k], tm[k] = G[g[0]], tau[g[0]]
            continue
        Gm[k] = G[g].sum()
        w = G[g] / Gm[k] if Gm[k] > 0 else np.full(len(g), 1.0 / len(g))
        tm[k] = np.exp(np.sum(w * np.log(tau[g])))
    return Gm, tm, [tuple(g) for g in groups]


#: Two like terms are candidates to merge when their shape constants agree to this
#: relative tolerance; the merge is kept only if the merged fit (polished) is no worse,
#: or its stresses differ from the fit's by less than the model's accuracy ``rtol`` of
#: the peak stress (the data cannot tell the two fits apart).
LIKE_RTOL = 1e-3


def _like_pair(terms: np.ndarray) -> tuple[int, int] | None:
    """The first pair of terms (rows: first constant linear, the rest the shape) that act
    as one: same shape constants, or one term whose linear constant is negligible."""
    top = float(np.max(np.abs(terms[:, 0])))
    for p in range(len(terms)):
        for q in range(p + 1, len(terms)):
            a, b = terms[p, 1:], terms[q, 1:]
            same = np.all(np.abs(a - b) <= LIKE_RTOL * np.maximum(np.abs(a), np.abs(b)))
            if same or min(abs(terms[p, 0]), abs(terms[q, 0])) < NEGLIGIBLE * top:
                return p, q
    return None


def _same_stresses(s1: np.ndarray, s2: np.ndarray, rtol: float) -> bool:
    """Whether two fits' stresses differ by less than ``rtol`` of the peak stress."""
    return bool(np.max(np.abs(s2 - s1)) <= rtol * np.max(np.abs(s1)))


def _merge_like_terms(prob, curves, model, x, err, msgs, heads):
    """Merge hyperelastic terms the data cannot tell apart into a law with fewer terms.

    A law that is a sum of like terms (``Hyperelastic.term``; Ogden) loses one term per
    merge: two terms with the same shape act as one with the sum of their linear
    constants, and a term with a negligible linear constant is absent. The merged fit
    is polished unless its stresses already differ from the fit's by less than
    ``model.rtol`` of the peak stress; it is kept only when then no worse or within that
    accuracy of the fit.
    """

    while True:
        hm = model.hyperelastic
        if not hm.term or hm.fewer is None:
            return prob, model, x, err
        nh, k = hm.n_params, hm.term
        terms = x[:nh].reshape(-1, k)
        pair = _like_pair(terms)
        if pair is None:
            return prob, model, x, err
        p, q = pair
        keep, drop = (p, q) if abs(terms[p, 0]) >= abs(terms[q, 0]) else (q, p)
        merged = terms.copy()
        merged[keep, 0] = terms[p, 0] + terms[q, 0]
        merged = np.delete(merged, drop, axis=0)
        fewer = model_from_spec(model.spec().replace(hyperelastic=hm.fewer))
        x2 = np.concatenate([merged.reshape(-1), x[nh:]])
        # the search bounds of the constants kept (the law's own where none were searched)
        bounds = {**dict(zip(fewer.hyperelastic.param_names, fewer.hyperelastic.bounds)),
                  **prob.bounds}
        prob2 = Problem(fewer, curves, prob.tau_b, bounds, prob.g_inf_min,
                        prob.objective_spec, prob.stability_range, prob.user_bounds,
                        prob.constrained)
        s1 = prob.batch(x[None, :])[0]
        same = _same_stresses(s1, prob2.batch(x2[None, :])[0], model.rtol)
        if not same:  # the merged constants as they are change the fit: polish them
            x2 = polish(prob2, x2)[0]
            same = _same_stresses(s1, prob2.batch(x2[None, :])[0], model.rtol)
        err2 = float(prob2.errors(x2[None, :])[0])
        if not (err2 <= err or same):
            return prob, model, x, err
        names = model.param_names
        a, b = names[k * p: k * p + k], names[k * q: k * q + k]
        msgs.append(
            f"the terms ({', '.join(a)}) and ({', '.join(b)}) act as one "
            f"({', '.join(f'{n} = {v:.6g}' for n, v in zip(a + b, np.r_[terms[p], terms[q]]))})"
            f": merged into {hm.fewer} (error {err:.6g} -> {err2:.6g})")
        heads.append(msgs[-1])
        prob, model, x, err = prob2, fewer, x2, err2


def _reduce_terms(prob, curves, model, x, err, prune_tol, msgs):
    """Sort the Prony terms by τ, merge coincident ones, drop negligible ones."""
    lay = model.layout
    # present terms from fastest to slowest; but a bound the user gave to a term by its
    # name (tau2, G1) holds for that name, so such a fit keeps its terms' order
    named = any(ParamLayout.parse(k) for k in prob.user_bounds)
    order = (np.arange(model.n_prony) if named else
             np.argsort(x[lay.times], kind="stable"))
    x = np.concatenate([x[lay.law]] + [x[lay.term(i)] for i in order])
    prob.tau_b = prob.tau_b[order]
    _, G, tau = lay.split(x)
    G, tau, groups = merge_terms(G, tau)
    merged = [g for g in groups if len(g) > 1]
    if merged:
        msgs.append(
            "relaxation times that coincide were merged: "
            + "; ".join(" and ".join(lay.time_name(i) for i in g) for g in merged)
            + f" (effective N = {len(groups)} before pruning)"
        )
    tau_b = np.array([[prob.tau_b[g, 0].min(), prob.tau_b[g, 1].max()] for g in groups]
                     ).reshape(-1, 2)
    # prune Prony terms whose modulus is negligible, and report the effective N
    keep = [i for i in range(G.size) if G[i] > prune_tol * max(G.sum(), 1e-300)]
    if len(keep) < len(groups):
        msgs.append(
            f"{len(groups) - len(keep)} Prony term(s) came out negligible and were "
            f"dropped: effective N = {len(keep)}"
        )
    if len(keep) == model.n_prony:
        return prob, model, x, err
    reduced = model_from_spec(model.spec().with_terms(len(keep)))
    x2 = reduced.layout.assemble(x[lay.law], G[keep], tau[keep])
    prob = Problem(reduced, curves, tau_b[keep] if keep else np.zeros((0, 2)), prob.bounds,
                   prob.g_inf_min, prob.objective_spec, prob.stability_range,
                   prob.user_bounds, prob.constrained)
    return prob, reduced, x2, float(prob.errors(x2[None, :])[0])


def finish(prob, curves, model, x, err, found, nfev: int, settings, options: dict,
           headlines=(), notes=()) -> Calibration:
    """The result of one search (``found``, a ``Search``) ending at ``x`` with error ``err``
    after ``nfev`` evaluations: terms sorted, merged and pruned, g, intervals, checks and
    warnings, as ``settings`` ask; ``options`` is the record of how the fit ran;
    ``headlines`` (warnings that head the summary) and ``notes`` (further warnings) come
    from the search (constants on a search bound, the unconstrained fit)."""
    heads: list[str] = list(headlines)
    msgs: list[str] = list(headlines) + list(notes)
    prob, model, x, err = _merge_like_terms(prob, curves, model, x, err, msgs, heads)
    prob, model, x, err = _reduce_terms(prob, curves, model, x, err, settings.prune_tol,
                                        msgs)
    E_inf = model.long_term_modulus(x)
    if model.n_prony and E_inf > 0:
        g, g_inf = prony_g(E_inf, model.split(x)[1])
    else:
        g, g_inf = np.zeros(model.n_prony), 1.0
    if prob.g_inf_min > 0 and model.n_prony and g_inf <= prob.g_inf_min * (1 + 1e-6):
        heads.append(
            f"g_inf sits at its floor ({prob.g_inf_min:g}): the best fit wants less long-term "
            "stiffness than FE solvers accept, so the material barely resists slow loading; "
            "add slower or relaxation tests, or lower g_inf_min to see what the floor costs"
        )
        msgs.append(heads[-1])
    conf: dict = {}
    cov = None
    if settings.uncertainty:
        cov = covariance(prob, x)
        conf, unident = confidence(prob, x, cov=cov)
        if unident:
            msgs.append(
                "the data cannot identify " + ", ".join(unident)
                + " (flat directions of the error): treat their values as one of many fits"
            )
    # constants the data do not determine head the summary (before the constants)
    degenerate = degenerate_warnings(model, x, conf, None if cov is None else cov[1])
    heads += degenerate
    msgs += degenerate
    # one line per τ: on a bound (automatic range or the user's, with its time-window
    # fact) it heads the summary, else its time-window fact alone
    on_bound = tau_bound_headlines(prob, x, curves, settings, time_windows(model, x, curves))
    heads += on_bound.values()
    msgs += list(on_bound.values()) + time_window_warnings(model, x, curves, on_bound)
    stress = prob.batch(x[None, :])[0]  # the fit's stresses: per-curve errors, slack check
    msgs += slack_warnings(prob.objective.split(stress), curves)
    # the range the search's admissible set used (a bare Problem has none: the settings')
    sr = prob.stability_range or settings.stability_range or data_stability_range(curves)
    stab = drucker(model.hyperelastic, x[:model.hyperelastic.n_params], sr, principal=True)
    if not stab.stable:
        msgs.append(stab.describe())
    for m in msgs:
        warnings.warn(m, CalibrationWarning, stacklevel=3)
    # the full search without polish holds the moduli to its box; every other route
    # (least squares of the moduli, the polish, the spectrum route) to the law's limits
    bounds = enforced_bounds(prob, not settings.space.separable and not settings.polish
                             and "route" not in options)
    return Calibration._make(
        model, x, rmsape=err,
        per_curve_rmsape=[float(v) for v in prob.objective.per_curve(stress)],
        nit=int(found.nit), nfev=int(nfev), wall_time=time.perf_counter() - found.t0,
        stop_reason=found.stop, g=[float(v) for v in g], g_inf=float(g_inf),
        bounds=bounds, history=found.history, confidence=conf, stability=stab,
        warnings=msgs, headlines=heads, options=options,
        curve_names=[str(c.name) for c in curves], curves=list(curves),
        settings=settings,
    )
