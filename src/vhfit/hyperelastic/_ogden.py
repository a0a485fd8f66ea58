"""The Ogden sums λk ∂W/∂λk = Σ_p (2μp/αp) λk^αp for whole populations, in one pass.

A calibration evaluates them for every parameter set (P of them) at every sample of the
kernel's grid (m of them), for three stretches. Written with numpy the powers need one
exp per term, stretch, set and sample and a P × m temporary per operation; here one
compiled loop writes the sums directly, and the kinematics of the homogeneous tests save
most of the exps: they tie the stretches together (λ2 = λ3 = λ1^(−1/2), λ2 = λ1, λ2 = 1
or λ3 = 1 in the built-in tests, and always λ1 λ2 λ3 = 1), so λ2^α and λ3^α follow from
λ1^α by a square root or a division. :func:`stretch_plan` finds those relations on the m
stretches once per call.
"""

from __future__ import annotations

import threading

import numpy as np

from vhfit._fixed import remembered

# how a stretch's power follows (rules of stretch_plan, as kernel codes)
EXP, SAME0, SAME1, ONE, RSQRT, INV, INCOMPRESSIBLE = range(7)

#: |α ln λ| below which λ^α, its square, square root and their reciprocals (the
#: derived powers) neither overflow nor underflow
SAFE_EXPONENT = 250.0


def stretch_plan(l1, l2, l3) -> tuple[list[int], list[np.ndarray]]:
    """How each principal power λk^α follows from λ1^α (or needs its own exp).

    Returns one rule per stretch — ``EXP`` (its own exp), ``SAME0`` / ``SAME1`` (equal to
    stretch 1 / 2), ``ONE`` (all 1), ``RSQRT`` (1/√(λ1^α)), ``INV`` (1/λ1^α) or
    ``INCOMPRESSIBLE`` (1/(λ1^α λ2^α)) — and the logarithms ln λk (length m each).
    A relation is used only where it holds to rounding on every sample.
    """
    lam = [np.ascontiguousarray(v, dtype=np.float64) for v in (l1, l2, l3)]
    logs: list = [np.log(lam[0]), None, None]
    rules = [EXP, EXP, EXP]
    for k in (1, 2):
        for j in range(k):
            if lam[k] is lam[j] or np.array_equal(lam[k], lam[j]):
                rules[k] = SAME0 if (j == 0 or rules[j] == SAME0) else SAME1
                logs[k] = logs[j]
                break
        else:
            logs[k] = np.log(lam[k])
            if np.all(lam[k] == 1.0):
                rules[k] = ONE
    with np.errstate(invalid="ignore"):
        resid = np.max(np.abs(logs[0] + logs[1] + logs[2]), initial=0.0)
        scale = np.max(np.abs(logs[0]), initial=0.0)
    # 1e-13: the rounding of stretches computed as λ^(−1/2), λ^(−2), 1/λ, exp(±a), ...
    if not resid <= 1e-13 * (1.0 + scale):
        return rules, logs
    if rules[1] == SAME0:
        rules[2] = INCOMPRESSIBLE  # λ2 = λ1: λ3 = λ^−2
    elif rules[1] == ONE:
        rules[2] = INV  # λ2 = 1: λ3 = 1/λ
    elif rules[2] == ONE:
        rules[1] = INV  # λ3 = 1: λ2 = 1/λ1
    elif rules[2] == SAME1:
        rules[1] = RSQRT  # λ2 = λ3 = λ1^(−1/2)
    elif rules[1] == EXP and rules[2] == EXP:
        rules[2] = INCOMPRESSIBLE  # λ2 its own exp: λ3 = 1/(λ1 λ2)
    return rules, logs


def _sums(logs, rules, big, mu, alpha, out):  # pragma: no cover - compiled
    """out[k, p, s] = Σ_t (2 μ[p, t]/α[p, t]) λk[s]^α[p, t] for the stretches with a row
    (a term with μ = 0 adds nothing, whatever its power).

    A term whose |α| max|ln λ| reaches SAFE_EXPONENT (or whose α is NaN) takes every
    power by its own exp: the choice is the term's own, so that a parameter set's sums
    never depend on the other sets evaluated with it.
    """
    P, T = mu.shape
    m = logs.shape[1]
    for p in range(P):
        for s in range(m):
            a0 = 0.0
            a1 = 0.0
            a2 = 0.0
            for t in range(T):
                if mu[p, t] == 0.0:
                    continue  # no share (the admissible set's rows are one term each)
                al = alpha[p, t]
                c = 2.0 * mu[p, t] / al
                r1 = rules[1]
                r2 = rules[2]
                if not abs(al) * big < SAFE_EXPONENT:
                    # the derived powers could overflow where λ^α itself does not
                    if r1 == RSQRT or r1 == INV:
                        r1 = EXP
                    if r2 == INV or r2 == INCOMPRESSIBLE:
                        r2 = EXP
                e0 = np.exp(al * logs[0, s])
                if r1 == EXP:
                    e1 = np.exp(al * logs[1, s])
                elif r1 == RSQRT:
                    e1 = 1.0 / np.sqrt(e0)
                elif r1 == INV:
                    e1 = 1.0 / e0
                elif r1 == SAME0:
                    e1 = e0
                else:  # ONE
                    e1 = 1.0
                if r2 == EXP:
                    e2 = np.exp(al * logs[2, s])
                elif r2 == INCOMPRESSIBLE:
                    e2 = 1.0 / (e0 * e1)
                elif r2 == INV:
                    e2 = 1.0 / e0
                elif r2 == SAME0:
                    e2 = e0
                elif r2 == SAME1:
                    e2 = e1
                else:  # ONE
                    e2 = 1.0
                a0 += c * e0
                a1 += c * e1
                a2 += c * e2
            out[0, p, s] = a0
            out[1, p, s] = a1
            out[2, p, s] = a2


