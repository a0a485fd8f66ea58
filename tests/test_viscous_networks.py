"""The integrator of the viscous networks (vhfit.viscous) against independent references.

* a tight reference written here: scipy's Radau (rtol 1e-10) on the ODEs of ln λ_cr, the
  total stretch of a creep test found by a scalar root-find at every evaluation; the
  one-coordinate tests (uniaxial, equibiaxial) take the network's stress from the law's
  stress in that test (``vhfit.modes.long_term_stress``), planar from Mooney–Rivlin's
  closed-form Kirchhoff stress;
* the solver's own results of two one-element creep tests (PRF-U1, PRF-U2);
* limits: A → 0 is the instantaneous law, A → ∞ the equilibrium law (1 − Σ s) W, and a
  Bergström–Boyce network with m = 1, C = 0 at small strain is a Maxwell element;
* properties: incompressible total and creep stretches, stresses between the two limits.

The STRAIN law with m < 0 has an infinite rate at ε̄ = 0. The reference starts from its
analytic early-time solution: over the first 1e-9 of the first interval the network is
still elastic, and w = ε̄^(1/(m+1)) obeys w' = (A q̃^n/(m+1))^(1/(m+1)), a regular
integral (for creep at constant q̃: ε̄ = A q̃^n t^(m+1)/(m+1)). The integrator needs no
special start: its stage equation stays bracketed and finite when ε̄ grows from 0 (see
``vhfit.viscous._integrate._stage``).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq

from vhfit import hyperelastic
from vhfit.modes import long_term_stress
from vhfit.viscous import Network, NetworkModel, flows, network_creep, network_stress
from vhfit.viscous._integrate import stretch_history

#: The accuracy the integrator promises at its default settings (relative).
PROMISE = 1e-6


# ------------------------------------------------------------------ the reference
def reference_rate(flow, c):
    """The flows' formulas, written again (scalar)."""
    if flow == "bergstrom_boyce":
        A, m, C, E = c
        return lambda q, lc, eb: A * (lc - 1 + E) ** C * q**m
    if flow == "strain":
        A, n, m = c
        return lambda q, lc, eb: ((A * q**n * ((m + 1) * max(eb, 1e-300)) ** m) ** (1 / (m + 1))
                                  if q > 0 else 0.0)
    if flow == "hyperb":
        A, B, n = c
        return lambda q, lc, eb: A * np.sinh(B * q) ** n
    raise KeyError(flow)


def early_creep_strain(flow, c, q_of_t, a, t0):
    """ε̄ at a + t0 of a network still elastic, q̃ = q_of_t(t) (see the module docstring)."""
    if flow == "strain":
        A, n, m = c
        w = quad(lambda t: (A * q_of_t(t) ** n / (m + 1)) ** (1 / (m + 1)), a, a + t0,
                 epsabs=0, epsrel=1e-12)[0]
        return w ** (m + 1)
    rate = reference_rate(flow, c)
    return quad(lambda t: rate(q_of_t(t), 1.0, 0.0), a, a + t0, epsabs=0, epsrel=1e-12)[0]


