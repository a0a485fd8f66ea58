"""Many independent calibrations at once: materials, seeds, model orders, strategies.

:func:`calibrate_many` runs a list of jobs — each a set of :func:`vhfit.calibrate`
arguments — in this process, in a pool of worker processes, or on anything that
executes Python callables: a :class:`concurrent.futures.Executor` (process or thread
pools, a Dask cluster's ``client.get_executor()``) or a map-like callable
(``multiprocessing.Pool().imap``, ``executor.map``). Results stream back as
:class:`JobResult` objects as the jobs finish; a job that fails — bad data, a bad
option, even a worker process that dies — is reported in its own result and never
stops the others.

A job gives bit-identical constants wherever it runs: in this process, in a pool, or
on a Dask worker (the calibration is a deterministic function of its curves and
options; only the wall time differs).
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import os
import time
import traceback as _tb
import warnings as _warnings
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vhfit._pools import cap_numba_threads, check_start_method, process_pool
from vhfit.calibration import calibrate
from vhfit.data import read_csv

__all__ = ["Job", "JobResult", "calibrate_many"]

#: Start method of the process pools that :func:`calibrate_many` creates itself.
#: "auto": "fork" where it is safe — Linux, one Python thread, and numba's threading
#: layer not started (its OpenMP layer aborts a child forked after it has run) — so the
#: workers inherit the imported, compiled kernels; else on Linux a fork server that has
#: imported and warmed vhfit; "spawn" (fresh interpreters) elsewhere.
DEFAULT_START_METHOD = "auto"


@dataclass
class Job:
    """One calibration to run: a name, the curves, and the :func:`vhfit.calibrate` keywords.

    Parameters
    ----------
    name : str
        Label of the job in its :class:`JobResult`.
    curves : sequence of Curve, or path(s)
        The curves to fit; a path or a list of paths is read with :func:`vhfit.read_csv`
        by the worker (so a bad file fails that job alone).
    kwargs : dict
        Keywords of :func:`vhfit.calibrate` (``hyperelastic``, ``n_prony``, ``seed``, ...).

    Examples
    --------
    >>> Job("SEBS, N = 3", curves=["sebs.csv"], kwargs=dict(n_prony=3, seed=0))
    Job(name='SEBS, N = 3', curves=['sebs.csv'], kwargs={'n_prony': 3, 'seed': 0})
    """

    name: str
    curves: Any
    kwargs: dict = field(default_factory=dict)


@dataclass
class JobResult:
    """Outcome of one job of :func:`calibrate_many`.

    Attributes
    ----------
    name : str
        The job's name.
    index : int
        Position of the job in the list given to :func:`calibrate_many` (results
        arrive in order of completion; sort by ``index`` for input order).
    calibration : Calibration or None
        The result, or None when the job failed.
    error : str or None
        ``"ExceptionType: message"`` when the job failed, else None.
    wall_time : float
        Seconds the job ran (in its worker), or until its failure was known.
    traceback : str or None
        The full traceback of a failure inside the job, for debugging.
    cpu_time : float
        CPU seconds of the job's process while it ran (all its threads; includes
        anything else that process did meanwhile, e.g. other threads' jobs).
    warnings : list of str
        Warnings raised while the job ran (``"Category: message"``, each once),
        collected here rather than printed by the worker. The calibration's own
        findings are also in ``calibration.warnings``.
    """

    name: str
    index: int
    calibration: Any = None
    error: str | None = None
    wall_time: float = 0.0
    traceback: str | None = None
    warnings: list = field(default_factory=list)
    cpu_time: float = 0.0

    @property
    def ok(self) -> bool:
        """True when the job produced a calibration."""
        return self.error is None

    def __repr__(self) -> str:
        if self.ok:
            cal = self.calibration
            what = f"RMSAPE {cal.rmsape:.4g} %, stop: {cal.stop_reason}"
        else:
            what = f"failed: {self.error}"
        return f"JobResult({self.name!r}, #{self.index}, {what}, {self.wall_time:.2f} s)"


# ------------------------------------------------------------------ the work itself
def _as_task(job: Any, index: int, seed: Any) -> tuple:
    """(index, name, curves, kwargs) of a job; raises ValueError/TypeError if malformed."""
    if isinstance(job, Job):
        name, curves, kwargs = job.name, job.curves, dict(job.kwargs or {})
    elif isinstance(job, Mapping):
        kwargs = dict(job)
        if "curves" not in kwargs:
            raise ValueError(
                f"job {index} has no 'curves': give a dict of calibrate keywords including "
                "curves=..., or a vhfit.parallel.Job"
            )
        curves = kwargs.pop("curves")
        name = kwargs.pop("name", None)
    else:
        raise TypeError(
            f"job {index} is a {type(job).__name__}: give a dict of calibrate keywords "
            "(with 'curves') or a vhfit.parallel.Job"
        )
    if seed is not None and "seed" not in kwargs:
        kwargs["seed"] = _job_seed(seed, index)
    return index, str(name) if name is not None else f"job {index}", curves, kwargs


def _job_seed(seed: Any, index: int) -> int:
    """A seed for job ``index`` derived from the run's ``seed`` (independent streams)."""
    entropy = [int(seed)] if np.ndim(seed) == 0 else [int(s) for s in seed]
    return int(np.random.SeedSequence(entropy + [index]).generate_state(1, np.uint64)[0])


