"""The documentation's sample outputs are what the current code prints.

Every block of program output in README.md and docs/*.md is marked with the generator
that writes it (``<!-- output: NAME -->``, see scripts/update_doc_outputs.py, which
also states the comparison rule). Here the check runs on the real pages, a copy with
altered blocks must fail it, and output-looking blocks without a marker are refused.
The docstring examples of docs/architecture.md run in tests/test_doctests.py.
"""

from __future__ import annotations

import argparse
import importlib.util
import io
import re
import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SPEC_ = importlib.util.spec_from_file_location("update_doc_outputs",
                                               ROOT / "scripts" / "update_doc_outputs.py")
udo = sys.modules.setdefault("update_doc_outputs", importlib.util.module_from_spec(SPEC_))
SPEC_.loader.exec_module(udo)


def test_every_output_block_matches_the_code():
    out = io.StringIO()
    stale = udo.run(ROOT, check=True, out=out)
    assert stale == 0, out.getvalue()


def _copy(tmp_path: Path) -> Path:
    root = tmp_path / "checkout"
    shutil.copytree(ROOT / "docs", root / "docs", ignore=shutil.ignore_patterns("figures"))
    shutil.copy(ROOT / "README.md", root / "README.md")
    return root


def _alter(path: Path, old: str, new: str) -> None:
    text = path.read_text(encoding="utf-8")
    assert text.count(old) >= 1, f"{old!r} not in {path.name}"
    path.write_text(text.replace(old, new, 1), encoding="utf-8")


def _same_pages(root: Path, page: str) -> bool:
    """Whether ``page`` under ``root`` equals this checkout's outside its generated
    blocks, and each block agrees with this checkout's under its generator's rule."""
    lines_a, blocks_a = udo.find_blocks(ROOT, page)
    lines_b, blocks_b = udo.find_blocks(root, page)
    outside = [ln for blk_lines, blks in ((lines_a, blocks_a), (lines_b, blocks_b))
               for ln in [[x for k, x in enumerate(blk_lines)
                           if not any(b.start <= k < b.stop for b in blks)]]]
    return outside[0] == outside[1] and len(blocks_a) == len(blocks_b) and all(
        a.name == b.name and udo.same(a.text, b.text, rtol=udo.GENERATORS[a.name].rtol,
                                      atol=udo.GENERATORS[a.name].atol)
        for a, b in zip(blocks_a, blocks_b))


def test_an_altered_block_fails_the_check_and_the_update_repairs_it(tmp_path, capsys):
    root = _copy(tmp_path)
    # a word of a block from the seeded search (compared on every platform) and a number
    # of a deterministic block
    _alter(root / "docs" / "tutorial.md", "vhfit calibration:", "vhfit fit:")
    _alter(root / "docs" / "cli.md", "t.csv, line 3:", "t.csv, line 9:")
    assert not _same_pages(root, "docs/tutorial.md") and not _same_pages(root, "docs/cli.md")
    assert udo.main(["--check", "--root", str(root)]) == 1
    msg = capsys.readouterr().out
    assert "2 documentation output block(s) no longer match" in msg
    assert "docs/tutorial.md:" in msg and "(demo-table)" in msg
    assert "docs/cli.md:" in msg and "(cli-ambiguous-columns)" in msg
    assert "python scripts/update_doc_outputs.py" in msg
    # the update rewrites exactly those blocks (the same rule as the check, on every
    # machine), back to what the pages hold up to that rule (a rewritten search block
    # shows this run's digits and wall times)
    assert udo.main(["--root", str(root)]) == 0
    assert "2 of" in capsys.readouterr().out
    for page in ("docs/tutorial.md", "docs/cli.md"):
        assert _same_pages(root, page)
    assert udo.main(["--check", "--root", str(root)]) == 0


