"""Several hyperelastic laws fitted to the same data side by side, and ranked.

:func:`compare` fits each law with :func:`vhfit.calibrate` (the same keywords, the same
seed), the laws spread over worker processes by :func:`vhfit.parallel.calibrate_many`
— the one pool of vhfit —, then scores every fit the same way: its error (RMSAPE,
paper Eq. 20) overall and per test mode, its number of constants, an information
criterion, its Drucker stability, the check of its solver cards, and its time. The
result, a :class:`Comparison`, holds each law's :class:`vhfit.Calibration` and the
table ranked by one stated rule (:data:`RULE`).

The information criterion is Schwarz's (BIC) on the relative residuals of the
objective points: with ``n`` objective points, ``k`` constants of the fitted model and
``e = RMSAPE / 100`` (the root mean square of the relative residuals),
``BIC = n ln(e²) + k ln(n)`` — lower is better; a constant must lower n ln(e²) by
more than ln(n) to pay for itself (docs/theory.md).
"""

from __future__ import annotations

import math
import os
import warnings as _warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vhfit import hyperelastic
from vhfit.calibration import (
    Calibration,
    CalibrationError,
    CalibrationSettings,
    refuse_unrepresentable,
)
from vhfit.export import export, get_solver, supported_laws
from vhfit.export import solvers as solver_names
from vhfit.export.check import check_cards
from vhfit.parallel import calibrate_many

__all__ = ["Comparison", "compare", "RULE", "bic", "resolve_laws"]

#: How :func:`compare` picks the best law.
RULE = ("lowest BIC among the fits that are Drucker-stable and whose cards pass their "
        "check in the solvers that integrate the fit's formulation (if none qualifies: "
        "lowest BIC of all finite fits)")

#: Keywords of :func:`vhfit.calibrate` that :func:`compare` sets itself or cannot share
#: between laws fitted in other processes.
_REFUSED = {
    "hyperelastic": "give the laws as laws=[...]",
    "callback": "a callback cannot follow fits that run in other processes",
    "checkpoint": "one checkpoint file cannot hold several laws' searches",
    "resume": "one checkpoint file cannot hold several laws' searches",
}


def bic(rmsape: float, n_points: int, n_constants: int) -> float:
    """Schwarz's information criterion of a fit on its relative residuals.

    Parameters
    ----------
    rmsape : float
        The fit's RMSAPE in percent (the root mean square of the relative residuals
        times 100).
    n_points : int
        Number of objective points.
    n_constants : int
        Number of constants of the fitted model.

    Returns
    -------
    float
        ``n ln((rmsape/100)²) + k ln(n)``; +inf for a fit without a finite error.

    Examples
    --------
    >>> round(bic(1.0, 100, 4), 1)  # 100 ln(1e-4) + 4 ln(100)
    -902.6
    """
    e = float(rmsape) / 100.0
    if not math.isfinite(e) or n_points < 1:
        return math.inf
    return n_points * math.log(max(e, 1e-300) ** 2) + n_constants * math.log(n_points)


def resolve_laws(laws: Any) -> list[str]:
    """The registered laws named by ``laws``: ``"all"``, a comma-separated string, or a
    sequence of names (each once, in the given order).

    Parameters
    ----------
    laws : str or sequence of str

    Returns
    -------
    list of str

    Raises
    ------
    ValueError
        One line naming the first unknown law (nothing is fitted).

    Examples
    --------
    >>> resolve_laws("yeoh,neo_hooke,yeoh")
    ['yeoh', 'neo_hooke']
    >>> resolve_laws(["yeoh", "gentt"])
    Traceback (most recent call last):
    ...
    ValueError: laws: unknown law 'gentt'; choose among arruda_boyce, gent, mooney_rivlin, ...
    """
    known = list(hyperelastic.available())
    if isinstance(laws, str):
        names = known if laws.strip() == "all" else [s.strip() for s in laws.split(",")]
    elif isinstance(laws, Sequence) and all(isinstance(s, str) for s in laws):
        names = [s.strip() for s in laws]
    else:
        raise ValueError(f"laws is a {type(laws).__name__}: give a list of law names, a "
                         "comma-separated string, or 'all'")
    if not names or any(not s for s in names):
        raise ValueError("laws: an empty law name; give names such as "
                         "'mooney_rivlin,yeoh' or 'all'")
    for s in names:
        if s not in known:
            raise ValueError(f"laws: unknown law {s!r}; choose among "
                             f"{', '.join(known[:3])}, ... (vhfit.hyperelastic.available())")
    return list(dict.fromkeys(names))


