"""The order scan of ``n_prony="auto"``: N = 1, 2, ... Prony terms, each a calibration,
and the rule that picks N — run on two processes side by side where that is safe.

Which N the rule reaches depends only on the errors of the smaller N, never on the time
or the process a fit ran in, and each N's fit is the same computation wherever it runs:
the scan's result is the same to the bit side by side and one after the other (only a
``max_time`` that cuts fits short can tell them apart).

*Side by side.* The rule reaches N = 3 unless N = 2 gains less than order_tol (on
every shared real record it does), and N = 3 is the longest of the first three fits, so
a forked child fits N = 3 while this process fits N = 1 then N = 2; beyond, this
process fits N while the child fits N + 1. A child's fit the rule does not reach is
thrown away. Both processes run numba's serial kernels (the threaded
ones would only share the same two cores). A user's callback sees the child's
generations too (relayed when this process is between its own); Ctrl-C, or a callback
asking to stop, reaches the child at its next generation boundary, so its checkpoint
is as consistent as this process's. A child that dies or cannot send its result back
leaves its N to this process.

*N terms contain N − 1* (:mod:`._nesting`): the fit of N starts from the fit of N − 1
(a member of its first population, and the floor of its error) where the scan has that
fit when N's begins side by side: N = 2, 4, 6, ... (N = 1 has none). N = 3, 5, ... (2
when max_prony is 2), fitted beside N − 1, start without it, and one that ends above
N − 1's error (beyond :data:`._nesting.FLOOR_RTOL`) is fitted again from it, in this
process. The rule is the same on one process, so that the result stays the same to
the bit; the child hands the fits it made of the laws the law contains to this
process, whose later N are seeded by them as on one process.
"""

from __future__ import annotations

import contextlib
import os
import time
import warnings
from collections.abc import Callable
from dataclasses import replace

from vhfit import _kernels
from vhfit._pools import INTERRUPT, ChildLost, ForkedCall, fork_is_safe, usable_cpus
from vhfit.calibration import _nesting, _spectrum
from vhfit.calibration._result import Calibration, CalibrationWarning
from vhfit.calibration._settings import CalibrationSettings

__all__ = ["order_scan", "side_by_side"]

#: The child's first N: the longest of N = 1, 2, 3, which this process fits meanwhile.
FIRST_CHILD = 3


def side_by_side(settings: CalibrationSettings) -> bool:
    """Whether this scan runs on two processes: ``scan_workers`` 2, or "auto" with two
    usable CPUs; never where a fork is unsafe (:func:`vhfit._pools.fork_is_safe`: not
    Linux, or another Python thread), inside a daemonic pool worker (it may not have
    children), with ``max_prony`` 1, or when the population is already evaluated by
    worker processes. Both processes run numba's serial kernels, so a thread pool
    started by an earlier fit of this process does not stop it."""
    import multiprocessing

    w = settings.scan_workers
    if w == 1 or (w == "auto" and usable_cpus() < 2) or settings.max_prony < 2:
        return False
    if settings.workers != 1 or multiprocessing.current_process().daemon:
        return False
    return fork_is_safe(serial_child=True)  # both sides run serial kernels


def beside(n: int, max_prony: int) -> bool:
    """Whether a two-process scan fits N = n beside N − 1 (in the child, begun before
    N − 1 ends): N = 3, 5, 7, ..., or 2 when max_prony is 2."""
    first = min(FIRST_CHILD, max_prony)
    return n >= first and (n - first) % 2 == 0 and n >= 2


def _level(cal, target: float) -> float:
    """The error the rule compares: the fit's, or the target where it is below it (errors
    below the target differ by the rounding of exact data: no term gains there)."""
    return max(cal.rmsape, target)


def _needed(n: int, results: dict, s: CalibrationSettings) -> bool:
    """Whether the rule goes on to N = n, from the errors of N < n (all known)."""
    if n <= 2:
        return True
    last = _level(results[n - 1], s.target)
    return last <= min(_level(results[k], s.target)
                       for k in range(1, n - 1)) * (1 - s.order_tol)


