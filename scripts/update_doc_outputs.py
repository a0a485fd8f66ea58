"""Regenerate, or check, the sample outputs shown in README.md and docs/*.md.

Every block of program output in the documentation (command output, printed summaries,
error messages, excerpts of written files) is produced here from the current code. A
generated block is an HTML comment naming its generator, on the line just before a
fenced block (both indented alike when the block sits in a list item)::

    <!-- output: demo-headline -->
    ```text
    abaqus: abaqus.inp: Abaqus will show RMSAPE ...
    ```

or, for output that is itself markdown (a table), around it::

    <!-- output: theory-verification-table -->
    | τ1 (s) | ...
    <!-- end output -->

The generators are the functions registered in ``GENERATORS`` below. They run vhfit's
command line (``python -m vhfit ...``) or its Python API on synthetic data only: the
bundled demo (``vhfit demo``) and small files written here. One demo run serves every
block taken from the demo. Blocks written by hand as illustrations are not marked and
say so in the text around them. Tables of benchmark results (timings, long studies, data
sets outside the project) are records of measured runs, not regenerated here: each is
marked ``<!-- benchmark record: COMMAND -->`` naming the command that measured it.

Usage::

    python scripts/update_doc_outputs.py            # rewrite the stale blocks
    python scripts/update_doc_outputs.py --check    # exit 1 listing the stale blocks

Comparison rule (what makes a block stale)
------------------------------------------
No block is compared to digits recorded on one platform: the same rule holds on every
machine, for the check and for the update, whatever CPU, BLAS kernel or compiler target
wrote the pages.

* Wall-clock times (``wall 1.61 s``, ``elapsed 0.6 s``) are never compared.
* A deterministic block (error messages, file heads, messages computed from a few
  exact numbers: the default) must match exactly, every character, trailing blanks
  aside.
* A block whose numbers come from a seeded search or sit at round-off level depends on
  the platform (another BLAS kernel changes the last bits, and a search then follows
  another path: other generation and evaluation counts, other last digits of what it
  finds). Its generator states the tolerance that computation guarantees (``rtol``,
  ``atol``). There every word, symbol and line must still match (whitespace runs
  aside), and a number matches when ``|shown - new| <= max(unit) + atol + rtol *
  max(|shown|, |new|)``, where ``unit`` is one unit of the last digit printed (so a
  value printed on the other side of a rounding boundary passes). The excerpts are
  chosen so that their words do not depend on the search's path (the demo's exact
  recovery, not its LS-DYNA fit, whose pruned terms and warnings may change with it).

The update mode rewrites only the blocks that fail this rule (an unchanged block keeps
its recorded digits and times, so reruns on any machine do not churn the files).
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import io
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
UPDATE_COMMAND = "python scripts/update_doc_outputs.py"

#: the pages scanned for generated blocks
PAGES = ["README.md", *sorted(p.relative_to(ROOT).as_posix()
                              for p in (ROOT / "docs").glob("*.md"))]

MARKER = re.compile(r"^(?P<indent>[ \t]*)<!-- output: (?P<name>[\w.-]+) -->\s*$")
END_MARKER = "<!-- end output -->"
RECORD = re.compile(r"^\s*<!-- benchmark record: (?P<command>.+?) -->\s*$")
#: wall-clock times: shown as recorded, never compared
VOLATILE = [re.compile(r"(?<=\bwall )\d[\d.e+-]*(?= s\b)"),
            re.compile(r"(?<=\belapsed )\d[\d.e+-]*(?= s\b)")]
#: a number standing alone (not the digits of a name such as tau1 or ogden3)
NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?(?![\w.])")


# ============================================================ generators
@dataclass(frozen=True)
class Generator:
    func: Callable[[], str]
    rtol: float  # relative tolerance of its numbers (0 with atol 0: exact, deterministic)
    atol: float  # absolute tolerance of its numbers (round-off level)
    child: bool  # its work runs in child processes (and no chdir): may run in a thread


GENERATORS: dict[str, Generator] = {}


def generator(name: str, *, rtol: float = 0.0, atol: float = 0.0, child: bool = False):
    """Register ``func`` as the generator ``name``; ``rtol``/``atol``: the tolerance its
    numbers are compared with (see the comparison rule above), 0 for a deterministic one."""
    def deco(func):
        GENERATORS[name] = Generator(functools.cache(func), rtol, atol, child)
        return func
    return deco


#: the demo's seeded search on one BLAS kernel and another follows another path: its
#: generation and evaluation counts, stopping errors (at the target, ~1e-8 %) and printed
#: parameters moved by up to 0.7 % across OpenBLAS's SkylakeX, Haswell, Zen, Sandybridge
#: and Prescott kernels (OPENBLAS_CORETYPE); 5 % keeps a margin for other kernels while a
#: change of the search or of the model (other counts by more, other parameters, another
#: error) still fails
DEMO_RTOL = 0.05


def _env() -> dict[str, str]:
    """The environment of a child ``python -m vhfit``: the vhfit this process imports
    first on its path (a mutated copy under test, say, not whatever is installed)."""
    import vhfit

    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(Path(vhfit.__file__).resolve().parents[1]),
                                         *filter(None, [env.get("PYTHONPATH")])])
    env.pop("COLUMNS", None)
    return env


@functools.cache
def _demo() -> tuple[str, str, dict[str, str]]:
    """One run of ``vhfit demo --out vhfit-demo``: its stdout, stderr and text files."""
    with tempfile.TemporaryDirectory() as d:
        proc = subprocess.run([sys.executable, "-m", "vhfit", "demo", "--out", "vhfit-demo"],
                              cwd=d, env=_env(), capture_output=True, text=True, timeout=600)
        if proc.returncode != 0:
            raise RuntimeError(f"vhfit demo failed ({proc.returncode}): {proc.stderr[-2000:]}")
        files = {p.name: p.read_text(encoding="utf-8")
                 for p in (Path(d) / "vhfit-demo").iterdir()
                 if p.suffix in {".inp", ".k", ".mac", ".json", ".txt", ".csv"}}
    return proc.stdout, proc.stderr, files


def _find(lines: list[str], prefix: str, start: int = 0) -> int:
    """Index of the first line from ``start`` that starts with ``prefix``."""
    for k in range(start, len(lines)):
        if lines[k].startswith(prefix):
            return k
    raise RuntimeError(f"no line starting with {prefix!r} in the output: its layout changed; "
                       "adapt the generator in scripts/update_doc_outputs.py")


def _section(lines: list[str], start: str, stop: str) -> list[str]:
    """From the first line starting with ``start`` to the next starting with ``stop``
    (included)."""
    i = _find(lines, start)
    return lines[i:_find(lines, stop, i) + 1]


@generator("demo-console", rtol=DEMO_RTOL, child=True)
def demo_console() -> str:
    """What a terminal shows of ``vhfit demo`` (progress on stderr first), abridged."""
    out, err, _ = _demo()
    lines = out.splitlines()
    head = lines[:_find(lines, "tau1") + 1]
    check = _section(lines, "card check:", "  lsdyna ")
    return "\n".join(["$ vhfit demo --out vhfit-demo", *_progress(err.splitlines()), *head,
                      "...", *check])


def _progress(lines: list[str]) -> list[str]:
    """stderr with each fit's progress reduced to its first and last generation line: the
    lines between come every 2 s of wall time (when stderr is not a terminal), so their
    number depends on the machine's speed."""
    keep = []
    for k, ln in enumerate(lines):
        gen = ln.startswith("generation ")
        if not gen or not (0 < k < len(lines) - 1 and lines[k - 1].startswith("generation ")
                           and lines[k + 1].startswith("generation ")):
            keep.append(ln)
    return keep


