"""The calibration workflow: curves in, a calibrated material out (:func:`calibrate`)."""

from __future__ import annotations

import itertools
import os
import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from vhfit._blas import one_blas_thread
from vhfit._words import in_python, setting, worded
from vhfit.calibration import _nesting, _spectrum
from vhfit.calibration._admissible import data_stability_range
from vhfit.calibration._bounds import (
    bound_hit_headlines,
    bound_hits,
    no_stable_headline,
    pinned_headlines,
    search_bounds,
    stable_box,
    widen_bounds,
)
from vhfit.calibration._identify import DEFAULT_N_PRONY, viscous_evidence
from vhfit.calibration._polish import polish
from vhfit.calibration._report import finish
from vhfit.calibration._result import Calibration, CalibrationWarning
from vhfit.calibration._scan import order_scan
from vhfit.calibration._search import (
    CalibrationError,
    final_polish,
    run_search,
    search_problem,
)
from vhfit.calibration._settings import (
    DEFAULT_DECADES_ABOVE,
    DEFAULT_DECADES_BELOW,
    DEFAULT_TAU_STRATEGY,
    DEFAULT_TOL,
    CalibrationSettings,
    bounds_for_terms,
)
from vhfit.calibration._space import SPACES, Problem
from vhfit.calibration._stop import Stop, StopKind
from vhfit.data import TestItem, is_moduli, read_csv
from vhfit.diagnostics import rate_sensitivity
from vhfit.hyperelastic import get as get_law
from vhfit.model import model_from_spec
from vhfit.modes import refusal_for
from vhfit.tts import shift_to_reference

__all__ = ["calibrate", "CalibrationError"]

#: Stretches per mode of the final stability check (vhfit.stability.drucker's default):
#: the admissible grid of a fit searched again where the search's grid missed a dip.
CHECK_POINTS = 400


def _as_curves(curves) -> list:
    """A list of curves from Curve objects, file paths (read with read_csv), or a mix."""
    if isinstance(curves, (TestItem, str, os.PathLike)):
        curves = [curves]
    try:
        items = list(curves)
    except TypeError:
        raise ValueError(
            f"curves must be Curve objects or CSV paths, got {type(curves).__name__}"
        ) from None
    out = []
    for i, c in enumerate(items):
        if isinstance(c, (str, os.PathLike)):
            out += read_csv(c)
        elif isinstance(c, TestItem):
            out.append(c)
        else:
            raise ValueError(
                f"curves[{i}] is a {type(c).__name__}: give vhfit.Curve objects "
                "(vhfit.Curve(strain=..., stress=..., strain_rate=...)), vhfit.FrequencySweep "
                "or vhfit.Relaxation objects, or CSV paths"
            )
    if not out:
        raise ValueError("calibrate needs at least one curve")
    return out


