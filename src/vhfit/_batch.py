"""Evaluation plan of a :class:`vhfit.model.ViscoHyperelastic` on fixed histories.

A :class:`Batch` lays out, once, the grids, sample stretches and gather indices of a set
of histories (uniaxial recursion, the general plans of :mod:`vhfit._plans`, long-term and
small-strain loads) and then evaluates whole populations of parameter sets at once: the
hot path of every search. Built by :meth:`vhfit.model.ViscoHyperelastic.batch`; kept
apart from the model, which describes one material and its keyword front door.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from vhfit import _kernels
from vhfit._deformation import refusal_for
from vhfit._linear import LinearLoad, LinearPlan
from vhfit._plans import EquilibriumPlan, GeneralPlan, on_uniaxial_kernel
from vhfit.history import History

__all__ = ["Batch"]

_MEASURES = ("true", "engineering")


def check_measure(measure) -> str:
    """``measure`` if it is a stress measure a model can give ("true": Cauchy,
    "engineering": nominal), else a one-line ValueError."""
    if measure not in _MEASURES:
        raise ValueError(f"measure = {measure!r}; choose 'true' or 'engineering'")
    return measure


def _history_of(item) -> History | LinearLoad:
    if isinstance(item, (History, LinearLoad)):
        return item
    try:
        h = item.history  # a test item (vhfit.data.TestItem): curve, sweep, relaxation
    except AttributeError:
        h = None
    if isinstance(h, (History, LinearLoad)):
        return h
    raise TypeError(
        f"expected a vhfit.History or a Curve (anything with a .history), got {type(item).__name__}"
    )


def _measure_of(item) -> str:
    """A test item's stress measure; a bare history's targets are true stresses."""
    return "true" if isinstance(item, (History, LinearLoad)) else item.measure


class Batch:
    """Evaluation plan of a model on fixed histories, for whole populations at once.

    Built by :meth:`ViscoHyperelastic.batch`. The grids, sample stretches and
    gather indices are computed once; each call evaluates the hyperelastic law at
    every sample for every parameter set (numpy) and the Prony recursion (numba,
    parallel over parameter sets and curves). Under the "hereditary" formulation,
    uniaxial histories run the uniaxial recursion of :func:`vhfit._kernels.overstress`;
    the other tests, and every test under another formulation, its general form
    (docs/theory.md §13–14), one kernel job per history and loaded direction;
    equilibrium histories need the long-term law alone; small-strain tests
    (:class:`vhfit._linear.LinearLoad`: frequency sweeps, relaxation tests) give the
    moduli of the generalised Maxwell model, the same in every formulation
    (docs/theory.md §10).
    """

    def __init__(self, model, histories: Sequence, measure=None):
        # model: a vhfit.model.ViscoHyperelastic (not imported: the model imports this)
        self.model = model
        items = list(histories)
        if not items:
            raise ValueError("give at least one history or curve")
        hs = [_history_of(it) for it in items]
        for h in hs:  # a test the law cannot deform in (J ≠ 1) has no stress to give
            why = refusal_for(model.hyperelastic, h.deformation)
            if why:
                raise ValueError(why)
        if measure is None or isinstance(measure, str):
            measures = [measure if measure is not None else _measure_of(it) for it in items]
        else:
            measures = list(measure)
            if len(measures) != len(items):
                raise ValueError("give one measure per history")
        for m in measures:
            check_measure(m)
        self.histories = hs
        self.measures = measures
        sizes = [h.out_time.size for h in hs]
        bounds = np.cumsum([0] + sizes)
        self.slices = [slice(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])]
        self.n_points = int(bounds[-1])
        self._eng = np.concatenate(
            [np.full(n, m == "engineering") for n, m in zip(sizes, measures)]
        )
        form = model._formulation
        self._linear = LinearPlan(hs, self.slices)  # small-strain tests: moduli
        uni = [c for c, h in enumerate(hs) if on_uniaxial_kernel(form, h)]
        self._plan_uniaxial(uni)
        self._general = GeneralPlan(model._dlog, hs, self.slices, form)
        self._equilibrium = EquilibriumPlan(hs, self.slices)
        out_stretch = np.empty(self.n_points)
        out_stretch[self._pos_u] = self._out_lam_u
        for h, sl in zip(hs, self.slices):
            if not on_uniaxial_kernel(form, h):
                out_stretch[sl] = h.out_loaded_stretch
        self.out_stretch = out_stretch

    def _plan_uniaxial(self, which: list[int]) -> None:
        """Grids and gather indices of the uniaxial histories with a rate or a time."""
        lam_s, hstep, gather_node, gather_sample, out_lam, pos = [], [], [], [], [], []
        s_off, k_off = [0], [0]
        v = _kernels.LOBATTO
        for c, k in enumerate(which):
            hist = self.histories[k]
            t, lam, idx = hist.grid(self.model._dlog)
            dt = np.diff(t)
            inner = lam[:-1, None] + (lam[1:] - lam[:-1])[:, None] * v[None, 1:]
            samples = np.concatenate([lam[:1], inner.reshape(-1)])
            node0 = k_off[-1] + c
            gather_node.append(node0 + idx)
            gather_sample.append(s_off[-1] + _kernels.STRIDE * idx)
            out_lam.append(lam[idx])
            lam_s.append(samples)
            hstep.append(dt)
            pos.append(np.arange(self.slices[k].start, self.slices[k].stop))
            s_off.append(s_off[-1] + samples.size)
            k_off.append(k_off[-1] + dt.size)
        cat = lambda parts, dtype=np.float64: (  # noqa: E731
            np.concatenate(parts) if parts else np.zeros(0, dtype=dtype))
        self.sample_stretch = cat(lam_s)
        # a read-only copy for the law: what it derives from the stretches is remembered
        self._fixed_stretch = self.sample_stretch.copy()
        self._fixed_stretch.flags.writeable = False
        self.step = cat(hstep)
        self.sample_off = np.array(s_off, dtype=np.int64)
        self.step_off = np.array(k_off, dtype=np.int64)
        self._gather_node = cat(gather_node, np.int64)
        self._gather_sample = cat(gather_sample, np.int64)
        self._out_lam_u = cat(out_lam)
        self._pos_u = cat(pos, np.int64)

    def shape_columns(self, hyper, tau, *, parallel: bool | None = None
                      ) -> tuple[np.ndarray, np.ndarray]:
        """Stress per unit modulus: the long-term shape and each Prony branch.

        For hyperelastic constants ``hyper`` (P, n_h) and relaxation times ``tau``
        (P, N), returns (``s_hat``, ``h``) with shapes (P, n_points) and
        (P, N, n_points) such that the stress is ``E∞ s_hat + Σ_i G_i h[:, i]``
        (in each curve's measure; the Prony columns of equilibrium histories are 0).
        For fixed shape and τ the model is linear in (E∞, G_i): the basis of the
        separable calibration (docs/theory.md §5, §10). ``parallel`` chooses numba's
        threaded kernel (None: by problem size).
        """
        hyper = np.atleast_2d(np.asarray(hyper, dtype=np.float64))
        tau = np.atleast_2d(np.asarray(tau, dtype=np.float64))
        P, N = tau.shape
        s_hat, ok, E_inf = self._s_hat(hyper)
        if self._pos_u.size == self.n_points:
            # all uniaxial with a rate or a time (positions in order): the gathers are the
            # columns themselves, no zeros to scatter them into
            ov = _kernels.overstress_columns(
                s_hat, self.sample_stretch, self.step, self.sample_off, self.step_off,
                np.ascontiguousarray(tau), _kernels.DERIV, parallel,
            )
            base = s_hat[:, self._gather_sample]
            h = ov[:, self._gather_node].reshape(P, N, self.n_points)
            base[~ok] = np.inf
            h[~ok] = np.inf
            return self._measure(base), self._measure(h)
        base = np.zeros((P, self.n_points))
        h = np.zeros((P, N, self.n_points))
        if self._pos_u.size:
            ov = _kernels.overstress_columns(
                s_hat, self.sample_stretch, self.step, self.sample_off, self.step_off,
                np.ascontiguousarray(tau), _kernels.DERIV, parallel,
            )
            h[:, :, self._pos_u] = ov[:, self._gather_node].reshape(P, N, self._pos_u.size)
            base[:, self._pos_u] = s_hat[:, self._gather_sample]
        if self._general.jobs:
            ok &= self._general.shape_columns(self.model.hyperelastic, hyper, E_inf, tau,
                                              base, h, parallel)
        self._linear.shape_columns(tau, base, h)
        with np.errstate(all="ignore"):  # E∞ <= 0: invalid, +inf below
            ok &= self._equilibrium.fill(self.model.hyperelastic, hyper, 1.0 / E_inf, base)
        base[~ok] = np.inf
        h[~ok] = np.inf
        return self._measure(base), self._measure(h)

    def _s_hat(self, hyper: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        hm = self.model.hyperelastic
        with np.errstate(all="ignore"):
            E_inf = 3.0 * hm.initial_shear_modulus(hyper)
            sig_h = hm.stress(self._fixed_stretch, hyper)
            s_hat = sig_h / E_inf[:, None]
        # an infinite constant is no material even where the law has a finite limit
        # (Arruda–Boyce with λm = ∞ is neo-Hooke)
        ok = (E_inf > 0) & np.all(np.isfinite(s_hat), axis=1) & np.all(np.isfinite(hyper), axis=1)
        s_hat[~ok] = 0.0
        return s_hat, ok, E_inf

    def _measure(self, s: np.ndarray) -> np.ndarray:
        """Nominal stress at the engineering curves' points, in place (``s`` is fresh)."""
        if self._eng.all():
            s /= self.out_stretch
        elif self._eng.any():
            s[..., self._eng] /= self.out_stretch[self._eng]
        return s

    def __call__(self, X) -> np.ndarray:
        """Stresses (P, n_points) for parameter sets X (P, n_params); +inf where invalid."""
        X = np.atleast_2d(np.asarray(X, dtype=np.float64))
        if X.shape[1] != self.model.n_params:
            raise ValueError(
                f"X has {X.shape[1]} columns; the model has {self.model.n_params} parameters "
                f"{self.model.param_names}"
            )
        hyper, G, tau = self.model.split(X)
        s_hat, ok, E_inf = self._s_hat(hyper)
        ok &= np.all((G >= 0) & (tau > 0), axis=1)
        with np.errstate(all="ignore"):  # invalid individuals become +inf below
            sig_u = E_inf[:, None] * s_hat[:, self._gather_sample]
        if self.model.n_prony and self._pos_u.size:
            ov = _kernels.overstress(
                s_hat, self.sample_stretch, self.step, self.sample_off, self.step_off,
                np.ascontiguousarray(G), np.ascontiguousarray(tau), _kernels.DERIV,
            )
            sig_u += ov[:, self._gather_node]
        if self._pos_u.size == self.n_points:
            sig = sig_u  # all uniaxial with a rate or time: today's plan as it was
        else:
            sig = np.zeros((X.shape[0], self.n_points))
            sig[:, self._pos_u] = sig_u
            if self._general.jobs:
                ok &= self._general.stress(self.model.hyperelastic, hyper, E_inf, G, tau, sig)
            ok &= self._equilibrium.fill(self.model.hyperelastic, hyper, 1.0, sig)
            self._linear.stress(E_inf, G, tau, sig)
        sig[~ok] = np.inf
        sig[~np.isfinite(sig)] = np.inf
        return self._measure(sig)