def test_search_numbers_pass_within_their_tolerance_and_fail_beyond_it(tmp_path, capsys):
    root = _copy(tmp_path)
    page = root / "docs" / "tutorial.md"

    def generations(k: float) -> None:  # the demo's generation count, times k
        text = re.sub(r"generations (\d+)", lambda m: f"generations {round(int(m[1]) * k)}",
                      page.read_text(encoding="utf-8"), count=1)
        page.write_text(text, encoding="utf-8")

    # a seeded search's generation count moves with the BLAS kernel: 2 % passes
    generations(1.02)
    assert page.read_text() != (ROOT / "docs" / "tutorial.md").read_text()
    assert udo.main(["--check", "--root", str(root)]) == 0
    capsys.readouterr()
    # beyond the search's tolerance, a search block's word, a deterministic block's
    # number and a round-off error grown past its floor all fail
    generations(1.2)
    _alter(root / "docs" / "cli.md", "t.csv, line 3:", "t.csv, line 4:")
    _alter(root / "docs" / "quickstart.md", "vhfit calibration:", "vhfit fit:")
    _alter(root / "docs" / "theory.md", "| 7.3e-14 |", "| 5e-08 |")
    assert udo.main(["--check", "--root", str(root)]) == 1
    msg = capsys.readouterr().out
    assert "4 documentation output block(s)" in msg
    for name in ("cli-ambiguous-columns", "demo-console", "demo-table",
                 "theory-verification-table"):
        assert f"({name})" in msg


def test_a_marker_must_name_a_generator_and_precede_a_fence(tmp_path):
    root = _copy(tmp_path)
    _alter(root / "docs" / "cli.md", "<!-- output: cli-missing-file -->",
           "<!-- output: no-such-generator -->")
    with pytest.raises(SystemExit, match="no generator named 'no-such-generator'"):
        udo.run(root, check=True, pages=["docs/cli.md"])
    page = root / "docs" / "quickstart.md"
    page.write_text("<!-- output: cli-missing-file -->\n\n    indented\n", encoding="utf-8")
    with pytest.raises(SystemExit, match="must be followed by a fenced block"):
        udo.run(root, check=True, pages=["docs/quickstart.md"])


# ------------------------------------------------------------ the comparison rule
@pytest.mark.parametrize("shown, new, rtol, atol, expected", [
    ("RMSAPE 2.14 %", "RMSAPE 2.14 %", 0, 0, True),
    ("RMSAPE 2.14 %", "RMSAPE 2.15 %", 0, 0, False),          # deterministic: exact
    ("line 3:", "line  3:", 0, 0, False),
    ("RMSAPE 2.14 %", "RMSAPE 2.15 %", 1e-9, 0, True),        # a last-digit flip
    ("RMSAPE 2.14 %", "RMSAPE 2.16 %", 1e-9, 0, False),       # two units: a change
    ("RMSAPE 2.14 %", "RMSAPE 2.24 %", 0.05, 0, True),        # within the search's 5 %
    ("RMSAPE 2.14 %", "RMSAPE 2.30 %", 0.05, 0, False),
    ("generations 46", "generations 48", 0.05, 0, True),
    ("generations 46", "generations 50", 0.05, 0, False),
    ("x 2", "x 1.9999", 1e-9, 0, True),                       # %g across a boundary
    ("tol 5e-08", "tol 6e-08", 1e-9, 0, True),
    ("tol 5e-08", "tol 7e-08", 1e-9, 0, False),
    ("err 4.6e-14", "err 9.9e-09", 0, 1e-8, True),            # round-off floor
    ("err 4.6e-14", "err 3.1e-08", 0, 1e-8, False),
    ("tau1 = 3", "tau2 = 3", 0.05, 0, False),                 # a name, not a number
    ("stop: target", "stop: converged", 0.05, 1, False),      # words always compared
    ("a  b\nc", "a b\nc", 1e-9, 0, True),                    # column widths
    ("wall 1.61 s   stop", "wall 9.9 s   stop", 0, 0, True),  # times: never
    ("elapsed 0.6 s", "elapsed 2.5 s", 0, 0, True),
    ("x\ny", "x\ny\nz", 0.05, 1, False),
])
def test_comparison_rule(shown, new, rtol, atol, expected):
    assert udo.same(shown, new, rtol=rtol, atol=atol) is expected


# ------------------------------------------------------------ coverage of the pages
OUTPUT_LOOKING = re.compile(r"^\s*(\$ vhfit |vhfit: |DataError: |vhfit calibration:|RMSAPE |"
                            r"generation +\d|card check:|\w+: \S+\.(inp|k|mac): )")