def calibrate(
    curves: Sequence,
    hyperelastic="mooney_rivlin",
    n_prony: int | str | None = None,
    *,
    tau_strategy: str | Callable = DEFAULT_TAU_STRATEGY,
    bounds: str | dict = "auto",
    objective: str = "rmsape",
    method: str = "separable",
    seed=None,
    workers=1,
    scan_workers: int | str = "auto",
    popsize: int | None = None,
    maxiter: int | None = None,
    tol: float = DEFAULT_TOL,
    target: float = 1e-4,
    stall: tuple[float, int] = (0.02, 2000),
    polish: bool = True,
    g_inf_min: float = 1e-6,
    max_time: float | None = None,
    max_prony: int = 5,
    order_tol: float = 0.05,
    prune_tol: float = 1e-6,
    decades_below: float = DEFAULT_DECADES_BELOW,
    decades_above: float = DEFAULT_DECADES_ABOVE,
    stability_range: tuple[float, float] | None = None,
    uncertainty: bool = True,
    callback: Callable | None = None,
    rtol: float = 1e-6,
    de_options: dict | None = None,
    checkpoint=None,
    checkpoint_every: float = 5.0,
    resume: bool = False,
    check_rates: bool = True,
    formulation: str = "hereditary",
    shift_factors=None,
    T_ref: float | None = None,
) -> Calibration:
    """Calibrate a hyperelastic law + Prony series to curves at several strain rates.

    Parameters
    ----------
    curves : Curve, path, or sequence of them
        Measured curves (``.history``, ``.target_stress``, ``.measure``, ``.strain_rate``,
        optional ``.weight`` and ``.name``; see :class:`vhfit.Curve`), or CSV files read
        with :func:`vhfit.read_csv`. Frequency sweeps and relaxation tests
        (:class:`vhfit.FrequencySweep`, :class:`vhfit.Relaxation`) may stand beside them:
        their moduli constrain the same constants through the model's small-strain limit
        (E∞ = 3 μ0 of the law and the Prony terms; docs/theory.md §10), each modulus
        measured by its relative error.
    hyperelastic : str
        Registered hyperelastic model name.
    n_prony : int, "auto" or None
        Number of Prony terms; "auto" fits N = 1, 2, ... while a term lowers the best
        error by ``order_tol`` (relative) or more, up to ``max_prony``, and keeps the
        smallest N whose error is within ``order_tol`` of the best. None (default):
        2, or 0 when the data cannot separate elastic from viscous response (one rate
        and monotonic loading, or only equilibrium curves; the reason is recorded in
        ``options["n_prony_reason"]`` and printed by :meth:`Calibration.summary`). A
        number > 0 given for such data is fitted, with a headline warning.
    tau_strategy : {"free", "semifree", "fixed"} or callable
        How the τ bounds are cut from the Eq. 22 range (docs/theory.md §11). Default "free".
    decades_below, decades_above : float
        Decades of that range below the fastest and above the slowest time scale of the
        tests (1/rate, 1/ω of a sweep, t of a relaxation test): 3 and 1 by default, one
        decade more below than the paper's Eq. 22, where a real τ1 can sit.
    bounds : "auto" or dict
        Search bounds; a dict overrides the automatic ones per parameter
        (``{"tau1": (1e-5, 1e-3), "C10": (0, 1)}``; τ bounds in s; equal limits fix a
        parameter). Each name is a constant of the law or a Prony term ``G<i>``/``tau<i>``
        the fit may have (i <= ``n_prony``; with ``"auto"`` <= ``max_prony``, each N's fit
        using the terms it has), its limits low <= high, finite (a constant the law is
        linear in may be unbounded) and inside the physical range (the law's own, G_i >=
        0, τ_i > 0): else a one-line ``ValueError`` before any computation (command line:
        ``--bounds NAME=LO:HI``).
    objective : {"rmsape", "rmse", "relative_l2"} or callable
        Eq. 20 in percent (default) or an alternative of :mod:`vhfit.objective`; per-curve
        and per-point weights of the curves apply.
    method : {"separable", "full"}
        Variable projection over (shape, log τ) with NNLS for the moduli (default), or
        the paper's all-parameter DE.
    seed : int or None
        Seeds the global search; same seed, same result.
    workers : int or map-like callable
        Passed to the DE (only the full method evaluates in parallel this way).
    scan_workers : {"auto", 1, 2}
        Processes the order scan (``n_prony="auto"``) fits its N on: 2 side by side (a
        forked child fits N = 3 while this process fits N = 1 and 2; the same result to
        the bit, in 55–70 % of the wall time on long records), 1 one after the other.
        "auto" (default): 2 where at least two CPUs are usable and this process may
        fork (Linux, no other Python thread; else 1). The result's
        ``options["scan_processes"]`` says which ran.
    popsize : int, optional
        Population size, exactly (default 64 separable, initialised by a Sobol
        sequence, and 60 full, the paper's, by Latin hypercube).
    maxiter : int, optional
        Generation cap (default 1000 separable, 100 000 full).
    tol : float
        Best–mean gap of a generation, relative to its mean, that ends the search
        (:class:`vhfit.optimize.BestMeanGap`; default 1e-6; 1e-5, the paper's 0.001 %,
        for the full method).
    stall : (float, int)
        The paper's first criterion: stop when the mean error improved by less than
        this fraction over this many generations (:class:`vhfit.optimize.MeanImprovement`).
    target : float
        Objective value (RMSAPE in percent) below which the search stops at once
        (:class:`vhfit.optimize.TargetValue`). The stopping criteria are those of
        docs/theory.md §12; ``max_time`` adds :class:`vhfit.optimize.MaxTime`.
    polish : bool
        Refine all parameters by bounded least squares afterwards.
    g_inf_min : float
        Floor on g∞ (FE solvers reject g∞ = 0); a warning says when it is active.
    max_time : float, optional
        Seconds after which the search stops with the best result so far.
    stability_range : (float, float) or None
        Stretch range (low < 1 < high) over which the fitted law must be Drucker-stable
        in the stability check's tests, in tension and compression: the search covers
        exactly the laws stable there with a positive initial modulus (docs/theory.md
        §11). None (default): the data's smallest and largest principal stretch, each
        10 % further from 1 (``options["stability_range"]`` records the range used).
    uncertainty : bool
        Compute 95 % intervals from the Jacobian.
    callback : callable, optional
        Called each generation with a dict (generation, best, mean, elapsed, n_prony, x);
        returning True stops the search.
    rtol : float
        Accuracy of the model evaluation.
    de_options : dict, optional
        Further keywords of the search's solver,
        :class:`vhfit.optimize.DifferentialEvolutionSolver` (SciPy's, plus ``strategy``
        ``"jde"``, ``"shade"`` or ``"lshade"`` and ``repair``), e.g. ``{"strategy":
        "rand1bin", "mutation": 0.8}``. Settings that calibrate owns (population size,
        generation cap, tolerances, seed, polish, callback, workers) are refused with
        the argument to use instead.
    checkpoint : path, optional
        File where the search state is written atomically every ``checkpoint_every``
        seconds (and at the end); with ``resume=True`` the search continues from it and
        reaches the same result as an uninterrupted run with the same seed.
    checkpoint_every : float
        Seconds between checkpoints.
    resume : bool
        Continue from ``checkpoint`` if it exists (it must belong to the same fit).
    check_rates : bool
        Warn, naming the curves, when the data's rise of stress with strain rate exceeds
        what the model can represent (:func:`vhfit.diagnostics.rate_sensitivity`; the
        paper's gelatin argument).
    formulation : str
        The viscoelastic formulation fitted (:mod:`vhfit.formulations`): "hereditary"
        (default; the corrected Eq. 19) or another registered one, such as the one a
        solver integrates (:data:`vhfit.formulations.SOLVER_FORMULATIONS`), so that the
        constants reproduce the data in that solver's law (docs/theory.md §14). The
        result's ``model.formulation`` names it.
    shift_factors : law, dict or (temperatures, log10 a_T), optional
        Time–temperature shift of tests at several temperatures (``temperature`` of
        sweeps and relaxation tests, ``metadata["temperature"]`` of curves): a law
        (:class:`vhfit.tts.WLF`, ...), a dict {T: log10 a_T} or a pair of arrays. Without
        it, tests at several temperatures are shifted with the factors built from the
        sweeps' overlap (docs/dma.md). The result's ``shift`` is the law (given, or WLF
        fitted to the factors used) and ``shift_table`` the log10 a_T per temperature.
    T_ref : float, optional
        Reference temperature of the fitted constants (default: the law's, or the middle
        sweep temperature).

    Returns
    -------
    Calibration
        Always with a finite error.

    Raises
    ------
    CalibrationError
        No parameter set the search tried has a finite error (the law is undefined on the
        data; the message names a bound at fault and the ``bounds`` that reach the data).
        Its ``checkpoint`` is removed. Interrupted before anything finite was found:
        ``KeyboardInterrupt``, the checkpoint kept for ``resume``.
    ValueError
        A bad argument (one line naming it and the fix).

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    >>> true = dict(C10=0.01, C01=0.005, G1=0.5, tau1=0.01)
    >>> eps = np.linspace(-0.05, -0.5, 10)
    >>> curves = [vhfit.Curve(strain=eps, stress=m.stress(true, strain=eps, strain_rate=r,
    ...           measure="engineering"), strain_rate=r) for r in (-1.0, -100.0)]
    >>> cal = vhfit.calibrate(curves, n_prony=1, seed=0)
    >>> cal.rmsape < 1e-3
    True
    """
    t0 = time.perf_counter()
    curves = _as_curves(curves)
    settings = CalibrationSettings(  # every argument checked here, before any computation
        hyperelastic, n_prony, tau_strategy=tau_strategy, bounds=bounds, objective=objective,
        method=method, seed=seed, workers=workers, scan_workers=scan_workers,
        popsize=popsize, maxiter=maxiter, tol=tol, target=target, stall=stall,
        polish=polish, g_inf_min=g_inf_min, max_time=max_time,
        max_prony=max_prony, order_tol=order_tol, prune_tol=prune_tol,
        decades_below=decades_below, decades_above=decades_above,
        stability_range=stability_range, uncertainty=uncertainty, callback=callback,
        rtol=rtol, de_options=de_options, checkpoint=checkpoint,
        checkpoint_every=checkpoint_every, resume=resume, check_rates=check_rates,
        formulation=formulation, shift_factors=shift_factors, T_ref=T_ref)
    s = settings
    refuse_unrepresentable(curves, s.hyperelastic)
    ref = shift_to_reference(curves, shift_factors=s.shift_factors, T_ref=s.T_ref)
    curves = ref.items  # tests at several temperatures: all at T_ref
    unidentified = viscous_evidence(curves)
    default_reason = unidentified if s.n_prony is None else None
    n_prony = s.n_prony
    if n_prony is None:
        n_prony = 0 if unidentified else DEFAULT_N_PRONY
        named = sorted(set(s.bounds) - set(bounds_for_terms(s.bounds, n_prony))
                       ) if isinstance(s.bounds, dict) else []
        if named:
            raise worded(ValueError,
                f"bounds name {', '.join(named)} but the fit has no Prony terms by default "
                f"({unidentified}): give {setting('n_prony=N', '--prony N')} to fit some, "
                "or drop those bounds")
    rate_msgs: list[str] = []
    if s.check_rates:
        n_check = s.max_prony if isinstance(n_prony, str) else int(n_prony)
        rate_msgs = rate_sensitivity([c for c in curves if not is_moduli(c)], s.hyperelastic,
                                     n_check)
    by_spectrum = _spectrum.applies(curves, s) and n_prony != 0
    if by_spectrum:  # sweeps and relaxation tests alone: the per-decade spectrum
        cal = _by_spectrum(curves, s, None if isinstance(n_prony, str) else int(n_prony), t0)
    else:
        with one_blas_thread():  # small solves: BLAS threads only wait for cores
            cal = (order_scan(curves, s, t0, _calibrate_n) if isinstance(n_prony, str) else
                   _calibrate_n(curves, s, int(n_prony), checkpoint=s.checkpoint,
                                max_time=s.max_time, t0=t0))
    for m in rate_msgs:  # the data ask for more rate sensitivity than the model has
        warnings.warn(m, CalibrationWarning, stacklevel=2)
    for m in ref.notes:  # the shift law's fit (a degenerate WLF and the law chosen)
        warnings.warn(m, CalibrationWarning, stacklevel=2)
    warns = list(ref.notes) + rate_msgs + cal.warnings
    heads, options = list(ref.notes) + list(cal.headlines), dict(cal.options)
    if default_reason:
        options["n_prony_reason"] = f"no Prony terms by default: {default_reason}"
    elif unidentified and cal.n_prony > 0:
        msg = (f"the data cannot separate elastic from viscous response ({unidentified}): "
               f"the {cal.n_prony} Prony term(s) are not identified by them; add tests at "
               f"other rates, a hold or an unloading, or fit {setting('n_prony=0', '--prony 0')}")
        warnings.warn(CalibrationWarning(msg), stacklevel=2)
        msg = in_python(msg)
        warns.insert(0, msg)
        heads.insert(0, msg)
    for msg in outside_bounds(s.bounds, cal.params):  # never silently past a user's limit
        warnings.warn(msg, CalibrationWarning, stacklevel=2)
        warns.insert(0, msg)
        heads.insert(0, msg)
    return replace(cal, warnings=warns, headlines=heads, options=options, **_shift_of(ref))