@dataclass(frozen=True)
class Comparison:
    """Result of :func:`compare`: each law's fit and the ranked table.

    Attributes
    ----------
    rows : list of dict
        One per law, best first (:data:`RULE`); failed fits last. Keys: ``rank``,
        ``law``, ``rmsape``, ``per_mode`` (mode -> RMSAPE %, the root mean square of
        the per-curve RMSAPE of that mode's curves), ``n_constants``, ``n_points``,
        ``bic``, ``stable`` (True/False/None), ``stability`` (text), ``cards``
        (solver -> ``{"rmsape", "allowed", "exceeds", "own"}`` or ``{"error"}``;
        ``own``: the solver integrates the fit's formulation), ``cards_pass``,
        ``qualified``, ``wall_time`` (s), ``n_prony`` and ``error`` (None, or why the
        fit failed).
    fits : dict
        Law -> :class:`vhfit.Calibration` (the laws that were fitted, in the given order).
    rule : str
        How the best was chosen.
    wall_time : float
        Seconds for the whole comparison.
    """

    rows: list = field(default_factory=list)
    fits: dict = field(default_factory=dict)
    rule: str = RULE
    wall_time: float = 0.0

    @property
    def best(self) -> str | None:
        """The law ranked first (None when no fit has a finite error)."""
        if self.rows and self.rows[0]["error"] is None and math.isfinite(self.rows[0]["bic"]):
            return self.rows[0]["law"]
        return None

    @property
    def calibration(self) -> Calibration | None:
        """The best law's :class:`vhfit.Calibration` (None without a best)."""
        return None if self.best is None else self.fits[self.best]

    def table(self) -> str:
        """The ranked table as text (errors in %, BIC, stability, card check, time)."""
        return "\n".join(table_lines(self))

    def __str__(self) -> str:
        return self.table()

    def to_dict(self) -> dict:
        """JSON-ready: the rule, the best law, the ranked rows (no calibrations)."""
        return {"rule": self.rule, "best": self.best, "wall_time": float(self.wall_time),
                "rows": [_finite(r) for r in self.rows]}


def _finite(v: Any) -> Any:
    """``v`` with every non-finite float as None (JSON has no inf)."""
    if isinstance(v, dict):
        return {k: _finite(x) for k, x in v.items()}
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def _fmt(v: float, digits: int = 4) -> str:
    return "-" if v is None or not math.isfinite(v) else f"{v:.{digits}g}"


def table_lines(comp: Comparison) -> list[str]:
    """The lines of :meth:`Comparison.table`."""
    rows = comp.rows
    modes = list(dict.fromkeys(m for r in rows for m in r["per_mode"]))
    solvers = list(dict.fromkeys(s for r in rows for s in r["cards"]))
    n = next((r["n_points"] for r in rows), 0)
    head = (f"{'rank':<5}{'law':<22}{'RMSAPE %':>9}"
            + "".join(f"{m[:11]:>12}" for m in modes)
            + f"{'consts':>7}{'BIC':>10}{'stable':>8}"
            + "".join(f"{s[:9]:>10}" for s in solvers) + f"{'time s':>8}")
    out = [f"laws compared: {len(rows)} on {n} objective points; best = {comp.best or 'none'}",
           f"ranked by {comp.rule}",
           "BIC = n ln((RMSAPE/100)^2) + k ln(n), n objective points, k constants; per-mode "
           "columns: RMSAPE % of each test mode; cards: ok / EXCEEDS (in the solver's own "
           "formulation), n/a (the solver integrates another formulation), - (no card)",
           head]
    for r in rows:
        if r["error"] is not None:
            out.append(f"{'-':<5}{r['law']:<22}failed: {r['error']}")
            continue
        stable = {True: "yes", False: "NO", None: "-"}[r["stable"]]
        cells = []
        for s in solvers:
            c = r["cards"].get(s)
            cells.append("-" if c is None or "error" in c else
                         "n/a" if not c["own"] else "EXCEEDS" if c["exceeds"] else "ok")
        out.append(f"{r['rank']:<5}{r['law']:<22}{_fmt(r['rmsape']):>9}"
                   + "".join(f"{_fmt(r['per_mode'].get(m)):>12}" for m in modes)
                   + f"{r['n_constants']:>7}{_fmt(r['bic'], 6):>10}{stable:>8}"
                   + "".join(f"{c:>10}" for c in cells) + f"{r['wall_time']:>8.3g}")
    return out


