"""The options of ``vhfit fit`` as a calibration's settings (:func:`fit_settings`), and
its time–temperature shift (``--shift``, ``--tref``: :func:`check_shift`)."""

from __future__ import annotations

from typing import Any

from vhfit import hyperelastic, tts
from vhfit.calibration import CalibrationSettings, bound_problem, bounds_terms
from vhfit.cli._common import UsageError, one_line

__all__ = ["fit_settings", "check_shift", "cli_bounds"]


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
    bounds = cli_bounds(args, model)
    if bounds:
        kw["bounds"] = bounds
    if args.stability_range is not None:  # else the data's range, as from Python
        kw["stability_range"] = args.stability_range
    return CalibrationSettings(
        model, args.prony, tau_strategy=strategy, method=args.method, seed=args.seed,
        workers=args.workers, popsize=args.popsize, maxiter=args.maxiter, target=args.target,
        scan_workers="auto" if args.scan_workers == "auto" else int(args.scan_workers),
        polish=not args.no_polish, g_inf_min=args.g_inf_min, max_time=args.max_time,
        checkpoint=checkpoint, checkpoint_every=args.checkpoint_every, resume=args.resume,
        **kw)


def cli_bounds(args, model: str) -> dict[str, tuple[float, float]] | None:
    """``calibrate``'s ``bounds=`` from ``--bounds NAME=LO:HI`` (repeatable), checked
    against the law and the number of Prony terms before anything is read or written.

    A name is matched case-insensitively to the parameter it names (``ALPHA1`` is
    ``alpha1``); a parameter given twice, a name the law with ``--prony`` terms does not
    have, or limits outside the parameter's physical range are one-line errors naming
    ``--bounds`` and the fix.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options of ``vhfit fit`` (``bounds``: (NAME, LO, HI) triples or None).
    model : str
        The law, resolved.

    Returns
    -------
    dict or None
        Parameter -> (LO, HI); None without ``--bounds``.

    Raises
    ------
    UsageError
        The first bad ``--bounds`` (one line).

    Examples
    --------
    >>> from vhfit.cli._parser import build_parser
    >>> args = build_parser().parse_args(["fit", "a.csv", "--model", "ogden",
    ...                                   "--bounds", "Alpha1=-40:40"])
    >>> cli_bounds(args, "ogden")
    {'alpha1': (-40.0, 40.0)}
    """
    given = args.bounds
    if not given:
        return None
    n_terms = bounds_terms(args.prony, args.max_prony)
    try:
        names = list(hyperelastic.get(model).param_names)
    except ValueError:  # a law not registered: run_fit names it
        names = []
    names += [f"{g}{i}" for i in range(1, n_terms + 1) for g in ("G", "tau")]
    canonical = {n.lower(): n for n in names}
    out: dict[str, tuple[float, float]] = {}
    for name, lo, hi in given:
        text = f"--bounds {name}={lo:g}:{hi:g}"
        name = canonical.get(name.lower(), name)
        if name in out:
            raise UsageError(f"{text}: {name} given twice; give each parameter once")
        fix = bound_problem(name, lo, hi, model, n_terms)
        if fix is not None:
            if "unknown parameter" in fix:
                fix += " (see 'vhfit models'; --model chooses the law)"
            raise UsageError(f"{text}: {fix}")
        out[name] = (lo, hi)
    return out


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
        raise UsageError(one_line(exc)) from None
    return law, (ref.items if ref.source != "none" else None)