def refuse_unrepresentable(curves, hyperelastic) -> None:
    """A CalibrationError naming the first test the law cannot represent at all.

    A test that changes the volume (confined compression, J = λ; a volumetric test) is
    refused by an incompressible law before any search, in one line that says why and
    what would work (the test's record, :func:`vhfit.modes.refusal_for`): fitted as
    uniaxial, it would give cards that look fine and are wrong.

    Examples
    --------
    >>> import vhfit
    >>> from vhfit.calibration._workflow import refuse_unrepresentable
    >>> c = vhfit.Curve(strain=[-0.1, -0.2], stress=[-0.1, -0.3], strain_rate=-0.01,
    ...                 deformation="confined", name="foam")
    >>> refuse_unrepresentable([c], "neo_hooke")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    vhfit.calibration._search.CalibrationError: curve 'foam': an incompressible law ...
    """
    law = get_law(hyperelastic)
    for c in curves:
        why = refusal_for(law, c.deformation)
        if why:
            raise CalibrationError(f"curve {c.name!r}: {why} ({law.name} is incompressible)")


def outside_bounds(bounds, params: dict) -> list[str]:
    """One message per fitted constant outside the limits the user gave in ``bounds``.

    The search, the exact solve of the moduli and the polish keep every parameter within
    its limits; but Prony terms whose τ coincide are merged after the search (and the
    terms re-sorted by τ), so a limit given to one term may end on the merged one. Such
    a result is named, never silently passed.

    Parameters
    ----------
    bounds : "auto" or dict
        ``calibrate``'s ``bounds=``.
    params : dict
        The fitted constants.

    Returns
    -------
    list of str

    Examples
    --------
    >>> from vhfit.calibration._workflow import outside_bounds
    >>> outside_bounds({"G1": (0.0, 0.2)}, {"G1": 0.1})
    []
    >>> outside_bounds({"G1": (0.0, 0.2)}, {"G1": 0.5})[0][:46]
    'G1 = 0.5 is outside the limits (0, 0.2) given '
    """
    if not isinstance(bounds, dict):
        return []
    out = []
    for name, (lo, hi) in bounds.items():
        if name not in params:
            continue
        v, lo, hi = float(params[name]), float(lo), float(hi)
        slack = 1e-9 * max(abs(b) for b in (lo, hi, 1e-300) if np.isfinite(b))
        if lo - slack <= v <= hi + slack:
            continue
        out.append(
            f"{name} = {v:.6g} is outside the limits ({lo:g}, {hi:g}) given in bounds: "
            "Prony terms whose relaxation times coincide were merged after the search (a "
            "limit of one term holds for the merged one only if every term has it); give "
            "all terms the same limits, or fit fewer terms ("
            + setting("bounds=, n_prony=", "--bounds, --prony") + ")")
    return out