def _is_path(x: Any) -> bool:
    return isinstance(x, (str, os.PathLike))


def _run_task(task: tuple, threads: int | None = None, capture: bool = True) -> JobResult:
    """Run one job where it lands (a worker process, a thread, here) and never raise.

    ``threads`` caps numba's threads for the job (so that W workers × T threads do
    not oversubscribe the cores); the previous setting is restored afterwards.
    ``capture`` collects the job's warnings into its result (not thread-safe: off in
    thread pools, where warnings go their usual way).
    """
    index, name, curves, kwargs = task
    t0, c0 = time.perf_counter(), time.process_time()
    old = None
    caught: list = []
    try:
        if threads is not None:
            old = cap_numba_threads(threads)
        with _warnings.catch_warnings(record=True) if capture else _no_capture() as caught:
            if capture:
                _warnings.simplefilter("always")
            if _is_path(curves) or (
                isinstance(curves, Sequence) and curves and all(_is_path(c) for c in curves)
            ):
                curves = read_csv(curves)
            cal = calibrate(curves, **kwargs)
        return JobResult(name, index, cal, None, time.perf_counter() - t0,
                         warnings=_messages(caught), cpu_time=time.process_time() - c0)
    except Exception as exc:  # a failing job is reported, never propagated
        return JobResult(name, index, None, _describe(exc), time.perf_counter() - t0,
                         _tb.format_exc(), warnings=_messages(caught),
                         cpu_time=time.process_time() - c0)
    finally:
        if old is not None:
            cap_numba_threads(old)


def _messages(caught) -> list[str]:
    out: list[str] = []
    for w in caught or ():
        text = f"{w.category.__name__}: {' '.join(str(w.message).split())}"
        if text not in out:
            out.append(text)
    return out


@contextlib.contextmanager
def _no_capture():
    yield []


@dataclass(frozen=True)
class _Runner:
    """The picklable function sent to executors: :func:`_run_task` with its settings."""

    threads: int | None = 1
    capture: bool = True

    def __call__(self, task: tuple) -> JobResult:
        return _run_task(task, self.threads, self.capture)


