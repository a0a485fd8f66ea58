"""calibrate_many: executors, streaming, failure isolation, determinism, numba's cache, Dask.

Process pools here use the "spawn" start method (workers are fresh interpreters), so
each pool costs an interpreter start and an import of vhfit; the tests share one
pool where they can. Jobs are small synthetic calibrations (a second or less).
"""

from __future__ import annotations

import concurrent.futures as cf
import functools
import multiprocessing
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import vhfit
from vhfit._pools import fork_is_safe, get_context, process_pool, worker_map
from vhfit.calibration import CalibrationWarning
from vhfit.parallel import Job, JobResult, calibrate_many

TRUTH = dict(C10=0.2, C01=0.1, G1=1.0, tau1=1e-2)
RATES = (-1.0, -100.0)


def curves(noise=0.05, seed=5, truth=TRUTH, rates=RATES):
    m = vhfit.ViscoHyperelastic("mooney_rivlin", sum(k.startswith("tau") for k in truth))
    rng = np.random.default_rng(seed)
    eps = np.linspace(-0.05, -0.5, 10)
    out = []
    for r in rates:
        s = m.stress(truth, strain=eps, strain_rate=r, measure="engineering")
        out.append(vhfit.Curve(strain=eps, stress=s * (1 + rng.uniform(-noise, noise, s.size)),
                               strain_rate=r, name=f"rate {r:g}"))
    return out


def small_jobs(n=3):
    c = curves()
    return [dict(name=f"seed {k}", curves=c, n_prony=1, seed=k, uncertainty=False)
            for k in range(n)]


def kill_self(state):
    """A callback that kills its own (worker) process: a stand-in for a segfault or OOM."""
    os.kill(os.getpid(), signal.SIGKILL)


def same(a: JobResult, b: JobResult) -> bool:
    ca, cb = a.calibration, b.calibration
    return (ca.params == cb.params and ca.history["best"] == cb.history["best"]
            and ca.history["mean"] == cb.history["mean"] and ca.nit == cb.nit)


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CalibrationWarning)
        yield


