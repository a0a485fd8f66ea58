"""``vhfit fit`` with files of moduli (a DMA sweep, a relaxation test) beside stress–strain
files: outputs for the new items, and one-line errors with exit 2 for bad moduli files."""

from __future__ import annotations

import csv
import json
from pathlib import Path

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


# ------------------------------------------------------- tests at several temperatures
C1, C2, T_REF = 8.86, 101.6, 20.0


def _log_aT(T):
    """WLF from its definition: −C1 (T − T_ref)/(C2 + T − T_ref)."""
    return -C1 * (T - T_REF) / (C2 + T - T_REF)


@pytest.fixture
def tts_files(tmp_path):
    """Sweeps at 0, 20, 40, 60 °C in one long file (a temperature column) and two ramps at
    30 °C ('# temperature:' lines), from TRUE at T_REF and the WLF law above."""
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    G, tau = np.array([3.0, 1.0]), np.array([1e-3, 0.1])
    f = np.logspace(-1, 2, 31)
    rows = []
    for T in (0.0, 20.0, 40.0, 60.0):
        e1, e2 = _maxwell(2 * np.pi * f * 10 ** _log_aT(T), 1.5, G, tau)
        rows += [(a, b, c, T) for a, b, c in zip(f, e1, e2)]
    dma = tmp_path / "dma.csv"
    np.savetxt(dma, np.array(rows), delimiter=",", comments="",
               header="frequency_Hz,storage_MPa,loss_MPa,temperature_C")
    out = [dma]
    eps = np.linspace(0, -0.4, 21)
    for r in (-1.0, -100.0):
        p = tmp_path / f"rate{abs(r):g}.csv"
        s = m.stress(TRUE, strain=eps, strain_rate=r * 10 ** _log_aT(30.0),
                     measure="engineering")
        np.savetxt(p, np.column_stack([eps, s]), delimiter=",", comments="",
                   header=f"# strain_rate: {r}\n# temperature: 30\nstrain,stress_MPa")
        out.append(p)
    return out


def _after(lines, head):
    """The numbers of the data line after the line ``head``."""
    k = [ln.strip() for ln in lines].index(head)
    return [float(v) for v in lines[k + 1].replace("TBDATA,1,", "").split(",")]


def test_fit_with_a_given_wlf_shift_writes_it_into_the_cards(tts_files, tmp_path, capsys):
    out = tmp_path / "out"
    code = cli.main(["fit", *map(str, tts_files), "--prony", "2", "--seed", "0",
                     "--shift", "wlf:8.86,101.6", "--tref", "20", "--out", str(out),
                     "--no-plot", "--quiet"])
    assert code == 0
    res = json.loads((out / "results.json").read_text())
    for k, v in TRUE.items():
        assert res["params"][k] == pytest.approx(v, rel=1e-6), k
    assert res["shift"]["constants"] == {"T_ref": 20.0, "C1": 8.86, "C2": 101.6}
    inp = (out / "abaqus.inp").read_text().splitlines()
    # Abaqus *TRS, DEFINITION=WLF: one data line "reference temperature, C1, C2", after
    # the material's *VISCOELASTIC
    assert _after(inp, "*TRS, DEFINITION=WLF") == [20.0, 8.86, 101.6]
    assert inp.index("*TRS, DEFINITION=WLF") > next(
        k for k, ln in enumerate(inp) if ln.startswith("*VISCOELASTIC"))
    mac = (out / "ansys.mac").read_text().splitlines()
    assert _after(mac, "TB,SHIFT,1,,,WLF") == [20.0, 8.86, 101.6]  # TBDATA,1,Tr,C1,C2
    assert "no time-temperature shift written" in (out / "lsdyna.k").read_text()
    summary = (out / "summary.txt").read_text()
    assert "time-temperature shift: WLF C1 = 8.86, C2 = 101.6 at T_ref = 20 (given)" in summary
    # vhfit check re-reads the files at their temperatures and shifts them as the fit did
    capsys.readouterr()
    assert cli.main(["check", str(out / "results.json"), "--json"]) == 0
    check = json.loads(capsys.readouterr().out)["card_check"]
    assert check["abaqus"]["rmsape"] < 1e-6 and check["ansys"]["rmsape"] < 1e-6


def test_fit_draws_the_sweeps_as_measured_so_that_temperature_colours_them(
        tts_files, tmp_path, capsys, monkeypatch):
    # the moduli plot shifts the sweeps itself: it must get them at their temperatures
    from vhfit import plot
    from vhfit.cli import _outputs

    seen = []
    # drawn in this process, where the replaced plot function records what it is given
    monkeypatch.setattr(_outputs.Drawer, "start", classmethod(lambda cls, args: None))
    monkeypatch.setattr(plot, "plot_moduli_fit",
                        lambda cal, items, path: seen.extend(items) or Path(path).touch())
    out = tmp_path / "out"
    assert cli.main(["fit", *map(str, tts_files), "--prony", "2", "--seed", "0",
                     "--shift", "wlf:8.86,101.6", "--tref", "20", "--out", str(out),
                     "--quiet"]) == 0
    temps = {c.temperature for c in seen if plot.is_moduli(c)}
    assert temps == {0.0, 20.0, 40.0, 60.0}


def test_fit_builds_the_shift_from_the_sweeps_and_export_keeps_it(tts_files, tmp_path,
                                                                  capsys):
    out = tmp_path / "out"
    assert cli.main(["fit", *map(str, tts_files), "--prony", "2", "--seed", "0", "--tref",
                     "20", "--out", str(out), "--no-plot", "--quiet"]) == 0
    T_ref, c1, c2 = _after((out / "abaqus.inp").read_text().splitlines(),
                           "*TRS, DEFINITION=WLF")
    assert T_ref == 20.0
    assert c1 == pytest.approx(C1, rel=0.01) and c2 == pytest.approx(C2, rel=0.01)
    capsys.readouterr()
    card = tmp_path / "again.inp"
    assert cli.main(["export", str(out / "results.json"), "--to", "abaqus", "--out",
                     str(card)]) == 0
    assert _after(card.read_text().splitlines(), "*TRS, DEFINITION=WLF") == [T_ref, c1, c2]


@pytest.mark.parametrize("extra, needle", [
    (["--shift", "wlf:8.86"], "--shift 'wlf:8.86': give wlf:C1,C2 or arrhenius:E_A[,T0]"),
    (["--shift", "vogel:1,2", "--tref", "20"], "--shift 'vogel:1,2': give wlf:C1,C2"),
    (["--shift", "wlf:8.86,101.6"], "--shift wlf:8.86,101.6: give --tref T"),
    (["--shift", "wlf:8.86,-5", "--tref", "20"], "WLF C2 = -5.0: C2 must be > 0"),
    ([], "rate1.csv: rate1: tests at 2 temperatures and no shift factors"),
])
def test_bad_shift_input_exits_2_with_one_line_and_writes_nothing(tts_files, tmp_path,
                                                                 capsys, extra, needle):
    hot = tmp_path / "hot.csv"  # a ramp at 80 °C: two temperatures, no sweep between
    hot.write_text(tts_files[1].read_text().replace("# temperature: 30", "# temperature: 80"))
    out = tmp_path / "out"
    assert cli.main(["fit", str(tts_files[1]), str(hot), "--out", str(out), "--quiet",
                     *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and len(err.splitlines()) == 1
    assert not out.exists()
