"""Read every CSV of the shared real datasets with vhfit.read_csv and report (not a test).

Run:  python benchmarks/check_real_data.py   (VHFIT_DATA overrides ../shared/data)
"""

import glob
import os
import time
import warnings

from vhfit.data import DataError, read_csv

ROOT = os.environ.get(
    "VHFIT_DATA",
    os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data"),
)


def main() -> None:
    root = os.path.normpath(ROOT)
    if not os.path.isdir(root):
        raise SystemExit(f"no datasets at {root}: set VHFIT_DATA to their directory")
    files = sorted(
        f for f in glob.glob(f"{root}/**/*.csv", recursive=True) if not f.endswith("index.csv")
    )
    ok = fail = 0
    for f in files:
        rel = f[len(root) + 1:]
        t0 = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                cs = read_csv(f)
            except DataError as e:
                fail += 1
                print(f"FAIL {rel}\n     {e}")
                continue
            except Exception as e:  # a bug: anything but DataError
                fail += 1
                print(f"BUG  {rel}\n     {type(e).__name__}: {e}")
                continue
        ok += 1
        dt = time.perf_counter() - t0
        for c in cs:
            h = c.history
            print(f"ok   {rel}: {c!r}  path {c.strain.size}->{h.time.size} pts, "
                  f"target {c.target_stress.min():.4g}..{c.target_stress.max():.4g} MPa "
                  f"[{dt * 1e3:.0f} ms]")
        for x in caught:
            print(f"     warning: {x.message}")
    print(f"\n{ok} files read, {fail} failed")


if __name__ == "__main__":
    main()
