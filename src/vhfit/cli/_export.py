"""``vhfit export``: the solver card of a results file."""

from __future__ import annotations

from vhfit.cli._cards import card_options, card_shift
from vhfit.cli._common import EXIT_OK, UsageError, emit, one_line
from vhfit.cli._results import load_calibration
from vhfit.export import export

__all__ = ["cmd_export"]


def cmd_export(args) -> int:
    """``vhfit export RESULTS.json --to SOLVER``."""
    cal = load_calibration(args.results)
    # several fits (vhfit fit --for abaqus,lsdyna): the card of a solver from its own fit
    own = (cal.context.get("card_fits") or {}).get(args.to)
    fit = cal.fits.get(own, cal) if isinstance(own, str) else cal
    kw = {}
    if args.name:
        kw["name"] = args.name
    if args.to != "json":
        kw.update(card_options(args))
        if args.abaqus_explicit:
            if args.to != "abaqus":
                raise UsageError(f"--explicit is an Abaqus variant: drop it, or give --to abaqus "
                                 f"(not {args.to})")
            kw["explicit"] = True
    shift, _ = card_shift(cal)
    if shift is not None and args.to != "json":
        kw["shift"] = shift
    try:
        text = export(fit, to=args.to, **kw)
    except ValueError as exc:
        raise UsageError(f"--to {args.to}: {one_line(exc)}") from None
    if not text.endswith("\n"):
        text += "\n"
    emit(text, args.out, what=f"{args.to} card")
    return EXIT_OK
