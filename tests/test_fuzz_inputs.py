"""Hostile-input fuzzing of the newer inputs: moduli files, temperatures, multi-mode and
biaxial columns, results files, checkpoints and command-line option values.

The companion of ``tests/test_fuzz.py`` (stress-strain CSV files, arrays, calibrate): the
same rule — every generated input ends in a correct result or in one of the documented
errors, a one-line ``ValueError`` (``vhfit.data.DataError`` for data) that names the file
and says what to do, or for the command line exit code 2 with one line on stderr — never
a traceback, never an exit code 1 "unexpected" error.

Inputs are generated with numpy from a seed that Hypothesis draws (the ``ci`` profile is
derandomised: the same inputs on every machine). Each example checks a batch of ``BATCH``
inputs, so ``EXAMPLES x BATCH`` >= 10 000 inputs per reader; the count is recorded and
``test_fuzz_budget_per_reader`` fails if a profile or a batch loop lowers it. The
``long`` profile (``--hypothesis-profile=long``) runs ten times more, with random seeds.

Readers and their generators:

* ``moduli``: frequency sweeps and relaxation tests through :func:`vhfit.read_csv` —
  header spellings, units, E or G, |E*| with tan δ, temperature columns with drifting
  levels, set columns, ``# temperature:`` lines; valid ones compared value by value,
  then mutated (bad cells, negative or zero moduli, missing columns, doubled roles,
  unknown units, truncation, byte flips);
* ``modes``: equibiaxial, planar, biaxial (``stretch2``/``stress2``), simple-shear and
  deformation-column files through :func:`vhfit.read_csv`, valid and mutated;
* ``results``: results files (``results.json``) of this and other versions, damaged at
  the JSON level (keys dropped, values of the wrong type, NaN, unknown laws) or the byte
  level (truncated, flipped, other encodings), through :meth:`vhfit.Calibration.load`;
* ``cli_results``: the same files through ``vhfit export``, ``vhfit simulate --results``
  and ``vhfit check`` (``main()`` in-process);
* ``cli_options``: option values of ``fit``, ``simulate`` and ``export`` (``--deformation``,
  ``--tref``, ``--shift``, ``--formulation``, ``--for``, numbers, windows...): accepted
  values parse to what they mean, refused ones exit 2 with one line naming the flag.
  Options that land later are one line each in ``OPTIONS`` (see the marked spot there).
"""

from __future__ import annotations

import contextlib
import copy
import io
import json
import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from _fuzzing import one_line_error, read_case, write_fresh
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from vhfit import Calibration
from vhfit.calibration import Stop
from vhfit.cli import _main as cli_main
from vhfit.cli import main