class OneCoordinate:
    """Uniaxial or equibiaxial: the networks' creep stretches keep the test's symmetry,
    e = z (1, −1/2, −1/2) or z (1, 1, −2); dz/dt = f ε̇ sign(σ_k), f = 1 or 1/2, and
    q̃ = |σ_k| = s_k |σ_h(λ1 / λ_cr,1)| in that test."""

    KIN = {"uniaxial": ((1.0, -0.5, -0.5), 1.0), "equibiaxial": ((1.0, 1.0, -2.0), 0.5)}

    def __init__(self, law, params, nets, mode):
        self.law, self.p, self.nets, self.mode = hyperelastic.get(law), params, nets, mode
        self.expo, self.fac = self.KIN[mode]
        self.rates = [reference_rate(f, c) for f, _, c in nets]
        self.eq = 1 - sum(s for _, s, _ in nets)

    def sig(self, lam):
        return float(long_term_stress(self.law, np.asarray(self.p), self.mode,
                                      np.array([lam]))[0])

    def rhs(self, L1, y):
        out = []
        for k, (_, s, _) in enumerate(self.nets):
            z, eb = y[2 * k], y[2 * k + 1]
            se = s * self.sig(np.exp(L1 - z))
            lam_cr = np.sqrt(np.mean([np.exp(2 * a * z) for a in self.expo]))
            r = self.rates[k](abs(se), lam_cr, eb)
            out += [self.fac * np.sign(se) * r, r]
        return out

    def total(self, L1, y):
        t = self.eq * self.sig(np.exp(L1))
        return t + sum(s * self.sig(np.exp(L1 - y[2 * k]))
                       for k, (_, s, _) in enumerate(self.nets))

    def start(self, q_of_t, sign, a, t0):
        y = np.zeros(2 * len(self.nets))
        for k, (f, s, c) in enumerate(self.nets):
            eb = early_creep_strain(f, c, lambda t, s=s: s * abs(q_of_t(t)), a, t0)
            y[2 * k], y[2 * k + 1] = self.fac * sign * eb, eb
        return y

    def strain(self, t, lam):
        def L1(tt):
            return np.log(np.interp(tt, t, lam))

        y = np.zeros(2 * len(self.nets))
        out, first = [self.total(L1(t[0]), y)], True
        for a, b in zip(t[:-1], t[1:]):
            if b > a and first:
                first, t0 = False, 1e-9 * (b - a)
                y = self.start(lambda tt: self.sig(np.exp(L1(tt))),
                               np.sign(lam[1] - lam[0]), a, t0)
                a = a + t0
            if b > a:
                y = solve_ivp(lambda tt, yy: self.rhs(L1(tt), yy), (a, b), y, method="Radau",
                              rtol=1e-10, atol=1e-14).y[:, -1]
            out.append(self.total(L1(b), y))
        return np.array(out)

    def solve_L(self, S, y, eng):
        return brentq(lambda L1: self.total(L1, y) - S * (np.exp(L1) if eng else 1.0),
                      -1.5, 2.0, xtol=1e-15, rtol=1e-15)

    def creep(self, S, times, eng=False, t0=1e-9):
        L0 = self.solve_L(S, np.zeros(2 * len(self.nets)), eng)
        y = self.start(lambda t: self.sig(np.exp(L0)), np.sign(S), 0.0, t0)
        sol = solve_ivp(lambda tt, yy: self.rhs(self.solve_L(S, yy, eng), yy), (t0, times[-1]),
                        y, method="Radau", rtol=1e-10, atol=1e-14,
                        t_eval=np.clip(times, t0, None))
        return np.array([np.exp(L0) if tt == 0 else np.exp(self.solve_L(S, sol.y[:, i], eng))
                         for i, tt in enumerate(times)])


class PlanarMooneyRivlin:
    """Planar (λ, 1, 1/λ), τ_i = 2 C10 λ_i² − 2 C01 λ_i^-2 (+ pressure) in closed form;
    each network's creep state (e1, e2, ε̄), e3 = −e1 − e2, flowing along (3/2) τ'/q̃."""

    def __init__(self, C10, C01, nets):
        self.C10, self.C01, self.nets = C10, C01, nets
        self.rates = [reference_rate(f, c) for f, _, c in nets]
        self.eq = 1 - sum(s for _, s, _ in nets)

    def tau(self, logs):
        return 2 * self.C10 * np.exp(2 * logs) - 2 * self.C01 * np.exp(-2 * logs)

    def rhs(self, L1, y):
        out = []
        for k, (_, s, _) in enumerate(self.nets):
            e = np.array([y[3 * k], y[3 * k + 1], -y[3 * k] - y[3 * k + 1]])
            tau = s * self.tau(np.array([L1, 0.0, -L1]) - e)
            dev = tau - tau.mean()
            q = np.sqrt(1.5 * np.sum(dev**2))
            r = self.rates[k](q, np.sqrt(np.mean(np.exp(2 * e))), y[3 * k + 2])
            d = 1.5 * dev / q if q > 0 else np.zeros(3)
            out += [r * d[0], r * d[1], r]
        return out

    def total(self, L1, y):
        t = self.eq * self.tau(np.array([L1, 0.0, -L1]))
        out = t[0] - t[2]
        for k, (_, s, _) in enumerate(self.nets):
            e = np.array([y[3 * k], y[3 * k + 1], -y[3 * k] - y[3 * k + 1]])
            tk = s * self.tau(np.array([L1, 0.0, -L1]) - e)
            out += tk[0] - tk[2]
        return out

    def strain(self, t, lam):
        def L1(tt):
            return np.log(np.interp(tt, t, lam))

        y = np.zeros(3 * len(self.nets))
        out = [self.total(L1(t[0]), y)]
        for a, b in zip(t[:-1], t[1:]):
            if b > a:
                y = solve_ivp(lambda tt, yy: self.rhs(L1(tt), yy), (a, b), y, method="Radau",
                              rtol=1e-10, atol=1e-14).y[:, -1]
            out.append(self.total(L1(b), y))
        return np.array(out)


