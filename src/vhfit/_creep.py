"""Stress-controlled histories (creep) of a visco-hyperelastic model (docs/theory.md §15).

A creep test holds a stress σ* from t = 0 on and measures the stretch. The model's
stress is a functional of the stretch path, σ(t) = σ_h(λ(t)) + Σ_i G_i h_i(t), and its
state is the recursion's running integrals R_k,i (:func:`vhfit._kernels.advance`), so
the test is stepped in time: at each node t_(n+1) of a fixed grid the one unknown
λ_(n+1) solves the scalar equation

    σ(λ_(n+1); R_n) = σ*,

the path over the step interpolating the nodes. :class:`MaterialPoint` is the
material-point contract (state in; stress and new state out) of one parameter set in
one test, written with the model's own formulation (its factors and weights) and the
kernel's own step; :func:`creep` steps it.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from vhfit import _kernels, modes

__all__ = ["MaterialPoint", "creep_grid", "creep"]

#: Nodes of the last steps the path through a step interpolates (the new node too):
#: a cubic, so that the path's error is fourth order in the step like the kernel's.
ORDER = 3

#: The stretches a root is looked for in: beyond them the law "cannot carry" the stress.
_LN_LIMIT = np.log(1e3)


class MaterialPoint:
    """One parameter set of a model in a one-stretch test: state in, stress and state out.

    The state of a Prony series is its recursion: the running integrals (R_0, R_1) of
    every term (docs/theory.md §6, §13), shape (2, N).

    Parameters
    ----------
    model : ViscoHyperelastic
    x : ndarray
        One checked parameter set.
    deformation : str
        A test in principal axes driven by λ1 alone (uniaxial, equibiaxial, planar...).
    measure : {"true", "engineering"}
    """

    def __init__(self, model, x, deformation: str, measure: str):
        self.law = model.hyperelastic
        self.form = model._formulation
        hyper, G, tau = model.split(x)
        self.hyper = hyper[None, :]
        self.E_inf = np.atleast_1d(model.long_term_modulus(x))
        self.G, self.tau = np.asarray(G, dtype=np.float64), np.asarray(tau, dtype=np.float64)
        self.deformation = deformation
        self.test = modes.get_deformation(deformation)
        self.nominal = measure == "engineering"

    def factors(self, lam) -> tuple[np.ndarray, np.ndarray]:
        """f_0, f_1 of the model's formulation at stretches ``lam`` (1-D)."""
        lam = np.asarray(lam, dtype=np.float64)
        with np.errstate(all="ignore"):
            f0, f1 = self.form.factors(self.law, self.hyper, self.E_inf, self.deformation, lam)
        return np.reshape(f0, -1), np.reshape(f1, -1)

    def _stress(self, lam: float, R0, R1) -> float:
        """σ = σ_h + Σ G_i (c_0 R_0,i + c_1 R_1,i) at λ, in the point's measure."""
        x1 = np.array([lam])
        with np.errstate(all="ignore"):
            s = float(np.reshape(modes.long_term_stress(self.law, self.hyper[0],
                                                        self.deformation, x1), -1)[0])
            c = np.reshape(self.form.weights(self.deformation, x1), -1)
            s += float(np.dot(self.G, c[0] * R0 + c[1] * R1))
            if self.nominal:
                s /= float(self.test.loaded_stretch(x1)[0])
        return s

    def start(self, lam: float) -> tuple[float, np.ndarray]:
        """The stress of a jump from rest to ``lam`` at t = 0, and the state after it.

        What the recursion gives for a step: R_k,i = f_k(λ), so h_i = ŝ(λ) in the
        hereditary formulation (the instantaneous law σ_h/g∞).
        """
        f0, f1 = self.factors([lam])
        state = np.stack([np.full(self.tau.size, f0[0]), np.full(self.tau.size, f1[0])])
        return self._stress(lam, state[0], state[1]), state

    def step(self, state: np.ndarray, lam_samples, h: float) -> tuple[float, np.ndarray]:
        """The stress at a step's end and the state there.

        ``lam_samples`` (5,): the stretch at the step's Gauss–Lobatto points
        (:data:`vhfit._kernels.LOBATTO`), the last one its end; ``h`` the step length.
        """
        f0, f1 = self.factors(lam_samples)
        R0, R1 = _kernels.advance(state[0], state[1], f0, f1, h, self.tau)
        return self._stress(float(lam_samples[-1]), R0, R1), np.stack([R0, R1])


