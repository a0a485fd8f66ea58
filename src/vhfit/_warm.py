"""Imported by the fork server of :func:`vhfit.calibrate_many` worker pools.

Importing the calibration stack and running the serial kernels once loads numba's
compiled code (from its on-disk cache) into the server, so every worker forked from it
starts ready. Only the serial kernels run here: loading the threaded one would start
numba's thread pool, and a process must not fork after that.
"""

import numpy as np

from vhfit.calibrate import calibrate  # noqa: F401  (the import is the point)
from vhfit.history import History
from vhfit.model import ViscoHyperelastic


def _warm() -> None:
    model = ViscoHyperelastic("mooney_rivlin", 1)
    batch = model.batch([History.constant_rate([0.0, -0.1], -1.0)], measure="engineering")
    batch.shape_columns(np.array([[0.5, 0.5]]), np.array([[1.0]]), parallel=False)
    batch(np.array([[0.5, 0.5, 1.0, 1.0]]))  # one parameter set: the serial kernel


_warm()
