"""The order scan (``n_prony="auto"``): its rule, and its two processes side by side
giving the result of one process to the bit."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
import warnings
from dataclasses import dataclass, field

import pytest

from vhfit.calibration import CalibrationSettings, CalibrationWarning, Stop, StopKind, _scan


@dataclass(frozen=True)
class Fit:
    """What the scan reads of one N's calibration (module level: it pickles)."""

    rmsape: float
    n_prony: int
    stop_reason: Stop = Stop.of(StopKind.CONVERGED)
    headlines: list = field(default_factory=list)
    warnings: list = field(default_factory=list)
    options: dict = field(default_factory=dict)
    order_scan: list = field(default_factory=list)
    wall_time: float = 0.0
    settings: object = None
    pid: int = 0

    @property
    def interrupted(self) -> bool:
        return self.stop_reason.interrupted


def _scan_of(errors, monkeypatch, workers, *, die_in_child=False):
    parent = os.getpid()

    def calibrate_n(curves, s, n, **kw):
        if die_in_child and os.getpid() != parent:
            os._exit(3)  # a child killed mid-fit
        return Fit(errors[n - 1], n, pid=os.getpid())

    # the rule's fits run no numba kernel: forking is safe whatever this process ran
    monkeypatch.setattr(_scan, "fork_is_safe", lambda serial_child=False: True)
    monkeypatch.setattr(_scan, "usable_cpus", lambda: 2)
    settings = CalibrationSettings(n_prony="auto", max_prony=5, order_tol=0.05,
                                   scan_workers=workers)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        cal = _scan.order_scan([], settings, 0.0, calibrate_n)
    assert cal.settings is settings  # the caller's, whichever process fitted the chosen N
    return cal, [str(w.message) for w in caught if w.category is CalibrationWarning]


@pytest.mark.parametrize("errors, fitted, chosen", [
    ((10.0, 5.0, 4.9, 1.0, 0.5), 3, 2),   # N = 3 gains 2 %: no N = 4, 5
    ((10.0, 5.0, 4.0, 3.9, 1.0), 4, 3),   # N = 3 gains 20 %, N = 4 2.5 %
    ((10.0, 9.8, 1.0, 0.5, 0.4), 2, 1),   # N = 2 gains 2 %: the scan ends at once
    ((10.0, 5.0, 2.0, 1.0, 0.5), 5, 5),   # every term pays: up to max_prony
])
@pytest.mark.parametrize("workers", [1, 2])
def test_the_order_scan_ends_when_a_term_gains_less_than_order_tol(
        monkeypatch, errors, fitted, chosen, workers):
    """The scan's rule on given errors per N (each N's calibration replaced): a term that
    lowers the best error by less than order_tol ends it; the smallest N within
    order_tol of the best fitted is kept — the same N on two processes, whose fits the
    rule does not reach (N = 3 begun beside N = 1) are thrown away."""
    cal, _ = _scan_of(errors, monkeypatch, workers)
    assert [r["rmsape"] for r in cal.order_scan] == list(errors[:fitted])
    assert cal.options["n_prony_chosen"] == chosen
    assert cal.options["scan_processes"] == workers


@pytest.mark.parametrize("workers", [1, 2])
def test_errors_below_the_target_count_as_the_target(monkeypatch, workers):
    """Exact data: N = 3 is 20 % below N = 2, both far below the target (1e-4 %, the
    default), where they differ by rounding: no term gained, the scan ends and keeps
    N = 2."""
    cal, _ = _scan_of((10.0, 1e-12, 8e-13, 1e-13, 1e-14), monkeypatch, workers)
    assert [r["rmsape"] for r in cal.order_scan] == [10.0, 1e-12, 8e-13]
    assert cal.options["n_prony_chosen"] == 2


