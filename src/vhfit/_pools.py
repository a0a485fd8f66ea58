"""Process pools of vhfit: the one place that creates them.

Both :func:`vhfit.calibrate` (``workers=``) and :func:`vhfit.parallel.calibrate_many`
get their process pools here, so the start method, the cap on numba's threads in each
worker and the warm-up of the fork server are decided once.

Start method ``"auto"``: *fork* where that is safe — Linux, a single Python thread, and
numba's threading layer not started in this process (its OpenMP layer aborts a child
forked after it has run) — so workers start at once with vhfit imported and its kernels
compiled; otherwise, on Linux, a *fork server* that has imported and warmed vhfit once
per session (:mod:`vhfit._preload`), and elsewhere *spawn* (fresh interpreters).

Nothing here runs at import: the warm-up is the function :func:`vhfit._warm.warm_up`,
called only in the fork server.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import multiprocessing
import os
import sys
import threading
import warnings
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np

__all__ = ["START_METHODS", "ChildLost", "ForkedCall", "cap_numba_threads",
           "check_start_method", "fork_is_safe", "forked", "get_context", "process_pool",
           "usable_cpus", "worker_map"]

#: Start methods accepted by :func:`get_context`; "auto" picks one of the others.
START_METHODS = ("auto", "fork", "forkserver", "spawn")

#: The module the fork server imports: importing it warms the server (multiprocessing
#: runs no function there, it only imports the modules of its preload list).
PRELOAD = "vhfit._preload"


def usable_cpus() -> int:
    """CPUs this process may run on (its affinity where the platform tells it).

    Examples
    --------
    >>> usable_cpus() >= 1
    True
    """
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # not Linux
        return os.cpu_count() or 1


def fork_is_safe(serial_child: bool = False) -> bool:
    """True in a single-threaded Linux process whose numba thread pool never started.

    Parameters
    ----------
    serial_child : bool
        The child will run numba's serial kernels only (:func:`vhfit._kernels.serial`
        set before the fork): then a started thread pool does not matter — GNU
        OpenMP fails only in a child that uses it.

    Examples
    --------
    >>> isinstance(fork_is_safe(), bool)
    True
    """
    if not sys.platform.startswith("linux") or threading.active_count() > 1:
        return False
    if serial_child or "numba.np.ufunc.parallel" not in sys.modules:
        return True  # (not imported: its thread pool never started, and numba unloaded)
    try:
        from numba.np.ufunc import parallel as nb_parallel
    except ImportError:  # pragma: no cover - numba is a dependency
        return False
    # getattr default: numba's private flag, absent in some numba versions
    return getattr(nb_parallel, "_is_initialized", True) is False


def check_start_method(mp_context: Any, name: str = "mp_context") -> None:
    """Refuse, in one line naming ``name``, a start method this platform cannot use.

    Parameters
    ----------
    mp_context : str or multiprocessing context
        One of :data:`START_METHODS` available here, or a context object.
    name : str
        The argument's name in the message.

    Examples
    --------
    >>> check_start_method("spawn")
    >>> check_start_method("threads")
    Traceback (most recent call last):
    ...
    ValueError: mp_context = 'threads': give 'auto', 'fork', 'forkserver', 'spawn' or a context
    """
    if isinstance(mp_context, str):
        usable = ["auto", *multiprocessing.get_all_start_methods()]
        if mp_context not in usable:
            names = ", ".join(repr(m) for m in START_METHODS if m in usable)
            raise ValueError(f"{name} = {mp_context!r}: give {names} or a context")
    # getattr default: any object may be given; only a context has the method
    elif not callable(getattr(mp_context, "get_start_method", None)):
        raise ValueError(
            f"{name} is a {type(mp_context).__name__}: give 'auto', 'fork', 'forkserver', "
            "'spawn' or a context")


def get_context(mp_context: Any = "auto"):
    """The multiprocessing context for ``mp_context`` ("auto" chooses, see the module).

    A fork server chosen here is told to import (and so warm) vhfit when it starts.

    Parameters
    ----------
    mp_context : str or multiprocessing context
        "auto", "fork", "forkserver", "spawn", or a context (returned as it is).

    Returns
    -------
    multiprocessing.context.BaseContext

    Examples
    --------
    >>> get_context("spawn").get_start_method()
    'spawn'
    """
    if not isinstance(mp_context, str):
        return mp_context
    if mp_context == "auto":
        if fork_is_safe():
            mp_context = "fork"
        elif sys.platform.startswith("linux") and (
            "forkserver" in multiprocessing.get_all_start_methods()
        ):
            mp_context = "forkserver"
        else:
            mp_context = "spawn"
    ctx = multiprocessing.get_context(mp_context)
    if mp_context == "forkserver":
        _preload_vhfit(ctx)
    return ctx


def _preload_vhfit(ctx) -> None:
    """Have the (single, per-session) fork server import and warm vhfit when it starts.

    The server is a fresh single-threaded interpreter, so forking from it is safe
    whatever this process runs; it is started once and reused by later pools. A
    server already running keeps its preload list.
    """
    from multiprocessing import forkserver

    # getattr defaults: CPython's private fork-server state, absent elsewhere
    server = getattr(forkserver, "_forkserver", None)
    if server is None or getattr(server, "_forkserver_pid", None) is not None:
        return
    have = list(getattr(server, "_preload_modules", None) or [])
    if PRELOAD not in have:
        ctx.set_forkserver_preload(have + [PRELOAD])


def cap_numba_threads(n: int) -> int | None:
    """Limit numba's threads in this process to ``n``; return the previous number.

    Workers × threads must not oversubscribe the cores. Returns None (and changes
    nothing) when numba is missing or refuses the setting.

    Examples
    --------
    >>> old = cap_numba_threads(1)
    >>> cap_numba_threads(old) == 1
    True
    """
    try:
        import numba

        old = numba.get_num_threads()
        numba.set_num_threads(max(1, min(int(n), numba.config.NUMBA_NUM_THREADS)))
    except (ImportError, ValueError):  # pragma: no cover - numba is a dependency
        return None
    return old


def _init_worker(numba_threads: int | None, initializer: Callable | None,
                 initargs: tuple) -> None:
    """First thing a pool worker runs: the thread cap, then the caller's initializer."""
    if numba_threads is not None:
        cap_numba_threads(numba_threads)
    if initializer is not None:
        initializer(*initargs)