def _mode(c) -> str:
    return "moduli" if c.is_moduli else str(c.deformation)


def _card_check(cal: Calibration, curves, solvers: Sequence[str] | None) -> dict:
    """Solver -> the check of the law's card in that solver (or why there is none)."""
    law = cal.model.hyperelastic.name
    chosen = [s for s in (solvers if solvers is not None else solver_names())]
    out: dict[str, dict] = {}
    for s in chosen:
        if law not in supported_laws(s):
            out[s] = {"error": f"no {s} card for {law}"}
            continue
        try:
            with _warnings.catch_warnings():
                _warnings.simplefilter("ignore")
                text = export(cal, to=s)
                chk = check_cards({s: text}, curves, fits=cal)[s]
        except Exception as exc:  # a card that cannot be written or read is reported
            out[s] = {"error": " ".join(str(exc).split())}
            continue
        out[s] = {"rmsape": float(chk.rmsape), "allowed": chk.allowed,
                  "exceeds": bool(chk.exceeds),
                  "own": get_solver(s).formulation == cal.model.formulation}
    return out


def _row(law: str, cal: Calibration | None, error: str | None, curves, wall: float,
         solvers) -> dict:
    n_points = int(sum(np.size(c.target_stress) for c in curves))
    if cal is None:
        return {"law": law, "rmsape": math.inf, "per_mode": {}, "n_constants": 0,
                "n_points": n_points, "bic": math.inf, "stable": None, "stability": "",
                "cards": {}, "cards_pass": None, "qualified": False, "wall_time": wall,
                "n_prony": None, "error": error}
    modes: dict[str, list[float]] = {}
    for c, e in zip(curves, cal.per_curve_rmsape):
        modes.setdefault(_mode(c), []).append(float(e))
    per_mode = {m: float(np.sqrt(np.mean(np.square(v)))) for m, v in modes.items()}
    k = len(cal.model.param_names)
    stab = cal.stability
    cards = _card_check(cal, cal.curves or curves, solvers)
    own = [c for c in cards.values() if "error" not in c and c["own"]]
    cards_pass = None if not own else not any(c["exceeds"] for c in own)
    finite = math.isfinite(float(cal.rmsape))
    return {"law": law, "rmsape": float(cal.rmsape), "per_mode": per_mode, "n_constants": k,
            "n_points": n_points, "bic": bic(cal.rmsape, n_points, k),
            "stable": None if stab is None else bool(stab.stable),
            "stability": "" if stab is None else stab.describe(), "cards": cards,
            "cards_pass": cards_pass,
            "qualified": finite and stab is not None and bool(stab.stable)
            and cards_pass is not False,
            "wall_time": float(wall), "n_prony": cal.n_prony, "error": None}


def rank(rows: list[dict]) -> list[dict]:
    """``rows`` best first by :data:`RULE` (failed fits last), each with its ``rank``."""
    order = sorted(range(len(rows)), key=lambda i: (
        rows[i]["error"] is not None, not rows[i]["qualified"], rows[i]["bic"], i))
    out = []
    for k, i in enumerate(order, 1):
        out.append({"rank": k, **rows[i]})
    return out


def _processes(workers: Any, n_laws: int) -> int:
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or (
            workers < 1 and workers != -1):
        raise ValueError(f"workers = {workers!r}: give -1 (one process per CPU) or a whole "
                         "number >= 1 of processes to fit the laws in")
    n = (os.cpu_count() or 1) if workers == -1 else int(workers)
    return max(1, min(n, n_laws))