def test_two_processes_fit_in_both(monkeypatch):
    """Side by side, N = 3 (and N = 5 beside N = 4) are fitted in the child."""
    calls = []
    real = _scan._Fits._run

    def spy(self, n, callback=None, floor=False):
        cal = real(self, n, callback, floor)
        calls.append(n)  # in this process only: the child's list is its own copy
        return cal

    monkeypatch.setattr(_scan._Fits, "_run", spy)
    cal, _ = _scan_of((10.0, 5.0, 2.0, 1.0, 0.5), monkeypatch, 2)
    assert calls == [1, 2, 4]
    assert [r["rmsape"] for r in cal.order_scan] == [10.0, 5.0, 2.0, 1.0, 0.5]


def test_a_child_that_dies_leaves_its_n_to_this_process(monkeypatch):
    """A child killed mid-fit: its N is fitted here, the scan's result unchanged, and a
    warning says so."""
    errors = (10.0, 5.0, 4.0, 3.9, 1.0)
    cal, msgs = _scan_of(errors, monkeypatch, 2, die_in_child=True)
    assert [r["rmsape"] for r in cal.order_scan] == list(errors[:4])
    assert cal.options["n_prony_chosen"] == 3
    assert any("N = 3 is fitted again in this process" in m for m in msgs)


def test_an_interrupt_ends_the_child_even_where_it_raises(monkeypatch):
    """Ctrl-C cuts N = 1 here while the child fits N = 3 and answers the interrupt with
    KeyboardInterrupt itself (a fit cut before its search had a result): the scan
    returns N = 1's interrupted fit, and no child is left."""
    import multiprocessing

    parent = os.getpid()

    def calibrate_n(curves, s, n, **kw):
        if os.getpid() != parent:
            for _ in range(5_000_000):  # (bounded: never a hang)
                s.callback({"n_prony": n})  # raises KeyboardInterrupt once asked to stop
            return Fit(99.0, n)
        return Fit(10.0, n, stop_reason=Stop.of(StopKind.INTERRUPTED))

    monkeypatch.setattr(_scan, "fork_is_safe", lambda serial_child=False: True)
    monkeypatch.setattr(_scan, "usable_cpus", lambda: 2)
    settings = CalibrationSettings(n_prony="auto", max_prony=5, scan_workers=2)
    cal = _scan.order_scan([], settings, 0.0, calibrate_n)
    assert cal.interrupted and len(cal.order_scan) == 1
    assert cal.options["scan_processes"] == 2
    assert not multiprocessing.active_children()


@pytest.mark.parametrize("workers", [1, 2])
def test_each_n_starts_from_n_minus_1_where_it_is_done_and_is_floored_by_it(
        monkeypatch, workers):
    """N terms contain N − 1. N = 2 and 4 begin after N − 1 has ended (on two processes
    too) and get its fit as ``prior``; N = 3 and 5, fitted beside N − 1 on two
    processes, get none on one process as well, and N = 3, ending above N = 2 here, is
    fitted again from it, in this process; N = 5, below N = 4, is not."""
    parent = os.getpid()
    # the plain searches of each N, and of N = 3 again from N = 2's fit
    plain = {1: 10.0, 2: 5.0, 3: 6.0, 4: 2.0, 5: 1.0}
    calls = []

    def calibrate_n(curves, s, n, prior=None, **kw):
        if os.getpid() == parent:  # (the child's own list is a copy)
            calls.append((n, None if prior is None else prior.n_prony))
        if n == 3 and prior is not None:
            assert prior.rmsape == 5.0
            return Fit(4.0, n)
        return Fit(plain[n], n, pid=os.getpid())

    monkeypatch.setattr(_scan, "fork_is_safe", lambda serial_child=False: True)
    monkeypatch.setattr(_scan, "usable_cpus", lambda: 2)
    settings = CalibrationSettings(n_prony="auto", max_prony=5, order_tol=0.05,
                                   scan_workers=workers)
    cal = _scan.order_scan([], settings, 0.0, calibrate_n)
    assert [r["rmsape"] for r in cal.order_scan] == [10.0, 5.0, 4.0, 2.0, 1.0]
    here = [(1, None), (2, 1), (3, 2), (4, 3)]  # N = 3 again, from N = 2
    if workers == 1:
        here = [(1, None), (2, 1), (3, None), (3, 2), (4, 3), (5, None)]
    assert calls == here
    assert [_scan.beside(n, 5) for n in range(1, 7)] == [False, False, True, False, True,
                                                         False]
    assert [_scan.beside(n, 2) for n in (1, 2)] == [False, True]


