"""``vhfit export``: the solver card of a results file."""

from __future__ import annotations

from vhfit.calibration import interrupted_in
from vhfit.cli._cards import (
    card_options,
    card_shift,
    json_marked,
    mark,
    refusal,
    unfinished,
)
from vhfit.cli._common import EXIT_OK, UsageError, emit
from vhfit.cli._results import load_calibration
from vhfit.export import export, get_solver, solvers

__all__ = ["cmd_export"]


def cmd_export(args, argv=()) -> int:
    """``vhfit export RESULTS.json --to SOLVER``."""
    cal = load_calibration(args.results)
    # several fits (vhfit fit --for A,B): the card of a solver from its own fit
    own = (cal.context.get("card_fits") or {}).get(args.to)
    fit = cal.fits.get(own, cal) if isinstance(own, str) else cal
    kw = {}
    if args.name:
        kw["name"] = args.name
    variants = [k[len("variant_"):] for k, v in vars(args).items()
                if k.startswith("variant_") and v]
    if args.to != "json":
        rec = get_solver(args.to)
        kw.update(card_options(args, rec.name))
        kw.update({v: True for v in variants if v in rec.variants})
    for v in variants:
        if args.to == "json" or v not in get_solver(args.to).variants:
            owners = [s for s in solvers() if v in get_solver(s).variants]
            raise UsageError(f"--{v} is a variant of the {' or '.join(owners)} card: drop it, "
                             f"or give --to {' or '.join(owners)} (not {args.to})")
    shift, _ = card_shift(cal)
    if shift is not None and args.to != "json":
        kw["shift"] = shift
    try:
        text = export(fit, to=args.to, **kw)
    except ValueError as exc:
        raise UsageError(f"--to {args.to}: {refusal(exc, args.to)}") from None
    if not text.endswith("\n"):
        text += "\n"
    status = unfinished(fit, interrupted_in(cal.context))
    if args.to == "json":  # an interrupted or unconverged fit says so first, as vhfit fit's
        text = json_marked(text, status)
    elif status:
        text = mark(text, get_solver(args.to).comment, status)
    emit(text, args.out, what=f"{args.to} card")
    return EXIT_OK