# ------------------------------------------------------------------ helpers
def model_of(law, params, nets):
    return NetworkModel(law, params, tuple(Network(f, s, c) for f, s, c in nets))


def cycle():
    """Load to λ = 2 in 20 s, hold 20 s, unload to λ = 1 in 20 s, hold 40 s."""
    t = np.concatenate([np.linspace(0, 20, 21), np.linspace(20, 40, 6)[1:],
                        np.linspace(40, 60, 21)[1:], np.linspace(60, 100, 6)[1:]])
    return t, np.interp(t, [0, 20, 40, 60, 100], [1.0, 2.0, 2.0, 1.0, 1.0])


def assert_close_to_reference(got, ref):
    """Within PROMISE of the curve's peak everywhere, and pointwise where the stress is
    more than 1 % of its peak (a stress through zero has no relative error)."""
    peak = np.abs(ref).max()
    assert np.abs(got - ref).max() <= PROMISE * peak
    big = np.abs(ref) > 0.01 * peak
    np.testing.assert_allclose(got[big], ref[big], rtol=PROMISE)


NETS_SB = [("strain", 0.4, (1e-2, 2.0, -0.5)), ("bergstrom_boyce", 0.3, (0.05, 4.0, -1.0, 0.01))]


# ------------------------------------------------------------------ (a) the reference
@pytest.mark.parametrize("mode", ["uniaxial", "equibiaxial"])
def test_strain_control_matches_radau_in_one_coordinate_tests(mode):
    """Loading, hold, unloading, hold; STRAIN (singular start) + Bergström–Boyce with
    C = −1, E = 0.01 on Arruda–Boyce."""
    t, lam = cycle()
    got = model_of("arruda_boyce", (0.5, 5.0), NETS_SB).stress(t, lam, deformation=mode)
    assert_close_to_reference(got, OneCoordinate("arruda_boyce", (0.5, 5.0), NETS_SB,
                                                 mode).strain(t, lam))


def test_strain_control_matches_radau_in_planar_tension():
    """Two creep coordinates per network (λ2 = 1 held: the networks' e2 is not 0)."""
    nets = [("hyperb", 0.4, (0.02, 2.0, 1.5)), ("bergstrom_boyce", 0.3, (0.05, 3.0, -0.5, 0.05))]
    t, lam = cycle()
    got = model_of("mooney_rivlin", (0.3, 0.1), nets).stress(t, lam, deformation="planar")
    assert_close_to_reference(got, PlanarMooneyRivlin(0.3, 0.1, nets).strain(t, lam))


def test_engineering_stress_is_true_stress_over_the_stretch():
    t, lam = cycle()
    m = model_of("neo_hooke", (0.25,), [("hyperb", 0.5, (0.02, 2.0, 1.0))])
    np.testing.assert_allclose(m.stress(t, lam, measure="engineering"),
                               m.stress(t, lam) / lam, rtol=1e-15)


@pytest.mark.parametrize("mode, measure, stress, nets", [
    ("uniaxial", "true", 0.6, [("strain", 0.5, (1e-2, 1.0, -0.5)),
                               ("hyperb", 0.3, (1e-2, 1.5, 2.0))]),
    ("equibiaxial", "engineering", 0.4, [("bergstrom_boyce", 0.5, (0.05, 2.0, -1.0, 0.01)),
                                          ("hyperb", 0.3, (1e-2, 1.5, 2.0))])])
def test_creep_matches_radau(mode, measure, stress, nets):
    """A Cauchy or a nominal stress held from t = 0; STRAIN's singular start included."""
    times = np.array([0.0, 0.5, 2.0, 5.0])
    got = model_of("arruda_boyce", (0.5, 5.0), nets).creep(stress, times, deformation=mode,
                                                           measure=measure)
    ref = OneCoordinate("arruda_boyce", (0.5, 5.0), nets, mode).creep(
        stress, times, eng=measure == "engineering")
    # the creep strain ln λ is what is compared (the stretch itself is near 1)
    np.testing.assert_allclose(np.log(got), np.log(ref), rtol=PROMISE)


# ------------------------------------------------------------------ (b) the solver itself
_AB = ("arruda_boyce", (20.0, 7.0))
_STRAIN = ("strain", 0.5, (1.0e-5, 1.0, -0.5))