def _shift_of(ref) -> dict:
    """The result's fields of the time–temperature shift its tests were put at T_ref with."""
    if ref.source != "none":
        return dict(shift=ref.law, shift_table=dict(ref.log_aT), shift_source=ref.source,
                    T_ref=ref.T_ref)
    return {}


def _by_spectrum(curves, settings: CalibrationSettings, n_prony: int | None,
                 t0: float) -> Calibration:
    """Moduli-only data: the per-decade spectrum route (``n_prony`` None: automatic N)."""
    s = settings

    def model_for(n: int):
        model = model_from_spec(s.model_spec(n))
        tau_b, auto = search_bounds(model, curves, s.tau_strategy, s.decades_below,
                                    s.decades_above, s.bounds)
        return model, tau_b, auto

    cal, scan, heads, n = _spectrum.spectrum_fit(curves, s, model_for, n_prony, t0)
    if scan is None:
        return cal
    for m in heads:
        warnings.warn(m, CalibrationWarning, stacklevel=3)
    return replace(
        cal, order_scan=scan, headlines=heads + list(cal.headlines),
        warnings=heads + list(cal.warnings),
        options={**cal.options, "n_prony": "auto", "n_prony_chosen": n,
                 "order_rule": f"smallest N whose RMSAPE on the per-decade tau grid (its "
                               f"pruning path) is within {s.order_tol:.0%} of the full "
                               f"grid's, over N = 1..{len(scan)} (one relaxation time per "
                               "decade of the data, one beyond each end); tau refined at "
                               "that N"},
        wall_time=time.perf_counter() - t0)


