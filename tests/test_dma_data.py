"""Frequency sweeps and relaxation tests as data (vhfit.FrequencySweep, vhfit.Relaxation,
read_csv of moduli files) and the small-strain responses of vhfit.viscoelastic
(docs/data.md, docs/theory.md §3 and §10)."""

from __future__ import annotations

import io

import numpy as np
import pytest
from _budget import accuracy
from hypothesis import given
from hypothesis import strategies as st

import vhfit
from vhfit.viscoelastic import loss_modulus, relaxation_modulus, storage_modulus


# ------------------------------------------------------------ linear responses
def maxwell_reference(omega, E_inf, G, tau):
    """E*(ω) = E∞ + Σ G_i iωτ_i / (1 + iωτ_i): each Maxwell branch's complex modulus."""
    w = np.asarray(omega, dtype=np.float64)[:, None]
    Es = E_inf + np.sum(np.asarray(G) * (1j * w * tau) / (1.0 + 1j * w * tau), axis=1)
    return Es.real, Es.imag


prony = st.lists(st.tuples(st.floats(1e-3, 1e3), st.floats(-6.0, 6.0)), min_size=1,
                 max_size=6)


@accuracy
@given(st.floats(1e-3, 1e3), prony, st.lists(st.floats(-8.0, 8.0), min_size=1, max_size=8))
def test_storage_and_loss_match_the_complex_modulus(E_inf, terms, log_omega):
    G = np.array([g for g, _ in terms])
    tau = 10.0 ** np.array([lt for _, lt in terms])
    omega = 10.0 ** np.array(log_omega)
    re, im = maxwell_reference(omega, E_inf, G, tau)
    np.testing.assert_allclose(storage_modulus(omega, E_inf, G, tau), re, rtol=1e-12)
    np.testing.assert_allclose(loss_modulus(omega, E_inf, G, tau), im, rtol=1e-12)


def test_limits_and_extremes_of_the_responses():
    """ω → 0: E′ → E∞, E″ → 0; ω → ∞: E′ → E∞ + ΣG; E″ peaks at ωτ = 1 with G/2; no
    overflow for ωτ from 1e-200 to 1e200; E(0) = E∞ + ΣG."""
    G, tau = [2.0, 3.0], [1e-3, 10.0]
    assert storage_modulus(1e-200, 1.0, G, tau) == pytest.approx(1.0, rel=1e-15)
    assert loss_modulus(1e-200, 1.0, G, tau) == pytest.approx(0.0, abs=1e-190)
    assert storage_modulus(1e200, 1.0, G, tau) == pytest.approx(6.0, rel=1e-15)
    assert loss_modulus(1e200, 1.0, G, tau) == pytest.approx(0.0, abs=1e-190)
    assert loss_modulus(1.0, 0.0, [4.0], [1.0]) == pytest.approx(2.0, rel=1e-15)
    assert relaxation_modulus(0.0, 1.0, G, tau) == pytest.approx(6.0, rel=1e-15)
    assert relaxation_modulus(np.inf, 1.0, G, tau) == pytest.approx(1.0, rel=1e-15)


def test_responses_reject_bad_frequencies():
    with pytest.raises(ValueError, match="omega = 0.0"):
        storage_modulus([1.0, 0.0], 1.0, [1.0], [1.0])
    with pytest.raises(ValueError, match="omega = -1.0"):
        loss_modulus(-1.0, 1.0, [1.0], [1.0])


# ------------------------------------------------------------------ the items
def test_sweep_from_storage_and_loss_keeps_e_type_moduli_in_mpa():
    f = np.array([0.1, 1.0, 10.0])
    s = vhfit.FrequencySweep(frequency=f, storage=[2.0, 3.0, 4.0], loss=[0.5, 0.4, 0.0],
                             kind="G", unit="kPa", temperature=25, name="dma")
    np.testing.assert_array_equal(s.frequency, f)
    np.testing.assert_allclose(s.omega, 2 * np.pi * f, rtol=1e-15)
    np.testing.assert_allclose(s.storage, [6e-3, 9e-3, 12e-3], rtol=1e-15)  # 3G, kPa -> MPa
    np.testing.assert_allclose(s.loss, [1.5e-3, 1.2e-3, 0.0], rtol=1e-15)
    assert (s.kind, s.temperature, s.name, s.n_points) == ("G", 25.0, "dma", 6)
    np.testing.assert_allclose(s.target_stress, [6e-3, 9e-3, 12e-3, 1.5e-3, 1.2e-3, 0.0])
    # relative error per point; a zero loss point is scaled by the mean |E″|
    np.testing.assert_allclose(s.target_scale, [6e-3, 9e-3, 12e-3, 1.5e-3, 1.2e-3, 0.9e-3])