@pytest.mark.parametrize("second, times, e11", [
    (("bergstrom_boyce", 0.3, (2.5e-5, 4.0, -1.0, 0.01)), [1.0, 483.31073, 983.31073, 1001.0],
     [0.032380641, 0.040189974, 0.041543677, 0.041575786]),
    (("hyperb", 0.3, (2.5e-5, 0.15, 2.0)), [1.0, 501.0, 1001.0],
     [0.032380641, 0.032633230, 0.032755878]),
], ids=["PRF-U1", "PRF-U2"])
def test_the_solvers_own_creep_results(second, times, e11):
    """One C3D8H element at a Cauchy stress of 2.0: a static step (elastic) to t = 1,
    then 1000 s of creep. The solver's t = 1 is t = 0 here; its E11 is ln λ. Its own time
    stepping (CETOL = 1e-2) is good to about 2e-4, hence 1e-3."""
    m = model_of(*_AB, [_STRAIN, second])
    lam = m.creep(2.0, np.array(times) - 1.0, measure="true")
    np.testing.assert_allclose(np.log(lam), e11, rtol=1e-3)


# ------------------------------------------------------------------ (c) limits
def test_slow_and_fast_flows_give_the_instantaneous_and_equilibrium_laws():
    """A = 1e-30 (nothing flows): the full law W; A = 1e30 (relaxed at once, a rate over 60
    decades and m = 4): (1 − Σ s) W; both in one batch, in uniaxial and planar tests.

    At A = 1e30 the Bergström–Boyce network still lags by the stress that drives it at
    the test's rate: q̃ ≤ (ε̇ (λ_cr − 1 + E)/A)^(1/m) with ε̇ ≤ 0.06 1/s and
    λ_cr − 1 + E ≤ 2 here, about 3e-8 MPa; σ11 ≤ 1.2 q̃ in these tests. HYPERB (n = 1)
    lags by ε̇/(A B), nothing."""
    law = hyperelastic.get("mooney_rivlin")
    p = np.array([0.3, 0.05])
    fl = [flows.get("bergstrom_boyce"), flows.get("hyperb")]
    ratios = np.array([0.3, 0.45])
    A = np.array([[1e-30], [1e30]])
    bb = np.concatenate([A, np.broadcast_to([4.0, -1.0, 0.01], (2, 3))], axis=1)
    hy = np.concatenate([A, np.broadcast_to([1.0, 1.0], (2, 2))], axis=1)
    t, lam = cycle()
    for mode in ("uniaxial", "planar"):
        sig = network_stress(law, p, fl, ratios, [bb, hy], t, lam, deformation=mode)
        full = long_term_stress(law, p, mode, lam)
        np.testing.assert_allclose(sig[0], full, rtol=1e-12, atol=1e-14)
        lag = 1.2 * (0.06 * 2.0 / 1e30) ** (1 / 4.0)
        np.testing.assert_allclose(sig[1], (1 - ratios.sum()) * full, rtol=1e-9, atol=lag)


def test_a_linear_network_at_small_strain_is_a_maxwell_element():
    """Bergström–Boyce with m = 1, C = 0: ε̇_cr = A q̃ = A σ_k in uniaxial tension, and
    σ_k = E_k (ε − ε_cr) at small strain (E_k = 3 s μ, μ = 2 C10): a Maxwell element of
    relaxation time τ = 1/(A E_k). A step ε0 at t = 0 then relaxes as
    σ = E∞ ε0 + E_k ε0 exp(−t/τ), E∞ = 3 (1 − s) μ; a ramp ε = r t gives
    σ = E∞ r t + E_k r τ (1 − exp(−t/τ)). Neo-Hooke's uniaxial stress is 3μ ε (1 + O(ε²))
    in ε = λ − 1 and the elastic log strain differs from ε by O(ε²): the relative error
    of the small-strain element is O(ε0), here 1e-5."""
    C10, s, A, eps = 0.5, 0.4, 2.0, 1e-5
    mu = 2 * C10
    Ek, Einf = 3 * s * mu, 3 * (1 - s) * mu
    tau = 1 / (A * Ek)
    m = model_of("neo_hooke", (C10,), [("bergstrom_boyce", s, (A, 1.0, 0.0, 0.01))])
    t = np.array([0.0, 0.0, 0.1, 0.3, 1.0, 2.0])  # a jump at t = 0, then held
    lam = np.array([1.0, 1 + eps, 1 + eps, 1 + eps, 1 + eps, 1 + eps])
    # the absolute tolerance of the integrator is in log strain: scaled to the strain here
    sig = network_stress(hyperelastic.get("neo_hooke"), [C10], [flows.get("bergstrom_boyce")],
                         [s], [[A, 1.0, 0.0, 0.01]], t, lam, atol=1e-10 * eps)
    relax = Einf * eps + Ek * eps * np.exp(-t[1:] / tau)
    np.testing.assert_allclose(sig[1:], relax, rtol=3 * eps)
    r = eps / 2.0
    t = np.linspace(0.0, 2.0, 9)
    sig = m.stress(t, 1 + r * t)
    ramp = Einf * r * t + Ek * r * tau * (1 - np.exp(-t / tau))
    np.testing.assert_allclose(sig[1:], ramp[1:], rtol=3 * eps)