@generator("demo-headline", rtol=DEMO_RTOL)
def demo_headline() -> str:
    """The summary's first lines: what each solver will show."""
    out = _demo()[0].splitlines()
    return "\n".join(out[:out.index("") if "" in out else None])


@generator("demo-table", rtol=DEMO_RTOL)
def demo_table() -> str:
    """The first fit's table of the demo's summary."""
    return "\n".join(_section(_demo()[0].splitlines(), "vhfit calibration:", "stability:"))


# the card's constants (printed to 16 digits) of the demo's exact recovery: the search
# stops at an error of ~5e-10 relative, which pins them to ~1e-9 (at most 3e-9 across
# the kernels above); 1e-6 leaves margin and fails a change of any constant
@generator("demo-abaqus-card", rtol=1e-6)
def demo_abaqus_card() -> str:
    """The material lines of the demo's Abaqus card (its comment header left out)."""
    lines = _demo()[2]["abaqus.inp"].splitlines()
    return "\n".join(lines[_find(lines, "*MATERIAL"):])


@generator("sebs-data-head")
def sebs_data_head() -> str:
    """The head of the bundled demo data file."""
    from vhfit import datasets

    lines = Path(datasets.sebs_path()).read_text(encoding="utf-8").splitlines()
    k = next(i for i, ln in enumerate(lines) if not ln.startswith("#"))
    return "\n".join([*lines[:5], "...", *lines[k:k + 3], "..."])


