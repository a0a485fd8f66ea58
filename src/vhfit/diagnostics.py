"""Diagnostics: can the chosen model represent the data at all?

:func:`rate_sensitivity` compares how much the measured stress rises between curves at
different strain rates with the most that a hyperelastic law plus a Prony series with
non-negative moduli can produce, and names the curve pairs it cannot fit (the paper's
gelatin argument, made exact for the model).

The bound
---------
For a constant-rate ramp from rest, λ(u) = 1 + r u, substitute the strain e = r u in the
corrected Eq. 19 (docs/theory.md §4). At strain ε the stress is

    σ(ε; r) = E∞ ŝ(ε) + Σ_i G_i φ(|r| τ_i; ε),
    φ(a; ε) = ∫_0^ε e^(−(ε−e)/a) ∂w/∂e de,   w(e) = ŝ(e) K(e, ε),

with ŝ = σ_h / E∞ and K the kernel of Eq. 19 (an integration by parts of the
overstress; w(0) = 0). The rate enters only through a = |r| τ: doubling the rate acts
on each term exactly like doubling its τ. Between rates r1 < r2 = k r1 at the same
strain, the stress ratio is a ratio of two sums whose terms pair up — E∞ ŝ with itself
(ratio 1) and G_i φ(k a_i) with G_i φ(a_i). When every term has the same sign, a ratio
of sums lies between the smallest and the largest term ratio (the mediant inequality),
so for all E∞, G_i ≥ 0 and τ_i > 0, and any number of terms N ≥ 1:

    min(1, inf_a φ(ka)/φ(a))  ≤  σ(ε; r2) / σ(ε; r1)  ≤  max(1, sup_a φ(ka)/φ(a)).

In the small-strain limit ŝ = ε and K = 1, so φ(a) = a (1 − e^(−ε/a)) — the closed form
σ = E∞ ε + Σ G_i r τ_i (1 − e^(−ε/(r τ_i))) of docs/theory.md §4 — and φ(ka)/φ(a) rises from 1
(a → ∞, the elastic limit) to exactly k (a → 0, the viscous limit): **doubling the rate
at most doubles the stress**, and only when E∞ → 0 and every τ_i ≪ ε / r (the paper's
argument for gelatin). The same holds at large strain whenever ∂w/∂e is non-negative and
non-decreasing along the path — then φ(a)/a is an average of ∂w/∂e over an exponential
memory that reaches further back as a grows, so it cannot rise — which is the case for
stiffening compression curves. This module does not assume it: the bound is evaluated
with the model's own Eq. 19 recursion on a grid of τ spanning the curves' time scales,
for each hyperelastic basis shape (the unit vectors of a law linear in its constants,
e.g. Mooney–Rivlin's C10 and C01 shapes, plus the law's example constants), at the
matched strains. In tension the sup can exceed k (the overstress of a C01 term changes
sign at large stretch); where a term changes sign no bound exists and the pair is not
checked. With N = 0 (no Prony term) both bounds are 1: the law has no rate dependence.

The data side uses the same mediant argument over strain points: the ratio of the
summed stresses of the faster and the slower curve at matched strains lies within the
extreme pointwise bounds, and is insensitive to noise at small strain.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from vhfit import hyperelastic as _hyper
from vhfit.history import History
from vhfit.model import ModelSpec, Prony, ViscoHyperelastic, model_from_spec
from vhfit.modes import get_deformation

__all__ = ["RatePair", "rate_pairs", "rate_ratio_bounds", "rate_sensitivity"]

_TAU_PER_DECADE = 8
_TAU_MARGIN = 4.0  # decades of τ beyond the curves' own time scales
_RELIABLE = 1e-9  # ignore terms this small against the largest (rounding noise)


@dataclass
class RatePair:
    """One pair of constant-rate curves compared by :func:`rate_pairs`.

    Attributes
    ----------
    slow, fast : str
        Names of the slower and the faster curve.
    rate_slow, rate_fast : float
        Their strain rates in 1/s.
    rate_ratio : float
        k = |rate_fast| / |rate_slow| (> 1).
    stress_ratio : float
        Σ σ_fast / Σ σ_slow over the matched strains (true stress).
    low, high : float
        Least and most stress ratio the model can produce between these rates at these
        strains (±inf where no bound exists).
    strain : ndarray
        The matched strains.
    too_steep : bool
        The data stiffen with rate more than the model can (beyond the tolerance).
    too_flat : bool
        The faster curve is softer than the model allows (beyond the tolerance).
    """

    slow: str
    fast: str
    rate_slow: float
    rate_fast: float
    rate_ratio: float
    stress_ratio: float
    low: float
    high: float
    strain: np.ndarray
    too_steep: bool = False
    too_flat: bool = False

    def judge(self, tol: float) -> RatePair:
        """Set ``too_steep`` and ``too_flat`` with a relative margin ``tol``; return self."""
        self.too_steep = bool(self.stress_ratio > self.high * (1.0 + tol))
        self.too_flat = bool(self.stress_ratio < self.low / (1.0 + tol))
        return self


def _model_of(model_or_name, n_prony) -> tuple[_hyper.Hyperelastic, int]:
    if isinstance(model_or_name, ViscoHyperelastic):
        hm = model_or_name.hyperelastic
        n = model_or_name.n_prony if n_prony is None else n_prony
    else:
        hm = _hyper.get(model_or_name)
        n = 1 if n_prony is None else n_prony
    if n == "auto":  # any N >= 1 gives the same bound
        n = 1
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
        raise ValueError(f"n_prony = {n_prony!r} must be a whole number >= 0")
    return hm, int(n)


def _bases(hm: _hyper.Hyperelastic) -> np.ndarray:
    """Hyperelastic shapes whose non-negative combinations the bound covers."""
    ex = np.array(hm.example, dtype=np.float64)
    out = [ex]
    if hm.linear:
        for k in range(hm.n_params):
            if hm.units[k] == "MPa":
                e = np.where(np.arange(hm.n_params) == k, 1.0, 0.0)
                e = np.where([u == "MPa" for u in hm.units], e, ex)
                out.append(e)
    keep = []
    for b in out:
        with np.errstate(all="ignore"):
            mu0 = float(np.asarray(hm.initial_shear_modulus(b[None, :])).ravel()[0])
        if np.isfinite(mu0) and mu0 > 0:
            keep.append(b)
    return np.array(keep).reshape(len(keep), hm.n_params)


def _term_ratios(hm, pairs, tau) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-unit Prony overstress at the slow and the fast rate, for each basis and τ.

    ``pairs`` is a list of (strain array, slow rate, fast rate). Returns
    (h_slow, h_fast, base) of shapes (B, T, n) and (B, n), concatenated over pairs.
    """
    model = model_from_spec(ModelSpec(hm, Prony(1)))
    hist = []
    for eps, r1, r2 in pairs:
        hist += [History.constant_rate(eps, r1), History.constant_rate(eps, r2)]
    batch = model.batch(hist, measure="true")
    bases = _bases(hm)
    B = bases.shape[0]
    # serial: ~20 ms either way, and a started numba thread pool would stop
    # calibrate_many from forking its workers afterwards
    base, H = batch.shape_columns(bases, np.tile(tau, (B, 1)), parallel=False)
    slow_idx, fast_idx = [], []
    for j in range(len(pairs)):
        slow_idx.append(np.arange(batch.slices[2 * j].start, batch.slices[2 * j].stop))
        fast_idx.append(np.arange(batch.slices[2 * j + 1].start, batch.slices[2 * j + 1].stop))
    si, fi = np.concatenate(slow_idx), np.concatenate(fast_idx)
    return H[:, :, si], H[:, :, fi], base[:, si]


