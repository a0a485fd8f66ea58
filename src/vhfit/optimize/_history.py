"""Per-generation records of a differential evolution run (``history=True``)."""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from vhfit.optimize._state import from_plain, plain_column, to_plain
from vhfit.optimize._stopping import StopState

__all__ = ["DEHistory"]


@dataclass(frozen=True, eq=False)
class DEHistory:
    """Per-generation record of a run, returned as ``result.history``.

    Row 0 is the initial population (generation 0); then one row per generation.
    A final polish (``polish=True``) is not part of the history.

    Attributes
    ----------
    nit : ndarray of int, shape (G,)
        Generation number.
    nfev : ndarray of int, shape (G,)
        Objective calls so far (SciPy's count).
    best : ndarray of float, shape (G,)
        Lowest energy in the population.
    mean : ndarray of float, shape (G,)
        Mean energy of the population (``inf`` while any member is infinite).
    time : ndarray of float, shape (G,)
        Wall time in seconds since the solve started.
    population_size : ndarray of int, shape (G,)
        Number of members (changes only with population-reducing strategies).
    snapshot_nit : ndarray of int, shape (K,)
        Generations at which a snapshot was stored (``snapshots=k``: every k-th).
    populations : list of ndarray
        Population (in parameter units, best first) at each snapshot.
    population_energies : list of ndarray
        Energies matching `populations`.
    """

    nit: np.ndarray
    nfev: np.ndarray
    best: np.ndarray
    mean: np.ndarray
    time: np.ndarray
    population_size: np.ndarray
    snapshot_nit: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    populations: list = field(default_factory=list)
    population_energies: list = field(default_factory=list)

    def __len__(self) -> int:
        return int(self.nit.size)

    def as_dict(self) -> dict:
        """The scalar series as a dict of arrays (e.g. for ``np.savez`` or pandas)."""
        return {
            "nit": self.nit,
            "nfev": self.nfev,
            "best": self.best,
            "mean": self.mean,
            "time": self.time,
            "population_size": self.population_size,
        }

    def __repr__(self) -> str:
        if len(self) == 0:
            return "DEHistory(empty)"
        return (
            f"DEHistory({len(self)} rows: nit 0..{int(self.nit[-1])}, best "
            f"{self.best[0]:.4g} -> {self.best[-1]:.4g}, {self.time[-1]:.3g} s, "
            f"{len(self.populations)} snapshots)"
        )


#: The history's per-generation rows and the dtype kinds they are stored with.
_ROWS = {"nit": "iu", "nfev": "iu", "best": "f", "mean": "f", "time": "f",
         "population_size": "iu"}


def _column(a, name: str, kinds: str) -> np.ndarray:
    """A stored history row: a 1-D array of ints (``kinds`` "iu") or floats ("f")."""
    if not isinstance(a, np.ndarray) or a.ndim != 1 or a.dtype.kind not in kinds:
        raise ValueError(f"the history's {name!r} row is not a 1-D array of "
                         f"{'integers' if 'i' in kinds else 'floats'} (damaged state)")
    return a


class _Recorder:
    """Cheap append-only recorder; also feeds the :class:`StopState`.

    Holds no reference to the solver (avoids reference cycles).
    """

    __slots__ = ("t0", "nit", "nfev", "time", "size", "every", "snap_nit", "snap_pop",
                 "snap_e", "state")

    def __init__(self, snapshots: int = 0) -> None:
        self.t0: float | None = None
        self.nit: list[int] = []
        self.nfev: list[int] = []
        self.time: list[float] = []
        self.size: list[int] = []
        self.every = int(snapshots)
        self.snap_nit: list[int] = []
        self.snap_pop: list[np.ndarray] = []
        self.snap_e: list[np.ndarray] = []
        self.state = StopState()

    def record(self, nit: int, nfev: int, energies: np.ndarray, scaled_population=None) -> None:
        if self.t0 is None:
            self.t0 = time.perf_counter()
        t = time.perf_counter() - self.t0
        n = energies.size
        best = float(energies[0])
        mean = float(energies.sum()) / n
        st = self.state
        st.nit = nit
        st.nfev = nfev
        st.best = best
        st.mean = mean
        st.population_energies = energies
        st.elapsed = t
        st.best_history.append(best)
        st.mean_history.append(mean)
        self.nit.append(nit)
        self.nfev.append(nfev)
        self.time.append(t)
        self.size.append(n)
        if self.every and nit % self.every == 0 and scaled_population is not None:
            self.snap_nit.append(nit)
            self.snap_pop.append(scaled_population())
            self.snap_e.append(energies.copy())

    @property
    def recorded(self) -> bool:
        return bool(self.nit)

    def dump(self) -> dict:
        """The rows (and snapshots) recorded so far, as plain JSON types."""
        st = self.state
        return {
            "nit": plain_column(self.nit, "int64"),
            "nfev": plain_column(self.nfev, "int64"),
            "best": plain_column(st.best_history, "float64"),
            "mean": plain_column(st.mean_history, "float64"),
            "time": plain_column(self.time, "float64"),
            "population_size": plain_column(self.size, "int64"),
            "snapshot_nit": plain_column(self.snap_nit, "int64"),
            "snapshot_populations": to_plain(self.snap_pop),
            "snapshot_energies": to_plain(self.snap_e),
        }

    def load(self, data: dict, energies: np.ndarray) -> None:
        """Restore :meth:`dump`'s rows; `energies` are the current population's."""
        d = from_plain(data)
        rows = {k: _column(d[k], k, kind) for k, kind in _ROWS.items()}
        if len({a.shape for a in rows.values()}) != 1:
            raise ValueError("the history's rows differ in length (damaged state)")
        self.nit = rows["nit"].tolist()
        self.nfev = rows["nfev"].tolist()
        self.time = rows["time"].tolist()
        self.size = rows["population_size"].tolist()
        self.snap_nit = _column(d["snapshot_nit"], "snapshot_nit", "iu").tolist()
        self.snap_pop = list(d["snapshot_populations"])
        self.snap_e = list(d["snapshot_energies"])
        st = self.state = StopState()
        st.best_history = rows["best"].tolist()
        st.mean_history = rows["mean"].tolist()
        if self.nit:
            st.nit, st.nfev, st.elapsed = self.nit[-1], self.nfev[-1], self.time[-1]
            st.best, st.mean = st.best_history[-1], st.mean_history[-1]
            st.population_energies = energies

    def result(self) -> DEHistory:
        st = self.state
        return DEHistory(
            nit=np.asarray(self.nit, dtype=np.int64),
            nfev=np.asarray(self.nfev, dtype=np.int64),
            best=np.asarray(st.best_history, dtype=np.float64),
            mean=np.asarray(st.mean_history, dtype=np.float64),
            time=np.asarray(self.time, dtype=np.float64),
            population_size=np.asarray(self.size, dtype=np.int64),
            snapshot_nit=np.asarray(self.snap_nit, dtype=np.int64),
            populations=list(self.snap_pop),
            population_energies=list(self.snap_e),
        )