@pytest.fixture(scope="module")
def serial():
    """The reference: every small job run in this process."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CalibrationWarning)
        return {r.name: r for r in calibrate_many(small_jobs())}


@pytest.fixture(scope="module")
def pool():
    """One user-supplied spawn process pool shared by the tests of this module."""
    ex = cf.ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn"))
    yield ex
    ex.shutdown(cancel_futures=True)


# ------------------------------------------------------------------ serial runs
def test_serial_run_yields_in_input_order_and_isolates_failures(serial):
    c = curves()
    jobs = [
        dict(name="good", curves=c, n_prony=1, seed=0, uncertainty=False),
        dict(name="bad option", curves=c, n_prony=1, method="simplex"),
        dict(name="no curves", n_prony=1),
        "not a job",
        dict(name="bad model", curves=c, hyperelastic="no_such_law"),
        Job("as Job", c, dict(n_prony=1, seed=0, uncertainty=False)),
        dict(name="unknown keyword", curves=c, n_prony=1, colour="red"),
        dict(name="empty", curves=[]),
    ]
    res = list(calibrate_many(jobs))
    by = {r.name: r for r in res}
    assert len(res) == len(jobs)
    assert sorted(r.index for r in res) == list(range(len(jobs)))
    assert by["good"].ok and by["as Job"].ok
    assert by["good"].calibration.params == by["as Job"].calibration.params
    assert by["bad option"].error.startswith("ValueError: method = 'simplex'")
    assert "has no 'curves'" in by["no curves"].error
    assert by["job 3"].error.startswith("TypeError: job 3 is a str")
    assert by["bad model"].error.startswith("ValueError") and "no_such_law" in by["bad model"].error
    assert by["unknown keyword"].error.startswith("TypeError") and "colour" in by[
        "unknown keyword"].error
    assert "at least one curve" in by["empty"].error
    assert "Traceback" in by["bad option"].traceback
    for r in res:
        assert (r.calibration is None) == (not r.ok)
        assert r.wall_time >= 0
        assert r.name in repr(r)


def test_warnings_of_a_job_are_collected_in_its_result():
    c = curves()
    [r] = calibrate_many([dict(curves=c, n_prony=3, seed=0, uncertainty=False)])
    assert r.ok
    assert any("effective N" in w and w.startswith("CalibrationWarning") for w in r.warnings)
    assert all(w.split(": ", 1)[1] in " ".join(r.warnings) for w in
               ["CalibrationWarning: " + m for m in r.calibration.warnings])


def test_serial_run_is_lazy():
    it = calibrate_many(small_jobs(2))
    first = next(it)
    assert first.index == 0 and first.ok
    it.close()


def test_paths_are_read_by_the_worker_and_a_bad_file_fails_alone(tmp_path):
    c = curves()[0]
    good = tmp_path / "good.csv"
    good.write_text("# strain_rate: -1\nstrain,stress_MPa\n" + "".join(
        f"{float(e)!r},{float(s)!r}\n" for e, s in zip(c.strain, c.stress)))
    jobs = [dict(name="file", curves=str(good), n_prony=1, seed=0, uncertainty=False),
            dict(name="files", curves=[good, good], n_prony=1, seed=0, uncertainty=False),
            dict(name="missing", curves=str(tmp_path / "nope.csv"), n_prony=1),
            dict(name="directory", curves=tmp_path, n_prony=1)]
    by = {r.name: r for r in calibrate_many(jobs)}
    assert by["file"].ok and by["files"].ok
    assert by["missing"].error.startswith("DataError") and "nope.csv" in by["missing"].error
    assert by["directory"].error.startswith("DataError") and "directory" in by["directory"].error


def test_base_seed_gives_each_job_its_own_repeatable_seed():
    c = curves()
    jobs = [dict(curves=c, n_prony=1, uncertainty=False, polish=False) for _ in range(2)]
    jobs.append(dict(curves=c, n_prony=1, uncertainty=False, polish=False, seed=3))
    a = list(calibrate_many(jobs, seed=11))
    b = list(calibrate_many(jobs, seed=11))
    seeds = [r.calibration.options["seed"] for r in a]
    assert seeds == [r.calibration.options["seed"] for r in b]
    assert seeds[0] != seeds[1] and seeds[2] == 3
    assert all(same(x, y) for x, y in zip(a, b))


@pytest.mark.parametrize(
    "executor, kw, err, says",
    [
        ("cluster", {}, ValueError, "executor = 'cluster'"),
        (0, {}, ValueError, "executor = 0"),
        (True, {}, TypeError, "executor = True"),
        (3.5, {}, TypeError, "executor is a float"),
        (None, {"max_workers": 0}, ValueError, "max_workers = 0"),
        (None, {"max_workers": 2.0}, ValueError, "max_workers = 2.0"),
        (None, {"threads_per_job": 0}, ValueError, "threads_per_job = 0"),
        (None, {"threads_per_job": 1.5}, ValueError, "threads_per_job = 1.5"),
        (None, {"max_pending": 0}, ValueError, "max_pending = 0"),
        (None, {"seed": -1}, ValueError, "seed = -1"),
        (None, {"seed": 1.5}, ValueError, "seed = 1.5"),
        (None, {"seed": []}, ValueError, "seed = []"),
        (None, {"seed": [1, "a"]}, ValueError, "seed = [1, 'a']"),
        (2, {"mp_context": "threads"}, ValueError, "mp_context = 'threads'"),
        (2, {"mp_context": 2}, ValueError, "mp_context is a int"),
        (2, {"initializer": "numpy"}, ValueError, "initializer is a str"),
        (2, {"initializer": print, "initargs": 1}, ValueError, "initargs is a int"),
        (2, {"max_workers": 3}, ValueError, "max_workers = 3 contradicts executor = 2"),
        (map, {"max_workers": 2}, ValueError, "max_workers sizes the pools created here"),
        (map, {"initializer": print}, ValueError, "initializer runs in the pools"),
        (None, {"initializer": print}, ValueError, "initializer runs in worker processes"),
    ],
)
def test_bad_arguments_are_refused_at_once_in_one_line(executor, kw, err, says):
    started = set(multiprocessing.active_children())
    with pytest.raises(err) as info:
        calibrate_many(small_jobs(1), executor, **kw)  # raises before the first next()
    msg = str(info.value)
    assert msg.startswith(says) and "\n" not in msg and "give" in msg
    assert set(multiprocessing.active_children()) == started  # no pool was started


@pytest.mark.parametrize("jobs", [{"curves": []}, "jobs.csv", 3,
                                  Job("one", curves=[], kwargs={})])
def test_jobs_that_are_not_a_list_of_jobs_are_refused(jobs):
    with pytest.raises(ValueError, match=r"^jobs is a \w+: give a list"):
        calibrate_many(jobs)


def test_good_arguments_pass_the_front_door():
    ctx = multiprocessing.get_context("spawn")
    for executor, kw in [(None, {}), (None, {"max_workers": 1}), (2, {"max_workers": 2}),
                         ("thread", {"max_workers": 2, "initializer": print}),
                         (2, {"mp_context": ctx, "seed": [1, 2], "threads_per_job": None}),
                         (map, {"seed": np.int64(3), "max_pending": 4})]:
        calibrate_many([], executor, **kw).close()  # a generator: nothing has started


# --------------------------------------------------------- the pools module
def square(x):
    return x * x


def numba_threads(_):
    import numba

    return numba.get_num_threads()


@pytest.mark.parametrize("workers", [0, -2, True, 2.0, "2", None])
def test_worker_map_refuses_what_calibrate_refuses(workers):
    with pytest.raises(ValueError, match=r"^workers = .*: give") as info:
        with worker_map(workers):
            pass
    assert "\n" not in str(info.value)


def test_worker_map_serial_map_like_and_all_cpus(monkeypatch):
    with worker_map(1) as (mapper, chunks):
        assert (mapper, chunks) == (None, 1)
    with worker_map(np.int64(1)) as (mapper, chunks):
        assert (mapper, chunks) == (None, 1)

    def my_map(f, xs):
        return map(f, xs)

    with worker_map(my_map) as (mapper, chunks):
        assert mapper is my_map and chunks == 2 * (os.cpu_count() or 2)
    monkeypatch.setattr(os, "cpu_count", lambda: 1)  # -1 = one worker per CPU
    with worker_map(-1) as (mapper, chunks):
        assert (mapper, chunks) == (None, 1)


@pytest.mark.parametrize("start", ["auto", "spawn"])
def test_worker_map_pool_maps_in_order_with_one_numba_thread_per_worker(start):
    before = set(multiprocessing.active_children())
    with worker_map(2, start) as (mapper, chunks):
        assert chunks == 2
        assert list(mapper(square, range(7))) == [k * k for k in range(7)]
        assert set(mapper(numba_threads, range(4))) == {1}
    assert set(multiprocessing.active_children()) <= before  # shut down on exit


def test_worker_map_pool_gives_calibrate_the_in_process_objective_values():
    # what calibrate sends through the map: batches of parameter vectors
    c = curves()
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    batch = m.batch(c)
    X = np.random.default_rng(0).uniform([0.1, 0.05, 0.5, 1e-3], [0.3, 0.2, 2.0, 1e-1],
                                         (8, 4))
    chunks = np.array_split(X, 2)
    with worker_map(2) as (mapper, _):
        got = np.concatenate(list(mapper(batch, chunks)))
    assert np.array_equal(got, batch(X))  # bit for bit


def set_env(key, value):
    os.environ[key] = value


def get_env(key):
    return os.environ.get(key)


def test_process_pool_runs_the_initializer_after_the_thread_cap():
    with process_pool(1, "spawn", numba_threads=1, initializer=set_env,
                      initargs=("VHFIT_TEST_INIT", "yes")) as pool:
        assert pool.submit(get_env, "VHFIT_TEST_INIT").result() == "yes"
        assert pool.submit(numba_threads, None).result() == 1


def test_importing_the_warm_module_runs_nothing():
    code = textwrap.dedent("""
        import vhfit.calibration

        def boom(*args, **kwargs):
            raise AssertionError("a calibration ran at import")

        vhfit.calibration.calibrate = boom  # what vhfit._warm calls
        import vhfit._warm
        print(vhfit._warm.calibrate is boom)
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["True"]


