"""The integrator of the viscous networks: L-stable SDIRK on principal log creep stretches.

State of network k: its principal logarithmic creep stretches e_k = ln λ_cr,k (fixed
principal axes, Σ e = 0: the creep is isochoric) and its accumulated equivalent creep
strain ε̄_k. With L = ln λ the total log stretches and w_k = L − e_k the elastic ones,

    de_k/dt = ε̇_cr(q̃_k, λ_cr,k, ε̄_k) (3/2) τ'_k / q̃_k,    dε̄_k/dt = ε̇_cr,

τ_k = s_k λ ∂W/∂λ at exp(w_k). e lives in the symmetry of the test: one coordinate when
two total stretches are equal (uniaxial, equibiaxial), two otherwise.

Time stepping: the 5-stage, order-4, L-stable, stiffly accurate SDIRK of Hairer and
Wanner (Solving ODEs II, Table IV.6.5, γ = 1/4), with its embedded order-3 solution for
an error estimate. Each stage is a backward-Euler step of length γh from a known start,
solved by Newton's method per network in a variable in which it is nearly linear
whatever the stiffness (:func:`_stage`). Steps never cross a data time (the stretch is
linear in time between data points, so the right-hand side is smooth within a step); each
curve and parameter set takes its own step sizes, so a result never depends on what else
was evaluated with it. The local error of e and ε̄ is held to ``atol + rtol |y|``.

Stress control (creep) is a DAE: at every stage the total stretch is found, by Newton's
method around the networks' stage solves, so that the stress equals the target.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vhfit._kirchhoff import constant_columns, principal_kirchhoff
from vhfit.hyperelastic import Hyperelastic
from vhfit.modes import get_deformation
from vhfit.viscous.flows import Flow

#: Default tolerances of the local error of ln λ_cr and ε̄ per step (absolute, relative):
#: they keep the stresses within 1e-6 relative of a tight reference (docs/theory.md).
ATOL, RTOL = 1e-11, 1e-9

# Hairer–Wanner SDIRK4: γ = 1/4, c = (1/4, 3/4, 11/20, 1/2, 1), b = last row of A.
_G = 0.25
_C = (0.25, 0.75, 11 / 20, 0.5, 1.0)
_A = ((), (0.5,), (17 / 50, -1 / 25), (371 / 1360, -137 / 2720, 15 / 544),
      (25 / 24, -49 / 48, 125 / 16, -85 / 12))
_BHAT = (59 / 48, -17 / 96, 225 / 32, -85 / 12, 0.0)
_BERR = tuple(b - bh for b, bh in zip(_A[4] + (_G,), _BHAT))  # y − ŷ = h Σ _BERR_i k_i

_VMAX = 700.0       # |v| cap of the stage variable: u or 1 − u below e^-700 is 0 or 1
_NEWTON = 60        # iterations per stage solve before the step is retried shorter
_MAX_STEPS = 2_000_000


# ------------------------------------------------------------------ kinematics
@dataclass(frozen=True)
class Frame:
    """The coordinates z of a principal log-stretch deviator e = basis @ z.

    ``metric`` gives the equivalent strain: sqrt(z·metric·z) = sqrt(2/3 e:e);
    ``pick`` the principal components that are z (so z* = L[pick] relaxes a network).
    """

    basis: np.ndarray
    pick: tuple[int, ...]

    @property
    def d(self) -> int:
        return len(self.pick)

    @property
    def metric(self) -> np.ndarray:
        return (2.0 / 3.0) * self.basis.T @ self.basis


_UNIAXIAL = Frame(np.array([[1.0], [-0.5], [-0.5]]), (0,))
_EQUIBIAXIAL = Frame(np.array([[1.0], [1.0], [-2.0]]), (0,))
_GENERAL = Frame(np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0]]), (0, 1))


def frame_of(deformation: str) -> Frame:
    """The smallest frame the test's symmetry allows (an isotropic flow keeps it):
    λ2 = λ3 -> one coordinate like uniaxial, λ1 = λ2 -> like equibiaxial, else two."""
    test = get_deformation(deformation)
    if test.shear:
        raise ValueError(f"deformation {test.name!r}: the networks are integrated in fixed "
                         "principal axes, and simple shear rotates them (not supported)")
    if test.refusal:
        raise ValueError(test.refusal)
    l1, l2, l3 = (float(np.asarray(v)) for v in test.stretches(np.float64(1.3),
                                                                np.float64(1.1)))
    if np.isclose(l2, l3, rtol=1e-12):
        return _UNIAXIAL
    if np.isclose(l1, l2, rtol=1e-12):
        return _EQUIBIAXIAL
    return _GENERAL


def log_stretches(deformation: str, x1, x2=None) -> np.ndarray:
    """ln of the test's principal stretches, shape (..., 3)."""
    lam = get_deformation(deformation).stretches(np.asarray(x1, dtype=np.float64), x2)
    return np.stack([np.log(np.broadcast_to(v, np.shape(x1))) for v in lam], axis=-1)


