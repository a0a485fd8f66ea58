"""Imported by the fork server of :func:`vhfit.calibrate_many` worker pools.

One tiny calibration imports everything a calibration loads lazily (SciPy's optimize
and qmc, the diagnostics) and loads numba's compiled kernels from the on-disk cache into
the server, so every worker forked from it starts ready. A calibration of this size runs
only the serial kernels: loading the threaded one would start numba's thread pool, and
a process must not fork after that.
"""

import warnings

import numpy as np

from vhfit.calibration import calibrate
from vhfit.data import Curve
from vhfit.model import ViscoHyperelastic


def _warm() -> None:
    model = ViscoHyperelastic("mooney_rivlin", 1)
    truth = dict(C10=0.2, C01=0.1, G1=1.0, tau1=0.01)
    eps = np.linspace(-0.05, -0.3, 6)
    curves = [Curve(strain=eps, strain_rate=r, stress=model.stress(truth, strain=eps,
                                                                   strain_rate=r))
              for r in (-1.0, -100.0)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        calibrate(curves, n_prony=1, seed=0, popsize=8, maxiter=2)


_warm()