def process_pool(n: int, mp_context: Any = "auto", *, numba_threads: int | None = None,
                 initializer: Callable | None = None,
                 initargs: tuple = ()) -> cf.ProcessPoolExecutor:
    """A process pool of ``n`` workers; the caller shuts it down.

    Parameters
    ----------
    n : int
        Number of worker processes.
    mp_context : str or multiprocessing context, default "auto"
        Start method, see :func:`get_context`.
    numba_threads : int, optional
        Cap on numba's threads in each worker (None: numba's default).
    initializer, initargs
        Run in every worker before its first task (after the thread cap).

    Returns
    -------
    concurrent.futures.ProcessPoolExecutor

    Examples
    --------
    >>> with process_pool(1, "spawn", numba_threads=1) as pool:
    ...     pool.submit(abs, -2).result()
    2
    """
    ctx = get_context(mp_context)
    pool = cf.ProcessPoolExecutor(n, mp_context=ctx, initializer=_init_worker,
                                  initargs=(numba_threads, initializer, tuple(initargs)))
    if ctx.get_start_method() == "fork":
        # fork every worker now, while it is known to be safe: the first task could
        # come after this process has started numba's thread pool
        pool.submit(int).result()
    return pool


@contextlib.contextmanager
def worker_map(workers: Any, mp_context: Any = "auto") -> Iterator[tuple[Callable | None, int]]:
    """``(map, n_chunks)`` for the ``workers`` argument of :func:`vhfit.calibrate`.

    Parameters
    ----------
    workers : int or map-like callable
        1: evaluate in this process (yields ``(None, 1)``); -1: a process pool with one
        worker per CPU; n > 1: a process pool of n workers, each capped to one numba
        thread (yields ``(pool.map, n)``); a map-like callable ``f(func, iterable)``:
        used as it is, with 2 × the number of CPUs chunks.
    mp_context : str or multiprocessing context, default "auto"
        Start method of the pool, see :func:`get_context`.

    Yields
    ------
    (callable or None, int)
        The map to evaluate a population with (None: in process) and the number of
        chunks to split it into.

    Raises
    ------
    ValueError
        For anything else (a bool, 0, -2, a str, ...).

    Examples
    --------
    >>> with worker_map(1) as (mapper, chunks):
    ...     print(mapper, chunks)
    None 1
    >>> with worker_map(map) as (mapper, chunks):
    ...     print(mapper is map, chunks == 2 * (os.cpu_count() or 2))
    True True
    """
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
            with process_pool(n, mp_context, numba_threads=1) as pool:
                yield pool.map, n
    else:
        raise ValueError(
            f"workers = {workers!r}: give an int (processes) or a map-like callable"
        )


