"""Self-adaptive differential evolution variants: jDE, SHADE and L-SHADE.

These strategies adapt the mutation factor F and the crossover rate CR while the run
goes, from which trials succeed. SciPy's callable-strategy hook cannot see which
trials succeeded, so they run inside vhfit's :class:`DifferentialEvolutionSolver`
(pass ``strategy="jde" | "shade" | "lshade"``, or an instance to change a parameter).

All three work in the solver's unit cube and keep every trial inside the bounds by
moving an out-of-bounds component halfway between the parent and the violated bound
(never SciPy's uniform re-draw over the whole range). All random numbers come from the
solver's generator, so a seed gives bit-identical runs, with any ``workers``.

References
----------
.. [1] J. Brest, S. Greiner, B. Boskovic, M. Mernik, V. Zumer, "Self-adapting control
   parameters in differential evolution: a comparative study on numerical benchmark
   problems", IEEE Trans. Evol. Comput. 10(6), 646-657 (2006).
.. [2] R. Tanabe, A. Fukunaga, "Success-history based parameter adaptation for
   differential evolution", IEEE CEC 2013, 71-78.
.. [3] R. Tanabe, A. Fukunaga, "Improving the search performance of SHADE using linear
   population size reduction", IEEE CEC 2014, 1658-1665.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from vhfit.optimize._state import from_plain, to_plain

__all__ = ["AdaptiveStrategy", "JDE", "SHADE", "LSHADE", "adaptive_strategies"]


# ----------------------------------------------------------------------------- helpers
def _integers(rng, high: int, size: int) -> np.ndarray:
    """Uniform integers in [0, high) from a Generator or a legacy RandomState."""
    if isinstance(rng, np.random.Generator):
        return rng.integers(0, high, size=size)
    return rng.randint(0, high, size=size)


def _pick(rng, n: int, size: int, exclude: list[np.ndarray]) -> np.ndarray:
    """One index in [0, n) per row, different from the same row of every `exclude`."""
    out = _integers(rng, n, size)
    while True:
        bad = np.zeros(size, dtype=bool)
        for ex in exclude:
            bad |= out == ex
        k = int(np.count_nonzero(bad))
        if k == 0:
            return out
        out[bad] = _integers(rng, n, k)


def _repair_midpoint(trial: np.ndarray, parents: np.ndarray) -> np.ndarray:
    """Move components outside [0, 1] halfway between the parent and the bound."""
    low = trial < 0.0
    if low.any():
        trial[low] = 0.5 * parents[low]
    high = trial > 1.0
    if high.any():
        trial[high] = 0.5 * (1.0 + parents[high])
    return trial


def _check(name: str, value: Any, lo: float, hi: float, *, integer: bool = False,
           open_lo: bool = False) -> Any:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    bad = not math.isfinite(v) or v > hi or (v <= lo if open_lo else v < lo)
    if integer and (isinstance(value, bool) or v != int(v)):
        bad = True
    if bad:
        kind = "an integer" if integer else "a number"
        lo_s = f"> {lo:g}" if open_lo else f">= {lo:g}"
        raise ValueError(f"{name} must be {kind} {lo_s} and <= {hi:g}, got {value!r}")
    return int(v) if integer else v


# ----------------------------------------------------------------------------- base
class AdaptiveStrategy:
    """Base class of strategies run by vhfit's own generation loop.

    A strategy object holds only its settings; run-time state lives in the object
    returned by :meth:`init_state`, stored on the solver, so one strategy instance can
    be reused for many runs. All vectors are in the solver's unit cube ``[0, 1]^N``.

    Per generation the solver calls :meth:`begin_generation` (draw every random number
    the generation needs, vectorised), then for each candidate :meth:`trial` and
    :meth:`report` (``updating='immediate'``), or :meth:`trials` and
    :meth:`report_many` once (``'deferred'``), then :meth:`end_generation`.
    """

    name = "adaptive"
    #: smallest population the strategy can work with
    min_population = 4

    def init_state(self, solver) -> Any:
        """Create the run-time state for `solver` (called before the first generation)."""
        raise NotImplementedError

    def begin_generation(self, solver, state) -> None:
        """Draw the generation's random numbers."""

    def trial(self, solver, state, c: int) -> np.ndarray:
        """Trial vector for candidate `c` (shape (N,), inside [0, 1])."""
        return self.trials(solver, state, np.array([c]))[0]

    def trials(self, solver, state, candidates: np.ndarray) -> np.ndarray:
        """Trial vectors for `candidates`, shape ``(len(candidates), N)``, inside [0, 1]."""
        raise NotImplementedError

    def report(self, solver, state, c: int, accepted: bool, delta: float,
               parent: np.ndarray) -> None:
        """Feedback on candidate `c`'s trial (see :meth:`report_many`)."""
        self.report_many(solver, state, np.array([c]), np.array([accepted]),
                         np.array([delta]), parent[None, :])

    def report_many(self, solver, state, candidates: np.ndarray, accepted: np.ndarray,
                    delta: np.ndarray, parents: np.ndarray) -> None:
        """Feedback after evaluating the trials of `candidates`.

        `accepted` says which trials replaced their parent, `delta` is the strict
        improvement ``f(parent) - f(trial)`` (0 where not a finite improvement), and
        `parents` are the parents' unit vectors before replacement.
        """

    def end_generation(self, solver, state) -> None:
        """Called once per generation after every candidate was processed."""

    def swap(self, state, i: int, j: int) -> None:
        """Population members `i` and `j` swapped places (best moved to slot 0)."""

    def resize(self, state, keep: np.ndarray) -> None:
        """The population was reduced to the members `keep` (in that order)."""

    def dump_state(self, state) -> dict:
        """The run-time `state` as plain JSON types (for the solver's ``state_dict``).

        The default stores every attribute of the state object (its ``__slots__`` or
        ``__dict__``) that holds numbers, strings, None, numpy arrays, or lists, tuples
        and dicts of those. Override it (with :meth:`restore_state`) for other state.
        """
        # getattr default: a state class with __slots__ has no __dict__, others no slots
        names = getattr(type(state), "__slots__", None) or list(vars(state))
        try:
            return {n: to_plain(getattr(state, n)) for n in names if hasattr(state, n)}
        except TypeError as exc:
            raise ValueError(
                f"strategy {self.name!r}: its run-time state cannot be stored ({exc}); "
                "override AdaptiveStrategy.dump_state and restore_state") from None

    def restore_state(self, solver, data: dict) -> Any:
        """A run-time state rebuilt from :meth:`dump_state`'s output, for `solver`."""
        state = self.init_state(solver)
        for name, value in data.items():
            setattr(state, name, from_plain(value))
        return state

    def __repr__(self) -> str:
        fields = ", ".join(f"{k}={v!r}" for k, v in vars(self).items())
        return f"{type(self).__name__}({fields})"