def _bounds_from_terms(h1, h2, base, k) -> tuple[np.ndarray, np.ndarray]:
    """Pointwise (low, high) of the stress ratio from the per-term responses."""
    n = h1.shape[-1]
    low = np.full(n, 1.0)
    high = np.full(n, 1.0)
    for j in range(n):
        s = np.sign(base[:, j])
        if not np.all(np.isfinite(base[:, j])) or np.any(s == 0) or np.any(s != s[0]):
            low[j], high[j] = -np.inf, np.inf
            continue
        a1, a2 = h1[:, :, j] * s[0], h2[:, :, j] * s[0]
        scale = max(float(np.nanmax(np.abs(a1))), float(np.nanmax(np.abs(a2))), 1e-300)
        ok = np.isfinite(a1) & np.isfinite(a2) & (np.abs(a1) > _RELIABLE * scale) \
            & (np.abs(a2) > _RELIABLE * scale)
        if np.any(ok & ((a1 < 0) | (a2 < 0))):  # a term of the opposite sign: unbounded
            low[j], high[j] = -np.inf, np.inf
            continue
        r = a2[ok] / a1[ok]
        # a -> 0 (viscous limit) gives k and a -> inf gives 1; both are limits of the set
        high[j] = max(1.0, k, float(r.max()) if r.size else k)
        low[j] = min(1.0, float(r.min()) if r.size else 1.0)
    return low, high


