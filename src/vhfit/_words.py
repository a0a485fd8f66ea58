"""A setting named in both of its spellings: the Python API's and the command line's.

A message that tells the user what to change names the setting with :func:`setting`,
once, and each reader sees their own words: ``setting("n_prony=0", "--prony 0")`` reads
"n_prony=0 (command line: --prony 0)" from Python (``str`` of the error or warning) and
"--prony 0" on the command line (:func:`on_command_line`, called by the CLI). A setting
with no flag gives the command-line words as prose ("leave its file out"), so that the
command line never shows a Python keyword.

The two spellings travel inside the text between private-use marks, so a message can be
composed, wrapped and re-raised as a string; :class:`Worded` renders them in ``str``.
"""

from __future__ import annotations

import re

__all__ = ["setting", "in_python", "on_command_line", "raw", "Worded", "worded"]

_OPEN, _SEP, _CLOSE = "\ue000", "\ue001", "\ue002"
_MARK = re.compile(f"{_OPEN}([^{_SEP}]*){_SEP}([^{_CLOSE}]*){_CLOSE}")


def setting(api: str, cli: str) -> str:
    """``api`` (Python words) and ``cli`` (command-line words) of one setting, marked."""
    return f"{_OPEN}{api}{_SEP}{cli}{_CLOSE}"


def in_python(text: str) -> str:
    """The message as the Python API reads it: "api (command line: cli)", or "api" alone
    for a setting the command line words as nothing (an aside of Python only)."""
    return _MARK.sub(lambda m: f"{m[1]} (command line: {m[2]})" if m[2] else m[1], text)


def on_command_line(text: str) -> str:
    """The message as the command line reads it: the command-line words only."""
    return _MARK.sub(lambda m: m[2], text)


def raw(exc: BaseException) -> str | None:
    """The marked text of ``exc``, if it carries one, else None."""
    marked = getattr(exc, "_vhfit_words", None)
    if marked is not None:
        return marked
    args = getattr(exc, "args", ())
    if args and isinstance(args[0], str) and _OPEN in args[0]:
        return args[0]
    return None


class Worded:
    """Mixin of vhfit's errors and warnings: ``str`` reads a marked message in Python words."""

    def __str__(self) -> str:
        text = raw(self)
        return in_python(text) if text is not None else super().__str__()


def worded(cls: type[BaseException], text: str) -> BaseException:
    """An exception of the plain class ``cls`` (e.g. ``ValueError``) reading ``text`` in
    Python words, which keeps the marked text for the command line (:func:`raw`)."""
    exc = cls(in_python(text))
    exc._vhfit_words = text
    return exc