def _calibrate_n(curves, settings: CalibrationSettings, n_prony: int, *, checkpoint, max_time,
                 t0, prior=None) -> Calibration:
    """One calibration with N Prony terms: bounds, global search, polish, a second search
    with widened bounds where a constant ended on one, report (``checkpoint`` and
    ``max_time``: this one's, of a scan over N; ``prior``: the fit of N − 1 that seeds
    and floors it, :func:`._nesting.fewer_terms`)."""
    s = settings
    model = model_from_spec(s.model_spec(n_prony))
    tau_b, auto = search_bounds(model, curves, s.tau_strategy, s.decades_below,
                                s.decades_above, bounds_for_terms(s.bounds, n_prony))
    sr = stability_range_of(s, curves)
    given = bounds_for_terms(s.bounds, n_prony)
    user = set(given) if isinstance(given, dict) else set()
    prob = Problem(model, curves, tau_b, auto, s.g_inf_min, s.objective, sr, user)
    # a box without a stable law: widen the constant that limits stability (Jm, λm), or
    # if none can, search the bounds as they are and say that the fit is unstable
    auto, stable_widened, stable = stable_box(prob)
    if stable_widened or not stable:
        prob = Problem(model, curves, tau_b, auto, s.g_inf_min, s.objective, sr, user,
                       constrained=stable)
    # the fits of the laws this one contains, and of N − 1 terms: seeds of its search,
    # and floors of its error
    nested = (_nesting.nested_fits(curves, s, n_prony, _calibrate_n)
              + _nesting.fewer_terms(curves, s, n_prony, prior))
    # a contained law's fit outside this box (its own search widened a bound it ended
    # on): the box grows to hold it, a point of this search that accept-if-lower can keep
    for_nesting = _nesting.containing_box(prob, nested)
    if for_nesting:
        auto = {**prob.bounds, **for_nesting}
        prob = Problem(model, curves, tau_b, auto, s.g_inf_min, s.objective, sr, user,
                       constrained=stable)
    found, x, err, nfev, kept = _search_polish(prob, curves, s, n_prony, checkpoint,
                                               max_time, t0, nested)
    hits = bound_hits(prob, x)
    widened: dict = {}
    # a fit already at the target needs no wider search; a cut one has no time for it
    if hits and err > s.target and found.stop.kind not in (StopKind.INTERRUPTED, StopKind.MAX_TIME):
        wide = widen_bounds(prob, hits)
        widened = {k: [float(v) for v in wide[k]] for k in hits if k not in user}
        left = None if max_time is None else max_time - (time.perf_counter() - t0)
        if widened and (left is None or left > 0):
            prob2 = Problem(model, curves, tau_b, wide, s.g_inf_min, s.objective, sr, user,
                            constrained=stable)
            found2, x2, err2, nfev2, kept2 = _search_polish(
                prob2, curves, s, n_prony, None if checkpoint is None else f"{checkpoint}.widened",
                left, time.perf_counter(), nested)
            nfev += nfev2
            if err2 <= err:
                prob, found, x, err, kept = prob2, found2, x2, err2, kept2
            hits = bound_hits(prob, x)
    if stable:  # unstable between the search's grid stretches: again on the check's own
        prob, x, err, n_fine, kept = _on_check_grid(prob, curves, s, n_prony, x, err,
                                                    max_time, t0, nested, kept)
        nfev += n_fine
    heads = bound_hit_headlines(prob, x, hits, widened) + pinned_headlines(prob, x, hits)
    if not stable:
        heads.insert(0, no_stable_headline(prob))
    notes = [f"no {model.hyperelastic.name} law of the automatic bounds is Drucker-stable "
             f"over {sr[0]:.3g} <= λ <= {sr[1]:.3g}: widened {k} to ({v[0]:.6g}, {v[1]:.6g})"
             for k, v in stable_widened.items()]
    free = (unconstrained_fit(prob, x, err) if s.space.separable and n_prony == 0
            and stable else None)
    space = SPACES[s.method]
    nest = ({"nested": {n.label: n.rmsape for n in nested},
             "nested_kept": kept or "search"} if nested else {})
    cal = finish(prob, curves, model, x, err, found, nfev, s, dict(
        hyperelastic=model.hyperelastic.name, n_prony=n_prony,
        tau_strategy=str(s.tau_strategy), objective=prob.objective.kind, method=s.method,
        seed=s.seed, popsize=s.popsize or space.popsize, maxiter=s.maxiter or space.maxiter,
        tol=s.effective_tol, target=s.target, polish=s.polish, g_inf_min=s.g_inf_min,
        rtol=s.rtol, stability_range=[float(v) for v in sr],
        **({"widened_bounds": widened} if widened else {}), **nest,
        **({"widened_for_stability": stable_widened} if stable_widened else {}),
        **({"widened_for_nesting": {k: [float(v) for v in b] for k, b in for_nesting.items()}}
           if for_nesting else {}),
        **({} if stable else {"no_stable_law": True}),
        **({"unconstrained_fit": free[0]} if free else {})),
        headlines=heads, notes=notes + ([free[1]] if free else []))
    if prior is None:  # (a fit seeded by N − 1 is not what the same call makes alone)
        _nesting.remember(curves, s, n_prony, cal)  # the seed of a later fit containing it
    return cal