def _unmarked_blocks(page: str, root: Path = ROOT) -> list[str]:
    """Fenced or indented blocks of ``page`` that look like program output but carry no
    output marker."""
    lines = (root / page).read_text(encoding="utf-8").split("\n")
    found, i = [], 0
    while i < len(lines):
        ln = lines[i]
        if ln.strip().startswith("```"):
            j = next(k for k in range(i + 1, len(lines)) if lines[k].strip() == "```")
            marked = i > 0 and udo.MARKER.match(lines[i - 1])
            lang = ln.strip()[3:]
            if not marked and lang in ("", "text", "console") and any(
                    OUTPUT_LOOKING.match(x) for x in lines[i + 1:j]):
                found.append(f"{page}:{i + 1}")
            i = j + 1
            continue
        if ln.startswith("    ") and (i == 0 or not lines[i - 1].strip()) and \
                OUTPUT_LOOKING.match(ln) and not ln.lstrip().startswith("$ vhfit") and \
                not ln.lstrip().startswith("vhfit "):
            found.append(f"{page}:{i + 1}")
        i += 1
    return found


@pytest.mark.parametrize("page", udo.PAGES)
def test_output_looking_blocks_are_generated(page):
    assert not _unmarked_blocks(page), (
        "blocks that look like program output but are written by hand: mark them "
        "<!-- output: NAME --> with a generator in scripts/update_doc_outputs.py")


def test_the_lint_sees_an_unmarked_output_block(tmp_path):
    (tmp_path / "x.md").write_text("text\n\n    vhfit: error: x\n\n```\nRMSAPE 1 %\n```\n"
                                   "<!-- output: demo-table -->\n```text\nRMSAPE 1 %\n```\n")
    assert _unmarked_blocks("x.md", tmp_path) == ["x.md:3", "x.md:5"]


def test_every_generator_serves_a_page_and_the_main_pages_have_blocks():
    used = {}
    for page in udo.PAGES:
        for blk in udo.find_blocks(ROOT, page)[1]:
            used.setdefault(blk.name, []).append(page)
    assert set(used) == set(udo.GENERATORS), "a generator without a block, or the reverse"
    pages = {p for ps in used.values() for p in ps}
    assert {"docs/quickstart.md", "docs/tutorial.md", "docs/cli.md"} <= pages


@pytest.mark.parametrize("page", udo.PAGES)
def test_docs_speak_of_the_product_only(page):
    text = (ROOT / page).read_text(encoding="utf-8")
    for word in ("SPEC", "../shared", "shared/data", "/work/", "/tmp/", "/home/"):
        assert word not in text, f"{page} mentions {word!r}"


# ------------------------------------------------------------ tables of numbers
NUMERIC_CELL = re.compile(r"^[*_]*[~≤<>≈]?\s*[-−+]?\d[\d.,]*(e[-−+]?\d+)?"
                          r"(\s*(%|s|ms|MB|×|x|min|gen\.?))?[*_]*$")


def _numeric_tables(text: str) -> list[int]:
    """0-based header lines of the markdown tables whose cells are mostly numbers."""
    lines, out, i = text.split("\n"), [], 0
    while i < len(lines):
        if lines[i].startswith("|") and i + 1 < len(lines) and \
                re.match(r"^\|\s*:?-", lines[i + 1]):
            j = i + 2
            while j < len(lines) and lines[j].startswith("|"):
                j += 1
            cells = [c.strip() for ln in lines[i + 2:j] for c in ln.strip().strip("|").split("|")]
            n = sum(bool(NUMERIC_CELL.match(c)) for c in cells if c)
            if n >= 4 and n >= 0.25 * len(cells):
                out.append(i)
            i = j
            continue
        i += 1
    return out


def _unlabelled_tables(text: str) -> list[int]:
    lines = text.split("\n")
    if any("generated by" in ln.lower() and "benchmarks/" in ln for ln in lines[:5]):
        return []  # a page written whole by a benchmark, which says so at its top
    ok = (udo.MARKER, udo.RECORD, re.compile(r"^<!-- paper-study-summary: start"))
    return [i + 1 for i in _numeric_tables(text)
            if not (i and any(p.match(lines[i - 1]) for p in ok))]


@pytest.mark.parametrize("page", udo.PAGES)
def test_tables_of_numbers_are_generated_or_labelled_benchmark_records(page):
    bad = _unlabelled_tables((ROOT / page).read_text(encoding="utf-8"))
    assert not bad, (f"{page}, lines {bad}: a table of numbers must be a generated block "
                     "(<!-- output: NAME -->) or a measured one (<!-- benchmark record: "
                     "COMMAND -->)")


