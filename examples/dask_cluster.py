"""Many calibrations on a Dask cluster with ``vhfit.parallel.calibrate_many``.

Fits two synthetic materials with 1 and 2 Prony terms and two seeds each (8
independent jobs) on a local Dask cluster of two single-threaded worker processes,
printing each result as it arrives, then checks that the constants are bit-identical
to the same jobs run in this process. On a real cluster, replace ``LocalCluster(...)``
by the scheduler's address: ``Client("tcp://scheduler:8786")`` (vhfit must be installed
on the workers).

Dask is optional (``pip install "vhfit[dask]"``); without it this script runs the same
jobs on a ``concurrent.futures`` process pool instead and says so.

    python examples/dask_cluster.py
"""

import concurrent.futures
import multiprocessing
import time
import warnings

import numpy as np

import vhfit
from vhfit.parallel import calibrate_many


def material_curves(truth, rates, noise, seed):
    """Engineering-stress compression curves of a known material, with noise."""
    model = vhfit.ViscoHyperelastic("mooney_rivlin", n_prony=sum(k[:3] == "tau" for k in truth))
    rng = np.random.default_rng(seed)
    strain = np.linspace(-0.05, -0.5, 10)
    curves = []
    for rate in rates:
        stress = model.stress(truth, strain=strain, strain_rate=rate, measure="engineering")
        curves.append(vhfit.Curve(strain=strain, stress=stress * (1 + noise * rng.uniform(
            -1, 1, strain.size)), strain_rate=rate, name=f"{rate:g} 1/s"))
    return curves


def make_jobs():
    materials = {
        "soft": material_curves(dict(C10=0.02, C01=0.01, G1=1.0, tau1=0.005, G2=0.3, tau2=0.5),
                                (-1.0, -10.0, -100.0), 0.02, 1),
        "stiff": material_curves(dict(C10=0.5, C01=0.2, G1=4.0, tau1=1e-3),
                                 (-10.0, -1000.0), 0.03, 2),
    }
    return [dict(name=f"{name}, N={n}, seed {seed}", curves=curves, n_prony=n, seed=seed,
                 uncertainty=False)
            for name, curves in materials.items() for n in (1, 2) for seed in (0, 1)]


def report(results):
    """Print results as they stream in; return them keyed by job name."""
    out = {}
    for r in results:
        what = f"RMSAPE {r.calibration.rmsape:7.3f} %" if r.ok else f"FAILED {r.error}"
        print(f"  {r.name:<22} {what}   ({r.wall_time:.2f} s)")
        out[r.name] = r
    return out


def main():
    warnings.simplefilter("ignore", vhfit.CalibrationWarning)
    jobs = make_jobs()
    print(f"{len(jobs)} jobs, first in this process:")
    local = report(calibrate_many(jobs))

    try:
        from distributed import Client, LocalCluster
    except ImportError:
        print("\nDask is not installed (pip install 'vhfit[dask]'): the same on a process pool")
        ctx = multiprocessing.get_context("spawn")
        with concurrent.futures.ProcessPoolExecutor(2, mp_context=ctx) as executor:
            t0 = time.perf_counter()
            remote = report(calibrate_many(jobs, executor))
        where = "process pool"
    else:
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            print(f"\nthe same jobs on {client}:")
            t0 = time.perf_counter()
            # get_executor() is a concurrent.futures.Executor: results stream back as
            # they finish; client.get_executor().map would return them in input order
            remote = report(calibrate_many(jobs, client.get_executor()))
        where = "Dask cluster"
    print(f"{where}: {time.perf_counter() - t0:.1f} s")

    same = all(remote[k].ok and remote[k].calibration.params == r.calibration.params
               for k, r in local.items())
    print(f"identical constants in this process and on the {where}: {same}")
    if not same:
        raise SystemExit(1)


if __name__ == "__main__":
    main()
