"""Evaluation plans of :class:`vhfit.model.Batch` for tests other than uniaxial.

:class:`GeneralPlan` lays out the histories with a rate or a time of every test but the
paper's uniaxial one (and of that one under a formulation without its kernel) for
:func:`vhfit._kernels.overstress_general`: one kernel curve per history and loaded
direction, its samples (the nodes of the history's grid and the inner Gauss–Lobatto
points of each step) and its weights c_k(t) at the nodes (docs/theory.md §13).
:class:`EquilibriumPlan` evaluates the long-term law at the samples of equilibrium
histories of any test. Both write into the batch's (P, n_points) arrays at their
histories' positions and return which parameter sets gave finite values.
"""

from __future__ import annotations

import numpy as np

from vhfit import _kernels, modes


def _lobatto(nodes: np.ndarray) -> np.ndarray:
    """Values at the kernel's samples of a quantity linear between the nodes."""
    v = _kernels.LOBATTO
    inner = nodes[:-1, None] + (nodes[1:] - nodes[:-1])[:, None] * v[None, 1:]
    return np.concatenate([nodes[:1], inner.reshape(-1)])


def _groups(keys: list, parts: list[np.ndarray]) -> dict:
    """(deformation, direction) -> concatenated index arrays of ``parts`` with that key."""
    out: dict = {}
    for key, idx in zip(keys, parts):
        out.setdefault(key, []).append(idx)
    return {k: np.concatenate(v) for k, v in out.items()}


def _frozen(a: np.ndarray) -> np.ndarray:
    """A read-only float64 copy: what the law derives from it alone (the stretches of
    the test, the Ogden sums' logarithms) is computed once per plan, not per call
    (:mod:`vhfit._fixed`)."""
    out = np.array(a, dtype=np.float64)
    out.flags.writeable = False
    return out


def _x2(deformation: str, x2):
    """The second stretch of a test that prescribes one, else None."""
    return x2 if modes.get_deformation(deformation).second_stretch else None


def _long_term_coefficients(key, x1, x2):
    """:func:`vhfit.modes.long_term_coefficients` of a (deformation, direction) group
    (None for uniaxial, whose stress is the law's own)."""
    deformation, d = key
    if modes.get_deformation(deformation).uniaxial:
        return None
    return modes.long_term_coefficients(deformation, x1, _x2(deformation, x2), d)


def on_uniaxial_kernel(formulation, hist) -> bool:
    """Whether ``hist`` runs the dedicated uniaxial kernel under ``formulation``."""
    return (formulation.uniaxial_kernel and not hist.is_linear and not hist.is_equilibrium
            and modes.get_deformation(hist.deformation).uniaxial)


