"""The command line with other tests than the paper's: --deformation for fit and simulate.

References are closed forms of Mooney–Rivlin at equilibrium (n_prony = 0): equibiaxial
nominal stress P = 2 (λ − λ⁻⁵)(C10 + C01 λ²), simple shear σ12 = 2 (C10 + C01) γ.
"""

from __future__ import annotations

import csv
import io

import numpy as np
import pytest

from vhfit import cli

C10, C01 = 0.2, 0.1


def _sim(text):
    rows = list(csv.DictReader(line for line in io.StringIO(text) if not line.startswith("#")))
    return np.array([[float(r["strain"]), float(r["stress"])] for r in rows])


def _simulate(capsys, *args):
    """stdout of ``vhfit simulate`` of Mooney-Rivlin (C10, C01) with ``args``."""
    assert cli.main(["simulate", "--model", "mooney_rivlin", "--param", f"C10={C10},C01={C01}",
                     *args]) == 0
    return capsys.readouterr().out


def test_simulate_an_equibiaxial_ramp(capsys):
    out = _simulate(capsys, "--rate", "0.5", "--strain-max", "1", "--points", "5",
                    "--deformation", "equibiaxial")
    assert "# deformation: equibiaxial" in out
    e, p = _sim(out).T
    lam = 1 + e
    np.testing.assert_allclose(e, [0, 0.25, 0.5, 0.75, 1.0])
    np.testing.assert_allclose(p, 2 * (lam - lam**-5) * (C10 + C01 * lam**2), rtol=1e-8,
                               atol=1e-15)


def test_simulate_simple_shear_reports_gamma_and_shear_stress(capsys):
    out = _simulate(capsys, "--rate", "1", "--strain-max", "2", "--points", "3",
                    "--deformation", "simple shear")
    assert "amount of shear" in out
    g, s = _sim(out).T
    np.testing.assert_allclose(g, [0, 1, 2])  # γ, not λ − 1
    np.testing.assert_allclose(s, 2 * (C10 + C01) * g, rtol=1e-8, atol=1e-15)


def _files(tmp_path):
    a = tmp_path / "eb.csv"
    b = tmp_path / "ps.csv"
    lam = np.linspace(1.0, 1.8, 9)
    pe = 2 * (lam - lam**-5) * (C10 + C01 * lam**2)
    pp = 2 * (lam - lam**-3) * (C10 + C01)  # planar: λ2 = 1
    for path, p in ((a, pe), (b, pp)):
        rows = "\n".join(f"{float(x)!r},{float(y)!r}" for x, y in zip(lam, p))
        path.write_text(f"# strain_rate: 0.01\nstretch,nominal_stress_MPa\n{rows}\n")
    return a, b


def test_fit_takes_a_deformation_per_file(tmp_path):
    a, b = _files(tmp_path)
    out = tmp_path / "out"
    code = cli.main(["fit", str(a), str(b), "--deformation", "equibiaxial", "--deformation",
                     "planar", "--prony", "1", "--maxiter", "30", "--seed", "1",
                     "--no-plot", "-q", "--out", str(out)])
    assert code == 0
    rows = list(csv.DictReader(line for line in open(out / "fitted_curves.csv")
                               if not line.startswith("#")))
    tests = {r["curve"]: r["deformation"] for r in rows}
    assert tests == {"eb": "equibiaxial", "ps": "planar"}
    pts = [r for r in rows if r["kind"] == "point"]
    # the exact Mooney-Rivlin data are matched at every sample (no viscosity to find)
    err = max(abs(float(r["stress_model"]) - float(r["stress_data"])) for r in pts)
    assert err < 1e-6