def compare(curves, laws: Any, *, n_prony: Any = None, solvers: Sequence[str] | None = None,
            workers: int = -1, mp_context: Any = "auto", **kwargs: Any) -> Comparison:
    """Fit several hyperelastic laws to the same curves side by side and rank them.

    Parameters
    ----------
    curves : sequence of Curve (or other test items)
        The data, as for :func:`vhfit.calibrate`.
    laws : str or sequence of str
        The laws: names, a comma-separated string, or ``"all"`` (every registered law).
    n_prony : int, "auto" or None
        As for :func:`vhfit.calibrate` (the same for every law).
    solvers : sequence of str, optional
        The solvers whose cards are checked (default: every registered solver whose
        cards hold the law).
    workers : int, default -1
        Processes that fit the laws side by side (-1: one per CPU; never more than
        the laws). Each law's own search runs in one process.
    mp_context : str or multiprocessing context, default "auto"
        Start method of those processes (see :func:`vhfit.parallel.calibrate_many`).
    **kwargs
        Further keywords of :func:`vhfit.calibrate` (``seed``, ``tau_strategy``,
        ``max_time``, ...), the same for every law. ``hyperelastic``, ``callback``,
        ``checkpoint`` and ``resume`` are refused.

    Returns
    -------
    Comparison
        Each law's calibration and the ranked table; ``.best`` and ``.calibration``
        are the law ranked first by :data:`RULE`.

    Raises
    ------
    ValueError
        Before anything is fitted: an unknown law, a refused or bad keyword.
    CalibrationError
        Before anything is fitted: a test that none of the laws can represent (confined
        compression for incompressible laws, :func:`vhfit.calibration.refuse_unrepresentable`).

    Examples
    --------
    >>> import numpy as np, vhfit
    >>> m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
    >>> true = dict(C10=0.01, C01=0.005, G1=0.5, tau1=0.01)
    >>> eps = np.linspace(-0.05, -0.5, 10)
    >>> curves = [vhfit.Curve(strain=eps, stress=m.stress(true, strain=eps, strain_rate=r,
    ...           measure="engineering"), strain_rate=r) for r in (-1.0, -100.0)]
    >>> comp = vhfit.compare(curves, ["neo_hooke", "mooney_rivlin"], n_prony=1, seed=0,
    ...                      workers=1)
    >>> comp.best
    'mooney_rivlin'
    """
    import time

    t0 = time.perf_counter()
    names = resolve_laws(laws)
    for k, why in _REFUSED.items():
        if k in kwargs and not (k == "resume" and kwargs[k] is False) and not (
                k in ("callback", "checkpoint") and kwargs[k] is None):
            raise ValueError(f"{k}: not a keyword of compare ({why})")
    if solvers is not None:
        known = solver_names()
        bad = [s for s in solvers if s not in known]
        if bad:
            raise ValueError(f"solvers: unknown solver {bad[0]!r}; choose among "
                             f"{', '.join(known)}")
    n_proc = _processes(workers, len(names))
    kwargs = {k: v for k, v in kwargs.items() if k not in _REFUSED}
    if kwargs.get("workers", 1) != 1:
        raise ValueError("workers: the processes of compare fit the laws side by side; "
                         "each law's search runs in one process (give workers=N to compare)")
    for law in names:  # every setting checked before anything is fitted
        CalibrationSettings(law, n_prony, **kwargs)
    curves = list(curves)
    refused = []  # a test no law can represent (confined compression): one line, no table
    for law in names:
        try:
            refuse_unrepresentable(curves, law)
        except CalibrationError as exc:
            refused.append(exc)
    if len(refused) == len(names):
        raise refused[0]
    # the laws with most constants (the slowest, as a rule) start first
    jobs = [dict(name=law, curves=curves, hyperelastic=law, n_prony=n_prony, **kwargs)
            for law in names]
    order = sorted(range(len(jobs)), key=lambda i: -hyperelastic.get(names[i]).n_params)
    jobs = [jobs[i] for i in order]
    results = {}
    for r in calibrate_many(jobs, None if n_proc == 1 else n_proc, mp_context=mp_context):
        results[r.name] = r
    fits, rows = {}, []
    for law in names:
        r = results[law]
        if r.ok:
            fits[law] = r.calibration
        rows.append(_row(law, r.calibration if r.ok else None, r.error, curves,
                         r.wall_time, solvers))
    return Comparison(rows=rank(rows), fits=fits, rule=RULE,
                      wall_time=time.perf_counter() - t0)
