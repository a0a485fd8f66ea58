"""The result of a calibration: constants, errors, report, and its results file."""

from __future__ import annotations

import json
import platform
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from datetime import datetime, timezone

import numpy as np

from vhfit._io import atomic_write, dumps
from vhfit._words import Worded
from vhfit.calibration._settings import CalibrationSettings, shift_law
from vhfit.calibration._stop import STATUS, Stop
from vhfit.data import TestItem
from vhfit.history import History
from vhfit.model import ModelSpec, ViscoHyperelastic, model_from_spec, spec_from_dict
from vhfit.stability import StabilityReport, drucker
from vhfit.viscous import ParamLayout

__all__ = ["Calibration", "CalibrationWarning", "RESULTS_FORMAT", "set_html_report", "grade",
           "GOOD_FIT", "WITHIN_FIT", "ROUGH_FIT"]

#: The results format this vhfit writes: 2 adds the model's spec (``"spec"``,
#: :meth:`vhfit.model.ModelSpec.to_dict`) to each fit.
RESULTS_FORMAT = "vhfit-results-2"
#: The results formats this vhfit reads: 1 has no spec (the model is read from its
#: ``hyperelastic``, ``n_prony`` and ``formulation`` and the accuracy from its options).
READ_FORMATS = ("vhfit-results-1", RESULTS_FORMAT)

#: The HTML report's builders (``"write"`` and ``"repr"``), given by :mod:`vhfit.report`
#: when it is imported: it draws with the plot and export modules, which sit above this
#: layer, so this layer only calls what it was handed (vhfit's ``__init__`` imports it).
_HTML: dict = {}


def set_html_report(write, repr_html) -> None:
    """Install the builders behind :meth:`Calibration.report` and ``_repr_html_``.

    Parameters
    ----------
    write : callable
        ``write(cal, path, curves=None, **kw)`` writes the report file.
    repr_html : callable
        ``repr_html(cal) -> str``: the verdict and the main plot as an HTML fragment.

    Returns
    -------
    None

    Examples
    --------
    >>> import vhfit.report  # installs its builders on import
    """
    _HTML["write"], _HTML["repr"] = write, repr_html


def _versions() -> dict[str, str]:
    from vhfit._version import __version__, package_version

    return {
        "vhfit": __version__,
        "numpy": np.__version__,
        "scipy": package_version("scipy"),
        "numba": package_version("numba"),  # not imported for it: a moduli fit needs none
        "python": platform.python_version(),
        "platform": platform.platform(),
    }


def _curve_info(c) -> dict:
    if c.is_moduli:  # frequency sweeps and relaxation tests
        return c.curve_info()
    return {
        "name": str(c.name),
        "strain_rate": None if c.strain_rate is None else float(c.strain_rate),
        "deformation": c.deformation,
        "measure": c.measure,
        "n_points": int(np.size(c.target_stress)),
        "source": c.source,
    }


def _fine_history(h: History, points: int) -> tuple[np.ndarray, History]:
    """A fine grid along a history: uniform in time, or for an equilibrium curve uniform
    in its strain (time NaN; an equilibrium curve with a second prescribed stretch keeps
    its own samples)."""
    if not h.is_equilibrium:
        t = np.linspace(0.0, h.duration, points)
        return t, h.with_outputs(t)
    if h.stretch2 is not None:  # a second prescribed stretch: no one-strain fine grid
        return np.full(h.out_time.size, np.nan), h.with_outputs(h.out_time)
    e = h.out_strain
    fine = np.linspace(float(e.min()), float(e.max()), points)
    return np.full(points, np.nan), History.equilibrium(fine, deformation=h.deformation)


def _n_prony(n, params: dict) -> int:
    """The number of Prony terms of a results entry: its ``n_prony``, which its
    parameters must match (``G1, tau1 ... GN, tauN``, all of them)."""
    found = ParamLayout.count_terms(params)
    # compared before any model is built: n_prony = 2**70 would never finish building
    if isinstance(n, bool) or not isinstance(n, (int, float)) or n != found:
        raise ValueError(f"n_prony = {n!r} does not fit 'params', which hold {found} "
                         "relaxation times")
    return found