# ----------------------------------------------------------------------- the grid
def creep_grid(time: np.ndarray, rtol: float) -> tuple[np.ndarray, np.ndarray]:
    """The internal time grid of a creep test and the node of each output time.

    From the output times and the accuracy alone (never from a parameter set): nodes
    uniform in ln t, ``per_decade(rtol)`` a decade, from t_0 = rtol^(1/2) times the
    first positive output time up to the last (the creep is fastest right after the
    load: a relaxation time below t_0 has relaxed, to e^(−1/rtol^(1/2)), before the
    first output), every output time a node (a log node closer than a quarter step to
    one is dropped), and t = 0.

    Returns
    -------
    t : ndarray
        Node times, t[0] = 0, increasing.
    idx : ndarray of int
        The node of each output time.
    """
    pos = time[time > 0]
    if not pos.size:
        return np.zeros(1), np.zeros(time.size, dtype=np.int64)
    t0, t1 = float(pos.min()) * rtol**0.5, float(pos.max())
    m = per_decade(rtol)
    n = max(1, int(np.ceil(m * np.log10(t1 / t0))))
    logs = t0 * (t1 / t0) ** (np.arange(n + 1) / n)
    out = np.unique(pos)
    # a log node too near an output time would make a tiny step: drop it
    j = np.clip(np.searchsorted(out, logs), 1, out.size) - 1
    near = np.minimum(np.abs(logs - out[j]),
                      np.abs(logs - out[np.minimum(j + 1, out.size - 1)]))
    logs = logs[near > 0.25 * (10 ** (1 / m) - 1) * logs]
    t = np.unique(np.concatenate([[0.0], logs, out]))
    t = t[t <= t1]
    return t, np.searchsorted(t, time)


def per_decade(rtol: float) -> int:
    """Grid nodes per decade of time for a relative accuracy ``rtol`` of the stretch.

    The path's cubic and the kernel's quartic make the error fourth order in the step
    ratio q = 10^(1/m) − 1; m = 6 rtol^(−1/4) (190 at rtol = 1e-6) keeps it below rtol
    at the fastest creep (tests/test_creep.py).
    """
    return max(20, int(np.ceil(6.0 * rtol ** -0.25)))


# ------------------------------------------------------------------- the stepping
def _lagrange(nodes: np.ndarray, at: np.ndarray) -> np.ndarray:
    """(len(at), len(nodes)): the Lagrange basis of ``nodes`` at the points ``at``."""
    B = np.ones((at.size, nodes.size))
    for j, tj in enumerate(nodes):
        for k, tk in enumerate(nodes):
            if k != j:
                B[:, j] *= (at - tk) / (tj - tk)
    return B


def _secant(g, guess: float) -> float | None:
    """The root of ``g`` by secant steps from ``guess`` (a few evaluations where the
    residual is smooth), or None when they do not settle to the last bits."""
    x0, g0 = guess, g(guess)
    if not np.isfinite(g0):
        return None
    if g0 == 0.0:
        return x0
    x1 = x0 * (1.0 + 1e-7)
    for _ in range(8):
        g1 = g(x1)
        if not np.isfinite(g1) or g1 == g0:
            return x1 if g1 == 0.0 else None
        x0, g0, x1 = x1, g1, x1 - g1 * (x1 - x0) / (g1 - g0)
        if not x1 > 0:
            return None
        if abs(x1 - x0) <= 4.0 * np.finfo(float).eps * x1:
            return x0  # as good to the last bits, and its state is known
    return None


