"""The options of ``vhfit fit`` as a calibration's settings (:func:`fit_settings`)."""

from __future__ import annotations

from typing import Any

from vhfit.calibration import CalibrationSettings

__all__ = ["fit_settings"]


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
    if getattr(args, "tref", None) is not None:
        kw["T_ref"] = args.tref
    return CalibrationSettings(
        model, args.prony, tau_strategy=strategy, method=args.method, seed=args.seed,
        workers=args.workers, popsize=args.popsize, maxiter=args.maxiter, target=args.target,
        polish=not args.no_polish, g_inf_min=args.g_inf_min, max_time=args.max_time,
        checkpoint=checkpoint, checkpoint_every=args.checkpoint_every, resume=args.resume,
        **kw)
