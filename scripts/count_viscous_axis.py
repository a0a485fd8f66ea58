"""How far the Prony series is the model's skeleton: counts by an AST walk over src/vhfit.

Three counts, docstrings and comments excluded (only code nodes are read):

1. **Modules that name Prony concepts in code**: a ``Name``, ``Attribute``, ``arg`` or
   ``keyword`` whose identifier is a Prony word (:data:`PRONY`: ``n_prony``, ``tau_b``,
   ``g_inf``, ``shape_columns``, ``formulation``, ...), a stride-2 slice from a named
   offset (``x[nh::2]``, ``x[nh + 1::2]``: the ``[G1, tau1, G2, tau2, ...]`` layout read
   by position) or an f-string that builds a Prony parameter name (``f"G{i}"``,
   ``f"tau{i + 1}"``). Modules under ``viscous/``
   (the axis's own home) and the solvers' card writers are listed apart.
2. **``ViscoHyperelastic(`` calls** in code (the model built, or rebuilt from another
   model's fields).
3. **Stop sentences compared as strings**: a comparison (``==``, ``!=``, ``in``,
   ``not in``) of a ``stop``/``stop_reason``/``status``/``message`` name or attribute with a string
   constant or a tuple of them.

Within count 1, the places that re-derive the parameter layout by hand instead of asking
:class:`vhfit.viscous.ParamLayout` (issue smell S1) are also counted on their own: the
stride-2 slices, the f-strings that build ``G<i>``/``tau<i>`` names, and the parsers of
such names (a regular expression's string naming ``tau`` or ``G`` followed by a digit
class, a group or an alternation, or ``.startswith("tau")``/``.startswith("G")``). Calls
to the layout (``model.layout.times``, ``ParamLayout.parse(name)``) name no Prony word and
are not counted.

Usage::

    python scripts/count_viscous_axis.py           # the three counts
    python scripts/count_viscous_axis.py -v        # with the places counted
    python scripts/count_viscous_axis.py --src OTHER/src/vhfit   # another tree (before/after)
"""

from __future__ import annotations

import argparse
import ast
import re
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "src" / "vhfit"

#: Identifiers that name the Prony series' layout, amplitudes, times or formulation.
PRONY = re.compile(
    r"(prony|^taus?$|^tau_|_tau$|_taus?_|^log_?taus?$|^g_inf|_g_inf|^g_i$|^gs$|shape_columns"
    r"|^formulations?$|maxwell)", re.IGNORECASE)

#: Solver card writers: their Prony blocks are the solvers' own conventions.
SOLVERS = {"export/abaqus.py", "export/lsdyna.py", "export/ansys.py"}

#: Names whose string comparisons are stop reasons used as state.
STOPS = re.compile(r"^(stop|stop_reason|status|message|reason)$")

#: The start of an f-string that builds a Prony parameter name.
PRONY_NAME = re.compile(r"^(G|g|tau)$")

#: A regular expression's text that parses Prony parameter names (``tau\\d+``,
#: ``^(G|tau)([1-9]...``).
PRONY_PARSE = re.compile(r"(tau|G)(\\d|\[|\)|\|)")

#: The words of count 1 that are the layout re-derived by hand (smell S1).
BY_HAND = ("::2 slice", "name parser")


def _identifier(node: ast.AST) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.arg):
        return node.arg
    if isinstance(node, ast.keyword):
        return node.arg
    return None


def _is_str_or_strs(node: ast.AST) -> bool:
    if isinstance(node, ast.Constant):
        return isinstance(node.value, str)
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return bool(node.elts) and all(isinstance(e, ast.Constant) and isinstance(e.value, str)
                                       for e in node.elts)
    return False


def _stop_operand(node: ast.AST) -> bool:
    name = _identifier(node) if isinstance(node, (ast.Name, ast.Attribute)) else None
    return bool(name and STOPS.match(name))