def _tau_grid(pairs) -> np.ndarray:
    lo = min(math.log10(float(np.min(np.abs(e))) / abs(r2)) for e, _, r2 in pairs)
    hi = max(math.log10(float(np.max(np.abs(e))) / abs(r1)) for e, r1, _ in pairs)
    lo -= _TAU_MARGIN
    hi += _TAU_MARGIN
    n = int(math.ceil((hi - lo) * _TAU_PER_DECADE)) + 1
    return 10.0 ** np.linspace(lo, hi, n)


def rate_ratio_bounds(model_or_name="mooney_rivlin", strain=None, rate_slow=-1.0,
                      rate_fast=-2.0, *, n_prony=None) -> tuple[np.ndarray, np.ndarray]:
    """Least and most stress ratio σ(rate_fast) / σ(rate_slow) the model can produce.

    For constant-rate ramps from rest and any non-negative moduli, any τ and any number
    of Prony terms (see the module notes for the derivation from Eq. 19).

    Parameters
    ----------
    model_or_name : str, Hyperelastic or ViscoHyperelastic
        The hyperelastic law (a ViscoHyperelastic also gives ``n_prony``).
    strain : array_like
        Engineering strains (sign of the rates), at which the ratio is bounded.
    rate_slow, rate_fast : float
        Strain rates in 1/s, same sign, ``|rate_fast| > |rate_slow|``.
    n_prony : int, optional
        Number of Prony terms; only 0 (bounds 1, 1) and ≥ 1 differ. Default: the
        model's, or 1 for a name.

    Returns
    -------
    low, high : ndarray
        Pointwise bounds of the ratio at each strain; (−inf, inf) where a term changes
        sign and no bound exists.

    Examples
    --------
    >>> import numpy as np
    >>> low, high = rate_ratio_bounds("mooney_rivlin", [-0.001, -0.5], -100.0, -200.0)
    >>> np.round(high, 6).tolist()     # doubling the rate at most doubles the stress
    [2.0, 2.0]
    """
    hm, n = _model_of(model_or_name, n_prony)
    eps = np.atleast_1d(np.asarray(strain, dtype=np.float64))
    r1, r2 = float(rate_slow), float(rate_fast)
    if not (r1 * r2 > 0 and abs(r2) > abs(r1)):
        raise ValueError(
            f"rates {r1:g} and {r2:g} 1/s: give two rates of the same sign with "
            "|rate_fast| > |rate_slow|"
        )
    if np.any(eps * r1 <= 0):
        raise ValueError("every strain must be non-zero and have the sign of the rates")
    if n == 0:
        return np.ones(eps.size), np.ones(eps.size)
    k = r2 / r1
    pairs = [(eps, r1, r2)]
    h1, h2, base = _term_ratios(hm, pairs, _tau_grid(pairs))
    return _bounds_from_terms(h1, h2, base, k)


