"""Fits for several solvers at once: one per viscoelastic formulation they integrate.

Each solver integrates a Prony series in its own finite-strain law
(:data:`vhfit.formulations.SOLVER_FORMULATIONS`, filled from the solver records of
:mod:`vhfit.export`); constants fitted in one law are wrong in another (docs/export.md,
"Card check"). :func:`calibrate_for` runs one :func:`vhfit.calibrate` per formulation the
solvers need. The first is an ordinary search; each further one starts from it
(:func:`start_options`): half of a population of 3/8 the size is a cloud around the
first fit's search vector, half a Sobol sequence over the whole box, so that the search
keeps its reach (the other law's optimum may lie in another basin) at under half the
evaluations of a fresh one. After an order scan the further fit is made at the N the
first chose (no scan of its own), and without Prony terms it is the first fit itself
in the other formulation (:func:`same_fit`: no search).
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Iterable, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from vhfit.calibration import _spectrum
from vhfit.calibration._admissible import data_stability_range
from vhfit.calibration._bounds import search_bounds
from vhfit.calibration._result import Calibration
from vhfit.calibration._settings import (
    DEFAULT_TOL,
    FULL_TOL,
    CalibrationSettings,
    bounds_for_terms,
)
from vhfit.calibration._space import SPACES, Problem, search_vector
from vhfit.calibration._workflow import (
    DEFAULT_DECADES_ABOVE,
    DEFAULT_DECADES_BELOW,
    DEFAULT_TAU_STRATEGY,
    _as_curves,
    calibrate,
)
from vhfit.formulations import FORMULATIONS, SOLVER_FORMULATIONS
from vhfit.hyperelastic import get as get_law
from vhfit.model import ModelSpec, Prony, model_from_spec
from vhfit.tts import shift_to_reference

__all__ = ["calibrate_for", "plan_formulations", "start_options", "same_fit", "CLOUD_WIDTH",
           "CLOUD_SHARE", "POPSIZE_SHARE", "MIN_POPSIZE", "SEEDED_TOL"]

#: Standard deviation of the cloud around the first fit, as a fraction of each search
#: bound's span.
CLOUD_WIDTH = 0.1
#: Share of the seeded population that is the cloud (the rest: a Sobol sequence).
CLOUD_SHARE = 0.5
#: Population of a seeded search, as a fraction of the first search's: on the data sets of
#: ``benchmarks/bench_solvers.py`` (two seeds) 3/8 reached the fresh search's optimum
#: everywhere with a median of 0.38 x the first fit's evaluations (1/2: 0.42; 5/16: 0.44).
POPSIZE_SHARE = 0.375
#: Smallest population of a seeded search.
MIN_POPSIZE = 16
#: Best-mean gap at which a seeded search stops (unless ``tol`` is looser): it starts in
#: the first fit's basin and the polish that follows converges the rest. On the data sets
#: of ``benchmarks/bench_solvers.py`` 1e-4 reached the same RMSAPE (6 digits, two seeds)
#: in about 30 % fewer generations than 1e-6; 1e-3 left so much to the polish that it
#: cost more, 1e-2 a worse optimum once.
SEEDED_TOL = 1e-4


def plan_formulations(solvers: Iterable[Any] | str) -> dict[str, list[str]]:
    """Formulation -> the solvers its fit serves, in the order the solvers are given.

    Parameters
    ----------
    solvers : iterable of str or solver records
        Registered solver names (:data:`vhfit.formulations.SOLVER_FORMULATIONS`), or
        solver records (:class:`vhfit.export.Solver`, registered or not: their ``name``
        and ``formulation``).

    Returns
    -------
    dict
        Formulation name -> list of solver names.

    Raises
    ------
    ValueError
        An unknown solver, or none at all.

    Examples
    --------
    >>> from vhfit.calibration import plan_formulations
    >>> from vhfit.export import get_solver, solvers
    >>> plan = plan_formulations([*solvers(), *solvers()])  # each solver served once
    >>> sorted(s for served in plan.values() for s in served) == sorted(solvers())
    True
    >>> all(get_solver(s).formulation == f for f, served in plan.items() for s in served)
    True
    >>> last = get_solver(solvers()[-1])
    >>> plan_formulations([last]) == {last.formulation: [last.name]}
    True
    """
    if isinstance(solvers, str) or _is_record(solvers):
        solvers = [solvers]
    plan: dict[str, list[str]] = {}
    for s in solvers:
        if _is_record(s):  # a solver record: its own name and formulation
            key, form = s.name, s.formulation
        else:
            key = str(s).lower()
            form = SOLVER_FORMULATIONS.get(key)
        if form is None or form not in FORMULATIONS:
            raise ValueError(f"solver {s!r}: unknown; choose among "
                             f"{', '.join(SOLVER_FORMULATIONS)} or give a solver record "
                             "(vhfit.export.Solver)")
        served = plan.setdefault(form, [])
        if key not in served:
            served.append(key)
    if not plan:
        raise ValueError("calibrate_for needs at least one solver: give names among "
                         f"{', '.join(SOLVER_FORMULATIONS)}")
    return plan


def _is_record(s) -> bool:
    """Whether ``s`` is a solver record (a :class:`vhfit.export.Solver`: a name and the
    formulation its solver integrates), registered or not."""
    if isinstance(s, str):
        return False
    try:  # duck-typed: the export layer (where Solver lives) comes after calibration
        return isinstance(s.name, str) and isinstance(s.formulation, str)
    except AttributeError:
        return False


def _in_law(first: Calibration, hm) -> np.ndarray | None:
    """The first fit's parameters as constants of the law ``hm``: the first fit's own, or
    those of a law of like terms that the first fit merged into fewer terms (the merged
    terms come back with a zero modulus); None for any other law."""
    own, x = first.model.hyperelastic, first.x
    if own.name == hm.name:
        return x
    name = hm.fewer
    while name is not None and name != own.name:
        name = get_law(name).fewer
    if name is None or not hm.term:
        return None
    empty = x[own.n_params - hm.term: own.n_params].copy()
    empty[0] = 0.0
    missing = (hm.n_params - own.n_params) // hm.term
    return np.concatenate([x[:own.n_params]] + [empty] * missing + [x[own.n_params:]])


def start_options(first: Calibration, curves, **kwargs) -> dict:
    """Keywords of :func:`vhfit.calibrate` that start its search from a fit made in
    another formulation.

    The population is :data:`POPSIZE_SHARE` of the first search's (at least
    :data:`MIN_POPSIZE`): a cloud of
    :data:`CLOUD_SHARE` of it around the first fit's search vector (that vector itself,
    and normal deviates of :data:`CLOUD_WIDTH` of each bound's span), the rest a
    scrambled Sobol sequence over the whole box. The search stops at a best-mean gap of
    :data:`SEEDED_TOL` (or the looser ``tol`` given): the polish that follows converges
    the rest. Everything else — bounds, other stopping criteria, polish, report — is the
    ordinary calibration's.

    After an order scan (``n_prony="auto"``) the new fit is made at the N the first
    fit's scan chose (``options["n_prony_chosen"]``) instead of a scan of its own, which
    would cost as much as the first: only ``n_prony`` is returned, and the search at
    that N is the one a scan in the new formulation would run there (a fresh
    population). On the shared real data sets (``benchmarks/bench_solvers.py
    --second-fit``) the seeded population reached a higher error than that fresh search
    on the Ogden fits of VHB, whose optimum in the other formulation lies in another
    basin (up to 8e-3 relative over three seeds), and a fresh search at one N costs a
    third of a scan. Small-strain data alone (the per-decade spectrum, whose moduli are
    the same in every formulation) start their τ from the first fit's as for a given N.

    Parameters
    ----------
    first : Calibration
        The fit to start from (same law, or the same law with like terms merged).
    curves : sequence
        The curves of both fits (as given to :func:`vhfit.calibrate`).
    **kwargs
        The keywords of the new fit (those of :func:`vhfit.calibrate`), its
        ``formulation`` among them.

    Returns
    -------
    dict
        ``popsize``, ``de_options`` (with an ``init`` population) and ``tol`` to add
        to the call; after an order scan ``n_prony`` (the first's chosen N), alone unless
        the fit is by the per-decade spectrum. Empty when there is nothing to start from
        (an ``init`` of the caller's own, a scan that chose no N, or a law with nothing
        to search). For data that take the per-decade spectrum route (sweeps and
        relaxation tests alone), which starts from the first fit's τ and searches no
        population, ``init`` is that one search vector.

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> from vhfit.calibration import start_options
    >>> m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    >>> true = dict(C10=0.01, C01=0.005, G1=0.5, tau1=0.01)
    >>> eps = np.linspace(-0.05, -0.5, 10)
    >>> curves = [vhfit.Curve(strain=eps, stress=m.stress(true, strain=eps, strain_rate=r,
    ...           measure="engineering"), strain_rate=r) for r in (-1.0, -100.0)]
    >>> first = vhfit.calibrate(curves, n_prony=1, seed=0)
    >>> other = next(f for f in vhfit.formulations.FORMULATIONS if f != "hereditary")
    >>> opts = start_options(first, curves, formulation=other, n_prony=1, seed=0)
    >>> opts["popsize"], opts["de_options"]["init"].shape
    (24, (24, 2))
    """
    n_prony = kwargs.get("n_prony")
    if n_prony is None:
        n_prony = first.options.get("n_prony")
    chosen = {}
    method = kwargs.get("method", "separable")
    route = _RouteKeys(method, kwargs)
    if isinstance(n_prony, str):  # an order scan: at the N the first fit's scan chose
        n_prony = first.options.get("n_prony_chosen")
        if not isinstance(n_prony, (int, np.integer)) or isinstance(n_prony, bool):
            return {}
        n_prony = int(n_prony)
        chosen = {"n_prony": n_prony}
        if not _spectrum.applies(_as_curves(curves), route):
            return chosen  # a search of its own at that N (see above)
    opts = dict(kwargs.get("de_options") or {})
    if "init" in opts or "x0" in opts:
        return {}
    ref = shift_to_reference(_as_curves(curves), shift_factors=kwargs.get("shift_factors"),
                             T_ref=kwargs.get("T_ref"))
    law = get_law(kwargs.get("hyperelastic", "mooney_rivlin"))
    x_first = _in_law(first, law)
    if x_first is None:
        return chosen
    model = model_from_spec(ModelSpec(law, Prony(int(n_prony),
                                                 kwargs.get("formulation", "hereditary")),
                                      kwargs.get("rtol", 1e-6)))
    tau_b, auto = search_bounds(
        model, ref.items, kwargs.get("tau_strategy", DEFAULT_TAU_STRATEGY),
        kwargs.get("decades_below", DEFAULT_DECADES_BELOW),
        kwargs.get("decades_above", DEFAULT_DECADES_ABOVE),
        bounds_for_terms(kwargs.get("bounds", "auto"), int(n_prony)))
    sr = kwargs.get("stability_range") or data_stability_range(ref.items)
    user = kwargs["bounds"] if isinstance(kwargs.get("bounds"), dict) else {}
    space = SPACES[method](Problem(model, ref.items, tau_b, auto,
                                   kwargs.get("g_inf_min", 1e-6),
                                   kwargs.get("objective", "rmsape"), sr, set(user)))
    b = np.array(space.bounds(), dtype=np.float64).reshape(-1, 2)
    if not len(b):
        return chosen
    lo, hi = b[:, 0], b[:, 1]
    z0 = np.clip(search_vector(space, x_first), lo, hi)
    popsize = max(MIN_POPSIZE, int(POPSIZE_SHARE * int(kwargs.get("popsize") or space.popsize)))
    tol = float(kwargs.get("tol", DEFAULT_TOL))
    if not SPACES[method].separable and tol == DEFAULT_TOL:
        tol = FULL_TOL  # (what the full method's search takes the default for)
    tol = max(tol, SEEDED_TOL)
    if int(n_prony) and _spectrum.applies(ref.items, route):
        # moduli alone take the spectrum route, which starts from the first fit's τ (the
        # init's first row) and searches no population: no cloud, no Sobol sequence
        return {**chosen, "popsize": popsize, "de_options": {**opts, "init": z0[None, :]},
                "tol": tol}
    rng = np.random.default_rng(kwargs.get("seed"))
    k = max(1, int(round(CLOUD_SHARE * popsize)))
    cloud = z0 + rng.normal(size=(k, len(z0))) * (CLOUD_WIDTH * (hi - lo))
    cloud[0] = z0
    from scipy.stats import qmc  # scipy.stats is slow to import: only here

    with warnings.catch_warnings():  # any prefix of a Sobol sequence fills the box
        warnings.filterwarnings("ignore", "The balance properties of Sobol", UserWarning)
        rest = qmc.Sobol(len(z0), seed=rng).random(popsize - k)
    init = np.clip(np.vstack([cloud, lo + rest * (hi - lo)]), lo, hi)
    return {**chosen, "popsize": popsize, "de_options": {**opts, "init": init}, "tol": tol}


class _RouteKeys:
    """What :func:`vhfit.calibration._spectrum.applies` reads of the settings, from the
    keywords of a calibrate call."""

    def __init__(self, method: str, kwargs: dict):
        self.space = SPACES[method]
        self.tau_strategy = kwargs.get("tau_strategy", DEFAULT_TAU_STRATEGY)
        self.bounds = kwargs.get("bounds", "auto")


def same_fit(first: Calibration, curves, **kwargs) -> Calibration | None:
    """The fit :func:`vhfit.calibrate` would make in another formulation, taken from a
    first fit without Prony terms; None where it is not that.

    A formulation says how the Prony series acts (:mod:`vhfit.formulations`): without
    Prony terms the stress is the law's long-term stress in every formulation, so the
    objective — and its optimum — is the first fit's. Such a fit is the first's
    constants, errors, intervals and checks with the model in the new formulation (no
    search: ``nit``, ``nfev`` 0; ``options["same_as"]`` names the fit it came from).
    That holds when the first fit was asked for no Prony terms (``n_prony=0``, or the
    default for data that cannot separate elastic from viscous response) and the new
    keywords are the first's but for ``formulation`` (and the ``checkpoint``,
    ``callback`` and ``resume`` that only steer a search).

    Parameters
    ----------
    first : Calibration
        The first fit (made by :func:`vhfit.calibrate`: its ``settings`` recorded).
    curves : sequence
        The curves of both fits (unused: the first's are the same).
    **kwargs
        The keywords of the new fit, its ``formulation`` among them.

    Returns
    -------
    Calibration or None

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> from vhfit.calibration import same_fit
    >>> eps = np.linspace(-0.05, -0.5, 10)
    >>> curves = [vhfit.Curve(strain=eps, stress=0.1 * eps, strain_rate=-1.0)]
    >>> first = vhfit.calibrate(curves, n_prony=0, seed=0)
    >>> other = next(f for f in vhfit.formulations.FORMULATIONS if f != "hereditary")
    >>> fit = same_fit(first, curves, n_prony=0, seed=0, formulation=other)
    >>> fit.model.formulation == other, fit.params == first.params, fit.nfev
    (True, True, 0)
    >>> same_fit(first, curves, n_prony=1, seed=0, formulation=other) is None
    True
    """
    t0 = time.perf_counter()
    form = kwargs.get("formulation", "hereditary")
    old = first.settings
    if old is None or first.model.n_prony != 0 or first.options.get("n_prony") != 0:
        return None
    try:
        new = CalibrationSettings(**kwargs)
        steer = dict(formulation=old.formulation, checkpoint=old.checkpoint,
                     callback=old.callback, resume=old.resume)
        if replace(new, **steer) != old:
            return None
    except (TypeError, ValueError):  # a keyword calibrate lacks; arrays compared
        return None
    model = model_from_spec(first.model.spec().replace(formulation=form))
    return replace(first, model=model, settings=new, nit=0, nfev=0, history={},
                   options={**first.options, "same_as": (
                       f"the '{first.model.formulation}' fit: without Prony terms every "
                       "formulation has the same stress")},
                   wall_time=time.perf_counter() - t0)


def calibrate_for(solvers: Sequence[Any] | str, curves, **kwargs) -> dict[str, Calibration]:
    """Calibrate once per viscoelastic formulation that the given solvers integrate.

    The first formulation (that of the first solver) is an ordinary
    :func:`vhfit.calibrate`; each further one starts its search from the first fit
    (:func:`start_options`), which costs well under a fresh search and reaches the same
    optimum. Write each solver's card from the fit of its formulation
    (``vhfit.export.export(fits[SOLVER_FORMULATIONS[s]], to=s)``).

    Parameters
    ----------
    solvers : sequence of str or solver records
        Names of registered solvers (:func:`vhfit.export.solvers`) or
        solver records (:class:`vhfit.export.Solver`, registered or not).
    curves : Curve, path, or sequence of them
        The data, as for :func:`vhfit.calibrate`.
    **kwargs
        Keywords of :func:`vhfit.calibrate` for every fit (not ``formulation``: the
        solvers choose it). A ``checkpoint`` path gets ``.FORMULATION`` appended for each
        fit after the first.

    Returns
    -------
    dict
        Formulation -> :class:`Calibration`, in the order of the solvers (which solvers
        each serves: :func:`plan_formulations`).

    Raises
    ------
    ValueError
        An unknown solver, a ``formulation`` keyword, or a bad argument of calibrate.

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    >>> true = dict(C10=0.01, C01=0.005, G1=0.5, tau1=0.01)
    >>> eps = np.linspace(-0.05, -0.5, 10)
    >>> curves = [vhfit.Curve(strain=eps, stress=m.stress(true, strain=eps, strain_rate=r,
    ...           measure="engineering"), strain_rate=r) for r in (-1.0, -100.0)]
    >>> from vhfit.export import get_solver, solvers
    >>> one_each = list({get_solver(s).formulation: s for s in solvers()}.values())
    >>> fits = vhfit.calibrate_for(one_each, curves, n_prony=1, seed=0)
    >>> list(fits) == [get_solver(s).formulation for s in one_each], len(fits) > 1
    (True, True)
    >>> fits["hereditary"].rmsape < 1e-3
    True
    >>> all(fit.model.formulation == f for f, fit in fits.items())
    True
    """
    if "formulation" in kwargs:
        raise ValueError("calibrate_for: the solvers choose each fit's formulation; drop "
                         "formulation= (or call calibrate(..., formulation=) for one fit)")
    plan = plan_formulations(solvers)
    curves = _as_curves(curves)
    fits: dict[str, Calibration] = {}
    first = None
    for form in plan:
        kw = dict(kwargs, formulation=form)
        if first is not None:
            if kw.get("checkpoint") is not None:
                kw["checkpoint"] = f"{kw['checkpoint']}.{form}"
            same = same_fit(first, curves, **kw)
            if same is not None:  # no Prony terms: the same fit in every formulation
                fits[form] = same
                continue
            kw.update(start_options(first, curves, **kw))
        fits[form] = cal = calibrate(curves, **kw)
        if first is None:
            first = cal
        if cal.interrupted:  # Ctrl-C ends them all
            break
    return fits