def _on_check_grid(prob: Problem, curves, settings: CalibrationSettings, n_prony: int,
                   x: np.ndarray, err: float, max_time, t0, nested=(), kept=None):
    """The fit again with the admissible set on the final check's stretches, where the
    search's coarser grid let it be unstable between two of its stretches: without Prony
    terms the linear constants solved again for the fit's nonlinear ones, then polished;
    otherwise the search and polish again. Either way the result is floored by the same
    ``nested`` fits (each passed its own check), and the search is seeded by them.
    Returns (prob, x, err, evaluations, kept), ``kept`` the label of the nested fit kept;
    the fit as it was (and ``kept`` as given) where the check already passes or the
    second one finds nothing finite."""
    from vhfit.stability import drucker

    nh = prob.hm.n_params
    if drucker(prob.hm, x[:nh], prob.stability_range, principal=True).stable:
        return prob, x, err, 0, kept
    fine = Problem(prob.model, curves, prob.tau_b, prob.bounds, prob.g_inf_min,
                   prob.objective_spec, prob.stability_range, prob.user_bounds,
                   grid_points=CHECK_POINTS)
    if n_prony == 0 and prob.hm.linear_index:
        X, e = SPACES["separable"](fine).solve_constants(x[None, :nh])
        if not np.isfinite(e[0]):
            return prob, x, err, 1, kept
        x1, e1, n = polish(fine, X[0]) if settings.polish else (X[0], float(e[0]), 0)
        x1, e1, kept1 = _nesting.accept_if_lower(fine, SPACES[settings.method](fine),
                                                 list(nested), x1, float(e1), settings.polish)
        return fine, x1, e1, n + 1, kept1
    left = None if max_time is None else max_time - (time.perf_counter() - t0)
    try:
        _, x1, e1, n, kept1 = _search_polish(fine, curves, settings, n_prony, None, left,
                                             time.perf_counter(), nested)
    except CalibrationError:
        return prob, x, err, 0, kept
    return fine, x1, e1, n, kept1


def stability_range_of(settings: CalibrationSettings, curves) -> tuple[float, float]:
    """The stretch range of the admissible set: the settings' ``stability_range``, or by
    default the data's (:func:`data_stability_range`)."""
    sr = settings.stability_range
    if sr is None:
        return data_stability_range(curves)
    return float(sr[0]), float(sr[1])


