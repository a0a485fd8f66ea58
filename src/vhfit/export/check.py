"""Card check: the error each solver will show with a written card, scored against the data.

A round trip (card -> parser -> the same stresses) proves that a card carries vhfit's
numbers; it cannot show that the solver, integrating its own viscoelastic law with
those numbers, reproduces the test data. The card check does that: each card is parsed
back (:func:`vhfit.export.parse`), re-simulated in the formulation its solver
integrates (its record's ``formulation``, :class:`vhfit.export.Solver`, collected in
:data:`vhfit.formulations.SOLVER_FORMULATIONS`; docs/theory.md §14) along every test
history, and scored with RMSAPE (paper Eq. 20) on the objective points of the data.
The fit's own error is scored the same way, so the two are comparable.

A card whose solver error exceeds the fit's by more than the margin
(:func:`allowed_rmsape`: 5 % relative plus 0.01 percentage point) gets a warning that
names the remedy: a fit in that solver's formulation (``vhfit fit --for SOLVER``,
``calibrate(..., formulation=...)``).

Passing says only that the card reproduces its fit, not that the fit is good: every
card is also graded on its own error, with the thresholds of the fit's verdict
(:func:`check_words`, :func:`vhfit.calibration.grade`), and the warnings of a card's own
fit (a solver's fit after the first) are named with the card (:func:`own_fit_warnings`).

Examples
--------
>>> import numpy as np, vhfit
>>> from vhfit.export import export, get_solver, solvers
>>> from vhfit.export.check import check_card
>>> m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=1)
>>> p = dict(C10=0.2, C01=0.05, G1=1.5, tau1=0.01)
>>> eps = np.linspace(-0.05, -0.4, 8)
>>> curves = [vhfit.Curve(strain=eps, stress=m.stress(p, strain=eps, strain_rate=r,
...                       measure="engineering"), strain_rate=r) for r in (-1.0, -100.0)]
>>> same = next(s for s in solvers() if get_solver(s).formulation == m.formulation)
>>> res = check_card(export(m, p, to=same), curves, solver=same, fit=(m, p))
>>> res.formulation, res.rmsape < 1e-9, res.exceeds
('hereditary', True, False)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from vhfit.export import parse
from vhfit.export._common import is_network_model
from vhfit.export._solvers import card_body, records, solver_of
from vhfit.formulations import SOLVER_FORMULATIONS
from vhfit.model import ViscoHyperelastic, model_from_spec

__all__ = [
    "SOLVER_FORMULATIONS",
    "MARGIN_RELATIVE",
    "MARGIN_ABSOLUTE",
    "CardCheck",
    "allowed_rmsape",
    "solver_formulation",
    "in_formulation",
    "card_solver",
    "card_stress",
    "network_stress",
    "NETWORKS",
    "check_card",
    "check_cards",
    "PASSES",
    "FAILS",
    "check_words",
    "own_fit_warnings",
]

#: A card passes when its RMSAPE <= fit RMSAPE × (1 + MARGIN_RELATIVE) + MARGIN_ABSOLUTE.
MARGIN_RELATIVE = 0.05
#: ... in percentage points: room for the card's printed digits on a near-exact fit.
MARGIN_ABSOLUTE = 0.01


#: The check's word for a card within the margin of its fit, and for one beyond: what
#: "ok" means, so that nobody reads it as a verdict on the fit.
PASSES, FAILS = "ok (card = its fit)", "EXCEEDS its fit"


def check_words(rmsape: float, exceeds: bool) -> str:
    """A card check in words: whether the card reproduces its fit, then the card's own
    grade (:func:`vhfit.calibration.grade_word`, the thresholds of the fit's verdict).

    Examples
    --------
    >>> check_words(2.0, False)
    'ok (card = its fit); good fit'
    >>> check_words(23.6, False)
    'ok (card = its fit); rough fit'
    >>> check_words(30.0, True)
    'EXCEEDS its fit; poor'
    """
    from vhfit.calibration import grade_word  # on demand: the card table loads no fit code

    return f"{FAILS if exceeds else PASSES}; {grade_word(rmsape)}"


def own_fit_warnings(fits: Mapping, served: Mapping) -> list[str]:
    """The headline warnings of the cards' own fits: of every fit after the first (the
    main one, whose warnings head its summary), those the first does not have, and an
    unstable fit's stability, each naming the cards it serves.

    Parameters
    ----------
    fits : mapping of str to Calibration
        Formulation -> fit, the main fit first.
    served : mapping of str to list of str
        Formulation -> the card keys (solver names) its fit was written into.

    Returns
    -------
    list of str
        ``"<label> card's own fit ('<formulation>'): <warning>"``, one line each.
    """
    items = list(fits.items())
    if not items:
        return []
    main = items[0][1]
    shown = set(main.headlines or [])
    out = []
    for form, cal in items[1:]:
        cards = [solver_of(s).label for s in served.get(form, [])]
        if not cards:
            continue
        who = (f"{cards[0]} card's" if len(cards) == 1
               else f"{', '.join(dict.fromkeys(cards))} cards'") + f" own fit ('{form}')"
        warns = [h for h in cal.headlines or [] if h not in shown]
        stab = cal.stability
        if stab is not None and not stab.stable:
            warns.append(stab.describe())
        out += [f"{who}: {w}" for w in dict.fromkeys(warns)]
    return out


def allowed_rmsape(fit_rmsape: float) -> float:
    """The largest card RMSAPE that passes against a fit's RMSAPE (percent).

    Examples
    --------
    >>> allowed_rmsape(2.0)
    2.11
    """
    return float(fit_rmsape) * (1.0 + MARGIN_RELATIVE) + MARGIN_ABSOLUTE


def solver_formulation(solver: str) -> str:
    """The formulation the solver integrates, from its record (a card variant,
    ``NAME_VARIANT``, counts as its solver).

    Examples
    --------
    >>> from vhfit.export import records
    >>> all(solver_formulation(r.name) == r.formulation for r in records())
    True
    >>> all(solver_formulation(f"{r.name}_{v}") == r.formulation
    ...     for r in records() for v in r.variants)
    True
    """
    return solver_of(solver).formulation


def _solver_key(solver: str) -> str:
    return solver_of(solver).name


#: The card check's formulation word of a network model: its networks, integrated as the
#: solver's parallel rheological framework defines them (:mod:`vhfit.viscous`).
NETWORKS = "networks"


def _formulation_of(model) -> str:
    return NETWORKS if is_network_model(model) else str(model.formulation)


def in_formulation(model: ViscoHyperelastic, formulation: str) -> ViscoHyperelastic:
    """The same law, number of terms and tolerance, integrated in ``formulation``.

    Examples
    --------
    >>> import vhfit
    >>> m = vhfit.ViscoHyperelastic("yeoh", n_prony=2)
    >>> in_formulation(m, "hereditary") is m
    True
    """
    if formulation == _formulation_of(model):
        return model
    return model_from_spec(model.spec().replace(formulation=formulation))


def _stress(model, params, curves: Sequence) -> np.ndarray:
    """The stresses of ``model`` at every objective point of the curves (a network model
    holds its constants: ``params`` is not read)."""
    if is_network_model(model):
        return np.concatenate([network_stress(model, c.history, c.measure) for c in curves])
    return model.batch(list(curves))(model.as_array(params)[None, :])[0]


def network_stress(model, history, measure: str = "true") -> np.ndarray:
    """A network model's stress at a history's output times, in the loaded direction.

    The model is integrated along the history's breakpoints and output times together (the
    stretch is linear in time between breakpoints, as the history says).

    Parameters
    ----------
    model : vhfit.viscous.NetworkModel
    history : History
        A strain-controlled history with time (not an equilibrium one), stresses asked in
        its first loaded direction.
    measure : {"true", "engineering"}

    Returns
    -------
    ndarray
        One stress per output time, in the order of ``history.out_time``.

    Examples
    --------
    >>> import numpy as np
    >>> from vhfit.history import History
    >>> from vhfit.viscous import Network, NetworkModel
    >>> frozen = NetworkModel("neo_hooke", (0.5,), (Network("strain", 0.5, (1e-30, 1, 0)),))
    >>> h = History.constant_rate(np.array([0.0, 0.5]), 1.0)
    >>> s = network_stress(frozen, h)           # A -> 0: the instantaneous law
    >>> bool(np.allclose(s, 2 * 0.5 * (1.5**2 - 1 / 1.5) * np.array([0.0, 1.0])))
    True
    """
    if history.is_equilibrium:
        raise ValueError("an equilibrium (rate-free) curve has no time: a network model's "
                         "stress needs a history with time")
    if history.out_direction is not None and (np.asarray(history.out_direction) != 1).any():
        raise ValueError("a network model's stress is computed in the first loaded "
                         "direction only: drop the outputs of the second direction")
    t = np.union1d(history.time, history.out_time)
    extra = ({} if history.stretch2 is None
             else {"stretch2": np.interp(t, history.time, history.stretch2)})
    stress = model.stress(t, np.interp(t, history.time, history.stretch),
                          deformation=history.deformation, measure=measure, **extra)
    return np.asarray(stress, dtype=np.float64)[np.searchsorted(t, history.out_time)]


def _scores(curves: Sequence, stress: np.ndarray) -> tuple[float, list[float]]:
    """RMSAPE and per-curve RMSAPE (Eq. 20) of ``stress`` on the curves."""
    # on demand: the objective brings the file readers, which the card writers (this
    # module is imported with vhfit.export) and 'vhfit models' do not need
    from vhfit.objective import Objective

    obj = Objective(list(curves), "rmsape")
    return float(obj(stress)), [float(v) for v in obj.per_curve(stress)]


@dataclass(frozen=True)
class CardCheck:
    """What one card gives in its solver's formulation, beside the fit it came from.

    Attributes
    ----------
    solver : str
        A registered solver's name (or a card variant's, ``NAME_VARIANT``).
    formulation : str
        The formulation the card was re-simulated in (its solver's).
    rmsape : float
        RMSAPE (Eq. 20, percent) of the card's stresses against the data.
    per_curve : list of float
        The same per curve.
    fit_formulation : str or None
        The formulation of the fit the card was written from (None: not given).
    fit_rmsape : float or None
        That fit's RMSAPE on the same points, scored the same way.
    fit_per_curve : list of float
        The same per curve.
    """

    solver: str
    formulation: str
    rmsape: float
    per_curve: list
    fit_formulation: str | None = None
    fit_rmsape: float | None = None
    fit_per_curve: list = field(default_factory=list)

    @property
    def allowed(self) -> float | None:
        """The largest RMSAPE that passes (:func:`allowed_rmsape` of the fit's)."""
        return None if self.fit_rmsape is None else allowed_rmsape(self.fit_rmsape)

    @property
    def exceeds(self) -> bool:
        """The card's error exceeds the fit's by more than the margin."""
        return self.allowed is not None and not self.rmsape <= self.allowed

    def warning(self) -> str | None:
        """The headline warning of a card that fails the check, with its remedy; else None."""
        if not self.exceeds:
            return None
        name = solver_of(self.solver).label
        head = (f"{name} card: {name} will show RMSAPE {self.rmsape:.4g} % on the data, the fit "
                f"{self.fit_rmsape:.4g} % (allowed {self.allowed:.4g} %)")
        if self.fit_formulation != self.formulation:
            return (f"{head}: {name} integrates the Prony series in the '{self.formulation}' "
                    f"formulation, the fit used '{self.fit_formulation}'; fit for it with "
                    f"`vhfit fit --for {_solver_key(self.solver)}` (Python: calibrate(..., "
                    f"formulation='{self.formulation}'))")
        return (f"{head}: the card's numbers do not reproduce the fit (rounded fields?); write "
                "it in full precision (the writer's long format, if it has one)")

    def to_dict(self) -> dict:
        """The ``card_check`` entry of a results file."""
        return {
            "rmsape": float(self.rmsape),
            "per_curve": [float(v) for v in self.per_curve],
            "formulation": self.formulation,
            "fit_formulation": self.fit_formulation,
            "fit_rmsape": None if self.fit_rmsape is None else float(self.fit_rmsape),
            "allowed": self.allowed,
            "exceeds": self.exceeds,
        }


def card_stress(text: str, curves: Sequence, *, solver: str | None = None
                ) -> tuple[ViscoHyperelastic, dict, np.ndarray]:
    """Parse a card and simulate it in its solver's formulation on the curves' histories.

    Parameters
    ----------
    text : str
        The card of a registered solver (the format is guessed when ``solver`` is None).
    curves : sequence of Curve
        The test data: their histories and objective points.
    solver : str, optional
        A registered solver's name.

    Returns
    -------
    model : ViscoHyperelastic or NetworkModel
        The card's law in the solver's formulation (a network card: its network model).
    params : dict
        The card's constants in vhfit's convention (a network card: by name).
    stress : ndarray
        The model stresses at every objective point of every curve (concatenated), in
        each curve's measure.
    """
    solver = solver or card_solver(text)
    model, params = parse(text, _solver_key(solver))
    if not is_network_model(model):  # a network card holds its solver's own framework
        model = in_formulation(model, solver_formulation(solver))
    return model, params, _stress(model, params, curves)


def card_solver(text: str) -> str:
    """The solver a card is written for, from its keywords.

    Examples
    --------
    >>> import vhfit
    >>> from vhfit.export import export, solvers
    >>> m = vhfit.ViscoHyperelastic("neo_hooke", n_prony=0)
    >>> all(card_solver(export(m, {"C10": 0.5}, to=s)) == s for s in solvers())
    True
    """
    body = card_body(text)
    for rec in records():
        if rec.sniff(body):
            return rec.name
    labels = [r.label for r in records()]
    raise ValueError(f"not an {', '.join(labels[:-1])} or {labels[-1]} material card (none "
                     "of their keywords found)")


def check_card(text: str, curves: Sequence, *, solver: str | None = None,
               fit=None) -> CardCheck:
    """Score one card against the data in its solver's formulation.

    Parameters
    ----------
    text : str
        The card.
    curves : sequence of Curve
        The data the fit was made to (the same objective points).
    solver : str, optional
        The card's solver (guessed from the text when None).
    fit : Calibration or (ViscoHyperelastic, params), optional
        The fit the card was written from: its own RMSAPE is scored the same way, in its
        own formulation (``fit.model.formulation``), for the comparison.

    Returns
    -------
    CardCheck
    """
    return _check(text, curves, solver, None if fit is None else _fit_scores(fit, curves))


def _fit_scores(fit, curves: Sequence) -> dict:
    """The fit's formulation and its RMSAPE, overall and per curve, on the curves."""
    fm, fp = (fit.model, fit.params) if hasattr(fit, "model") else fit
    e, per = _scores(curves, _stress(fm, fp, curves))
    return dict(fit_formulation=_formulation_of(fm), fit_rmsape=e, fit_per_curve=per)


def _check(text: str, curves: Sequence, solver: str | None, fit_scores: dict | None
           ) -> CardCheck:
    solver = solver or card_solver(text)
    model, params, stress = card_stress(text, curves, solver=solver)
    e, per = _scores(curves, stress)
    return CardCheck(solver=solver, formulation=_formulation_of(model), rmsape=e,
                     per_curve=per, **(fit_scores or {}))


def check_cards(cards: Mapping[str, str], curves: Sequence, *, fits=None) -> dict[str, CardCheck]:
    """Score every card of a fit against the data (see :func:`check_card`).

    Parameters
    ----------
    cards : mapping of str to str
        Card key (a registered solver's name, or a variant's: ``NAME_VARIANT``) ->
        card text.
    curves : sequence of Curve
        The data.
    fits : Calibration, or mapping of solver to Calibration, optional
        The fit each card was written from (one for all cards, or one per solver).

    Returns
    -------
    dict of str to CardCheck
        In the order of ``cards``.
    """
    out, scored = {}, {}  # a fit serving several cards is scored once
    for solver, text in cards.items():
        fit = fits.get(solver) if isinstance(fits, Mapping) else fits
        if fit is not None and id(fit) not in scored:
            scored[id(fit)] = _fit_scores(fit, curves)
        out[solver] = _check(text, curves, solver, scored.get(id(fit)))
    return out