class GeneralPlan:
    """Kernel layout of the histories with a rate or a time that the uniaxial kernel
    does not run."""

    def __init__(self, dlog: float, histories, slices, formulation):
        x1, x2, w, steps, gnode, gsample, pos, keys, samples = ([] for _ in range(9))
        s_off, k_off = [0], [0]
        self.jobs = 0
        self.formulation = formulation
        for hist, sl in zip(histories, slices):
            if hist.is_equilibrium or hist.is_linear or on_uniaxial_kernel(formulation, hist):
                continue
            t, x1n, idx = hist.grid(dlog)
            x2n = hist.stretch2_at(t)
            for d in (1, 2):
                sel = np.flatnonzero(hist.out_direction == d)
                if not sel.size:
                    continue
                c = self.jobs
                self.jobs += 1
                xs1 = _lobatto(x1n)
                x1.append(xs1)
                x2.append(_lobatto(x2n) if x2n is not None else np.ones_like(xs1))
                w.append(np.asarray(formulation.weights(hist.deformation, x1n, x2n, d),
                                    dtype=np.float64).T)
                steps.append(np.diff(t))
                gnode.append(k_off[-1] + c + idx[sel])
                gsample.append(s_off[-1] + _kernels.STRIDE * idx[sel])
                pos.append(sl.start + sel)
                keys.append((hist.deformation, d))
                samples.append(np.arange(s_off[-1], s_off[-1] + xs1.size))
                s_off.append(s_off[-1] + xs1.size)
                k_off.append(k_off[-1] + t.size - 1)
        if not self.jobs:
            return
        self.x1, self.x2 = _frozen(np.concatenate(x1)), _frozen(np.concatenate(x2))
        self.w = np.ascontiguousarray(np.concatenate(w))
        self.step = np.concatenate(steps)
        self.sample_off = np.array(s_off, dtype=np.int64)
        self.step_off = np.array(k_off, dtype=np.int64)
        self.gather_node = np.concatenate(gnode)
        self.gather_sample = np.concatenate(gsample)
        self.pos = np.concatenate(pos)
        self.sample_groups = _groups(keys, samples)
        # each group's data, fixed: one array per group and plan, not per call
        self.sample_data = self._data(self.sample_groups)
        # the kinematic part of the factors (of invariant laws, hereditary), once per plan
        self.coefficients = {(deformation, d): formulation.prepare(deformation, x1, x2, d)
                             for (deformation, d), (x1, x2) in self.sample_data.items()}
        if formulation.kinematic:  # the same factors for every parameter set: once
            self.kinematic_factors = self._factors(None, None, None)[:2]
            f0, f1 = (f[0] for f in self.kinematic_factors)
            self.steps = _kernels.step_derivatives(f0, f1, self.sample_off, self.step_off,
                                                   _kernels.DERIV)
        self.out_groups = _groups(keys, gsample)  # sample index of each output, by key
        self.out_pos = _groups(keys, pos)
        self.out_data = self._data(self.out_groups)
        self.out_coefficients = {key: _long_term_coefficients(key, *self.out_data[key])
                                 for key in self.out_groups}

    def _data(self, groups: dict) -> dict:
        """(deformation, direction) -> (x1, x2 or None) at the samples ``groups`` index."""
        if len(groups) == 1 and all(idx.size == self.x1.size and np.array_equal(
                idx, np.arange(idx.size)) for idx in groups.values()):
            ((deformation, d),) = groups
            return {(deformation, d): (self.x1, _x2(deformation, self.x2))}
        return {(deformation, d): (_frozen(self.x1[idx]),
                                   _x2(deformation, _frozen(self.x2[idx])))
                for (deformation, d), idx in groups.items()}

    def _factors(self, hm, hyper, E_inf):
        """f0, f1 (P, S) at every sample, and which parameter sets gave finite values.

        A kinematic formulation's are computed once, ``hyper`` None, (1, S) for all sets.
        """
        form = self.formulation
        rows = 1 if hyper is None else hyper.shape[0]
        with np.errstate(all="ignore"):
            if len(self.sample_groups) == 1:  # one test and direction: no scatter
                ((deformation, d), (x1, x2)), = self.sample_data.items()
                f0, f1 = form.factors(hm, hyper, E_inf, deformation, x1, x2, d,
                                      self.coefficients[deformation, d])
                f0, f1 = (np.broadcast_to(f, (rows, self.x1.size)) for f in (f0, f1))
            else:
                f0 = np.empty((rows, self.x1.size))
                f1 = np.empty((rows, self.x1.size))
                for (deformation, d), idx in self.sample_groups.items():
                    x1, x2 = self.sample_data[deformation, d]
                    f0[:, idx], f1[:, idx] = form.factors(
                        hm, hyper, E_inf, deformation, x1, x2, d,
                        self.coefficients[deformation, d])
            # a sum is finite exactly when every term is (short of overflow near 1e308)
            ok = np.isfinite(np.sum(f0, axis=1) + np.sum(f1, axis=1))
        if not ok.all():
            f0, f1 = np.array(f0), np.array(f1)
            f0[~ok] = 0.0
            f1[~ok] = 0.0
        return np.ascontiguousarray(f0), np.ascontiguousarray(f1), ok

    def _long_term(self, hm, hyper, scale, out) -> np.ndarray:
        ok = np.ones(hyper.shape[0], dtype=bool)
        with np.errstate(all="ignore"):
            for key, (x1, x2) in self.out_data.items():
                deformation, d = key
                s = modes.long_term_stress(hm, hyper, deformation, x1, x2, d,
                                           self.out_coefficients[key])
                s = s * scale
                out[:, self.out_pos[key]] = s
                ok &= np.all(np.isfinite(s), axis=1)
        return ok

    def _overstress(self, hm, hyper, E_inf, G, tau, parallel=None):
        """Σ_i G_i h_i at the nodes (rows of G, tau; ``len(G)`` a multiple of the sets),
        and which parameter sets gave finite factors."""
        G, tau = np.ascontiguousarray(G), np.ascontiguousarray(tau)
        steps = None
        if self.formulation.kinematic:  # one set of factors and step coefficients for all
            (f0, f1), ok, steps = self.kinematic_factors, np.ones(hyper.shape[0], bool), self.steps
        else:
            f0, f1, ok = self._factors(hm, hyper, E_inf)
        return _kernels.overstress_general(
            f0, f1, self.w, self.step, self.sample_off, self.step_off, G, tau, _kernels.DERIV,
            parallel, repeat=G.shape[0] // f0.shape[0], steps=steps), ok

    def stress(self, hm, hyper, E_inf, G, tau, sig) -> np.ndarray:
        """Write σ = σ_h + Σ G_i h_i at this plan's outputs into ``sig``; valid sets."""
        ok = self._long_term(hm, hyper, 1.0, sig)
        if G.shape[1]:
            ov, ok_f = self._overstress(hm, hyper, E_inf, G, tau)
            sig[:, self.pos] += ov[:, self.gather_node]
            ok &= ok_f
        return ok

    def shape_columns(self, hm, hyper, E_inf, tau, base, h, parallel) -> np.ndarray:
        """Write σ_h/E∞ into ``base`` and each branch's h_i into ``h``; valid sets."""
        P, N = tau.shape
        with np.errstate(all="ignore"):
            ok = self._long_term(hm, hyper, 1.0 / E_inf[:, None], base)
        ov, ok_f = self._overstress(hm, hyper, E_inf, np.ones((P * N, 1)),
                                    tau.reshape(P * N, 1), parallel)
        h[:, :, self.pos] = ov[:, self.gather_node].reshape(P, N, self.pos.size)
        return ok & ok_f


class EquilibriumPlan:
    """The long-term law at the samples of the equilibrium histories."""

    def __init__(self, histories, slices):
        self.groups: dict = {}
        for hist, sl in zip(histories, slices):
            if not hist.is_equilibrium:
                continue
            x1 = hist.out_stretch
            x2 = hist.stretch2_at(hist.out_time)
            for d in (1, 2):
                sel = np.flatnonzero(hist.out_direction == d)
                if sel.size:
                    g = self.groups.setdefault((hist.deformation, d), ([], [], []))
                    g[0].append(x1[sel])
                    g[1].append(x2[sel] if x2 is not None else np.ones(sel.size))
                    g[2].append(sl.start + sel)
        self.groups = {k: (_frozen(np.concatenate(x1)), _frozen(np.concatenate(x2)),
                           np.concatenate(pos))
                       for k, (x1, x2, pos) in self.groups.items()}
        self.coefficients = {k: _long_term_coefficients(k, x1, x2)
                             for k, (x1, x2, _) in self.groups.items()}

    def fill(self, hm, hyper, scale, out) -> np.ndarray:
        """Write the long-term stress times ``scale`` into ``out[:, positions]``; valid sets."""
        ok = np.ones(hyper.shape[0], dtype=bool)
        scale = np.reshape(scale, (-1, 1)) if np.ndim(scale) else scale
        with np.errstate(all="ignore"):
            for (deformation, d), (x1, x2, pos) in self.groups.items():
                s = modes.long_term_stress(hm, hyper, deformation, x1, _x2(deformation, x2), d,
                                           self.coefficients[deformation, d])
                s = np.broadcast_to(s * scale, (hyper.shape[0], pos.size))
                out[:, pos] = s
                ok &= np.all(np.isfinite(s), axis=1)
        return ok