def unconstrained_fit(prob: Problem, x: np.ndarray, err: float):
    """The best fit without the stability inequalities, for the nonlinear constants of
    ``x`` (no Prony terms: one least squares solve), when it is lower than ``err`` and
    unstable: (record, sentence) — its error, constants and Drucker report — else None."""
    from vhfit.stability import drucker

    nh = prob.hm.n_params
    c, e = SPACES["separable"](prob).solve_constants(x[None, :nh], constrained=False)
    e_u = float(e[0])
    if not (np.isfinite(e_u) and e_u < err * (1 - 1e-6)):
        return None
    rep = drucker(prob.hm, c[0], prob.stability_range, principal=True)
    if rep.stable:
        return None
    params = {n: float(v) for n, v in zip(prob.hm.param_names, c[0])}
    lo, hi = prob.stability_range
    text = (f"without the stability constraint the best {prob.hm.name} fit reaches "
            f"{e_u:.4g} % (this fit: {err:.4g} %) with "
            + ", ".join(f"{k} = {v:.4g}" for k, v in params.items())
            + f", but it is {rep.describe()}: the data ask for a law unstable within "
            f"{lo:.3g} <= λ <= {hi:.3g} (stability_range= / --stability-range set it)")
    return {"rmsape": e_u, "params": params, "stability": rep.describe()}, text


def _search_polish(prob: Problem, curves, settings: CalibrationSettings, n_prony: int,
                   checkpoint, max_time, t0, nested=()):
    """The global search over the method's space, then the polish: (found, x, err, nfev,
    kept). ``nested``: the fits of contained laws and of N − 1 terms (:mod:`._nesting`),
    members of the first population; the result is the lowest of them where the
    search's is higher (``kept``: its label, else None)."""
    space = SPACES[settings.method](prob)
    short = search_problem(prob, curves) if settings.space.separable else prob
    searched = space if short is prob else SPACES[settings.method](short)  # coarser
    # moduli beside large-strain curves: the moduli's spectrum is one member of the start
    # (not over a start population of the caller's own, e.g. a first fit's)
    x0 = None if "init" in (settings.de_options or {}) else _spectrum.seed_from_moduli(
        curves, searched, settings, n_prony)
    # the nested fits enter the first population where they beat the draw
    seeds = _nesting.seed_rows(searched, list(nested)) or None
    found = run_search(searched, settings, n_prony=n_prony, checkpoint=checkpoint,
                       max_time=max_time, t0=t0, x0=x0, full=None if short is prob else prob,
                       seeds=seeds)
    x = space.to_params(found.z)  # the linear constants solved on every point
    err = float(prob.errors(x[None, :])[0])
    if not np.isfinite(err) and found.polished is not None:
        # the solve on every point can fail where the search's own polish (on its coarser
        # problem) did not: keep that polish's constants, the final polish starts there
        xp = np.asarray(found.polished[0], dtype=np.float64)
        ep = float(prob.errors(xp[None, :])[0])
        if np.isfinite(ep):
            x, err = xp, ep
    if not np.isfinite(err) and nested and not found.stop.interrupted:
        # no individual was finite, but a contained law's fit is a point of this space
        xn, en, kept = _nesting.accept_if_lower(prob, space, list(nested), x, err,
                                                settings.polish)
        if np.isfinite(en):
            return found, xn, en, found.nfev, kept
    if not np.isfinite(err):  # no individual was finite: nothing that looks like a result
        if found.stop.interrupted:
            raise KeyboardInterrupt  # the search may yet find one: resume the checkpoint
        if checkpoint is not None and os.path.exists(checkpoint):
            os.remove(checkpoint)  # resuming it would only end in the same failure
        raise CalibrationError(no_fit_message(prob, found.nfev, found.stop))
    nfev = found.nfev
    if found.polished is not None and searched is space:  # ended by this polish of its best
        x, err = found.polished
    elif settings.polish and not found.stop.interrupted:
        x, err, n_pol = final_polish(space, found, x, err)
        nfev += n_pol
    kept = None
    if nested and not found.stop.interrupted:
        x, err, kept = _nesting.accept_if_lower(prob, space, list(nested), x, err,
                                                settings.polish)
    return found, x, err, nfev, kept


