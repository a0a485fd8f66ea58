"""SciPy's own test suite for differential evolution, run against vhfit.optimize.

At run time the installed SciPy's ``scipy/optimize/tests/test__differential_evolution.py``
is copied to a temporary directory, its imports of ``differential_evolution`` and
``DifferentialEvolutionSolver`` are pointed at :mod:`vhfit.optimize` (everything else
it imports still comes from SciPy), a guard test is appended that fails unless the
names really are vhfit's, and the file runs under pytest in a subprocess. Every
collected test must pass; nothing is skipped or deselected (SciPy's ``xslow`` test
runs too, which SciPy's own conftest would skip without ``SCIPY_XSLOW=1``).

Nothing from SciPy is committed to this repository.
"""

from __future__ import annotations

import ast
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
import scipy.optimize
from scipy.optimize import OptimizeResult, rosen
from scipy.optimize._differentialevolution import _ConstraintWrapper

import vhfit.optimize as vo

OURS = {"differential_evolution", "DifferentialEvolutionSolver"}
SOURCE_MODULES = {"scipy.optimize", "scipy.optimize._differentialevolution"}

GUARD = '''

def test_vhfit_is_under_test():
    import vhfit.optimize as _vo
    assert differential_evolution is _vo.differential_evolution
    assert DifferentialEvolutionSolver is _vo.DifferentialEvolutionSolver
    assert DifferentialEvolutionSolver.__module__.startswith("vhfit.")
'''

CONFTEST = '''
def pytest_configure(config):
    for name in ("slow", "xslow", "fail_slow", "xfail_on_32bit", "array_api_backends",
                 "skip_xp_backends", "thread_unsafe", "parallel_threads"):
        config.addinivalue_line("markers", f"{name}: SciPy test marker")
'''


def scipy_de_test_file() -> Path:
    return Path(scipy.optimize.__file__).parent / "tests" / "test__differential_evolution.py"


def rewrite(source: str) -> tuple[str, int]:
    """Point the imports of our names at vhfit.optimize; return (source, n rewritten)."""
    tree = ast.parse(source)
    n = 0
    body = []
    for node in tree.body:
        if isinstance(node, ast.ImportFrom) and node.module in SOURCE_MODULES and node.level == 0:
            mine = [a for a in node.names if a.name in OURS]
            rest = [a for a in node.names if a.name not in OURS]
            if mine:
                n += len(mine)
                if rest:
                    body.append(ast.ImportFrom(module=node.module, names=rest, level=0))
                body.append(ast.ImportFrom(module="vhfit.optimize", names=mine, level=0))
                continue
        body.append(node)
    tree.body = body
    return ast.unparse(ast.fix_missing_locations(tree)), n


def count_tests(source: str) -> int:
    """Number of test functions/methods defined in a test module."""
    tree = ast.parse(source)
    return sum(isinstance(node, ast.FunctionDef) and node.name.startswith("test")
               for node in ast.walk(tree))


def test_rewrite_points_only_our_names_at_vhfit():
    src = ("from scipy.optimize._differentialevolution import (DifferentialEvolutionSolver,\n"
           "    _ConstraintWrapper)\n"
           "from scipy.optimize import differential_evolution, OptimizeResult\n"
           "from scipy.optimize import rosen\n")
    out, n = rewrite(src)
    assert n == 2
    ns: dict = {}
    exec(out, ns)
    assert ns["differential_evolution"] is vo.differential_evolution
    assert ns["DifferentialEvolutionSolver"] is vo.DifferentialEvolutionSolver
    assert ns["_ConstraintWrapper"] is _ConstraintWrapper
    assert ns["OptimizeResult"] is OptimizeResult and ns["rosen"] is rosen


def test_scipy_differential_evolution_suite_passes(tmp_path):
    path = scipy_de_test_file()
    if not path.is_file():
        pytest.fail(f"SciPy's DE test suite is not installed at {path}; it is needed to "
                    "prove compatibility (install a SciPy that ships its tests)")
    source = path.read_text(encoding="utf-8")
    rewritten, n = rewrite(source)
    assert n == 2, "expected to rewrite both differential_evolution and the solver class"
    (tmp_path / "test__differential_evolution_vhfit.py").write_text(rewritten + GUARD)
    (tmp_path / "conftest.py").write_text(CONFTEST)
    (tmp_path / "pytest.ini").write_text("[pytest]\nfilterwarnings =\n    error\n")
    expected = count_tests(source) + 1  # + the guard test
    report = tmp_path / "report.xml"
    t0 = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:randomly",
         f"--junitxml={report}", "--rootdir", str(tmp_path), "-c", str(tmp_path / "pytest.ini"),
         str(tmp_path / "test__differential_evolution_vhfit.py")],
        cwd=tmp_path, capture_output=True, text=True, timeout=600)
    elapsed = time.perf_counter() - t0
    tail = (proc.stdout + proc.stderr)[-6000:]
    assert report.is_file(), tail
    suite = ET.parse(report).getroot()
    suite = suite if suite.tag == "testsuite" else suite.find("testsuite")
    tests = int(suite.get("tests"))
    failures, errors = int(suite.get("failures")), int(suite.get("errors"))
    skipped = int(suite.get("skipped"))
    print(f"SciPy DE suite against vhfit.optimize: {tests} tests, {failures} failures, "
          f"{errors} errors, {skipped} skipped, {elapsed:.1f} s")
    assert proc.returncode == 0, tail
    assert failures == 0 and errors == 0, tail
    assert skipped == 0, tail
    assert tests == expected >= 60, (tests, expected, tail)