def _crossover_draws(rng, NP: int, N: int) -> tuple[np.ndarray, np.ndarray]:
    """Uniforms and j_rand of a generation's binomial crossovers."""
    return rng.uniform(size=(NP, N)), _integers(rng, N, NP)


def _crossover(u: np.ndarray, jrand: np.ndarray, cr: np.ndarray, cand: np.ndarray,
               mutants: np.ndarray, parents: np.ndarray) -> np.ndarray:
    """Binomial crossover of candidates `cand`: component j_rand always from the mutant."""
    mask = u[cand] < cr[:, None]
    mask[np.arange(cand.size), jrand[cand]] = True
    return np.where(mask, mutants, parents)


# ----------------------------------------------------------------------------- jDE
class _JDEState:
    __slots__ = ("F", "CR", "new_F", "new_CR", "r", "u", "jrand")


class JDE(AdaptiveStrategy):
    """jDE: self-adapting F and CR per individual, rand/1/bin (Brest et al. 2006).

    Each individual carries its own F and CR. Before making its trial, with
    probability `tau_F` a new F is drawn from U[`F_lower`, `F_lower` + `F_range`], and
    with probability `tau_CR` a new CR from U[0, 1]; the new values survive only if
    the trial replaces the parent.

    Parameters
    ----------
    tau_F, tau_CR : float, optional
        Probabilities of re-drawing F and CR. Default 0.1 each.
    F_lower, F_range : float, optional
        New F values are drawn from U[F_lower, F_lower + F_range]. Default 0.1, 0.9.
    F_init, CR_init : float, optional
        Initial F and CR of every individual. Default 0.5 and 0.9.
    """

    name = "jde"

    def __init__(self, tau_F: float = 0.1, tau_CR: float = 0.1, F_lower: float = 0.1,
                 F_range: float = 0.9, F_init: float = 0.5, CR_init: float = 0.9) -> None:
        self.tau_F = _check("JDE: tau_F", tau_F, 0, 1)
        self.tau_CR = _check("JDE: tau_CR", tau_CR, 0, 1)
        self.F_lower = _check("JDE: F_lower", F_lower, 0, 2)
        self.F_range = _check("JDE: F_range", F_range, 0, 2)
        self.F_init = _check("JDE: F_init", F_init, 0, 2, open_lo=True)
        self.CR_init = _check("JDE: CR_init", CR_init, 0, 1)

    def init_state(self, solver) -> _JDEState:
        n = solver.num_population_members
        st = _JDEState()
        st.F = np.full(n, self.F_init)
        st.CR = np.full(n, self.CR_init)
        return st

    def begin_generation(self, solver, st: _JDEState) -> None:
        rng = solver.random_number_generator
        NP, N = solver.population.shape
        cand = np.arange(NP)
        u = rng.uniform(size=(4, NP))
        st.new_F = np.where(u[0] < self.tau_F, self.F_lower + u[1] * self.F_range, st.F)
        st.new_CR = np.where(u[2] < self.tau_CR, u[3], st.CR)
        r1 = _pick(rng, NP, NP, [cand])
        r2 = _pick(rng, NP, NP, [cand, r1])
        r3 = _pick(rng, NP, NP, [cand, r1, r2])
        st.r = np.stack([r1, r2, r3])
        st.u, st.jrand = _crossover_draws(rng, NP, N)

    def trial(self, solver, st: _JDEState, c: int) -> np.ndarray:
        pop = solver.population
        r1, r2, r3 = st.r[:, c]
        parent = pop[c]
        mutant = pop[r1] + st.new_F[c] * (pop[r2] - pop[r3])
        mask = st.u[c] < st.new_CR[c]
        mask[st.jrand[c]] = True
        return _repair_midpoint(np.where(mask, mutant, parent), parent)

    def trials(self, solver, st: _JDEState, cand: np.ndarray) -> np.ndarray:
        pop = solver.population
        r1, r2, r3 = st.r[:, cand]
        parents = pop[cand]
        mutant = pop[r1] + st.new_F[cand, None] * (pop[r2] - pop[r3])
        trial = _crossover(st.u, st.jrand, st.new_CR[cand], cand, mutant, parents)
        return _repair_midpoint(trial, parents)

    def report(self, solver, st: _JDEState, c, accepted, delta, parent) -> None:
        if accepted:
            st.F[c] = st.new_F[c]
            st.CR[c] = st.new_CR[c]

    def report_many(self, solver, st: _JDEState, cand, accepted, delta, parents) -> None:
        win = cand[accepted]
        st.F[win] = st.new_F[win]
        st.CR[win] = st.new_CR[win]

    def swap(self, st: _JDEState, i: int, j: int) -> None:
        # F and CR belong to the individual; the generation's index and crossover
        # draws belong to the slot (they exclude the slot's own index)
        for a in (st.F, st.CR, st.new_F, st.new_CR):
            a[[i, j]] = a[[j, i]]

    def resize(self, st: _JDEState, keep: np.ndarray) -> None:
        st.F, st.CR = st.F[keep], st.CR[keep]


