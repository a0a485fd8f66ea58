"""vhfit's differential evolution as a drop-in for SciPy's.

``vhfit.optimize.differential_evolution`` has SciPy's signature and result; the same
call runs unchanged with either import. Its keyword-only extras add what the paper
needed: an absolute population size, the paper's stopping criteria and a
per-generation history. ``vhfit.optimize.de`` plugs the same solver into
``scipy.optimize.minimize``. Runs in about a second.

    python examples/scipy_dropin.py
"""

import numpy as np
import scipy.optimize

from vhfit.optimize import de, differential_evolution


def rastrigin(x):
    """A classic multimodal test function; global minimum 0 at x = 0."""
    x = np.asarray(x)
    return 10 * x.size + np.sum(x**2 - 10 * np.cos(2 * np.pi * x))


bounds = [(-5.12, 5.12)] * 3

# 1. Exactly SciPy's call and result...
ours = differential_evolution(rastrigin, bounds, rng=1, tol=1e-8)
theirs = scipy.optimize.differential_evolution(rastrigin, bounds, rng=1, tol=1e-8)
print("vhfit :", ours.x.round(6), ours.fun, ours.nit)
print("scipy :", theirs.x.round(6), theirs.fun, theirs.nit)
assert np.array_equal(ours.x, theirs.x)  # bit-identical without extras

# 2. ...plus extras: 40 individuals (absolute, as in the paper), the paper's stopping
#    criteria, and the history of best and mean error per generation.
res = differential_evolution(rastrigin, bounds, rng=1, population_size=40, stop="paper",
                             history=True, maxiter=2000)
print(f"extras: f = {res.fun:.3g} after {res.nit} generations, stopped by {res.stop_reason}")
print(f"        best per generation: {res.history.best[0]:.3g} -> {res.history.best[-1]:.3g}")

# 3. The same solver as a scipy.optimize.minimize method.
res = scipy.optimize.minimize(rastrigin, x0=[1.0, 1.0, 1.0], method=de, bounds=bounds,
                              options={"rng": 1, "maxiter": 300})
print("minimize(method=de):", res.x.round(6), res.fun)
assert res.fun < 1e-6
