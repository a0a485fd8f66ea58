"""What every command shares: exit codes, errors, progress, signals and file output."""

from __future__ import annotations

import math
import signal
import sys
import time
from pathlib import Path
from typing import TextIO

from vhfit._words import on_command_line, raw

__all__ = [
    "EXIT_OK",
    "EXIT_FAILED",
    "EXIT_USAGE",
    "UsageError",
    "FitFailed",
    "one_line",
    "Progress",
    "Signals",
    "prepare_out",
    "emit",
]

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_USAGE = 2
DEMO_PRONY = 4  # Prony terms of ``vhfit demo`` (here: the parser shows it without the fit code)


class UsageError(Exception):
    """Bad input on the command line or in a file: exit code 2, one-line message."""


class FitFailed(Exception):
    """The calibration could not produce a result: exit code 1."""


def one_line(exc: BaseException) -> str:
    """The message of ``exc`` on one line, in the command line's words (an OSError names
    its file)."""
    marked = raw(exc)
    text = on_command_line(marked) if marked is not None else (str(exc) or type(exc).__name__)
    if isinstance(exc, OSError) and exc.filename:
        text = f"{exc.filename}: {exc.strerror or text}"
    return " ".join(part.strip() for part in text.splitlines() if part.strip())


def _is_tty(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


# ================================================================== output
def prepare_out(out: str | None, default: str, *, force: bool, resume: bool) -> Path:
    """The output folder: created, and never a non-empty one unless asked.

    With no ``--out``, the default name is used, or ``NAME-2``, ``NAME-3``, ... if it
    is taken (a fresh folder every run); an explicit non-empty ``--out`` needs
    ``--force`` (overwrite) or ``--resume``.
    """
    if out is None:
        path = Path(default)
        if not resume:
            k = 2
            while path.exists() and (not path.is_dir() or any(path.iterdir())):
                path = Path(f"{default}-{k}")
                k += 1
    else:
        path = Path(out)
    if path.exists() and not path.is_dir():
        raise UsageError(f"--out {path}: exists and is not a folder; choose another --out")
    if resume:
        if not path.is_dir():
            raise UsageError(
                f"--resume: output folder {path} does not exist; give the --out of the "
                "interrupted run"
            )
        return path
    if path.is_dir() and any(path.iterdir()) and not force:
        raise UsageError(
            f"output folder {path} is not empty: choose another --out, add --force to "
            "overwrite it, or --resume to continue an interrupted fit there"
        )
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UsageError(f"--out {path}: cannot create the folder ({exc.strerror})") from None
    return path


def emit(text: str, out: str | None, *, what: str) -> None:
    """Write ``text`` to the file ``out``, or to standard output (None or ``-``)."""
    if out in (None, "-"):
        sys.stdout.write(text)
        return
    from vhfit._io import atomic_write  # numpy (its JSON encoder): not for every command

    try:
        parent = Path(out).resolve().parent
        if not parent.is_dir():
            raise UsageError(f"--out {out}: folder {parent} does not exist; create it first")
        atomic_write(Path(out), text)
    except OSError as exc:
        raise UsageError(f"--out {out}: cannot write ({exc.strerror})") from None
    print(f"wrote {what} to {out}", file=sys.stderr)


# ================================================================== progress
class Progress:
    """Live progress of a fit: one updating line on a terminal, periodic lines otherwise.

    Parameters
    ----------
    stream : text stream
        Where to write (stderr).
    quiet : bool
        Write nothing.
    every : float
        Seconds between lines when ``stream`` is not a terminal.
    scan : bool
        The fit scans the number of Prony terms: N is shown, from the callback's
        ``n_prony`` if it has one, else counted (a restart of the generation count
        means the next N, starting from ``first_n``; None hides N). A scan that fits
        two N side by side shows both on the line (each N that reported in the last
        ``RECENT`` seconds).
    """

    RECENT = 0.5

    def __init__(self, stream: TextIO, *, quiet: bool = False, every: float = 2.0,
                 scan: bool = False, first_n: int | None = 1):
        self.stream = stream
        self.quiet = quiet
        self.tty = _is_tty(stream)
        self.every = every
        self.scan = scan
        self.n = first_n
        self.last_gen = 0
        self.last_print = -math.inf
        self.width = 0
        self.last: dict | None = None
        self.latest: dict = {}  # N -> (time, report): each N's latest report

    def _text(self, d: dict) -> str:
        n = d.get("n_prony", self.n)
        now: dict = {}
        if self.scan and n is not None:
            now = {k: o for k, (t, o) in self.latest.items()
                   if t >= time.perf_counter() - self.RECENT}
            now[n] = d
        if len(now) > 1:
            return "  |  ".join(
                f"N={k}  generation {o['generation']:>5}  best {o['best']:.4g} %"
                for k, o in sorted(now.items())) + f"  elapsed {d['elapsed']:.1f} s"
        pre = f"N={n}  " if self.scan and n is not None else ""
        return (
            f"{pre}generation {d['generation']:>5}  best {d['best']:.4g} %  "
            f"mean {d['mean']:.4g} %  elapsed {d['elapsed']:.1f} s"
        )

    def __call__(self, d: dict) -> None:
        if "n_prony" in d:
            self.latest[d["n_prony"]] = (time.perf_counter(), d)
        elif d["generation"] < self.last_gen and self.n is not None:
            self.n += 1
        self.last_gen = d["generation"]
        self.last = d
        if self.quiet:
            return
        now = time.perf_counter()
        if self.tty:
            if now - self.last_print >= 0.1:
                text = self._text(d)
                self.stream.write("\r" + text.ljust(self.width))
                self.stream.flush()
                self.width = len(text)
                self.last_print = now
        elif now - self.last_print >= self.every:
            self.stream.write(self._text(d) + "\n")
            self.stream.flush()
            self.last_print = now

    def close(self) -> None:
        """End the updating line (terminal) or print the last state (not a terminal)."""
        if self.quiet or self.last is None:
            return
        if self.tty:
            self.stream.write("\r" + self._text(self.last).ljust(self.width) + "\n")
        else:
            self.stream.write(self._text(self.last) + "\n")
        self.stream.flush()


class Signals:
    """SIGINT/SIGTERM handling around a fit.

    The first signal asks the search to stop at the end of the current generation
    (the progress callback then raises KeyboardInterrupt, which :func:`vhfit.calibrate`
    catches to return the best individual so far): stopping on a generation boundary
    keeps the checkpoint consistent, so ``--resume`` reaches exactly the result of an
    uninterrupted run. A second signal interrupts at once. While the outputs are
    written, signals are deferred (the third one aborts anyway), so that an
    interrupted fit still leaves complete files.
    """

    def __init__(self):
        self.count = 0
        self.writing = False
        self.stopped_search = False
        self.old: dict = {}

    def __enter__(self):
        for sig in (signal.SIGINT, signal.SIGTERM):
            try:
                self.old[sig] = signal.signal(sig, self._handler)
            except (ValueError, OSError):  # not the main thread
                pass
        return self

    def __exit__(self, *exc):
        for sig, old in self.old.items():
            signal.signal(sig, old)
        return False

    def _handler(self, signum, frame):
        self.count += 1
        if self.writing:
            if self.count < 3:
                sys.stderr.write("\nvhfit: interrupted: finishing the output files...\n")
                return
        elif self.count == 1:
            sys.stderr.write("\nvhfit: interrupted: stopping after this generation and "
                             "writing the outputs (interrupt again to stop at once)\n")
            return
        raise KeyboardInterrupt

    def check(self) -> None:
        """Called at each generation boundary: stop the search if a signal came."""
        if self.count and not self.writing:
            self.stopped_search = True
            raise KeyboardInterrupt