# ------------------------------------------------------------------- executors
def wait_for_file(path, state):
    """A callback that holds its generation until ``path`` exists (at most 300 s)."""
    deadline = time.monotonic() + 300
    while not os.path.exists(path) and time.monotonic() < deadline:
        time.sleep(0.01)


def test_user_executor_streams_results_as_they_finish(pool, serial, tmp_path):
    # the slow job cannot finish before the fast one has been streamed back: its first
    # generation waits for a file written only once the first result has arrived (an
    # event, not a race between a sleep and the machine's speed)
    go = tmp_path / "go"
    c = curves()
    slow = dict(name="slow", curves=c, n_prony=1, seed=0, maxiter=3, tol=0.0, target=0.0,
                stall=(0.0, 10**6), polish=False, uncertainty=False,
                callback=functools.partial(wait_for_file, str(go)))
    fast = dict(name="fast", curves=c, n_prony=1, seed=0, polish=False, uncertainty=False,
                maxiter=2)
    order = []
    for r in calibrate_many([slow, fast], pool):
        assert r.ok, r.error
        order.append(r.name)
        go.touch()
    assert order == ["fast", "slow"]


def test_process_pool_constants_are_bit_identical_to_in_process(pool, serial):
    res = {r.name: r for r in calibrate_many(small_jobs(), pool)}
    assert set(res) == set(serial)
    for name, r in res.items():
        assert r.ok, r.error
        assert same(r, serial[name])


