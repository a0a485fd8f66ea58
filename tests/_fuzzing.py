"""What the hostile-input suites (``test_fuzz.py``, ``test_fuzz_inputs.py``) share: how a
generated input is written, and what a reader's answer to it must be.

A reader answers a case with a result or with one of its documented errors: a one-line
``ValueError`` that names what was read (the file, the curve; the line where known) and
says what to do. A case marked ``"same"`` (valid as written) must be read; one marked
``"error"`` (not an input at all) must be refused; ``"any"`` may go either way.
"""

from __future__ import annotations

import re
from pathlib import Path

#: Words that say what to do; every error message must contain one.
FIX_WORDS = re.compile(
    r"\b(give|use|pass|add|delete|remove|fix|check|repair|name|write|sort|fill|choose|"
    r"separate|correct|convert|split|drop|rename|save|ignore|negate|keep|set|replace|"
    r"trim|make|declare|provide|store|say|select|supply|try|put|enter|change|start|rerun|"
    r"see)\b", re.I)


def write_fresh(path: Path, data: bytes) -> Path:
    """Write ``data`` to a new file at ``path``: rewriting a file in place makes some file
    systems (ext4's replace-by-truncate rule) flush it to disk on close, 50x slower."""
    path.unlink(missing_ok=True)
    path.write_bytes(data)
    return path


def one_line_error(msg: str, *, names: str | None = None, limit: int = 800) -> None:
    """``msg`` is one line, shorter than ``limit``, says what to do and names ``names``."""
    assert "\n" not in msg, f"error message spans lines: {msg!r}"
    assert len(msg) < limit, f"error message of {len(msg)} characters"
    assert FIX_WORDS.search(msg), f"error message says nothing about the fix: {msg!r}"
    if names is not None:
        assert names in msg, f"error message does not name {names!r}: {msg!r}"


def refused(expect: str, exc: Exception, *, names: str | None = None,
            line: int | None = None, limit: int = 800) -> str:
    """A reader refused a case expected ``expect``: fine unless the case was valid, and
    only in one line naming ``names`` (and ``line``) and the fix. Returns ``"error"``."""
    msg = str(exc)
    assert expect != "same", f"valid input rejected: {msg}"
    one_line_error(msg, names=names, limit=limit)
    if line is not None:
        assert f"line {line}" in msg, f"error message does not name line {line}: {msg!r}"
    return "error"


def accepted(expect: str, what: object) -> None:
    """A reader read a case expected ``expect``: fine unless it was no input at all."""
    assert expect != "error", f"misleading success: {what!r}"


def read_case(path: Path, data: bytes, read, expect: str, *, line: int | None = None):
    """Write a generated input ``data`` to a new file at ``path`` and read it with
    ``read(path)``, as every fuzz checker does.

    Returns what ``read`` gave, checked by :func:`accepted` (a case that is no input at
    all must not be read), or None when it refused with a ``ValueError``, checked by
    :func:`refused` (a valid case must be read; the error is one line naming the file,
    ``line`` where given, and the fix). The checker goes on with its own checks of a result.
    """
    write_fresh(path, data)
    try:
        got = read(path)
    except ValueError as exc:
        refused(expect, exc, names=path.name, line=line)
        return None
    assert got is not None, f"{path.name}: the reader answered None"
    accepted(expect, got)
    return got