def _spec_of(res: dict, options: dict) -> ModelSpec:
    """The model spec of a results entry: its ``spec`` (format 2), else its flat fields
    with the accuracy of its options (format 1); its terms must be those of its
    parameters (compared before any model is built)."""
    if "spec" in res:
        spec = spec_from_dict(res)
        _n_prony(spec.n_prony, res["params"])
        return spec
    if not isinstance(res["hyperelastic"], str):
        raise TypeError("entry 'hyperelastic' is not a law's name")
    flat = {k: res[k] for k in ("hyperelastic", "formulation") if k in res}
    return spec_from_dict({**flat, "n_prony": _n_prony(res.get("n_prony", 0), res["params"]),
                           "rtol": float(options.get("rtol", 1e-6))})


def _shift_from(d) -> dict:
    """The ``shift`` fields of a Calibration from the results file's ``shift`` entry."""
    if not isinstance(d, dict):
        return {}
    try:
        return _shift_fields(d)
    except (KeyError, TypeError, ValueError) as exc:
        raise ValueError(f"entry 'shift' is not a shift law and table ({exc})") from None


def _shift_fields(d: dict) -> dict:
    law = shift_law(d.get("law"), d.get("constants") or {})
    table = dict(zip(map(float, d.get("temperatures", [])), map(float, d.get("log_aT", []))))
    T_ref = d.get("T_ref")
    return {"shift": law, "shift_table": table, "shift_source": d.get("source"),
            "T_ref": None if T_ref is None else float(T_ref)}


#: The entries of a results file that :meth:`Calibration.from_dict` reads: the others are
#: the file's context (``Calibration.context``).
_OWN_KEYS = frozenset((
    "hyperelastic", "formulation", "n_prony", "spec", "param_names", "units", "params", "g",
    "g_inf", "rmsape", "per_curve_rmsape", "curve_names", "nit", "nfev", "wall_time", "stop_reason",
    "bounds", "confidence", "stability", "order_scan", "warnings", "headlines", "options",
    "shift", "history", "fits", "settings"))


#: The plain verdict of a fit's RMSAPE (percent, paper Eq. 20): at most ``GOOD_FIT`` a
#: good fit, at most ``WITHIN_FIT`` within 10 %, at most ``ROUGH_FIT`` a rough fit, above
#: it poor (docs/cli.md, "The summary").
GOOD_FIT, WITHIN_FIT, ROUGH_FIT = 5.0, 10.0, 25.0


def grade(rmsape: float) -> tuple[str, str]:
    """The verdict of an overall RMSAPE in percent: (level, plain words).

    Parameters
    ----------
    rmsape : float
        The fit's RMSAPE, percent.

    Returns
    -------
    (str, str)
        Level ``"good"``, ``"fair"`` or ``"poor"``, and the words of the verdict.

    Examples
    --------
    >>> grade(3.0)
    ('good', 'good fit')
    >>> grade(7.5)[1]
    'fits within 10 %'
    """
    e = float(rmsape)
    if not np.isfinite(e):
        return "poor", "no valid fit: the error is not finite; check the data and the model"
    if e <= GOOD_FIT:
        return "good", "good fit"
    if e <= WITHIN_FIT:
        return "fair", "fits within 10 %"
    if e <= ROUGH_FIT:
        return "fair", "rough fit: check the worst curve and the residuals"
    return "poor", ("poor: the law cannot follow the data; try another model (vhfit fit "
                    "--model all compares them), more Prony terms (--prony auto) or check "
                    "the data")


#: The levels of :func:`grade`, best first (a page's colour is the worst of its fits').
GRADES = ("good", "fair", "poor")


def grade_word(rmsape: float) -> str:
    """The verdict of :func:`grade` without its advice: the words before the first colon.

    Examples
    --------
    >>> grade_word(3.0), grade_word(17.0), grade_word(40.0)
    ('good fit', 'rough fit', 'poor')
    """
    return grade(rmsape)[1].split(":")[0]


