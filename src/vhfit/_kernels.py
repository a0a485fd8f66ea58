"""The hot loop: Prony overstress of the corrected Eq. 19 by an O(n·N) recursion.

Integration by parts of the conditioned form (docs/theory.md §5) gives the overstress of
branch i as

    h_i(t) = (2/3) λ(t)² P_i(t) + (1/3) λ(t)⁻¹ Q_i(t),
    P_i(t) = a(0) e^(−t/τ_i) + ∫_0^t e^(−(t−u)/τ_i) a'(u) du,   a = ŝ λ⁻²,
    Q_i(t) = b(0) e^(−t/τ_i) + ∫_0^t e^(−(t−u)/τ_i) b'(u) du,   b = ŝ λ,

with ŝ = σ_h / E∞. Over a step of length h the states decay by e^(−h/τ) and gain the
step's integral, which is exact for a quartic interpolant of a (and b) through five
Gauss–Lobatto points of the step: with p'(v) = Σ_j d_j v^j, j = 0..3 (v ∈ [0, 1]),

    ∫_0^1 e^(−x(1−v)) p'(v) dv = Σ_j d_j ψ_j(x),   x = h/τ.

A quartic, not a cubic: when τ is far below the step, the overstress is τ times the
slope of the interpolant at the step's end, and that slope is one order less accurate
than the values; with five points it is fourth order, like the values of a cubic.

Nothing is divided by τ (τ → 0 gives x → ∞ and ψ_j → 0; τ → ∞ gives x = 0 and
ψ_j = 1/(j+1)), and no two large numbers are subtracted.

Every other test (docs/theory.md §13) has the same structure with general factors:
h_i(t) = c_0(t) R_0(t) + c_1(t) R_1(t), R_k the running integral of f_k, where the
f_k (per parameter set, at every sample) and c_k (per node) come from
:mod:`vhfit.modes`; :func:`overstress_general` evaluates it with the same steps. The
uniaxial kernel above is kept as it is, so that uniaxial results do not change by a bit.
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator

import numpy as np

# numba is imported when a kernel first runs, not with the package: its import takes a
# fifth of a second that a fit which never runs a kernel (sweeps and relaxation tests
# alone) need not pay. Each kernel below is written as plain Python under a placeholder
# (:class:`_Kernel`); the first call of any of them compiles them all (from numba's
# cache) and puts numba's dispatchers in their place in this module, where the compiled
# kernels find one another.
prange = range  # numba.prange once the kernels are compiled
_KERNELS: list[_Kernel] = []
_LOCK = threading.Lock()


class _Kernel:
    """A kernel until numba compiles it: calling it compiles every kernel, then calls
    the compiled one."""

    def __init__(self, fn, options: dict):
        self.py_func, self.options = fn, options

    def __call__(self, *args):
        return compiled(self.py_func.__name__)(*args)


def _njit(**options):
    """numba.njit, deferred: registers the function as a :class:`_Kernel`."""
    def decorator(fn):
        kernel = _Kernel(fn, options)
        _KERNELS.append(kernel)
        return kernel

    return decorator


def compiled(name: str):
    """The numba dispatcher of the kernel ``name``, every kernel compiled on first use
    (in the order written: a kernel's callees before it).

    Parameters
    ----------
    name : str
        A kernel of this module (``"_psi"``, ``"_overstress_seq"``, ...).

    Returns
    -------
    numba dispatcher
        Called like the kernel.

    Examples
    --------
    >>> compiled("_psi")(0.0)[:3]
    (1.0, 1.0, 0.5)
    """
    kernel = globals()[name]
    if not isinstance(kernel, _Kernel):
        return kernel
    with _LOCK:
        if isinstance(globals()[name], _Kernel):
            import numba

            globals()["prange"] = numba.prange
            for k in _KERNELS:
                globals()[k.py_func.__name__] = numba.njit(**k.options)(k.py_func)
    return globals()[name]

# Gauss–Lobatto points of a step (v in [0, 1]) and the matrix mapping the five values
# of a quartic at those points to the coefficients of its derivative in v.
LOBATTO = np.array([0.0, 0.5 - 0.5 * np.sqrt(3.0 / 7.0), 0.5, 0.5 + 0.5 * np.sqrt(3.0 / 7.0),
                    1.0])
STRIDE = LOBATTO.size - 1  # samples a step adds: its inner points and its end
_V = np.vander(LOBATTO, LOBATTO.size, increasing=True)
DERIV = (np.diag(np.arange(1.0, LOBATTO.size)) @ np.linalg.inv(_V)[1:, :]).copy()

# 1/(k+4)! for the series of ψ3 at small x
_INV_FACT4 = np.array([1.0 / np.prod(np.arange(1.0, k + 5.0)) for k in range(20)])


@_njit(cache=True, inline="always", error_model="numpy")
def _psi(x):
    """e^(−x) and ψ_j(x) = ∫_0^1 e^(−x(1−v)) v^j dv for j = 0..3.

    Below x = 1 the series ψ3 = 6 Σ_k (−x)^k/(k+4)! and the stable downward recurrence
    ψ_(j−1) = (1 − x ψ_j)/j; above, e^(−x) and the upward ψ_j = (1 − j ψ_(j−1))/x.
    """
    if x < 1.0:
        s = _INV_FACT4[19]
        for k in range(18, -1, -1):
            s = _INV_FACT4[k] - x * s
        psi3 = 6.0 * s
        psi2 = (1.0 - x * psi3) / 3.0
        psi1 = 0.5 * (1.0 - x * psi2)
        psi0 = 1.0 - x * psi1
        return 1.0 - x * psi0, psi0, psi1, psi2, psi3
    e = np.exp(-x)
    psi0 = (1.0 - e) / x
    psi1 = (1.0 - psi0) / x
    psi2 = (1.0 - 2.0 * psi1) / x
    psi3 = (1.0 - 3.0 * psi2) / x
    return e, psi0, psi1, psi2, psi3


@_njit(cache=True, inline="always", error_model="numpy")
def _decay_add(r, e, q0, q1, q2, q3, d0, d1, d2, d3):
    """A running integral over one step: e^(−x) r + Σ_j d_j ψ_j(x) (the step of §6)."""
    return e * r + d0 * q0 + d1 * q1 + d2 * q2 + d3 * q3


@_njit(cache=True, error_model="numpy")
def _job(p, c, s_hat, lam, h, sample_off, step_off, G, tau, D, columns, out):
    """One parameter set on one curve: the recursion over the curve's steps.

    ``columns`` False: Σ_i G_i h_i into row p of ``out``. True: each branch's h_i per unit
    modulus into row p·N + i (``G`` unused), the step's interpolant built once for all
    τ — the same arithmetic per τ as unit moduli with one τ a row, to the bit.
    """
    N = tau.shape[1]
    s0 = sample_off[c]
    k0 = step_off[c]
    nsteps = step_off[c + 1] - k0
    node0 = k0 + c
    Ps = np.empty(N)
    Qs = np.empty(N)
    l0 = lam[s0]
    a0 = s_hat[p, s0] / (l0 * l0)
    b0 = s_hat[p, s0] * l0
    acc = 0.0
    for i in range(N):
        Ps[i] = a0
        Qs[i] = b0
        if columns:
            out[p * N + i, node0] = (0.0 + 1.0) * s_hat[p, s0]
        else:
            acc += G[p, i]
    if not columns:
        out[p, node0] = acc * s_hat[p, s0]
    for k in range(nsteps):
        base = s0 + 4 * k
        da0 = 0.0
        da1 = 0.0
        da2 = 0.0
        da3 = 0.0
        db0 = 0.0
        db1 = 0.0
        db2 = 0.0
        db3 = 0.0
        for m in range(5):
            lm = lam[base + m]
            fa = s_hat[p, base + m] / (lm * lm)
            fb = s_hat[p, base + m] * lm
            da0 += D[0, m] * fa
            da1 += D[1, m] * fa
            da2 += D[2, m] * fa
            da3 += D[3, m] * fa
            db0 += D[0, m] * fb
            db1 += D[1, m] * fb
            db2 += D[2, m] * fb
            db3 += D[3, m] * fb
        hk = h[k0 + k]
        le = lam[base + 4]
        w2 = (2.0 / 3.0) * le * le
        w1 = (1.0 / 3.0) / le
        acc = 0.0
        for i in range(N):
            e, q0, q1, q2, q3 = _psi(hk / tau[p, i])
            Ps[i] = _decay_add(Ps[i], e, q0, q1, q2, q3, da0, da1, da2, da3)
            Qs[i] = _decay_add(Qs[i], e, q0, q1, q2, q3, db0, db1, db2, db3)
            if columns:
                out[p * N + i, node0 + k + 1] = 0.0 + 1.0 * (w2 * Ps[i] + w1 * Qs[i])
            else:
                acc += G[p, i] * (w2 * Ps[i] + w1 * Qs[i])
        if not columns:
            out[p, node0 + k + 1] = acc


@_njit(cache=True, parallel=True, error_model="numpy")
def _overstress_par(s_hat, lam, h, sample_off, step_off, G, tau, D, columns):
    C = sample_off.shape[0] - 1
    rows = tau.shape[0] * (tau.shape[1] if columns else 1)
    out = np.empty((rows, h.shape[0] + C))
    for job in prange(s_hat.shape[0] * C):
        _job(job // C, job % C, s_hat, lam, h, sample_off, step_off, G, tau, D, columns, out)
    return out


@_njit(cache=True, error_model="numpy")
def _overstress_seq(s_hat, lam, h, sample_off, step_off, G, tau, D, columns):
    C = sample_off.shape[0] - 1
    rows = tau.shape[0] * (tau.shape[1] if columns else 1)
    out = np.empty((rows, h.shape[0] + C))
    for job in range(s_hat.shape[0] * C):
        _job(job // C, job % C, s_hat, lam, h, sample_off, step_off, G, tau, D, columns, out)
    return out


# Threads pay off only for large populations or long histories: on a small shared
# machine the threaded kernel's median time under contention is several times the
# serial one's when the jobs are small (the paper's 10-point curves: ~5e4 step-terms a
# call), while calls of >= 1e5 step-terms (multi-mode fits on every sample, long
# records) run about twice as fast on 2 cores.
PARALLEL_MIN_JOBS = 4096
PARALLEL_MIN_WORK = 100_000  # rows x terms x steps of one call
PARALLEL_MIN_JOBS_WORK = 8  # ... with at least this many (row, curve) jobs to share


_SERIAL = threading.Event()  # set: every kernel serial, see serial()


@contextlib.contextmanager
def serial() -> Iterator[None]:
    """Every kernel call inside runs serially (the threaded kernels are not even loaded).

    For work that already runs side by side in processes (an order scan's N): threads
    would only oversubscribe the cores, and a process whose numba thread pool never
    started can still fork. Kernels are independent per (parameter set, curve), so the
    results are the same to the bit.
    """
    was = _SERIAL.is_set()
    _SERIAL.set()
    try:
        yield
    finally:
        if not was:
            _SERIAL.clear()


def use_threads(rows: int, terms: int, steps: int, curves: int) -> bool:
    """Whether a kernel call is large enough for numba's threads (see above); never
    inside :func:`serial`."""
    if _SERIAL.is_set():
        return False
    jobs = rows * curves
    return jobs >= PARALLEL_MIN_JOBS or (
        rows * terms * steps >= PARALLEL_MIN_WORK and jobs >= PARALLEL_MIN_JOBS_WORK)


def overstress(s_hat, lam, h, sample_off, step_off, G, tau, D, parallel=None):
    """Σ_i G_i h_i at every node of every curve, for every parameter set.

    Parameters
    ----------
    s_hat : (P, S) normalised hyperelastic stress σ_h/E∞ at every sample; curve c owns
        samples ``sample_off[c] : sample_off[c+1]``: its first node, then for each step
        the three inner Lobatto points and the step's end node.
    lam : (S,) stretch at every sample.
    h : (K,) step lengths in s; curve c owns steps ``step_off[c] : step_off[c+1]``.
    G, tau : (P, N) Prony moduli and relaxation times.
    D : (4, 5) Lobatto values -> derivative coefficients (``DERIV``).
    parallel : bool or None
        Use the threaded kernel; None: by :func:`use_threads` (at least
        ``PARALLEL_MIN_JOBS`` (parameter set, curve) jobs, or ``PARALLEL_MIN_WORK``
        step-terms). False keeps numba's thread pool unstarted (merely loading the
        threaded kernel starts it), so the process can still fork safely.

    Returns
    -------
    (P, K + C) overstress at the nodes; curve c owns nodes from ``step_off[c] + c``.
    """
    if parallel is None:
        parallel = use_threads(G.shape[0], G.shape[1], h.shape[0], sample_off.shape[0] - 1)
    f = compiled("_overstress_par" if parallel else "_overstress_seq")
    return f(s_hat, lam, h, sample_off, step_off, G, tau, D, False)


_NO_MODULI = np.ones((1, 1))  # the G argument of the per-τ columns, which ignore it


def overstress_columns(s_hat, lam, h, sample_off, step_off, tau, D, parallel=None):
    """Each branch's overstress per unit modulus, h_i, for every row's N relaxation times.

    The same as :func:`overstress` of ``np.repeat(s_hat, N, axis=0)`` with unit moduli
    and ``tau.reshape(P * N, 1)`` — to the bit — without the copies, and with each
    step's interpolant built once per row rather than once per τ.

    Returns
    -------
    (P * N, K + C) overstress at the nodes; row p·N + i is row p's i-th τ.
    """
    P, N = tau.shape
    if parallel is None:
        parallel = use_threads(P * N, 1, h.shape[0], sample_off.shape[0] - 1)
    f = compiled("_overstress_par" if parallel else "_overstress_seq")
    return f(s_hat, lam, h, sample_off, step_off, _NO_MODULI, tau, D, True)


# ------------------------------------------------------------- every other test
@_njit(cache=True, error_model="numpy")
def _job_general(p, c, f0, f1, w, h, sample_off, step_off, G, tau, D, rep, d, out):
    """One parameter set on one curve: h = Σ_i G_i (c_0 R_0,i + c_1 R_1,i) at every node.

    Row p of G and tau uses row p // rep of the factors. ``d`` (K, 8): each step's
    derivative coefficients if precomputed (:func:`step_derivatives`), else empty.
    """
    N = G.shape[1]
    q = p // rep
    s0 = sample_off[c]
    k0 = step_off[c]
    nsteps = step_off[c + 1] - k0
    node0 = k0 + c
    R0 = np.empty(N)
    R1 = np.empty(N)
    acc = 0.0
    for i in range(N):
        R0[i] = f0[q, s0]
        R1[i] = f1[q, s0]
        acc += G[p, i]
    out[p, node0] = acc * (w[node0, 0] * f0[q, s0] + w[node0, 1] * f1[q, s0])
    shared = d.shape[0] > 0
    n_sum = 0 if shared else 5
    for k in range(nsteps):
        base = s0 + 4 * k
        da0 = 0.0
        da1 = 0.0
        da2 = 0.0
        da3 = 0.0
        db0 = 0.0
        db1 = 0.0
        db2 = 0.0
        db3 = 0.0
        for m in range(n_sum):
            fa = f0[q, base + m]
            fb = f1[q, base + m]
            da0 += D[0, m] * fa
            da1 += D[1, m] * fa
            da2 += D[2, m] * fa
            da3 += D[3, m] * fa
            db0 += D[0, m] * fb
            db1 += D[1, m] * fb
            db2 += D[2, m] * fb
            db3 += D[3, m] * fb
        if shared:  # the coefficients were computed once for every row
            row = k0 + k
            da0, da1, da2, da3 = d[row, 0], d[row, 1], d[row, 2], d[row, 3]
            db0, db1, db2, db3 = d[row, 4], d[row, 5], d[row, 6], d[row, 7]
        hk = h[k0 + k]
        node = node0 + k + 1
        w0 = w[node, 0]
        w1 = w[node, 1]
        acc = 0.0
        for i in range(N):
            e, q0, q1, q2, q3 = _psi(hk / tau[p, i])
            R0[i] = _decay_add(R0[i], e, q0, q1, q2, q3, da0, da1, da2, da3)
            R1[i] = _decay_add(R1[i], e, q0, q1, q2, q3, db0, db1, db2, db3)
            acc += G[p, i] * (w0 * R0[i] + w1 * R1[i])
        out[p, node] = acc


@_njit(cache=True, parallel=True, error_model="numpy")
def _general_par(f0, f1, w, h, sample_off, step_off, G, tau, D, rep, d):
    C = sample_off.shape[0] - 1
    out = np.empty((G.shape[0], h.shape[0] + C))
    for job in prange(G.shape[0] * C):
        _job_general(job // C, job % C, f0, f1, w, h, sample_off, step_off, G, tau, D, rep,
                     d, out)
    return out


@_njit(cache=True, error_model="numpy")
def _general_seq(f0, f1, w, h, sample_off, step_off, G, tau, D, rep, d):
    C = sample_off.shape[0] - 1
    out = np.empty((G.shape[0], h.shape[0] + C))
    for job in range(G.shape[0] * C):
        _job_general(job // C, job % C, f0, f1, w, h, sample_off, step_off, G, tau, D, rep,
                     d, out)
    return out


_NO_STEPS = np.zeros((0, 8))  # no precomputed step coefficients


def overstress_general(f0, f1, w, h, sample_off, step_off, G, tau, D, parallel=None,
                       repeat: int = 1, steps=None):
    """Σ_i G_i (c_0 R_0,i + c_1 R_1,i) at every node of every curve, for every parameter set.

    Parameters
    ----------
    f0, f1 : (P, S) the factors f_k(u) of the kernel (per unit E∞) at every sample, laid
        out as in :func:`overstress`.
    w : (K + C, 2) the weights c_k(t) at every node; curve c owns nodes from
        ``step_off[c] + c``.
    h, sample_off, step_off, G, tau, D, parallel : as in :func:`overstress`.
    repeat : int
        Rows of G and tau per row of the factors: row p of G, tau uses row
        ``p // repeat`` of f0, f1 (G, tau have ``repeat`` times the rows of f0, f1), so
        that one factor set serves several relaxation times without copies.
    steps : (K, 8), optional
        :func:`step_derivatives` of the factors, when one factor set serves every row
        (a kinematic formulation): computed once rather than per row and τ, the same
        bits.

    Returns
    -------
    (G.shape[0], K + C) overstress at the nodes.
    """
    if G.shape[0] != repeat * f0.shape[0]:
        raise ValueError(f"G has {G.shape[0]} rows; expected repeat * f0 rows = "
                         f"{repeat * f0.shape[0]}")
    if parallel is None:
        parallel = use_threads(G.shape[0], G.shape[1], h.shape[0], sample_off.shape[0] - 1)
    f = compiled("_general_par" if parallel else "_general_seq")
    return f(f0, f1, w, h, sample_off, step_off, G, tau, D, int(repeat),
             _NO_STEPS if steps is None else steps)


# ------------------------------------------------------------ one step, from a state
@_njit(cache=True, error_model="numpy")
def _advance(R0, R1, f0, f1, h, tau, D):
    """The running integrals R_0, R_1 of every τ after one step of length ``h``: the
    arithmetic of :func:`_job_general`'s step, from a given state."""
    d = np.zeros(8)
    for m in range(STRIDE + 1):  # the kernel's order of summation: the same bits
        for j in range(4):
            d[j] += D[j, m] * f0[m]
            d[4 + j] += D[j, m] * f1[m]
    out0 = np.empty(tau.shape[0])
    out1 = np.empty(tau.shape[0])
    for i in range(tau.shape[0]):
        e, q0, q1, q2, q3 = _psi(h / tau[i])
        out0[i] = _decay_add(R0[i], e, q0, q1, q2, q3, d[0], d[1], d[2], d[3])
        out1[i] = _decay_add(R1[i], e, q0, q1, q2, q3, d[4], d[5], d[6], d[7])
    return out0, out1


def advance(R0, R1, f0, f1, h: float, tau) -> tuple[np.ndarray, np.ndarray]:
    """One step of the recursion from a state: the kernel stepped by hand.

    The state of a Prony series is its running integrals, R_k,i (k = 0, 1; one per
    relaxation time τ_i); over a step of length ``h`` they decay by e^(−h/τ_i) and gain
    the step's integral of the factors' quartic interpolant (docs/theory.md §6, §13), as
    in :func:`overstress_general`. A stress-controlled history (a creep test) takes its
    steps one at a time, the stretch at a step's end being unknown until it is solved.

    Parameters
    ----------
    R0, R1 : (N,) the running integrals at the step's start.
    f0, f1 : (5,) the factors f_k at the step's Gauss–Lobatto points (``LOBATTO``).
    h : float
        Step length in s.
    tau : (N,) relaxation times.

    Returns
    -------
    R0, R1 : (N,) the running integrals at the step's end (new arrays).

    Examples
    --------
    A constant factor only decays (here over one relaxation time):

    >>> R0, R1 = advance(np.ones(1), np.zeros(1), np.full(5, 2.0), np.zeros(5), 1.0, np.ones(1))
    >>> round(float(R0[0]), 12) == round(float(np.exp(-1.0)), 12), float(R1[0])
    (True, 0.0)
    """
    f = compiled("_advance")
    return f(np.ascontiguousarray(R0, dtype=np.float64),
             np.ascontiguousarray(R1, dtype=np.float64),
             np.ascontiguousarray(f0, dtype=np.float64),
             np.ascontiguousarray(f1, dtype=np.float64), float(h),
             np.ascontiguousarray(tau, dtype=np.float64), DERIV)


# ------------------------------------------------- factors shared by every row
def step_derivatives(f0, f1, sample_off, step_off, D) -> np.ndarray:
    """(K, 8): each step's derivative coefficients of the interpolants of f0 and f1.

    For factors that are the same for every parameter set (a kinematic formulation,
    :mod:`vhfit.formulations`), shape (S,): the d_j of :func:`overstress_general`'s
    steps (j = 0..3 for f0, then for f1), computed once instead of once per row and τ,
    summed in the kernel's order (the same bits).
    """
    starts = [sample_off[c] + STRIDE * np.arange(step_off[c + 1] - step_off[c])
              for c in range(sample_off.size - 1)]
    base = np.concatenate(starts + [np.zeros(0, dtype=np.int64)]).astype(np.int64)
    out = np.zeros((base.size, 8))
    for k, f in enumerate((f0, f1)):
        for m in range(STRIDE + 1):  # the kernel's order of summation: the same bits
            out[:, 4 * k:4 * k + 4] += D[:, m][None, :] * f[base + m][:, None]
    return out


# ------------------------------------------------ simple shear's factors, in one pass
@_njit(cache=True, error_model="numpy")
def _shear_factors(ta, tb, t3, gamma, la, la2, q, E, f0, f1):
    """f0 = (τ12 − γ S22)/E∞, f1 = S22/E∞ from the principal τ (P, S): the arithmetic of
    :func:`vhfit._kirchhoff.shear_kirchhoff` and the shear record's factors, in their
    order (the same bits), without their (P, S) temporaries."""
    P, S = ta.shape
    for p in range(P):
        e = E[p, 0]
        for s in range(S):
            a = ta[p, s]
            b = tb[p, s]
            t11 = (la2[s] * a + b) * q[s]
            t22 = (a + la2[s] * b) * q[s]
            t12 = (a - b) * la[s] * q[s]
            s22 = (2.0 * t22 - t11 - t3[p, s]) / 3.0
            f0[p, s] = (t12 - gamma[s] * s22) / e
            f1[p, s] = s22 / e


def shear_factors(ta, tb, t3, gamma, la, la2, q, E) -> tuple[np.ndarray, np.ndarray] | None:
    """The factors of simple shear from the principal Kirchhoff stresses (compiled).

    Parameters
    ----------
    ta, tb, t3 : (P, S) τ along λ, 1/λ and out of plane, per parameter set and sample.
    gamma, la, la2, q : (S,) γ, λ, λ² and 1/(1 + λ²) (:func:`vhfit._kirchhoff.shear_frame`).
    E : (P, 1) E∞ of each parameter set.

    Returns
    -------
    (f0, f1), each (P, S), or None when the arrays are not of that layout (the caller's
    numpy form handles every other shape).
    """
    P, S = np.shape(ta)[0] if np.ndim(ta) == 2 else -1, np.shape(gamma)[-1]
    arrays = (ta, tb, t3)
    if (P < 0 or any(not isinstance(v, np.ndarray) or v.shape != (P, S)
                     or v.dtype != np.float64 for v in arrays)
            or any(np.shape(v) != (S,) for v in (gamma, la, la2, q))
            or np.shape(E) != (P, 1)):
        return None
    f0, f1 = np.empty((P, S)), np.empty((P, S))
    compiled("_shear_factors")(ta, tb, t3, gamma, la, la2, q,
                               np.asarray(E, dtype=np.float64), f0, f1)
    return f0, f1
