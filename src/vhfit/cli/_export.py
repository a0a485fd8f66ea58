"""``vhfit export``: the solver card of a results file."""

from __future__ import annotations

from vhfit.cli._cards import card_options
from vhfit.cli._common import EXIT_OK, UsageError, count_prony, emit, load_results, one_line
from vhfit.cli._plugins import resolve_model_name
from vhfit.export import export
from vhfit.model import ViscoHyperelastic
from vhfit.tts import WLF

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
    shift = _wlf(res.get("shift"), args.results)
    if shift is not None and args.to != "json":
        kw["shift"] = shift
    try:
        text = export(model, params, to=args.to, **kw)
    except ValueError as exc:
        raise UsageError(f"--to {args.to}: {one_line(exc)}") from None
    if not text.endswith("\n"):
        text += "\n"
    emit(text, args.out, what=f"{args.to} card")
    return EXIT_OK


def _wlf(entry, path):
    """The WLF shift of a results file's ``shift`` entry (None without one, or for another
    law: the cards take WLF only)."""
    if not isinstance(entry, dict) or entry.get("law") != "wlf":
        return None
    c = entry.get("constants") or {}
    try:
        return WLF(C1=float(c["C1"]), C2=float(c["C2"]), T_ref=float(c["T_ref"]))
    except (KeyError, TypeError, ValueError) as exc:
        raise UsageError(f"{path}: shift entry {c!r} is not a WLF law ({one_line(exc)}); "
                         "give the results.json written by vhfit fit") from None