def _solve(g, a: float, guess: float, what: str) -> float:
    """The root of ``g`` (a stress residual, increasing in λ) near ``guess``: secant
    steps, or else bracketed from ``a`` outwards in ln λ and found by Brent's method; a
    one-line error if no root lies within λ in [1e-3, 1e3]."""
    root = _secant(g, guess)
    if root is not None:
        return root
    ga = g(a)
    if ga == 0.0:
        return a
    up = ga < 0.0  # the stress grows with the stretch
    d = max(abs(np.log(guess / a)) * 2.0, 1e-9)
    lo = a
    while True:
        ln_b = np.log(lo) + (d if up else -d)
        if abs(ln_b) > _LN_LIMIT:
            ln_b = np.copysign(_LN_LIMIT, ln_b)
        b = float(np.exp(ln_b))
        gb = g(b)
        if gb == 0.0:
            return b
        if np.isfinite(gb) and (gb > 0.0) == up:
            break
        if not np.isfinite(gb):  # past the law's domain (a locking stretch): come back
            d *= 0.5
            if d < 1e-14:
                raise ValueError(f"{what}: the law is undefined just past λ = {lo:.6g}")
            continue
        if abs(ln_b) >= _LN_LIMIT:
            raise ValueError(f"{what}: no stretch in [1e-3, 1e3] gives it")
        lo = b
        d *= 4.0
    x0, x1 = (lo, b) if lo < b else (b, lo)
    return brentq(g, x0, x1, xtol=1e-15 * x0, rtol=4.0 * np.finfo(float).eps, maxiter=200)


def _path(lam_start: float, past: np.ndarray, new: np.ndarray, lam_end: float) -> np.ndarray:
    """The stretch at a step's Gauss–Lobatto points: the interpolant through the last
    nodes and the step's end, its two nodes exactly."""
    samples = past + new * lam_end
    samples[0], samples[-1] = lam_start, lam_end
    return samples


def creep(point: MaterialPoint, stress: float, time: np.ndarray, rtol: float) -> np.ndarray:
    """λ1 at ``time`` of a creep test of ``point`` under ``stress`` held from t = 0.

    See :meth:`vhfit.model.ViscoHyperelastic.creep`.
    """
    t, idx = creep_grid(time, rtol)
    lam = np.empty(t.size)
    scale = max(abs(stress), 1e-300)  # residuals relative to the load (well scaled)
    lam[0] = _solve(lambda x: (point.start(x)[0] - stress) / scale, 1.0,
                    1.0 + 1e-3 * np.sign(stress),
                    f"σ = {stress:g} MPa applied at once (the instantaneous response)")
    state = point.start(lam[0])[1]
    for n in range(t.size - 1):
        h = t[n + 1] - t[n]
        k = max(0, n - ORDER + 1)  # the first node the step's interpolant passes through
        nodes = t[k:n + 2]
        B = _lagrange(nodes, t[n] + _kernels.LOBATTO * h)
        past, new = B[:, :-1] @ lam[k:n + 1], B[:, -1]
        guess = float(_lagrange(nodes[:-1], t[n + 1:n + 2])[0] @ lam[k:n + 1])
        start = float(lam[n])
        tried: dict[float, np.ndarray] = {}  # the state at each stretch tried

        def g(x: float, state=state, past=past, new=new, start=start, h=h,
              tried=tried) -> float:
            s, tried[x] = point.step(state, _path(start, past, new, x), h)
            return (s - stress) / scale

        lam[n + 1] = _solve(g, start, guess if guess > 0 else start,
                            f"σ = {stress:g} MPa held at t = {t[n + 1]:g} s (the model "
                            "creeps without bound: its long-term law cannot carry it)")
        if lam[n + 1] not in tried:  # a root the solver did not evaluate
            g(lam[n + 1])
        state = tried[lam[n + 1]]
    return lam[idx]
