"""The shape of the package, read from its source with ``ast`` (nothing is imported but
the solver registry, by the last check).

* private names: an underscore name (``from X import _y``, ``X._y`` on an imported vhfit
  module, or a private module ``X._m`` itself) is used only where ``X`` is a private
  module (``_x.py``) — or, for a private module, the package — of the importer's own
  package;
* no import cycle among vhfit's modules (function-local imports included);
* layers point one way: infrastructure → physics → data → objective → optimize →
  calibration → interfaces; nothing imports a module of a higher layer, and every
  module has a layer;
* a solver is named only by its own module: no source file outside ``export/<solver>.py``
  and ``formulations.py`` holds a registered solver's name, alias or label;

Module and function sizes are not limited: modules are split along concepts, not line
counts.
"""

from __future__ import annotations

import ast
import importlib
import pkgutil
import re
from functools import cache
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src"
TOP = "vhfit"

#: Layers from the bottom up; a module belongs to the first layer one of whose names is
#: the module or a package containing it. A module may import its own layer and those
#: below it, never one above.
LAYERS: list[tuple[str, tuple[str, ...]]] = [
    ("infrastructure", ("vhfit._io", "vhfit._pools", "vhfit._version", "vhfit._blas",
                        "vhfit._nnls", "vhfit._words")),
    ("physics", ("vhfit.hyperelastic", "vhfit.viscoelastic", "vhfit.history", "vhfit.model",
                 "vhfit._batch", "vhfit.modes", "vhfit._plans", "vhfit.formulations",
                 "vhfit._linear", "vhfit._kernels", "vhfit.stability", "vhfit._derivatives",
                 "vhfit._kirchhoff", "vhfit._deformation", "vhfit._fixed",
                 "vhfit.viscous")),
    ("data", ("vhfit.data", "vhfit.datasets",
              "vhfit.tts")),
    ("objective", ("vhfit.objective", "vhfit.diagnostics",
                   "vhfit.spectrum")),
    ("optimize", ("vhfit.optimize",)),
    ("calibration", ("vhfit.calibration",)),
    ("interfaces", ("vhfit.parallel", "vhfit.comparison", "vhfit.export", "vhfit.plot",
                    "vhfit.report", "vhfit.cli", "vhfit._warm", "vhfit._preload",
                    "vhfit.__main__", "vhfit")),
]


