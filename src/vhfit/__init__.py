"""vhfit: calibrate visco-hyperelastic material models to multi-rate stress-strain curves."""

from vhfit.history import History

__version__ = "0.1.0"

__all__ = ["History", "__version__"]