def test_the_table_lint_sees_an_unlabelled_table():
    table = "| a | b |\n|---|---|\n| 1.5 | 2 % |\n| 3 | 4 s |\n"
    assert _unlabelled_tables("text\n\n" + table) == [3]
    assert _unlabelled_tables("text\n<!-- benchmark record: python x.py -->\n" + table) == []
    assert _unlabelled_tables("| name | flag |\n|---|---|\n| --x | a 1.5 b |\n") == []


def test_benchmark_records_name_scripts_that_exist():
    for page in udo.PAGES:
        for ln in (ROOT / page).read_text(encoding="utf-8").split("\n"):
            m = udo.RECORD.match(ln)
            if not m:
                continue
            names = re.findall(r"[\w/]+\.py", m["command"])
            assert names, ln
            for name in names:
                assert (ROOT / name).is_file() or (ROOT / "benchmarks" / name).is_file(), (
                    f"{page}: {name} does not exist")


def test_pages_with_interpreter_sessions_run_as_doctests():
    import test_doctests

    for page in udo.PAGES:
        if ">>> " in (ROOT / page).read_text(encoding="utf-8"):
            assert page.removeprefix("docs/") in test_doctests.DOC_PAGES, page


# ------------------------------------------------------------ flags the pages name
#: ``vhfit SUB ...`` up to the end of its code span or line (a line ending in ``\``
#: goes on), and the ``--flags`` in it.
COMMAND = re.compile(r"\bvhfit\s+(?P<sub>[a-z]+)\b(?P<rest>(?:[^`\n]|\\\n)*)")
FLAG = re.compile(r"(?<![\w-])--[A-Za-z][\w-]*")
#: What a sentence says when it claims a flag is missing.
ABSENT = re.compile(r"\b(?:has|have|there is|there are) no\b|\bno `--|\bnot yet\b|"
                    r"\bstill being added\b|\byet to\b|\bdoes(?: not|n't) exist\b|"
                    r"\bno such (?:flag|option)\b|\bnot (?:a )?(?:command-line )?flags?\b|"
                    r"\bonly (?:from|in) (?:the )?Python\b", re.IGNORECASE)
NEAR = 80


def _flags_of_commands() -> dict[str, set[str]]:
    """Each ``vhfit`` sub-command's option strings, from the parser the CLI builds."""
    from vhfit.cli._parser import build_parser

    parser = build_parser()
    top = set(parser._option_string_actions)
    subs = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {name: top | set(p._option_string_actions) for name, p in subs.choices.items()}


def _wrong_flags(root: Path, pages: list[str], commands: dict[str, set[str]]) -> list[str]:
    """``page:line: vhfit SUB --flag`` for each flag (or sub-command) a page writes that
    the parser does not have."""
    bad = []
    for page in pages:
        text = (root / page).read_text(encoding="utf-8")
        for m in COMMAND.finditer(text):
            line = text.count("\n", 0, m.start()) + 1
            if m["sub"] not in commands:
                if FLAG.search(m["rest"]):  # 'vhfit fits ...' is prose; with flags, a command
                    bad.append(f"{page}:{line}: vhfit {m['sub']} (no such command)")
                continue
            bad += [f"{page}:{line}: vhfit {m['sub']} {f}" for f in FLAG.findall(m["rest"])
                    if f not in commands[m["sub"]]]
    return bad


def _absence_claims(root: Path, pages: list[str], commands: dict[str, set[str]]) -> list[str]:
    """``page:line: --flag`` (the flag's line) where a sentence says that a flag the
    parser has is missing."""
    every = set().union(*commands.values())
    bad = []
    for page in pages:
        text = (root / page).read_text(encoding="utf-8")
        # sentences: up to '. ', a blank line or a table row's end
        for m in re.finditer(r"[^\n.|]*(?:\.(?!\s)[^\n.|]*|\n(?!\s*\n)[^\n.|]*)*", text):
            sentence = m[0]
            claims = [c.span() for c in ABSENT.finditer(sentence)]
            # a flag of the sentence within NEAR characters of a claim (a long sentence
            # may speak of a flag and, further on, of something else not being there)
            bad += [f"{page}:{text.count(chr(10), 0, m.start() + f.start()) + 1}: {f[0]}"
                    for f in FLAG.finditer(sentence) if f[0] in every and any(
                        max(a - f.end(), f.start() - b) <= NEAR for a, b in claims)]
    return bad