def test_sweep_from_modulus_and_tan_delta_and_from_omega():
    """|E*| = 5, tan δ = 3/4: E′ = 4, E″ = 3; storage + tan δ: E″ = E′ tan δ."""
    s = vhfit.FrequencySweep(omega=[2.0], modulus=[5.0], tan_delta=[0.75])
    assert s.storage[0] == pytest.approx(4.0, rel=1e-15)
    assert s.loss[0] == pytest.approx(3.0, rel=1e-15)
    assert s.frequency[0] == pytest.approx(1.0 / np.pi, rel=1e-15)
    assert s.modulus[0] == pytest.approx(5.0, rel=1e-15)
    assert s.tan_delta[0] == pytest.approx(0.75, rel=1e-15)
    t = vhfit.FrequencySweep(frequency=[1.0], storage=[4.0], tan_delta=[0.5])
    assert t.loss[0] == pytest.approx(2.0, rel=1e-15)


def test_shifted_items_are_at_the_reference_temperature():
    s = vhfit.FrequencySweep(frequency=[0.1, 1.0], storage=[1.0, 2.0], loss=[0.1, 0.2],
                             kind="G", temperature=40.0)
    r = vhfit.Relaxation(time=[0.0, 2.0, 8.0], modulus=[3.0, 2.0, 1.0], temperature=-10.0)
    s2, r2 = s.shifted(1e-3), r.shifted(4.0)
    np.testing.assert_allclose(s2.frequency, [1e-4, 1e-3], rtol=1e-15)
    np.testing.assert_allclose(s2.omega, 2 * np.pi * np.array([1e-4, 1e-3]), rtol=1e-15)
    np.testing.assert_array_equal(s2.storage, s.storage)  # 3 G, not 9 G
    assert (s2.temperature, s2.kind) == (None, "G")
    np.testing.assert_allclose(r2.time, [0.0, 0.5, 2.0], rtol=1e-15)
    assert r2.temperature is None
    with pytest.raises(vhfit.DataError, match="a_T"):
        s.shifted(0.0)


@pytest.mark.parametrize("kwargs, match", [
    (dict(frequency=[0.0, 1.0], storage=[1, 2], loss=[0, 0]), r"frequency\[0\]: frequency 0 <= 0"),
    (dict(frequency=[-1.0, 1.0], storage=[1, 2], loss=[0, 0]), "frequency -1 <= 0"),
    (dict(omega=[1.0, 2.0], storage=[1, 2], loss=[0.1, -0.2]), r"loss\[1\]: loss modulus -0.2 < 0"),
    (dict(frequency=[1.0], tan_delta=[0.1]), "tan delta needs the storage modulus"),
    (dict(frequency=[1.0, 2.0], storage=[1.0], loss=[0.1, 0.2]), "1 values for 2 points"),
    (dict(frequency=[1.0, np.nan], storage=[1, 2], loss=[0, 0]), "nan is not a finite number"),
    (dict(frequency=[1.0], storage=[0.0], loss=[0.0]), "storage modulus 0 <= 0"),
    (dict(frequency=[1.0], storage=[1.0]), "loss= .or tan_delta=. beside it"),
    (dict(storage=[1.0], loss=[1.0]), "give frequency= .Hz. or omega="),
    (dict(frequency=[1.0], storage=[1.0], loss=[1.0], kind="K"), "kind='K'"),
    (dict(frequency=[1.0], modulus=[1.0], loss=[1.0]), "with modulus= .*tan_delta="),
])
def test_bad_sweeps_get_one_line_errors(kwargs, match):
    with pytest.raises(vhfit.DataError, match=match) as e:
        vhfit.FrequencySweep(**kwargs)
    assert "\n" not in str(e.value)


def test_bad_relaxation_tests_get_one_line_errors():
    with pytest.raises(vhfit.DataError, match=r"time\[1\]: time -1 < 0"):
        vhfit.Relaxation(time=[0.0, -1.0], modulus=[2.0, 1.0])
    with pytest.raises(vhfit.DataError, match=r"modulus\[0\]: relaxation modulus -2 <= 0"):
        vhfit.Relaxation(time=[0.0, 1.0], modulus=[-2.0, 1.0])
    r = vhfit.Relaxation(time=[0.0, 1.0], modulus=[2.0, 1.0], kind="g", unit="GPa")
    np.testing.assert_allclose(r.modulus, [6e3, 3e3])
    assert r.kind == "G"