# ------------------------------------------------------------ error messages
def _cli(argv: list[str], cwd: Path) -> str:
    """stderr of ``vhfit ARGV`` run in-process in ``cwd``."""
    from vhfit import cli

    err = io.StringIO()
    old = Path.cwd()
    try:
        os.chdir(cwd)
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            code = cli.main(argv)
    finally:
        os.chdir(old)
    if code == 0:
        raise RuntimeError(f"vhfit {' '.join(argv)} succeeded; an error was expected")
    return err.getvalue().strip()


def _session(*commands: list[str], files: dict[str, str] | None = None) -> str:
    """``$ vhfit ...`` lines, each followed by what it printed on stderr."""
    with tempfile.TemporaryDirectory() as d:
        for name, text in (files or {}).items():
            (Path(d) / name).write_text(text, encoding="utf-8")
        out = []
        for argv in commands:
            out += ["$ vhfit " + " ".join(argv), _cli(argv, Path(d))]
    return "\n".join(out)


def _data_error(func: Callable[[Path], object], files: dict[str, str], *,
                prefix: str = "", width: int | None = None) -> str:
    """The message of the DataError that ``func(folder)`` raises, wrapped if asked."""
    from vhfit import DataError

    with tempfile.TemporaryDirectory() as d:
        for name, text in files.items():
            (Path(d) / name).write_text(text, encoding="utf-8")
        old = Path.cwd()
        try:
            os.chdir(d)
            func(Path(d))
        except DataError as exc:
            msg = prefix + str(exc)
        else:
            raise RuntimeError(f"{func.__name__}: no DataError")
        finally:
            os.chdir(old)
    return textwrap.fill(msg, width, break_on_hyphens=False) if width else msg


AMBIGUOUS = {"t.csv": "strain,stress_kPa,stress_MPa\n0,0,0\n-0.1,-50,-0.5\n"}
RAMP = "".join(f"{-0.02 * k:g},{-0.01 * k - 0.002 * k * k:g}\n" for k in range(11))
COLD_HOT = {f"{name}.csv": f"# strain_rate: -1\n# temperature: {T}\nstrain,stress_MPa\n{RAMP}"
            for name, T in (("cold", 0), ("hot", 60))}


@generator("cli-missing-file")
def cli_missing_file() -> str:
    return _session(["fit", "tests/missing.csv"])


@generator("cli-ambiguous-columns")
def cli_ambiguous_columns() -> str:
    return _session(["fit", "t.csv", "--rate", "-1"], files=AMBIGUOUS)


@generator("cli-shift-errors")
def cli_shift_errors() -> str:
    return _session(["fit", "cold.csv", "hot.csv"],
                    ["fit", "dma.csv", "ramp30.csv", "--shift", "wlf:8.86"], files=COLD_HOT)


@generator("cli-nothing-finite", rtol=DEMO_RTOL)
def cli_nothing_finite() -> str:
    """Gent on a neo-Hooke tension test to λ = 12, past every Jm of the range the user gives
    (an automatic range would be widened)."""
    import numpy as np

    from vhfit import ViscoHyperelastic

    eps = np.linspace(0.05, 11.0, 20)
    s = ViscoHyperelastic("neo_hooke", 0).stress(dict(C10=0.005), strain=eps,
                                                  strain_rate=0.1, measure="engineering")
    text = "strain,stress_MPa\n" + "".join(f"{e:.6g},{v:.6g}\n" for e, v in zip(eps, s))
    msg = _session(["fit", "locking.csv", "--model", "gent", "--bounds", "Jm=0.1:100",
                    "--seed", "0", "-q"],
                   files={"locking.csv": text})
    return msg.splitlines()[-1]