# ------------------------------------------------------------------ (d) properties
_BB = st.tuples(st.floats(-6.0, 6.0), st.floats(1.0, 6.0), st.floats(-1.0, 0.0),
                st.floats(1e-3, 0.5))


@settings(max_examples=15, deadline=None)
@given(bb=_BB, s=st.floats(0.05, 0.9), peak=st.floats(1.05, 2.5), mode=st.sampled_from(
    ["uniaxial", "equibiaxial", "planar"]))
def test_stretches_are_incompressible_and_stresses_between_the_limits(bb, s, peak, mode):
    """det F = det F_cr = 1 at every point, and in loading from rest each network's
    elastic stretch lies between none and all of the total one, so the stress lies
    between the equilibrium law's (1 − s) W and the instantaneous law's W (rate limits)."""
    logA, mexp, C, E = bb
    law = hyperelastic.get("neo_hooke")
    t = np.array([0.0, 0.5, 1.0, 1.5, 2.0])
    lam = 1 + (peak - 1) * t / 2.0
    args = (law, [0.3], [flows.get("bergstrom_boyce")], [s], [[10.0**logA, mexp, C, E]], t,
            lam)
    total, creep = stretch_history(*args, deformation=mode)
    np.testing.assert_allclose(np.prod(total, axis=-1), 1.0, rtol=1e-14)
    np.testing.assert_allclose(np.prod(creep, axis=-1), 1.0, rtol=1e-14)
    assert np.all(creep[..., 0] >= 1.0 - 1e-14) and np.all(creep[..., 0] <= total[..., 0] + 1e-14)
    sig = network_stress(*args, deformation=mode)
    full = long_term_stress(law, np.array([0.3]), mode, lam)
    assert np.all(sig <= full * (1 + 1e-12)) and np.all(sig >= (1 - s) * full * (1 - 1e-12))


@settings(max_examples=6, deadline=None)
@given(logA=st.floats(-3.0, 1.0), stress=st.floats(0.05, 0.5))
def test_creep_starts_at_the_instantaneous_response_and_creeps_towards_equilibrium(logA, stress):
    """At t = 0 the stretch is the full law's at the load; it then grows, and never past
    the equilibrium law's (1 − s) W stretch at that load."""
    law = hyperelastic.get("neo_hooke")
    s = 0.5
    lam = network_creep(law, [0.3], [flows.get("hyperb")], [s], [[10.0**logA, 2.0, 1.0]],
                        stress, np.array([0.0, 0.5, 2.0, 5.0]))
    inst = brentq(lambda x: float(long_term_stress(law, np.array([0.3]), "uniaxial",
                                                   np.array([x]))[0]) - stress, 1.0, 5.0,
                  xtol=1e-15)
    eq = brentq(lambda x: (1 - s) * float(long_term_stress(law, np.array([0.3]), "uniaxial",
                                                           np.array([x]))[0]) - stress, 1.0, 5.0,
                xtol=1e-15)
    assert lam[0] == pytest.approx(inst, rel=1e-12)
    assert np.all(np.diff(lam) >= -1e-14) and np.all(lam <= eq * (1 + 1e-12))


def test_batches_match_one_by_one():
    """Leading axes (parameter sets × curves) give each row's own result: each row takes
    its own step sizes, so what it is batched with does not change its integration. Bit
    identity is not promised: numpy's reductions may round the last bit differently for
    another batch shape, and that can move a step-size decision; the results then agree
    to the integrator's tolerance (1e-8 of the peak, far below PROMISE)."""
    law = hyperelastic.get("neo_hooke")
    fl = [flows.get("bergstrom_boyce")]
    t, lam = cycle()
    consts = np.array([[[0.01, 2.0, -1.0, 0.01]], [[10.0, 4.0, -0.5, 0.1]]])  # (2, 1, 4)
    curves = np.stack([lam, 1 + 0.5 * (lam - 1)])                              # (2, m)
    batch = network_stress(law, [0.3], fl, [0.4], [consts], t, curves)          # (2, 2, m)
    assert batch.shape == (2, 2, t.size)
    for i in range(2):
        for j in range(2):
            one = network_stress(law, [0.3], fl, [0.4], [consts[i, 0]], t, curves[j])
            np.testing.assert_allclose(batch[i, j], one, rtol=0,
                                       atol=1e-8 * np.abs(one).max())