# ------------------------------------------------------------------ CSV files
def test_read_csv_gives_one_sweep_per_temperature(tmp_path):
    p = tmp_path / "dma.csv"
    p.write_text("Temperature [°C],Frequency [Hz],G' [kPa],G'' [kPa],strain_amplitude\n"
                 "20,0.1,2000,500,0.001\n20,1,3000,400,0.001\n"
                 "40,0.1,1000,300,0.001\n40,1,1500,200,0.001\n")
    a, b = vhfit.read_csv(p)
    assert isinstance(a, vhfit.FrequencySweep) and (a.temperature, b.temperature) == (20, 40)
    assert a.kind == "G" and a.name == "dma [T = 20]"
    np.testing.assert_allclose(a.storage, [6.0, 9.0])       # 3 G in MPa
    np.testing.assert_allclose(b.loss, [0.9, 0.6])
    np.testing.assert_allclose(b.frequency, [0.1, 1.0])


def test_read_csv_recognises_rad_per_s_modulus_tan_delta_and_relaxation():
    sweep = "omega [rad/s],|E*| (Pa),tan δ\n1,5e6,0.75\n10,1e7,0\n"
    [s] = vhfit.read_csv(io.StringIO(sweep))
    np.testing.assert_allclose(s.omega, [1.0, 10.0])
    np.testing.assert_allclose(s.storage, [4.0, 10.0])
    np.testing.assert_allclose(s.loss, [3.0, 0.0], atol=1e-15)
    relax = "# temperature: 60\ntime_ms,E(t) [MPa]\n0,5\n1000,3\n"
    [r] = vhfit.read_csv(io.StringIO(relax))
    assert isinstance(r, vhfit.Relaxation) and r.kind == "E" and r.temperature == 60.0
    np.testing.assert_allclose(r.time, [0.0, 1.0])
    np.testing.assert_allclose(r.modulus, [5.0, 3.0])


@pytest.mark.parametrize("text, match", [
    ("f_Hz,storage_MPa,loss_MPa\n0.1,2,0.5\n0,3,0.4\n",
     r"dma.csv, line 3, column 'f_Hz'\): frequency 0 <= 0"),
    ("f_Hz,storage_MPa,loss_MPa\n0.1,2,0.5\n1,3,-0.4\n",
     r"dma.csv, line 3, column 'loss_MPa'\): loss modulus -0.4 < 0"),
    ("frequency_Hz,tan_delta\n0.1,0.5\n1,0.4\n",
     r"dma.csv, column 'tan_delta'\): tan delta needs the storage modulus"),
    ("frequency_furlongs,storage_MPa,loss_MPa\n0.1,2,0.5\n",
     r"dma.csv, column 'frequency_furlongs': unit 'furlongs' is not understood"),
])
def test_bad_moduli_files_name_the_file_line_and_column(tmp_path, text, match):
    p = tmp_path / "dma.csv"
    p.write_text(text)
    with pytest.raises(vhfit.DataError, match=match) as e:
        vhfit.read_csv(p)
    assert "\n" not in str(e.value)


def test_curves_from_arrays_reads_a_mapping_of_moduli():
    [s] = vhfit.data.curves_from_arrays({"frequency_Hz": [0.1, 1.0], "storage_MPa": [1.0, 2.0],
                                         "loss_MPa": [0.1, 0.2]}, name="m")
    assert isinstance(s, vhfit.FrequencySweep) and s.name == "m"
    np.testing.assert_allclose(s.loss, [0.1, 0.2])
    with pytest.raises(vhfit.DataError, match="column 'loss_MPa'.*loss modulus -0.2 < 0"):
        vhfit.data.curves_from_arrays({"frequency_Hz": [0.1, 1.0], "storage_MPa": [1.0, 2.0],
                                       "loss_MPa": [0.1, -0.2]})


def test_metadata_lines_units_and_columns_of_moduli_files():
    """'# kind: G' makes unmarked moduli shear moduli; units= and columns= apply."""
    text = "# kind: G\n# name: rubber\nT_C,freq,Storage,Loss\n20,1,1,0.1\n20,2,2,0.2\n"
    [s] = vhfit.read_csv(io.StringIO(text), units={"modulus": "kPa"})
    assert (s.name, s.kind, s.temperature) == ("rubber [T = 20]", "G", 20.0)
    np.testing.assert_allclose(s.storage, [3e-3, 6e-3])
    text = "a,b,c\n1,1,0.1\n2,2,0.2\n"
    [s] = vhfit.read_csv(io.StringIO(text), columns={"frequency": "a", "storage": "b",
                                                     "loss": "c"})
    np.testing.assert_allclose(s.loss, [0.1, 0.2])
