"""The entry point: parse, run the command, turn every failure into an exit code."""

from __future__ import annotations

import atexit
import os
import sys
import warnings
from collections.abc import Sequence

from vhfit.cli._common import EXIT_FAILED, EXIT_USAGE, FitFailed, UsageError, one_line
from vhfit.cli._parser import build_parser, command_in, glue_windows

__all__ = ["main", "program"]


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


def program() -> None:
    """The ``vhfit`` program (the console script, ``python -m vhfit``): :func:`main` on
    ``sys.argv``, then exit with its code.

    Why not ``sys.exit(main())`` alone: once the outputs are written, the interpreter's
    teardown of what a fit loaded (numpy, scipy, numba's compiled kernels, matplotlib:
    some 1500 modules) takes another half second or more, for nothing. The exit hook
    registered here runs after every exit handler registered since (multiprocessing's,
    temporary files', logging's: they run last-registered first) and after the threads
    have been joined, and ends the process with the code without that teardown. A run
    that raised, and one under a tracer (coverage), exit as usual.
    """
    done: dict[str, int] = {}
    atexit.register(_exit_now, done)
    done["code"] = main()
    sys.exit(done["code"])


def _exit_now(done: dict[str, int]) -> None:
    if "code" not in done or sys.gettrace() is not None:
        return
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError, AttributeError):  # closed, or a pipe gone
            pass
    os._exit(done["code"])


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