# ------------------------------------------------------------------ one network
@dataclass
class _Net:
    """One network over n rows: its flow, s_k (n, 1) and constant columns (n, 1)."""

    flow: Flow
    ratio: np.ndarray
    cols: list

    def rows(self, idx) -> _Net:
        return _Net(self.flow, self.ratio[idx], [c[idx] for c in self.cols])


def _tau(law: Hyperelastic, lcols, ratio, le):
    """s τ(exp(le)) of the law at elastic log stretches le, (n, j, 3) or (n, 3), for the
    law's constant columns (n, 1) and s (n, 1) or (n,); the shape of le."""
    flat = le.ndim == 2
    le3 = le[:, None, :] if flat else le
    r = ratio if ratio.ndim == 2 else ratio[:, None]
    t = principal_kirchhoff(law, lcols, *(np.exp(le3[..., i]) for i in range(3)))
    out = r[..., None] * np.stack(np.broadcast_arrays(*t), axis=-1)
    return out[:, 0, :] if flat else out


def _flow_terms(law, lcols, net: _Net, frame: Frame, zstar, w, eb_s, ws):
    """At elastic coordinates w (n, j, d): τ (n, j, 3), q̃ (n, j), the flow direction n in
    z-coordinates (n, j, d; unit equivalent strain) and the rate ε̇_cr (n, j)."""
    B = frame.basis
    le = w @ B.T
    tau = _tau(law, lcols, net.ratio, le)
    dev = tau - tau.mean(axis=-1, keepdims=True)
    q = np.sqrt(1.5 * np.sum(dev * dev, axis=-1))
    with np.errstate(divide="ignore", invalid="ignore"):
        direction = (1.5 * dev / q[..., None])[..., list(frame.pick)]
        e = (zstar[:, None, :] - w) @ B.T
        lam_cr = np.sqrt(np.mean(np.exp(2.0 * e), axis=-1))
        inc = ws[:, None, :] - w
        eb = eb_s[:, None] + np.sqrt(np.maximum(
            np.einsum("...i,ij,...j->...", inc, frame.metric, inc), 0.0))
        rate = net.flow.rate(q, lam_cr, np.maximum(eb, 0.0), *net.cols)
    return tau, q, direction, np.broadcast_to(rate, q.shape)