def scan(path: Path) -> dict[str, list[tuple[int, str]]]:
    """Per count, the (line, what) places of one module."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    out: dict[str, list[tuple[int, str]]] = defaultdict(list)
    for node in ast.walk(tree):
        ident = _identifier(node)
        if (isinstance(node, ast.Constant) and isinstance(node.value, str)
                and len(node.value) < 60 and PRONY_PARSE.search(node.value)):
            out["prony"].append((node.lineno, "name parser"))
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
                and node.func.attr == "startswith" and node.args
                and isinstance(node.args[0], ast.Constant) and node.args[0].value in ("tau", "G")):
            out["prony"].append((node.lineno, "name parser"))
        if ident and PRONY.search(ident):
            out["prony"].append((getattr(node, "lineno", 0), ident))
        if (isinstance(node, ast.Slice) and isinstance(node.step, ast.Constant)
                and node.step.value == 2 and node.lower is not None
                and any(isinstance(n, ast.Name) for n in ast.walk(node.lower))):
            out["prony"].append((getattr(node, "lineno", 0), "::2 slice"))
        if isinstance(node, ast.JoinedStr) and len(node.values) >= 2:
            first, second = node.values[0], node.values[1]
            if (isinstance(first, ast.Constant) and isinstance(first.value, str)
                    and PRONY_NAME.match(first.value) and isinstance(second, ast.FormattedValue)):
                out["prony"].append((node.lineno, f'f"{first.value}{{...}}"'))
        if isinstance(node, ast.Call):
            f = node.func
            name = f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) \
                else None
            if name == "ViscoHyperelastic":
                out["model_calls"].append((node.lineno, "ViscoHyperelastic("))
        if isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            if any(_stop_operand(s) for s in sides) and any(_is_str_or_strs(s) for s in sides):
                out["stop_strings"].append((node.lineno, ast.unparse(node)))
    return out


def _by_hand(word: str) -> bool:
    return word in BY_HAND or word.startswith('f"')


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-v", "--verbose", action="store_true", help="list the places counted")
    ap.add_argument("--src", type=Path, default=SRC, help="the package tree to count")
    args = ap.parse_args(argv)
    src = args.src.resolve()
    modules = sorted(p for p in src.rglob("*.py"))
    prony_mods, viscous_mods, solver_mods = [], [], []
    calls, stops = [], []
    for p in modules:
        rel = p.relative_to(src).as_posix()
        found = scan(p)
        if found.get("prony"):
            (viscous_mods if rel.startswith("viscous/") else
             solver_mods if rel in SOLVERS else prony_mods).append((rel, found["prony"]))
        calls += [(rel, *c) for c in found.get("model_calls", [])]
        stops += [(rel, *c) for c in found.get("stop_strings", [])]
    print(f"source modules: {len(modules)}")
    print(f"modules naming Prony concepts in code (outside viscous/ and the solvers' card "
          f"writers): {len(prony_mods)}")
    print(f"  (under viscous/: {len(viscous_mods)}; solvers' card writers: {len(solver_mods)})")
    by_hand = [(rel, [(n, w) for n, w in places if _by_hand(w)]) for rel, places in prony_mods]
    by_hand = [(rel, places) for rel, places in by_hand if places]
    print(f"  of them re-deriving the layout by hand (slices, name f-strings, name parsers): "
          f"{sum(len(p) for _, p in by_hand)} places in {len(by_hand)} modules")
    print(f"ViscoHyperelastic( calls in code: {len(calls)}")
    print(f"stop sentences compared as strings: {len(stops)}")
    if args.verbose:
        for rel, places in prony_mods:
            words = sorted({w for _, w in places})
            print(f"  prony  {rel}: {len(places)} ({', '.join(words[:8])}"
                  f"{', ...' if len(words) > 8 else ''})")
        for rel, places in by_hand:
            print(f"  layout {rel}: " + ", ".join(f"{n} {w}" for n, w in sorted(places)))
        for rel, line, _ in calls:
            print(f"  model  {rel}:{line}")
        for rel, line, text in stops:
            print(f"  stop   {rel}:{line}: {text}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
