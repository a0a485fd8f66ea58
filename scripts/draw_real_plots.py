"""Draw vhfit's plots of every shared real dataset, to look at them.

Run::

    python scripts/draw_real_plots.py [--data DIR] [--out DIR] [--only name,name]

The data are read at run time from ``--data`` (default ``$VHFIT_DATA`` or the
``shared/data`` folder beside the repository); nothing is copied into the
project. Each dataset is fitted once (seed 0, the law and N of ``DATASETS``, N = "auto" up
to 4, no intervals; the calibration is kept in
``--out``/cache and reused on the next run), then its figures are written to ``--out``
(default ``/tmp/vhfit_real_plots``): ``NAME_fit.png`` (:func:`vhfit.plot.plot_fit`),
``NAME_moduli.png`` for frequency sweeps and relaxation tests, and for the DMA
sweeps the raw and shifted sweeps, the master curve with a Prony spectrum, the shift
factors and the residuals. Warnings raised while drawing are errors: a plot that
warns is reported as failed.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import traceback
import warnings
from pathlib import Path

import vhfit
from vhfit import plot, tts
from vhfit.data import DataWarning, is_moduli
from vhfit.spectrum import prony_spectrum

HERE = Path(__file__).resolve().parent
DEFAULT_DATA = Path(os.environ.get("VHFIT_DATA", HERE.parent.parent / "shared" / "data"))

ZHAO = ["vhb4910_zhao_rate_relaxation/loading_unloading/0d01_3d0.csv",
        "vhb4910_zhao_rate_relaxation/loading_unloading/0d03_3d0.csv",
        "vhb4910_zhao_rate_relaxation/loading_unloading/0d05_3d0.csv",
        "vhb4910_zhao_rate_relaxation/relaxation/relax_3d0.csv"]
HOSSAIN = [f"vhb4910_hossain2012_digitized/loading_unloading_rate_{r}.csv"
           for r in ("0.01", "0.03", "0.05")]
HNBR = "hnbr50_miehe_goktepe2005/"
MUSCLE = "muscle_compression_relaxation_digitized/"
TRELOAR = "treloar1944_kawabata1981/"
SILICONE = "silicone_tensile_srmd/"

#: name -> (files, read_csv options, calibrate options)
DATASETS = {
    "vhb_zhao": (ZHAO, {}, {"model": "ogden2", "n_prony": "auto"}),
    "vhb_hossain": (HOSSAIN, {"sort": True}, {"model": "ogden2", "n_prony": "auto"}),
    "hnbr_cycles": ([HNBR + f"tension_compression_cycles_rate_{r}.csv"
                     for r in ("1.07e-3", "8.60e-3", "8.33e-2")], {},
                    {"model": "mooney_rivlin", "n_prony": "auto"}),
    "hnbr_compression": ([HNBR + f"pure_compression_cycles_rate_{r}.csv"
                          for r in ("9.45e-4", "8.50e-3", "7.05e-2")], {},
                         {"model": "mooney_rivlin", "n_prony": 3}),
    "hnbr_multistep": ([HNBR + "multistep_relaxation_tension_compression.csv"], {},
                       {"model": "mooney_rivlin", "n_prony": 3}),
    "muscle_rate": ([MUSCLE + f"fibre_rate_F_{r}.csv" for r in ("005", "01", "05")], {},
                    {"model": "mooney_rivlin", "n_prony": "auto"}),
    "muscle_strain": ([MUSCLE + f"cross-fibre_strain_XF_{r}.csv" for r in ("10", "20", "30")],
                      {}, {"model": "mooney_rivlin", "n_prony": 2}),
    "brain_cortex": (["brain_budday2017_quasistatic/budday2017_brain.csv"],
                     {"select": {"region": "cortex"}}, {"model": "ogden", "n_prony": 0}),
    "treloar": ([TRELOAR + f"treloar1944_{m}.csv" for m in
                 ("uniaxial_tension", "equibiaxial_tension", "pure_shear")],
                {"deformation": ["uniaxial", "equibiaxial", "planar"]},
                {"model": "ogden3", "n_prony": 0}),
    "kawabata": ([TRELOAR + "kawabata1981_biaxial.csv"], {"deformation": "biaxial"},
                 {"model": "ogden3", "n_prony": 0}),
    "silicone_ecoflex30": ([SILICONE + "Ecoflex_00_30.csv"],
                           {"columns": {"time": None}, "rate": 0.2273}, {"model": "yeoh"}),
    "silicone_dragonskin30": ([SILICONE + "Dragon_Skin_30.csv"], {}, {"model": "yeoh"}),
    "silicone_rtv615": ([SILICONE + "RTV615.csv"], {}, {"model": "yeoh"}),
    "dma_freq_master": (["pyvisco_dmta_examples/freq_user_master.csv"], {},
                        {"model": "mooney_rivlin", "n_prony": "auto"}),
    "dma_time_master": (["pyvisco_dmta_examples/time_user_master.csv"], {},
                        {"model": "mooney_rivlin", "n_prony": "auto"}),
    "dma_freq_raw": (["pyvisco_dmta_examples/freq_user_raw.csv"], {},
                     {"model": "mooney_rivlin", "n_prony": "auto"}),
}

#: raw DMA sweeps drawn through vhfit.tts (name -> file)
SWEEPS = {"tts_freq": "pyvisco_dmta_examples/freq_user_raw.csv",
          "tts_time": "pyvisco_dmta_examples/time_user_raw.csv"}


def fit(name: str, root: Path, cache: Path):
    files, read_kw, fit_kw = DATASETS[name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataWarning)
        curves = vhfit.read_csv([str(root / f) for f in files], **read_kw)
    path = cache / f"{name}.json"
    if path.exists():
        return vhfit.Calibration.load(path), curves
    fit_kw = dict(fit_kw)
    model = vhfit.ViscoHyperelastic(fit_kw.pop("model"), fit_kw.pop("n_prony", 1)
                                    if fit_kw.get("n_prony") != "auto" else 1)
    if "n_prony" in fit_kw:  # "auto"
        fit_kw["max_prony"] = 4
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate(curves, model.hyperelastic.name, seed=0, uncertainty=False,
                              **({"n_prony": model.n_prony} | fit_kw))
    cal.save(path)
    return cal, curves


def draw(name: str, root: Path, out: Path, cache: Path) -> list[str]:
    """The figures of one dataset; returns the files written."""
    written = []
    if name in SWEEPS:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DataWarning)
            sweeps = vhfit.read_csv(str(root / SWEEPS[name]))
        mc = tts.master_curve(sweeps, law="wlf")
        spec = prony_spectrum(mc, tolerance=0.05)
        for kind, make in (("sweeps", lambda p: plot.plot_sweeps(mc, p)),
                           ("shifted", lambda p: plot.plot_sweeps(mc, p, shifted=True)),
                           ("master", lambda p: plot.plot_master_curve(mc, spec, p)),
                           ("shift", lambda p: plot.plot_shift_factors(mc, p)),
                           ("residuals", lambda p: plot.plot_spectrum_residuals(mc, spec, p))):
            p = out / f"{name}_{kind}.png"
            make(p)
            written.append(p.name)
        return written
    cal, curves = fit(name, root, cache)
    if any(not is_moduli(c) for c in curves):
        plot.plot_fit(cal, curves, out / f"{name}_fit.png")
        written.append(f"{name}_fit.png")
    if any(is_moduli(c) for c in curves):
        plot.plot_moduli_fit(cal, curves, out / f"{name}_moduli.png")
        written.append(f"{name}_moduli.png")
    return written


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA)
    ap.add_argument("--out", type=Path, default=Path("/tmp/vhfit_real_plots"))
    ap.add_argument("--only", default="", help="comma-separated dataset names")
    args = ap.parse_args(argv)
    names = [*DATASETS, *SWEEPS]
    if args.only:
        names = [n for n in names if n in args.only.split(",")]
    cache = args.out / "cache"
    cache.mkdir(parents=True, exist_ok=True)
    failed = 0
    for name in names:
        t0 = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error")  # a plot that warns fails
                warnings.simplefilter("ignore", DataWarning)  # reading the files
                files = draw(name, args.data, args.out, cache)
            print(f"{name}: {', '.join(files)} ({time.perf_counter() - t0:.1f} s)")
        except Exception:
            failed += 1
            print(f"{name}: FAILED\n{traceback.format_exc()}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
