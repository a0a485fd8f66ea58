"""vhfit: calibrate visco-hyperelastic material models to multi-rate stress-strain curves.

The public API (SPEC §7)::

    import vhfit
    m = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=2)
    m.stress(params, strain=eps, strain_rate=-100.0)
"""

from vhfit import hyperelastic, viscoelastic
from vhfit.history import History
from vhfit.model import Batch, ViscoHyperelastic

__version__ = "0.1.0"

__all__ = [
    "Batch",
    "History",
    "ViscoHyperelastic",
    "hyperelastic",
    "viscoelastic",
    "__version__",
]
