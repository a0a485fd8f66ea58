"""One BLAS thread for the many small dense solves of a fit.

OpenBLAS (numpy's and scipy's) runs a QR or a matrix product of a few hundred rows by a
few dozen columns on every core by default. On such sizes the threads gain nothing, and
where a core is busy with other work they wait for it: on a 2-core machine shared with
one other job, the spectrum route's thousand small QR factorisations took 4 s instead
of 0.25 s. :func:`one_blas_thread` sets every OpenBLAS loaded in the process to one
thread for the duration of a block and restores its setting afterwards (the variable
``OPENBLAS_NUM_THREADS`` set before start-up does the same for a whole process).

Only OpenBLAS is touched, found among the process's loaded libraries (Linux: the
process's memory map); elsewhere, or without it, the block runs unchanged.
"""

from __future__ import annotations

import contextlib
import ctypes
import threading
from collections.abc import Iterator

__all__ = ["one_blas_thread"]

#: (get, set) symbol pairs of the OpenBLAS builds numpy and scipy ship, and of plain ones
_SYMBOLS = (("scipy_openblas_get_num_threads64_", "scipy_openblas_set_num_threads64_"),
            ("scipy_openblas_get_num_threads", "scipy_openblas_set_num_threads"),
            ("openblas_get_num_threads64_", "openblas_set_num_threads64_"),
            ("openblas_get_num_threads", "openblas_set_num_threads"))

_found: dict[str, tuple | None] = {}  # library path -> (get, set) or None
_lock = threading.Lock()
_depth = 0  # nested blocks: only the outermost sets and restores
_saved: list[tuple] = []


def _libraries() -> list[tuple]:
    """(get, set) of every OpenBLAS loaded in this process (new ones opened once)."""
    try:
        with open("/proc/self/maps", encoding="utf-8", errors="replace") as fh:
            paths = {line.split()[-1] for line in fh
                     if "openblas" in line.lower() and line.rstrip().split()[-1].startswith("/")}
    except OSError:
        return []
    for path in sorted(paths - set(_found)):
        _found[path] = None
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for get_name, set_name in _SYMBOLS:
            get, put = getattr(lib, get_name, None), getattr(lib, set_name, None)
            if get is not None and put is not None:
                get.restype, get.argtypes = ctypes.c_int, []
                put.restype, put.argtypes = None, [ctypes.c_int]
                _found[path] = (get, put)
                break
    return [f for p, f in _found.items() if f is not None and p in paths]


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """Run the block with one OpenBLAS thread, restoring each library's setting after.

    Examples
    --------
    >>> import numpy as np
    >>> from vhfit._blas import one_blas_thread
    >>> with one_blas_thread():
    ...     q, r = np.linalg.qr(np.eye(3))
    >>> float(abs(r).sum())
    3.0
    """
    global _depth
    with _lock:
        if _depth == 0:
            _saved.clear()
            for get, put in _libraries():
                n = int(get())
                if n > 1:
                    put(1)
                    _saved.append((put, n))
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0:
                for put, n in _saved:
                    put(n)
                _saved.clear()