def test_map_like_callables_give_input_order_and_identical_constants(pool, serial):
    via_map = list(calibrate_many(small_jobs(), pool.map))
    assert [r.index for r in via_map] == [0, 1, 2]
    assert all(same(r, serial[r.name]) for r in via_map)
    via_builtin = list(calibrate_many(small_jobs(), map))
    assert all(same(r, serial[r.name]) for r in via_builtin)


def test_a_broken_map_reports_the_remaining_jobs():
    def mapper(fn, tasks):
        for k, t in enumerate(tasks):
            if k == 1:
                raise RuntimeError("cluster lost")
            yield fn(t)

    res = list(calibrate_many(small_jobs(3), mapper))
    assert res[0].ok
    assert [r.index for r in res] == [0, 1, 2]
    assert all("cluster lost" in r.error for r in res[1:])


def test_thread_pool_runs_jobs(serial):
    res = {r.name: r for r in calibrate_many(small_jobs(2), "thread", max_workers=2)}
    assert all(same(r, serial[r.name]) for r in res.values())


@pytest.mark.parametrize("start", ["auto", "spawn"])
def test_own_pool_isolates_a_job_that_kills_its_worker(serial, start):
    jobs = small_jobs()
    c = jobs[0]["curves"]
    jobs.insert(1, dict(name="killer", curves=c, n_prony=1, seed=0, callback=kill_self))
    jobs.insert(2, dict(name="bad option", curves=c, n_prony=1, method="simplex"))
    before = set(multiprocessing.active_children())
    res = {r.name: r for r in calibrate_many(jobs, 2, mp_context=start)}
    assert len(res) == len(jobs)
    assert res["killer"].error.startswith("WorkerDied")
    assert res["bad option"].error.startswith("ValueError")
    for name, r in serial.items():
        assert res[name].ok and same(res[name], r)
    assert set(multiprocessing.active_children()) <= before


def test_auto_start_method_forks_only_a_single_threaded_process():
    assert get_context("spawn").get_start_method() == "spawn"
    done = threading.Event()
    t = threading.Thread(target=done.wait)
    t.start()
    try:
        assert not fork_is_safe()  # another thread might hold a lock across the fork
        expected = "forkserver" if sys.platform.startswith("linux") else "spawn"
        assert get_context("auto").get_start_method() == expected
    finally:
        done.set()
        t.join()


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="fork server: Linux path")
def test_forkserver_pool_gives_the_serial_constants(serial):
    res = {r.name: r for r in calibrate_many(small_jobs(), 2, mp_context="forkserver")}
    assert all(r.ok for r in res.values())
    assert all(same(r, serial[r.name]) for r in res.values())