def test_the_child_hands_its_remembered_fits_to_this_process(monkeypatch):
    """The fits the child remembered (its N's contained laws) are remembered here once
    it is collected, as they would be on one process: they seed the later N here."""
    import numpy as np

    from vhfit.calibration import _nesting

    parent = os.getpid()

    def calibrate_n(curves, s, n, **kw):
        _nesting.keep([(("test", n, os.getpid() == parent), (float(n), np.zeros(2)))])
        return Fit((10.0, 5.0, 4.0)[n - 1], n)

    monkeypatch.setattr(_scan, "fork_is_safe", lambda serial_child=False: True)
    monkeypatch.setattr(_scan, "usable_cpus", lambda: 2)
    settings = CalibrationSettings(n_prony="auto", max_prony=3, scan_workers=2)
    cal = _scan.order_scan([], settings, 0.0, calibrate_n)
    assert cal.options["scan_processes"] == 2
    kept = _nesting.snapshot()
    assert {("test", 1, True), ("test", 2, True), ("test", 3, False)} <= kept
    assert ("test", 3, True) not in kept  # N = 3 was fitted in the child only


def test_a_contained_laws_fit_is_never_seeded_by_n_minus_1():
    """The contained laws' fits are made as the same call alone would make them (no N − 1
    seed), so that remembering them changes no later result."""
    import numpy as np

    from vhfit.calibration import _nesting

    seen = []

    def calibrate_n(curves, s, n, prior=None, **kw):
        seen.append((s.hyperelastic, n, prior))
        return _Cal(1.0, np.array([0.1]))

    s = CalibrationSettings("yeoh", 2, uncertainty=False)
    _nesting.clear_cache()
    _nesting.nested_fits([], s, 2, calibrate_n)
    assert seen == [("neo_hooke", 2, None)]


@dataclass(frozen=True)
class _Cal:
    rmsape: float
    x: object


def test_scan_workers_is_checked():
    with pytest.raises(ValueError, match=r"^scan_workers = 3: give 'auto', 1"):
        CalibrationSettings(scan_workers=3)
    with pytest.raises(ValueError, match="scan_workers = True"):
        CalibrationSettings(scan_workers=True)


