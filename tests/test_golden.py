"""Golden calibrations: the outputs recorded before a refactoring, compared bit for bit.

The cases (``tests/golden/cases.py``) cover the separable and full searches, the
free/semifree/fixed τ strategies, N = 1..5 and ``n_prony="auto"``, polish on and off,
checkpoint and resume, two workers, constant-rate and time histories, three laws, a
weighted alternative objective, and the command line's results.json, summary,
fitted curves and solver cards. A change of any recorded number is a change of
behaviour: it needs its own commit, its evidence, and a new recording
(``python tests/golden/record.py``).

Bit for bit only on the platform of the recording (``record.fingerprint``: numpy, scipy,
numba and Python versions, the CPU, and the overrides of OpenBLAS's kernel and numba's
target CPU). Elsewhere floating-point results differ in the last bits (another BLAS
kernel, another compiled instruction set) and a seeded search then follows another path:
its parameters, generation counts and file texts may differ, so only what every path
must reach is compared, each fit's error (RMSAPE), to 1e-3 relative, or 1e-9 absolute
for an exact recovery's error at round-off level (1e-12 %, which moved by half its value
between OpenBLAS's SkylakeX and Haswell kernels). The other errors moved by at most
1.2e-7 relative between the SkylakeX, Haswell and Sandybridge kernels and numba's generic
target, so 1e-3 fails a fit that got worse or better while any kernel passes.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent / "golden"
sys.path.insert(0, str(HERE))

import cases  # noqa: E402
from record import same_platform  # noqa: E402

GOLDEN = json.loads((HERE / "golden.json").read_text())
EXACT = same_platform(GOLDEN["fingerprint"])


def _diff(a, b, path="") -> list[str]:
    """Paths where a and b differ (floats compared exactly; NaN equals NaN)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = [f"{path}/{k}: missing" for k in a.keys() ^ b.keys()]
        for k in a.keys() & b.keys():
            out += _diff(a[k], b[k], f"{path}/{k}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path}: length {len(a)} != {len(b)}"]
        out = []
        for i, (x, y) in enumerate(zip(a, b)):
            out += _diff(x, y, f"{path}[{i}]")
        return out
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return []
    return [] if a == b and type(a) is type(b) else [f"{path}: {a!r} != {b!r}"]


def _errors(rec) -> list[float]:
    if "results" in rec:
        return [rec["results"]["rmsape"]]
    if "resumed" in rec:
        return [rec["cut"]["rmsape"], rec["resumed"]["rmsape"]]
    return [rec["rmsape"]]


@pytest.mark.parametrize("name", sorted(cases.CASES))
def test_golden_calibration_unchanged(name, tmp_path):
    got = json.loads(json.dumps(cases.run(name, tmp_path)))
    want = GOLDEN["cases"][name]
    if EXACT:
        diff = _diff(want, got)
        assert not diff, f"{len(diff)} differences, first: " + "; ".join(diff[:5])
    else:
        for w, g in zip(_errors(want), _errors(got)):
            assert g == pytest.approx(w, rel=1e-3, abs=1e-9)


def test_golden_file_covers_every_case():
    assert sorted(GOLDEN["cases"]) == sorted(cases.CASES)


def test_a_kernel_override_is_another_platform(monkeypatch):
    """OPENBLAS_CORETYPE changes the last bits on the same machine: bit for bit then no
    longer holds, and an older recording without the override keys means none."""
    from record import fingerprint

    monkeypatch.delenv("OPENBLAS_CORETYPE", raising=False)
    here = fingerprint()
    old = {k: v for k, v in here.items() if k != "openblas_coretype"}
    assert same_platform(here) and same_platform(old)
    monkeypatch.setenv("OPENBLAS_CORETYPE", "Zen")
    assert not same_platform(here) and not same_platform(old)