def _describe(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _failed(task: tuple, error: str, t0: float) -> JobResult:
    return JobResult(task[1], task[0], None, error, time.perf_counter() - t0)


# ------------------------------------------------------------------- the scheduler
def calibrate_many(
    jobs: Iterable[Mapping[str, Any] | Job],
    executor: None | int | str | cf.Executor | Callable = None,
    *,
    max_workers: int | None = None,
    seed: Any = None,
    threads_per_job: int | None = 1,
    max_pending: int | None = None,
    mp_context: str | Any = DEFAULT_START_METHOD,
    initializer: Callable | None = None,
    initargs: tuple = (),
) -> Iterator[JobResult]:
    """Run many independent calibrations; yield each :class:`JobResult` as it finishes.

    Parameters
    ----------
    jobs : iterable of dict or Job
        Each job is a dict of :func:`vhfit.calibrate` keywords including ``curves``
        (and optionally ``name``), or a :class:`Job`. ``curves`` may be a path or a
        list of paths, read by the worker with :func:`vhfit.read_csv`.
    executor : None, int, "process", "thread", Executor or map-like callable
        Where the jobs run:

        * ``None`` — one after another in this process, as the iterator is consumed
          (with ``max_workers`` > 1: a process pool of that size);
        * an int ``n`` or ``"process"`` — a process pool of ``n`` (or ``max_workers``,
          default the number of CPUs) workers, created and shut down here;
        * ``"thread"`` — a thread pool in this process (the GIL limits the speed-up;
          warnings then are not collected per job);
        * any :class:`concurrent.futures.Executor` — e.g. your own
          ``ProcessPoolExecutor`` or a Dask ``distributed.Client(...).get_executor()``;
          jobs are submitted to it and results come back as they complete;
        * any map-like callable ``f(function, iterable) -> iterable`` — e.g.
          ``multiprocessing.Pool(2).imap`` or ``client.get_executor().map``; results
          then come back in input order.
    max_workers : int, optional
        Size of the pool for ``executor`` = None, "process" or "thread".
    seed : int or sequence of int, optional
        Base seed: a job without its own ``seed`` gets one derived from this and its
        index (``numpy.random.SeedSequence([seed, index])``), so a run of many seeds
        is reproducible. Jobs with a ``seed`` keep it.
    threads_per_job : int or None, default 1
        Cap on numba's threads inside each job run by an executor, so that workers ×
        threads does not oversubscribe the cores. None leaves numba alone. Serial runs
        (``executor=None``) always use numba's current setting.
    max_pending : int, optional
        Most jobs submitted to an executor and not yet finished (the rest wait here),
        which bounds the memory of very long job lists. Default: 2 × the workers for
        pools created here, unbounded for a given executor.
    mp_context : "auto", "spawn", "fork", "forkserver" or a multiprocessing context
        Start method of process pools created here. "auto" (default) forks where that
        is safe (Linux, a single Python thread, numba's thread pool not yet started in
        this process) — workers then start at once with vhfit loaded; otherwise, on
        Linux, it uses a fork server that has imported and warmed vhfit once per
        session (e.g. in Jupyter, which runs threads), and elsewhere it spawns.
        "fork" is unsafe once this process has run numba's parallel kernel.
    initializer, initargs
        Run in every worker of a process pool created here before its first job (e.g.
        to import a module that registers your own hyperelastic law).

    Yields
    ------
    JobResult
        One per job, in order of completion (input order for map-like callables and
        serial runs). A job that failed has ``calibration=None`` and ``error`` set.

    Raises
    ------
    ValueError
        At once, before any job runs, for a bad argument of this function (``jobs``
        not a list of jobs, ``max_workers``, ``seed``, ``threads_per_job``,
        ``max_pending``, ``mp_context``, ``initializer``/``initargs``, or settings that
        contradict each other); problems of a job are reported in its result.
    TypeError
        For an ``executor`` of the wrong type (a bool, a float, ...).

    Notes
    -----
    *Isolation.* An exception inside a job becomes its ``error`` (with the
    traceback in ``traceback``). If a worker process of a pool created here dies
    (killed, out of memory, a crash in compiled code), the pool is rebuilt; the jobs
    that were running are re-run one at a time to find the one that kills its worker,
    which is reported as failed, and the rest carry on. A given executor that breaks
    cannot be rebuilt here: its unfinished jobs are reported as failed.

    *Determinism.* A job's constants do not depend on where it runs; give each job a
    ``seed`` (or ``seed=`` here) for repeatable results.

    *Dask.* ``client.submit`` treats equal arguments as the same task; the job's
    index is part of the arguments, so identical jobs still run separately.

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> from vhfit.parallel import calibrate_many
    >>> m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    >>> true = dict(C10=0.01, C01=0.005, G1=0.5, tau1=0.01)
    >>> eps = np.linspace(-0.05, -0.5, 10)
    >>> curves = [vhfit.Curve(strain=eps, stress=m.stress(true, strain=eps, strain_rate=r,
    ...           measure="engineering"), strain_rate=r) for r in (-1.0, -100.0)]
    >>> jobs = [dict(name=f"N={n}", curves=curves, n_prony=n, seed=0) for n in (1, 2)]
    >>> jobs.append(dict(name="broken", curves=curves, n_prony=-1))
    >>> for r in sorted(calibrate_many(jobs), key=lambda r: r.index):
    ...     print(r.name, r.ok, r.calibration.rmsape < 1e-3 if r.ok else r.error)
    N=1 True True
    N=2 True True
    broken False ValueError: n_prony = -1: give a whole number >= 0, 'auto', or None (the default)
    """
    executor, max_workers = _check_arguments(
        jobs, executor, max_workers, seed, threads_per_job, max_pending, mp_context,
        initializer, initargs)
    return _generate(jobs, executor, max_workers, seed, threads_per_job, max_pending,
                     mp_context, initializer, initargs)


def _whole(value: Any, least: int) -> bool:
    """True for an int (not a bool) >= ``least``."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool) and (
        value >= least)


def _check_arguments(jobs, executor, max_workers, seed, threads, max_pending, mp_context,
                     initializer, initargs) -> tuple:
    """Refuse bad arguments of :func:`calibrate_many` in one line each; return
    ``(executor, max_workers)`` normalised (an int executor becomes "process")."""
    if isinstance(jobs, (str, bytes, Mapping, Job)) or not isinstance(jobs, Iterable):
        raise ValueError(f"jobs is a {type(jobs).__name__}: give a list (or any iterable) of "
                         "dicts of calibrate keywords or of vhfit.parallel.Job")
    if max_workers is not None and not _whole(max_workers, 1):
        raise ValueError(f"max_workers = {max_workers!r}: give a whole number >= 1")
    if threads is not None and not _whole(threads, 1):
        raise ValueError(f"threads_per_job = {threads!r}: give a whole number >= 1 or None")
    if max_pending is not None and not _whole(max_pending, 1):
        raise ValueError(f"max_pending = {max_pending!r}: give a whole number >= 1 or None")
    if seed is not None and not (_whole(seed, 0) or (
        isinstance(seed, Sequence) and not isinstance(seed, str) and len(seed) > 0
        and all(_whole(s, 0) for s in seed)
    )):
        raise ValueError(f"seed = {seed!r}: give a whole number >= 0, a non-empty list of "
                         "them, or None")
    check_start_method(mp_context)
    if initializer is not None and not callable(initializer):
        raise ValueError(f"initializer is a {type(initializer).__name__}: give a function "
                         "(run once in every worker) or None")
    if not isinstance(initargs, (tuple, list)):
        raise ValueError(f"initargs is a {type(initargs).__name__}: give a tuple of the "
                         "initializer's arguments")
    if isinstance(executor, bool):
        raise TypeError("executor = True/False: give None, a number of processes, or an executor")
    if isinstance(executor, (int, np.integer)):
        if executor < 1:
            raise ValueError(f"executor = {executor!r}: give a number of workers >= 1")
        if max_workers is not None and max_workers != executor:
            raise ValueError(f"max_workers = {max_workers!r} contradicts executor = "
                             f"{executor!r}: give the number of workers once")
        return "process", int(executor)
    if isinstance(executor, str) and executor not in ("process", "thread"):
        raise ValueError(f"executor = {executor!r}: give 'process', 'thread', a number, "
                         "an Executor or a map-like callable")
    if not (executor is None or isinstance(executor, (str, cf.Executor)) or callable(executor)):
        raise TypeError(
            f"executor is a {type(executor).__name__}: give None, a number of processes, "
            "'process', 'thread', a concurrent.futures.Executor or a map-like callable"
        )
    if executor is None and max_workers is not None and max_workers > 1:
        executor = "process"
    if executor is not None and not isinstance(executor, str):
        if max_workers is not None:
            raise ValueError("max_workers sizes the pools created here: give the size to your "
                             "own executor, or pass executor='process' or 'thread'")
        if initializer is not None:
            raise ValueError("initializer runs in the pools created here: give it to your own "
                             "executor, or pass executor='process' or a number of workers")
    elif executor is None and initializer is not None:
        raise ValueError("initializer runs in worker processes and jobs run here when "
                         "executor=None: give executor='process' or a number of workers")
    return executor, max_workers


def _generate(jobs, executor, max_workers, seed, threads, max_pending, mp_context,
              initializer, initargs) -> Iterator[JobResult]:
    tasks: list[tuple] = []
    bad: list[JobResult] = []
    for i, job in enumerate(jobs):
        t0 = time.perf_counter()
        try:
            tasks.append(_as_task(job, i, seed))
        except (TypeError, ValueError) as exc:
            # getattr default: a job is a mapping or any object, named or not
            name = getattr(job, "name", None) or (
                job.get("name") if isinstance(job, Mapping) else None)
            bad.append(JobResult(str(name or f"job {i}"), i, None, _describe(exc),
                                 time.perf_counter() - t0))
    yield from bad
    threaded = executor == "thread" or isinstance(executor, cf.ThreadPoolExecutor)
    fn = _Runner(threads, capture=not threaded)
    if executor is None:
        for task in tasks:
            yield _run_task(task, None)
    elif isinstance(executor, str):
        n = max_workers or os.cpu_count() or 1
        yield from _own_pool(tasks, executor, n, fn, max_pending or 2 * n, mp_context,
                             initializer, initargs)
    elif isinstance(executor, cf.Executor):
        yield from _submit_all(executor, tasks, fn, max_pending)
    else:
        yield from _map_all(executor, tasks, fn)


def _map_all(mapper: Callable, tasks: list[tuple], fn: _Runner) -> Iterator[JobResult]:
    """A map-like callable: results in input order; a broken map fails the rest."""
    t0 = time.perf_counter()
    done = 0
    try:
        for res in mapper(fn, tasks):
            done += 1
            yield res
    except Exception as exc:  # the map itself broke (worker lost, cluster gone, ...)
        msg = f"the map-like executor failed before this job returned: {_describe(exc)}"
        for task in tasks[done:]:
            yield _failed(task, msg, t0)


def _submit_all(ex: cf.Executor, tasks: list[tuple], fn: _Runner, max_pending,
                on_broken: Callable | None = None) -> Iterator[JobResult]:
    """Submit to an executor (at most ``max_pending`` in flight); yield as completed.

    ``on_broken(running, waiting)`` is called with the tasks left when the executor
    breaks; without it they are reported as failed.
    """
    todo = list(reversed(tasks))
    inflight: dict[cf.Future, tuple] = {}
    t0 = time.perf_counter()
    try:
        while todo or inflight:
            while todo and (max_pending is None or len(inflight) < max_pending):
                task = todo.pop()
                try:
                    inflight[ex.submit(fn, task)] = task
                except Exception as exc:  # broken or shut down executor
                    todo.append(task)
                    yield from _broken(exc, inflight, todo, on_broken, t0)
                    return
            done, _ = cf.wait(list(inflight), return_when=cf.FIRST_COMPLETED)
            for fut in done:
                task = inflight.pop(fut)
                try:
                    yield fut.result()
                except cf.process.BrokenProcessPool as exc:
                    inflight[fut] = task
                    yield from _broken(exc, inflight, todo, on_broken, t0)
                    return
                except cf.CancelledError:
                    yield _failed(task, "CancelledError: the executor cancelled this job", t0)
                except Exception as exc:  # e.g. the result could not be sent back
                    yield _failed(task, _describe(exc), t0)
    finally:
        for fut in inflight:
            fut.cancel()


def _broken(exc, inflight, todo, on_broken, t0) -> Iterator[JobResult]:
    running = [task for fut, task in inflight.items() if not fut.done() or _died(fut)]
    finished = [fut for fut in inflight if fut.done() and not _died(fut)]
    for fut in finished:  # results that made it out before the break
        yield fut.result() if not fut.exception() else _failed(
            inflight[fut], _describe(fut.exception()), t0)
    inflight.clear()
    waiting = list(reversed(todo))
    todo.clear()
    if on_broken is not None:
        yield from on_broken(running, waiting)
        return
    msg = f"the executor broke before this job finished: {_describe(exc)}"
    for task in running + waiting:
        yield _failed(task, msg, t0)


def _died(fut: cf.Future) -> bool:
    return fut.done() and not fut.cancelled() and isinstance(
        fut.exception(), cf.process.BrokenProcessPool)


def _make_pool(kind: str, n: int, mp_context, initializer, initargs) -> cf.Executor:
    if kind == "thread":
        return cf.ThreadPoolExecutor(n, initializer=initializer, initargs=initargs)
    return process_pool(n, mp_context, initializer=initializer, initargs=initargs)


def _shutdown(pool: cf.Executor, abandon: bool) -> None:
    """Shut a pool down; when abandoning it (consumer gone, error), stop its workers now."""
    if abandon:
        # getattr default: only a ProcessPoolExecutor has (private) _processes
        for p in list((getattr(pool, "_processes", None) or {}).values()):
            p.terminate()
    pool.shutdown(wait=True, cancel_futures=True)


def _own_pool(tasks, kind, n, fn, max_pending, mp_context, initializer,
              initargs) -> Iterator[JobResult]:
    """A pool created here; rebuilt when a worker dies, the culprit found by isolation."""
    pending = list(tasks)
    while pending:
        pool = _make_pool(kind, n, mp_context, initializer, initargs)
        box: dict[str, list] = {}

        def on_broken(running, waiting, box=box):
            box["suspects"], box["waiting"] = running, waiting
            return iter(())

        clean = False
        try:
            yield from _submit_all(pool, pending, fn, max_pending, on_broken)
            clean = True
        finally:
            _shutdown(pool, abandon=not clean or bool(box))
        pending = []
        if box:
            # a worker died: re-run the jobs that were in flight one at a time, each in
            # a fresh single-worker pool, so the one that kills its worker is named
            yield from _isolated(box["suspects"], kind, fn, mp_context, initializer,
                                 initargs)
            pending = box["waiting"]


def _isolated(tasks, kind, fn, mp_context, initializer, initargs) -> Iterator[JobResult]:
    """Run ``tasks`` one at a time in a single-worker pool, rebuilt after each death."""
    pool = None
    clean = False
    try:
        for task in tasks:
            if pool is None:
                pool = _make_pool(kind, 1, mp_context, initializer, initargs)
            t0 = time.perf_counter()
            try:
                yield pool.submit(fn, task).result()
            except cf.process.BrokenProcessPool:
                yield _failed(task, "WorkerDied: the worker process running this job died "
                              "(killed by a signal, out of memory, or a crash in compiled "
                              "code)", t0)
                _shutdown(pool, abandon=True)
                pool = None
            except Exception as exc:
                yield _failed(task, _describe(exc), t0)
        clean = True
    finally:
        if pool is not None:
            _shutdown(pool, abandon=not clean)
