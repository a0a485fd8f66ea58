"""Why a search stopped: a :class:`Stop` record, its kind for the code and its sentence
for the reader.

The sentence (``message``) is what the summary, the results file's ``"stop_reason"``, the
cards and the command line show; the code decides by the kind (``kind``, a
:class:`StopKind`) and never by the sentence. A sentence read back from a file (a results
file, a checkpoint) gives its kind again (:meth:`Stop.read`): every sentence that a
search writes belongs to one kind.

The results file's ``"status"`` of a run (``"complete"``, ``"interrupted"``) is written
and read here too (:data:`STATUS`, :func:`interrupted_in`).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from enum import Enum

__all__ = ["Stop", "StopKind", "STATUS", "interrupted_in"]


class StopKind(Enum):
    """What ended a search (the kinds of :class:`Stop`)."""

    #: the best error reached the target
    TARGET = "target"
    #: a polish of the best member reached the target
    TARGET_POLISHED = "target_polished"
    #: the best–mean gap of a generation fell below ``tol``
    CONVERGED = "converged"
    #: the population gathered in one basin, ended by a polish of its best member
    GATHERED = "gathered"
    #: the mean error improved too little over a window of generations
    STALLED = "stalled"
    #: the time budget ran out
    MAX_TIME = "max_time"
    #: the generation budget ran out
    MAX_ITER = "maxiter"
    #: the user's callback asked to stop
    CALLBACK = "callback"
    #: Ctrl-C (or a signal): the best member so far
    INTERRUPTED = "interrupted"
    #: no member had a finite error for many generations
    NO_FINITE = "no_finite"
    #: no nonlinear constant to search
    NOTHING = "nothing"
    #: fitted by the spectrum route, without a search
    SPECTRUM = "spectrum"
    #: any other end the solver reported, in its own words
    OTHER = "other"


@dataclass(frozen=True)
class Stop:
    """Why a search stopped: its kind and the sentence shown for it.

    ``str(stop)`` is the sentence, so that a stop prints as the sentence did, and a stop
    equals its sentence (``cal.stop_reason == "maxiter"``, as for a string): the user's
    comparisons keep working, while vhfit's own code asks the kind.

    Examples
    --------
    >>> from vhfit.calibration import Stop, StopKind
    >>> stop = Stop.of(StopKind.MAX_TIME)
    >>> str(stop), stop.interrupted
    ('max_time', False)
    >>> Stop.read("interrupted").kind is StopKind.INTERRUPTED
    True
    >>> stop == "max_time"
    True
    """

    kind: StopKind
    message: str

    def __str__(self) -> str:
        return self.message

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Stop):
            return self.kind is other.kind and self.message == other.message
        if isinstance(other, str):
            return self.message == other
        return NotImplemented

    def __hash__(self) -> int:  # equal to its sentence, so hashed as the sentence
        return hash(self.message)

    @property
    def interrupted(self) -> bool:
        """Whether the search was interrupted (its result the best member so far)."""
        return self.kind is StopKind.INTERRUPTED

    @classmethod
    def of(cls, kind: StopKind) -> Stop:
        """The stop of a kind whose sentence is fixed (not :attr:`StopKind.STALLED`,
        :attr:`StopKind.NO_FINITE` or :attr:`StopKind.OTHER`, which say more)."""
        return cls(kind, _FIXED[kind])

    @classmethod
    def stalled(cls, rel: float, window: int) -> Stop:
        """The mean error improved by less than ``rel`` over ``window`` generations."""
        return cls(StopKind.STALLED, f"mean error improved < {rel:.0%} over {window} "
                                     "generations")

    @classmethod
    def no_finite(cls, generations: int) -> Stop:
        """No member had a finite error in ``generations`` generations."""
        return cls(StopKind.NO_FINITE, f"no finite error in {generations} generations")

    @classmethod
    def read(cls, message: str) -> Stop:
        """The stop a sentence written by a search stands for (a results file's
        ``"stop_reason"``, a checkpoint's); a sentence of no known kind is
        :attr:`StopKind.OTHER`."""
        message = str(message)
        kind = _BY_MESSAGE.get(message)
        if kind is None:
            kind = next((k for k, p in _PATTERNS.items() if p.fullmatch(message)),
                        StopKind.OTHER)
        return cls(kind, message)


#: The sentence of each kind that says nothing more (unchanged from the sentences the
#: results files of earlier releases hold).
_FIXED = {
    StopKind.TARGET: "target reached",
    StopKind.TARGET_POLISHED: "target reached by a polish of the best member",
    StopKind.CONVERGED: "converged",
    StopKind.GATHERED: "converged: population gathered, ended by a polish of the best "
                       "member",
    StopKind.MAX_TIME: "max_time",
    StopKind.MAX_ITER: "maxiter",
    StopKind.CALLBACK: "callback",
    StopKind.INTERRUPTED: "interrupted",
    StopKind.NOTHING: "nothing to search",
    StopKind.SPECTRUM: "per-decade spectrum (NNLS on a tau grid, pruning, free-tau "
                       "refinement)",
}
_BY_MESSAGE = {m: k for k, m in _FIXED.items()}
#: The sentences of the kinds that carry numbers (:meth:`Stop.stalled`,
#: :meth:`Stop.no_finite`), as read back.
_PATTERNS = {
    StopKind.STALLED: re.compile(r"mean error improved < \S+% over \d+ generations"),
    StopKind.NO_FINITE: re.compile(r"no finite error in \d+ generations"),
}

#: The results file's ``"status"`` word of a run, by whether it was interrupted.
STATUS = {False: "complete", True: "interrupted"}
_INTERRUPTED_BY_WORD = {w: flag for flag, w in STATUS.items()}


def interrupted_in(record: Mapping) -> bool:
    """Whether a results file's entries (or their ``context``) say that its run was
    interrupted: its ``"interrupted"`` flag, else its ``"status"`` word."""
    if "interrupted" in record:
        return bool(record["interrupted"])
    return _INTERRUPTED_BY_WORD.get(record.get("status"), False)
