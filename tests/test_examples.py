"""Every script in examples/ runs to completion (each well under a minute of CPU time)."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest

try:
    import resource
except ImportError:  # pragma: no cover - not POSIX
    resource = None


def child_seconds() -> float:
    """CPU seconds of this process's finished children (wall time where unknown): the
    work a script does, whatever else the machine is running beside it."""
    if resource is None:  # pragma: no cover
        return time.perf_counter()
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime

EXAMPLES = sorted((Path(__file__).resolve().parents[1] / "examples").glob("*.py"))


def test_the_examples_are_there():
    names = {p.name for p in EXAMPLES}
    assert {"calibrate_from_csv.py", "custom_gent.py", "scipy_dropin.py",
            "export_cards.py"} <= names


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.name)
def test_example_runs(script, tmp_path):
    t0 = child_seconds()
    proc = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-4000:]
    # "runs in a few seconds" (the scripts' own words), in CPU time, not in wall time
    # that a loaded machine stretches: a minute is room for a cold numba cache
    assert child_seconds() - t0 < 60
