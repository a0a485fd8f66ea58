"""Input ambiguities (vhfit.data._ambiguous): competing columns, varying text columns,
ambiguous unit suffixes — each settled by its stated rule or refused in one line, in the
reader and through the command line (exit 2, nothing written)."""

from __future__ import annotations

import re

import numpy as np
import pytest

import vhfit
from vhfit.cli import main
from vhfit.data import DataError


def write(tmp_path, text, name="t.csv"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def refused(pattern, path, **kw):
    with pytest.raises(DataError) as info:
        vhfit.read_csv(path, **kw)
    msg = str(info.value)
    assert "\n" not in msg
    assert re.search(pattern, msg), msg
    return msg


# ============================================================ competing columns
def test_disagreeing_stress_columns_are_refused_naming_both_and_the_choice(tmp_path):
    p = write(tmp_path, "strain,stress_kPa,stress_MPa\n0,0,0\n-0.1,-50,-0.5\n")
    refused(r"line 3: columns 'stress_MPa' and 'stress_kPa' could both be the stress but "
            r"differ \(-0\.5 vs -0\.05 MPa\): say which with columns=\{'stress': "
            r"'stress_MPa'\} \(command line: --columns stress=stress_MPa\)", p, rate=-1.0)
    [c] = vhfit.read_csv(p, rate=-1.0, columns={"stress": "stress_kPa"}, n_points=None)
    np.testing.assert_allclose(c.stress, [0.0, -0.05])
    [c] = vhfit.read_csv(p, rate=-1.0, columns={"stress": "stress_MPa"}, n_points=None)
    np.testing.assert_allclose(c.stress, [0.0, -0.5])


def test_agreeing_columns_read_the_finest_written_one(tmp_path):
    # -50.04 kPa (rounding 0.005 kPa) and -0.05 MPa (rounding 0.005 MPa) agree; the kPa
    # column carries more digits and is read
    p = write(tmp_path, "strain,stress_MPa,stress_kPa\n0,0,0\n-0.1,-0.05,-50.04\n")
    [c] = vhfit.read_csv(p, rate=-1.0, n_points=None)
    np.testing.assert_allclose(c.stress, [0.0, -0.05004])
    assert c.metadata["columns"]["stress"] == "stress_kPa"


def test_columns_that_differ_by_more_than_their_rounding_are_refused(tmp_path):
    # agreement: within twice the sum of the written roundings. -50.16 kPa = -0.05016 MPa
    # against -0.0501 MPa (rounding 5e-5 MPa): 6e-5 <= 2 (5e-5 + 5e-6) = 1.1e-4, agree
    # (once the sum, 5.5e-5, would refuse it); against -0.0500: 1.6e-4 > 1.1e-4, refused
    ok = write(tmp_path, "strain,stress_kPa,stress_MPa\n0,0,0\n-0.1,-50.16,-0.0501\n")
    [c] = vhfit.read_csv(ok, rate=-1.0, n_points=None)
    np.testing.assert_allclose(c.stress, [0.0, -0.05016])
    bad = write(tmp_path, "strain,stress_kPa,stress_MPa\n0,0,0\n-0.1,-50.16,-0.0500\n")
    refused(r"could both be the stress but differ", bad, rate=-1.0)


@pytest.mark.parametrize("text, pattern", [
    ("strain,stretch,stress\n0.00,1.00,0\n-0.10,0.80,-0.5\n",
     r"columns 'strain' and 'stretch' could both be the strain but differ \(-0\.1 vs -0\.2\)"
     r": say which with columns=\{'strain': 'strain'\} \(command line: --columns "
     r"strain=strain\)"),
    ("time_s,time_ms,strain,stress\n0,0,0,0\n1.0,100,-0.1,-0.5\n",
     r"columns 'time_s' and 'time_ms' could both be the time but differ \(1 vs 0\.1 s\): "
     r"say which with columns=\{'time': 'time_s'\}"),
    ("strain_rate,rate_1/min,strain,stress\n-1.0,-6.0,0,0\n-1.0,-6.0,-0.1,-0.5\n",
     r"columns 'strain_rate' and 'rate_1/min' could both be the strain rate but differ "
     r"\(-1 vs -0\.1 1/s\)"),
])
def test_strain_time_and_rate_columns_that_disagree_are_refused(tmp_path, text, pattern):
    refused(pattern, write(tmp_path, text), **({} if "time" in text or "rate" in text
                                               else {"rate": -1.0}))


def test_a_true_strain_agreeing_with_the_engineering_strain_is_no_ambiguity(tmp_path):
    # ln(1.5) = 0.405465: written to 6 decimals, it agrees with 0.5 through exp(e); the
    # engineering strain, written as finely (its rounding is not magnified by exp(e)), is read
    p = write(tmp_path, "engineering_strain,true_strain,stress\n0,0,0\n0.500000,0.405465,1\n")
    [c] = vhfit.read_csv(p, rate=1.0, n_points=None)
    np.testing.assert_allclose(c.strain, [0.0, 0.5])
    assert c.metadata["columns"]["strain"] == "engineering_strain"
    # written coarser (0.5: rounding 0.05), the true strain is the finer one and is read
    p = write(tmp_path, "engineering_strain,true_strain,stress\n0,0,0\n0.5,0.405465,1\n")
    [c] = vhfit.read_csv(p, rate=1.0, n_points=None)
    np.testing.assert_allclose(c.strain, [0.0, np.expm1(0.405465)])
    p = write(tmp_path, "engineering_strain,true_strain,stress\n0,0,0\n0.50,0.50,1.0\n")
    refused(r"'engineering_strain' and 'true_strain' could both be the strain", p, rate=1.0)


def test_the_rounding_of_a_true_strain_grows_through_the_conversion(tmp_path):
    # at ε = 16 the true strain ln 17 = 2.833 written as 2.83 (rounding 0.005) means
    # ε within ±0.005 e^2.83 = ±0.085: it agrees with 16.000
    p = write(tmp_path, "engineering_strain,true_strain,stress\n0,0,0\n16.000,2.83,1\n")
    [c] = vhfit.read_csv(p, rate=1.0, n_points=None)
    np.testing.assert_allclose(c.strain, [0.0, 16.0])


def test_an_amount_of_shear_is_not_compared_with_a_stretch(tmp_path):
    text = "time_s,gamma,stretch,shear_stress_kPa\n0,0,1.00,0\n1,0.20,1.10,20\n"
    [c] = vhfit.read_csv(write(tmp_path, text), n_points=None)
    assert c.deformation == "simple_shear"
    np.testing.assert_allclose(c.strain, [0.0, 0.2])


def test_a_column_with_another_qualifier_is_another_channel(tmp_path):
    # crosshead_strain (an unknown qualifier) is not compared: the extensometer strain is read
    p = write(tmp_path, "strain,crosshead_strain,stress\n0,0,0\n-0.100,-0.300,-0.5\n")
    [c] = vhfit.read_csv(p, rate=-1.0, n_points=None)
    np.testing.assert_allclose(c.strain, [0.0, -0.1])


def test_a_competing_column_with_a_unit_that_does_not_parse_is_refused(tmp_path):
    p = write(tmp_path, "strain,stress,stress_foo\n0,0,0\n-0.1,-1,-1\n")
    refused(r"column 'stress_foo': could also be the stress beside 'stress', but unit 'foo' "
            r"is not understood for stress: say which column is the stress with "
            r"columns=\{'stress': 'stress'\} \(command line: --columns stress=stress\)",
            p, rate=-1.0)


def test_sweep_columns_compared_by_value(tmp_path):
    ok = "frequency_Hz,omega_rad/s,storage_MPa,loss_MPa\n1.0,6.283185,1,0.1\n10.0,62.83185,2,0.2\n"
    [s] = vhfit.read_csv(write(tmp_path, ok))  # ω written finer: read, as Hz
    np.testing.assert_allclose(s.frequency, [6.283185 / (2 * np.pi), 62.83185 / (2 * np.pi)])
    bad = "frequency_Hz,omega_rad/s,storage_MPa,loss_MPa\n1,6.283,1,0.1\n10,6.283,2,0.2\n"
    refused(r"line 3: columns 'frequency_Hz' and 'omega_rad/s' could both be the frequency "
            r"but differ \(10 vs 0\.999\d* Hz\): say which with columns=\{'frequency': "
            r"'frequency_Hz'\} \(command line: --columns frequency=frequency_Hz\)",
            write(tmp_path, bad))
    eg = "frequency_Hz,E_storage_MPa,G_storage_MPa,loss_MPa\n1,3,1,0.1\n10,6,2,0.2\n"
    [s] = vhfit.read_csv(write(tmp_path, eg))  # E' = 3 G': the same modulus
    np.testing.assert_allclose(s.storage, [3.0, 6.0])
    eg_bad = "frequency_Hz,E_storage_MPa,G_storage_MPa,loss_MPa\n1,3.0,2.0,0.1\n10,6,2,0.2\n"
    refused(r"'E_storage_MPa' and 'G_storage_MPa' could both be the storage but differ "
            r"\(3 vs 6 MPa\)", write(tmp_path, eg_bad))


def test_temperature_columns_with_descriptive_words(tmp_path):
    head = "frequency_Hz,storage_MPa,loss_MPa,nominal_temperature_C,measured_sample_temperature_C\n"
    agree = head + "1,1,0.1,40,40.3\n10,2,0.2,40,40.2\n1,0.5,0.1,60,60.1\n10,1,0.1,60,60.2\n"
    # 40 (rounding 0.5) and 40.3 agree: the finer-written measured temperature is read
    a, b = vhfit.read_csv(write(tmp_path, agree))
    assert (a.temperature, b.temperature) == (pytest.approx(40.25), pytest.approx(60.15))
    a, b = vhfit.read_csv(write(tmp_path, agree), columns={"temperature": "nominal_temperature_C"})
    assert (a.temperature, b.temperature) == (40.0, 60.0)
    differ = head + "1,1,0.1,40,41.3\n10,2,0.2,40,41.2\n"
    refused(r"line 2: columns 'nominal_temperature_C' and 'measured_sample_temperature_C' "
            r"could both be the temperature but differ \(40 vs 41\.3\): say which with "
            r"columns=\{'temperature': 'nominal_temperature_C'\} \(command line: --columns "
            r"temperature=nominal_temperature_C\)", write(tmp_path, differ))


# ============================================================ ambiguous unit suffixes
def test_a_symbol_after_the_keyword_is_a_word_not_a_unit(tmp_path):
    p = write(tmp_path, "time_s,shear_strain_gamma,shear_stress_kPa\n0,0,0\n1,0.1,20\n2,0.2,35\n")
    [c] = vhfit.read_csv(p, n_points=None)
    assert c.deformation == "simple_shear"
    np.testing.assert_allclose(c.strain, [0.0, 0.1, 0.2])
    np.testing.assert_allclose(c.stress, [0.0, 0.02, 0.035])


def test_bar_after_a_symbol_is_refused_until_the_unit_is_given(tmp_path):
    p = write(tmp_path, "strain,sigma_bar\n0,0\n-0.1,-1\n")
    refused(r"column 'sigma_bar': 'bar' after a symbol may be the unit or an overbar \(a "
            r"mean\): .*units=\{'stress': \.\.\.\} \(command line: --units stress=UNIT\)",
            p, rate=-1.0)
    [c] = vhfit.read_csv(p, rate=-1.0, units={"stress": "MPa"}, n_points=None)
    np.testing.assert_allclose(c.stress, [0.0, -1.0])
    [c] = vhfit.read_csv(p, rate=-1.0, units={"stress": "bar"}, n_points=None)
    np.testing.assert_allclose(c.stress, [0.0, -0.1])
    [c] = vhfit.read_csv(write(tmp_path, "strain,stress_bar\n0,0\n-0.1,-1\n"), rate=-1.0,
                         n_points=None)  # after a word, bar is the unit
    np.testing.assert_allclose(c.stress, [0.0, -0.1])


def test_an_unknown_units_role_is_refused(tmp_path):
    p = write(tmp_path, "strain,stress\n0,0\n-0.1,-1\n")
    refused(r"units=\{'stres': \.\.\.\} \(command line: --units stres=UNIT\): unknown role",
            p, rate=-1.0, units={"stres": "kPa"})


# ============================================================ varying text columns
BRAIN = ("region,mode,stretch_or_shear_amount,nominal_stress_kPa\n"
         "cortex,uniaxial_tension_compression,0.90,-1.10\n"
         "cortex,uniaxial_tension_compression,1.10,0.90\n"
         "cortex,simple_shear,-0.20,-0.30\ncortex,simple_shear,0.20,0.30\n"
         "callosum,uniaxial_tension_compression,0.90,-0.50\n"
         "callosum,uniaxial_tension_compression,1.10,0.40\n"
         "callosum,simple_shear,-0.20,-0.10\ncallosum,simple_shear,0.20,0.10\n")


def test_a_varying_text_column_is_refused_with_the_flags(tmp_path):
    refused(r"^\S*brain\.csv, column 'region': 2 different values \('callosum', 'cortex'\) "
            r"would be merged into one curve: fit the groups as one material with "
            r"group_by='region' \(command line: --group-by region\) or keep one with "
            r"select=\{'region': 'callosum'\} \(command line: --select region=callosum\)$",
            write(tmp_path, BRAIN, "brain.csv"))


def test_group_by_splits_and_select_keeps(tmp_path):
    p = write(tmp_path, BRAIN, "brain.csv")
    cs = vhfit.read_csv(p, group_by="region")
    assert [(c.name, c.deformation) for c in cs] == [
        ("brain [cortex, uniaxial_tension_compression]", "uniaxial"),
        ("brain [cortex, simple_shear]", "simple_shear"),
        ("brain [callosum, uniaxial_tension_compression]", "uniaxial"),
        ("brain [callosum, simple_shear]", "simple_shear")]
    np.testing.assert_allclose(cs[2].stress, [-5e-4, 4e-4])
    np.testing.assert_allclose(cs[3].strain, [-0.2, 0.2])
    uni, shear = vhfit.read_csv(p, select={"region": "callosum"})
    np.testing.assert_allclose(uni.strain, [-0.1, 0.1], atol=1e-12)
    np.testing.assert_allclose(shear.stress, [-1e-4, 1e-4])
    refused(r"select=\{'region': 'pons'\} \(command line: --select region=pons\) keeps no "
            r"rows; column 'region' holds callosum, cortex", p, select={"region": "pons"})


def test_a_text_column_constant_in_each_curve_row_labels_and_ignored_columns_pass(tmp_path):
    # 'series' follows the rate groups; 'stamp' differs on every row (a label); 'note' is
    # ignored by the user
    text = ("series,stamp,note,strain_rate,strain,stress\n"
            "slow,a1,x,-1,0,0\nslow,a2,y,-1,-0.1,-1\nfast,a3,x,-10,0,0\nfast,a4,y,-10,-0.1,-2\n")
    p = write(tmp_path, text)
    refused(r"column 'note': 2 different values", p)
    cs = vhfit.read_csv(p, columns={"ignore": "note"}, n_points=None)
    assert [c.strain_rate for c in cs] == [-1.0, -10.0]
    np.testing.assert_allclose(cs[1].stress, [0.0, -2.0])


def test_a_moduli_file_with_a_varying_text_column(tmp_path):
    text = ("material,frequency_Hz,storage_MPa,loss_MPa\n"
            "A,1,1,0.1\nA,10,2,0.2\nB,1,0.5,0.05\nB,10,1,0.1\n")
    p = write(tmp_path, text)
    refused(r"column 'material': 2 different values \('A', 'B'\) would be merged", p)
    a, b = vhfit.read_csv(p, group_by="material")
    assert (a.name, b.name) == ("t [A]", "t [B]")
    np.testing.assert_allclose(b.storage, [0.5, 1.0])
    [b] = vhfit.read_csv(p, select={"material": "B"})
    np.testing.assert_allclose(b.loss, [0.05, 0.1])
    refused(r"columns=\{'ignore': 'nope'\} \(command line: --columns ignore=nope\): no such "
            r"column", p,
            columns={"ignore": "nope"})


def test_select_matches_numbers_by_value(tmp_path):
    text = "set,strain,stress\n1.0,0,0\n1.0,-0.1,-1\n2,0,0\n2,-0.1,-3\n"
    [c] = vhfit.read_csv(write(tmp_path, text), rate=-1.0, select={"set": "1"}, n_points=None)
    np.testing.assert_allclose(c.stress, [0.0, -1.0])


# ============================================================ the command line
def _fit(tmp_path, *args):
    out = tmp_path / "out"
    code = main(["fit", *map(str, args), "--out", str(out), "--prony", "0", "--no-plot", "-q",
                 "--maxiter", "3"])
    return code, out


@pytest.mark.parametrize("text, flags, pattern", [
    ("strain,stress_kPa,stress_MPa\n0,0,0\n-0.1,-50,-0.5\n-0.2,-120,-1.2\n", ["--rate", "-1"],
     r"could both be the stress but differ .*--columns stress=stress_MPa"),
    (BRAIN, [], r"column 'region': .*--group-by region.*--select region=callosum"),
    (BRAIN, ["--select", "region=pons"],
     r": --select region=pons keeps no rows; column 'region' holds callosum, cortex"),
    (BRAIN, ["--columns", "stress"], r"--columns 'stress': give ROLE=NAME"),
    (BRAIN, ["--columns", "strass=x"], r"brain\.csv: --columns strass=NAME: unknown role"),
    (BRAIN, ["--units", "stres=kPa"], r"error: --units stres=UNIT: unknown role"),
    (BRAIN, ["--group-by", "regio"], r"no column 'regio' \(group_by=, --group-by regio\)"),
])
def test_cli_refuses_ambiguous_input_in_one_line_and_writes_nothing(tmp_path, capsys, text,
                                                                      flags, pattern):
    p = write(tmp_path, text, "brain.csv")
    code, out = _fit(tmp_path, p, *flags)
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and re.search(pattern, err), err
    assert not out.exists()


def test_cli_columns_units_select_and_group_by_reach_the_reader(tmp_path, capsys):
    p = write(tmp_path, BRAIN, "brain.csv")
    code, out = _fit(tmp_path, p, "--select", "region=cortex", "--select",
                     "mode=uniaxial_tension_compression", "--units", "stress=Pa",
                     "--columns", "stress=nominal_stress_kPa")
    assert code == 0
    import json

    res = json.loads((out / "results.json").read_text())
    assert res["cli_options"]["select"] == [["region", "cortex"],
                                            ["mode", "uniaxial_tension_compression"]]
    rows = (out / "fitted_curves.csv").read_text().splitlines()
    points = [r.split(",") for r in rows if ",point," in r]
    # -1.10 and 0.90 given in Pa (--units) are -1.1e-6 and 9e-7 MPa
    np.testing.assert_allclose([float(r[6]) for r in points], [-1.1e-6, 9e-7])
    code = main(["fit", str(p), "--group-by", "region", "--out", str(tmp_path / "o2"),
                 "--prony", "0", "--no-plot", "-q", "--maxiter", "3"])
    assert code == 0
    res = json.loads((tmp_path / "o2" / "results.json").read_text())
    assert len(res["curves"]) == 4


def test_cli_check_reads_the_data_as_the_fit_did(tmp_path, capsys):
    p = write(tmp_path, BRAIN, "brain.csv")
    out = tmp_path / "o"
    assert main(["fit", str(p), "--select", "region=cortex", "--out", str(out), "--prony",
                 "0", "--no-plot", "-q", "--maxiter", "3", "--for", "abaqus"]) == 0
    capsys.readouterr()
    # the fit's --select, recorded in results.json, is the check's too: without it the
    # file would be refused for its region column
    assert main(["check", str(out / "results.json")]) == 0
    cortex = capsys.readouterr().out
    assert "brain [simple_shear]" in cortex
    assert main(["check", str(out / "results.json"), "--select", "region=callosum"]) == 0
    callosum = capsys.readouterr().out
    assert "brain [simple_shear]" in callosum and callosum != cortex  # other data


def test_cli_columns_role_without_a_name_ignores_the_role(tmp_path, capsys):
    # a measured rate channel: refused naming --columns rate=, which then reads the file
    text = "strain_rate,strain,stress\n-1,0,0\n-2,-0.1,-1\n-3,-0.2,-2\n-4,-0.3,-3\n"
    p = write(tmp_path, text)
    code, out = _fit(tmp_path, p)
    assert code == 2 and "--columns rate=" in capsys.readouterr().err and not out.exists()
    code, out = _fit(tmp_path, p, "--columns", "rate=", "--rate", "-1")
    assert code == 0 and (out / "results.json").exists()


# ============================================================ loading histories
def test_history_units_and_competing_columns(tmp_path):
    from vhfit.data import read_history

    t, e = read_history(write(tmp_path, "time_ms,strain_%\n1000,-20\n3000,-20\n"))
    np.testing.assert_allclose(t, [0.0, 1.0, 3.0])
    np.testing.assert_allclose(e, [0.0, -0.2, -0.2])
    t, e = read_history(write(tmp_path, "time_s,time_ms,strain\n0,0,0\n1.0,1000,-0.2\n"))
    np.testing.assert_allclose(t, [0.0, 1.0])
    p = write(tmp_path, "time_s,time_ms,strain\n0,0,0\n1.0,100,-0.2\n")
    with pytest.raises(DataError, match=r"data row 3: columns 'time_ms' and 'time_s' could "
                                        r"both be the time but differ \(0\.1 vs 1 s\): the "
                                        r"history reads 'time_s'; delete or rename the other"):
        read_history(p)
    with pytest.raises(DataError, match=r"column 'strain_gauge': unit 'gauge' is not "
                                        r"understood for strain"):
        read_history(write(tmp_path, "time,strain_gauge\n0,0\n1,0.1\n"))


# ============================================ extra numeric channels (lab files as written)
def _hydrogel(n: int = 3276) -> tuple[str, np.ndarray, np.ndarray]:
    """A hydrogel tension file as its lab writes it: the derived reduced stress is nan at
    λ = 1 (0/0) and differs on every other row."""
    lam = np.linspace(1.0, 3.0, n)
    nominal = 10.0 * (lam - lam**-2)  # kPa, neo-Hooke with μ = 10 kPa
    with np.errstate(invalid="ignore", divide="ignore"):
        reduced = nominal / (lam - lam**-2) * (1.0 + 0.01 * (lam - 1.0))
    lines = ["time_s, stretch, engineering_strain, nominal_stress_kPa, reduced_stress_kPa"]
    for k, (lm, sn, sr) in enumerate(zip(lam, nominal, reduced)):
        red = "nan" if not np.isfinite(sr) else f"{sr:.4f}"
        lines.append(f"{0.05 * k:.2f}, {lm:.6f}, {lm - 1.0:.6f}, {sn:.5f}, {red}")
    return "\n".join(lines) + "\n", lam, nominal


def test_the_hydrogel_file_with_a_derived_column_nan_at_rest_is_read(tmp_path):
    """Issue: 'reduced_stress_kPa' (nan on the first row) was refused as 3275 specimens."""
    text, lam, nominal = _hydrogel()
    p = write(tmp_path, text)
    with pytest.warns(vhfit.DataWarning) as rec:
        [c] = vhfit.read_csv(p, n_points=None)
    np.testing.assert_allclose(c.strain, lam - 1.0, atol=1e-6)
    np.testing.assert_allclose(c.stress, nominal * 1e-3, atol=1e-8)  # kPa -> MPa
    notes = [str(w.message) for w in rec if "not used by the fit" in str(w.message)]
    assert notes == [f"{p}: column 'reduced_stress_kPa' read and not used by the fit"]


@pytest.mark.parametrize("cell", ["nan", "", "inf", "-inf", "NaN", "N/A"])
def test_a_numeric_channel_with_non_finite_cells_is_data_not_a_label(tmp_path, cell):
    rows = "".join(f"{0.1 * k:.1f},{k:.1f},{cell if k == 2 else 3.1 * k + 0.7}\n"
                   for k in range(6))
    p = write(tmp_path, "strain,stress_MPa,force_N\n" + rows)
    with pytest.warns(vhfit.DataWarning, match=r"column 'force_N' read and not used by the "
                                               r"fit"):
        [c] = vhfit.read_csv(p, rate=0.1, n_points=None)
    np.testing.assert_allclose(c.stress, np.arange(6.0))


def test_numbers_in_few_contiguous_blocks_are_a_specimen_label(tmp_path):
    """specimen = 1, 1, 1, 2, 2, 2 under a header no reader knows: a label, refused with
    the flags; group_by= splits by it; the same numbers interleaved are a channel."""
    rows = "".join(f"{0.1 * (k % 3):.1f},{k % 3:.1f},{1 + k // 3}\n" for k in range(6))
    p = write(tmp_path, "strain,stress_MPa,sample_no\n" + rows)
    refused(r"column 'sample_no': 2 different values \('1', '2'\) would be merged into one "
            r"curve: .*--group-by sample_no", p, rate=0.1)
    a, b = vhfit.read_csv(p, rate=0.1, group_by="sample_no", n_points=None)
    np.testing.assert_allclose(a.stress, [0.0, 1.0, 2.0])
    np.testing.assert_allclose(b.stress, [0.0, 1.0, 2.0])
    mixed = "".join(f"{0.1 * k:.1f},{k:.1f},{1 + k % 2}\n" for k in range(6))
    q = write(tmp_path, "strain,stress_MPa,channel\n" + mixed, "q.csv")
    with pytest.warns(vhfit.DataWarning, match="'channel' read and not used"):
        [c] = vhfit.read_csv(q, rate=0.1, n_points=None)
    assert c.n_points == 6


def test_many_values_in_blocks_are_a_channel_not_a_label():
    """A stepped channel with more values than LABEL_VALUES is data."""
    from vhfit.data._ambiguous import LABEL_VALUES, _is_block_label

    few = np.repeat(np.arange(3.0), 4)
    assert _is_block_label(few)
    assert not _is_block_label(np.repeat(np.arange(LABEL_VALUES + 1.0), 2))
    assert not _is_block_label(np.arange(12.0))  # every value differs
    assert not _is_block_label(np.array([1.0, 1.0, 2.0, 2.0, 1.0, 1.0]))  # 1 comes back
    assert not _is_block_label(np.array([1.0, 1.0, 2.0, 3.0, 3.0]))  # a block of one row


def test_a_true_stress_beside_the_nominal_one_is_no_conflict(tmp_path):
    """The nominal stress is fitted, and the note says so and how to fit the true one."""
    eps = np.linspace(0.0, 0.5, 6)
    s = 2.0 * eps
    rows = "".join(f"{e:.2f},{a:.3f},{a * (1 + e):.4f}\n" for e, a in zip(eps, s))
    p = write(tmp_path, "strain,nominal_stress_MPa,true_stress_MPa\n" + rows)
    with pytest.warns(vhfit.DataWarning) as rec:
        [c] = vhfit.read_csv(p, rate=0.1, n_points=None)
    assert c.measure == "engineering"
    np.testing.assert_allclose(c.stress, s, atol=1e-12)
    [msg] = [str(w.message) for w in rec if "stress" in str(w.message)]
    assert ("the nominal stress 'nominal_stress_MPa' is fitted, not the true stress "
            "'true_stress_MPa'") in msg and "--measure true" in msg, msg
    [t] = vhfit.read_csv(p, rate=0.1, n_points=None, measure="true")
    assert t.measure == "true"
    np.testing.assert_allclose(t.stress, s * (1 + eps), atol=1e-4)


def test_cli_reads_the_hydrogel_file_and_says_which_column_it_ignored(tmp_path, capsys):
    text, _, _ = _hydrogel(400)
    p = write(tmp_path, text)
    code = main(["fit", str(p), "--model", "neo_hooke", "--prony", "0", "--no-plot",
                 "--out", str(tmp_path / "out"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 0, err
    lines = [ln for ln in err.splitlines() if "reduced_stress_kPa" in ln]
    assert len(lines) == 1 and "not used by the fit" in lines[0], err


# ============================================ plausibility notes (never change the data)
def _notes(path, **kw):
    """The curves read and the DataWarning lines of one read."""
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        curves = vhfit.read_csv(path, rate=0.1, n_points=None, **kw)
    msgs = [str(w.message) for w in caught if issubclass(w.category, vhfit.DataWarning)]
    assert all("\n" not in m for m in msgs), msgs
    return curves, msgs


def test_a_strain_beyond_5_with_no_unit_asks_whether_it_is_percent(tmp_path):
    p = write(tmp_path, "strain,stress_MPa\n0,0\n10,0.5\n50,1.5\n")
    [c], msgs = _notes(p)
    [m] = [m for m in msgs if "is it in %" in m]
    assert "column 'strain': the strain reaches 50 (a stretch of 51)" in m, m
    assert "units={'strain': '%'}" in m and "--units strain=%" in m, m
    np.testing.assert_allclose(c.strain, [0.0, 10.0, 50.0])  # read as written
    [c], msgs = _notes(p, units={"strain": "%"})  # followed: no note, λ up to 1.5
    assert not [m for m in msgs if "is it in %" in m], msgs
    np.testing.assert_allclose(c.strain, [0.0, 0.1, 0.5])
    q = write(tmp_path, "strain_%,stress_MPa\n0,0\n10,0.5\n50,1.5\n", "q.csv")
    assert not [m for m in _notes(q)[1] if "is it in %" in m]  # a unit is stated
    q = write(tmp_path, "strain [mm/mm],stress_MPa\n0,0\n10,0.5\n50,1.5\n", "q.csv")
    assert not [m for m in _notes(q)[1] if "is it in %" in m]  # stated: not percent
    r = write(tmp_path, "strain,stress_MPa\n0,0\n2,0.5\n4.9,1.5\n", "r.csv")
    assert not [m for m in _notes(r)[1] if "is it in %" in m]  # up to 5: plausible


def test_a_stress_with_no_unit_is_said_to_be_read_as_mpa(tmp_path):
    p = write(tmp_path, "strain,stress\n0,0\n0.1,0.5\n0.5,1.5\n")
    [c], msgs = _notes(p)
    assert [m for m in msgs if "no unit: read as MPa" in m] == [
        f"{p}, column 'stress': no unit: read as MPa; another unit with units={{'stress': "
        "'kPa'} (command line: --units stress=kPa)"]
    np.testing.assert_allclose(c.stress, [0.0, 0.5, 1.5])
    for ok in ("strain,stress_MPa\n", "strain,stress [kPa]\n"):
        q = write(tmp_path, ok + "0,0\n0.1,0.5\n", "q.csv")
        assert not [m for m in _notes(q)[1] if "no unit" in m]
    [c], msgs = _notes(p, units={"stress": "kPa"})  # said: no note, read in kPa
    assert not [m for m in msgs if "no unit" in m or "overrides" in m], msgs
    np.testing.assert_allclose(c.stress, [0.0, 5e-4, 1.5e-3])


def test_units_overriding_a_stated_unit_is_said(tmp_path):
    p = write(tmp_path, "strain,stress_psi\n0,0\n0.1,100\n0.5,300\n")
    [c], msgs = _notes(p, units={"stress": "kPa"})
    [m] = [m for m in msgs if "overrides" in m]
    assert m == (f"{p}, column 'stress_psi': units={{'stress': 'kPa'}} (command line: "
                 "--units stress=kPa) overrides the unit 'psi' the header states: read as "
                 "kPa"), m
    np.testing.assert_allclose(c.stress, [0.0, 0.1, 0.3])  # the override is obeyed
    [c], msgs = _notes(p, units={"stress": "PSI"})  # the same unit: nothing to say
    assert not [m for m in msgs if "overrides" in m], msgs
    np.testing.assert_allclose(c.stress, np.array([0.0, 100, 300]) * 6.894757293168361e-3)


def test_a_stress_implausible_for_its_unit_is_said(tmp_path):
    p = write(tmp_path, "strain,stress_MPa\n0,0\n0.1,5000\n0.5,12000\n")
    [c], msgs = _notes(p)
    [m] = [m for m in msgs if "implausible" in m]
    assert "column 'stress_MPa': the stress reaches 12000 MPa as read, implausible for a " \
           "soft solid: check its unit" in m and "--units stress=Pa" in m, m
    np.testing.assert_allclose(c.stress, [0.0, 5000.0, 12000.0])
    q = write(tmp_path, "strain,stress_Pa\n0,0\n0.1,5000\n0.5,12000\n", "q.csv")
    [c], msgs = _notes(q)  # in Pa the same numbers are 0.012 MPa: plausible
    assert not [m for m in msgs if "implausible" in m], msgs
    r = write(tmp_path, "strain,stress_MPa\n0,0\n0.1,5000\n0.5,9999\n", "r.csv")
    assert not [m for m in _notes(r)[1] if "implausible" in m]  # below 1e4 MPa


def test_notes_do_not_change_the_data_read(tmp_path):
    """The same numbers give the same curve read with three notes firing (no units, a
    strain beyond 5, a stress beyond 1e4 MPa) and read under headers that state the
    units the notes assume."""
    text = "\n".join(f"{e:.3f},{s:.3f}" for e, s in zip(np.linspace(0, 60, 7),
                                                         np.linspace(0, 2e4, 7))) + "\n"
    noisy = write(tmp_path, "strain,stress\n" + text, "noisy.csv")
    quiet = write(tmp_path, "strain [-],stress_MPa\n" + text, "quiet.csv")
    [a], msgs = _notes(noisy)
    assert len([m for m in msgs if "is it in %" in m or "no unit" in m
                or "implausible" in m]) == 3, msgs
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        [b] = vhfit.read_csv(quiet, rate=0.1, n_points=None)
    np.testing.assert_array_equal(a.strain, b.strain)
    np.testing.assert_array_equal(a.stress, b.stress)
    assert a.strain_rate == b.strain_rate and a.measure == b.measure


def test_cli_prints_a_plausibility_note_as_one_warning_line(tmp_path, capsys):
    p = write(tmp_path, "strain,stress\n" + "".join(
        f"{e:.2f},{0.5 * e:.4f}\n" for e in np.linspace(0, 0.5, 12)))
    code = main(["fit", str(p), "--model", "neo_hooke", "--prony", "0", "--rate", "0.1",
                 "--no-plot", "--out", str(tmp_path / "out"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 0, err
    [line] = [ln for ln in err.splitlines() if "read as MPa" in ln]
    assert line.startswith("warning: ") and "--units stress=kPa" in line, err
