"""vhfit: calibrate visco-hyperelastic material models to multi-rate stress-strain curves.

The public API::

    import vhfit
    m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=2)
    m.stress(params, strain=eps, strain_rate=-100.0)
    curves = vhfit.read_csv("tests.csv")
    cal = vhfit.calibrate(curves, hyperelastic="mooney_rivlin", n_prony=2, seed=0)
"""

from vhfit import export, formulations, hyperelastic, report, spectrum, tts, viscoelastic
from vhfit._version import __version__
from vhfit.calibration import (
    Calibration,
    CalibrationError,
    CalibrationSettings,
    CalibrationWarning,
    calibrate,
    calibrate_for,
)
from vhfit.comparison import Comparison, compare
from vhfit.data import Curve, DataError, DataWarning, FrequencySweep, Relaxation, read_csv
from vhfit.history import History
from vhfit.model import Batch, ViscoHyperelastic
from vhfit.objective import Objective, per_curve_rmsape, rmsape
from vhfit.parallel import Job, JobResult, calibrate_many


def __getattr__(name: str):
    # the optimizer pulls in scipy.optimize (~0.3 s): load it when first used
    if name == "optimize":
        import importlib

        return importlib.import_module("vhfit.optimize")
    raise AttributeError(f"module 'vhfit' has no attribute {name!r}")

__all__ = [
    "Batch",
    "Calibration",
    "CalibrationError",
    "CalibrationSettings",
    "CalibrationWarning",
    "Comparison",
    "Curve",
    "DataError",
    "DataWarning",
    "FrequencySweep",
    "History",
    "Job",
    "JobResult",
    "Objective",
    "Relaxation",
    "ViscoHyperelastic",
    "calibrate",
    "calibrate_for",
    "calibrate_many",
    "compare",
    "export",
    "formulations",
    "hyperelastic",
    "optimize",
    "per_curve_rmsape",
    "read_csv",
    "report",
    "rmsape",
    "spectrum",
    "tts",
    "viscoelastic",
    "__version__",
]