@generator("cli-interrupt", child=True)
def cli_interrupt() -> str:
    """A real Ctrl-C: SIGINT once the search has written its second checkpoint."""
    import numpy as np

    from vhfit import ViscoHyperelastic

    m = ViscoHyperelastic("mooney_rivlin", 2)
    p = dict(C10=0.1, C01=0.05, G1=2.0, tau1=1e-3, G2=0.5, tau2=0.1)
    eps = np.linspace(0, -0.4, 21)
    rng = np.random.default_rng(0)
    with tempfile.TemporaryDirectory() as d:
        for name, r in (("a", -10.0), ("b", -1000.0)):
            s = m.stress(p, strain=eps, strain_rate=r, measure="engineering")
            s = s * (1 + 0.03 * rng.standard_normal(s.size))
            (Path(d) / f"{name}.csv").write_text(
                f"# strain_rate: {r:g}\nstrain,stress_MPa\n"
                + "".join(f"{e:.6g},{v:.6g}\n" for e, v in zip(eps, s)), encoding="utf-8")
        # a long search (all-parameter DE, no target) with frequent checkpoints
        argv = ["fit", "a.csv", "b.csv", "--prony", "3", "--method", "full", "--maxiter",
                "100000", "--target", "0", "--checkpoint-every", "0.2", "--no-plot", "--out",
                "res"]
        proc = subprocess.Popen([sys.executable, "-m", "vhfit", *argv], cwd=d,
                                env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True)
        ck = Path(d) / "res" / "checkpoint.json"

        def generations() -> int:  # replaced atomically: always whole
            return json.loads(ck.read_text())["solver"]["generations"] if ck.exists() else 0

        first, deadline = None, time.monotonic() + 300
        while first is None or generations() <= first:  # wait for events, not a duration
            if proc.poll() is not None or time.monotonic() > deadline:
                proc.kill()
                raise RuntimeError("the fit to interrupt ended or stalled: "
                                   + proc.communicate()[1][-2000:])
            if first is None and ck.exists():
                first = generations()
            time.sleep(0.05)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=300)
    return "\n".join(["$ vhfit " + " ".join(argv), "^C", err.strip().splitlines()[-1]])


@generator("data-ambiguous-columns")
def data_ambiguous_columns() -> str:
    import vhfit

    return _data_error(lambda d: vhfit.read_csv("t.csv", rate=-1.0), AMBIGUOUS, width=90)


@generator("data-negative-loss")
def data_negative_loss() -> str:
    import vhfit

    rows = "".join(f"{f:g},{1 + f:g},{0.1 * f:g}\n" for f in (0.1, 0.3, 1, 3, 10))
    rows += "30,31,-0.3\n100,101,10\n"
    files = {"dma.csv": "frequency_Hz,storage_MPa,loss_MPa\n" + rows}
    return _data_error(lambda d: vhfit.read_csv("dma.csv"), files, width=90)


@generator("data-not-monotonic")
def data_not_monotonic() -> str:
    import vhfit

    rows = [(-100, -0.02 * k, -0.03 * k) for k in range(1, 11)]
    rows.append((-100, -0.19, -0.285))
    files = {"tests.csv": "strain_rate,strain,stress_MPa\n" + "".join(
        f"{r:g},{e:g},{s:g}\n" for r, e, s in [(-1, 0, 0), *[(-1, -0.02 * k, -0.02 * k)
                                                             for k in range(1, 6)],
                                               (-100, 0, 0), *rows])}
    return _data_error(lambda d: vhfit.read_csv("tests.csv"), files, width=90)


@generator("reliability-hostile")
def reliability_hostile() -> str:
    import vhfit

    bad = "# strain_rate: -1\nstrain,stress_kPa\n0,0\n-0.1,-5\nnan_row,nan\n"
    bad = bad.replace("nan_row", "-0.2")
    empty = "strain,stress_MPa\n"
    return "\n".join(_data_error(lambda d: vhfit.read_csv("tests.csv"), {"tests.csv": t})
                     for t in (bad, empty))