def order_scan(curves, settings: CalibrationSettings, t0: float,
               calibrate_n: Callable) -> Calibration:
    """N = 1, 2, ... each a calibration (``calibrate_n``), while a term lowers the best
    error by order_tol (relative) or more, up to max_prony; the smallest N within
    order_tol of the best.

    A term that gains less than order_tol ends the scan: a further one is not worth its
    constants by the same rule that chooses N, and each N costs a global search. An error
    below the target counts as the target (on exact data the fits of N and N + 1 differ
    there by rounding alone, which an N fitted again from N − 1 can lower). Two
    processes where :func:`side_by_side` allows (see the module).
    """
    s = settings
    results: dict[int, Calibration] = {}
    fit = _Fits(curves, s, t0, calibrate_n, results)
    with contextlib.ExitStack() as stack:
        if side_by_side(s):
            stack.enter_context(_kernels.serial())
            stack.push(fit.cancel)
            fit.start(min(FIRST_CHILD, s.max_prony))
        for n in range(1, s.max_prony + 1):
            if not _needed(n, results, s) or fit.time_left() == 0.0:
                break
            if fit.child_n == n:
                results[n] = fit.collect()
            else:
                if fit.side and fit.child_n is None and n + 1 <= s.max_prony:
                    fit.start(n + 1)  # ahead of the rule: thrown away if it stops at n
                results[n] = fit.here(n)
            if results[n].interrupted:  # Ctrl-C ends the whole scan
                fit.interrupt()
                break
            if fit.below_floor(n):  # fitted beside N − 1 and above it: again from it
                results[n] = fit.here(n, floor=True)
                if results[n].interrupted:
                    fit.interrupt()
                    break
    scan = [results[n] for n in sorted(results)]
    return _choose(scan, s, t0, fit.side)


