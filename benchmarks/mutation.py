"""Mutation benchmark: plant small bugs one at a time and check that the tests catch them.

Each mutant of :mod:`mutants` (this directory) replaces one exact snippet of one file of
``src/vhfit`` by a realistic slip (a sign, an index, a swapped constant, a disabled
check, a moved threshold, an ignored tolerance). For every mutant the runner copies
``src/`` to a temporary directory, applies the replacement there, and runs the mutant's
relevant tests against the copy (``PYTHONPATH=<tmp>/src``). The working tree is never
modified.

A mutant is *killed* when the tests fail, *survived* when they pass, *equivalent* when
the list says why no test can tell it from the original (it is still run, and counts
as killed if a test does kill it), and an *error* when its snippet is not found exactly
once (the list must follow the code) or its tests time out.

Usage::

    python benchmarks/mutation.py                 # every mutant, kill table, kill rate
    python benchmarks/mutation.py --list          # names, files and descriptions
    python benchmarks/mutation.py --only NAME ... # a subset (names or fnmatch patterns)
    python benchmarks/mutation.py --jobs 2        # mutants in parallel
    python benchmarks/mutation.py --since REV     # mutants of files changed since a commit,
                                                  # kill rates per file

The exit status is 0 when the kill rate reaches ``--target`` (default 0.9) and no
mutant is in error, 1 otherwise, 2 when the original code fails its tests.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import contextlib
import fnmatch
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))

from mutants import MUTANTS, Mutant  # noqa: E402

PYTEST = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider",
          "--no-header", "-o", "addopts=", "-m", "not slow", "-rfE"]


def check_list(mutants: list[Mutant]) -> list[str]:
    """Problems of the list itself: duplicate names, unknown test files."""
    out, seen = [], set()
    for m in mutants:
        if m.name in seen:
            out.append(f"{m.name}: duplicate name")
        seen.add(m.name)
        for t in m.tests:
            path = ROOT / t.split("::")[0]
            if not path.is_file():
                out.append(f"{m.name}: test file {t} not found")
            elif "::" in t:  # a test function, possibly with parameters
                func = t.split("::")[1].split("[")[0]
                if f"def {func}(" not in path.read_text(encoding="utf-8"):
                    out.append(f"{m.name}: test {t} not found")
        if not m.tests:
            out.append(f"{m.name}: no tests")
    return out


def apply(src_root: Path, m: Mutant) -> str | None:
    """Apply ``m`` to the copy under ``src_root``; a message when its snippet is not unique."""
    path = src_root / m.file
    text = path.read_text(encoding="utf-8")
    n = text.count(m.original)
    if n != 1:
        return f"snippet found {n} times in {m.file} (the list must follow the code)"
    path.write_text(text.replace(m.original, m.replacement), encoding="utf-8")
    return None


def run_tests(src: Path, tests: tuple[str, ...], timeout: float, extra: tuple[str, ...] = ()):
    """(returncode or None on timeout, last lines of output) of pytest on ``tests``."""
    env = dict(os.environ, PYTHONPATH=str(src))
    env.pop("PYTEST_ADDOPTS", None)
    cmd = PYTEST + list(extra) + list(tests)
    # its own session: a timed-out run is ended with every process it started (a test's
    # forked children among them), not pytest alone
    with subprocess.Popen(cmd, cwd=ROOT, env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, start_new_session=True) as p:
        try:
            out, _ = p.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            with contextlib.suppress(ProcessLookupError):
                if hasattr(os, "killpg"):
                    os.killpg(p.pid, signal.SIGKILL)
                else:  # no process groups here: pytest alone
                    p.kill()
            p.communicate()
            return None, "timeout"
    lines = out.strip().splitlines()
    return p.returncode, "\n".join(lines[-15:])


def copy_src(dst: Path) -> Path:
    """A copy of the tree's ``src`` (with mtimes, so numba's on-disk cache stays valid)."""
    shutil.copytree(ROOT / "src", dst / "src", ignore=shutil.ignore_patterns("*.egg-info"))
    return dst / "src"


def run_mutant(m: Mutant, base: Path, work: Path, timeout: float) -> tuple[str, float, str]:
    """(status, seconds, detail) of one mutant."""
    t = time.perf_counter()
    d = Path(tempfile.mkdtemp(prefix=m.name + "-", dir=work))
    try:
        shutil.copytree(base, d / "src")
        err = apply(d / "src", m)
        if err:
            return "error", time.perf_counter() - t, err
        rc, out = run_tests(d / "src", m.tests, timeout)
    finally:
        shutil.rmtree(d, ignore_errors=True)
    dt = time.perf_counter() - t
    if rc is None:
        return "error", dt, f"timeout after {timeout:g} s"
    if rc == 0:
        return ("equivalent" if m.equivalent else "survived"), dt, out
    if rc in (1,):  # tests failed: the mutant is caught, by the first FAILED test
        failed = [ln for ln in out.splitlines() if ln.startswith(("FAILED", "ERROR"))]
        return "killed", dt, (failed or out.splitlines() or [""])[0]
    # 2: interrupted/collection error (e.g. an import fails): also a catch, but say so
    return "killed", dt, f"pytest exit {rc}: " + (out.splitlines()[-1] if out else "")


def module_of(m: Mutant, by_file: bool = False) -> str:
    p = m.file.removeprefix("vhfit/").removesuffix(".py")
    return p if by_file or "/" not in p else p.split("/")[0] + "/"


def changed_since(rev: str) -> set[str]:
    """The files under ``src/`` changed since the git revision ``rev`` (relative to src/)."""
    out = subprocess.run(["git", "diff", "--name-only", rev, "--", "src"], cwd=ROOT,
                         capture_output=True, text=True, check=True).stdout
    return {f.removeprefix("src/") for f in out.split()}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", nargs="+", metavar="NAME",
                    help="run only these mutants (names or fnmatch patterns)")
    ap.add_argument("--list", action="store_true", help="list the mutants and exit")
    ap.add_argument("--jobs", type=int, default=1, help="mutants run in parallel (default 1)")
    ap.add_argument("--timeout", type=float, default=300.0,
                    help="seconds per mutant's test run (default 300)")
    ap.add_argument("--target", type=float, default=0.9, help="kill rate to reach (default 0.9)")
    ap.add_argument("--verbose", "-v", action="store_true",
                    help="also print the test that killed each mutant")
    ap.add_argument("--since", metavar="REV",
                    help="only the mutants of files changed since this git revision (e.g. "
                    "the last release), with kill rates per file")
    args = ap.parse_args(argv)

    problems = check_list(MUTANTS)
    if problems:
        print("mutant list is inconsistent:\n  " + "\n  ".join(problems))
        return 1
    chosen = MUTANTS
    if args.only:
        chosen = [m for m in MUTANTS if any(fnmatch.fnmatchcase(m.name, p) for p in args.only)]
        if not chosen:
            print(f"--only {args.only}: no such mutant (see --list)")
            return 1
    if args.since:
        changed = changed_since(args.since)
        chosen = [m for m in chosen if m.file in changed]
        bare = sorted(f for f in changed if f.endswith(".py")
                      and not any(m.file == f for m in MUTANTS))
        if bare:  # changed code that no mutant covers: the rate says nothing of it
            print(f"changed since {args.since} without a mutant: {', '.join(bare)}")
    if args.list:
        for m in chosen:
            eq = "  [equivalent]" if m.equivalent else ""
            print(f"{m.name:34s} {m.file:34s} {m.description}{eq}")
        print(f"{len(chosen)} mutants")
        return 0

    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="vhfit-mutation-") as tmp:
        work = Path(tmp)
        base = copy_src(work / "base")
        # baseline: the original code must pass every test file the chosen mutants use
        tests = tuple(sorted({t for m in chosen for t in m.tests}))
        print(f"baseline: {len(tests)} test targets on the unmutated copy ...", flush=True)
        rc, out = run_tests(base, tests, args.timeout * 4)
        if rc != 0:
            print(out)
            print("baseline FAILED: the original code does not pass the mutants' tests; "
                  "fix that first")
            return 2
        print(f"baseline passed in {time.perf_counter() - t0:.0f} s", flush=True)
        results = {}
        with concurrent.futures.ThreadPoolExecutor(max(1, args.jobs)) as ex:
            futs = {ex.submit(run_mutant, m, base, work, args.timeout): m for m in chosen}
            for f in concurrent.futures.as_completed(futs):
                m = futs[f]
                status, dt, detail = f.result()
                results[m.name] = (status, dt, detail)
                print(f"  {status:10s} {dt:6.1f} s  {m.name}", flush=True)
                if status in ("survived", "error") or args.verbose:
                    print("    " + detail.replace("\n", "\n    "))
    return report(chosen, results, time.perf_counter() - t0, args.target, bool(args.since))


def report(chosen, results, total, target, by_file: bool = False) -> int:
    print()
    print(f"{'mutant':34s} {'module':22s} {'status':10s} {'time':>6s}")
    for m in chosen:
        s, dt, _ = results[m.name]
        print(f"{m.name:34s} {module_of(m, by_file):22s} {s:10s} {dt:6.1f}")
    print()
    mods: dict[str, dict[str, int]] = {}
    for m in chosen:
        row = mods.setdefault(module_of(m, by_file), {"killed": 0, "survived": 0, "equivalent": 0,
                                              "error": 0})
        row[results[m.name][0]] += 1
    print(f"{'module':26s} {'killed':>7s} {'survived':>9s} {'equivalent':>11s} {'error':>6s}"
          f" {'rate':>7s}")
    for mod, r in sorted(mods.items()):
        k = r["killed"] + r["survived"] + r["error"]
        print(f"{mod:26s} {r['killed']:7d} {r['survived']:9d} {r['equivalent']:11d} "
              f"{r['error']:6d} {r['killed'] / k if k else 1.0:7.1%}")
    counts = {k: sum(r[k] for r in mods.values()) for k in
              ("killed", "survived", "equivalent", "error")}
    n = len(chosen)
    # equivalent mutants (no test can tell them from the original) are left out of the rate
    scored = n - counts["equivalent"]
    rate = counts["killed"] / scored if scored else 0.0
    print(f"\n{n} mutants: {counts['killed']} killed, {counts['survived']} survived, "
          f"{counts['equivalent']} equivalent, {counts['error']} error")
    print(f"kill rate {rate:.1%} (killed / non-equivalent mutants; target {target:.0%})")
    print(f"total time {total:.0f} s")
    return 0 if rate >= target and not counts["error"] else 1


if __name__ == "__main__":
    sys.exit(main())