@generator("dma-no-overlap")
def dma_no_overlap() -> str:
    """Sweeps at 0 and 50 °C (one file, a temperature column) whose moduli do not overlap."""
    import vhfit
    from vhfit import tts

    rows = "".join(f"{f:g},{E1:g},{0.1 * f:g},{T:g}\n" for T, lift in ((0, 1.1), (50, 100))
                   for f in (0.1, 0.3, 1, 3, 10) for E1 in [lift + f * (1 if T == 0 else 0.05)])
    files = {"dma.csv": "frequency_Hz,storage_MPa,loss_MPa,temperature_C\n" + rows}
    return _data_error(lambda d: tts.master_curve(vhfit.read_csv("dma.csv")), files,
                       prefix="DataError: ", width=88)


@generator("dma-cold-hot")
def dma_cold_hot() -> str:
    import vhfit

    def fit(d):
        vhfit.calibrate(vhfit.read_csv(["cold.csv", "hot.csv"]), n_prony=1)

    return _data_error(fit, COLD_HOT, prefix="DataError: ", width=88)


@generator("paper-study-rate-warnings")
def paper_study_rate_warnings() -> str:
    """The rate-stiffening warnings on the gelatin stand-in of benchmarks/paper_study.py
    (which writes them into docs/paper-study.md too)."""
    from vhfit.diagnostics import rate_sensitivity

    # benchmarks/ and tests/golden/ each have a module named cases: import this one's
    saved = sys.modules.pop("cases", None)
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        import paper_study
    finally:
        sys.path.pop(0)
        if saved is not None:
            sys.modules["cases"] = saved
    msgs = rate_sensitivity(paper_study.gelatin_reported_curves(), "mooney_rivlin", 5)
    return "\n".join(msgs) if msgs else "(no warning)"


# errors of the model against quadrature at round-off level (1e-14 to 1e-9 of the
# stress; they change by up to 53 % between BLAS kernels) are all below 1e-8, far under
# the model's rtol 1e-6 that the table demonstrates: an error above 1e-8 is a change
@generator("theory-verification-table", atol=1e-8, child=True)
def theory_verification_table() -> str:
    """docs/make_theory_table.py's table: the model against quadrature (errors at
    round-off level, hence ``atol``)."""
    proc = subprocess.run([sys.executable, str(ROOT / "docs" / "make_theory_table.py")],
                          env=_env(), capture_output=True, text=True, timeout=600)
    if proc.returncode != 0:
        raise RuntimeError(f"make_theory_table.py failed: {proc.stderr[-2000:]}")
    return proc.stdout.strip()


# ============================================================ blocks in the pages
@dataclass
class Block:
    page: str
    line: int  # 1-based line of the marker
    name: str
    indent: str
    start: int  # index of the first content line
    stop: int  # index of the closing fence
    text: str


def find_blocks(root: Path, page: str) -> tuple[list[str], list[Block]]:
    lines = (root / page).read_text(encoding="utf-8").split("\n")
    blocks = []
    for i, ln in enumerate(lines):
        m = MARKER.match(ln)
        if not m:
            continue
        indent, name = m["indent"], m["name"]
        fenced = i + 1 < len(lines) and lines[i + 1].strip().startswith("```")
        end = "```" if fenced else END_MARKER
        first = i + 2 if fenced else i + 1
        j = next((k for k in range(first, len(lines)) if lines[k].strip() == end), None)
        if j is None or (not fenced and any(MARKER.match(x) for x in lines[first:j])):
            raise SystemExit(f"{page}:{i + 1}: the output marker '{name}' must be followed "
                             f"by a fenced block (```text ... ```) or by markdown closed by "
                             f"{END_MARKER}")
        body = [ln[len(indent):] if ln.startswith(indent) else ln.lstrip()
                for ln in lines[first:j]]
        blocks.append(Block(page, i + 1, name, indent, first, j, "\n".join(body)))
    return lines, blocks


def _mask(text: str) -> str:
    for pattern in VOLATILE:
        text = pattern.sub("<time>", text)
    return "\n".join(ln.rstrip() for ln in text.strip("\n").split("\n"))