# ============================================================ one call in a forked child
class ChildLost(RuntimeError):
    """A :class:`ForkedCall`'s child ended without an answer (killed, or its result could
    not be pickled): the caller runs the call itself."""


#: The value of a :class:`ForkedCall`'s stop flag: go on, stop as a callback returning
#: True does, stop as Ctrl-C does.
GO, STOP, INTERRUPT = 0, 1, 2


class ForkedCall:
    """``fn(*args, callback=relay, **kwargs)`` run in a forked child process.

    The child starts at once with everything this process has (imported modules,
    compiled kernels, the arguments themselves: nothing is pickled on the way in). It
    ignores SIGINT and SIGTERM: this process relays them through :meth:`stop`, which the
    child's ``relay`` callback reads at each call (a generation boundary of a search),
    so an interrupted child ends as cleanly as an interrupted search here. ``relay``
    returns True after ``stop(STOP)``, raises KeyboardInterrupt after
    ``stop(INTERRUPT)``, forwards its argument to this process when ``forward`` is set
    (:meth:`poll` hands it to a callback here), and exits the child if this process has
    died. Warnings the child raises are raised here again when :meth:`result` is read.

    Fork only where :func:`fork_is_safe`; the caller checks.

    Parameters
    ----------
    fn : callable
        Called as ``fn(*args, callback=relay, **kwargs)`` in the child.
    forward : bool
        Send each ``relay`` argument to this process (for a user's callback).

    Examples
    --------
    >>> def twice(x, callback):
    ...     callback({"step": 1})
    ...     return 2 * x
    >>> call = ForkedCall(twice, 21, forward=True)
    >>> seen = []
    >>> call.result(seen.append), seen
    (42, [{'step': 1}])
    """

    def __init__(self, fn: Callable, /, *args: Any, forward: bool = False, **kwargs: Any):
        ctx = multiprocessing.get_context("fork")
        self._conn, child_end = ctx.Pipe()
        self._flag = ctx.RawValue("i", GO)
        self._done: tuple | None = None
        self.process = ctx.Process(target=_forked_main, daemon=True, args=(
            child_end, self._flag, os.getpid(), forward, fn, args, kwargs))
        self.process.start()
        child_end.close()

    def stop(self, how: int = INTERRUPT) -> None:
        """Ask the child to stop at its next ``relay`` call (``STOP`` or ``INTERRUPT``)."""
        self._flag.value = max(self._flag.value, how)

    def poll(self, callback: Callable | None = None, timeout: float = 0.0) -> bool:
        """Hand every message that has arrived to ``callback``; True once the answer is in.

        The callback's own stop requests reach the child: True asks it to stop,
        KeyboardInterrupt asks it to stop as interrupted and is raised again here.
        """
        while self._done is None and self._conn.poll(timeout):
            timeout = 0.0
            try:
                kind, *body = self._conn.recv()
            except (EOFError, OSError):
                self._done = self._lost()
                break
            if kind != "message":
                self._done = (kind, *body)
                break
            if callback is not None:
                try:
                    if callback(body[0]):
                        self.stop(STOP)
                except BaseException:
                    self.stop(INTERRUPT)
                    raise
        return self._done is not None

    def result(self, callback: Callable | None = None) -> Any:
        """Wait for the child's answer, relaying its messages to ``callback`` meanwhile.

        A KeyboardInterrupt here (Ctrl-C, or raised by ``callback``) asks the child to
        stop as interrupted and goes on waiting for its answer: the child's own search
        returns an interrupted result, as it would here.

        Returns
        -------
        The child's return value.

        Raises
        ------
        ChildLost
            The child died or its answer could not be pickled.
        Exception
            Whatever ``fn`` raised in the child.
        """
        while True:
            try:
                if self.poll(callback, timeout=0.05):
                    break
                if not self.process.is_alive() and not self._conn.poll(0):
                    self._done = self._lost()
                    break
            except KeyboardInterrupt:
                self.stop(INTERRUPT)
        self.process.join()
        self._conn.close()
        kind, *body = self._done
        if kind == "lost":
            raise ChildLost(body[0])
        if kind == "raised":
            raise body[0]
        value, caught = body
        for message, category in caught:
            warnings.warn(message, category, stacklevel=2)
        return value

    def _lost(self) -> tuple:
        self.process.join(5.0)  # the pipe closes as the child exits
        return ("lost", f"the child process ended (exit code {self.process.exitcode}) "
                        "without an answer")

    def cancel(self) -> None:
        """End the child now, whatever it is doing; its answer is not wanted."""
        if self.process.is_alive():
            self.process.kill()
        self.process.join()
        self._conn.close()