def _stage(law, lcols, net: _Net, frame: Frame, zstar, ws, eb_s, hg, v0):
    """One backward-Euler stage of one network: w = ws − hg ε̇(w) n(w).

    ws (n, d) is the elastic strain if the network did not flow (the trial), hg (n,) the
    stage's step γh. The solution is w = (1 − u)(ws + s t), t ⊥ ws in the equivalent
    metric with |t| = |ws|: u ∈ (0, 1) is the share of ws the step relaxes (u → 1 for a
    stiff flow, u → 0 for a slow one) and s the turn of the elastic strain (0 in the
    one-coordinate tests). Newton's method works on v = logit u and s with

        H1 = ln(u |ws|) − ln(hg ε̇ cos θ),   H2 = (1 − u) s + u tan θ,

    θ the angle between the flow direction and ws. H1 is asymptotically linear in v at
    both ends for power-law and exponential flows, so neither a rate over many decades
    nor a large stress exponent, nor the STRAIN law's singular rate at ε̄ = 0 (ε̄ grows
    with u from the stage's start), slows the solve. In one coordinate H1 is monotone and
    its sign brackets the root (bisection when Newton leaves the bracket).

    Returns w (n, d), τ (n, 3) at w, v (n,) for the next warm start, and ok (n,).
    """
    n, d = ws.shape
    M = frame.metric
    norm = np.sqrt(np.einsum("ni,ij,nj->n", ws, M, ws))
    live = (norm > 1e-300) & (hg > 0.0)
    v = np.clip(np.where(np.isfinite(v0), v0, 0.0), -_VMAX, _VMAX)
    s = np.zeros(n)
    if d == 2:
        Mw = ws @ M
        t = np.stack([-Mw[:, 1], Mw[:, 0]], axis=-1)
        tn = np.sqrt(np.einsum("ni,ij,nj->n", t, M, t))
        with np.errstate(invalid="ignore", divide="ignore"):
            t = t * (norm / tn)[:, None]
        t = np.where(live[:, None], t, 0.0)
    lo, hi = np.full(n, -np.inf), np.full(n, np.inf)
    done = ~live
    ok = np.ones(n, bool)
    dv, ds = 1e-6, 1e-7

    def residual(vv, ss, rows):
        """H1, H2 at points vv, ss (r, j) of the rows."""
        u = 1.0 / (1.0 + np.exp(-vv))
        one_u = 1.0 / (1.0 + np.exp(vv))
        target = ws[rows][:, None, :]
        if d == 2:
            target = target + ss[..., None] * t[rows][:, None, :]
        w = one_u[..., None] * target
        tau, q, direc, rate = _flow_terms(law, [c[rows] for c in lcols], net.rows(rows),
                                          frame, zstar[rows], w, eb_s[rows], ws[rows])
        nr = norm[rows][:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            cos = np.einsum("rjd,de,re->rj", direc, M, ws[rows]) / nr
            h1 = np.log(u * nr) - np.log(hg[rows][:, None] * rate * cos)
            h1 = np.where(q > 0.0, h1, np.inf)  # no stress: the root has more relaxation
            if d == 1:
                return h1, None, w, tau
            sin = np.einsum("rjd,de,re->rj", direc, M, t[rows]) / nr
            h2 = one_u * ss + u * sin / cos
        return h1, h2, w, tau

    for _ in range(_NEWTON):
        rows = np.nonzero(~done)[0]
        if rows.size == 0:
            break
        vr, sr = v[rows], s[rows]
        if d == 1:
            pv = np.stack([vr, vr + dv], axis=1)
            h1, _, _, _ = residual(pv, None, rows)
            f, fv = h1[:, 0], (h1[:, 1] - h1[:, 0]) / dv
            bad = np.isnan(f)
            hi[rows] = np.where(f > 0, vr, hi[rows])
            lo[rows] = np.where(f < 0, vr, lo[rows])
            with np.errstate(divide="ignore", invalid="ignore"):
                step = -f / fv
            new = vr + np.clip(np.where(np.isfinite(step), step, 0.0), -20.0, 20.0)
            l, h = lo[rows], hi[rows]
            outside = ~np.isfinite(step) | (fv <= 0) | (new <= l) | (new >= h)
            bis = np.where(np.isfinite(l) & np.isfinite(h), 0.5 * (l + h),
                           np.where(np.isfinite(h), h - 4.0, l + 4.0))
            new = np.where(outside, bis, new)
            new = np.clip(new, -_VMAX, _VMAX)
            conv = (np.abs(new - vr) <= 1e-11) | (f == 0)
            # a root past the cap: u or 1 − u is below e^-700 (0 or 1 in double)
            conv |= ((f > 0) & (vr <= -_VMAX)) | ((f < 0) & (vr >= _VMAX))
            conv |= np.isfinite(l) & np.isfinite(h) & (h - l <= 1e-11)
            v[rows] = new
        else:
            pv = np.stack([vr, vr + dv, vr], axis=1)
            ps = np.stack([sr, sr, sr + ds], axis=1)
            h1, h2, _, _ = residual(pv, ps, rows)
            a, b = (h1[:, 1] - h1[:, 0]) / dv, (h1[:, 2] - h1[:, 0]) / ds
            c, e = (h2[:, 1] - h2[:, 0]) / dv, (h2[:, 2] - h2[:, 0]) / ds
            f1, f2 = h1[:, 0], h2[:, 0]
            bad = ~(np.isfinite(f1) & np.isfinite(f2))
            with np.errstate(divide="ignore", invalid="ignore"):
                det = a * e - b * c
                stv = -(e * f1 - b * f2) / det
                sts = -(a * f2 - c * f1) / det
            bad |= ~(np.isfinite(stv) & np.isfinite(sts))
            stv = np.clip(np.where(bad, 0.0, stv), -10.0, 10.0)
            sts = np.clip(np.where(bad, 0.0, sts), -0.5, 0.5)
            new = np.clip(vr + stv, -_VMAX, _VMAX)
            conv = (np.abs(new - vr) <= 1e-11) & (np.abs(sts) <= 1e-12)
            conv |= ((f1 > 0) & (vr <= -_VMAX)) | ((f1 < 0) & (vr >= _VMAX))
            v[rows], s[rows] = new, sr + sts
        ok[rows[bad]] = False
        done[rows[conv | bad]] = True
    ok &= done
    # the solution and its stress, evaluated at the converged (v, s)
    u_one = np.where(live, 1.0 / (1.0 + np.exp(v)), 1.0)
    target = ws + (s[:, None] * t if d == 2 else 0.0)
    w = u_one[:, None] * target
    le = w @ frame.basis.T
    tau = _tau(law, lcols, net.ratio[:, 0], le)
    ok &= np.all(np.isfinite(tau), axis=-1)
    return w, tau, v, ok


# ------------------------------------------------------------------ the time loop
@dataclass
class _Problem:
    """A batch of n rows: the law, its constant columns (n, 1), the networks, the frame."""

    law: Hyperelastic
    lcols: list
    nets: list
    frame: Frame
    deformation: str

    def rows(self, idx) -> _Problem:
        return _Problem(self.law, [c[idx] for c in self.lcols],
                        [n.rows(idx) for n in self.nets], self.frame, self.deformation)

    @property
    def eq_share(self) -> np.ndarray:
        return 1.0 - sum(n.ratio[:, 0] for n in self.nets)


def _network_solves(P: _Problem, L, Z0, EB0, hg, V):
    """Every network's stage solve at total log stretches L (n, 3); lists per network."""
    zstar = L[:, list(P.frame.pick)]
    out = []
    for k, net in enumerate(P.nets):
        ws = zstar - Z0[k]
        if np.all(hg == 0.0):  # an instantaneous response: no network flows
            w, v, ok = ws, V[k], np.ones(len(ws), bool)
            tau = _tau(P.law, P.lcols, net.ratio[:, 0], ws @ P.frame.basis.T)
        else:
            w, tau, v, ok = _stage(P.law, P.lcols, net, P.frame, zstar, ws, EB0[k], hg, V[k])
        out.append((zstar - w, ws - w, tau, v, ok))
    return out


def _loaded(P: _Problem, L, taus):
    """σ11 = Σ τ1 − τ_c of the equilibrium network and the networks (c stress-free)."""
    c = get_deformation(P.deformation).stress_free - 1
    teq = _tau(P.law, P.lcols, P.eq_share, L)
    total = teq[:, 0] - teq[:, c]
    for tau in taus:
        total = total + tau[:, 0] - tau[:, c]
    return total


class _Creep:
    """The stress-controlled stage: the total stretch ln λ1 = x such that σ11 = target."""

    def __init__(self, P: _Problem, target, engineering: bool):
        self.P, self.target, self.engineering = P, target, engineering

    def logs(self, x):
        return log_stretches(self.P.deformation, np.exp(x))

    def solve(self, P, target, x0, Z0, EB0, hg, V, rows=None):
        """Newton on x (finite-difference slope through the networks' stage solves)."""
        n = len(x0)
        x = x0.copy()
        ok = np.ones(n, bool)
        dx = 1e-7
        for _ in range(40):
            xs = np.concatenate([x, x + dx])
            idx = np.concatenate([np.arange(n)] * 2)
            sub = P.rows(idx)
            res = _network_solves(sub, self.logs(xs), [z[idx] for z in Z0],
                                  [e[idx] for e in EB0], hg[idx], [v[idx] for v in V])
            sig = _loaded(sub, self.logs(xs), [r[2] for r in res])
            goal = target[idx] * (np.exp(xs) if self.engineering else 1.0)
            f = sig - goal
            f0, slope = f[:n], (f[n:] - f[:n]) / dx
            good = np.all([r[4][:n] & r[4][n:] for r in res], axis=0) & (slope > 0)
            step = np.where(good, -f0 / np.where(good, slope, 1.0), 0.0)
            step = np.clip(step, -0.25, 0.25)
            x = x + step
            ok &= good
            if np.all((np.abs(step) <= 1e-13 * np.maximum(1.0, np.abs(x))) | ~ok):
                break
        else:
            ok &= np.abs(step) <= 1e-10
        res = _network_solves(P, self.logs(x), Z0, EB0, hg, V)
        for r in res:
            ok &= r[4]
        return x, res, ok


def _run(P: _Problem, time, drive, creep: _Creep | None, rtol, atol):
    """Integrate every row over its time grid; the state at each data time.

    ``drive(rows, t)`` gives the total log stretches (r, 3) at times t (r,) of rows whose
    current data intervals are ``seg[rows]`` (strain control); for creep ``creep`` solves
    the total stretch instead. Returns per data time: the log stretches (n, m, 3) and
    each network's creep coordinates (n, m, d).
    """
    n, m = time.shape
    K, d = len(P.nets), P.frame.d
    Z = [np.zeros((n, d)) for _ in range(K)]
    EB = [np.zeros(n) for _ in range(K)]
    V = [np.zeros(n) for _ in range(K)]
    Lout = np.zeros((n, m, 3))
    Zout = np.zeros((K, n, m, d))
    seg = np.zeros(n, int)
    if creep is None:
        Lout[:, 0] = drive(np.arange(n), seg, time[:, 0])
        X = None
    else:
        # the instantaneous response: every network elastic from λ_cr = 1
        X, _, ok = creep.solve(P, creep.target, _initial_guess(P, creep), Z, EB,
                               np.zeros(n), V)
        if not np.all(ok):
            raise ValueError("the instantaneous response to the creep load was not found "
                             "(the law cannot carry this stress)")
        Lout[:, 0] = creep.logs(X)
    tc = time[:, 0].copy()
    span = np.maximum(time[:, -1] - time[:, 0], np.finfo(float).tiny)
    h = np.maximum(np.diff(time, axis=1).max(axis=1) if m > 1 else span, 1e-300)
    steps = 0
    while True:
        # data points reached (zero-length intervals are jumps: no time passes)
        while True:
            at = (seg < m - 1) & (time[np.arange(n), np.minimum(seg + 1, m - 1)] <= tc)
            if not np.any(at):
                break
            r = np.nonzero(at)[0]
            seg[r] += 1
            if creep is None:
                Lout[r, seg[r]] = drive(r, seg[r] - 1, time[r, seg[r]])
            else:
                Lout[r, seg[r]] = creep.logs(X[r])
            for k in range(K):
                Zout[k, r, seg[r]] = Z[k][r]
        rows = np.nonzero(seg < m - 1)[0]
        if rows.size == 0:
            break
        steps += 1
        if steps > _MAX_STEPS:
            raise RuntimeError("the network integrator took too many steps")
        t_end = time[rows, seg[rows] + 1]
        hr = np.minimum(h[rows], t_end - tc[rows])
        last = hr >= t_end - tc[rows]
        sub = P.rows(rows)
        kz = [[None] * 5 for _ in range(K)]
        ke = [[None] * 5 for _ in range(K)]
        ok = np.ones(rows.size, bool)
        hg = _G * hr
        Vr = [v[rows] for v in V]
        Xs = None if X is None else X[rows].copy()
        for i in range(5):
            Z0 = [Z[k][rows] + hr[:, None] * sum((a * kz[k][j] for j, a in enumerate(_A[i])),
                                                 np.zeros((rows.size, d))) for k in range(K)]
            E0 = [EB[k][rows] + hr * sum((a * ke[k][j] for j, a in enumerate(_A[i])),
                                         np.zeros(rows.size)) for k in range(K)]
            if creep is None:
                res = _network_solves(sub, drive(rows, seg[rows], tc[rows] + _C[i] * hr),
                                      Z0, E0, hg, Vr)
            else:
                Xs, res, okx = creep.solve(sub, creep.target[rows], Xs, Z0, E0, hg, Vr)
                ok &= okx
            for k, (_, dz, _, v, okk) in enumerate(res):
                with np.errstate(invalid="ignore", divide="ignore"):
                    kz[k][i] = dz / hg[:, None]
                    ke[k][i] = np.sqrt(np.maximum(np.einsum(
                        "ni,ij,nj->n", dz, P.frame.metric, dz), 0.0)) / hg
                Vr[k] = v
                ok &= okk
        err = np.zeros(rows.size)
        newZ, newE = [], []
        for k in range(K):
            z1 = Z[k][rows] + hr[:, None] * sum(b * kz[k][i] for i, b in enumerate(_A[4] + (_G,)))
            e1 = EB[k][rows] + hr * sum(b * ke[k][i] for i, b in enumerate(_A[4] + (_G,)))
            ez = hr[:, None] * sum(b * kz[k][i] for i, b in enumerate(_BERR))
            ee = hr * sum(b * ke[k][i] for i, b in enumerate(_BERR))
            sz = atol + rtol * np.maximum(np.abs(z1), np.abs(Z[k][rows]))
            se = atol + rtol * np.maximum(e1, EB[k][rows])
            with np.errstate(invalid="ignore"):
                err = np.maximum(err, np.max(np.abs(ez) / sz, axis=1))
                err = np.maximum(err, np.abs(ee) / se)
            newZ.append(z1)
            newE.append(e1)
        err = np.where(ok & np.isfinite(err), err, np.inf)
        acc = err <= 1.0
        with np.errstate(divide="ignore"):
            fac = np.where(np.isfinite(err), 0.9 * np.maximum(err, 1e-10) ** -0.25, 0.25)
        h[rows] = hr * np.clip(fac, 0.2, 4.0)
        a = rows[acc]
        for k in range(K):
            Z[k][a] = newZ[k][acc]
            EB[k][a] = newE[k][acc]
            V[k][a] = Vr[k][acc]
        if X is not None:
            X[a] = Xs[acc]
        tc[a] = np.where(last[acc], t_end[acc], tc[a] + hr[acc])
        if np.any(h[rows] < 1e-14 * span[rows]):
            raise RuntimeError("the network integrator could not converge (step size "
                               "underflow): the flow constants are outside what it handles")
    return Lout, Zout


def _initial_guess(P: _Problem, creep: _Creep):
    """x = ln λ1 of the linearised instantaneous response (a start for Newton)."""
    n = len(creep.target)
    dx = 1e-6
    L = creep.logs(np.full(n, dx))
    taus = [_tau(P.law, P.lcols, net.ratio[:, 0], L) for net in P.nets]
    slope = _loaded(P, L, taus) / dx
    return np.clip(creep.target / slope, -0.5, 0.5)


# ------------------------------------------------------------------ the public entry points
def _setup(law, law_params, flows_, ratios, constants, deformation, lead):
    """The problem over the flattened leading shape ``lead``."""
    n = int(np.prod(lead, dtype=int))
    lp = np.broadcast_to(np.asarray(law_params, dtype=np.float64), lead + (law.n_params,))
    lcols = constant_columns(law, lp.reshape(n, law.n_params))
    rs = np.broadcast_to(np.asarray(ratios, dtype=np.float64), lead + (len(flows_),))
    rs = rs.reshape(n, len(flows_))
    nets = []
    for k, (f, c) in enumerate(zip(flows_, constants)):
        cc = np.broadcast_to(np.asarray(c, dtype=np.float64), lead + (f.n_params,))
        cc = cc.reshape(n, f.n_params)
        nets.append(_Net(f, rs[:, k, None], [cc[:, j, None] for j in range(f.n_params)]))
    return _Problem(law, lcols, nets, frame_of(deformation), get_deformation(deformation).name)


def _lead_shape(law, law_params, ratios, constants, flows_, *data):
    shapes = [np.shape(law_params)[:-1], np.shape(ratios)[:-1]]
    shapes += [np.shape(c)[:-1] for c in constants]
    shapes += [np.shape(x)[:-1] for x in data]
    return np.broadcast_shapes(*shapes)


def network_stress(law: Hyperelastic, law_params, flows_: list[Flow], ratios, constants,
                   time, stretch, stretch2=None, *, deformation: str = "uniaxial",
                   measure: str = "true", rtol: float = RTOL,
                   atol: float = ATOL) -> np.ndarray:
    """σ11 along stretch histories for batches of constants (strain control).

    Leading axes of ``law_params`` (..., n_law), ``ratios`` (..., K), each of
    ``constants`` (..., n_k), ``time`` and ``stretch`` (..., m) broadcast together.
    The stretch is linear in time between data points; the networks start at λ_cr = 1
    at time[..., 0] (a stretch there other than 1 is applied at once).
    """
    t = np.asarray(time, dtype=np.float64)
    x1 = np.asarray(stretch, dtype=np.float64)
    x2 = None if stretch2 is None else np.asarray(stretch2, dtype=np.float64)
    lead = _lead_shape(law, law_params, ratios, constants, flows_, t, x1,
                       *([] if x2 is None else [x2]))
    m = np.broadcast_shapes(t.shape, x1.shape)[-1]
    n = int(np.prod(lead, dtype=int))
    T = np.broadcast_to(t, lead + (m,)).reshape(n, m)
    X1 = np.broadcast_to(x1, lead + (m,)).reshape(n, m)
    X2 = None if x2 is None else np.broadcast_to(x2, lead + (m,)).reshape(n, m)
    if np.any(np.diff(T, axis=1) < 0) or not np.all(np.isfinite(T)):
        raise ValueError("time must be finite and non-decreasing")
    if not (np.all(X1 > 0) and (X2 is None or np.all(X2 > 0))):
        raise ValueError("stretches must be positive")
    P = _setup(law, law_params, flows_, ratios, constants, deformation, lead)

    def drive(rows, j, tt):
        t0, t1 = T[rows, j], T[rows, np.minimum(j + 1, m - 1)]
        with np.errstate(invalid="ignore", divide="ignore"):
            f = np.where(t1 > t0, (tt - t0) / (t1 - t0), 1.0)
        a = X1[rows, j] + f * (X1[rows, np.minimum(j + 1, m - 1)] - X1[rows, j])
        b = None if X2 is None else X2[rows, j] + f * (X2[rows, np.minimum(j + 1, m - 1)]
                                                        - X2[rows, j])
        return log_stretches(P.deformation, a, b)

    Lout, Zout = _run(P, T, drive, None, rtol, atol)
    sig = _stress_at(P, Lout, Zout)
    if measure == "engineering":
        sig = sig / np.exp(Lout[..., 0])
    return sig.reshape(lead + (m,))


def _stress_at(P: _Problem, Lout, Zout):
    """σ11 (n, m) from the log stretches and the networks' creep coordinates."""
    n, m, _ = Lout.shape
    idx = np.repeat(np.arange(n), m)
    sub = P.rows(idx)
    L = Lout.reshape(n * m, 3)
    zstar = L[:, list(P.frame.pick)]
    taus = [_tau(P.law, sub.lcols, net.ratio[:, 0],
                 (zstar - Zout[k].reshape(n * m, -1)) @ P.frame.basis.T)
            for k, net in enumerate(sub.nets)]
    return _loaded(sub, L, taus).reshape(n, m)


def network_creep(law: Hyperelastic, law_params, flows_: list[Flow], ratios, constants,
                  stress, time, *, deformation: str = "uniaxial", measure: str = "true",
                  rtol: float = RTOL, atol: float = ATOL) -> np.ndarray:
    """λ1 under a load held from t = 0 (stress control), for batches of constants."""
    t = np.asarray(time, dtype=np.float64)
    S = np.asarray(stress, dtype=np.float64)
    lead = _lead_shape(law, law_params, ratios, constants, flows_, t, S[..., None])
    m = t.shape[-1]
    n = int(np.prod(lead, dtype=int))
    T = np.broadcast_to(t, lead + (m,)).reshape(n, m)
    if np.any(np.diff(T, axis=1) < 0) or np.any(T[:, 0] < 0) or not np.all(np.isfinite(T)):
        raise ValueError("creep times must be finite, non-negative and non-decreasing")
    P = _setup(law, law_params, flows_, ratios, constants, deformation, lead)
    if P.frame.d != 1 and get_deformation(deformation).second_stretch:
        raise ValueError(f"creep in {deformation!r}: a held load needs a one-stretch test "
                         "(uniaxial, equibiaxial or planar)")
    target = np.broadcast_to(S, lead).reshape(n).astype(np.float64)
    # the load acts from t = 0: integrate from 0 and report at the asked times
    T0 = np.concatenate([np.zeros((n, 1)), T], axis=1)
    creep = _Creep(P, target, measure == "engineering")
    Lout, _ = _run(P, T0, None, creep, rtol, atol)
    return np.exp(Lout[:, 1:, 0]).reshape(lead + (m,))


def _model_args(model):
    from vhfit import hyperelastic
    from vhfit.viscous import flows

    law = hyperelastic.get(model.law)
    fl = [flows.get(n.flow) for n in model.networks]
    return (law, np.array(model.law_params), fl, np.array([n.ratio for n in model.networks]),
            [np.array(n.constants) for n in model.networks])


def _check_measure(measure: str) -> None:
    if measure not in ("true", "engineering"):
        raise ValueError(f"measure {measure!r}: use 'true' (Cauchy) or 'engineering' (nominal)")


def model_stress(model, time, stretch, *, deformation, stretch2, measure):
    _check_measure(measure)
    t = np.asarray(time, dtype=np.float64)
    x = np.asarray(stretch, dtype=np.float64)
    if t.ndim != 1 or x.shape != t.shape:
        raise ValueError(f"time and stretch must be 1-D of one length, got {t.shape} and "
                         f"{x.shape}")
    if get_deformation(deformation).second_stretch and stretch2 is None:
        raise ValueError(f"deformation {deformation!r} needs stretch2 (λ2 at each time)")
    return network_stress(*_model_args(model), t, x, stretch2, deformation=deformation,
                          measure=measure)


def model_creep(model, stress, time, *, deformation, measure):
    _check_measure(measure)
    t = np.asarray(time, dtype=np.float64)
    if t.ndim != 1:
        raise ValueError(f"time must be 1-D, got shape {t.shape}")
    if np.ndim(stress) != 0 or not np.isfinite(stress):
        raise ValueError(f"stress must be one finite number, got {stress!r}")
    return network_creep(*_model_args(model), float(stress), t, deformation=deformation,
                         measure=measure)
