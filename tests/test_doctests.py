"""Every module's docstring examples run, and pass.

The modules are discovered by walking the imported ``vhfit`` package (not the source
tree), so the examples are checked against what is installed and new modules are picked
up without a list to maintain. A module that cannot be imported fails its test: nothing
is skipped silently.
"""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import numpy as np
import pytest

import vhfit

MODULES = sorted(
    {"vhfit"} | {m.name for m in pkgutil.walk_packages(vhfit.__path__, prefix="vhfit.")}
)
FLAGS = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS


def test_modules_are_found():
    assert {"vhfit.model", "vhfit.hyperelastic", "vhfit.stability", "vhfit.plot"} <= set(MODULES)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name, tmp_path, monkeypatch):
    module = importlib.import_module(name)
    if name == "vhfit.plot":
        import matplotlib

        matplotlib.use("Agg")  # no display; an example that writes a figure writes it here
    monkeypatch.chdir(tmp_path)  # examples that write files write them here
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    with np.printoptions(legacy=False):
        for test in finder.find(module, name):
            runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {name} failed"
