"""End-to-end time of the command line, each run in a fresh process.

Two parts:

* the quick commands ``vhfit --version``, ``vhfit --help`` and ``vhfit models`` load
  only what they print (target: 0.3 s on a quiet machine, of which the interpreter's
  own start is ~0.1 s);
* ``vhfit fit`` on every shared dataset, exactly as ``docs/real-data.md`` writes the
  command (the ``DATASETS`` table of ``bench_real.py``), run from the dataset's folder
  with ``--out`` a temporary folder (nothing is written beside the data). One warm-up
  run first (numba's cache warm), then ``--repeat`` timed runs. Beside them, the same
  fits in this process: ``vhfit.calibrate_for`` every solver (one fit per formulation,
  as the command makes them) on the curves ``bench_real.py`` reads with the command's
  options, with its settings (one warm-up call: imports and kernels loaded, then the
  median of ``--repeat`` calls, each without the nested laws' fits that an earlier call
  left in memory; the first fit's RMSAPE must equal the command's, else the benchmark
  stops). The overhead (the interpreter, the imports, reading, the
  card check, the plots, the report) is the difference of the two medians, measured
  side by side. Targets: overhead ≤ 1.0 s on every dataset, end to end ≤ 2.5 s for
  every rate-free dataset. (The ``wall_time`` in ``results.json`` is not that figure:
  it counts the last search only, not the imports a fresh process pays inside
  ``calibrate``.)

Every run is a fresh process with a warm numba cache and compiled modules (the
``__pycache__`` an installed package has; ``PYTHONDONTWRITEBYTECODE`` is dropped from the
runs' environment unless ``--no-bytecode``), after one untimed warm-up run.

``--base DIR`` (another checkout's ``src``, e.g. the main branch's) times the same
commands with that code too, the two alternating run by run, so that a change is
measured side by side on the same machine load.

Run: ``PYTHONPATH=src python benchmarks/bench_cli.py [--repeat 5] [--quick-repeat 9]
[--only treloar,...] [--no-fit] [--no-quick] [--data DIR] [--base OTHER/src]
[--no-bytecode]``; prints medians.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

COMMANDS = (["--version"], ["--help"], ["models"])
#: end to end minus the fit (s), and end to end for a rate-free dataset (s)
OVERHEAD_TARGET, RATE_FREE_TARGET = 1.0, 2.5


#: Set by main(): keep PYTHONDONTWRITEBYTECODE in the runs' environment (--no-bytecode).
KEEP_NO_BYTECODE = False


def env_for(src: str | None) -> dict:
    """The environment of a run of the code in ``src`` (None: this process's own).

    Without ``PYTHONDONTWRITEBYTECODE`` (unless --no-bytecode): an installed package has
    its modules compiled, and the warm-up run writes them for a source tree, as it fills
    numba's cache; with it set, every run compiles vhfit's sources again.
    """
    env = dict(os.environ)
    if not KEEP_NO_BYTECODE:
        env.pop("PYTHONDONTWRITEBYTECODE", None)
    if src is not None:
        env["PYTHONPATH"] = str(Path(src).resolve())
    return env


def time_command(argv: list[str], repeat: int, srcs=(None,)) -> list[list[float]]:
    """Wall times of ``python -m vhfit ARGV`` in ``repeat`` fresh processes, for each
    source tree of ``srcs`` (run in turn)."""
    times: list[list[float]] = [[] for _ in srcs]
    for src in srcs:  # warm-up: the compiled modules written
        subprocess.run([sys.executable, "-m", "vhfit", *argv], check=True,
                       stdout=subprocess.DEVNULL, env=env_for(src))
    for _ in range(repeat):
        for k, src in enumerate(srcs):
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "vhfit", *argv], check=True,
                           stdout=subprocess.DEVNULL, env=env_for(src))
            times[k].append(time.perf_counter() - t0)
    return times


def fit_argv(ds) -> list[str]:
    """The documented command's arguments after ``vhfit`` (bench_real's table)."""
    import shlex

    return shlex.split(ds.command())[1:]


def time_fit(ds, folder: Path, repeat: int, srcs=(None,)) -> tuple[list[list[float]],
                                                                  list[float]]:
    """(end-to-end wall times, RMSAPE) per source tree of ``srcs`` of ``repeat`` runs of
    the dataset's command after one warm-up run each, every run in a fresh process, the
    trees alternating."""
    wall: list[list[float]] = [[] for _ in srcs]
    err = [float("nan")] * len(srcs)
    with tempfile.TemporaryDirectory(prefix="bench_cli_") as tmp:
        for k in range(repeat + 1):
            for j, src in enumerate(srcs):
                out = Path(tmp) / f"run{k}-{j}"
                argv = [sys.executable, "-m", "vhfit", *fit_argv(ds), "--out", str(out)]
                t0 = time.perf_counter()
                done = subprocess.run(argv, cwd=folder, stdout=subprocess.DEVNULL,
                                      stderr=subprocess.PIPE, text=True, env=env_for(src))
                t = time.perf_counter() - t0
                if done.returncode != 0:
                    raise SystemExit(f"{ds.name}: exit {done.returncode}: "
                                     f"{done.stderr.strip()}")
                if k == 0:  # warm-up: numba's cache, the file system's
                    continue
                wall[j].append(t)
                err[j] = float(json.loads((out / "results.json").read_text())["rmsape"])
    return wall, err


def time_calibrate(ds, root: Path, repeat: int) -> tuple[float, float]:
    """(median wall time, RMSAPE) of the same fits in this process, after one warm-up
    call: :func:`vhfit.calibrate_for` every solver, as the command fits (one fit per
    formulation the solvers integrate, the second started from the first; the first's
    RMSAPE is the results' own).

    The fits that seed a law's search with the laws it contains are remembered by the
    process (``vhfit.calibration._nesting``): they are forgotten before each call, as a
    fresh command starts without them, so that each call is the command's whole fit.
    """
    import warnings

    from bench_real import read

    import vhfit
    from vhfit.calibration._nesting import clear_cache

    curves = read(ds, root)
    kw = {"hyperelastic": ds.law, "seed": 0, **ds.fit}
    times, err = [], float("nan")
    for k in range(repeat + 1):  # the first: imports, numba's kernels
        clear_cache()
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", vhfit.CalibrationWarning)
            fits = vhfit.calibrate_for(vhfit.export.solvers(), curves, **kw)
        if k:
            times.append(time.perf_counter() - t0)
        err = float(next(iter(fits.values())).rmsape)
    return statistics.median(times), err


def rate_free(ds) -> bool:
    """True for a dataset fitted without Prony terms (equilibrium or one rate)."""
    return ds.fit.get("n_prony") in (None, 0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="timed runs of each fit")
    ap.add_argument("--quick-repeat", type=int, default=9,
                    help="timed runs of each quick command")
    ap.add_argument("--no-bytecode", action="store_true",
                    help="keep PYTHONDONTWRITEBYTECODE if set: every run compiles the sources")
    ap.add_argument("--only", default="", help="datasets, comma-separated (bench_real names)")
    ap.add_argument("--no-fit", action="store_true", help="the quick commands only")
    ap.add_argument("--no-quick", action="store_true", help="the fits only")
    ap.add_argument("--data", type=Path, default=None,
                    help="folder of the datasets (default as bench_real.py)")
    ap.add_argument("--base", default=None,
                    help="another checkout's src folder, timed alternately beside this one")
    args = ap.parse_args()
    global KEEP_NO_BYTECODE
    KEEP_NO_BYTECODE = args.no_bytecode
    srcs = (None,) if args.base is None else (None, args.base)
    tags = [""] if args.base is None else ["", " (base)"]
    if not args.no_quick:
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", "pass"], check=True)
        print(f"{'python -c pass':<24} {time.perf_counter() - t0:6.3f} s (one run)")
        for argv in COMMANDS:
            for times, tag in zip(time_command(argv, args.quick_repeat, srcs), tags):
                print(f"{'vhfit ' + ' '.join(argv) + tag:<24} "
                      f"{statistics.median(times):6.3f} s (median of {len(times)})")
    if args.no_fit:
        return
    from bench_real import DATASETS, DEFAULT_DATA

    root = args.data or DEFAULT_DATA
    names = [n for n in args.only.split(",") if n]
    chosen = [d for d in DATASETS if not names or d.name in names]
    print(f"\nvhfit fit, end to end against calibrate in-process (median of {args.repeat} "
          f"after a warm-up run; targets: overhead <= {OVERHEAD_TARGET} s, rate-free "
          f"<= {RATE_FREE_TARGET} s)")
    print(f"{'dataset':<22} {'end to end':>10} {'calibrate':>10} {'overhead':>9}  target")
    for ds in chosen:
        folder = root / ds.folder
        if not all((folder / f).is_file() for f in ds.files):
            print(f"{ds.name:<22} skipped: files not found under {folder}")
            continue
        walls, errs = time_fit(ds, folder, args.repeat, srcs)
        f, err_py = time_calibrate(ds, root, args.repeat)
        for wall, err, tag in zip(walls, errs, tags):
            if not abs(err - err_py) <= 1e-6 * abs(err_py):
                raise SystemExit(f"{ds.name}{tag}: the command's RMSAPE {err:.9g} % is not "
                                 f"the in-process fit's {err_py:.9g} %: not the same fit")
            w = statistics.median(wall)
            over = w - f
            ok = over <= OVERHEAD_TARGET and (not rate_free(ds) or w <= RATE_FREE_TARGET)
            print(f"{(ds.name + tag):<22} {w:9.2f}s {f:9.2f}s {over:8.2f}s  "
                  f"{'met' if ok else 'MISSED'}{' (rate-free)' if rate_free(ds) else ''}",
                  flush=True)


if __name__ == "__main__":
    main()
