"""End-to-end time of the command line's quick commands, each in a fresh process.

``vhfit --version``, ``vhfit --help`` and ``vhfit models`` load only what they print
(target: 0.3 s on a quiet machine, of which the interpreter's own start is ~0.1 s).
Run: ``PYTHONPATH=src python benchmarks/bench_cli.py [--repeat 5]``; prints the median.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time

COMMANDS = (["--version"], ["--help"], ["models"])


def time_command(argv: list[str], repeat: int) -> list[float]:
    """Wall times of ``python -m vhfit ARGV`` in ``repeat`` fresh processes."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "vhfit", *argv], check=True,
                       stdout=subprocess.DEVNULL)
        times.append(time.perf_counter() - t0)
    return times


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", "pass"], check=True)
    print(f"{'python -c pass':<24} {time.perf_counter() - t0:6.3f} s (one run)")
    for argv in COMMANDS:
        times = time_command(argv, args.repeat)
        print(f"{'vhfit ' + ' '.join(argv):<24} {statistics.median(times):6.3f} s "
              f"(median of {len(times)})")


if __name__ == "__main__":
    main()
