"""Warm-up of a process that will fork calibration workers (the pools' fork server).

:func:`warm_up` runs one tiny calibration: it imports everything a calibration loads
lazily (SciPy's optimize and qmc, the diagnostics) and loads numba's compiled kernels
from the on-disk cache, so every worker forked afterwards starts ready. Nothing runs at
import; :mod:`vhfit._preload` calls it in the fork server.
"""

from __future__ import annotations

import warnings

import numpy as np

from vhfit.calibration import calibrate
from vhfit.data import Curve
from vhfit.model import ViscoHyperelastic


def warm_up() -> None:
    """Run one tiny calibration (a second or less) and discard it.

    A calibration of this size runs only the serial kernels: loading the threaded one
    would start numba's thread pool, and a process must not fork after that.

    Examples
    --------
    >>> warm_up()
    """
    model = ViscoHyperelastic("mooney_rivlin", 1)
    truth = dict(C10=0.2, C01=0.1, G1=1.0, tau1=0.01)
    eps = np.linspace(-0.05, -0.3, 6)
    curves = [Curve(strain=eps, strain_rate=r, stress=model.stress(truth, strain=eps,
                                                                   strain_rate=r))
              for r in (-1.0, -100.0)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        calibrate(curves, n_prony=1, seed=0, popsize=8, maxiter=2)
