"""vhfit: calibrate visco-hyperelastic material models to multi-rate stress-strain curves.

The public API::

    import vhfit
    m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=2)
    m.stress(params, strain=eps, strain_rate=-100.0)
    curves = vhfit.read_csv("tests.csv")
    cal = vhfit.calibrate(curves, hyperelastic="mooney_rivlin", n_prony=2, seed=0)
"""

from vhfit._version import __version__

# Names load on first use (PEP 562), so that ``vhfit --version``, ``--help`` and
# ``models`` do not pay for numpy, scipy and numba: each public name -> its module.
_LAZY = {
    "Calibration": "vhfit.calibration",
    "CalibrationError": "vhfit.calibration",
    "CalibrationSettings": "vhfit.calibration",
    "CalibrationWarning": "vhfit.calibration",
    "calibrate": "vhfit.calibration",
    "calibrate_for": "vhfit.calibration",
    "Comparison": "vhfit.comparison",
    "compare": "vhfit.comparison",
    "Curve": "vhfit.data",
    "DataError": "vhfit.data",
    "DataWarning": "vhfit.data",
    "FrequencySweep": "vhfit.data",
    "Relaxation": "vhfit.data",
    "read_csv": "vhfit.data",
    "History": "vhfit.history",
    "Batch": "vhfit.model",
    "ViscoHyperelastic": "vhfit.model",
    "Objective": "vhfit.objective",
    "per_curve_rmsape": "vhfit.objective",
    "rmsape": "vhfit.objective",
    "Job": "vhfit.parallel",
    "JobResult": "vhfit.parallel",
    "calibrate_many": "vhfit.parallel",
}


def __getattr__(name: str):
    import importlib

    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        if _LAZY[name].startswith("vhfit.calibration"):
            # the HTML report registers Calibration.report's writer: load it with the fit
            importlib.import_module("vhfit.report")
    elif not name.startswith("__"):
        try:  # a submodule (vhfit.export, vhfit.optimize, ...): imported when first asked
            value = importlib.import_module(f"vhfit.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"vhfit.{name}":
                raise
            raise AttributeError(f"module 'vhfit' has no attribute {name!r}") from None
    else:
        raise AttributeError(f"module 'vhfit' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


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