# ----------------------------------------------------------------------------- SHADE
class _SHADEState:
    __slots__ = ("M_F", "M_CR", "k", "archive", "n_archive", "cap", "S_F", "S_CR", "S_w",
                 "F", "CR", "u", "jrand", "u_best", "n_best", "r1", "u2", "np_init",
                 "max_nfev")


class SHADE(AdaptiveStrategy):
    """SHADE: success-history based adaptation, current-to-pbest/1/bin with archive.

    Tanabe & Fukunaga (2013). F and CR of each trial are drawn around entries of a
    memory of size `memory_size` (Cauchy for F, normal for CR, scale 0.1); the memory
    is updated each generation with improvement-weighted (Lehmer) means of the
    successful values. Mutation: ``v = x_i + F (x_pbest - x_i) + F (x_r1 - x_r2)``,
    x_pbest random among the best ``p·NP`` members, x_r2 drawn from the population
    and an archive of recently replaced parents.

    Parameters
    ----------
    memory_size : int, optional
        Number of memory slots H. Default 6.
    p : float or None, optional
        Fraction of the population from which x_pbest is drawn; None (default) draws
        p per trial from U[2/NP, 0.2] as in SHADE.
    archive_rate : float, optional
        Archive capacity as a multiple of the population size. Default 1.0.
    F_init, CR_init : float, optional
        Initial memory entries. Default 0.5 each.
    """

    name = "shade"
    _lehmer_cr = False  # SHADE: weighted arithmetic mean for CR

    def __init__(self, memory_size: int = 6, p: float | None = None,
                 archive_rate: float = 1.0, F_init: float = 0.5, CR_init: float = 0.5) -> None:
        cls = type(self).__name__
        self.memory_size = _check(f"{cls}: memory_size", memory_size, 1, 1e9, integer=True)
        self.p = None if p is None else _check(f"{cls}: p", p, 0, 1, open_lo=True)
        self.archive_rate = _check(f"{cls}: archive_rate", archive_rate, 0, 1e6)
        self.F_init = _check(f"{cls}: F_init", F_init, 0, 1, open_lo=True)
        self.CR_init = _check(f"{cls}: CR_init", CR_init, 0, 1)

    def init_state(self, solver) -> _SHADEState:
        NP, N = solver.population.shape
        st = _SHADEState()
        # F, CR and the index/crossover draws are per slot and per generation (not
        # carried by individuals), so promotion swaps need no bookkeeping here
        st.M_F = np.full(self.memory_size, self.F_init)
        st.M_CR = np.full(self.memory_size, self.CR_init)
        st.k = 0
        st.cap = int(round(self.archive_rate * NP))
        st.archive = np.zeros((max(st.cap, 1), N))  # rows past n_archive are never read
        st.n_archive = 0
        st.S_F, st.S_CR, st.S_w = [], [], []
        st.np_init = NP
        st.max_nfev = None
        return st

    def begin_generation(self, solver, st: _SHADEState) -> None:
        rng = solver.random_number_generator
        NP, N = solver.population.shape
        r = _integers(rng, self.memory_size, NP)
        m_cr = st.M_CR[r]
        CR = np.clip(m_cr + 0.1 * rng.standard_normal(NP), 0.0, 1.0)
        CR[np.isnan(m_cr)] = 0.0  # terminal value (L-SHADE)
        m_f = st.M_F[r]
        F = m_f + 0.1 * rng.standard_cauchy(NP)
        bad = F <= 0.0
        while bad.any():
            F[bad] = m_f[bad] + 0.1 * rng.standard_cauchy(int(np.count_nonzero(bad)))
            bad = F <= 0.0
        st.F = np.minimum(F, 1.0)
        st.CR = CR
        p = (rng.uniform(min(2.0 / NP, 0.2), 0.2, size=NP) if self.p is None
             else np.full(NP, self.p))
        st.n_best = np.clip(np.rint(p * NP).astype(np.int64), 2, NP)
        st.u_best = rng.uniform(size=NP)
        st.r1 = _pick(rng, NP, NP, [np.arange(NP)])
        st.u2 = rng.uniform(size=NP)
        st.u, st.jrand = _crossover_draws(rng, NP, N)

    def _r2(self, solver, st: _SHADEState, cand: np.ndarray) -> np.ndarray:
        """Indices into population ∪ archive, different from the candidate and r1."""
        NP = solver.num_population_members
        n = NP + st.n_archive
        r2 = np.minimum((st.u2[cand] * n).astype(np.int64), n - 1)
        r1 = st.r1[cand]
        clash = (r2 == cand) | (r2 == r1)
        if clash.any():
            r2[clash] = _pick(solver.random_number_generator, n, int(clash.sum()),
                              [cand[clash], r1[clash]])
        return r2

    def trials(self, solver, st: _SHADEState, cand: np.ndarray) -> np.ndarray:
        pop = solver.population
        NP = pop.shape[0]
        order = np.argsort(solver.population_energies, kind="stable")
        nb = st.n_best[cand]
        pbest = order[np.minimum((st.u_best[cand] * nb).astype(np.int64), nb - 1)]
        r2 = self._r2(solver, st, cand)
        x2 = pop[np.minimum(r2, NP - 1)]
        from_archive = r2 >= NP
        if from_archive.any():
            x2[from_archive] = st.archive[r2[from_archive] - NP]
        xc = pop[cand]
        Fc = st.F[cand, None]
        mutant = xc + Fc * (pop[pbest] - xc) + Fc * (pop[st.r1[cand]] - x2)
        return _repair_midpoint(_crossover(st.u, st.jrand, st.CR[cand], cand, mutant, xc), xc)

    def report(self, solver, st: _SHADEState, c, accepted, delta, parent) -> None:
        if accepted and delta > 0:
            st.S_F.append(float(st.F[c]))
            st.S_CR.append(float(st.CR[c]))
            st.S_w.append(float(delta))
            self._archive_add(solver, st, parent)

    def report_many(self, solver, st: _SHADEState, cand, accepted, delta, parents) -> None:
        imp = accepted & (delta > 0)
        if not imp.any():
            return
        c = cand[imp]
        st.S_F.extend(st.F[c].tolist())
        st.S_CR.extend(st.CR[c].tolist())
        st.S_w.extend(delta[imp].tolist())
        for row in parents[imp]:
            self._archive_add(solver, st, row)

    @staticmethod
    def _archive_add(solver, st: _SHADEState, row: np.ndarray) -> None:
        if st.cap <= 0:
            return
        if st.n_archive < st.cap:
            st.archive[st.n_archive] = row
            st.n_archive += 1
        else:  # archive full: a random member makes room
            st.archive[int(_integers(solver.random_number_generator, st.cap, 1)[0])] = row

    def end_generation(self, solver, st: _SHADEState) -> None:
        if st.S_F:
            w = np.asarray(st.S_w)
            w = w / w.sum()
            sf = np.asarray(st.S_F)
            scr = np.asarray(st.S_CR)
            st.M_F[st.k] = np.sum(w * sf * sf) / np.sum(w * sf)
            if self._lehmer_cr:
                if np.isnan(st.M_CR[st.k]) or scr.max() == 0.0:
                    st.M_CR[st.k] = np.nan
                else:
                    st.M_CR[st.k] = np.sum(w * scr * scr) / np.sum(w * scr)
            else:
                st.M_CR[st.k] = np.sum(w * scr)
            st.k = (st.k + 1) % self.memory_size
            st.S_F, st.S_CR, st.S_w = [], [], []