def _unit(token: str) -> float:
    """One unit of the last digit printed in ``token``."""
    mant, _, exp = token.lower().partition("e")
    decimals = len(mant.partition(".")[2])
    return 10.0 ** (int(exp or 0) - decimals)


def same(shown: str, new: str, *, rtol: float = 0.0, atol: float = 0.0) -> bool:
    """Whether a block still shows ``new`` (see the module docstring for the rule):
    exactly when ``rtol`` and ``atol`` are 0, else its words exactly and its numbers
    within one unit of their last digit + ``atol`` + ``rtol`` relative."""
    a, b = _mask(shown), _mask(new)
    if a == b or (rtol == 0 and atol == 0):
        return a == b
    ta, tb = a.split(), b.split()
    if len(ta) != len(tb):
        return False
    for x, y in zip(ta, tb):
        if x == y:
            continue
        nx, ny = NUMBER.split(x), NUMBER.split(y)
        if nx != ny:  # the text around the numbers differs
            return False
        for u, v in zip(NUMBER.findall(x), NUMBER.findall(y)):
            fu, fv = float(u), float(v)
            allowed = max(_unit(u), _unit(v)) + atol + rtol * max(abs(fu), abs(fv))
            if abs(fu - fv) > allowed * (1 + 1e-9):
                return False
    return True


def run(root: Path = ROOT, *, check: bool, pages: list[str] | None = None,
        out=None) -> int:
    """Check (or update) every generated block of ``pages`` under ``root``.

    Returns the number of stale blocks (check) or of rewritten blocks (update).
    """
    out = out or sys.stdout
    parsed = {page: find_blocks(root, page) for page in pages or PAGES}
    for page, (_, blocks) in parsed.items():
        for blk in blocks:
            if blk.name not in GENERATORS:
                raise SystemExit(f"{page}:{blk.line}: no generator named '{blk.name}' "
                                 f"(known: {', '.join(sorted(GENERATORS))})")
    # the generators that wait on child processes run side by side (a quarter of the time
    # on two cores); the others change the working directory and run one at a time after
    used = {blk.name for _, blocks in parsed.values() for blk in blocks}
    with ThreadPoolExecutor(4) as pool:
        for f in [pool.submit(GENERATORS[n].func) for n in sorted(used) if GENERATORS[n].child]:
            f.result()
    found, stale = 0, []
    for page, (lines, blocks) in parsed.items():
        for blk in reversed(blocks):  # from the end: earlier line numbers stay valid
            found += 1
            gen = GENERATORS[blk.name]
            new = gen.func()
            if same(blk.text, new, rtol=gen.rtol, atol=gen.atol):
                continue
            stale.append(f"{page}:{blk.line} ({blk.name})")
            if not check:
                lines[blk.start:blk.stop] = [(blk.indent + ln).rstrip()
                                             for ln in new.split("\n")]
        if stale and not check:
            (root / page).write_text("\n".join(lines), encoding="utf-8")
    if found == 0:
        raise SystemExit("no generated block found: is the root right?")
    stale.reverse()
    if check:
        if stale:
            print(f"{len(stale)} documentation output block(s) no longer match what the "
                  f"code prints: " + "; ".join(stale)
                  + f". Run `{UPDATE_COMMAND}` to regenerate them (and review the diff).",
                  file=out)
        else:
            print(f"{found} documentation output blocks match the code", file=out)
    else:
        print(f"{len(stale)} of {found} blocks rewritten"
              + (": " + "; ".join(stale) if stale else ""), file=out)
    return len(stale)


def main(argv: list[str] | None = None) -> int:
    if not os.environ.get("PYTHONPATH"):  # this checkout's vhfit, not an installed one
        sys.path.insert(0, str(ROOT / "src"))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", action="store_true",
                    help="change nothing; exit 1 listing the blocks that are stale")
    ap.add_argument("--root", type=Path, default=ROOT,
                    help="the checkout whose README.md and docs/ are read (default: this one)")
    args = ap.parse_args(argv)
    n = run(args.root, check=args.check)
    return 1 if args.check and n else 0


if __name__ == "__main__":
    sys.exit(main())
