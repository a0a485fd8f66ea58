"""Calibration: curves at several strain rates in, a visco-hyperelastic material out.

The public face is :func:`vhfit.calibrate` and its result, :class:`Calibration`.
Inside, one module per concern:

* ``_settings`` — the front door: :class:`CalibrationSettings`, every argument checked
  once, before any computation, and read by the rest;
* ``_identify`` — which data identify a Prony series (the default N);
* ``_bounds`` — τ ranges from the rates (Eq. 22) and the moduli's search limits;
* ``_space`` — the fitted problem and the two search spaces (``separable``, ``full``);
* ``_search`` — the differential evolution with its stopping tests and checkpoints;
* ``_stop`` — why a search stopped (:class:`Stop`: a kind for the code, a sentence for
  the reader);
* ``_checkpoint`` — the saved search state, resumed exactly;
* ``_polish`` — bounded least squares on all parameters afterwards;
* ``_report`` — pruning, uncertainty, stability and warnings; the result;
* ``_result`` — :class:`Calibration`, its summary and its results file;
* ``_for`` — :func:`calibrate_for`: one fit per formulation that the solvers need.
"""

from vhfit.calibration._bounds import auto_bounds
from vhfit.calibration._for import calibrate_for, plan_formulations, same_fit, start_options
from vhfit.calibration._identify import default_n_prony, viscous_evidence
from vhfit.calibration._result import (
    GOOD_FIT,
    GRADES,
    RESULTS_FORMAT,
    ROUGH_FIT,
    WITHIN_FIT,
    Calibration,
    CalibrationWarning,
    grade,
    grade_word,
    set_html_report,
    worst_grade,
)
from vhfit.calibration._settings import (
    CalibrationSettings,
    RecordedCallable,
    bound_problem,
    bounds_terms,
)
from vhfit.calibration._stop import Stop, StopKind, interrupted_in
from vhfit.calibration._workflow import CalibrationError, calibrate, refuse_unrepresentable

__all__ = ["calibrate", "Calibration", "CalibrationSettings", "CalibrationWarning",
           "CalibrationError", "RecordedCallable", "auto_bounds", "RESULTS_FORMAT",
           "default_n_prony", "viscous_evidence", "set_html_report", "calibrate_for",
           "bound_problem", "bounds_terms", "plan_formulations", "start_options", "grade",
           "grade_word", "worst_grade", "GRADES",
           "GOOD_FIT", "WITHIN_FIT", "ROUGH_FIT", "same_fit", "refuse_unrepresentable",
           "Stop", "StopKind", "interrupted_in"]
