"""Every public name of vhfit is exercised by at least one test.

The public names are those in the ``__all__`` of vhfit and of each of its public modules
and subpackages (no path component starting with ``_``). A name counts as tested when it
appears as a word in a test file other than this one; a test that merely imports it
would pass this check, so the list of names added here was reviewed by hand (each has a
test of its behaviour in the test file of its module).
"""

from __future__ import annotations

import importlib
import pkgutil
import re
from pathlib import Path

import pytest

import vhfit

TESTS = Path(__file__).resolve().parent


def public_modules() -> list[str]:
    """vhfit and every module below it whose dotted path has no private component."""
    names = ["vhfit"] + [m.name for m in pkgutil.walk_packages(vhfit.__path__, "vhfit.")]
    return [n for n in names if not any(part.startswith("_") for part in n.split("."))]


def public_names() -> dict[str, list[str]]:
    """Each name of an ``__all__`` -> the modules that list it."""
    out: dict[str, list[str]] = {}
    for module in public_modules():
        for name in getattr(importlib.import_module(module), "__all__", ()):
            out.setdefault(name, []).append(module)
    return out


def test_the_public_modules_are_found():
    """The walk reaches the subpackages and skips private modules (guards the check below)."""
    modules = public_modules()
    for expected in ("vhfit", "vhfit.optimize", "vhfit.data", "vhfit.cli",
                     "vhfit.calibration", "vhfit.export", "vhfit.export.abaqus",
                     "vhfit.datasets", "vhfit.model"):
        assert expected in modules
    assert not [m for m in modules if "._" in m]
    names = public_names()
    assert len(names) > 100
    assert {"ViscoHyperelastic", "calibrate", "differential_evolution", "Curve"} <= set(names)


def test_every_public_name_appears_in_a_test():
    text = "\n".join(p.read_text(encoding="utf-8") for p in sorted(TESTS.glob("*.py"))
                     if p.name != Path(__file__).name)
    missing = {name: modules for name, modules in public_names().items()
               if not re.search(rf"\b{re.escape(name)}\b", text)}
    assert not missing, f"public names no test refers to: {missing}"


def test_a_lazy_submodule_that_misses_a_dependency_says_which(monkeypatch):
    import importlib

    import vhfit

    real = importlib.import_module

    def fake(name, package=None):
        if name == "vhfit.brokenmod":  # a submodule whose own import needs a missing package
            raise ModuleNotFoundError("No module named 'somedep'", name="somedep")
        return real(name, package)

    monkeypatch.setattr(importlib, "import_module", fake)
    with pytest.raises(ModuleNotFoundError, match="somedep"):
        vhfit.brokenmod  # noqa: B018
    with pytest.raises(AttributeError, match="no attribute 'nosuchname'"):
        vhfit.nosuchname  # noqa: B018


def test_the_fit_loaded_on_demand_brings_the_report_writer():
    # Calibration.report needs vhfit.report's writer; a fresh process that asks only for
    # vhfit.calibrate must have it registered
    import subprocess
    import sys

    code = ("import sys, vhfit; vhfit.calibrate; "
            "print('vhfit.report' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "True"