def test_calibration_keeps_numba_thread_pool_unstarted_so_pools_can_fork():
    # a fresh interpreter: this one may have run the threaded kernel in other tests
    code = textwrap.dedent(f"""
        import warnings; warnings.simplefilter("ignore")
        import numpy as np, vhfit
        from numba.np.ufunc import parallel as p
        from vhfit._pools import get_context
        m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
        eps = np.linspace(-0.05, -0.5, 10)
        curves = [vhfit.Curve(strain=eps, strain_rate=r, name=str(r),
                              stress=m.stress({TRUTH!r}, strain=eps, strain_rate=r))
                  for r in {RATES!r}]
        vhfit.calibrate(curves, n_prony=1, seed=0)
        print(p._is_initialized, get_context("auto").get_start_method())
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr
    expected = "fork" if sys.platform.startswith("linux") else "spawn"
    assert out.stdout.split() == ["False", expected]


def test_closing_the_stream_early_stops_the_workers():
    before = set(multiprocessing.active_children())
    it = calibrate_many(small_jobs(6), 2, max_pending=6)
    assert next(it).ok
    assert set(multiprocessing.active_children()) > before
    it.close()
    deadline = time.monotonic() + 10
    while set(multiprocessing.active_children()) - before and time.monotonic() < deadline:
        time.sleep(0.05)
    assert set(multiprocessing.active_children()) <= before


# ----------------------------------------------------------------- numba's cache
WARM = textwrap.dedent(
    """
    import hashlib
    import numpy as np, vhfit
    from vhfit import _kernels
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    eps = np.linspace(-0.05, -0.5, 10)
    cs = [vhfit.Curve(strain=eps, stress=eps, strain_rate=r) for r in (-1.0, -10.0, -100.0)]
    b = m.batch(cs)
    P = _kernels.PARALLEL_MIN_JOBS // 3 + 1  # big enough for the parallel kernel too
    X = np.tile([0.1, 0.05, 1.0, 1e-3, 2.0, 1e-1], (P, 1)) * np.linspace(1, 2, P)[:, None]
    one = m.stress([0.1, 0.05, 1.0, 1e-3, 2.0, 1e-1], strain=eps, strain_rate=-10.0)
    out = np.concatenate([b(X).ravel(), b(X[:2]).ravel(), one])
    print(hashlib.sha256(out.tobytes()).hexdigest())
    """
)


def _start_many(n, cache):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "NUMBA_NUM_THREADS": "2",
           "NUMBA_DEBUG_CACHE": "1"}
    return [subprocess.Popen([sys.executable, "-c", WARM], env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True) for _ in range(n)]


# five writers and four readers on two cores: more processes than cores race for the
# cache in both waves (eight and eight took two minutes, for no further evidence)
@pytest.mark.parametrize("writers, readers", [(5, 4)])
def test_numba_cache_is_safe_when_many_processes_start_at_once(tmp_path, writers, readers):
    cache = tmp_path / "numba-cache"
    results, loaded, saved = [], [], []
    # first wave: all compile and write the empty cache together; second: all load it
    for wave, n in enumerate((writers, readers)):
        procs = _start_many(n, cache)
        for p in procs:
            out, err = p.communicate(timeout=600)
            assert p.returncode == 0, err[-2000:]
            lines = out.splitlines()
            results.append(lines[-1])
            if wave == 1:
                loaded.append(sum(line.startswith("[cache] data loaded") for line in lines))
                saved.append(sum(line.startswith("[cache] data saved") for line in lines))
    assert len(set(results)) == 1  # every process computed the same stresses, bit for bit
    assert any(f.suffix == ".nbi" for f in cache.rglob("*"))
    # the readers loaded both kernels (sequential and parallel) and compiled nothing
    assert min(loaded) >= 2 and max(saved) == 0


# ------------------------------------------------------------------------ Dask
def test_local_dask_cluster_gives_identical_constants(serial):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        ex = client.get_executor()
        streamed = {r.name: r for r in calibrate_many(small_jobs(), ex)}
        mapped = list(calibrate_many(small_jobs(), ex.map))
    for name, r in serial.items():
        assert streamed[name].ok, streamed[name].error
        assert same(streamed[name], r)
    assert [r.index for r in mapped] == [0, 1, 2]
    assert all(same(r, serial[r.name]) for r in mapped)


def test_the_dask_example_runs_on_a_local_cluster(tmp_path):
    pytest.importorskip("distributed")
    script = Path(__file__).resolve().parents[1] / "examples" / "dask_cluster.py"
    proc = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert "identical constants in this process and on the Dask cluster: True" in proc.stdout


# ------------------------------------------------------- one call in a forked child
fork_only = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="fork: Linux")


@fork_only
def test_forked_call_raises_what_the_child_raised():
    from vhfit._pools import ForkedCall

    def bad(callback):
        raise ValueError("no curves")

    with pytest.raises(ValueError, match="no curves"):
        ForkedCall(bad).result()


@fork_only
@pytest.mark.parametrize("how", ["dies", "unpicklable"])
def test_forked_call_says_when_the_child_gives_no_answer(how):
    from vhfit._pools import ChildLost, ForkedCall

    def fn(callback):
        if how == "dies":
            os._exit(5)
        return lambda: 1  # a lambda does not pickle

    with pytest.raises(ChildLost, match="exit code 5" if how == "dies" else "pickled"):
        ForkedCall(fn).result()


@fork_only
def test_forked_call_relays_messages_stops_and_warnings():
    """The child's messages reach a callback here; the callback's True reaches the
    child's relay as a stop; its warnings are raised here."""
    from vhfit._pools import ForkedCall

    def count(callback):
        # until the stop comes: the pipe holds a few thousand messages, so the child
        # cannot run far ahead of the callback that asks it to stop
        for k in range(200_000):
            if callback({"k": k}):
                warnings.warn(f"stopped at {k}", UserWarning, stacklevel=2)
                return k
        return -1

    seen = []
    with pytest.warns(UserWarning, match="stopped at"):
        k = ForkedCall(count, forward=True).result(lambda d: seen.append(d["k"]) or d["k"] == 2)
    # the stop asked at message 2 is read at that relay call or a later one (the child
    # does not wait for answers: on a loaded machine the parent may answer before the
    # child reads the flag after sending message 2); every message before the result
    # arrives, in order
    assert k >= 2 and seen == list(range(k + 1))


@fork_only
def test_forked_call_interrupt_reaches_the_child_at_its_next_relay():
    from vhfit._pools import INTERRUPT, ForkedCall

    started = multiprocessing.get_context("fork").Event()

    def loop(callback):
        started.set()
        while True:
            callback(None)

    call = ForkedCall(loop)
    assert started.wait(60)
    call.stop(INTERRUPT)
    call.process.join(60)  # the child's exit is the event waited for
    assert call.process.exitcode is not None, "the interrupt never reached the child"
    with pytest.raises(KeyboardInterrupt):
        call.result()


# ------------------------------------------------ a bare forked copy (_pools.forked)
@fork_only
def test_forked_copy_answers_with_this_process_state():
    from vhfit._pools import forked

    state = {"x": np.arange(5.0)}  # in the copy's memory, not pickled on the way in
    answer = forked(lambda: (os.getpid(), float(state["x"].sum())))
    pid, total = answer()
    assert pid != os.getpid() and total == 10.0


@fork_only
@pytest.mark.parametrize("how", ["raises", "unpicklable"])
def test_forked_copy_without_an_answer_gives_none(how):
    from vhfit._pools import forked

    def fn():
        if how == "raises":
            raise ValueError("no figure")
        return lambda: 1  # a lambda does not pickle

    assert forked(fn)() is None


@fork_only
def test_forked_copy_ends_with_its_parent(tmp_path):
    # the parent (a fresh interpreter) dies while its copy still works: the kernel ends
    # the copy too (it would otherwise go on writing files for nobody)
    pid_file = tmp_path / "copy.pid"
    code = (
        "import os, sys, time\n"
        "from vhfit._pools import forked\n"
        "def work():\n"
        f"    open({str(pid_file)!r}, 'w').write(str(os.getpid()))\n"
        "    time.sleep(120)\n"
        "forked(work)\n"
        "for _ in range(600):\n"
        f"    if os.path.exists({str(pid_file)!r}) and open({str(pid_file)!r}).read():\n"
        "        break\n"
        "    time.sleep(0.05)\n"
        "os._exit(0)\n")
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)
    pid = int(pid_file.read_text())

    def running() -> bool:  # a zombie not yet reaped by its new parent has ended too
        try:
            stat = Path(f"/proc/{pid}/stat").read_text()
        except OSError:
            return False
        return stat.rsplit(")", 1)[1].split()[0] != "Z"

    for _ in range(200):
        if not running():
            break
        time.sleep(0.05)
    else:
        os.kill(pid, signal.SIGKILL)
        pytest.fail("the copy outlived its parent")