def _matched(slow, fast, n: int = 10):
    """Matched strains in the overlap of two curves' objective points, and true stresses."""
    out = []
    for c in (slow, fast):
        e = np.asarray(c.target_strain, dtype=np.float64)
        s = np.asarray(c.target_stress, dtype=np.float64)
        if c.measure == "engineering":
            s = s * (1.0 + e)
        o = np.argsort(np.abs(e))
        out.append((np.abs(e[o]), s[o], float(np.sign(e[o][-1]))))
    (e1, s1, sg1), (e2, s2, sg2) = out
    lo = max(e1[0], e2[0])
    hi = min(e1[-1], e2[-1])
    if not hi > lo or hi <= 0:
        return None
    grid = np.linspace(lo, hi, n)
    return sg1 * grid, np.interp(grid, e1, s1), np.interp(grid, e2, s2)


def rate_pairs(curves: Sequence, model_or_name="mooney_rivlin", n_prony=None, *,
               tol: float = 0.05) -> list[RatePair]:
    """Every pair of constant-rate curves of one loading mode, with data and model ratios.

    Parameters
    ----------
    curves : sequence of Curve
        Curves with ``strain_rate``, ``target_strain``, ``target_stress``, ``measure``,
        ``name`` and ``is_constant_rate`` (curves with a time column are skipped: the
        bound is for ramps from rest; so are curves of another deformation than
        uniaxial, for which the bound is not derived, and equilibrium curves).
    model_or_name, n_prony
        See :func:`rate_ratio_bounds`.
    tol : float
        Relative margin for noise before a pair counts as out of bounds.

    Returns
    -------
    list of RatePair
        Pairs with different rates whose ratio could be bounded, each judged with
        ``tol`` (``too_steep``, ``too_flat``).
    """
    hm, n = _model_of(model_or_name, n_prony)
    cs = []
    for i, c in enumerate(curves):
        r = c.strain_rate
        if r is None or not np.isfinite(r) or r == 0 or not c.is_constant_rate:
            continue
        if not get_deformation(c.deformation).uniaxial:
            continue
        cs.append((abs(float(r)), i, c))
    cs.sort(key=lambda t: t[0])
    cand = []
    for a in range(len(cs)):
        for b in range(a + 1, len(cs)):
            (ra, _, ca), (rb, _, cb) = cs[a], cs[b]
            if np.sign(ca.strain_rate) != np.sign(cb.strain_rate) or rb <= ra * (1 + 1e-6):
                continue
            m = _matched(ca, cb)
            if m is None:
                continue
            eps, s1, s2 = m
            if np.any(eps * ca.strain_rate <= 0):
                continue
            den = float(np.sum(s1))
            if den == 0 or np.sign(den) != np.sign(ca.strain_rate):
                continue
            cand.append((ca, cb, eps, float(np.sum(s2)) / den))
    if not cand:
        return []
    specs = [(eps, float(ca.strain_rate), float(cb.strain_rate)) for ca, cb, eps, _ in cand]
    if n == 0:
        bounds = [(np.ones(e.size), np.ones(e.size)) for e, _, _ in specs]
    elif _bases(hm).size == 0:  # no usable shape of the law: nothing can be bounded
        return []
    else:
        try:
            with np.errstate(all="ignore"):
                h1, h2, base = _term_ratios(hm, specs, _tau_grid(specs))
        except (ValueError, ArithmeticError):  # a law undefined on these strains
            return []
        bounds, j = [], 0
        for eps, r1, r2 in specs:
            sl = slice(j, j + eps.size)
            bounds.append(_bounds_from_terms(h1[:, :, sl], h2[:, :, sl], base[:, sl], r2 / r1))
            j += eps.size
    out = []
    for (ca, cb, eps, ratio), (low, high) in zip(cand, bounds):
        out.append(RatePair(
            slow=str(ca.name), fast=str(cb.name),
            rate_slow=float(ca.strain_rate), rate_fast=float(cb.strain_rate),
            rate_ratio=float(cb.strain_rate / ca.strain_rate), stress_ratio=ratio,
            low=float(np.min(low)), high=float(np.max(high)), strain=eps,
        ).judge(tol))
    return out