def worst_grade(levels) -> str:
    """The worst of grade levels (:data:`GRADES`); ``"good"`` for none.

    Examples
    --------
    >>> worst_grade(["good", "poor", "fair"])
    'poor'
    """
    return max(levels, key=GRADES.index, default=GRADES[0])


def _g(v: float, digits: int = 4) -> str:
    """A number rounded for reading."""
    return f"{float(v):.{digits}g}"


class CalibrationWarning(Worded, UserWarning):
    """Something about a calibration the user should know (floor active, unidentifiable τ…)."""



@dataclass(frozen=True)
class Calibration:
    """Result of :func:`calibrate`: built once, complete, and not changed afterwards (a
    variant is made with :func:`dataclasses.replace`).

    Attributes
    ----------
    model : ViscoHyperelastic
        The calibrated model (after pruning of negligible Prony terms).
    params : dict
        Name -> value (moduli in MPa, τ in s). Hyperelastic constants are long-term.
    rmsape : float
        Eq. 20 in percent on the objective points.
    per_curve_rmsape : list of float
        Eq. 20 of each curve alone, percent.
    nit, nfev : int
        Generations and model evaluations of the global search (plus polish evaluations).
    wall_time : float
        Seconds.
    stop_reason : Stop
        Why the global search stopped: its kind (``stop_reason.kind``) and its sentence
        (``str(stop_reason)``: "converged", "target reached", "target reached by a
        polish of the best member", "max_time", "maxiter", "interrupted", ...). A
        sentence given is read as the stop it says (:meth:`Stop.read`).
    g, g_inf : list of float, float
        Dimensionless Prony weights (docs/theory.md §3).
    bounds : dict
        Search bounds used (τ bounds in s).
    history : dict
        Per-generation best and mean error and wall time, of the objective the search
        compares (with Prony terms, the separable search's coarser model and, for long
        records, fewer points: docs/theory.md §12); ``rmsape`` is that of every point.
    confidence : dict
        Name -> (low, high) 95 % interval from the Jacobian at the optimum.
    stability : StabilityReport
    order_scan : list of dict
        With ``n_prony="auto"``: error against N.
    warnings : list of str
    headlines : list of str
        The warnings that change how the result may be used (a g∞ at its floor, Prony
        terms the data cannot identify, constants the data do not determine: terms that
        act as one, effectively zero constants, intervals wider than their value):
        :meth:`summary` and the solver cards' comments put them first.
    shift : WLF, Arrhenius, PolynomialShift or None
        Time–temperature shift law of tests at several temperatures: the given law, or
        the WLF law fitted to the shift factors used — where that fit degenerates, the law
        the data choose (:func:`vhfit.tts.choose_shift_law`; docs/dma.md); None when every test
        was at one temperature. The constants are those at ``T_ref``.
    shift_table : dict
        Temperature -> log10 a_T applied to the tests at it.
    shift_source : str or None
        "law" (given), "table" (given factors), "overlap" (built from the sweeps).
    T_ref : float or None
        Reference temperature of the constants (with a shift).
    curves : list
        The curves (at ``T_ref``) it was fitted to, for its report and plots; not saved
        in the results file (empty after :meth:`load`).
    settings : CalibrationSettings or None
        How the fit was made: :func:`calibrate`'s arguments, checked (None for a result
        built by hand or read from a results file written before they were recorded).
    """

    model: ViscoHyperelastic
    params: dict
    rmsape: float
    per_curve_rmsape: list
    nit: int
    nfev: int
    wall_time: float
    stop_reason: Stop
    g: list = field(default_factory=list)
    g_inf: float = 1.0
    bounds: dict = field(default_factory=dict)
    history: dict = field(default_factory=dict)
    confidence: dict = field(default_factory=dict)
    stability: StabilityReport | None = None
    order_scan: list = field(default_factory=list)
    warnings: list = field(default_factory=list)
    headlines: list = field(default_factory=list)
    options: dict = field(default_factory=dict)
    curve_names: list = field(default_factory=list)
    shift: object = None
    shift_table: dict = field(default_factory=dict)
    shift_source: str | None = None
    T_ref: float | None = None
    settings: CalibrationSettings | None = field(default=None, repr=False, compare=False)
    #: formulation -> fit, of a results file that holds several (:meth:`load`)
    fits: dict = field(default_factory=dict, repr=False, compare=False)
    #: the results file's entries that are not the fit's own (inputs, options, cards)
    context: dict = field(default_factory=dict, repr=False, compare=False)
    curves: list = field(default_factory=list, repr=False, compare=False)

    def __post_init__(self):
        if not isinstance(self.stop_reason, Stop):  # a sentence (by hand, a results file)
            object.__setattr__(self, "stop_reason", Stop.read(self.stop_reason))

    @property
    def interrupted(self) -> bool:
        """Whether the search was interrupted: the result is the best found so far."""
        return self.stop_reason.interrupted

    @property
    def x(self) -> np.ndarray:
        """Parameters as an array in ``model.param_names`` order."""
        return self.model.as_array(self.params)

    @property
    def n_prony(self) -> int:
        return self.model.n_prony

    def predict(self, history=None, **kwargs) -> np.ndarray:
        """Stress of the calibrated material along a history or curve (see ``model.stress``)."""
        if not kwargs and isinstance(history, TestItem):
            kwargs["measure"] = history.measure
        return self.model.stress(self.params, history, **kwargs)

    def worst_curve(self) -> tuple[str, float] | None:
        """Name and RMSAPE (percent) of the curve with the largest error; None with fewer
        than two curves.

        Returns
        -------
        (str, float) or None

        Examples
        --------
        >>> import vhfit
        >>> cal = vhfit.Calibration(model=vhfit.ViscoHyperelastic("neo_hooke", 0),
        ...                         params=dict(C10=0.5), rmsape=6.0,
        ...                         per_curve_rmsape=[2.0, 9.0], nit=1, nfev=1,
        ...                         wall_time=0.0, stop_reason="converged",
        ...                         curve_names=["slow", "fast"])
        >>> cal.worst_curve()
        ('fast', 9.0)
        """
        errs = [float(e) for e in (self.per_curve_rmsape or [])]
        if len(errs) < 2:
            return None
        k = int(np.argmax(np.where(np.isfinite(errs), errs, np.inf)))
        names = list(self.curve_names or [])
        return (names[k] if k < len(names) else f"curve {k + 1}"), errs[k]

    def verdict(self, *, interrupted: bool = False) -> str:
        """One line: the error, a plain verdict (:func:`grade`) and the worst curve.

        Parameters
        ----------
        interrupted : bool
            The search was interrupted (its run, or a signal that stopped it): the line
            says so first.

        Returns
        -------
        str

        Examples
        --------
        >>> cal.verdict()  # doctest: +SKIP
        'RMSAPE 6 %: fits within 10 %; worst curve fast (9 %)'
        """
        text = f"RMSAPE {_g(self.rmsape)} %: {grade(self.rmsape)[1]}"
        worst = self.worst_curve()
        if worst is not None:
            text += f"; worst curve {worst[0]} ({_g(worst[1])} %)"
        stab = self.stability
        if stab is not None and not stab.stable:  # before anything else: not usable as is
            lo, hi = stab.stretch_range
            text = (f"NO STABLE LAW: {stab.describe()} within the stated {lo:.3g} <= λ <= "
                    f"{hi:.3g}; give a narrower stability_range (--stability-range), wider "
                    "bounds (--bounds) or another law. " + text)
        if interrupted:
            text = "INTERRUPTED (best so far, not converged): " + text
        return text

    def summary(self, verdict: bool = True) -> str:
        """A readable summary, top-down: the verdict, the warnings, then the constants
        with their intervals, the errors per curve and the checks.

        Parameters
        ----------
        verdict : bool
            Start with :meth:`verdict` (the command line puts it above its own lines).

        Returns
        -------
        str
            Numbers rounded for reading (4–6 significant digits); the results file and
            the cards keep full precision.
        """
        units = dict(zip(self.model.param_names, self.model.units))
        lines = [
            *([self.verdict()] if verdict else []),
            f"vhfit calibration: {self.model.spec().describe(formulation=True)}",
            f"RMSAPE {self.rmsape:.4g} %   generations {self.nit}   evaluations {self.nfev}   "
            f"wall {self.wall_time:.2f} s   stop: {self.stop_reason}",
            *(f"WARNING: {h}" for h in self.headlines),
            *(f"warning: {w}" for w in self.warnings if w not in self.headlines),
            *([f"note: {self.options['n_prony_reason']}"]
              if self.options.get("n_prony_reason") else []),
            "",
            f"{'parameter':<10}{'value':>14}  {'unit':<5}{'95 % interval':>30}",
        ]
        for name, v in self.params.items():
            ci = self.confidence.get(name)
            cis = f"[{ci[0]:.4g}, {ci[1]:.4g}]" if ci else ""
            lines.append(f"{name:<10}{v:>14.6g}  {units[name]:<5}{cis:>30}")
        if self.shift_source is not None:
            lines += ["", *self._shift_lines()]
        if self.n_prony:
            lines.append("")
            lines.append("g_i = " + ", ".join(f"{g:.6g}" for g in self.g)
                         + f"   g_inf = {self.g_inf:.6g}")
        lines.append("")
        lines.append("per-curve RMSAPE:")
        for name, e in zip(self.curve_names, self.per_curve_rmsape):
            lines.append(f"  {name:<30} {e:.4g} %")
        if self.order_scan:
            lines.append("")
            lines.append("error against number of Prony terms:")
            for row in self.order_scan:
                mark = "  <- chosen" if row["n_prony"] == self.options.get("n_prony_chosen") else ""
                lines.append(
                    f"  N = {row['n_prony']}: RMSAPE {row['rmsape']:.4g} %  "
                    f"(effective N = {row['effective_n']}){mark}"
                )
        if self.stability is not None:
            lines.append("")
            lines.append("stability: " + self.stability.describe())
        return "\n".join(lines)

    def _shift_lines(self) -> list[str]:
        """The time–temperature shift in a few lines of the summary."""
        how = {"law": "given", "table": "fitted to the given shift factors",
               "overlap": "fitted to the shift factors built from the sweeps' overlap"}
        law = self.shift
        if law is None:
            head = (f"time-temperature shift: given table (T_ref {_g(self.T_ref, 6)}), no "
                    "law fitted")
        else:
            consts = ", ".join(f"{k} = {v:.6g}" for k, v in law.constants().items()
                               if k != "T_ref")
            head = (f"time-temperature shift: {law.name.upper()} {consts} at T_ref = "
                    f"{law.T_ref:g} ({how.get(self.shift_source, self.shift_source)})")
        table = "  ".join(f"{T:g}: {L + 0.0:.4g}" for T, L in sorted(self.shift_table.items())
                          ) or "none (no test has a temperature)"
        return [head, f"  log10 a_T by temperature: {table}",
                "  constants above are at T_ref; a test at T ran with its times / a_T"]

    def _shift_dict(self) -> dict:
        law = self.shift
        return {
            "law": None if law is None else law.name,
            "constants": None if law is None else law.constants(),
            "T_ref": None if self.T_ref is None else float(self.T_ref),
            "source": self.shift_source,
            "temperatures": [float(T) for T in self.shift_table],
            "log_aT": [float(v) for v in self.shift_table.values()],
        }

    def to_dict(self) -> dict:
        """JSON-ready dict with everything needed to reproduce and export the result
        (a ``shift`` entry only for tests at several temperatures)."""
        out = self._base_dict()
        if self.shift_source is not None:
            out["shift"] = self._shift_dict()
        return out

    def _base_dict(self) -> dict:
        return {
            **self.model.spec().flat_fields(),
            "spec": self.model.spec().to_dict(),
            "param_names": list(self.model.param_names),
            "units": list(self.model.units),
            "params": {k: float(v) for k, v in self.params.items()},
            "g": [float(v) for v in self.g],
            "g_inf": float(self.g_inf),
            "rmsape": float(self.rmsape),
            "per_curve_rmsape": [float(v) for v in self.per_curve_rmsape],
            "curve_names": list(self.curve_names),
            "nit": int(self.nit),
            "nfev": int(self.nfev),
            "wall_time": float(self.wall_time),
            "stop_reason": self.stop_reason.message,
            "bounds": {k: [float(a), float(b)] for k, (a, b) in self.bounds.items()},
            "confidence": {k: [float(a), float(b)] for k, (a, b) in self.confidence.items()},
            "stability": None if self.stability is None else {
                "stable": self.stability.stable,
                "stretch_range": list(self.stability.stretch_range),
                "principal": self.stability.principal,
                "unstable": {k: [list(i) for i in v] for k, v in self.stability.unstable.items()},
            },
            "order_scan": self.order_scan,
            "warnings": list(self.warnings),
            "headlines": list(self.headlines),
            "options": self.options,
        }

    def save(self, path, *, interrupted: bool = False, curves: Sequence | None = None,
             extra: dict | None = None) -> None:
        """Write the results file (JSON) atomically: :meth:`to_dict` plus its context, and
        the settings it was made with (``"settings"``: :meth:`CalibrationSettings.to_dict`).

        Parameters
        ----------
        path : path-like
            The file to write (``results.json`` of ``vhfit fit``).
        interrupted : bool
            The search did not run to its end (the file's ``"status"`` is
            ``"interrupted"``, else ``"complete"``).
        curves : sequence of Curve, optional
            The fitted curves, described by name, rate, measure, size and source.
        extra : dict, optional
            Further top-level entries (the command line adds its inputs and options).
        """
        res = self.to_dict()
        res.update({
            "format": RESULTS_FORMAT,
            "status": STATUS[bool(interrupted)],
            "interrupted": bool(interrupted),
            "curves": [_curve_info(c) for c in (curves or [])],
            "versions": _versions(),
            "timestamp": datetime.now(timezone.utc).isoformat(timespec="seconds"),
            "history": self.history,
        })
        if self.settings is not None:
            res["settings"] = self.settings.to_dict()
        res.update(extra or {})
        atomic_write(path, dumps(res, indent=2) + "\n")

    @classmethod
    def load(cls, path) -> Calibration:
        """Read a results file written by :meth:`save` (or by ``vhfit fit``).

        The model (law, number of terms, formulation and accuracy) and constants, errors,
        counts, bounds, intervals, warnings, history and time–temperature shift come
        back; the stability report is recomputed from the constants. A file that holds
        several fits (``vhfit fit --for`` solvers of different formulations) gives each
        in :attr:`fits`, and the file's other entries (its inputs, options and cards) in
        :attr:`context`.

        Parameters
        ----------
        path : path-like
            The results file.

        Returns
        -------
        Calibration

        Raises
        ------
        ValueError
            One line naming the file, for a file that is not valid JSON (e.g. truncated),
            not a results file, in a format this version does not read (it reads
            :data:`READ_FORMATS`: today's and the one before the model spec), or naming a
            law or formulation this vhfit does not know.

        Examples
        --------
        >>> import os, tempfile, vhfit
        >>> form = [f for f in vhfit.formulations.FORMULATIONS if f != "hereditary"][0]
        >>> m = vhfit.ViscoHyperelastic("neo_hooke", 1, formulation=form)
        >>> cal = vhfit.Calibration(model=m, params=dict(C10=0.5, G1=3.0, tau1=0.1),
        ...                         rmsape=1.0, per_curve_rmsape=[1.0], nit=1, nfev=1,
        ...                         wall_time=0.0, stop_reason="converged")
        >>> path = os.path.join(tempfile.mkdtemp(), "results.json")
        >>> cal.save(path)
        >>> back = vhfit.Calibration.load(path)
        >>> back.model.formulation == form, back.params == cal.params
        (True, True)
        """
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except UnicodeDecodeError:
            raise ValueError(f"{path}: not a text file; give the results.json written by "
                             "vhfit") from None
        try:
            res = json.loads(text)
        except ValueError as exc:
            raise ValueError(f"{path}: not valid JSON ({exc}; truncated?); give the complete "
                             "results.json written by vhfit") from None
        if not isinstance(res, dict) or "params" not in res or "hyperelastic" not in res:
            raise ValueError(f"{path}: not a vhfit results file (no 'hyperelastic' and "
                             "'params'); give the results.json written by vhfit")
        fmt = res.get("format", RESULTS_FORMAT)
        if not (isinstance(fmt, str) and fmt.startswith("vhfit-results-")):
            raise ValueError(f"{path}: format {fmt!r} is not a vhfit results format; give "
                             "the results.json written by vhfit")
        if fmt not in READ_FORMATS:
            raise ValueError(f"{path}: results format {fmt!r}, written by another version "
                             f"of vhfit; this version reads {' and '.join(map(repr, READ_FORMATS))}"
                             ": rerun the fit with this version, or read it with the version "
                             "that wrote it")
        own = cls.from_dict(res, where=str(path))
        fits = res.get("fits") or {}
        if not isinstance(fits, dict):
            raise ValueError(f"{path}: 'fits' is not a mapping of formulation to fit; give "
                             "the results.json written by vhfit")
        others = {}
        for form, entry in fits.items():
            if form != own.model.formulation:
                others[form] = cls.from_dict(entry, where=f"{path}: entry 'fits', '{form}'")
        every: dict = {}  # filled below: the loaded result is its own first fit
        cal = replace(own, fits=every,
                      context={k: v for k, v in res.items() if k not in _OWN_KEYS})
        every.update({cal.model.formulation: cal, **others})
        return cal

    @classmethod
    def from_dict(cls, res: dict, *, where: str = "results") -> Calibration:
        """A Calibration from :meth:`to_dict` (one entry of a results file).

        Parameters
        ----------
        res : dict
            What :meth:`to_dict` wrote.
        where : str
            Names the source in error messages.

        Returns
        -------
        Calibration

        Examples
        --------
        >>> import vhfit
        >>> m = vhfit.ViscoHyperelastic("yeoh", 0)
        >>> cal = vhfit.Calibration(model=m, params=dict(C10=0.5, C20=-0.01, C30=1e-3),
        ...                         rmsape=1.0, per_curve_rmsape=[1.0], nit=1, nfev=1,
        ...                         wall_time=0.0, stop_reason="converged")
        >>> Calibration.from_dict(cal.to_dict()).params == cal.params
        True
        """
        if not isinstance(res, dict) or "params" not in res or "hyperelastic" not in res:
            raise ValueError(f"{where}: not a vhfit fit (no 'hyperelastic' and 'params'); "
                             "give the results.json written by vhfit")
        try:
            return cls._from_dict(res)
        except (KeyError, TypeError, ValueError, AttributeError, IndexError,
                OverflowError) as exc:
            what = f"missing entry {exc}" if isinstance(exc, KeyError) else str(exc)
            raise ValueError(f"{where}: {' '.join(what.split())}; give the results.json "
                             "written by vhfit") from None

    @classmethod
    def _make(cls, model: ViscoHyperelastic, x, **record) -> Calibration:
        """The one place the library builds a Calibration, complete: the end of a fit
        (``calibration._report.finish``) and each entry of a results file
        (:meth:`from_dict`) both come here. The constants are read from ``x`` in the
        model's order; a per-curve error list and the curve names must agree."""
        per_curve, names = record.get("per_curve_rmsape", []), record.get("curve_names", [])
        if per_curve and names and len(per_curve) != len(names):
            raise ValueError(f"{len(per_curve)} per-curve errors for {len(names)} curves")
        return cls(model=model, params=model.as_dict(x), **record)

    @classmethod
    def _from_dict(cls, res: dict) -> Calibration:
        options = dict(res.get("options") or {})
        params = res["params"]
        if not isinstance(params, dict) or not all(
                isinstance(k, str) and isinstance(v, (int, float)) and not isinstance(v, bool)
                for k, v in params.items()):
            raise TypeError("entry 'params' is not a mapping of constant names to numbers")
        model = model_from_spec(_spec_of(res, options))
        x = model.check(params)
        lo_hi = options.get("stability_range")
        stab = drucker(model.hyperelastic, x[: model.hyperelastic.n_params],
                       tuple(lo_hi) if lo_hi else (0.2, 5.0), principal=bool(lo_hi))
        return cls._make(
            model, x, rmsape=float(res["rmsape"]),
            per_curve_rmsape=list(res.get("per_curve_rmsape", [])),
            nit=int(res.get("nit", 0)), nfev=int(res.get("nfev", 0)),
            wall_time=float(res.get("wall_time", 0.0)),
            stop_reason=Stop.read(res.get("stop_reason", "")), g=list(res.get("g", [])),
            g_inf=float(res.get("g_inf", 1.0)),
            bounds={k: tuple(v) for k, v in res.get("bounds", {}).items()},
            history=dict(res.get("history", {})),
            confidence={k: tuple(v) for k, v in res.get("confidence", {}).items()},
            stability=stab, order_scan=list(res.get("order_scan", [])),
            warnings=list(res.get("warnings", [])),
            headlines=list(res.get("headlines", [])), options=options,
            curve_names=list(res.get("curve_names", [])),
            **_shift_from(res.get("shift")),
            settings=(None if res.get("settings") is None
                      else CalibrationSettings.from_dict(res["settings"])),
        )

    def fitted_curves(self, curves: Sequence, points: int = 200) -> list[dict[str, np.ndarray]]:
        """Model stresses along each curve, at its points and on a fine grid.

        Parameters
        ----------
        curves : sequence of Curve
            The curves it was fitted to (each with ``.history`` and ``.measure``).
        points : int
            Size of the fine, uniform-in-time grid along each history.

        Returns
        -------
        list of dict
            Per curve: ``time``, ``strain``, ``stress`` (objective points: data and
            ``model``), and ``fine_time``, ``fine_strain``, ``fine_model``. Stresses are
            in the curve's own measure, MPa; strain is λ1 − 1 (γ in simple shear). An
            equilibrium curve has no time (NaN) and its fine grid is uniform in strain.
        """
        out = []
        for c in curves:
            if c.is_moduli:  # frequency sweeps and relaxation tests: moduli
                out.append(c.fitted_curve(self.model, self.params, int(points)))
                continue
            h = c.history
            measure = c.measure
            model = self.model.stress(self.params, h, measure=measure)
            t_fine, fh = _fine_history(h, int(points))
            fine = self.model.stress(self.params, fh, measure=measure)
            out.append({
                "time": (np.full(h.out_time.size, np.nan) if h.is_equilibrium
                         else np.asarray(h.out_time, dtype=np.float64)),
                "strain": np.asarray(h.out_strain, dtype=np.float64),
                "stress": np.asarray(c.target_stress, dtype=np.float64),
                "model": np.asarray(model, dtype=np.float64),
                "fine_time": t_fine,
                "fine_strain": np.asarray(fh.out_strain, dtype=np.float64),
                "fine_model": np.asarray(fine, dtype=np.float64),
            })
        return out

    def report(self, path, curves: Sequence | None = None, **kw) -> None:
        """Write the HTML report: verdict, plots, constants, checks and cards in one file.

        Parameters
        ----------
        path : path-like
            The file to write (``report.html``).
        curves : sequence of Curve, optional
            The data it was fitted to; default the curves it keeps from the fit.
        **kw
            Passed to :func:`vhfit.report.write_report`.

        Returns
        -------
        None

        Examples
        --------
        >>> cal.report("report.html")  # doctest: +SKIP
        """
        if "write" not in _HTML:
            raise RuntimeError("the HTML report is not installed: import vhfit.report")
        _HTML["write"](self, path, curves, **kw)

    def _repr_html_(self) -> str:
        """The report's verdict and main plot, for Jupyter."""
        if "repr" not in _HTML:
            return "<pre>" + self.summary().replace("&", "&amp;").replace("<", "&lt;") + "</pre>"
        return _HTML["repr"](self)

    def to_json(self, path=None, **kw) -> str:
        """Serialise :meth:`to_dict`; write it atomically to ``path`` if given."""
        text = dumps(self.to_dict(), indent=2, **kw)
        if path is not None:
            atomic_write(path, text)
        return text