def forked(fn: Callable[[], Any]) -> Callable[[], Any]:
    """``fn()`` in a forked copy of this process, which dies with it; returns the call
    that waits for its answer (None if it failed, could not start, or its answer did not
    pickle).

    Unlike :class:`ForkedCall` (a :mod:`multiprocessing` child, which a daemonic process
    such as a ForkedCall's own child may not have), the copy is a bare ``os.fork``: it is
    for a short call made by a forked child itself. The kernel ends it with this process
    (``PR_SET_PDEATHSIG``), so that a copy whose parent is killed does not go on writing
    files. Linux only, where fork is safe (:func:`fork_is_safe`); elsewhere the answer
    is None.

    Examples
    --------
    >>> forked(lambda: 6 * 7)() in (42, None)  # None where there is no fork
    True
    """
    if not sys.platform.startswith("linux"):
        return lambda: None
    import ctypes
    import pickle
    import signal

    parent = os.getpid()
    r, w = os.pipe()
    try:
        pid = os.fork()
    except OSError:
        os.close(r)
        os.close(w)
        return lambda: None
    if pid == 0:  # the copy: answer once, then exit without this process's teardown
        code = 1
        try:
            os.close(r)
            libc = ctypes.CDLL(None, use_errno=True)
            if libc.prctl(1, int(signal.SIGKILL), 0, 0, 0) == 0 and os.getppid() == parent:
                data = pickle.dumps(fn())  # 1: PR_SET_PDEATHSIG; parent alive after it
                with os.fdopen(w, "wb") as f:
                    f.write(data)
                code = 0
        finally:
            os._exit(code)
    os.close(w)

    def answer() -> Any:
        with os.fdopen(r, "rb") as f:
            data = f.read()
        _, status = os.waitpid(pid, 0)
        return pickle.loads(data) if status == 0 and data else None

    return answer


def _forked_main(conn, flag, parent: int, forward: bool, fn: Callable, args: tuple,
                 kwargs: dict) -> None:
    """The child of a :class:`ForkedCall`: run, answer once, close."""
    import signal

    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, signal.SIG_IGN)  # the parent relays them through the flag

    def relay(message: Any) -> bool:
        if os.getppid() != parent:  # the parent is gone: nobody wants the answer
            os._exit(1)
        if forward:
            conn.send(("message", message))
        if flag.value == INTERRUPT:
            raise KeyboardInterrupt
        return flag.value == STOP

    try:
        with warnings.catch_warnings(record=True) as caught:
            value = fn(*args, callback=relay, **kwargs)
        answer = ("value", value, [(str(w.message), w.category) for w in caught])
    except (Exception, KeyboardInterrupt) as exc:  # the parent raises it again
        answer = ("raised", exc)
    try:
        conn.send(answer)
    except Exception:  # noqa: BLE001 - unpicklable: the parent runs the call itself
        conn.send(("lost", "the child's answer could not be pickled"))
    conn.close()
