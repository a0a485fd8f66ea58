"""The entry point: parse, run the command, turn every failure into an exit code."""

from __future__ import annotations

import sys
import warnings
from collections.abc import Sequence

from vhfit.cli._common import EXIT_FAILED, EXIT_USAGE, FitFailed, UsageError, one_line
from vhfit.cli._parser import build_parser, command_in, glue_windows

__all__ = ["main"]


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``vhfit`` command line; returns the exit code.

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments without the program name (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 success, 1 fit failed or interrupted, 2 bad input.

    Examples
    --------
    >>> from vhfit.cli import main
    >>> main(["export", "no-such-results.json", "--to", "json"])  # a one-line error
    2
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    try:
        words = glue_windows(argv)
        parser = build_parser(command_in(words))  # only the flags of the command run
        args = parser.parse_args(words)
        if args.command is None:
            parser.print_help()
            return EXIT_USAGE
        with warnings.catch_warnings():
            warnings.showwarning = _show_warning  # one line, no source excerpt
            return int(args.func(args, argv))
    except UsageError as exc:
        if debug:
            raise
        _error(one_line(exc))
        return EXIT_USAGE
    except FitFailed as exc:
        if debug:
            raise
        _error(one_line(exc))
        return EXIT_FAILED
    except KeyboardInterrupt:
        if debug:
            raise
        _error("interrupted")
        return EXIT_FAILED
    except (ValueError, OSError) as exc:  # DataError is a ValueError: bad input
        if debug:
            raise
        _error(one_line(exc))
        return EXIT_USAGE
    except Exception as exc:
        if debug:
            raise
        _error(f"{type(exc).__name__}: {one_line(exc)} (unexpected: rerun with --debug "
               "for the traceback, and please report it)")
        return EXIT_FAILED


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    if issubclass(category, UserWarning):
        msg = message if isinstance(message, Warning) else Warning(message)
        text = f"warning: {one_line(msg)}"
        try:
            (file or sys.stderr).write(text + "\n")
        except (OSError, ValueError):
            pass


def _error(msg: str) -> None:
    try:
        sys.stderr.write(f"vhfit: error: {msg}\n")
        sys.stderr.flush()
    except (OSError, ValueError):
        pass