def _plan(lam: list) -> tuple:
    """:func:`stretch_plan` of ``lam`` (rules, ln λk), its largest |ln λ|, and the kernel's
    arguments (ln λk stacked, the rules' codes); remembered for arrays that cannot change
    (a batch's samples, the stability grid: :mod:`vhfit._fixed`)."""
    def plan():
        rules, logs = stretch_plan(*lam)
        return (rules, max(float(np.max(np.abs(v), initial=0.0)) for v in logs),
                np.stack(logs), np.array(rules, dtype=np.int64))

    return remembered("ogden plan", tuple(lam), plan)


_COMPILED: list = []
_LOCK = threading.Lock()


def _compiled_sums():
    """:func:`_sums` compiled by numba (from its cache), on first use: numba's import
    takes a fifth of a second that a fit with another law need not pay."""
    if not _COMPILED:
        with _LOCK:
            if not _COMPILED:
                from numba import njit

                _COMPILED.append(njit(cache=True, error_model="numpy")(_sums))
    return _COMPILED[0]


def ogden_sums(l1, l2, l3, mus, alphas) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """λk ∂W/∂λk = Σ_p (2μp/αp) λk^αp, k = 1, 2, 3, of an n-term Ogden law.

    Parameters
    ----------
    l1, l2, l3 : array_like, shape (m,)
        Principal stretches, one value per sample (any other shape: the numpy form).
    mus, alphas : sequence of array_like
        The terms' constants, each a scalar or a column (P, 1).

    Returns
    -------
    three ndarrays, (P, m)
        A stretch equal to an earlier one gets the earlier one's array.

    Examples
    --------
    One term, μ = 0.5 and α = 2 (neo-Hooke), at λ = (4, 1/2, 1/2): μ λk², to rounding

    >>> [round(float(v[0]), 12) for v in ogden_sums([4.0], [0.5], [0.5], [0.5], [2.0])]
    [8.0, 0.125, 0.125]
    """
    lam = [np.asarray(v) for v in (l1, l2, l3)]
    consts = [np.asarray(v) for v in (*mus, *alphas)]
    if lam[0].ndim != 1 or any(v.shape != lam[0].shape or v.dtype.kind != "f" for v in lam):
        return _numpy_sums(lam, mus, alphas)  # other shapes or types (e.g. complex)
    first = consts[0].shape
    if len(first) == 2 and first[1] == 1 and all(
            v.shape == first and v.dtype == np.float64 for v in consts):
        lead = first  # the columns (P, 1) of a population: the common case, no copies
        mu, al = np.hstack(consts[:len(mus)]), np.hstack(consts[len(mus):])
    else:
        lead = np.broadcast_shapes(*(v.shape for v in consts))
        if (not (lead == () or (len(lead) == 2 and lead[1] == 1))
                or any(v.dtype.kind != "f" for v in consts)):
            return _numpy_sums(lam, mus, alphas)
        P = lead[0] if lead else 1
        cols = [np.broadcast_to(v, lead).reshape(P) for v in consts]
        mu, al = np.column_stack(cols[:len(mus)]), np.column_stack(cols[len(mus):])
    rules, big, logs, codes = _plan(lam)
    out = np.empty((3, mu.shape[0], lam[0].size))
    _compiled_sums()(logs, codes, big, mu, al, out)
    res = [out[0], out[1], out[2]] if lead else [out[0, 0], out[1, 0], out[2, 0]]
    for k in (1, 2):
        if rules[k] in (SAME0, SAME1):
            res[k] = res[0 if rules[k] == SAME0 else 1]
    return res[0], res[1], res[2]


def _numpy_sums(lam, mus, alphas):
    """The same sums by numpy broadcasting (any shapes), one exp per term and stretch."""
    out = []
    for la in lam:
        lnl = np.log(la)
        acc = 0.0
        for mu, alpha in zip(mus, alphas):
            acc = acc + 2 * mu / alpha * np.exp(alpha * lnl)
        out.append(acc)
    return tuple(out)
