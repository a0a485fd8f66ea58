"""The command line reaches what the Python API can: ``--bounds``, ``--sort``, ``--select``
and files as labs write them (descriptive suffixes on column names, two temperature
columns). Every refusal is one line naming the flag and the fix, exit code 2, and the
``--out`` folder exactly as it was; ``bounds=`` of :func:`vhfit.calibrate` is refused by
the same front door (:class:`vhfit.CalibrationSettings`) in one line.

Runs in-process through :func:`vhfit.cli.main` (the code path of the console script minus
the process start; ``tests/test_cli.py`` covers the real script).
"""

from __future__ import annotations

import json
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from _folders import listing

import vhfit
from vhfit import cli
from vhfit.cli._inputs import read_curves
from vhfit.cli._parser import build_parser

TRUTH = dict(mu1=0.2, alpha1=5.0)  # one-term Ogden (Abaqus form), exact data
EPS = np.linspace(0.02, 0.8, 40)


def ogden_engineering(mu: float, alpha: float, eps: np.ndarray) -> np.ndarray:
    """Nominal stress of incompressible uniaxial tension of one-term Ogden in the Abaqus
    form W = 2μ/α² (λ1^α + λ2^α + λ3^α − 3), written out: σ = (2μ/α)(λ^α − λ^(−α/2)),
    P = σ/λ."""
    lam = 1.0 + eps
    return 2.0 * mu / alpha * (lam**alpha - lam ** (-alpha / 2.0)) / lam


def write(path: Path, header: str, rows) -> Path:
    path.write_text(header + "\n" + "".join(",".join(map(repr, map(float, r))) + "\n"
                                            for r in rows))
    return path


