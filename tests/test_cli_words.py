"""Messages in the command line's words: every error and warning text the command line
can print, walked in the source, names flags, never a keyword of the Python API.

The walk reads each ``raise DataError(...)`` / ``CalibrationError`` / ``UsageError`` /
``FitFailed`` and each ``warn(..., DataWarning | CalibrationWarning)`` of the package with
``ast``, renders it as the command line does (a :func:`vhfit._words.setting` becomes its
command-line words, any other interpolation a placeholder) and looks for ``name=`` where
``name`` is a parameter of the functions the command line calls (``read_csv``,
``calibrate``, ``compare``, the curve and history constructors). A message the command line
cannot reach is listed in ``API_ONLY`` with the reason.
"""

from __future__ import annotations

import ast
import inspect
import re
from pathlib import Path

import pytest

from vhfit._words import in_python, on_command_line, raw, setting
from vhfit.cli._common import one_line

SRC = Path(__file__).resolve().parents[1] / "src" / "vhfit"
RAISED = {"DataError", "CalibrationError", "UsageError", "FitFailed"}
WARNED = {"DataWarning", "CalibrationWarning"}

#: Modules whose messages the command line cannot print, and why.
API_ONLY = {
    "hyperelastic/_registry.py": "registering a law is Python only",
    "optimize/": "the optimizer's own keywords; the command line sets them itself",
    "parallel.py": "vhfit.parallel is Python only",
    "plot.py": "plot functions are Python only",
    "viscoelastic.py": "Prony objects are built by vhfit itself on the command line",
    "spectrum.py": "vhfit.spectrum is Python only",
}


def api_keywords() -> set[str]:
    """Parameter names of what the command line calls with keywords."""
    import vhfit
    from vhfit.data import Curve, read_csv

    names: set[str] = set()
    for f in (read_csv, vhfit.calibrate, vhfit.compare, Curve, vhfit.calibrate_for):
        names |= set(inspect.signature(f).parameters)
    return names - {"self", "args", "kwargs"}


def _cli_text(node: ast.AST) -> str:
    """The command-line rendering of a message expression: constants kept, settings
    rendered by their command-line words, every other value a placeholder."""
    if isinstance(node, ast.Constant):
        return node.value if isinstance(node.value, str) else "{}"
    if isinstance(node, ast.JoinedStr):
        return "".join(_cli_text(v) for v in node.values)
    if isinstance(node, ast.FormattedValue):
        return _cli_text(node.value)
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add):
        return _cli_text(node.left) + _cli_text(node.right)
    if isinstance(node, ast.Call) and getattr(node.func, "id", "") == "setting":
        return _cli_text(node.args[1])
    if isinstance(node, ast.IfExp):
        return _cli_text(node.body) + " | " + _cli_text(node.orelse)
    if isinstance(node, ast.Name):
        return "{}"
    return "{}"


def _name(func: ast.AST) -> str:
    return getattr(func, "id", getattr(func, "attr", ""))


def messages() -> list[tuple[str, int, str]]:
    """(module, line, command-line text) of every error and warning the walk finds."""
    out = []
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC).as_posix()
        if any(rel.startswith(k) for k in API_ONLY):
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        # a message built in a local variable: the variable's assignments count too
        assigned: dict[str, list[ast.AST]] = {}
        for node in ast.walk(tree):
            if isinstance(node, ast.Assign):
                for t in node.targets:
                    if isinstance(t, ast.Name):
                        assigned.setdefault(t.id, []).append(node.value)
        for node in ast.walk(tree):
            call = None
            if isinstance(node, ast.Raise) and isinstance(node.exc, ast.Call):
                if _name(node.exc.func) in RAISED:
                    call = node.exc
            elif isinstance(node, ast.Call) and _name(node.func) == "warn":
                if any(_name(a) in WARNED for a in node.args[1:]) or any(
                        _name(k.value) in WARNED for k in node.keywords):
                    call = node
                elif node.args and isinstance(node.args[0], ast.Call) \
                        and _name(node.args[0].func) in WARNED:
                    call = node.args[0]
            if call is None or not call.args:
                continue
            arg = call.args[0]
            parts = [arg]
            if isinstance(arg, ast.Name):
                parts = assigned.get(arg.id, [])
            for p in parts:
                out.append((rel, node.lineno, _cli_text(p)))
    return out


def test_the_walk_finds_the_messages():
    found = messages()
    # the readers alone raise well over a hundred DataErrors: an empty walk is a broken walk
    assert len(found) > 150
    assert any("--prony" in t for _, _, t in found)


def test_no_message_the_command_line_prints_names_a_python_keyword():
    kws = api_keywords()
    pattern = re.compile(r"(?<![\w\-])(" + "|".join(sorted(kws, key=len, reverse=True))
                         + r")=")
    flag = re.compile(r"--[a-z][\w-]*(?:[ =][^\s,;)]+)?")  # a flag and its value
    bad = [f"{m}:{line}: {text[:160]!r}" for m, line, text in messages()
           if pattern.search(flag.sub("--FLAG", text))]
    assert not bad, ("messages that show a Python keyword on the command line (name the "
                     "setting with vhfit._words.setting):\n" + "\n".join(bad))


def test_a_setting_reads_in_each_readers_words():
    text = "curve 'slow': no rate: fit " + setting("n_prony=0", "--prony 0")
    assert in_python(text) == "curve 'slow': no rate: fit n_prony=0 (command line: --prony 0)"
    assert on_command_line(text) == "curve 'slow': no rate: fit --prony 0"


def test_errors_carry_both_spellings_through_str_and_the_command_line():
    from vhfit.calibration import CalibrationError
    from vhfit.data import DataError

    for cls in (DataError, CalibrationError):
        exc = cls("bad: try " + setting("n_prony=0", "--prony 0"))
        assert str(exc) == "bad: try n_prony=0 (command line: --prony 0)"
        assert one_line(exc) == "bad: try --prony 0"
        assert raw(exc) is not None
    plain = ValueError("no marks here")
    assert raw(plain) is None and one_line(plain) == "no marks here"


@pytest.mark.parametrize("cls_name", sorted(WARNED))
def test_warnings_read_in_python_words(cls_name):
    import vhfit.calibration as cal
    import vhfit.data as data

    cls = getattr(data, cls_name, None) or getattr(cal, cls_name)
    w = cls("note: " + setting("units={'stress': 'kPa'}", "--units stress=kPa"))
    assert str(w) == "note: units={'stress': 'kPa'} (command line: --units stress=kPa)"
    assert one_line(w) == "note: --units stress=kPa"
