"""Record the golden calibrations (see cases.py): ``python tests/golden/record.py``."""

from __future__ import annotations

import json
import os
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
    # OpenBLAS (bundled with numpy and scipy, so fixed by their versions) picks its kernels
    # by the CPU unless told otherwise, and numba compiles for the host unless told
    # otherwise: the overrides change the last bits on the same machine. A recording
    # without these keys was made without overrides (None).
    overrides = {"openblas_coretype": os.environ.get("OPENBLAS_CORETYPE") or None,
                 "numba_cpu_name": numba.config.CPU_NAME or None,
                 "numba_cpu_features": numba.config.CPU_FEATURES or None}
    return {"numpy": numpy.__version__, "scipy": scipy.__version__, "numba": numba.__version__,
            "python": platform.python_version(), "machine": platform.machine(),
            "cpu": llvm.get_host_cpu_name(), "cpu_features": features[:16], **overrides}


def same_platform(recorded: dict) -> bool:
    """Whether this process computes as the one that wrote ``recorded`` did (bit for bit):
    the same versions, CPU and kernel overrides (a key the recording lacks counts as
    None)."""
    return all(recorded.get(k) == v for k, v in fingerprint().items())


def main() -> None:
    out = {"fingerprint": fingerprint(), "cases": {}}
    for name in cases.CASES:
        with tempfile.TemporaryDirectory() as d:
            out["cases"][name] = cases.run(name, Path(d))
        print(name, "recorded", flush=True)
    (HERE / "golden.json").write_text(json.dumps(out, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
