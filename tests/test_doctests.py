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
import sys

import numpy as np
import pytest

import vhfit

MODULES = sorted(
    {"vhfit"} | {m.name for m in pkgutil.walk_packages(vhfit.__path__, prefix="vhfit.")}
)
FLAGS = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS


def test_modules_are_found():
    assert {"vhfit.model", "vhfit.hyperelastic", "vhfit.stability", "vhfit.plot"} <= set(MODULES)


@pytest.fixture
def registries_restored(request):
    """Undo what examples register (models, τ strategies, ...) once they have run.

    Every module-level dict of the package is a potential registry; each is restored in
    place, so other tests (which may run the same examples) start from the same state.
    """
    try:  # the module under test first, so that its own registries are saved too
        importlib.import_module(request.node.callspec.params["name"])
    except Exception:  # noqa: BLE001 - the test itself reports the failed import
        pass
    saved, seen = [], set()
    for mod in list(sys.modules.values()):
        if getattr(mod, "__name__", "").split(".")[0] != "vhfit":
            continue
        for key, value in vars(mod).items():
            if type(value) is dict and not key.startswith("__") and id(value) not in seen:
                seen.add(id(value))
                saved.append((value, dict(value)))
    yield
    for value, copy in saved:
        value.clear()
        value.update(copy)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name, tmp_path, monkeypatch, registries_restored):
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


#: Documentation pages whose examples run as written (the extension points among them).
DOC_PAGES = ["architecture.md", "optimizer.md"]
DOCS = __import__("pathlib").Path(__file__).resolve().parents[1] / "docs"


@pytest.mark.parametrize("name", DOC_PAGES)
def test_documentation_examples(name, tmp_path, monkeypatch, registries_restored):
    text = (DOCS / name).read_text(encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    test = doctest.DocTestParser().get_doctest(text, {}, name, str(DOCS / name), 0)
    assert test.examples, f"docs/{name} has no examples"
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    with np.printoptions(legacy=False):
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {name} failed"
