"""``vhfit fit`` with files of moduli (a DMA sweep, a relaxation test) beside stress–strain
files: outputs for the new items, and one-line errors with exit 2 for bad moduli files."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

import vhfit
from vhfit import cli

TRUE = dict(C10=0.2, C01=0.05, G1=3.0, tau1=1e-3, G2=1.0, tau2=0.1)


def _maxwell(omega, E_inf, G, tau):
    """(E′, E″) from E* = E∞ + Σ G iωτ/(1 + iωτ)."""
    Es = E_inf + np.sum(G * (1j * omega[:, None] * tau) / (1 + 1j * omega[:, None] * tau), 1)
    return Es.real, Es.imag


@pytest.fixture
def files(tmp_path):
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    G, tau = np.array([3.0, 1.0]), np.array([1e-3, 0.1])
    f = np.logspace(-2, 3, 21)
    e1, e2 = _maxwell(2 * np.pi * f, 1.5, G, tau)
    dma = tmp_path / "dma.csv"
    np.savetxt(dma, np.column_stack([f, e1 * 1e3, e2 * 1e3]), delimiter=",", comments="",
               header="frequency_Hz,storage_kPa,loss_kPa")
    out = [dma]
    eps = np.linspace(0, -0.4, 21)
    for r in (-1.0, -100.0):
        p = tmp_path / f"rate{abs(r):g}.csv"
        s = m.stress(TRUE, strain=eps, strain_rate=r, measure="engineering")
        np.savetxt(p, np.column_stack([eps, s]), delimiter=",", comments="",
                   header=f"# strain_rate: {r}\nstrain,stress_MPa")
        out.append(p)
    return out


def test_fit_with_a_dma_file_beside_rate_curves(files, tmp_path, capsys):
    out = tmp_path / "out"
    code = cli.main(["fit", *map(str, files), "--prony", "2", "--seed", "0", "--out", str(out),
                     "--no-plot", "--quiet"])
    assert code == 0
    res = json.loads((out / "results.json").read_text())
    for k, v in TRUE.items():
        assert res["params"][k] == pytest.approx(v, rel=1e-6), k
    assert [c.get("type") for c in res["curves"]] == ["frequency_sweep", None, None]
    rows = list(csv.DictReader(line for line in open(out / "fitted_moduli.csv")
                               if not line.startswith("#")))
    pts = [r for r in rows if r["kind"] == "point" and r["quantity"] == "loss"]
    assert len(pts) == 21
    assert float(pts[0]["modulus_model"]) == pytest.approx(float(pts[0]["modulus_data"]),
                                                           rel=1e-6)
    curves = (out / "fitted_curves.csv").read_text()
    assert "rate1" in curves and "dma" not in curves  # moduli have their own file


@pytest.mark.parametrize("text, needle", [
    ("frequency_Hz,storage_MPa,loss_MPa\n0.1,2,0.5\n0,3,0.4\n",
     "bad.csv, line 3, column 'frequency_Hz'): frequency 0 <= 0"),
    ("omega_rad/s,storage_MPa,loss_MPa\n0.1,2,0.5\n-2,3,0.4\n",
     "bad.csv, line 3, column 'omega_rad/s'): omega -2 <= 0"),
    ("frequency_Hz,storage_MPa,loss_MPa\n0.1,2,0.5\n1,3,-0.4\n",
     "bad.csv, line 3, column 'loss_MPa'): loss modulus -0.4 < 0"),
    ("frequency_Hz,tan_delta\n0.1,0.5\n1,0.4\n",
     "bad.csv, column 'tan_delta'): tan delta needs the storage modulus (or |E*|) beside it: "
     "add a storage-modulus column"),
])
def test_bad_moduli_files_exit_2_with_one_line(files, tmp_path, capsys, text, needle):
    bad = tmp_path / "bad.csv"
    bad.write_text(text)
    out = tmp_path / "out"
    assert cli.main(["fit", str(bad), str(files[1]), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and len(err.splitlines()) == 1
    assert not out.exists()


def test_fit_with_plots_draws_the_moduli_beside_the_stress(files, tmp_path, capsys):
    """With matplotlib, a fit of moduli and stress draws fit.png (stress–strain curves
    only) and moduli.png (the sweep), and says nothing failed."""
    pytest.importorskip("matplotlib")
    out = tmp_path / "out"
    assert cli.main(["fit", *map(str, files), "--prony", "2", "--seed", "0", "--out",
                     str(out)]) == 0
    printed = capsys.readouterr()
    assert "plots failed" not in printed.out + printed.err
    assert (out / "fit.png").stat().st_size > 0 and (out / "moduli.png").stat().st_size > 0