@pytest.fixture(scope="module")
def ogden_csv(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("ogden")
    s = ogden_engineering(TRUTH["mu1"], TRUTH["alpha1"], EPS)
    return write(folder / "ogden.csv", "strain,stress_MPa", zip(EPS, s))


def refused(argv, out: Path, capsys, before: str = "absent") -> str:
    """Run ``argv`` (with ``--out out``) against ``out`` in state ``before``; assert exit
    2, one error line, no traceback and ``out`` untouched; return the message."""
    force = []
    if before != "absent":
        out.mkdir()
        force = ["--force"]
    if before == "files":
        (out / "notes.txt").write_text("mine\n")
    was = listing(out)
    capsys.readouterr()
    code = cli.main([*argv, "--out", str(out), "--no-plot", "-q", *force])
    cap = capsys.readouterr()
    err = [x for x in cap.err.splitlines() if x.strip()]
    assert code == 2, (code, cap.err)
    assert "Traceback" not in cap.err
    assert len(err) == 1 and err[0].startswith("vhfit: error: "), cap.err
    assert listing(out) == was, "the run changed --out"
    return err[0][len("vhfit: error: "):]


# ==================================================================== --bounds
BAD_BOUNDS = [
    ("unknown-name", ["--model", "ogden", "--prony", "0", "--bounds", "beta1=0:1"],
     r"--bounds beta1=0:1: unknown parameter of the ogden law without Prony terms; give one "
     r"of mu1, alpha1 \(see 'vhfit models'; --model chooses the law\)"),
    ("law-has-no-such", ["--bounds", "alpha1=-40:40"],  # the default law: Mooney-Rivlin
     r"--bounds alpha1=-40:40: unknown parameter of the mooney_rivlin law with up to 2 "
     r"Prony term\(s\); give one of C10, C01, G1, tau1, G2, tau2 .*"),
    ("term-beyond-N", ["--prony", "2", "--bounds", "tau3=1e-3:1"],
     r"--bounds tau3=0\.001:1: unknown parameter .*\(more terms: raise --prony\); .*"),
    ("low-above-high", ["--model", "ogden", "--bounds", "alpha1=3:1"],
     r"argument --bounds: --bounds 'alpha1=3:1': LO must be below HI; give alpha1=1:3 with "
     r"LO < HI .*"),
    ("low-equals-high", ["--model", "ogden", "--bounds", "alpha1=2:2"],
     r".*--bounds 'alpha1=2:2': LO must be below HI.*"),
    ("not-numbers", ["--bounds", "C10=a:1"], r".*--bounds 'C10=a:1': LO and HI are not "
     r"numbers; give NAME=LO:HI.*"),
    ("no-range", ["--bounds", "C10"], r".*--bounds 'C10': give NAME=LO:HI.*"),
    ("infinite", ["--bounds", "C10=0:inf"], r".*--bounds 'C10=0:inf': give finite LO and "
     r"HI.*"),
    ("negative-modulus", ["--model", "neo_hooke", "--bounds", "C10=-1:1"],
     r"--bounds C10=-1:1: outside the physical range of C10 of the neo_hooke law, \[0, inf\]: "
     r"give limits within it"),
    ("locking-stretch", ["--model", "arruda_boyce", "--prony", "0", "--bounds",
                         "lambda_m=0.5:3"],
     r"--bounds lambda_m=0\.5:3: outside the physical range of lambda_m of the arruda_boyce "
     r"law, \[1, inf\]: give limits within it"),
    ("tau-not-positive", ["--prony", "1", "--bounds", "tau1=0:1"],
     r"--bounds tau1=0:1: a relaxation time is > 0 s: give 0 < low"),
    ("prony-modulus-negative", ["--prony", "1", "--bounds", "G1=-1:1"],
     r"--bounds G1=-1:1: a Prony modulus G_i is >= 0: give low >= 0"),
    ("given-twice", ["--model", "ogden", "--bounds", "alpha1=0:1", "--bounds", "ALPHA1=0:2"],
     r"--bounds ALPHA1=0:2: alpha1 given twice; give each parameter once"),
]


@pytest.mark.parametrize("before", ["absent", "empty", "files"])
@pytest.mark.parametrize("case, extra, pattern", BAD_BOUNDS,
                         ids=[c[0] for c in BAD_BOUNDS])
def test_bad_bounds_are_one_line_exit_2_and_nothing_written(case, extra, pattern, before,
                                                            ogden_csv, tmp_path, capsys):
    msg = refused(["fit", str(ogden_csv), *extra], tmp_path / "out", capsys, before)
    assert re.fullmatch(pattern, msg), msg
    assert "--bounds" in msg


def test_bounds_on_prony_terms_the_default_fit_does_not_have_are_refused(ogden_csv,
                                                                          tmp_path, capsys):
    """Equilibrium data (no rate, no time): no Prony term by default, so a bound on τ1
    cannot apply; the error says to give --prony (the check runs in calibrate, after the
    data are read: --out is still left as it was)."""
    msg = refused(["fit", str(ogden_csv), "--model", "ogden", "--bounds", "tau1=1e-3:1"],
                  tmp_path / "out", capsys, "files")
    assert re.fullmatch(r"bounds name tau1 but the fit has no Prony terms by default \(.*\): "
                        r"give --prony N to fit some, or drop "
                        r"those bounds", msg), msg


@pytest.mark.parametrize("kw, pattern", [
    (dict(hyperelastic="ogden", n_prony=0, bounds={"beta1": (0, 1)}),
     r"bounds\['beta1'\] = \(0, 1\): unknown parameter of the ogden law without Prony "
     r"terms; give one of mu1, alpha1"),
    (dict(hyperelastic="neo_hooke", bounds={"C10": (-1.0, 1.0)}),
     r"bounds\['C10'\] = \(-1\.0, 1\.0\): outside the physical range of C10 of the "
     r"neo_hooke law, \[0, inf\]: give limits within it"),
    (dict(n_prony=1, bounds={"tau1": (-1.0, 1.0)}),
     r"bounds\['tau1'\] = \(-1\.0, 1\.0\): a relaxation time is > 0 s: give 0 < low"),
    (dict(n_prony=1, bounds={"G1": (-1.0, 1.0)}),
     r"bounds\['G1'\] = \(-1\.0, 1\.0\): a Prony modulus G_i is >= 0: give low >= 0"),
    (dict(hyperelastic="ogden", bounds={"alpha1": (3.0, 1.0)}),
     r"bounds\['alpha1'\] = \(3\.0, 1\.0\): the lower limit is above the upper: give low "
     r"<= high"),
    (dict(hyperelastic="ogden", bounds={"alpha1": (np.nan, 1.0)}),
     r"bounds\['alpha1'\] = \(nan, 1\.0\): give two numbers \(low, high\), not NaN"),
    (dict(hyperelastic="ogden", bounds={"alpha1": (-np.inf, 1.0)}),
     r"bounds\['alpha1'\] = \(-inf, 1\.0\): give finite limits .*"),
    (dict(n_prony=2, bounds={"tau3": (1e-3, 1.0)}),
     r"bounds\['tau3'\] = \(0\.001, 1\.0\): unknown parameter .*"),
    (dict(hyperelastic="ogden", bounds={"alpha1": (1.0,)}),
     r"bounds\['alpha1'\] = \(1\.0,\): give a pair \(low, high\)"),
])
def test_calibrate_refuses_the_same_bounds_at_its_front_door(kw, pattern):
    """The Python API refuses what --bounds refuses, in one line, on construction of the
    settings (before any data is looked at) and in calibrate."""
    with pytest.raises(ValueError) as info:
        vhfit.CalibrationSettings(**kw)
    msg = str(info.value)
    assert "\n" not in msg and re.fullmatch(pattern, msg), msg
    curves = [vhfit.Curve(strain=EPS, stress=ogden_engineering(0.2, 5.0, EPS),
                          strain_rate=0.01)]
    with pytest.raises(ValueError, match=re.escape(msg)):
        vhfit.calibrate(curves, **kw)


def test_calibrate_accepts_what_the_api_always_took():
    """Equal limits fix a parameter; a linear constant may be unbounded; the bounds of an
    order scan may name its largest N's terms (the smaller N's fits leave them out); a law
    that is not registered is not second-guessed (its fit names it)."""
    vhfit.CalibrationSettings(n_prony=1, bounds={"tau1": (1e-3, 1e-3)})
    vhfit.CalibrationSettings(bounds={"C01": (-np.inf, np.inf)})
    vhfit.CalibrationSettings(n_prony="auto", max_prony=3, bounds={"tau3": (1.0, 10.0)})
    vhfit.CalibrationSettings("not_registered_here", bounds={"k": (0.0, 1.0)})


def test_order_scan_applies_a_term_bound_only_to_the_fits_that_have_the_term():
    """n_prony='auto' with a bound on τ2: the N = 1 fit runs (it has no τ2) and the N = 2
    fit keeps τ2 inside the bound."""
    m = vhfit.ViscoHyperelastic("neo_hooke", 2)
    true = dict(C10=0.1, G1=0.5, tau1=0.01, G2=0.3, tau2=1.0)
    eps = np.linspace(-0.02, -0.4, 15)
    curves = [vhfit.Curve(strain=eps, stress=m.stress(true, strain=eps, strain_rate=r,
                                                      measure="engineering"), strain_rate=r)
              for r in (-0.1, -10.0, -1000.0)]
    cal = vhfit.calibrate(curves, hyperelastic="neo_hooke", n_prony="auto", max_prony=2,
                          seed=0, maxiter=60, uncertainty=False,
                          bounds={"tau2": (0.5, 2.0)})
    assert [r["n_prony"] for r in cal.order_scan] == [1, 2]
    if cal.n_prony == 2:
        assert 0.5 <= cal.params["tau2"] <= 2.0


def _constrained_best(alpha_hi: float) -> tuple[float, float]:
    """The least RMSAPE (Eq. 20: residuals over the curve's mean |stress|) of one-term
    Ogden on the exact data with α ≤ ``alpha_hi``, found independently of vhfit's search:
    for each α of a fine grid the best μ is the closed form of linear least squares,
    μ = Σ b y / Σ b² with b the stress at μ = 1; returns (α, RMSAPE %) of the grid's
    best."""
    y = ogden_engineering(TRUTH["mu1"], TRUTH["alpha1"], EPS)
    best = (np.nan, np.inf)
    for a in np.linspace(0.5, alpha_hi, 3001):
        b = ogden_engineering(1.0, a, EPS)
        mu = (b * y).sum() / (b * b).sum()
        e = 100.0 * float(np.sqrt(np.mean((mu * b - y) ** 2))) / float(np.mean(np.abs(y)))
        if e < best[1]:
            best = (float(a), e)
    return best


def test_bounds_change_the_fit_as_the_api_does(ogden_csv, tmp_path, capsys):
    """The data's α1 = 5 sits outside --bounds alpha1=-3:2: the fit ends on the bound with
    the error of the best material that the bound allows (found by an independent scan),
    and calibrate(bounds=...) gives the same; without the flag the data are recovered."""
    a_best, e_best = _constrained_best(2.0)
    assert a_best == pytest.approx(2.0)  # the premise: the bound is active
    assert e_best > 5.0
    out = tmp_path / "bounded"
    assert cli.main(["fit", str(ogden_csv), "--model", "ogden", "--prony", "0", "--bounds",
                     "alpha1=-3:2", "--out", str(out), "--no-plot", "-q"]) == 0
    res = json.loads((out / "results.json").read_text())
    assert res["params"]["alpha1"] <= 2.0
    assert res["params"]["alpha1"] == pytest.approx(2.0, abs=1e-6)
    assert res["rmsape"] == pytest.approx(e_best, rel=1e-6)
    assert res["settings"]["bounds"] == {"alpha1": [-3.0, 2.0]}
    curves = vhfit.read_csv(ogden_csv)
    api = vhfit.calibrate(curves, hyperelastic="ogden", n_prony=0, seed=0,
                          bounds={"alpha1": (-3.0, 2.0)})
    assert api.rmsape == pytest.approx(res["rmsape"], rel=1e-9)
    free = tmp_path / "free"
    assert cli.main(["fit", str(ogden_csv), "--model", "ogden", "--prony", "0",
                     "--out", str(free), "--no-plot", "-q"]) == 0
    res = json.loads((free / "results.json").read_text())
    assert res["params"]["alpha1"] == pytest.approx(5.0, rel=1e-6)
    assert res["rmsape"] < 1e-4
    capsys.readouterr()


# ====================================================================== --sort
@pytest.fixture(scope="module")
def shuffled(tmp_path_factory) -> tuple[Path, Path]:
    """A relaxation-free ramp with a time column, its rows out of order, and the same rows
    in order."""
    folder = tmp_path_factory.mktemp("sort")
    m = vhfit.ViscoHyperelastic("neo_hooke", 1)
    t = np.linspace(0.0, 4.0, 21)
    eps = 0.1 * t
    s = m.stress(dict(C10=0.1, G1=0.2, tau1=1.0), strain=eps, strain_rate=0.1,
                 measure="engineering")
    rows = np.column_stack([t, eps, s])
    order = np.random.default_rng(3).permutation(len(t))
    order = np.concatenate([[0], order[order != 0]])  # the test still starts at t = 0
    return (write(folder / "shuffled.csv", "time_s,strain,stress_MPa", rows[order]),
            write(folder / "ordered.csv", "time_s,strain,stress_MPa", rows))


def test_sort_reads_rows_out_of_order_as_the_ordered_file(shuffled, tmp_path, capsys):
    bad, good = shuffled
    msg = refused(["fit", str(bad), "--prony", "1"], tmp_path / "out", capsys, "files")
    assert "time goes back" in msg and "--sort" in msg, msg
    parser = build_parser()
    [a], _ = read_curves([str(bad)], parser.parse_args(["fit", str(bad), "--sort"]))
    [b], _ = read_curves([str(good)], parser.parse_args(["fit", str(good)]))
    assert np.array_equal(a.history.time, b.history.time)
    assert np.array_equal(a.target_stress, b.target_stress)


def test_sort_is_recorded_and_check_reads_the_files_with_it(shuffled, tmp_path, capsys):
    bad, _ = shuffled
    out = tmp_path / "o"
    assert cli.main(["fit", str(bad), "--prony", "1", "--sort", "--out", str(out),
                     "--no-plot", "-q", "--maxiter", "30"]) == 0
    assert json.loads((out / "results.json").read_text())["cli_options"]["sort"] is True
    capsys.readouterr()
    assert cli.main(["check", str(out / "results.json")]) == 0, capsys.readouterr().err


# ==================================================================== --select
def test_select_of_a_value_that_is_not_there_lists_those_present(tmp_path, capsys):
    rows = "".join(f"{r},{e!r},{10 * e!r}\n" for r in ("cortex", "white") for e in
                   (0.0, 0.1, 0.2))
    path = tmp_path / "regions.csv"
    path.write_text("region,strain,stress_kPa\n" + rows)
    msg = refused(["fit", str(path), "--select", "region=grey"], tmp_path / "out", capsys,
                  "files")
    assert re.fullmatch(re.escape(f"{path}: --select region=grey keeps no rows; column 'region' "
                                  "holds cortex, white"), msg), msg


# ================================================= column names as labs write them
def test_descriptive_suffixes_are_names_not_units(tmp_path):
    """'_gamma', '_tau', '_sigma' after a quantity's name say what it is; '_C' after a
    temperature is its unit."""
    gamma = np.array([0.0, 0.1, 0.2, 0.3])
    tau_kpa = np.array([0.0, 10.0, 19.0, 27.0])
    path = write(tmp_path / "shear.csv", "shear_strain_gamma,shear_stress_tau_kPa,"
                 "nominal_temperature_C,measured_sample_temperature_C",
                 zip(gamma, tau_kpa, [25.0] * 4, [25.01, 24.99, 25.02, 25.0]))
    [c] = vhfit.read_csv(path, n_points=None)
    assert c.deformation == "simple_shear"
    assert c.temperature == pytest.approx(25.005)
    assert np.allclose(np.trim_zeros(c.target_stress), tau_kpa[1:] / 1000.0)
    path = write(tmp_path / "shear2.csv", "strain_gamma,stress_sigma_MPa",
                 zip(gamma, tau_kpa / 1000.0))
    [c] = vhfit.read_csv(path, n_points=None)
    assert c.deformation == "simple_shear"
    assert np.allclose(np.trim_zeros(c.target_stress), tau_kpa[1:] / 1000.0)
    path = write(tmp_path / "uni.csv", "engineering_strain_eps,nominal_stress_sigma_kPa",
                 zip(gamma, tau_kpa))
    [c] = vhfit.read_csv(path, n_points=None)
    assert c.deformation == "uniaxial" and c.measure == "engineering"
    assert np.allclose(np.trim_zeros(c.target_stress), tau_kpa[1:] / 1000.0)


def test_nominal_and_measured_temperatures_that_disagree_name_both_and_the_flag(tmp_path,
                                                                                capsys):
    rows = [(f, 10.0 + f, 1.0, T, T - 0.4 - 0.01 * k) for T in (25.0, 50.0)
            for k, f in enumerate((0.1, 1.0, 10.0))]
    path = tmp_path / "dma.csv"
    path.write_text("frequency_Hz,storage_MPa,loss_MPa,nominal_temperature_C,"
                    "measured_sample_temperature_C\n"
                    + "".join(f"{f:g},{e:g},{lo:g},{T:.1f},{m:.2f}\n" for f, e, lo, T, m in rows))
    msg = refused(["fit", str(path)], tmp_path / "out", capsys)
    assert "'nominal_temperature_C'" in msg and "'measured_sample_temperature_C'" in msg
    assert msg.endswith("say which with --columns temperature=nominal_temperature_C"), msg
    items = vhfit.read_csv(path, columns={"temperature": "measured_sample_temperature_C"})
    assert [round(i.temperature, 2) for i in items] == [24.59, 49.59]
    parser = build_parser()
    items, _ = read_curves([str(path)], parser.parse_args(
        ["fit", str(path), "--columns", "temperature=nominal_temperature_C"]))
    assert [i.temperature for i in items] == [25.0, 50.0]


# ============================================ temperatures of stress–strain files
def _shear_file(path: Path, nominal: float, measured) -> Path:
    gamma = np.linspace(0.0, 0.3, len(measured))
    rows = "".join(f"{g:.3f},{20.0 * g:.4f},{nominal:.1f},{m:.2f}\n"
                   for g, m in zip(gamma, measured))
    path.write_text("shear_strain_gamma,shear_stress_kPa,nominal_temperature_C,"
                    "measured_sample_temperature_C\n" + rows)
    return path


def test_temperature_columns_of_a_stress_strain_file_are_read_or_refused(tmp_path, capsys):
    """Recognised with their descriptive words; agreeing within their rounding, the finer
    one is read; disagreeing, refused naming both and --columns temperature=NAME; a curve
    is at one temperature (its readings within CURVE_TEMPERATURE_SPREAD); --columns
    temperature= ignores the column."""
    ok = _shear_file(tmp_path / "ok.csv", 40.0, [40.02, 40.01, 39.98, 40.03])
    [c] = vhfit.read_csv(ok)
    assert c.temperature == pytest.approx(40.01)
    assert c.metadata["columns"]["temperature"] == "measured_sample_temperature_C"
    off = _shear_file(tmp_path / "off.csv", 40.0, [38.6, 38.7, 38.8, 38.8])
    msg = refused(["fit", str(off)], tmp_path / "out", capsys, "files")
    assert "'nominal_temperature_C' and 'measured_sample_temperature_C' could both be the " \
           "temperature but differ (40 vs 38.6)" in msg, msg
    assert msg.endswith("say which with --columns temperature=nominal_temperature_C"), msg
    parser = build_parser()
    [c], _ = read_curves([str(off)], parser.parse_args(
        ["fit", str(off), "--columns", "temperature=measured_sample_temperature_C"]))
    assert c.temperature == pytest.approx(38.725)
    [c], _ = read_curves([str(off)], parser.parse_args(
        ["fit", str(off), "--columns", "temperature="]))
    assert c.temperature is None
    drift = _shear_file(tmp_path / "drift.csv", 40.0, [40.0, 45.0, 50.0, 55.0])
    msg = refused(["fit", str(drift), "--columns", "temperature=measured_sample_temperature_C"],
                  tmp_path / "out2", capsys)
    assert re.search(r"column 'measured_sample_temperature_C': the temperature goes from 40 "
                     r"to 55 within one curve: .*--columns temperature=$", msg), msg


def test_stress_strain_files_at_two_temperatures_are_not_merged(tmp_path, capsys):
    """Before, their temperature columns were ignored and the tests fitted as if at one
    temperature; now they need a shift, as tests with '# temperature:' lines do."""
    a = _shear_file(tmp_path / "a.csv", 20.0, [20.0, 20.0, 20.0, 20.0])
    b = _shear_file(tmp_path / "b.csv", 60.0, [60.0, 60.0, 60.0, 60.0])
    msg = refused(["fit", str(a), str(b), "--rate", "0.01"], tmp_path / "out", capsys)
    assert "tests at 2 temperatures" in msg and "--shift" in msg, msg


def test_bound_problem_and_bounds_terms_are_the_one_check_of_both_doors():
    """``vhfit.calibration.bound_problem`` words the fix without the flag or keyword (each
    door adds its own); ``bounds_terms`` is how many Prony terms a fit may have."""
    from vhfit.calibration import bound_problem, bounds_terms

    assert (bounds_terms(3), bounds_terms("auto", 7), bounds_terms(None)) == (3, 7, 2)
    assert bound_problem("alpha1", -40.0, 40.0, "ogden", 0) is None
    assert bound_problem("tau2", 1e-3, 1.0, "yeoh", 2) is None
    assert bound_problem("tau3", 1e-3, 1.0, "yeoh", 2).startswith("unknown parameter")
    assert bound_problem("C20", -1.0, 1.0, "yeoh", 0) is None  # Yeoh's C20 may be < 0
    assert "physical range" in bound_problem("C10", -1.0, 1.0, "yeoh", 0)
    assert "physical range" in bound_problem("beta", 0.5, 1.5, "van_der_waals", 0)
    assert bound_problem("beta", 0.0, 1.0, "van_der_waals", 0) is None


@pytest.mark.parametrize("header, unit", [("sample_temperature", ""), ("temperature_C", "C"),
                                          ("temp [K]", "K"), ("measured_temperature_degC",
                                                              "degC")])
def test_a_word_after_temperature_is_no_unit(tmp_path, header, unit):
    """Only C, K or F (and their spellings) after a temperature are its unit; other words
    qualify it ('sample_temperature' is a temperature without a unit)."""
    path = tmp_path / "t.csv"
    path.write_text(f"strain,stress_MPa,{header}\n0.0,0.0,30.1\n0.1,1.0,30.2\n")
    [c] = vhfit.read_csv(path)
    assert c.temperature == pytest.approx(30.15)
    from vhfit.data._columns import _classify
    assert _classify(2, header).unit.lower() == unit.lower()


def test_a_user_limit_of_a_modulus_holds_with_the_default_method():
    """An upper limit on G1 below the data's: the exact solve of the moduli holds it (the
    best fit within it sits on it), and nothing is said to lie outside it."""
    m = vhfit.ViscoHyperelastic("neo_hooke", 1)
    true = dict(C10=0.1, G1=0.5, tau1=0.01)
    eps = np.linspace(-0.02, -0.4, 15)
    curves = [vhfit.Curve(strain=eps, stress=m.stress(true, strain=eps, strain_rate=r,
                                                      measure="engineering"), strain_rate=r)
              for r in (-1.0, -100.0)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate(curves, hyperelastic="neo_hooke", n_prony=1, seed=0,
                              bounds={"G1": (0.0, 0.2)}, uncertainty=False)
    assert cal.params["G1"] <= 0.2 * (1 + 1e-12)
    assert cal.params["G1"] == pytest.approx(0.2, rel=1e-6)  # the data want more
    assert not any("outside the limits" in w for w in cal.warnings)


def test_a_limit_of_one_prony_term_passed_by_merging_terms_is_named():
    """One relaxation time with G = 0.5 in the data, two terms each limited to 0.3: the
    exact fit puts both at that τ (0.3 + 0.2), which are then merged into one term of
    0.5 — past the limit given to G1, which the result names in its first lines."""
    m = vhfit.ViscoHyperelastic("neo_hooke", 1)
    true = dict(C10=0.1, G1=0.5, tau1=0.01)
    eps = np.linspace(-0.02, -0.4, 15)
    curves = [vhfit.Curve(strain=eps, stress=m.stress(true, strain=eps, strain_rate=r,
                                                      measure="engineering"), strain_rate=r)
              for r in (-1.0, -10.0, -100.0)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate(curves, hyperelastic="neo_hooke", n_prony=2, seed=0,
                              bounds={"G1": (0.0, 0.3), "G2": (0.0, 0.3)},
                              uncertainty=False)
    assert cal.n_prony == 1 and cal.params["G1"] == pytest.approx(0.5, rel=1e-4)
    named = [h for h in cal.headlines if h.startswith("G1 = ") and "outside the limits" in h]
    assert len(named) == 1 and "(0, 0.3)" in named[0]