def test_the_pages_name_only_flags_the_commands_have():
    commands = _flags_of_commands()
    assert not _wrong_flags(ROOT, udo.PAGES, commands), (
        "the pages write flags that 'vhfit' does not have (see docs/cli.md for the list)")
    assert not _absence_claims(ROOT, udo.PAGES, commands), (
        "the pages say that flags 'vhfit' has are missing")


def test_the_flag_check_sees_a_wrong_flag_and_a_false_absence(tmp_path):
    root = _copy(tmp_path)
    commands = _flags_of_commands()
    _alter(root / "docs" / "real-data.md", "--model ogden --select region=cortex",
           "--model ogden --choose region=cortex")
    _alter(root / "README.md", "vhfit demo", "vhfit demo --fast")
    _alter(root / "docs" / "cli.md", "vhfit models", "vhfit modles --json")
    assert _wrong_flags(root, udo.PAGES, commands) == [
        f"{page}:{line}: {what}" for page, line, what in (
            ("README.md", _line(root / "README.md", "vhfit demo --fast"), "vhfit demo --fast"),
            ("docs/cli.md", _line(root / "docs" / "cli.md", "vhfit modles"),
             "vhfit modles (no such command)"),
            ("docs/real-data.md", _line(root / "docs" / "real-data.md", "--choose"),
             "vhfit fit --choose"))]
    # the sentence this check was written for, and a flag that exists said to be missing
    page = root / "docs" / "real-data.md"
    page.write_text(page.read_text(encoding="utf-8") + "\nThe command line has no\n`--sort` "
                    "yet. `--select` and `--columns` are command-line flags still being "
                    "added. `--nonesuch` is not a flag.\n", encoding="utf-8")
    n = page.read_text(encoding="utf-8").count("\n")
    assert _absence_claims(root, udo.PAGES, commands) == [
        f"docs/real-data.md:{n}: --sort", f"docs/real-data.md:{n}: --select",
        f"docs/real-data.md:{n}: --columns"]


#: ``python benchmarks/NAME.py ...`` (or scripts/) up to the end of its code span or line.
SCRIPT = re.compile(r"\bpython\s+(?P<script>(?:benchmarks|scripts)/[\w/]+\.py)\b"
                    r"(?P<rest>(?:[^`\n]|\\\n)*)")


def _wrong_script_flags(root: Path, pages: list[str]) -> list[str]:
    """``page:line: SCRIPT --flag`` for each flag a page gives a script of this checkout
    that the script does not define (its source has no ``"--flag"``), or a missing script."""
    bad = []
    for page in pages:
        text = (root / page).read_text(encoding="utf-8")
        for m in SCRIPT.finditer(text):
            line = text.count("\n", 0, m.start()) + 1
            src = ROOT / m["script"]
            if not src.is_file():
                bad.append(f"{page}:{line}: {m['script']} (no such script)")
                continue
            code = src.read_text(encoding="utf-8")
            bad += [f"{page}:{line}: {m['script']} {f}" for f in FLAG.findall(m["rest"])
                    if f'"{f}"' not in code and f"'{f}'" not in code]
    return bad


def test_the_pages_give_scripts_only_flags_they_have(tmp_path):
    assert not _wrong_script_flags(ROOT, udo.PAGES)
    root = _copy(tmp_path)
    _alter(root / "README.md", "python benchmarks/mutation.py --jobs 2",
           "python benchmarks/mutation.py --workers 2")
    _alter(root / "docs" / "real-data.md", "python benchmarks/bench_real.py --data DIR",
           "python benchmarks/bench_reel.py --data DIR")
    line = _line(root / "README.md", "mutation.py --workers")
    assert _wrong_script_flags(root, udo.PAGES) == [
        f"README.md:{line}: benchmarks/mutation.py --workers",
        f"docs/real-data.md:{_line(root / 'docs' / 'real-data.md', 'bench_reel')}: "
        "benchmarks/bench_reel.py (no such script)"]


def _line(path: Path, text: str) -> int:
    """1-based line of the first ``text`` in ``path``."""
    body = path.read_text(encoding="utf-8")
    return body.count("\n", 0, body.index(text)) + 1