BATCH = 100
#: Hypothesis examples per reader: >= 10 000 inputs in CI, 10x more with the long profile.
EXAMPLES = max(100, settings.default.max_examples * 100 // BATCH)
FUZZ = settings(max_examples=EXAMPLES, suppress_health_check=[HealthCheck.too_slow,
                HealthCheck.function_scoped_fixture], deadline=None)
SEEDS = st.integers(0, 2**63 - 1)
#: Inputs each reader's fuzz test has checked in this session (read by the budget test).
CHECKED: dict[str, int] = {}
def _count(reader: str, n: int) -> None:
    CHECKED[reader] = CHECKED.get(reader, 0) + n


def _batch(reader: str, seed: int, make, check, explain) -> dict[str, int]:
    """``BATCH`` inputs from ``make(rng)``, each checked by ``check(case)`` ('ok'/'error')."""
    rng = np.random.default_rng(seed)
    counts = {"ok": 0, "error": 0}
    for _ in range(BATCH):
        case = make(rng)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                counts[check(case)] += 1
        except AssertionError as exc:
            raise AssertionError(f"{exc}\n{explain(case)}") from None
        except Exception as exc:  # a crash: anything but the documented errors
            raise AssertionError(f"crash {type(exc).__name__}: {exc}\n{explain(case)}") from exc
    _count(reader, sum(counts.values()))
    return counts


# =========================================================== the command line
@contextlib.contextmanager
def _fast_parser():
    """``main()`` with its parser built once: building it costs milliseconds, parsing it
    microseconds, and a parser is not changed by parsing (everything else in ``main`` —
    parsing, the command, the exit codes and messages — runs as it does for a user)."""
    parser = cli_main.build_parser()
    old = cli_main.build_parser
    cli_main.build_parser = lambda commands=None: parser  # every command's flags
    try:
        yield
    finally:
        cli_main.build_parser = old


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    """Exit code, stdout and stderr of ``vhfit ARGV`` run in this process."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:  # argparse's --help / --version
            code = exc.code if isinstance(exc.code, int) else 2
    return code, out.getvalue(), err.getvalue()


def check_cli_outcome(code: int, err: str, *, names: str | None = None, echo: int = 0
                      ) -> str:
    """Exit 0, or exit 2 with one ``vhfit: error:`` line (warnings aside), no traceback."""
    assert "Traceback" not in err, f"a traceback: {err!r}"
    assert "(unexpected:" not in err, f"an unexpected error (a crash): {err!r}"
    assert code in (0, 2), f"exit code {code}, stderr {err!r}"
    if code == 0:
        return "ok"
    lines = [x for x in err.splitlines() if x.strip() and not x.startswith("warning:")]
    assert len(lines) == 1 and lines[0].startswith("vhfit: error:"), f"stderr {err!r}"
    msg = lines[0]
    assert len(msg) < 800 + echo, f"error message of {len(msg)} characters"
    if names is not None:
        assert names in msg, f"the message does not name {names!r}: {msg!r}"
    return "error"


# ============================================================ results files
def _two_curves(data: Path) -> Path:
    """Two small compression curves (1/s and 100/s) as CSV files in ``data``."""
    data.mkdir(exist_ok=True)
    for rate, k in ((-1.0, 1.2), (-100.0, 1.5)):
        eps = -np.linspace(0.0, 0.2, 6)
        sig = k * eps * (1 - 2 * eps)
        (data / f"r{abs(rate):g}.csv").write_text(
            f"# strain_rate: {rate}\nstrain,stress_MPa\n"
            + "".join(f"{float(e)!r},{float(s)!r}\n" for e, s in zip(eps, sig)))
    return data


def _fit_folder(tmp: Path, name: str, extra: list[str]) -> Path:
    """A real ``vhfit fit`` of two small curves into ``tmp/name`` (seconds)."""
    data = _two_curves(tmp / "data")
    out = tmp / name
    code, _, err = run_cli(["fit", str(data / "r1.csv"), str(data / "r100.csv"), "--out",
                            str(out), "--maxiter", "2", "--popsize", "8", "--prony", "1",
                            "--no-plot", "-q", *extra])
    assert code == 0, err
    return out


@pytest.fixture(scope="module")
def results_bases(tmp_path_factory) -> list[tuple[str, dict]]:
    """Results files of today's vhfit: one fit, and two fits (--for abaqus,lsdyna); each
    also with a WLF shift entry (tests at several temperatures)."""
    tmp = tmp_path_factory.mktemp("fuzz-results")
    one = _fit_folder(tmp, "one", [])
    two = _fit_folder(tmp, "two", ["--for", "abaqus,lsdyna"])
    bases = []
    for folder in (one, two):
        res = json.loads((folder / "results.json").read_text(encoding="utf-8"))
        bases.append((str(folder), res))
        shifted = copy.deepcopy(res)
        shifted["shift"] = {"law": "wlf", "constants": {"T_ref": 20.0, "C1": 17.4,
                                                       "C2": 51.6},
                            "T_ref": 20.0, "source": "law", "temperatures": [0.0, 20.0],
                            "log_aT": [1.9, 0.0]}
        bases.append((str(folder), shifted))
    return bases


#: Values a damaged or hand-edited results file may hold where something else belongs.
HOSTILE_VALUES = [None, "", "abc", "0.1", 0, -1, 1e308, -1e308, float("nan"), float("inf"),
                  True, [], [1, 2], [None], {}, {"a": 1}, [[1]], "mooney_rivlin", 2**70]
#: Keys older (or newer) versions lack or add.
OLD_FORMATS = [None, "vhfit-results-0", "vhfit-results-2", "", 1]


def _paths(tree, prefix=()):
    """Every (path, value) in a JSON tree."""
    yield prefix, tree
    if isinstance(tree, dict):
        for k, v in tree.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(tree, list):
        for i, v in enumerate(tree[:6]):
            yield from _paths(v, prefix + (i,))


def _set(tree, path, value):
    node = tree
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value


def _delete(tree, path):
    node = tree
    for k in path[:-1]:
        node = node[k]
    del node[path[-1]]


#: Keys a results file is read by: mutations land on them more often.
READ_KEYS = ("hyperelastic", "params", "n_prony", "formulation", "rmsape", "options", "g",
             "g_inf", "bounds", "confidence", "history", "shift", "fits", "card_fits",
             "cards", "inputs", "cli_options", "curve_names", "per_curve_rmsape",
             "stop_reason", "nit", "nfev", "wall_time", "order_scan", "warnings",
             "headlines", "stability")


_BASE_TEXT: dict[int, str] = {}


#: Files that are no JSON file of vhfit's at all.
NOT_A_FILE = [b"", b"[]", b"null", b"42", b"strain,stress\n0,0\n", b"{}"]


def damage_bytes(rng: np.random.Generator, text: bytes, word: str, others=()
                 ) -> tuple[bytes, str, str]:
    """``text`` (a JSON file) damaged at the byte level, the expectation and what was done:
    cut short (a full disk, a copy cut short), bytes flipped, another encoding, another
    file, random bytes, NaN literals (Python's json writes them), indented by hand, or
    invalid UTF-8 inside ``word``."""
    how, expect = int(rng.integers(7)), "any"
    if how == 0:
        raw, expect = text[: int(rng.integers(len(text)))], "error"
    elif how == 1:
        b = bytearray(text)
        for _ in range(int(rng.integers(1, 4))):
            b[int(rng.integers(len(b)))] = int(rng.integers(256))
        raw = bytes(b)
    elif how == 2:
        raw = text.decode().encode(str(rng.choice(["utf-16", "utf-8-sig"])))
    elif how == 3:
        files = NOT_A_FILE + list(others)
        raw, expect = files[int(rng.integers(len(files)))], "error"
    elif how == 4:
        raw, expect = rng.bytes(int(rng.integers(1, 300))), "error"
    elif how == 5:
        raw = text.replace(b'": ', b'": NaN, "x": ', 1)
    elif rng.random() < 0.5:
        raw = json.dumps(json.loads(text), indent=int(rng.integers(5))).encode()
    else:
        raw = text.replace(word.encode(), word[:3].encode() + b"\xff\xfe" + word[3:].encode(), 1)
    return raw, expect, f"bytes damaged ({how})"


def results_case(rng: np.random.Generator, bases) -> dict:
    """A results file: as written, from another version, or damaged; with its expectation."""
    folder, base = bases[int(rng.integers(len(bases)))]
    if id(base) not in _BASE_TEXT:
        _BASE_TEXT[id(base)] = json.dumps(base)
    res = json.loads(_BASE_TEXT[id(base)])  # a fresh copy (5x faster than deepcopy)
    kind = int(rng.integers(12))
    expect, what, raw = "any", "", None
    if kind == 0:  # as written
        expect, what = "same", "as written"
    elif kind == 1:  # another version: another format tag, keys missing or added
        fmt = OLD_FORMATS[int(rng.integers(len(OLD_FORMATS)))]
        if fmt is None:
            res.pop("format", None)
        else:
            res["format"] = fmt
        gone = [k for k in res if k not in ("hyperelastic", "params") and rng.random() < 0.3]
        for k in gone:
            del res[k]
        res[f"new_key_{int(rng.integers(100))}"] = HOSTILE_VALUES[
            int(rng.integers(len(HOSTILE_VALUES)))]
        what = f"format {fmt!r}, without {gone}"
    elif kind in (2, 3, 4, 5):  # a value replaced by one of another type
        paths = [p for p, _ in _paths(res) if p and (kind != 2 or p[0] in READ_KEYS)]
        if kind in (3, 4):
            paths = [p for p in paths if p[0] in ("params", "shift", "fits", "card_fits",
                                                   "options", "hyperelastic", "n_prony",
                                                   "formulation", "cards")] or paths
        p = paths[int(rng.integers(len(paths)))]
        v = HOSTILE_VALUES[int(rng.integers(len(HOSTILE_VALUES)))]
        _set(res, p, copy.deepcopy(v))
        what = f"{'/'.join(map(str, p))} = {v!r}"
    elif kind == 6:  # a key deleted
        paths = [p for p, _ in _paths(res) if p and (p[0] in READ_KEYS or rng.random() < 0.1)]
        p = paths[int(rng.integers(len(paths)))]
        _delete(res, p)
        what = f"no {'/'.join(map(str, p))}"
        if p in (("params",), ("hyperelastic",)):
            expect = "error"
    elif kind == 7:  # a parameter renamed, added or its value changed
        params = res["params"]
        name = list(params)[int(rng.integers(len(params)))]
        how = int(rng.integers(4))
        if how == 0:
            params[name + "x"] = params.pop(name)
        elif how == 1:
            params[str(rng.choice(["G2", "tau2", "G9", "mu", "C20", "tau0", "G123456789",
                                   "tau99999999999"]))] = 0.1
        elif how == 2:
            params[name] = -abs(params[name]) - 1.0
        else:
            params[name] = float(rng.choice([0.0, 1e-300, 1e300, -0.0]))
        what = f"params edited ({how}, {name})"
    elif kind == 8:  # the model or formulation changed
        key = str(rng.choice(["hyperelastic", "formulation"]))
        res[key] = str(rng.choice(["ogden", "neo_hookean", "gent", "yeoh", "nonsense",
                                   "lsdyna", "hereditary", "lsdyna_deviatoric", "Mooney-Rivlin",
                                   ""]))
        what = f"{key} = {res[key]!r}"
    elif kind == 9:  # the shift entry damaged
        sh = res.setdefault("shift", {"law": "wlf", "constants": {"T_ref": 20.0, "C1": 17.4,
                                                                   "C2": 51.6}})
        how = int(rng.integers(5))
        if how == 0:
            sh["law"] = str(rng.choice(["arrhenius", "polynomial", "WLF", "none", ""]))
        elif how == 1:
            sh["constants"] = {str(rng.choice(["C1", "C2", "T_ref", "E_a", "c1"])): 1.0}
        elif how == 2:
            sh["temperatures"], sh["log_aT"] = [0.0, 20.0, 40.0], ["a"]
        elif how == 3:
            sh["constants"] = dict(sh.get("constants") or {}, C2=-float(rng.uniform(0, 100)))
        else:
            sh["T_ref"] = str(rng.choice(["20", "warm", "nan"]))
        what = f"shift damaged ({how})"
    elif kind == 10:  # two fits: one damaged
        if "fits" in res:
            form = list(res["fits"])[int(rng.integers(len(res["fits"])))]
            fit = res["fits"][form]
            k = str(rng.choice(["params", "hyperelastic", "solvers"]))
            fit[k] = HOSTILE_VALUES[int(rng.integers(len(HOSTILE_VALUES)))]
            what = f"fits/{form}/{k} damaged"
        else:
            res["fits"] = HOSTILE_VALUES[int(rng.integers(len(HOSTILE_VALUES)))]
            what = f"fits = {res['fits']!r}"
    else:  # byte-level damage of the file
        raw, expect, what = damage_bytes(
            rng, json.dumps(res).encode(), "mooney_rivlin",
            others=[b'"params"', b'{"params": {}, "hyperelastic": "mooney_rivlin"}'])
    if raw is None:
        raw = json.dumps(res).encode()
    return {"raw": raw, "expect": expect, "what": what, "folder": folder, "base": base}


def _explain_results(case) -> str:
    return f"[{case['what']}; expect {case['expect']}] file:\n{case['raw'][:2000]!r}"


def _results_file(case, tmp: Path) -> Path:
    """The case written beside the real fit's cards (what ``check`` reads)."""
    return write_fresh(Path(case["folder"]) / "fuzzed.json", case["raw"])


def check_load(case, tmp: Path) -> str:
    cal = read_case(Path(case["folder"]) / "fuzzed.json", case["raw"], Calibration.load,
                    case["expect"])
    if cal is None:
        return "error"
    assert isinstance(cal, Calibration)
    assert list(cal.params) == list(cal.model.param_names)
    assert not any(math.isnan(v) for v in cal.params.values()), cal.params
    if case["expect"] == "same":
        assert cal.params == case["base"]["params"]
        assert cal.model.hyperelastic.name == case["base"]["hyperelastic"]
    return "ok"


@FUZZ
@given(seed=SEEDS)
def test_results_file_fuzz(results_bases, tmp_path_factory, seed):
    tmp = tmp_path_factory.getbasetemp()
    counts = _batch("results", seed, lambda rng: results_case(rng, results_bases),
                    lambda c: check_load(c, tmp), _explain_results)
    assert counts["ok"] > 0 and counts["error"] > 0


#: Commands that read a results file, with their other arguments, and their share.
RESULT_COMMANDS = [
    (["export", "{path}", "--to", "abaqus"], 0.3),
    (["export", "{path}", "--to", "lsdyna", "--poisson", "0.49"], 0.15),
    (["export", "{path}", "--to", "json"], 0.1),
    (["simulate", "--results", "{path}", "--rate", "-1", "--points", "4"], 0.33),
    (["simulate", "--results", "{path}", "--rate", "0.5", "--points", "3",
      "--deformation", "planar"], 0.1),
    (["check", "{path}"], 0.02),
]


def check_cli_results(case, rng, tmp: Path) -> str:
    path = _results_file(case, tmp)
    k = rng.choice(len(RESULT_COMMANDS), p=[w for _, w in RESULT_COMMANDS])
    argv = [a.replace("{path}", str(path)) for a in RESULT_COMMANDS[k][0]]
    case["argv"] = argv
    code, out, err = run_cli(argv)
    outcome = check_cli_outcome(code, err)
    if outcome == "ok":
        assert case["expect"] != "error", "a file that is no results file was read"
        assert out.strip(), "exit 0 but nothing written"
    elif case["expect"] == "same":
        raise AssertionError(f"a results file as written is refused: {err!r}")
    return outcome


@FUZZ
@given(seed=SEEDS)
def test_cli_results_fuzz(results_bases, tmp_path_factory, seed):
    tmp = tmp_path_factory.getbasetemp()
    rng = np.random.default_rng(seed ^ 0x5EED)
    with _fast_parser():
        counts = _batch("cli_results", seed, lambda r: results_case(r, results_bases),
                        lambda c: check_cli_results(c, rng, tmp),
                        lambda c: f"vhfit {' '.join(c.get('argv', []))}\n"
                                  + _explain_results(c))
    assert counts["ok"] > 0 and counts["error"] > 0


# ============================================================== moduli files
def _explain_data(case) -> str:
    return f"[{case['what']}; expect {case['expect']}] input:\n{case['data'][:3000]!r}"


#: Moduli units in headers: factor to MPa.
MODULUS_UNITS = {"": 1.0, "MPa": 1.0, "kPa": 1e-3, "Pa": 1e-6, "GPa": 1e3}
BAD_CELLS = ["nan", "inf", "-inf", "", "abc", "1e400", "--1", "1.2.3", "12 kPa", "N/A",
             "#DIV/0!", "1 2", "0x1p3"]


def _head(name: str, unit: str, style: int) -> str:
    if not unit:
        return name
    return [f"{name}_{unit}", f"{name} [{unit}]", f"{name} ({unit})"][style]


def valid_moduli(rng: np.random.Generator) -> dict:
    """A sweep or relaxation file with known meaning: levels, units, kinds, spellings."""
    sweep = rng.random() < 0.7
    n_levels = int(rng.choice([0, 1, 2, 3]))
    n = int(rng.choice([2, 3, 5, 12]))
    kind = "G" if rng.random() < 0.3 else "E"
    unit = str(rng.choice(list(MODULUS_UNITS)))
    f_mod = MODULUS_UNITS[unit] * (3.0 if kind == "G" else 1.0)
    style = int(rng.integers(3))
    cols: list[tuple[str, str]] = []  # (header, role)
    if sweep:
        fh, f_scale = [("frequency_Hz", 1.0), ("f [Hz]", 1.0), ("frequency [kHz]", 1e3),
                       ("omega [rad/s]", 1 / (2 * np.pi)), ("freq_Hz", 1.0),
                       ("angular_frequency_rad/s", 1 / (2 * np.pi))][int(rng.integers(6))]
        form = int(rng.integers(3))  # storage+loss, storage+tan delta, |E*|+tan delta
        k = kind
        names = {0: [(_head(str(rng.choice([f"{k}'", "storage_modulus"])), unit, style),
                      "storage"),
                     (_head(str(rng.choice([f"{k}''", "loss_modulus"])), unit, style), "loss")],
                 1: [(_head(str(rng.choice([f"{k}'", "storage_modulus"])), unit, style),
                      "storage"), (str(rng.choice(["tan_delta", "tan δ", "loss_factor"])),
                                   "tan_delta")],
                 2: [(_head(f"|{k}*|", unit, style), "modulus"),
                     (str(rng.choice(["tan_delta", "tan δ"])), "tan_delta")]}[form]
        if kind == "G" and any(not h.startswith("G") and not h.startswith("|G")
                               for h, r in names if r != "tan_delta"):
            names = [(h if r == "tan_delta" or h.startswith(("G", "|G")) else
                      "shear_" + h, r) for h, r in names]
        cols = [(fh, "x")] + names
    else:
        th, f_scale = [("time_s", 1.0), ("t [s]", 1.0), ("time [min]", 60.0),
                       ("time_ms", 1e-3)][int(rng.integers(4))]
        mh = f"{kind}(t)" if kind == "G" or rng.random() < 0.5 else "relaxation_modulus"
        cols = [(th, "x"), (_head(mh, unit, style), "relaxation")]
    set_col = n_levels > 0 and rng.random() < 0.3
    if n_levels:
        cols.append((str(rng.choice(["temperature_C", "T [°C]", "temp_C",
                                     "Temperature (K)"])), "T"))
        if set_col:
            cols.append((str(rng.choice(["set", "set_index", "segment"])), "set"))
    if rng.random() < 0.2:  # a column the reader must ignore
        cols.insert(int(rng.integers(1, len(cols) + 1)),
                    (str(rng.choice(["force_N", "phase_deg", "note"])), "other"))
    levels = max(1, n_levels)
    level_T = np.cumsum(rng.uniform(5, 40, levels)) - 20
    rows, meant = [], []
    for L in range(levels):
        x = np.sort(10 ** rng.uniform(-2, 3, n))
        x = np.unique(x)
        if not sweep and rng.random() < 0.5:
            x[0] = 0.0
        m = 10 ** rng.uniform(-1, 3) * (1 + 1 / (1 + x)) if not sweep else \
            10 ** rng.uniform(-1, 3) * (1 + np.log1p(x))
        td = rng.uniform(0.01, 1.5, x.size)
        T = level_T[L] + rng.uniform(-0.2, 0.2, x.size)
        for i in range(x.size):
            row = {}
            for h, r in cols:
                row[h] = {"x": x[i], "storage": m[i], "loss": m[i] * td[i], "tan_delta": td[i],
                          "modulus": m[i], "relaxation": m[i], "T": T[i], "set": L + 1,
                          "other": 7.0}[r]
            rows.append(row)
        meant.append((x, m, td, T))
    sep = str(rng.choice([",", ";", "\t"]))
    dec_comma = sep != "," and rng.random() < 0.3
    lines = []
    meta_T = None
    if not n_levels and rng.random() < 0.3:
        meta_T = float(rng.uniform(-20, 80))
        lines.append(f"# temperature: {meta_T!r}")
    if kind == "G" and rng.random() < 0.2:
        lines.append("# kind: G")

    def cell(v, h):
        t = repr(float(v)) if h not in ("set", "set_index", "segment") else str(int(v))
        return t.replace(".", ",") if dec_comma else t

    lines.append(sep.join(h for h, _ in cols))
    header_line = len(lines)
    for row in rows:
        lines.append(sep.join(cell(row[h], h) if h != "note" else "ok" for h, _ in cols))
    return {"data": ("\n".join(lines) + "\n").encode(), "sweep": sweep, "kind": kind,
            "f_mod": f_mod, "f_scale": f_scale, "cols": cols, "meant": meant,
            "form": form if sweep else None, "n_levels": n_levels, "meta_T": meta_T,
            "header_line": header_line, "sep": sep, "expect": "same", "line": None,
            "what": f"valid {'sweep' if sweep else 'relaxation'} {kind} {unit or 'MPa'}, "
                    f"{n_levels} temperature levels"}


def moduli_case(rng: np.random.Generator) -> dict:
    """A valid moduli file, or one mutated in one way, with what the mutation calls for."""
    case = valid_moduli(rng)
    if rng.random() < 0.3:
        return case
    lines = case["data"].decode().split("\n")[:-1]
    h, sep, cols = case["header_line"], case["sep"], case["cols"]
    n_rows = len(lines) - h
    roles = [r for _, r in cols]
    i = int(rng.integers(n_rows))  # a data row (0-based among data rows)
    cells = lines[h + i].split(sep)
    kind = int(rng.integers(10))
    case["expect"], case["line"] = "error", None
    if kind == 0:  # a bad cell in a column that is read
        j = int(rng.choice([k for k, r in enumerate(roles) if r not in ("other",)]))
        bad = str(rng.choice(BAD_CELLS))
        cells[j] = bad if sep not in bad else "abc"
        case["line"] = h + i + 1
        case["what"] = f"bad cell {cells[j]!r} in {cols[j][0]!r}"
        if roles[j] == "set" and cells[j] in ("nan", "inf", "-inf", "1e400"):
            case["expect"], case["line"] = "any", None  # a set number that is not finite
    elif kind == 1:  # a value out of range: negative or zero modulus, frequency, time
        cands = [k for k, r in enumerate(roles) if r in ("x", "storage", "loss", "modulus",
                                                         "relaxation", "tan_delta")]
        j = int(rng.choice(cands))
        cells[j] = str(rng.choice(["-1", "-0.5", "0"] if roles[j] != "x" or case["sweep"]
                                  else ["-1", "-0.5"]))
        if cells[j] == "0" and roles[j] in ("loss", "tan_delta"):
            case["expect"] = "any"  # a zero loss modulus is allowed
        else:
            case["line"] = h + i + 1
        if roles[j] == "x" and not case["sweep"]:
            case["expect"], case["line"] = "any", None  # times: order rules apply
        case["what"] = f"{cells[j]} in {cols[j][0]!r}"
    elif kind == 2:  # a field too few or too many
        drop = rng.random() < 0.5
        cells = cells[:-1] if drop else cells + ["1"]
        case["line"] = h + i + 1
        case["what"] = "wrong number of fields"
        if drop and roles[-1] == "other":  # an ignored last column: may be fine
            case["expect"], case["line"] = "any", None
    elif kind == 3:  # a moduli (or the frequency / time) column removed
        j = int(rng.choice([k for k, r in enumerate(roles) if r not in ("T", "set", "other")]))
        for k in range(h - 1, len(lines)):
            c = lines[k].split(sep)
            del c[j]
            lines[k] = sep.join(c)
        case["what"] = f"column {cols[j][0]!r} removed"
        cells = lines[h + i].split(sep)
    elif kind == 4:  # a second column for a role
        j = int(rng.choice([k for k, r in enumerate(roles) if r in ("storage", "loss",
                                                                     "modulus", "x")]))
        lines[h - 1] += sep + cols[j][0].replace("_", " ", 1)
        for k in range(h, len(lines)):
            lines[k] += sep + "1.0"
        cells = lines[h + i].split(sep)
        case["expect"], case["what"] = "any", f"a second {cols[j][0]!r}"
    elif kind == 5:  # a unit that is no unit
        j = int(rng.choice([k for k, r in enumerate(roles) if r in ("storage", "loss",
                                                                     "modulus", "relaxation",
                                                                     "x")]))
        hdr = lines[h - 1].split(sep)
        hdr[j] = re.sub(r"[\[\(].*[\]\)]$", "", hdr[j]).strip() + " [furlongs]"
        lines[h - 1] = sep.join(hdr)
        case["what"] = f"unit of {hdr[j]!r}"
    elif kind == 6:  # truncated, or bytes flipped
        raw = "\n".join(lines).encode()
        if rng.random() < 0.5:
            raw = raw[: int(rng.integers(len(raw) + 1))]
        else:
            b = bytearray(raw)
            for _ in range(int(rng.integers(1, 4))):
                b[int(rng.integers(len(b)))] = int(rng.integers(256))
            raw = bytes(b)
        case.update(data=raw, expect="any", what="truncated or flipped")
        return case
    elif kind == 7:  # header only
        lines = lines[:h]
        case["what"] = "header only"
    elif kind == 8:  # a temperature reading that is not a number
        j = [k for k, r in enumerate(roles) if r == "T"]
        if not j:
            case["expect"], case["what"] = "same", "unchanged"
        else:
            cells[j[0]] = str(rng.choice(["warm", "nan", "", "inf"]))
            case["what"] = f"temperature {cells[j[0]]!r}"
            case["line"] = h + i + 1 if cells[j[0]] in ("warm", "") else None
    else:  # rows of another level in between (no set column): levels by temperature
        case["expect"], case["what"] = "any", "rows moved"
        k = int(rng.integers(n_rows))
        lines.insert(h + k, lines.pop(h + i))
        cells = lines[h + i].split(sep)
    if kind in (0, 1, 2, 8):
        lines[h + i] = sep.join(cells)
    case["data"] = ("\n".join(lines) + "\n").encode()
    return case


def check_moduli(case, path: Path) -> str:
    from vhfit import FrequencySweep, Relaxation, read_csv

    items = read_case(path, case["data"], read_csv, case["expect"], line=case["line"])
    if items is None:
        return "error"
    for it in items:
        if isinstance(it, FrequencySweep):
            for a in (it.frequency, it.storage, it.loss):
                assert np.all(np.isfinite(a))
            assert np.all(it.frequency > 0) and np.all(it.storage > 0) and np.all(it.loss >= 0)
        elif isinstance(it, Relaxation):
            assert np.all(np.isfinite(it.time)) and np.all(it.modulus > 0)
    if case["expect"] == "same":
        assert len(items) == max(1, case["n_levels"]), [i.name for i in items]
        for it, (x, m, td, T) in zip(items, case["meant"]):
            assert isinstance(it, FrequencySweep if case["sweep"] else Relaxation)
            assert it.kind == case["kind"]
            f = case["f_mod"]
            if case["sweep"]:
                np.testing.assert_allclose(it.frequency, x * case["f_scale"], rtol=1e-12)
                e1, e2 = {0: (m, m * td), 1: (m, m * td),
                          2: (m * np.cos(np.arctan(td)), m * np.sin(np.arctan(td)))}[case["form"]]
                np.testing.assert_allclose(it.storage, e1 * f, rtol=1e-9)
                np.testing.assert_allclose(it.loss, e2 * f, rtol=1e-9)
            else:
                np.testing.assert_allclose(it.time, x * case["f_scale"], rtol=1e-12)
                np.testing.assert_allclose(it.modulus, m * f, rtol=1e-12)
            if case["n_levels"]:
                assert it.temperature == pytest.approx(float(np.mean(T)), abs=1e-9)
            elif case["meta_T"] is not None:
                assert it.temperature == pytest.approx(case["meta_T"])
    return "ok"


@FUZZ
@given(seed=SEEDS)
def test_moduli_files_fuzz(tmp_path_factory, seed):
    path = tmp_path_factory.getbasetemp() / "fuzz-moduli.csv"
    counts = _batch("moduli", seed, moduli_case, lambda c: check_moduli(c, path),
                    _explain_data)
    assert counts["ok"] > 0 and counts["error"] > 0


# ============================================= multi-mode and biaxial columns
MODE_SPELLINGS = {"uniaxial": ["uniaxial", "uniaxial_tension_compression", "UT"],
                  "equibiaxial": ["equibiaxial", "equibiaxial tension", "EBT"],
                  "planar": ["planar", "pure shear", "PS"],
                  "simple_shear": ["simple_shear", "simple shear", "SS"],
                  "biaxial": ["biaxial", "general biaxial"]}


def _mode_block(rng, dfm: str, n: int) -> dict:
    """Columns of one test (tension; simple shear: γ > 0), with their meaning."""
    top = rng.uniform(0.05, 1.0)
    e = np.linspace(top / n, top, n)
    k = 10 ** rng.uniform(-2, 1)
    out = {"e1": e, "s1": k * e * (1 + rng.uniform(0, 0.3, n))}
    if dfm == "biaxial":
        out["e2"] = e * rng.uniform(0.2, 1.0)
        out["s2"] = k * out["e2"] * (1 + rng.uniform(0, 0.3, n))
    elif dfm == "equibiaxial" and rng.random() < 0.5:
        out["s2"] = out["s1"] * (1 + rng.uniform(-0.05, 0.05, n))
    return out


def valid_modes(rng: np.random.Generator) -> dict:
    """A file of one or several tests (a deformation column), with known meaning."""
    by_column = rng.random() < 0.4
    modes = list(MODE_SPELLINGS)
    # (in a file of several tests, the columns only some tests have would be blank on the
    # other rows, which the reader refuses: several tests share one set of columns here)
    one_path = ["uniaxial", "equibiaxial", "planar", "simple_shear"]
    tests = ([str(m) for m in rng.choice(one_path, size=int(rng.integers(1, 4)),
                                         replace=False)]
             if by_column else [str(rng.choice(modes))])
    n = int(rng.choice([2, 3, 6, 15]))
    blocks = [_mode_block(rng, t, n) for t in tests]
    if len(tests) > 1:
        for b in blocks:
            b.pop("s2", None)
    has2 = any("e2" in b for b in blocks)
    hass2 = any("s2" in b for b in blocks)
    shear_only = tests == ["simple_shear"]
    if by_column and "simple_shear" in tests and len(tests) > 1:
        d1 = "stretch_or_shear_amount"
    elif shear_only:
        d1 = str(rng.choice(["gamma", "shear_strain", "amount_of_shear"]))
    else:
        d1 = str(rng.choice(["stretch", "lambda1", "stretch_1"]))
    unit = str(rng.choice(["MPa", "kPa"]))
    f = 1.0 if unit == "MPa" else 1e-3
    head = [d1, f"stress_{unit}"]
    if has2:
        head.append(str(rng.choice(["stretch2", "lambda2", "stretch_2"])))
    if hass2:
        head.append(f"stress2_{unit}")
    if by_column:
        head.insert(int(rng.integers(len(head) + 1)),
                    str(rng.choice(["deformation", "test_type", "mode"])))
    lines = []
    declared = not by_column and (tests[0] in ("uniaxial", "equibiaxial", "planar")
                                  or rng.random() < 0.5)
    if declared:
        lines.append(f"# deformation: {rng.choice(MODE_SPELLINGS[tests[0]])}")
    rate = None
    if rng.random() < 0.4:
        rate = float(10 ** rng.uniform(-3, 1))
        lines.append(f"# strain_rate: {rate!r}")
    lines.append(",".join(head))
    meant = []
    for t, b in zip(tests, blocks):
        spelled = str(rng.choice(MODE_SPELLINGS[t]))
        for i in range(n):
            row = []
            for h in head:
                if h == d1:
                    v = b["e1"][i] if t == "simple_shear" or d1 in ("gamma", "shear_strain",
                                                                     "amount_of_shear") \
                        else b["e1"][i] + 1
                elif h.startswith("stress2"):
                    v = b["s2"][i] / f if "s2" in b else ""
                elif h.startswith("stress"):
                    v = b["s1"][i] / f
                elif h in ("deformation", "test_type", "mode"):
                    v = spelled
                else:  # the second stretch
                    v = b["e2"][i] + 1 if "e2" in b else ""
                row.append(v if isinstance(v, str) else repr(float(v)))
            lines.append(",".join(row))
        meant.append((t, b))
    return {"data": ("\n".join(lines) + "\n").encode(), "meant": meant, "rate": rate,
            "f": f, "head": head, "n": n, "expect": "same", "line": None,
            "header_line": len(lines) - n * len(tests),
            "what": f"valid {tests} "
                    f"({'column' if by_column else 'declared' if declared else 'inferred'})"}


def modes_case(rng: np.random.Generator) -> dict:
    case = valid_modes(rng)
    if rng.random() < 0.35:
        return case
    lines = case["data"].decode().split("\n")[:-1]
    h, head = case["header_line"], case["head"]
    i = int(rng.integers(len(lines) - h))
    cells = lines[h + i].split(",")
    case["expect"] = "error"
    kind = int(rng.integers(8))
    if kind == 0:  # a bad cell in a numeric column
        j = int(rng.choice([k for k, x in enumerate(head)
                            if x not in ("deformation", "test_type", "mode")]))
        if cells[j] == "":
            case["expect"] = "any"
        cells[j] = str(rng.choice(BAD_CELLS)) or "abc"
        case["line"] = h + i + 1 if case["expect"] == "error" else None
        case["what"] = f"bad cell {cells[j]!r} in {head[j]!r}"
        if cells[j] in ("nan", "") and case["expect"] == "error":
            case["expect"], case["line"] = "any", None  # an empty cell may mean 'not measured'
    elif kind == 1:  # a test name that names no test
        j = [k for k, x in enumerate(head) if x in ("deformation", "test_type", "mode")]
        if not j:
            lines = [x for x in lines if not x.startswith("# deformation:")]
            lines.insert(0, f"# deformation: {rng.choice(['triaxial', 'bending', '?'])}")
            case["what"] = "unknown '# deformation:'"
        else:
            cells[j[0]] = str(rng.choice(["triaxial", "bending", "", "123"]))
            case["what"] = f"unknown test {cells[j[0]]!r}"
            case["expect"] = "any"  # a 'mode' column may be read as something else
    elif kind == 2:  # a stretch <= 0
        j = int(rng.choice([k for k, x in enumerate(head) if x.startswith(("stretch", "lambda"))]
                           or [0]))
        cells[j] = str(rng.choice(["0", "-0.5", "-2"]))
        case["what"], case["expect"] = f"{cells[j]} in {head[j]!r}", "any"
    elif kind == 3:  # the wrong sign of a sheet's stress
        j = next(k for k, x in enumerate(head) if x.startswith("stress_"))
        cells[j] = repr(-abs(float(cells[j])))
        case["what"], case["expect"] = "stress of the wrong sign in a row", "any"
    elif kind == 4:  # a declared test that contradicts the columns
        lines.insert(0, f"# deformation: {rng.choice(['uniaxial', 'simple_shear', 'biaxial'])}")
        case["what"], case["expect"] = "declared test contradicting", "any"
    elif kind == 5:  # truncated or bytes flipped
        raw = "\n".join(lines).encode()
        if rng.random() < 0.5:
            raw = raw[: int(rng.integers(len(raw) + 1))]
        else:
            b = bytearray(raw)
            for _ in range(int(rng.integers(1, 4))):
                b[int(rng.integers(len(b)))] = int(rng.integers(256))
            raw = bytes(b)
        case.update(data=raw, expect="any", what="truncated or flipped")
        return case
    elif kind == 6:  # a column removed
        j = int(rng.integers(len(head)))
        for k in range(h - 1, len(lines)):
            c = lines[k].split(",")
            del c[j]
            lines[k] = ",".join(c)
        cells = lines[h + i].split(",")
        case["what"], case["expect"] = f"column {head[j]!r} removed", "any"
    else:  # a field too few or too many
        drop = rng.random() < 0.5
        cells = cells[:-1] if drop else cells + ["1"]
        case["what"], case["line"] = "wrong number of fields", h + i + 1
        if drop and head[-1] == "mode":
            # a 'mode' column with a blank cell is no longer read as the tests (one curve
            # of every row): a varying text column, refused once the readers refuse those
            case["expect"], case["line"] = "any", None
    if kind in (0, 1, 2, 3, 7):
        lines[h + i] = ",".join(cells)
    case["data"] = ("\n".join(lines) + "\n").encode()
    return case


def check_modes(case, path: Path) -> str:
    from vhfit import read_csv

    curves = read_case(path, case["data"], read_csv, case["expect"], line=case["line"])
    if curves is None:
        return "error"
    for c in curves:
        assert np.all(np.isfinite(c.strain)) and np.all(np.isfinite(c.stress))
        if c.deformation != "simple_shear":
            assert np.all(c.strain > -1)
        if c.strain2 is not None:
            assert np.all(c.strain2 > -1)
    if case["expect"] == "same":
        assert len(curves) == len(case["meant"]), [c.name for c in curves]
        for c, (t, b) in zip(curves, case["meant"]):
            assert c.deformation == t
            np.testing.assert_allclose(c.strain, b["e1"], rtol=1e-12, atol=1e-15)
            np.testing.assert_allclose(c.stress, b["s1"], rtol=1e-12)
            if "e2" in b:
                np.testing.assert_allclose(c.strain2, b["e2"], rtol=1e-12, atol=1e-15)
            if "s2" in b:
                np.testing.assert_allclose(c.stress2, b["s2"], rtol=1e-12)
            else:
                assert c.stress2 is None
            assert c.strain_rate == case["rate"]
    return "ok"


@FUZZ
@given(seed=SEEDS)
def test_mode_columns_fuzz(tmp_path_factory, seed):
    path = tmp_path_factory.getbasetemp() / "fuzz-modes.csv"
    counts = _batch("modes", seed, modes_case, lambda c: check_modes(c, path),
                    _explain_data)
    assert counts["ok"] > 0 and counts["error"] > 0


# ============================================ extra numeric channels of a lab file
#: Channels a lab writes beside strain and stress (no role in a fit).
CHANNELS = ["force_N", "displacement_mm", "reduced_stress_kPa", "load_cell_V", "extension_mm",
            "true_stress_MPa", "Chamber T", "cycle_count"]
NOT_FINITE = ["nan", "", "inf", "-inf", "NaN", "N/A"]


def channels_case(rng: np.random.Generator) -> dict:
    """A strain/stress file with extra numeric channels (non-finite cells among them), and
    maybe a numeric label column in contiguous blocks, in shuffled column order."""
    n = int(rng.integers(6, 40))
    e = np.linspace(0.0, rng.uniform(0.05, 1.0), n)
    s = 10 ** rng.uniform(-2, 1) * e
    cols = {"strain": [f"{v:.6g}" for v in e], "stress_MPa": [f"{v:.6g}" for v in s]}
    extras = [str(h) for h in rng.choice(CHANNELS, size=int(rng.integers(0, 4)), replace=False)]
    for h in extras:
        v = rng.normal(size=n).cumsum() + np.arange(n)  # a channel: its values differ
        cells = [f"{x:.5g}" for x in v]
        for k in rng.choice(n, size=int(rng.integers(0, 3)), replace=False):
            cells[k] = str(rng.choice(NOT_FINITE))
        cols[h] = cells
    label = None
    if rng.random() < 0.3:  # numbers naming specimens: few values in contiguous blocks
        k = int(rng.integers(1, 4))
        cuts = np.sort(rng.choice(np.arange(2, n - 1), size=k - 1, replace=False))
        if k == 1 or np.diff(np.r_[0, cuts, n]).min() >= 2:
            label = k
            cols["sample_no"] = [str(1 + int(np.searchsorted(cuts, i, side="right")))
                                 for i in range(n)]
    names = list(cols)
    rng.shuffle(names)
    text = ",".join(names) + "\n" + "".join(
        ",".join(cols[h][i] for h in names) + "\n" for i in range(n))
    return {"what": "channels", "data": text.encode(), "stress": s, "extras": extras,
            "label": label,
            "expect": "error" if label and label > 1 else "same"}


def check_channels(case, path: Path) -> str:
    import vhfit

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = read_case(path, case["data"], lambda p: vhfit.read_csv(p, rate=0.1,
                                                                       n_points=None),
                        case["expect"])
    if got is None:
        return "error"
    [c] = got
    np.testing.assert_allclose(c.stress, case["stress"], rtol=1e-5)
    notes = [str(w.message) for w in caught if "not used by the fit" in str(w.message)
             or "is fitted, not" in str(w.message)]
    unused = [h for h in case["extras"] if h != "true_stress_MPa"]
    unused += ["sample_no"] if case["label"] == 1 else []
    if not unused and "true_stress_MPa" not in case["extras"]:
        assert not notes, notes
        return "ok"
    assert len(notes) == 1, notes  # one line for the file
    for h in unused:
        assert repr(h) in notes[0], (h, notes[0])
    if "true_stress_MPa" in case["extras"]:
        assert "not the true stress 'true_stress_MPa'" in notes[0], notes[0]
    return "ok"


@settings(FUZZ, max_examples=max(10, EXAMPLES // 5))  # a modest budget: one reader's path
@given(seed=SEEDS)
def test_extra_numeric_channels_fuzz(tmp_path_factory, seed):
    path = tmp_path_factory.getbasetemp() / "fuzz-channels.csv"
    counts = _batch("channels", seed, channels_case, lambda c: check_channels(c, path),
                    _explain_data)
    assert counts["ok"] > 0


# ==================================================== command-line option values
#: Values typed where a number, a name or a window belongs.
HOSTILE_TEXTS = ["", " ", "abc", "nan", "NaN", "inf", "-inf", "1e400", "-1e400", "0", "-0",
                 "-1", "1.5", "1e-320", "0x10", "1_000", "\u0663", "\uff11", "1,5", "--", "-",
                 "=", "None", "true", "1 2", "9" * 5000, ":", "1:", ":1", "2:1", "nan:1",
                 "a:b", "wlf:", "wlf:1,2", "arrhenius:1e5", "wlf:1,2,3", "wlf:nan,1",
                 "uniaxial", "Pure Shear", "biaxial", "abaqus", "ls-dyna,ansys", "abaqus,,",
                 "hereditary", "lsdyna_deviatoric", "auto", "all", "C10=0:1", "x=1", "\x00",
                 "--", "-5", "1e5:-1e5", "=x", "stress=", "region=", "=", "a=b=c",
                 "alpha1=-40:40", "tau1=0:1", "G1=-1:0", "C10=1:1", "tau3=1:2", "C10=0:inf",
                 "C10=nan:1", "c10=0:1", "tau1=1e-3:", "=0:1", "C10=1:0", "G2=0:1e400"]


def _real(lo: float, hi: float, *, log: bool = False, signed: bool = False):
    """A generator of (text, value) of a float in [lo, hi] (10**lo..10**hi with ``log``,
    of either sign with ``signed``), in one of several spellings."""
    def gen(rng):
        v = 10 ** rng.uniform(lo, hi) if log else rng.uniform(lo, hi)
        v = float(-v if signed and rng.random() < 0.3 else v)
        text = [repr(v), f"{v:.3e}", f"{v:g}", f" {v!r} "][int(rng.integers(4))]
        return text, float(text)
    return gen


def _whole_number(lo: int, hi: int, extra: tuple = ()):
    def gen(rng):
        if extra and rng.random() < 0.3:
            return extra[int(rng.integers(len(extra)))]
        n = int(rng.integers(lo, hi + 1))
        return str(n), n
    return gen


def _pick(pairs):
    return lambda rng: pairs[int(rng.integers(len(pairs)))]


#: --bounds of the default law (Mooney–Rivlin) with up to 2 Prony terms (the default N)
BOUND_NAMES = {"c10": "C10", "c01": "C01", "g1": "G1", "tau1": "tau1", "g2": "G2",
               "tau2": "tau2"}


def _bounds_value(rng):
    """``--bounds NAME=LO:HI``: a valid one (text, meaning), or one the law refuses (an
    unknown name, LO >= HI, a negative τ or G_i) with meaning '?'."""
    spelled = list(BOUND_NAMES)[int(rng.integers(len(BOUND_NAMES)))]
    name = BOUND_NAMES[spelled]
    if rng.random() < 0.5:
        spelled = spelled.upper() if rng.random() < 0.5 else name
    if name.startswith("tau"):
        lo, hi = sorted(10.0 ** rng.uniform(-6, 4, 2))
    elif name.startswith("G"):
        lo, hi = sorted(rng.uniform(0, 100, 2))
    else:
        lo, hi = sorted(rng.uniform(-10, 10, 2))
    lo, hi = float(lo), float(hi)
    how = int(rng.integers(6))
    if how == 0:  # a name the law does not have with this N
        spelled = ["alpha1", "tau3", "G3", "mu", "C20", "tau0"][int(rng.integers(6))]
        return f"{spelled}={lo!r}:{hi!r}", "?"
    if how == 1:  # the limits swapped, or equal
        return f"{spelled}={hi!r}:{hi if rng.random() < 0.3 else lo!r}", "?"
    if how == 2 and name[0] in "Gt":  # a modulus or time below 0
        return f"{spelled}={-hi!r}:{hi!r}", "?"
    return f"{spelled}={lo!r}:{hi!r}", (spelled, lo, hi)


def _is_bound(v):
    """What any accepted --bounds must be: a known name, finite LO < HI, in range."""
    name, lo, hi = v
    if name.lower() not in BOUND_NAMES or not (_finite(lo) and _finite(hi) and lo < hi):
        return False
    return lo > 0 if name.lower().startswith("tau") else (
        lo >= 0 if name.lower().startswith("g") else True)


def _window_value(rng):
    lo, hi = map(float, sorted(rng.uniform(-1, 1, 2)))
    how = int(rng.integers(3))
    if how == 0:
        return f"{lo!r}:{hi!r}", (lo, hi)
    if how == 1:
        return f"{lo!r}:", (lo, None)
    return f":{hi!r}", (None, hi)


def _finite(v):
    return isinstance(v, float) and math.isfinite(v)


def _is_window(v):
    return v is None or (len(v) == 2 and all(x is None or _finite(x) for x in v)
                         and (None in v or v[0] < v[1]))


DEFORMATION_NAMES = [("uniaxial", "uniaxial"), ("equibiaxial", "equibiaxial"),
                     ("planar", "planar"), ("pure_shear", "planar"), ("Pure-Shear", "planar"),
                     ("simple_shear", "simple_shear"), ("shear", "simple_shear"),
                     ("biaxial", "biaxial"), (" Equibiaxial ", "equibiaxial")]


class Opt:
    """A command-line option: where it is taken, how valid values are spelled and what
    they mean, and what any accepted value must satisfy."""

    def __init__(self, flag, commands, dest, valid, ok, *, last=True):
        self.flag, self.commands, self.dest = flag, commands, dest
        self.valid, self.ok, self.last = valid, ok, last

    def parsed(self, ns):
        v = getattr(ns, self.dest)
        return v[-1] if self.last and isinstance(v, list) else v


FIT, SIM, EXP, CHK = ("fit",), ("simulate",), ("export",), ("check",)
OPTIONS = [
    Opt("--deformation", FIT + SIM + CHK, "deformation", _pick(DEFORMATION_NAMES),
        lambda v: v in dict(DEFORMATION_NAMES).values()),
    Opt("--tref", FIT, "tref", _real(-100, 300), _finite),
    Opt("--shift", FIT, "shift", _pick([("wlf:17.44,51.6", ("wlf", (17.44, 51.6))),
                                        ("WLF: 8.86 , 101.6", ("wlf", (8.86, 101.6))),
                                        ("arrhenius:1e5", ("arrhenius", (1e5,))),
                                        ("arrhenius:2e5,-273.15",
                                         ("arrhenius", (2e5, -273.15)))]),
        lambda v: v[0] in ("wlf", "arrhenius") and all(map(math.isfinite, v[1]))),
    Opt("--formulation", FIT, "formulation",
        _pick([(f, f) for f in ("hereditary", "lsdyna", "lsdyna_deviatoric")]),
        lambda v: isinstance(v, str)),
    Opt("--for", FIT, "targets", _pick([("abaqus", ["abaqus"]), ("LS-DYNA", ["lsdyna"]),
                                        ("abaqus,ansys", ["abaqus", "ansys"]),
                                        ("dyna, apdl", ["lsdyna", "ansys"])]),
        lambda v: set(v) <= {"abaqus", "lsdyna", "ansys"}),
    Opt("--rate", FIT + SIM + CHK, "rate", _real(-4, 4, log=True, signed=True), _finite),
    Opt("--points", FIT + CHK, "points", _whole_number(2, 10**6, (("all", None),
                                                                  ("None", None))),
        lambda v: v is None or (isinstance(v, int) and v >= 2)),
    Opt("--points", SIM, "points", _whole_number(2, 5000), lambda v: isinstance(v, int)
        and v >= 2),
    Opt("--prony", FIT, "prony", _whole_number(0, 12, (("auto", "auto"), ("AUTO", "auto"))),
        lambda v: v == "auto" or (isinstance(v, int) and v >= 0)),
    Opt("--popsize", FIT, "popsize", _whole_number(1, 10**4), lambda v: v >= 1),
    Opt("--maxiter", FIT, "maxiter", _whole_number(1, 10**6), lambda v: v >= 1),
    Opt("--workers", FIT, "workers", _whole_number(1, 64), lambda v: v >= 1),
    Opt("--scan-workers", FIT, "scan_workers", _pick([("auto", "auto"), ("1", "1"),
                                                      ("2", "2")]),
        lambda v: v in ("auto", "1", "2")),
    Opt("--max-time", FIT, "max_time", _real(-3, 5, log=True), lambda v: v > 0),
    Opt("--checkpoint-every", FIT, "checkpoint_every", _real(0.01, 100), lambda v: v > 0),
    Opt("--target", FIT, "target", _real(-6, 2, log=True, signed=True), _finite),
    Opt("--g-inf-min", FIT, "g_inf_min", _real(0, 0.5), _finite),
    Opt("--stability-range", FIT, "stability_range",
        _pick([("0.5:2", (0.5, 2.0)), (" 0.8 : 1.25 ", (0.8, 1.25)), ("1e-1:1e1", (0.1, 10.0))]),
        lambda v: len(v) == 2 and 0 < v[0] < 1 < v[1] and math.isfinite(v[1])),
    Opt("--seed", FIT, "seed", _whole_number(0, 2**62), lambda v: isinstance(v, int)),
    Opt("--trim-strain", FIT + CHK, "trim_strain", _window_value, _is_window),
    Opt("--trim-time", FIT + CHK, "trim_time", _window_value, _is_window),
    Opt("--strain-max", SIM, "strain_max", _real(-0.9, 2), _finite),
    Opt("--density", FIT + EXP, "density", _real(-12, -6, log=True), lambda v: v > 0),
    Opt("--poisson", FIT + EXP, "poisson", _real(-0.99, 0.4999), lambda v: -1 < v < 0.5),
    Opt("--bulk-modulus", FIT + EXP, "bulk_modulus", _real(1, 1e5), lambda v: v > 0),
    Opt("--to", EXP, "to", _pick([(t, t) for t in ("abaqus", "lsdyna", "ansys", "json")]),
        lambda v: v in ("abaqus", "lsdyna", "ansys", "json")),
    Opt("--measure", FIT + SIM + CHK, "measure", _pick([("true", "true"),
                                                        ("engineering", "engineering")]),
        lambda v: v in ("true", "engineering")),
    Opt("--bounds", FIT, "bounds", _bounds_value, _is_bound),
    # the readers' choices
    Opt("--select", FIT + CHK, "select", _pick([("region=cortex", ("region", "cortex")),
                                                (" set = 1 ", ("set", "1"))]),
        lambda v: len(v) == 2 and all(isinstance(x, str) and x for x in v)),
    Opt("--group-by", FIT + CHK, "group_by", _pick([("region", "region"),
                                                   ("specimen", "specimen")]),
        lambda v: isinstance(v, str) and v != ""),
    Opt("--columns", FIT + CHK, "columns", _pick([("stress=S11", ("stress", "S11")),
                                                  ("time=", ("time", "")),
                                                  ("ignore=region", ("ignore", "region"))]),
        lambda v: len(v) == 2 and isinstance(v[0], str) and v[0] != ""),
    Opt("--units", FIT + CHK, "units", _pick([("stress=kPa", ("stress", "kPa")),
                                              ("time=ms", ("time", "ms"))]),
        lambda v: len(v) == 2 and isinstance(v[0], str) and v[0] != ""),
]


def option_case(rng: np.random.Generator, tmp: Path) -> dict:
    """One option value on one command: a valid spelling (with its meaning) or a hostile
    text; the rest of the command names a file that does not exist, so that an accepted
    option is seen to pass the front door (the error is then about the file) and nothing
    is computed."""
    opt = OPTIONS[int(rng.integers(len(OPTIONS)))]
    cmd = opt.commands[int(rng.integers(len(opt.commands)))]
    if rng.random() < 0.4:
        text, meaning = opt.valid(rng)
    else:
        text, meaning = HOSTILE_TEXTS[int(rng.integers(len(HOSTILE_TEXTS)))], "?"
    missing = str(tmp / ("missing.csv" if cmd == "fit" else "missing.json"))
    head = {"fit": ["fit", missing, "--out", str(tmp / "out")],
            "simulate": ["simulate", "--results", missing, "--rate", "-1"],
            "export": ["export", missing, "--to", "abaqus"],
            "check": ["check", missing]}[cmd]
    # '--flag=value': values starting with '-' are values, as a user writes them
    argv = head + ([f"{opt.flag}={text}"] if rng.random() < 0.7 or text.startswith("-")
                   else [opt.flag, text])
    return {"opt": opt, "text": text, "meaning": meaning, "argv": argv, "missing": missing}


def check_option(case, parser) -> str:
    opt, argv = case["opt"], case["argv"]
    code, _, err = run_cli(argv)
    outcome = check_cli_outcome(code, err, echo=2 * len(case["text"]))  # it may echo it
    assert outcome == "error", "a command ran on a missing file"
    if case["missing"] in err:  # accepted: the option passed the front door
        ns = parser.parse_args(cli_main.glue_windows(argv))
        value = opt.parsed(ns)
        assert opt.ok(value), f"{opt.flag} {case['text']!r} accepted as {value!r}"
        if case["meaning"] != "?":
            assert value == case["meaning"], f"{opt.flag} {case['text']!r} read as {value!r}"
        return "ok"
    assert case["meaning"] == "?", f"a valid {opt.flag} {case['text']!r} refused: {err!r}"
    assert opt.flag in err, f"the message does not name {opt.flag}: {err!r}"
    return "error"


@FUZZ
@given(seed=SEEDS)
def test_cli_option_values_fuzz(tmp_path_factory, seed):
    tmp = tmp_path_factory.getbasetemp()
    with _fast_parser():
        parser = cli_main.build_parser()
        counts = _batch("cli_options", seed, lambda rng: option_case(rng, tmp),
                        lambda c: check_option(c, parser),
                        lambda c: f"vhfit {' '.join(map(repr, c['argv']))}")
    assert counts["ok"] > 0 and counts["error"] > 0


# ====================================================== regressions found by fuzzing
def test_results_file_damaged_is_a_one_line_value_error(tmp_path):
    """Calibration.load: a truncated file, a missing entry or one of the wrong type is a
    ValueError naming the file (found: JSONDecodeError without the file, KeyError,
    TypeError, AttributeError)."""
    good = {"hyperelastic": "mooney_rivlin", "n_prony": 0, "params": {"C10": 0.1, "C01": 0.0},
            "rmsape": 1.0}
    assert Calibration.load(write_fresh(tmp_path / "ok.json", json.dumps(good).encode())
                            ).params == good["params"]
    for name, text in [("cut.json", json.dumps(good)[:40]),
                       ("norms.json", json.dumps({**good, "rmsape": None}).replace(
                           ', "rmsape": null', "")),
                       ("opts.json", json.dumps({**good, "options": [1, 2]})),
                       ("bounds.json", json.dumps({**good, "bounds": {"C10": 0}})),
                       ("shift.json", json.dumps({**good, "shift": {"law": "wlf"}}))]:
        p = write_fresh(tmp_path / name, text.encode())
        with pytest.raises(ValueError, match=re.escape(str(p))) as exc:
            Calibration.load(p)
        one_line_error(str(exc.value), names=name)


def test_results_file_with_a_huge_n_prony_is_refused_at_once(tmp_path):
    """n_prony = 1e308 (or 2**70) made Calibration.load build a model of that many terms."""
    for n in (3, 1e308, 2**70):  # (3 first: a check that lets it by fails fast there)
        p = write_fresh(tmp_path / "n.json", json.dumps(
            {"hyperelastic": "mooney_rivlin", "n_prony": n, "params": {"C10": 0.1, "C01": 0.0},
             "rmsape": 1.0}).encode())
        with pytest.raises(ValueError, match="n_prony = .* does not fit"):
            Calibration.load(p)


@pytest.mark.parametrize("entry, value", [
    ("fits", "abc"), ("fits", {"lsdyna": {"params": 1.0, "hyperelastic": "mooney_rivlin"}}),
    ("card_fits", 12), ("cards", {"lsdyna": 1.5}), ("params", {"C10": [], "C01": 0.0}),
    ("params", [1, 2]), ("inputs", [None]), ("shift", {"temperatures": [[None]]}),
    ("cli_options", {"rate": -1.0}), ("hyperelastic", 3)])
def test_cli_damaged_results_entry_is_exit_2_naming_it(tmp_path, entry, value):
    """export/simulate/check on a results file whose entry has the wrong type: exit 2 and
    one line naming the file and the entry (found: AttributeError, TypeError, exit 1)."""
    res = {"hyperelastic": "mooney_rivlin", "n_prony": 0, "params": {"C10": 0.1, "C01": 0.0},
           "rmsape": 1.0, entry: value}
    p = write_fresh(tmp_path / "results.json", json.dumps(res).encode())
    for argv in (["export", str(p), "--to", "abaqus"],
                 ["simulate", "--results", str(p), "--rate", "-1"], ["check", str(p)]):
        code, _, err = run_cli(argv)
        assert check_cli_outcome(code, err, names=str(p)) == "error"
        assert repr(entry) in err, err


def test_cli_prony_term_of_a_huge_index_is_exit_2_at_once(tmp_path):
    """A constant 'G123456789' made the CLI list 246913578 missing names (minutes, GBs)."""
    for index in (1000, 123456789):  # (1000 first: a check that lets it by fails fast)
        res = {"hyperelastic": "mooney_rivlin", "params": {"C10": 0.1, "C01": 0.0,
                                                           f"G{index}": 1.0}}
        p = write_fresh(tmp_path / "results.json", json.dumps(res).encode())
        code, _, err = run_cli(["export", str(p), "--to", "abaqus"])
        assert check_cli_outcome(code, err) == "error"
        assert f"G{index}" in err, err  # named by the results file's one reader


def test_simulate_with_a_prony_term_of_a_huge_index_is_exit_2_at_once():
    """The same through simulate --param (the constants come from the command line)."""
    for index in (1000, 123456789):
        code, _, err = run_cli(["simulate", "--model", "mooney_rivlin", "--param",
                                f"C10=0.1,C01=0,G{index}=1", "--rate", "-1"])
        assert check_cli_outcome(code, err) == "error"
        assert f"1..{index}" in err, err


def test_export_of_prony_moduli_that_leave_no_long_term_weight_is_a_value_error():
    """G1 = 1e300 over E_inf = 0.9 MPa: g_inf = 1 - sum(g_i) rounds to 0 (found: a
    ZeroDivisionError in every card writer)."""
    from vhfit.export import export
    from vhfit.model import ViscoHyperelastic

    m = ViscoHyperelastic("mooney_rivlin", 1)
    for to in ("abaqus", "lsdyna", "ansys", "json"):
        with pytest.raises(ValueError, match="g_inf = 0"):
            export(m, {"C10": 0.1, "C01": 0.05, "G1": 1e300, "tau1": 0.01}, to=to)
    assert "*VISCOELASTIC" in export(m, {"C10": 0.1, "C01": 0.05, "G1": 1e15, "tau1": 0.01},
                                     to="abaqus").upper()


@pytest.mark.parametrize("argv", [["export", "r.json", "--to", "abaqus", "--density=--"],
                                  ["fit", "a.csv", "--rate=--"], ["fit", "a.csv", "--shift=--"]])
def test_cli_option_given_dash_dash_as_its_value_is_exit_2_naming_it(argv):
    """'--density=--' was parsed as density = [] (argparse drops '--'), then crashed."""
    code, _, err = run_cli(argv)
    assert check_cli_outcome(code, err, names=argv[-1][:-3]) == "error"
    assert "is not a value" in err


def test_moduli_file_with_bare_prime_headers_is_a_sweep(tmp_path):
    """Headers E' and E'' (documented) lost their primes as if they were quotes, and the
    file was refused: "columns E' and E'' could both be the relaxation"."""
    from vhfit import FrequencySweep, read_csv

    p = write_fresh(tmp_path / "dma.csv", b"frequency_Hz,E',E''\n1,2,0.5\n10,3,0.25\n")
    [sweep] = read_csv(p)
    assert isinstance(sweep, FrequencySweep)
    np.testing.assert_array_equal(sweep.storage, [2.0, 3.0])
    np.testing.assert_array_equal(sweep.loss, [0.5, 0.25])
    p = write_fresh(tmp_path / "quoted.csv", b"'frequency_Hz','E [MPa]'\n1,2\n10,3\n")
    with pytest.raises(ValueError, match="no frequency|moduli"):
        read_csv(p)  # quoted headers are still unquoted: E is a relaxation modulus


def test_moduli_file_with_a_relaxation_modulus_but_no_time_is_a_data_error(tmp_path):
    """E(t) beside a loss modulus, no time column: a KeyError 'time' (found by fuzzing)."""
    from vhfit import read_csv

    p = write_fresh(tmp_path / "relax.csv", b"E(t) [MPa],loss_MPa\n2,1\n1,1\n")
    with pytest.raises(ValueError, match="no frequency or time column") as exc:
        read_csv(p)
    one_line_error(str(exc.value), names="relax.csv")


def test_moduli_file_errors_name_the_file_and_the_fix(tmp_path):
    """A missing loss column and a negative time: the messages named neither the file nor
    a fix (found by fuzzing)."""
    from vhfit import read_csv

    for name, text in [("noloss.csv", b"frequency_Hz,storage_MPa,phase_deg\n1,2,7\n10,3,7\n"),
                       ("negt.csv", b"time_s,E(t) [MPa]\n0,2\n-1,1\n")]:
        with pytest.raises(ValueError) as exc:
            read_csv(write_fresh(tmp_path / name, text))
        one_line_error(str(exc.value), names=name)


# ================================================ checkpoints (fit --resume)
def _resume_setup(tmp: Path):
    import vhfit

    eps = -np.linspace(0, 0.2, 6)
    curves = [vhfit.Curve(strain=eps, stress=k * eps * (1 - 2 * eps), strain_rate=r)
              for r, k in ((-1.0, 1.2), (-100.0, 1.5))]
    kw = dict(hyperelastic="mooney_rivlin", n_prony=1, maxiter=3, popsize=8, seed=0,
              polish=False, uncertainty=False)
    ck = tmp / "checkpoint.json"
    vhfit.calibrate(curves, checkpoint=str(ck), **kw)
    base = json.loads(ck.read_text())
    base["done"] = None  # (an unfinished search: the state is loaded and resumed)
    return curves, kw, ck, base


def test_damaged_checkpoint_is_a_one_line_value_error(tmp_path):
    """A checkpoint of the right fit whose solver state is damaged (an entry missing or of
    the wrong type): was a KeyError/TypeError/AttributeError from deep in the solver."""
    import vhfit

    curves, kw, ck, base = _resume_setup(tmp_path)
    for path, value in [(("evaluations",), None), (("solver", "history", "mean"), None),
                        (("solver", "random_state"), [1, 2]), (("solver", "elapsed"), "x")]:
        d = copy.deepcopy(base)
        if value is None:
            _delete(d, path)
        else:
            _set(d, path, value)
        write_fresh(ck, json.dumps(d).encode())
        with pytest.raises(ValueError, match="checkpoint .* delete it") as exc:
            vhfit.calibrate(curves, checkpoint=str(ck), resume=True, **kw)
        one_line_error(str(exc.value), names=ck.name)


@pytest.mark.parametrize("path, value, why", [
    (("solver", "population", "data", 0), -0.5, "unit cube"),
    (("solver", "population", "data", 1), 2.0, "unit cube"),
    (("solver", "population", "data", 2), "nan", "unit cube"),
    (("solver", "population_energies", "data", 0), "nan", "NaN"),
    (("solver", "population_energies", "data", 0), -1.0, "errors are negative"),
    (("solver", "nfev"), 2**70, "not counts"),
    (("solver", "generations"), -1, "not counts"),
    (("solver", "elapsed"), -1.0, "not a time"),
    (("solver", "elapsed"), "inf", "not a time"),
    (("evaluations",), -1, "not a count"),
    (("evaluations",), 1e308, "not a count"),
    (("done",), 1.0, "stop reason"),
    (("solver", "donor_index", "data", 0), 1, "permutation"),
    (("solver", "history", "best", "__ndarray__"), "complex128", "'best' row"),
    (("solver", "history", "nit"), {"__ndarray__": "int64", "shape": [2], "data": [0, 1]},
     "length"),
    (("solver", "version"), True, "version"),
    (("solver", "extras"), [None], "extras")])
def test_checkpoint_with_values_no_run_writes_is_refused(checkpoint_base, path, value, why):
    """Values that no search writes in a checkpoint were resumed (found by the fuzz
    below): members outside the unit cube (constants outside their bounds, tau1 = 1e7 s
    of a bound 10 s) or NaN (then "the law is undefined at the data", a wrong cause), NaN
    or negative errors, counts that overflowed mid-search (OverflowError), a negative or
    infinite time, a stop reason 1.0, a donor index that is no permutation, history rows
    of complex numbers (TypeError) or of different lengths, version true, extras [None]."""
    import vhfit

    cb = checkpoint_base
    d = json.loads(cb["text"])
    if path[-2:] == ("data", 0) and path[1] == "donor_index":
        value = d["solver"]["donor_index"]["data"][1]  # a member twice, one never
    _set(d, path, value)
    write_fresh(cb["path"], json.dumps(d).encode())
    with pytest.raises(ValueError, match="checkpoint .* delete it") as exc:
        vhfit.calibrate(cb["curves"], checkpoint=str(cb["path"]), resume=True, **cb["kw"])
    one_line_error(str(exc.value), names=cb["path"].name)
    assert why in str(exc.value), exc.value


@pytest.fixture(scope="module")
def checkpoint_base(tmp_path_factory) -> dict:
    """A real checkpoint of a tiny fit, and what reads it: the fit's search space,
    settings and key, and a solver of that search (built as the fit builds it)."""
    from vhfit.calibration import _checkpoint, _search, _workflow

    tmp = tmp_path_factory.mktemp("fuzz-checkpoint")
    seen = {}
    real = _workflow.run_search

    def spy(space, settings, **kw):
        seen.update(space=space, settings=settings)
        return real(space, settings, **kw)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_workflow, "run_search", spy)
        curves, kw, ck, base = _resume_setup(tmp)
    space, s = seen["space"], seen["settings"]
    key = _checkpoint.fit_key(space.prob, space.layout, s.seed, s.popsize, s.effective_tol,
                              s.target, s.de_options)
    crits, _ = _search.stop_criteria(s.effective_tol, s.target, s.stall, None)
    solver = _search.new_solver(space, s, _search._Objective(space), None, crits)
    return {"curves": curves, "kw": kw, "path": ck, "base": base, "text": json.dumps(base),
            "key": key, "solver": solver, "space": space,
            "paths": [p for p, _ in _paths(base) if p], "arrays": _arrays(base)}


#: Numbers a damaged or hand-edited state may hold: the unit box's edges and beyond.
EDGE_VALUES = [0.0, 1.0, -0.0, 5e-324, -1e-12, 1.0 + 2**-52, 2.0, -0.5, "nan", "inf",
               "-inf", 1e308, -1e308, 2**70, -1, None, "x", True, [0.5]]


def _arrays(tree):
    """The paths of the stored arrays (``{"__ndarray__": ...}``) in a JSON tree."""
    return [p for p, v in _paths(tree) if isinstance(v, dict) and "__ndarray__" in v]


def checkpoint_case(rng: np.random.Generator, cb: dict) -> dict:
    """A checkpoint of the fit: as written, or damaged; with its expectation."""
    d = json.loads(cb["text"])
    kind = int(rng.integers(10))
    expect, what, raw = "any", "", None
    arrays = cb["arrays"]  # (every copy of the base has the same paths)
    if kind == 0:
        expect, what = "same", "as written"
    elif kind in (1, 2):  # a value replaced by one of another type, or a key deleted
        paths = cb["paths"]
        p = paths[int(rng.integers(len(paths)))]
        if kind == 1:
            v = HOSTILE_VALUES[int(rng.integers(len(HOSTILE_VALUES)))]
            _set(d, p, copy.deepcopy(v))
            what = f"{'/'.join(map(str, p))} = {v!r}"
        else:
            _delete(d, p)
            what = f"no {'/'.join(map(str, p))}"
    elif kind in (3, 4):  # numbers in an array: the box's edges, beyond, non-finite
        a = arrays[int(rng.integers(len(arrays)))]
        if kind == 3:  # most often the population and its energies
            a = (("solver", "population"), ("solver", "population_energies"))[
                int(rng.integers(2))]
        node = d
        for k in a:
            node = node[k]
        if node["data"]:
            i = int(rng.integers(len(node["data"])))
            node["data"][i] = EDGE_VALUES[int(rng.integers(len(EDGE_VALUES)))]
            what = f"{'/'.join(map(str, a))}[{i}] = {node['data'][i]!r}"
    elif kind == 5:  # an array's dtype, shape or length changed
        a = arrays[int(rng.integers(len(arrays)))]
        node = d
        for k in a:
            node = node[k]
        how = int(rng.integers(3))
        if how == 0:
            node["__ndarray__"] = str(rng.choice(["complex128", "object", "<U3", "float16",
                                                  "int8", "bool", "bogus", "V8", "M8[s]"]))
        elif how == 1:
            node["shape"] = [[-1], [0], [], [16], [1, 16], [4, 4], [2**40], [8, 2, 1],
                             "8", [None]][int(rng.integers(10))]
        else:
            node["data"] = node["data"][: int(rng.integers(len(node["data"]) + 1))] \
                if rng.random() < 0.5 else node["data"] * 2
        what = f"{'/'.join(map(str, a))} reshaped ({how}): {node}"
    elif kind == 6:  # another fit, another format or version
        k = [("format",), ("key",), ("solver", "format"), ("solver", "version"),
             ("solver", "parameter_count"), ("solver", "strategy"),
             ("solver", "extras")][int(rng.integers(7))]
        old = d
        for x in k:
            old = old[x]
        _set(d, k, {"format": "vhfit-checkpoint-1", "key": "0" * 64}.get(k[-1], 2)
             if rng.random() < 0.5 else HOSTILE_VALUES[int(rng.integers(len(HOSTILE_VALUES)))])
        expect = "error" if json.dumps(old) != json.dumps(_get(d, k)) else "any"
        what = f"{'/'.join(k)} = {_get(d, k)!r}"
    elif kind == 7:  # the checkpoint's own numbers: what was done, evaluated, spent
        k = [("done",), ("evaluations",), ("solver", "elapsed"), ("solver", "nfev"),
             ("solver", "generations"), ("solver", "evaluations"),
             ("solver", "population_size")][int(rng.integers(7))]
        v = (EDGE_VALUES + ["converged", "", "maxiter", 0.5])[int(rng.integers(23))]
        _set(d, k, v)
        what = f"{'/'.join(k)} = {v!r}"
    elif kind == 8:  # the random generator's state
        rs = d["solver"]["random_state"]
        paths = [p for p, _ in _paths(rs) if p]
        p = paths[int(rng.integers(len(paths)))]
        v = [-1, 2**128, 2**200, 0, "PCG64DXSM", "MT19937", 1.5, None, "x", []][
            int(rng.integers(10))]
        _set(rs, p, v)
        what = f"random_state/{'/'.join(map(str, p))} = {v!r}"
    else:
        raw, expect, what = damage_bytes(rng, json.dumps(d).encode(), "best1bin")
    if raw is None:
        raw = json.dumps(d).encode()
    return {"raw": raw, "expect": expect, "what": what}


def _get(tree, path):
    for k in path:
        tree = tree[k]
    return tree


def check_checkpoint(case, cb: dict, rng: np.random.Generator) -> str:
    """Read the case into the fit's solver as a resumed fit does: one line naming the file,
    or a state a search can go on from (a box-bounded finite population, errors that
    are errors, a count and a time that are ones); then, sometimes, one more generation."""
    from vhfit.calibration import _checkpoint

    solver = cb["solver"]
    got = read_case(cb["path"], case["raw"],
                    lambda path: _checkpoint.resume(path, cb["key"], solver), case["expect"])
    if got is None:
        return "error"
    state, evaluations, done, elapsed = got
    pop, e = solver.population, solver.population_energies
    assert pop.dtype == np.float64 and pop.shape == (solver.num_population_members, 2)
    assert np.isfinite(pop).all() and (pop >= 0).all() and (pop <= 1).all(), pop
    assert e.dtype == np.float64 and not np.isnan(e).any() and (e >= 0).all(), e
    idx = solver._random_population_index
    assert sorted(idx.tolist()) == list(range(len(pop))), idx  # SciPy's donor draw
    assert isinstance(evaluations, int) and evaluations >= 0, evaluations
    assert done is None or (isinstance(done, Stop) and done.message), done
    assert math.isfinite(elapsed) and elapsed >= 0, elapsed
    if case["expect"] == "same":
        np.testing.assert_array_equal(pop.ravel(), cb["base"]["solver"]["population"]["data"])
    if rng.random() < 0.3:  # go on: a generation, the stopping tests, the history
        next(solver)
        solver.converged()
        h = solver.history
        assert np.isfinite(solver.population).all() and len(h.best) == len(h.nit)
    return "ok"


@FUZZ
@given(seed=SEEDS)
def test_checkpoint_file_fuzz(checkpoint_base, seed):
    """Checkpoints of a real fit, damaged: read into that fit's solver as ``--resume`` does
    (no fit per case: 10**4 cases in seconds)."""
    rng = np.random.default_rng(seed ^ 0xC4EC)
    counts = _batch("checkpoint", seed, lambda r: checkpoint_case(r, checkpoint_base),
                    lambda c: check_checkpoint(c, checkpoint_base, rng),
                    lambda c: f"[{c['what']}; expect {c['expect']}] file:\n{c['raw'][:3000]!r}")
    assert counts["ok"] > 0 and counts["error"] > 0


def test_checkpoint_fuzz_through_calibrate(checkpoint_base):
    """A few of the same damaged checkpoints resumed by ``calibrate`` itself: a result
    within the bounds, or a one-line ValueError."""
    import vhfit

    cb = checkpoint_base
    rng = np.random.default_rng(2026)
    counts = {"ok": 0, "error": 0}
    while sum(counts.values()) < 40:
        case = checkpoint_case(rng, cb)
        write_fresh(cb["path"], case["raw"])
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                cal = vhfit.calibrate(cb["curves"], checkpoint=str(cb["path"]), resume=True,
                                      **cb["kw"])
        except ValueError as exc:
            one_line_error(str(exc), names=cb["path"].name)
            counts["error"] += 1
            continue
        except Exception as exc:
            raise AssertionError(f"crash {type(exc).__name__}: {exc} ({case['what']})") from exc
        assert math.isfinite(cal.rmsape), case["what"]
        for name, v in cal.params.items():
            lo, hi = cal.bounds[name]
            assert lo <= v <= hi, (name, v, lo, hi, case["what"])
        counts["ok"] += 1
    assert counts["ok"] > 0 and counts["error"] > 0


def _cut_cli_fit(tmp_path: Path, ctrl_c) -> tuple[list[str], Path, Path]:
    """``vhfit fit`` of two small curves cut (Ctrl-C) in generation 3: its arguments, its
    ``--out`` folder and the checkpoint it left there."""
    data = _two_curves(tmp_path / "data")
    out = tmp_path / "out"
    argv = ["fit", str(data / "r1.csv"), str(data / "r100.csv"), "--out", str(out),
            "--maxiter", "6", "--popsize", "8", "--prony", "1", "--for", "abaqus",
            "--no-plot", "-q", "--checkpoint-every", "0.001"]
    with ctrl_c(3):
        assert run_cli(argv)[0] == 1
    return argv, out, out / "checkpoint.json"


def test_cli_resume_of_a_checkpoint_that_is_not_utf8_is_exit_2_leaving_it(tmp_path,
                                                                          ctrl_c_in_fit):
    """A checkpoint whose bytes are no UTF-8: 'vhfit: error: 'utf-8' codec can't decode
    byte 0xbc' (found by the fuzz below: the folder's guard read it as text to restore it
    on bad input); now the checkpoint's own one-line error, and the file kept as it was."""
    argv, out, ck = _cut_cli_fit(tmp_path, ctrl_c_in_fit)
    raw = b"\xbc" + ck.read_bytes()[1:]
    write_fresh(ck, raw)
    code, _, err = run_cli(argv + ["--resume"])
    assert check_cli_outcome(code, err, names=str(ck)) == "error"
    assert "delete it" in err and ck.read_bytes() == raw


def test_cli_resume_of_damaged_checkpoints(tmp_path, ctrl_c_in_fit):
    """A handful of the same damages on a checkpoint ``vhfit fit`` left when cut (Ctrl-C),
    resumed by ``vhfit fit --resume``: exit 0, or exit 2 with one line naming the
    checkpoint and the folder as it was."""
    argv, out, ck = _cut_cli_fit(tmp_path, ctrl_c_in_fit)
    text = ck.read_text()
    base = json.loads(text)
    cb = {"text": text, "arrays": _arrays(base), "paths": [p for p, _ in _paths(base) if p]}
    rng = np.random.default_rng(7)
    outcomes = set()
    for _ in range(6):
        case = checkpoint_case(rng, cb)
        for f in out.iterdir():  # the folder as the cut run left it, with the damaged file
            if f.name != ck.name:
                f.unlink()
        write_fresh(ck, case["raw"])
        code, _, err = run_cli(argv + ["--resume"])
        outcome = check_cli_outcome(code, err, names=str(out))
        if outcome == "error":
            assert sorted(p.name for p in out.iterdir()) == [ck.name], case["what"]
            assert ck.read_bytes() == case["raw"], case["what"]
        outcomes.add(outcome)
    assert outcomes == {"ok", "error"}


# ====================================================================== budget
def test_fuzz_budget_per_reader(results_bases, tmp_path_factory, request):
    """Counts the inputs each reader's fuzz test really checked (runs it if it has not).

    This test comes after the fuzz tests in the file, so in a whole run it only reads the
    counts; it fails if a profile, a ``settings`` or a batch loop lowers the budget.
    """
    runs = {
        "results": lambda: test_results_file_fuzz(results_bases, tmp_path_factory),
        "cli_results": lambda: test_cli_results_fuzz(results_bases, tmp_path_factory),
        "cli_options": lambda: test_cli_option_values_fuzz(tmp_path_factory),
        "moduli": lambda: test_moduli_files_fuzz(tmp_path_factory),
        "modes": lambda: test_mode_columns_fuzz(tmp_path_factory),
        "checkpoint": lambda: test_checkpoint_file_fuzz(
            request.getfixturevalue("checkpoint_base")),
    }
    for reader, run in runs.items():
        if reader not in CHECKED:
            run()
        assert CHECKED[reader] >= 10_000, f"{reader}: only {CHECKED[reader]} inputs checked"
