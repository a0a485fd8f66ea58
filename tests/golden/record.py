"""Record the golden calibrations (see cases.py): ``python tests/golden/record.py``."""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import cases  # noqa: E402


def fingerprint() -> dict:
    import hashlib
    import platform

    import llvmlite.binding as llvm
    import numba
    import numpy
    import scipy

    # numba compiles for the host CPU: another CPU may round differently
    features = hashlib.sha256(llvm.get_host_cpu_features().flatten().encode()).hexdigest()
    return {"numpy": numpy.__version__, "scipy": scipy.__version__, "numba": numba.__version__,
            "python": platform.python_version(), "machine": platform.machine(),
            "cpu": llvm.get_host_cpu_name(), "cpu_features": features[:16]}


def main() -> None:
    out = {"fingerprint": fingerprint(), "cases": {}}
    for name in cases.CASES:
        with tempfile.TemporaryDirectory() as d:
            out["cases"][name] = cases.run(name, Path(d))
        print(name, "recorded", flush=True)
    (HERE / "golden.json").write_text(json.dumps(out, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
