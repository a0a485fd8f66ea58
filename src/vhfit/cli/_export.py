"""``vhfit export``: the solver card of a results file."""

from __future__ import annotations

from vhfit.cli._cards import card_options
from vhfit.cli._common import EXIT_OK, UsageError, count_prony, emit, load_results, one_line
from vhfit.cli._plugins import resolve_model_name
from vhfit.export import export
from vhfit.model import ViscoHyperelastic

__all__ = ["cmd_export"]


def cmd_export(args) -> int:
    """``vhfit export RESULTS.json --to SOLVER``."""
    res = load_results(args.results)
    # several fits (vhfit fit --for abaqus,lsdyna): the card of a solver from its own fit
    own = (res.get("fits") or {}).get((res.get("card_fits") or {}).get(args.to))
    if isinstance(own, dict) and "params" in own and "hyperelastic" in own:
        res = own
    name = resolve_model_name(res["hyperelastic"])
    params = res["params"]
    try:
        model = ViscoHyperelastic(name, count_prony(params))
        model.check(params)
    except ValueError as exc:
        raise UsageError(f"{args.results}: {one_line(exc)}") from None
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
    try:
        text = export(model, params, to=args.to, **kw)
    except ValueError as exc:
        raise UsageError(f"--to {args.to}: {one_line(exc)}") from None
    if not text.endswith("\n"):
        text += "\n"
    emit(text, args.out, what=f"{args.to} card")
    return EXIT_OK