def no_fit_message(prob: Problem, nfev: int, stop: Stop) -> str:
    """Why the search found no parameter set with a finite error, and what to change.

    Each of the law's nonlinear constants (α, λm, Jm, ...) is probed alone, the others
    at the law's example values and no Prony modulus, over its search bounds and beyond
    them within its physical limits: a finite stress only outside the bounds names the
    bound as the cause, with a range that reaches it.
    """
    hm = prob.hm
    head = (f"the {hm.name} fit found no parameter set with a finite error "
            f"({nfev} evaluated, stop: {stop})")
    stiff = _stiffness_from_bounds(prob)
    if stiff:
        return (f"{head}: the bounds given on {stiff} leave the {hm.name} law no positive "
                "initial shear modulus (a material without stiffness); widen them with "
                + setting("the bounds= keyword", "--bounds"))
    inside = False
    for k in range(hm.n_params):
        if k in hm.linear_index:
            continue
        name = hm.param_names[k]
        lo, hi = (float(v) for v in prob.bounds[name])
        plo, phi = (float(v) for v in hm.bounds[k])
        values = _probe_values(lo, hi, plo, phi)
        finite = _finite_at(prob, k, values)
        if finite[:9].any():
            inside = True
            continue
        above = [v for v, f in zip(values[9:], finite[9:]) if f and v > hi]
        below = [v for v, f in zip(values[9:], finite[9:]) if f and v < lo]
        if above or below:
            new = (max(below) if below else lo, min(above) if above else hi)
            side = f"{name} <= {hi:g}" if above else f"{name} >= {lo:g}"
            return (f"{head}: its search bounds ({side}) leave the {hm.name} law undefined "
                    f"at the data's deformation everywhere, but {name} = "
                    f"{new[1] if above else new[0]:g} is not; widen them, e.g. "
                    + setting(f"bounds={{'{name}': ({new[0]:g}, {new[1]:g})}}",
                              f"--bounds {name}={new[0]:g}:{new[1]:g}"))
    if inside:
        return (f"{head}: some parameter sets within the bounds have a finite error but the "
                "search did not reach them; narrow the bounds ("
                + setting("bounds=", "--bounds NAME=LO:HI") + ") or give a larger "
                + setting("popsize=", "--popsize"))
    return (f"{head}: the {hm.name} law is undefined at the data's deformation for any of "
            "its constants; check the data's strain and units, or choose another law")


def _stiffness_from_bounds(prob: Problem) -> str:
    """The linear constants whose bounds the user gave, if with them no law of the search
    box has a positive initial shear modulus μ0; else "".

    μ0 is linear in the linear constants: for given other constants its largest value is
    at a corner of their bounds. The other constants are tried at the law's example
    values and at every corner of their search bounds (μ0 of the built-in laws is at
    most bilinear in them, e.g. Ogden's Σ μ_i α_i / 2).
    """
    hm = prob.hm
    lin = list(hm.linear_index)
    given = [hm.param_names[k] for k in lin if hm.param_names[k] in prob.user_bounds]
    if not given:
        return ""
    other = [k for k in range(hm.n_params) if k not in lin]
    shapes = [np.asarray(hm.example, dtype=np.float64)]
    for corner in itertools.product(*[prob.bounds[hm.param_names[k]] for k in other]):
        x = shapes[0].copy()
        x[other] = corner
        shapes.append(x)
    for ex in shapes:
        U = np.repeat(ex[None, :], len(lin) + 1, axis=0)
        U[:, lin] = 0.0
        U[np.arange(1, len(lin) + 1), lin] = 1.0
        with np.errstate(all="ignore"):
            mu = np.asarray(hm.initial_shear_modulus(U), dtype=np.float64).reshape(-1)
        best = mu[0]
        for c, k in zip(mu[1:] - mu[0], lin):
            lo, hi = (float(v) for v in prob.bounds[hm.param_names[k]])
            best += max(c * lo, c * hi) if c != 0 else 0.0
        if not (np.isfinite(best) and best <= 0):
            return ""
    return ", ".join(given)


def _probe_values(lo: float, hi: float, plo: float, phi: float) -> list[float]:
    """9 values across [lo, hi], then up to 4 decades beyond each end within (plo, phi)."""
    if lo > 0 and hi > lo:
        values = list(np.geomspace(lo, hi, 9))
        out = [hi * 10.0**j for j in range(1, 5)] + [lo / 10.0**j for j in range(1, 5)]
    else:
        values = list(np.linspace(lo, hi, 9))
        span = max(hi - lo, 1.0)
        out = [hi + span * 10.0**j for j in range(4)] + [lo - span * 10.0**j for j in range(4)]
    return values + [v for v in out if plo < v < phi]


def _finite_at(prob: Problem, k: int, values: list[float]) -> np.ndarray:
    """Whether the error is finite with the law's constant ``k`` at each of ``values``
    (the other constants at the law's example, Prony moduli 0)."""
    hm, nh = prob.hm, prob.hm.n_params
    X = np.zeros((len(values), prob.model.n_params))
    X[:, :nh] = np.asarray(hm.example, dtype=np.float64)
    X[:, k] = values
    X[:, prob.model.layout.times] = 10.0 ** prob.tau_b[:, 0]
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        return np.isfinite(prob.errors(X))