class _Fits:
    """The scan's fits: here, or in the one forked child at a time."""

    def __init__(self, curves, settings: CalibrationSettings, t0: float, calibrate_n,
                 results: dict):
        self.curves, self.s, self.t0, self.calibrate_n = curves, settings, t0, calibrate_n
        self.results = results  # the fits of N so far (the seeds of later N)
        self.side = False
        self.child_n: int | None = None
        self.child: ForkedCall | None = None

    def time_left(self) -> float | None:
        if self.s.max_time is None:
            return None
        return max(0.0, self.s.max_time - (time.perf_counter() - self.t0))

    def _checkpoint(self, n: int, floor: bool = False):
        ckpt = self.s.checkpoint  # one checkpoint per N of the scan (and per fit again)
        return None if ckpt is None else f"{ckpt}.N{n}{'.floor' if floor else ''}"

    def below_floor(self, n: int) -> bool:
        """Whether N = n, fitted beside N − 1 (without its seed), ended above N − 1's
        error: fitted again from it, unless a max_time cuts the scan."""
        r = self.results
        return (beside(n, self.s.max_prony) and n - 1 in r and self.s.max_time is None
                and r[n].rmsape > r[n - 1].rmsape * (1 + _nesting.FLOOR_RTOL))

    def _run(self, n: int, callback=None, floor: bool = False) -> Calibration:
        s = self.s if callback is None else replace(self.s, callback=callback)
        # the fit of N − 1 where the scan has it when N's begins on two processes
        prior = (self.results.get(n - 1) if floor or not beside(n, self.s.max_prony)
                 else None)
        cal = self.calibrate_n(self.curves, s, n, checkpoint=self._checkpoint(n, floor),
                               max_time=self.time_left(), t0=time.perf_counter(),
                               prior=prior)
        return replace(cal, settings=self.s)  # the caller's, not a relaying callback's

    def _in_child(self, n: int, callback):
        # the settings stay behind: the user's callables need not pickle; the fits it
        # made of the contained laws go to the parent (the seeds of its later N)
        before = _nesting.snapshot()
        cal = replace(self._run(n, callback), settings=None)
        return cal, _nesting.added_since(before)

    def start(self, n: int) -> None:
        """Fork the child that fits N = n."""
        self.side, self.child_n = True, n
        self.child = ForkedCall(self._in_child, n, forward=self.s.callback is not None)

    def here(self, n: int, floor: bool = False) -> Calibration:
        """Fit N = n in this process (``floor``: again, from the fit of N − 1); the
        child's messages reach the user's callback between this process's generations."""
        user, child = self.s.callback, self.child
        if user is None or child is None:
            return self._run(n, floor=floor)

        def callback(d):
            child.poll(user)
            return user(d)

        return self._run(n, callback, floor)

    def collect(self) -> Calibration:
        """The child's fit, once it is done; its N fitted here if the child was lost."""
        n, child = self.child_n, self.child
        try:
            cal, fits = child.result(self.s.callback)
        except ChildLost as exc:
            self.child_n = self.child = None
            warnings.warn(f"the order scan's N = {n} is fitted again in this process "
                          f"({exc})", CalibrationWarning, stacklevel=4)
            return self._run(n)
        # (any other exception leaves the child to cancel(), which ends it)
        self.child_n = self.child = None
        _nesting.keep(fits)
        return replace(cal, settings=self.s)

    def interrupt(self) -> None:
        """Ctrl-C: the child stops at its next generation boundary (its checkpoint
        consistent, for a resume), and its fit is not used."""
        if self.child is not None:
            self.child.stop(INTERRUPT)
            # its answer is not used: an interrupted fit, or the KeyboardInterrupt of a
            # fit cut before its search had a result
            with contextlib.suppress(Exception, KeyboardInterrupt):
                self.child.result()
            self.child_n = self.child = None

    def cancel(self, exc_type=None, *_) -> None:
        """The scan ends with the child still fitting: end it. If the rule stopped before
        the child's N, remove its checkpoint too (an N the rule never reached has none);
        if an exception ends the scan, keep it (a resume continues it)."""
        if self.child is not None:
            self.child.cancel()
            ckpt = self._checkpoint(self.child_n)
            if ckpt is not None and exc_type is None:
                for path in (ckpt, f"{ckpt}.widened"):
                    with contextlib.suppress(FileNotFoundError):
                        os.remove(path)
            self.child_n = self.child = None


def _choose(results: list[Calibration], s: CalibrationSettings, t0: float,
            side: bool) -> Calibration:
    """The smallest N within order_tol of the best, with the scan's record."""
    order_tol = s.order_tol
    best = min(_level(r, s.target) for r in results)
    chosen = next(r for r in results
                  if _level(r, s.target) <= best * (1 + order_tol) + 1e-12)
    heads = []
    if results.index(chosen) + 1 == len(results) == s.max_prony:
        heads.append(_spectrum.cap_message(
            len(results), f"N = 1..{len(results)}, max_prony / --max-prony",
            "raise max_prony (--max-prony) to try more"))
        warnings.warn(heads[0], CalibrationWarning, stacklevel=4)
    return replace(
        chosen, headlines=heads + list(chosen.headlines), warnings=heads + list(chosen.warnings),
        order_scan=[{"n_prony": n + 1, "rmsape": r.rmsape, "effective_n": r.n_prony}
                    for n, r in enumerate(results)],
        options={**chosen.options, "n_prony": "auto",
                 "n_prony_chosen": results.index(chosen) + 1,
                 "scan_processes": 2 if side else 1,
                 "order_rule": f"N = 1, 2, ... while a term lowers the best RMSAPE by "
                               f"{order_tol:.0%} or more (max_prony = {s.max_prony}); "
                               f"the smallest N whose RMSAPE is within {order_tol:.0%} of the "
                               f"best over N = 1..{len(results)}"},
        wall_time=time.perf_counter() - t0)