# ------------------------------------------------------------------ the source tree
@cache
def modules() -> dict[str, Path]:
    """Dotted name -> file of every module of the package (a package is its __init__)."""
    out = {}
    for path in sorted((SRC / TOP).rglob("*.py")):
        parts = list(path.relative_to(SRC).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


def is_package(name: str) -> bool:
    return modules()[name].name == "__init__.py"


def package_of(name: str) -> str:
    """The package whose private modules ``name`` may use: itself for a package."""
    return name if is_package(name) else name.rpartition(".")[0]


def is_private_module(name: str) -> bool:
    last = name.rpartition(".")[2]
    return name in modules() and last.startswith("_") and not last.startswith("__")


def is_private_name(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


@cache
def tree(name: str) -> ast.Module:
    return ast.parse(modules()[name].read_text(encoding="utf-8"), str(modules()[name]))


def absolute(importer: str, module: str | None, level: int) -> str:
    """The dotted name ``from <level dots><module> import ...`` refers to."""
    if not level:
        return module or ""
    base = package_of(importer).split(".")
    base = base[: len(base) - (level - 1)]
    return ".".join(base + ([module] if module else []))


def existing(name: str) -> str | None:
    """``name`` if it is a vhfit module, else its longest prefix that is one."""
    parts = name.split(".")
    while parts:
        if ".".join(parts) in modules():
            return ".".join(parts)
        parts.pop()
    return None


# ------------------------------------------------------------------ the imports
class Use:
    """One use of a vhfit module by another: target, the private thing used, where."""

    def __init__(self, target: str, line: int, private: str | None = None,
                 owner: str | None = None):
        self.target, self.line = target, line
        self.private, self.owner = private, owner  # underscore name and the module it is in


@cache
def uses(name: str) -> tuple[Use, ...]:
    """Every import (anywhere in the module) and every ``module._attr`` of a vhfit module."""
    out: list[Use] = []
    bound: dict[str, str] = {}  # local name -> vhfit module it is bound to (anywhere)
    for node in ast.walk(tree(name)):
        if isinstance(node, ast.Import):
            for alias in node.names:
                target = existing(alias.name)
                if target is None:
                    continue
                out.extend(_module_uses(target, node.lineno))
                if alias.asname:
                    bound[alias.asname] = target
                else:
                    bound[alias.name.split(".")[0]] = alias.name.split(".")[0]
        elif isinstance(node, ast.ImportFrom):
            base = absolute(name, node.module, node.level)
            if existing(base) is None:
                continue
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                if sub in modules():  # a module imported by name
                    out.extend(_module_uses(sub, node.lineno))
                    bound[alias.asname or alias.name] = sub
                else:
                    target = existing(base)
                    out.extend(_module_uses(target, node.lineno))
                    if is_private_name(alias.name):
                        out.append(Use(target, node.lineno, alias.name, target))
        elif isinstance(node, ast.Call) and _is_import_call(node):
            target = existing(node.args[0].value)
            if target is not None:
                out.extend(_module_uses(target, node.lineno))
    for node in ast.walk(tree(name)):
        if isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Load):
            out.extend(_attribute_uses(node, bound))
    return tuple(out)


def _module_uses(target: str, line: int) -> list[Use]:
    """Importing (from) module ``target``: itself, and each private module on its path."""
    out = [Use(target, line)]
    parts = target.split(".")
    for k in range(2, len(parts) + 1):
        mod = ".".join(parts[:k])
        if is_private_module(mod):
            out.append(Use(mod, line, parts[k - 1], ".".join(parts[: k - 1])))
    return out


def _is_import_call(node: ast.Call) -> bool:
    f = node.func
    fname = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", None)
    return fname in ("import_module", "__import__") and bool(node.args) and isinstance(
        node.args[0], ast.Constant) and isinstance(node.args[0].value, str)


def _attribute_uses(node: ast.Attribute, bound: dict[str, str]) -> list[Use]:
    """``m.a.b`` where ``m`` names a vhfit module: the private modules/names it reaches.

    Only the outermost attribute of a chain is analysed (its inner parts are the same
    chain seen from further in).
    """
    chain = []
    cur: ast.AST = node
    while isinstance(cur, ast.Attribute):
        chain.append(cur.attr)
        cur = cur.value
    if not isinstance(cur, ast.Name) or cur.id not in bound:
        return []
    if getattr(node, "_inner", False):
        return []
    inner = node.value
    while isinstance(inner, ast.Attribute):
        inner._inner = True  # type: ignore[attr-defined]
        inner = inner.value
    out = []
    mod = bound[cur.id]
    for attr in reversed(chain):
        sub = f"{mod}.{attr}"
        if sub in modules():
            if is_private_name(attr):
                out.append(Use(sub, node.lineno, attr, mod))
            mod = sub
            continue
        if is_private_name(attr):
            out.append(Use(mod, node.lineno, attr, mod))
        break
    return out


# ------------------------------------------------------------------ the checks
def private_use_violations() -> list[str]:
    """Private modules: of the own package, or of the top package (shared infrastructure,
    public names only); underscore names: from a private module of the own package."""
    bad = []
    for name in modules():
        own = package_of(name)
        for u in uses(name):
            if u.private is None:
                continue
            if is_private_module(f"{u.owner}.{u.private}"):
                allowed = u.owner in (own, TOP)
            else:
                allowed = is_private_module(u.owner) and package_of(u.owner) == own
            if not allowed:
                bad.append(f"{name}:{u.line} uses {u.owner}.{u.private}")
    return bad


def import_graph() -> dict[str, set[str]]:
    return {name: {u.target for u in uses(name) if u.target != name} for name in modules()}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """One cycle (as a path a -> ... -> a) per strongly connected component."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    comps: list[list[str]] = []

    def visit(v: str) -> None:  # Tarjan's algorithm
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                comps.append(comp)

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return [_cycle_in(graph, set(c)) for c in comps]


def _cycle_in(graph: dict[str, set[str]], comp: set[str]) -> list[str]:
    start = min(comp)
    prev = {start: None}
    frontier = [start]
    while frontier:  # breadth first: the shortest way back to start
        nxt = []
        for v in frontier:
            for w in sorted(graph[v] & comp):
                if w == start:
                    path = [v]
                    while prev[path[-1]] is not None:
                        path.append(prev[path[-1]])
                    return [start, *reversed(path[:-1]), start]
                if w not in prev:
                    prev[w] = v
                    nxt.append(w)
        frontier = nxt
    return sorted(comp)  # pragma: no cover - a component always has a cycle


def layer_of(name: str) -> int | None:
    best, depth = None, -1
    for k, (_, names) in enumerate(LAYERS):
        for prefix in names:
            if (name == prefix or name.startswith(prefix + ".")) and prefix.count(".") > depth:
                best, depth = k, prefix.count(".")
    return best


def layer_violations() -> list[str]:
    bad = []
    for name in modules():
        mine = layer_of(name)
        if mine is None:
            bad.append(f"{name} has no layer: add it to LAYERS in tests/test_architecture.py")
            continue
        for u in uses(name):
            theirs = layer_of(u.target)
            if theirs is not None and theirs > mine:
                bad.append(f"{name}:{u.line} ({LAYERS[mine][0]}) imports {u.target} "
                           f"({LAYERS[theirs][0]})")
    return sorted(set(bad))


def report(problems: list[str]) -> str:
    return "\n  " + "\n  ".join(problems)


# ------------------------------------------------------------------ the tests
def test_the_source_tree_is_found():
    assert {"vhfit", "vhfit.model", "vhfit.optimize"} <= set(modules())


def test_underscore_names_are_used_only_from_private_modules_of_the_own_package():
    bad = private_use_violations()
    assert not bad, "private names used across package boundaries:" + report(bad)


def test_there_is_no_import_cycle():
    found = cycles(import_graph())
    assert not found, "import cycles:" + report([" -> ".join(c) for c in found])


def test_layers_point_one_way():
    bad = layer_violations()
    assert not bad, "imports against the layers:" + report(bad)


# ------------------------------------------------------------------ the checker itself
def _fake_tree(tmp_path: Path, files: dict[str, str]) -> None:
    for rel, text in files.items():
        p = tmp_path / "vhfit" / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    globals()["SRC"] = tmp_path
    for f in (modules, tree, uses):
        f.cache_clear()


def test_the_checks_find_what_they_look_for(tmp_path):
    saved = SRC
    try:
        _fake_tree(tmp_path, {
            "__init__.py": "",
            "_kernels.py": "def _fast(): pass\n",
            "model.py": "from vhfit._kernels import _fast\nfrom vhfit import data\n",
            "data/__init__.py": "from vhfit.data._table import _x\nfrom . import _table\n",
            "data/_table.py": "from vhfit.model import ViscoHyperelastic\n_x = 1\n",
            "objective.py": ("import vhfit.data._table as t\nimport vhfit.model\n"
                             "from vhfit._kernels import Kernel\n"
                             "from vhfit.data._table import Table\n"
                             "def f():\n    from vhfit.data import _table\n"
                             "    return vhfit.model._y, t._x\n"),
            "optimize/__init__.py": "from vhfit.optimize._de import Solver\n",
            "optimize/_stop.py": "from vhfit.optimize._de import _state\nimport vhfit._io\n",
            "_io.py": "",
            "optimize/_de.py": "",
            "plot.py": "def g():\n    import vhfit.objective\n",
            "stability.py": "import importlib\nimportlib.import_module('vhfit.plot')\n",
        })
        assert sorted(private_use_violations()) == [
            "vhfit.objective:1 uses vhfit.data._table",
            "vhfit.objective:4 uses vhfit.data._table",
            "vhfit.objective:6 uses vhfit.data._table",
            "vhfit.objective:7 uses vhfit.data._table._x",
            "vhfit.objective:7 uses vhfit.model._y",
        ]
        assert cycles(import_graph()) == [
            ["vhfit.data", "vhfit.data._table", "vhfit.model", "vhfit.data"]]
        assert "vhfit.model:2 (physics) imports vhfit.data (data)" in layer_violations()
        assert "vhfit.stability:2 (physics) imports vhfit.plot (interfaces)" in (
            layer_violations())
    finally:
        globals()["SRC"] = saved
        for f in (modules, tree, uses):
            f.cache_clear()


# ------------------------------------------------- a solver is named by its module only
def shipped_solvers() -> dict[Path, object]:
    """Source file (relative to the package: ``export/NAME.py``, the same for a checkout
    and an installed copy) -> record of each solver module of vhfit.export (a public
    module that defines a registered ``RECORD``), found as the package finds them."""
    import vhfit
    import vhfit.export as export

    top = Path(vhfit.__file__).resolve().parent

    out = {}
    for info in pkgutil.iter_modules(export.__path__):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"vhfit.export.{info.name}")
        record = getattr(module, "RECORD", None)
        if isinstance(record, export.Solver):
            assert export.get_solver(record.name) is record, f"{info.name}: not registered"
            out[Path(module.__file__).resolve().relative_to(top)] = record
    return out


def solver_pattern(records) -> re.Pattern:
    """Any name, alias or label of the records (also with ``-`` written ``_``, `` `` or
    nothing), case-insensitive, not inside a longer word (``_`` separates words:
    ``to_NAME`` counts)."""
    words = set()
    for rec in records:
        for w in (rec.name, *rec.aliases, rec.label):
            w = w.lower()
            words |= {w, w.replace("-", "_"), w.replace("-", " "), w.replace("-", "")}
    alternatives = "|".join(sorted(map(re.escape, words), key=len, reverse=True))
    return re.compile(rf"(?<![a-z0-9])(?:{alternatives})(?![a-z0-9])", re.IGNORECASE)


def solver_mentions(allowed: set[Path], pattern: re.Pattern, root: Path = SRC) -> list[str]:
    """``file:line: text`` of every line of a source file under ``root/vhfit`` outside
    ``allowed`` (paths relative to ``root/vhfit``) that names a solver."""
    hits = []
    for path in sorted((root / TOP).rglob("*.py")):
        if path.relative_to(root / TOP) in allowed:
            continue
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if pattern.search(line):
                hits.append(f"{path.relative_to(root)}:{i}: {line.strip()}")
    return hits


def test_only_a_solvers_own_module_names_it():
    """Adding a solver is adding its module: no other source file names one.

    A grep test (a property of the text, not of behaviour), so it has no mutant in
    benchmarks/mutants.py; the test below shows that it finds a name put back.
    """
    shipped = shipped_solvers()
    assert len(shipped) >= 3, "the solver modules of vhfit.export are not found"
    # the flow registry keeps each flow's LAW= word of the solver that defines the
    # framework, as formulations.py keeps the solvers' conventions
    allowed = {*shipped, Path("formulations.py"), Path("viscous/flows.py")}
    hits = solver_mentions(allowed, solver_pattern(shipped.values()))
    assert not hits, ("source files outside the solver modules name a solver (read it from "
                      "the registry, vhfit.export.solvers(), or word it generically):\n"
                      + "\n".join(hits))


def test_the_solver_name_check_finds_a_name(tmp_path):
    """Guards the check above: each kind of mention is found, ordinary words are not, and
    a name is reported in any file but the allowed ones."""
    shipped = shipped_solvers()
    pattern = solver_pattern(shipped.values())
    for rec in shipped.values():
        for text in (f"to_{rec.name}(model)", f"the {rec.label} card", f"'{rec.name}'",
                     f"{rec.label.upper()}'s law", *(f"--for {a}" for a in rec.aliases)):
            assert pattern.search(text), text
    for text in ("dynamic analyses", "the polynomial form", "ansatz", "abacus"):
        assert not pattern.search(text), text
    rec = next(iter(shipped.values()))
    (tmp_path / TOP / "export").mkdir(parents=True)
    own = tmp_path / TOP / "export" / f"{rec.name}.py"
    other = tmp_path / TOP / "model.py"
    own.write_text(f'"""The {rec.label} card."""\n')
    other.write_text(f'"""Stress."""\n\nDEFAULT = "{rec.name}"\n')
    assert solver_mentions({own.relative_to(tmp_path / TOP)}, pattern, tmp_path) == [
        f"{TOP}/model.py:3: DEFAULT = \"{rec.name}\""]
