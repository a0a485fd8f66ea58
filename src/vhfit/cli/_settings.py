"""The options of ``vhfit fit`` as a calibration's settings (:func:`fit_settings`), and
its time–temperature shift (``--shift``, ``--tref``: :func:`check_shift`)."""

from __future__ import annotations

from typing import Any

from vhfit import tts
from vhfit.calibration import CalibrationSettings
from vhfit.cli._common import UsageError, one_line

__all__ = ["fit_settings", "check_shift"]


def fit_settings(args, *, model: str, strategy: str, checkpoint: str | None = None,
                 shift_law=None) -> CalibrationSettings:
    """The settings of ``vhfit fit`` (and ``demo``) from its parsed options, checked.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options of ``vhfit fit``.
    model : str
        The law, resolved (``--model`` or a plug-in's name).
    strategy : str
        The τ strategy, checked (``--strategy``).
    checkpoint : str, optional
        The checkpoint file of the run's first fit (``--resume`` needs it).
    shift_law : optional
        The time–temperature shift law of ``--shift`` at ``--tref``.

    Returns
    -------
    CalibrationSettings
        In the hereditary formulation, without a callback: each fit of the run sets its
        own formulation, checkpoint and callback (:func:`dataclasses.replace`).

    Raises
    ------
    ValueError
        An option out of range (one line naming the setting and the fix).

    Examples
    --------
    >>> from vhfit.cli._parser import build_parser
    >>> args = build_parser().parse_args(["fit", "a.csv", "--seed", "3"])
    >>> fit_settings(args, model="mooney_rivlin", strategy=args.strategy).seed
    3
    """
    kw: dict[str, Any] = {}
    if args.prony == "auto":  # else the default, as calibrate is called from Python
        kw["max_prony"] = args.max_prony
    if shift_law is not None:
        kw["shift_factors"] = shift_law
    if args.tref is not None:
        kw["T_ref"] = args.tref
    if args.stability_range is not None:  # else the data's range, as from Python
        kw["stability_range"] = args.stability_range
    return CalibrationSettings(
        model, args.prony, tau_strategy=strategy, method=args.method, seed=args.seed,
        workers=args.workers, popsize=args.popsize, maxiter=args.maxiter, target=args.target,
        polish=not args.no_polish, g_inf_min=args.g_inf_min, max_time=args.max_time,
        checkpoint=checkpoint, checkpoint_every=args.checkpoint_every, resume=args.resume,
        **kw)


def _shift_law(args):
    """The law of ``--shift`` at ``--tref`` (None without ``--shift``)."""
    given = args.shift
    if given is None:
        return None
    name, vals = given
    text = f"{name}:{','.join(f'{v:g}' for v in vals)}"
    if args.tref is None:
        raise UsageError(f"--shift {text}: give --tref T, the reference temperature of the law")
    try:
        if name == "wlf":
            return tts.WLF(C1=vals[0], C2=vals[1], T_ref=args.tref)
        return tts.Arrhenius(vals[0], args.tref, *vals[1:])
    except ValueError as exc:
        raise UsageError(f"--shift {text}: {one_line(exc)}") from None


def check_shift(curves, args) -> tuple[Any, list | None]:
    """Tests at several temperatures: their shift to --tref, checked before anything is
    written. Returns the law of ``--shift`` (or None) and the tests at the reference for
    the outputs (None when every test is at one temperature)."""
    law = _shift_law(args)
    try:
        ref = tts.shift_to_reference(curves, shift_factors=law, T_ref=args.tref)
    except ValueError as exc:
        raise UsageError(f"{one_line(exc)} (command line: --shift wlf:C1,C2 --tref T)"
                         ) from None
    return law, (ref.items if ref.source != "none" else None)