@pytest.mark.parametrize("extra, needle", [
    (["--deformation", "torsion"], "'torsion': use one of uniaxial, equibiaxial"),
    (["--deformation", "planar", "--deformation", "planar", "--deformation", "planar"],
     "--deformation given 3 times for 2 files"),
    (["--deformation", "biaxial"], "second stretch"),
    (["--deformation", "simple_shear"], "amount of shear"),
])
def test_fit_bad_deformations_are_exit_2_one_line_nothing_written(tmp_path, capsys, extra,
                                                                    needle):
    a, b = _files(tmp_path)
    out = tmp_path / "out"
    code = cli.main(["fit", str(a), str(b), *extra, "--no-plot", "-q", "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and needle in err[0], err
    assert not out.exists()


def test_fit_refuses_an_equibiaxial_file_compressed_under_tension(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("stretch,stress\n1.0,0\n0.9,0.1\n0.8,0.3\n")
    out = tmp_path / "out"
    assert cli.main(["fit", str(bad), "--deformation", "equibiaxial", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "bad.csv, line 4" in err[0] and "wrong sign" in err[0]
    assert not out.exists()


def test_simulate_refuses_biaxial(capsys):
    assert cli.main(["simulate", "--model", "mooney_rivlin", "--param", "C10=0.2,C01=0.1",
                     "--rate", "1", "--deformation", "biaxial"]) == 2
    assert "second stretch" in capsys.readouterr().err


def test_equilibrium_files_fit_without_prony_terms_and_give_abaqus_test_data(tmp_path, capsys):
    lam = np.linspace(1.1, 1.8, 8)
    eb, ps = tmp_path / "eb.csv", tmp_path / "ps.csv"
    for path, p in ((eb, 2 * (lam - lam**-5) * (C10 + C01 * lam**2)),
                    (ps, 2 * (lam - lam**-3) * (C10 + C01))):
        rows = "\n".join(f"{float(x)!r},{float(y)!r}" for x, y in zip(lam, p))
        path.write_text(f"stretch,nominal_stress_MPa\n{rows}\n")  # no rate, no time
    out = tmp_path / "out"
    assert cli.main(["fit", str(eb), str(ps), "--deformation", "equibiaxial",
                     "--deformation", "planar", "--out", str(out), "--no-plot"]) == 0
    err = capsys.readouterr().err
    assert "fitting mooney_rivlin + 0 Prony term(s)" in err
    assert "no Prony terms: only equilibrium (rate-free) curves" in err
    summary = (out / "summary.txt").read_text()
    assert "note: no Prony terms by default: only equilibrium" in summary
    text = (out / "abaqus_test_data.inp").read_text()
    assert "*HYPERELASTIC, MOONEY-RIVLIN, TEST DATA INPUT" in text
    blocks = text.split("*BIAXIAL TEST DATA\n")[1].split("*PLANAR TEST DATA\n")
    first = [float(v) for v in blocks[0].splitlines()[0].split(",")]
    np.testing.assert_allclose(first, [2 * (1.1 - 1.1**-5) * (C10 + C01 * 1.21), 0.1],
                               rtol=1e-12)
    assert len(blocks[1].splitlines()) == lam.size


def test_one_monotonic_rate_defaults_to_no_prony_terms_and_forcing_warns(tmp_path, capsys):
    lam = np.linspace(1.05, 1.5, 10)
    f = tmp_path / "one.csv"
    p = 2 * (lam - lam**-2) * (C10 + C01 / lam)  # uniaxial Mooney-Rivlin, nominal
    rows = "\n".join(f"{float(x - 1)!r},{float(y)!r}" for x, y in zip(lam, p))
    f.write_text(f"# strain_rate: 0.1\nstrain,nominal_stress_MPa\n{rows}\n")
    assert cli.main(["fit", str(f), "--out", str(tmp_path / "a"), "--no-plot"]) == 0
    assert "no Prony terms: one strain rate (0.1 1/s)" in capsys.readouterr().err
    assert cli.main(["fit", str(f), "--prony", "1", "--maxiter", "20",
                     "--out", str(tmp_path / "b"), "--no-plot"]) == 0
    summary = (tmp_path / "b" / "summary.txt").read_text().splitlines()
    head = [ln for ln in summary if ln.startswith("WARNING: ")]
    assert head and "cannot separate elastic from viscous response" in head[0]
    card = (tmp_path / "b" / "abaqus.inp").read_text()
    assert "** WARNING: the data cannot separate elastic from viscous" in card
