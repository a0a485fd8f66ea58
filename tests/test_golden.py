"""Golden calibrations: the outputs recorded before a refactoring, compared bit for bit.

The cases (``tests/golden/cases.py``) cover the separable and full searches, the
free/semifree/fixed τ strategies, N = 1..5 and ``n_prony="auto"``, polish on and off,
checkpoint and resume, two workers, constant-rate and time histories, three laws, a
weighted alternative objective, and the command line's results.json, summary,
fitted curves and solver cards. A change of any recorded number is a change of
behaviour: it needs its own commit, its evidence, and a new recording
(``python tests/golden/record.py``).

On another platform or other numpy/scipy/numba versions floating-point results may
differ in the last bits and a search then follows another path: there the errors
are compared to 1e-3 relative, not bit for bit.
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
from record import fingerprint  # noqa: E402

GOLDEN = json.loads((HERE / "golden.json").read_text())
EXACT = GOLDEN["fingerprint"] == fingerprint()


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
