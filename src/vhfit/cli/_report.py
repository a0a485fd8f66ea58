"""``report.html`` of ``vhfit fit``: the run's cards, check, plots and command handed to
:func:`vhfit.report.write_report`."""

from __future__ import annotations

import shlex
from pathlib import Path

from vhfit import report
from vhfit.cli._cards import CARD_FILES
from vhfit.cli._common import one_line

__all__ = ["FILE", "write_fit_report"]

FILE = "report.html"


def write_fit_report(cal, curves, out: Path, cards, plots: dict, args, *, command,
                     label, inputs, interrupted: bool, comparison=None,
                     drawn: tuple | None = None) -> tuple[dict[str, str], str | None]:
    """Write ``report.html`` into ``out``: ({file: what it is}, None), or ({}, why not).

    The cards are read back from the files written (what the user gets), the PNG plots
    already drawn are inlined rather than drawn again, and so are the report's own
    figures where ``drawn`` holds them (:func:`vhfit.report.draw_figures`); a failure
    never stops the other outputs, it becomes a note in the summary.
    """
    try:
        report.write_report(
            cal, out / FILE, curves, command=shlex.join(["vhfit", *command]),
            cards={**{s: (out / f).read_text() for s, f in cards.files.items()
                      if s in CARD_FILES and s != "json"},
                   **{s: None for s in cards.errors if s in CARD_FILES}},  # no card: why
            card_check=cards.check, card_warnings=cards.warnings,
            fit_warnings=cards.fit_warnings,
            card_notes={**cards.notes, **{s: [f"no card: {e}"] for s, e in cards.errors.items()}},
            interrupted=interrupted, title=label, inputs=inputs,
            figures=not args.no_plot, images={k: out / f for k, f in plots.items()},
            comparison=comparison, drawn=drawn)
    except Exception as exc:  # the report never stops the other outputs
        return {}, f"no report: {one_line(exc)}"
    return {FILE: "everything above as one page to open in a browser"}, None