class LSHADE(SHADE):
    """L-SHADE: SHADE with linear population size reduction (Tanabe & Fukunaga 2014).

    The population shrinks linearly with the number of evaluated individuals, from its
    initial size (``population_size`` or ``popsize * N``) to `min_size` at `max_nfev`
    evaluations, dropping the worst members; the archive shrinks with it. CR memory
    uses a weighted Lehmer mean with a terminal value, as in the paper.

    Parameters
    ----------
    max_nfev : int or None, optional
        Evaluation budget over which the population shrinks. None (default) uses the
        solver's ``maxfun`` when finite, else ``(maxiter + 1) * NP_init``.
        Individual evaluations are counted (also with ``vectorized=True``).
    min_size : int, optional
        Final population size. Default 4.
    memory_size, p, archive_rate, F_init, CR_init : optional
        As :class:`SHADE`; defaults 6, 0.11, 2.6, 0.5, 0.5 (the L-SHADE paper's).
    """

    name = "lshade"
    _lehmer_cr = True

    def __init__(self, max_nfev: int | None = None, min_size: int = 4, memory_size: int = 6,
                 p: float | None = 0.11, archive_rate: float = 2.6, F_init: float = 0.5,
                 CR_init: float = 0.5) -> None:
        super().__init__(memory_size=memory_size, p=p, archive_rate=archive_rate,
                         F_init=F_init, CR_init=CR_init)
        self.max_nfev = None if max_nfev is None else _check("LSHADE: max_nfev", max_nfev, 1,
                                                             1e18, integer=True)
        self.min_size = _check("LSHADE: min_size", min_size, 4, 1e9, integer=True)

    def init_state(self, solver) -> _SHADEState:
        st = super().init_state(solver)
        if self.max_nfev is not None:
            st.max_nfev = self.max_nfev
        elif np.isfinite(solver.maxfun):
            st.max_nfev = int(solver.maxfun)
        else:
            st.max_nfev = (int(solver.maxiter) + 1) * st.np_init
        return st

    def end_generation(self, solver, st: _SHADEState) -> None:
        super().end_generation(solver, st)
        NP = solver.num_population_members
        frac = min(1.0, solver._vh_nevals / st.max_nfev)
        target = int(round(st.np_init + (self.min_size - st.np_init) * frac))
        target = max(self.min_size, min(NP, target))
        if target < NP:
            solver._vh_shrink(target)
            cap = int(round(self.archive_rate * target))
            if st.n_archive > cap:
                rng = solver.random_number_generator
                keep = np.sort(rng.permutation(st.n_archive)[:cap])
                st.archive[:cap] = st.archive[keep]
                st.n_archive = cap
            st.cap = cap


_REGISTRY: dict[str, type[AdaptiveStrategy]] = {"jde": JDE, "shade": SHADE, "lshade": LSHADE}


def adaptive_strategies() -> tuple[str, ...]:
    """Names accepted as ``strategy=`` for the self-adaptive variants."""
    return tuple(_REGISTRY)


def _resolve(strategy: Any) -> AdaptiveStrategy | None:
    """An AdaptiveStrategy for a name or instance, else None."""
    if isinstance(strategy, AdaptiveStrategy):
        return strategy
    if isinstance(strategy, str) and strategy.lower() in _REGISTRY:
        return _REGISTRY[strategy.lower()]()
    return None
