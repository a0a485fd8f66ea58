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

from vhfit._words import in_python, on_command_line, raw, setting, worded
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
            if isinstance(node, ast.Raise) and isinstance(node.exc, ast.Call) \
                    and _name(node.exc.func) == "worded" and len(node.exc.args) > 1:
                call = ast.Call(func=node.exc.func, args=node.exc.args[1:], keywords=[])
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


TEXT = "bad: try " + setting("n_prony=0", "--prony 0")


def test_errors_carry_both_spellings_through_str_and_the_command_line():
    from vhfit.calibration import CalibrationError
    from vhfit.data import DataError

    for exc in (DataError(TEXT), CalibrationError(TEXT), worded(ValueError, TEXT)):
        assert str(exc) == "bad: try n_prony=0 (command line: --prony 0)"
        assert one_line(exc) == "bad: try --prony 0"
        assert raw(exc) is not None
    assert type(worded(ValueError, TEXT)) is ValueError  # doctests and users see the class
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


# ------------------------------------------------------------ hints, followed
def _refusal(argv: list[str], capsys) -> str | None:
    """The one-line refusal of ``vhfit fit argv`` up to reading the data and checking the
    settings (``--maxiter 1``: a hint is followed if the fit then starts), or None."""
    from vhfit import cli

    capsys.readouterr()
    code = cli.main(["fit", *argv, "--no-plot", "-q", "--maxiter", "1", "--popsize", "5"])
    err = [x for x in capsys.readouterr().err.splitlines() if x.startswith("vhfit: error: ")]
    if code == 2:
        assert len(err) == 1, err
        return err[0].removeprefix("vhfit: error: ")
    return None


def _hints(msg: str) -> list[list[str]]:
    """The flags a refusal suggests, each as arguments to append."""
    out = []
    for m in re.finditer(r"(--[a-z][\w-]*)(?: ([^\s,;)]+))?", msg):
        flag, value = m[1], m[2]
        if value is None or value.startswith("--") or value.isupper() or "=UNIT" in value \
                or value.endswith("=NAME"):
            continue  # a placeholder (--prony N, --units stress=UNIT): nothing to follow
        out.append([flag, value])
    return out


BRAIN = ("region,strain,stress_kPa,time_s\n"
         + "".join(f"{r},{e:g},{s:g},{t:g}\n" for r, k in (("cortex", 1.0), ("callosum", 0.5))
                   for e, s, t in ((0.0, 0.0, 0.0), (0.1, 0.3 * k, 1.0), (0.2, 0.7 * k, 2.0),
                                   (0.3, 1.2 * k, 3.0))))


def _dma(drift: float) -> str:
    """Two isothermal sweeps, measured temperature first, drifting by ``drift`` a point."""
    rows = [(f, 10.0 + f, 1.0, T, T - 0.2 + drift * k) for T in (25.0, 50.0)
            for k, f in enumerate((0.1, 0.3, 1.0, 3.0, 10.0))]
    return ("frequency_Hz,storage_MPa,loss_MPa,measured_sample_temperature_C,"
            "nominal_temperature_C\n"
            + "".join(f"{f:g},{e:g},{lo:g},{m:.2f},{T:.1f}\n" for f, e, lo, T, m in rows))


@pytest.mark.parametrize("name, text, extra", [
    ("text-column", BRAIN, []),
    ("two-stresses", "strain,stress_kPa,stress_MPa,time_s\n0,0,0,0\n0.1,50,0.5,1\n"
                     "0.2,120,1.5,2\n0.3,200,2.0,3\n", []),
    ("rate-free-with-prony", "strain,stress_MPa\n0,0\n0.1,0.3\n0.2,0.7\n0.3,1.2\n",
     ["--prony", "1"]),
    ("dma-drifting-temperature", _dma(0.3), []),
])
def test_each_hint_the_command_line_gives_gets_past_its_refusal(tmp_path, capsys, name, text,
                                                                 extra):
    path = tmp_path / f"{name}.csv"
    path.write_text(text)
    argv = [str(path), *extra, "--out", str(tmp_path / "out")]
    msg = _refusal(argv, capsys)
    assert msg is not None, "the case must be refused to test its hint"
    hints = _hints(msg)
    assert hints, f"no hint to follow in: {msg}"
    for k, hint in enumerate(hints):
        args = [a for a in argv if a not in extra or hint[0] not in extra]
        if hint[0] in extra:  # a hint that replaces a flag given
            i = extra.index(hint[0])
            args = [str(path), *extra[:i], *extra[i + 2:], "--out", str(tmp_path / "out")]
        args[-1] = str(tmp_path / f"out{k}")
        again = _refusal([*args, *hint], capsys)
        assert again != msg, f"following {' '.join(hint)} gives the same refusal: {msg}"
        assert again is None, f"following {' '.join(hint)} of '{msg}' is refused: {again}"


def test_the_drifting_temperature_hint_names_the_nominal_column_and_says_why(tmp_path,
                                                                              capsys):
    path = tmp_path / "dma.csv"
    path.write_text(_dma(0.3))
    msg = _refusal([str(path), "--out", str(tmp_path / "out")], capsys)
    assert "'measured_sample_temperature_C' drifts within the file" in msg, msg
    assert msg.endswith("--columns temperature=nominal_temperature_C"), msg
    import vhfit

    items = vhfit.read_csv(path, columns={"temperature": "nominal_temperature_C"})
    assert sorted(i.temperature for i in items) == [25.0, 50.0]


def test_prony_terms_on_rate_free_data_name_the_files_and_the_flag(tmp_path, capsys):
    path = tmp_path / "equilibrium.csv"
    path.write_text("strain,stress_MPa\n0,0\n0.1,0.3\n0.2,0.7\n0.3,1.2\n")
    msg = _refusal([str(path), "--prony", "1", "--out", str(tmp_path / "out")], capsys)
    assert f"the equilibrium (rate-free) curves ({path}) carry no viscous response" in msg, msg
    assert msg.endswith("fit --prony 0"), msg


@pytest.mark.parametrize("gap, levels", [(0.3, 1), (0.8, 2)])
def test_sweeps_are_one_temperature_level_within_half_a_degree(tmp_path, gap, levels):
    # the documented rule: a reading within 0.5 degrees of a level's first joins it
    import vhfit

    rows = [(f, 10.0 + f, 1.0, T) for T in (25.0, 25.0 + gap) for f in (0.1, 1.0, 10.0)]
    path = tmp_path / "dma.csv"
    path.write_text("frequency_Hz,storage_MPa,loss_MPa,temperature_C\n"
                    + "".join(f"{f:g},{e:g},{lo:g},{T:.2f}\n" for f, e, lo, T in rows))
    assert len(vhfit.read_csv(path)) == levels


def test_a_file_without_a_header_is_refused_in_command_line_words(tmp_path, capsys):
    from vhfit import cli

    f = tmp_path / "numbers.csv"
    f.write_text("0,0\n0.1,1\n0.2,2\n")
    code = cli.main(["fit", str(f), "--no-plot", "-q", "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "numbers.csv, line 1: the first line holds numbers" in err
    assert "add a header row" in err and "names=" not in err
