"""Process pools: one place that creates them."""

from __future__ import annotations

import contextlib
import os

import numpy as np

__all__ = ["worker_map"]


def _single_thread_worker() -> None:
    # two processes x two numba threads would oversubscribe two cores
    try:
        import numba

        numba.set_num_threads(1)
    except (ImportError, ValueError):
        pass


@contextlib.contextmanager
def worker_map(workers):
    """(map, n_chunks) for ``workers``: 1 -> in process; int -> process pool; map-like."""
    if callable(workers):
        yield workers, 2 * (os.cpu_count() or 2)
    elif isinstance(workers, (int, np.integer)) and not isinstance(workers, bool):
        n = int(workers)
        if n == -1:
            n = os.cpu_count() or 1
        if n < 1:
            raise ValueError(f"workers = {workers!r}: give -1, a whole number >= 1, or a map")
        if n == 1:
            yield None, 1
        else:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            # spawn, not fork: forking after numba's OpenMP threads started is unsafe
            ctx = multiprocessing.get_context("spawn")
            with ProcessPoolExecutor(n, mp_context=ctx, initializer=_single_thread_worker) as ex:
                yield ex.map, n
    else:
        raise ValueError(
            f"workers = {workers!r}: give an int (processes) or a map-like callable"
        )