# A fresh interpreter: forking is safe there (this one may have started numba's threads).
_SCRIPT = textwrap.dedent("""
    import json, os, sys, time, warnings
    import numpy as np
    import vhfit
    from vhfit.calibration import CalibrationWarning
    warnings.simplefilter("ignore", CalibrationWarning)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    truth = dict(C10=0.2, C01=0.1, G1=1.0, tau1=1e-3, G2=2.0, tau2=1e-1)
    eps = np.linspace(-0.02, -0.4, 12)
    curves = [vhfit.Curve(strain=eps, strain_rate=r, stress=m.stress(
                  truth, strain=eps, strain_rate=r, measure="engineering")
                  * (1 + 0.01 * np.sin(7 * eps * r)))
              for r in (-0.5, -20.0, -900.0)]
    case = sys.argv[1]
    out = {}
    if case == "same":
        for w in (2, 1):
            seen = []
            cal = vhfit.calibrate(curves, n_prony="auto", max_prony=3, seed=1,
                                  scan_workers=w, callback=lambda d: seen.append(d["n_prony"]))
            out[w] = dict(x=cal.x.tolist(), rmsape=cal.rmsape, scan=cal.order_scan,
                          processes=cal.options["scan_processes"],
                          stop=str(cal.stop_reason), seen=sorted(set(seen)),
                          callback=cal.settings.callback is not None)
    else:  # Ctrl-C, as a callback raising it, on the child's first generation
        ck = sys.argv[2]
        def cut(d):
            if d["n_prony"] == 3:
                raise KeyboardInterrupt
        kw = dict(n_prony="auto", max_prony=3, seed=1, checkpoint=ck, checkpoint_every=0)
        from vhfit.calibration import _scan
        in_child = _scan._Fits._in_child

        def waiting(self, n, callback):  # the child waits at its first generation
            def hold(d):                 # until the interrupt comes: an event, not a time
                for _ in range(12000):   # (a minute at most: never a hang)
                    callback(d)          # raises KeyboardInterrupt once it is asked to
                    time.sleep(0.005)
                raise SystemExit("the interrupt never reached the child")
            return in_child(self, n, hold)

        _scan._Fits._in_child = waiting
        cal = vhfit.calibrate(curves, callback=cut, **kw)
        _scan._Fits._in_child = in_child
        import multiprocessing
        with open(ck + ".N3") as f:  # the child's checkpoint: done is null if cut
            done3 = json.load(f)["done"]
        out["cut"] = dict(stop=str(cal.stop_reason), scan=len(cal.order_scan),
                          processes=cal.options["scan_processes"],
                          children=len(multiprocessing.active_children()), done3=done3)
        resumed = vhfit.calibrate(curves, resume=True, **kw)
        fresh = vhfit.calibrate(curves, n_prony="auto", max_prony=3, seed=1, scan_workers=1)
        out["resumed"] = [resumed.x.tolist(), resumed.rmsape, str(resumed.stop_reason)]
        out["fresh"] = [fresh.x.tolist(), fresh.rmsape, str(fresh.stop_reason)]
    print(json.dumps(out))
""")


def _run(*args) -> dict:
    r = subprocess.run([sys.executable, "-c", _SCRIPT, *args], capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 0, r.stderr[-3000:]
    return json.loads(r.stdout.strip().splitlines()[-1])


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="fork: Linux only")
def test_side_by_side_is_the_same_scan_to_the_bit():
    """A real scan (noisy data, N = 1..3) on two processes and on one: the same
    constants, errors and N to the last bit, and the user's callback sees the child's
    generations (N = 3) as well as this process's."""
    out = _run("same")
    two, one = out["2"], out["1"]
    assert (two["processes"], one["processes"]) == (2, 1)
    for key in ("x", "rmsape", "scan", "stop"):
        assert two[key] == one[key], key
    assert two["seen"] == one["seen"] == [1, 2, 3]
    assert two["callback"] and one["callback"]  # the result keeps the caller's settings


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="fork: Linux only")
def test_ctrl_c_reaches_the_child_and_a_resume_ends_where_a_whole_run_does(tmp_path):
    """Ctrl-C (a callback raising KeyboardInterrupt) on the child's first report of
    N = 3 (the child held there until the interrupt reaches it): the child stops at that
    generation boundary and leaves its checkpoint unfinished, it has ended when the scan
    returns, and resuming the checkpoints reaches the constants of an uninterrupted
    scan to the bit.

    The report reaches this process while it fits N = 1 or 2 (that fit is then cut too
    and ends the scan) or once it waits for the child (the scan then has N = 1..3 and
    its chosen N's stop reason): either is an interrupted scan, as in one process."""
    out = _run("cut", str(tmp_path / "ck"))
    cut = out["cut"]
    assert cut["processes"] == 2 and cut["children"] == 0
    assert cut["done3"] is None  # the child was cut before it ended
    assert cut["scan"] == 3 or cut["stop"] == "interrupted"
    assert out["resumed"][:2] == out["fresh"][:2]