def rate_sensitivity(curves: Sequence, model_or_name="mooney_rivlin", n_prony=None, *,
                     tol: float = 0.05) -> list[str]:
    """Warnings naming the curve pairs whose rate sensitivity the model cannot represent.

    For every two constant-rate curves of one loading mode at rates r1 < r2 (in
    magnitude), the summed true stress at matched strains of the faster curve over that
    of the slower one is compared with the least and most ratio a hyperelastic law plus
    Prony terms with G_i ≥ 0 can produce between these rates (:func:`rate_ratio_bounds`;
    in compression at most r2/r1 — doubling the rate at most doubles the stress — and
    at least 1). A pair outside the bounds by more than ``tol`` cannot be fitted by any
    parameters of the model.

    Parameters
    ----------
    curves : sequence of Curve
        The calibration curves.
    model_or_name : str, Hyperelastic or ViscoHyperelastic
        The hyperelastic law (or the whole model).
    n_prony : int or "auto", optional
        Number of Prony terms (0: no rate dependence at all). Default: the model's, or 1.
    tol : float
        Relative margin for noise (default 5 %).

    Returns
    -------
    list of str
        One message per offending pair, naming both curves; empty if all is well.

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> eps = np.linspace(-0.05, -0.5, 10)
    >>> slow = vhfit.Curve(strain=eps, stress=eps, strain_rate=-1000.0, name="slow")
    >>> fast = vhfit.Curve(strain=eps, stress=3 * eps, strain_rate=-2000.0, name="fast")
    >>> msgs = rate_sensitivity([slow, fast], "mooney_rivlin", 3)
    >>> len(msgs), "'slow'" in msgs[0] and "'fast'" in msgs[0]
    (1, True)
    """
    hm, n = _model_of(model_or_name, n_prony)
    pairs = rate_pairs(curves, model_or_name, n_prony, tol=tol)
    if n == 0:
        bad = [p for p in pairs if p.too_steep or p.too_flat]
        if not bad:
            return []
        names = []
        for p in bad:
            names += [x for x in (p.slow, p.fast) if x not in names]
        ratios = [p.stress_ratio for p in bad]
        return [
            f"curves {', '.join(repr(x) for x in names)} differ with the strain rate (stress "
            f"ratios x{min(ratios):.3g} to x{max(ratios):.3g} at matched strains), but "
            f"{hm.name} without Prony terms gives the same stress at every rate: no parameters "
            "fit them all; add Prony terms (n_prony >= 1)"
        ]
    msgs = []
    for p in pairs:
        head = (f"curves {p.slow!r} ({p.rate_slow:g} 1/s) and {p.fast!r} ({p.rate_fast:g} 1/s): "
                f"the rate rises x{p.rate_ratio:.3g} and the measured stress "
                f"x{p.stress_ratio:.3g} (at matched strains up to "
                f"{float(np.max(np.abs(p.strain))):.3g}), but {hm.name} with {n} Prony "
                "term(s), G_i >= 0, ")
        if p.too_steep:
            msgs.append(
                head + f"can raise the stress at most x{p.high:.3g} between these rates "
                "(a Prony term's stress is at most proportional to the rate, Eq. 19): no "
                "parameters fit both curves; expect a large error on them, or use a model "
                "with stronger rate stiffening"
            )
        elif p.too_flat:
            msgs.append(
                head + f"makes the faster curve at least x{p.low:.3g} as stiff: no parameters "
                "fit both curves; check the data (rate labels, specimen scatter, heating)"
            )
    return msgs
