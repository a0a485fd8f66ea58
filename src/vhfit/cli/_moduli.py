"""``fitted_moduli.csv`` of ``vhfit fit``: data and model moduli of frequency sweeps and
relaxation tests (the stress–strain curves go to ``fitted_curves.csv``)."""

from __future__ import annotations

import csv
import io

__all__ = ["FILE", "is_moduli_fit", "fitted_moduli_csv"]

FILE = "fitted_moduli.csv"


def is_moduli_fit(fit: dict) -> bool:
    """A fitted-curve dict of a sweep or relaxation test (no strain axis)."""
    return "strain" not in fit


def fitted_moduli_csv(items, fits, interrupted: bool = False) -> str:
    """One row per data point and per fine-grid point of each sweep or relaxation test."""
    buf = io.StringIO()
    buf.write("# vhfit fitted moduli: frequency sweeps and relaxation tests, data and model"
              + ("; INTERRUPTED (best so far, not converged)" if interrupted else "") + "\n")
    buf.write("# kind=point: data (modulus_data) and model; kind=fine: model on a fine grid; "
              "quantity: storage, loss (at frequency_hz) or relaxation (at time_s)\n")
    buf.write("# units: Hz, s, MPa; E-type moduli (shear data were multiplied by 3)\n")
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["item", "quantity", "kind", "frequency_hz", "time_s", "modulus_data",
                "modulus_model"])
    for c, f in zip(items, fits):
        name = str(c.name)
        if "omega" in f:
            for q in ("storage", "loss"):
                for x, d, m in zip(f["frequency"], f[q], f[f"model_{q}"]):
                    w.writerow([name, q, "point", f"{x:.9g}", "", f"{d:.9g}", f"{m:.9g}"])
                for x, m in zip(f["fine_frequency"], f[f"fine_{q}"]):
                    w.writerow([name, q, "fine", f"{x:.9g}", "", "", f"{m:.9g}"])
        else:
            for x, d, m in zip(f["time"], f["modulus"], f["model"]):
                w.writerow([name, "relaxation", "point", "", f"{x:.9g}", f"{d:.9g}", f"{m:.9g}"])
            for x, m in zip(f["fine_time"], f["fine_model"]):
                w.writerow([name, "relaxation", "fine", "", f"{x:.9g}", "", f"{m:.9g}"])
    return buf.getvalue()
