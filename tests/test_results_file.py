"""The results file, written by ``Calibration.save`` and read by ``Calibration.load`` only.

Every command that takes a results file (``export``, ``simulate``, ``check``) works on the
loaded Calibration, so the model it uses is the fit's own: its law, number of terms,
formulation, accuracy and time–temperature shift. The round trip is checked for every
registered formulation, for a shifted (time–temperature) fit and for a multi-mode fit,
against the stresses of the calibration in memory (the fit itself), to 1e-12 relative.
Two regressions are pinned: ``vhfit export --to json`` and ``vhfit simulate --results`` of
a fit in the LS-DYNA formulation used to rebuild the model in the hereditary one.
"""

from __future__ import annotations

import argparse
import json
import warnings

import numpy as np
import pytest

import vhfit
from vhfit import cli, tts
from vhfit.cli._simulate import _material
from vhfit.export import from_abaqus, from_json
from vhfit.formulations import FORMULATIONS

P = dict(C10=0.2, C01=0.1, G1=1.8, tau1=0.01)
RATES = (-1.0, -30.0, -1000.0)


def ramps(formulation: str = "hereditary", deformation: str = "uniaxial") -> list:
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1, formulation=formulation)
    eps = np.linspace(0.0, -0.4 if deformation == "uniaxial" else 0.4, 15)
    rates = RATES if deformation == "uniaxial" else tuple(-r for r in RATES[:2])
    return [vhfit.Curve(strain=eps, stress=m.stress(P, strain=eps, strain_rate=r,
                                                     measure="engineering",
                                                     deformation=deformation),
                        strain_rate=r, measure="engineering", deformation=deformation,
                        name=f"{deformation} {r:g}") for r in rates]


def fit(curves, **kw) -> vhfit.Calibration:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return vhfit.calibrate(curves, n_prony=kw.pop("n_prony", 1), seed=0, maxiter=8,
                               popsize=12, **kw)


def shifted_fit() -> tuple[vhfit.Calibration, list]:
    """Sweeps at two temperatures and ramps at a third, WLF shift known."""
    law = tts.WLF(C1=8.86, C2=101.6, T_ref=20.0)
    f = np.logspace(-1, 2, 9)
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    items = []
    for T in (0.0, 40.0):
        w = 2 * np.pi * f * 10 ** law.log_aT(T)
        E_inf = 6 * (P["C10"] + P["C01"])
        wt = w * P["tau1"]
        items.append(vhfit.FrequencySweep(
            frequency=f, storage=E_inf + P["G1"] * wt**2 / (1 + wt**2),
            loss=P["G1"] * wt / (1 + wt**2), temperature=T, name=f"dma {T:g}"))
    eps = np.linspace(0.0, -0.3, 11)
    for r in (-1.0, -100.0):
        s = m.stress(P, strain=eps, strain_rate=r * 10 ** law.log_aT(30.0), measure="engineering")
        items.append(vhfit.Curve(strain=eps, stress=s, strain_rate=r, measure="engineering",
                                 metadata={"temperature": 30.0}, name=f"rate {r:g}"))
    cal = fit(items, shift_factors=law, T_ref=20.0)
    assert cal.shift is not None and len(cal.shift_table) == 3
    return cal, tts.shift_to_reference(items, shift_factors=law, T_ref=20.0).items


def stress_of(model, params, curves) -> np.ndarray:
    return model.batch(list(curves))(model.as_array(params)[None, :])[0]


def same(a, b, rtol: float = 1e-12) -> bool:
    return bool(np.all(np.abs(a - b) <= rtol * np.abs(b)))


# ============================================================ the round trip
CASES = [*(("formulation", f) for f in FORMULATIONS), ("shifted", None), ("multimode", None)]


@pytest.fixture(scope="module", params=CASES, ids=lambda c: c[1] or c[0])
def saved(request, tmp_path_factory):
    kind, form = request.param
    if kind == "formulation":
        curves = ramps(form)
        cal = fit(curves, formulation=form)
    elif kind == "shifted":
        cal, curves = shifted_fit()
    else:
        curves = ramps("hereditary") + ramps("hereditary", "equibiaxial")
        cal = fit(curves, n_prony=2, rtol=1e-7)  # and an accuracy other than the default
    path = tmp_path_factory.mktemp("results") / "results.json"
    cal.save(path, curves=curves)
    return cal, curves, path


def test_load_of_save_is_the_same_model_and_stresses(saved):
    cal, curves, path = saved
    back = vhfit.Calibration.load(path)
    assert repr(back.model) == repr(cal.model)
    assert back.model.formulation == cal.model.formulation
    assert back.model.rtol == cal.model.rtol
    assert back.params == cal.params
    assert same(stress_of(back.model, back.params, curves),
                stress_of(cal.model, cal.params, curves))
    assert back.shift_source == cal.shift_source and back.T_ref == cal.T_ref
    assert back.shift_table == cal.shift_table
    assert (None if cal.shift is None else cal.shift.constants()) == (
        None if back.shift is None else back.shift.constants())


def test_export_from_the_results_file_reproduces_the_fit(saved, tmp_path):
    cal, curves, path = saved
    fitted = stress_of(cal.model, cal.params, curves)
    out = tmp_path / "m.json"
    assert cli.main(["export", str(path), "--to", "json", "--out", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["formulation"] == cal.model.formulation
    assert doc.get("rtol", 1e-6) == cal.model.rtol
    model, params = from_json(out.read_text())
    assert same(stress_of(model, params, curves), fitted)
    card = tmp_path / "a.inp"
    assert cli.main(["export", str(path), "--to", "abaqus", "--out", str(card)]) == 0
    model, params = from_abaqus(card.read_text())
    # the card holds no formulation (nor the integral's accuracy): the fit's own
    model = vhfit.ViscoHyperelastic(model.hyperelastic.name, model.n_prony,
                                    rtol=cal.model.rtol, formulation=cal.model.formulation)
    assert same(stress_of(model, params, curves), fitted, 1e-12)
    if cal.shift is not None:
        assert "*TRS" in card.read_text()


def test_simulate_from_the_results_file_reproduces_the_fit(saved, tmp_path):
    cal, curves, path = saved
    ns = argparse.Namespace(results=str(path), model=None, param=None)
    model, params, _ = _material(ns)
    assert repr(model) == repr(cal.model)
    assert same(stress_of(model, params, curves), stress_of(cal.model, cal.params, curves))
    # the command itself, to the 9 digits it prints
    out = tmp_path / "s.csv"
    assert cli.main(["simulate", "--results", str(path), "--rate", "-100", "--strain-max",
                     "-0.3", "--points", "7", "--measure", "true", "--out", str(out)]) == 0
    rows = np.loadtxt(out, delimiter=",", comments="#", skiprows=6, usecols=(2, 3, 4))
    want = cal.model.stress(cal.params, strain=rows[:, 1], strain_rate=-100.0,
                            measure="true")
    assert np.allclose(rows[:, 2], want, rtol=5e-9, atol=1e-12)


# ============================================================ the two regressions
@pytest.fixture(scope="module")
def lsdyna_run(tmp_path_factory) -> tuple:
    folder = tmp_path_factory.mktemp("dyna")
    paths = []
    for c in ramps("lsdyna"):
        p = folder / f"r{-c.strain_rate:g}.csv"
        p.write_text(f"# strain_rate: {c.strain_rate}\nstrain,stress_MPa\n"
                     + "".join(f"{float(e)!r},{float(s)!r}\n"
                               for e, s in zip(c.strain, c.stress)))
        paths.append(str(p))
    out = folder / "o"
    assert cli.main(["fit", *paths, "--prony", "1", "--for", "lsdyna", "--maxiter", "10",
                     "--popsize", "12", "--no-plot", "-q", "--out", str(out)]) == 0
    return out, vhfit.Calibration.load(out / "results.json")


def test_export_to_json_of_an_lsdyna_fit_says_lsdyna(lsdyna_run, tmp_path):
    out, cal = lsdyna_run
    assert cal.model.formulation == "lsdyna"
    dest = tmp_path / "m.json"
    assert cli.main(["export", str(out / "results.json"), "--to", "json", "--out",
                     str(dest)]) == 0
    assert json.loads(dest.read_text())["formulation"] == "lsdyna"


def test_simulate_of_an_lsdyna_fit_uses_the_lsdyna_law(lsdyna_run, tmp_path):
    out, cal = lsdyna_run
    dest = tmp_path / "s.csv"
    assert cli.main(["simulate", "--results", str(out / "results.json"), "--rate", "-1000",
                     "--strain-max", "-0.4", "--points", "9", "--measure", "true", "--out",
                     str(dest)]) == 0
    rows = np.loadtxt(dest, delimiter=",", comments="#", skiprows=6, usecols=(3, 4))
    kw = dict(strain=rows[:, 0], strain_rate=-1000.0, measure="true")
    dyna = cal.model.stress(cal.params, **kw)
    here = vhfit.ViscoHyperelastic("mooney_rivlin", cal.n_prony).stress(cal.params, **kw)
    assert np.allclose(rows[:, 1], dyna, rtol=5e-9, atol=1e-12)
    assert np.max(np.abs(dyna - here)[1:] / np.abs(here[1:])) > 1e-3  # the laws differ here


# ============================================================ bad results files
def _bad_files(good: dict) -> dict[str, tuple[str, str]]:
    text = json.dumps(good)
    other = dict(good, format="vhfit-results-99")
    unknown = dict(good, formulation="maxwell_mystery")
    return {"truncated": (text[: len(text) // 2], "not valid JSON"),
            "other version": (json.dumps(other), "another version"),
            "unknown formulation": (json.dumps(unknown), "maxwell_mystery"),
            "terms mismatch": (json.dumps(dict(good, n_prony=3)), "n_prony = 3")}


@pytest.fixture(scope="module")
def good(tmp_path_factory) -> dict:
    path = tmp_path_factory.mktemp("good") / "results.json"
    fit(ramps()).save(path)
    return json.loads(path.read_text())


@pytest.mark.parametrize("case", ["truncated", "other version", "unknown formulation",
                                  "terms mismatch"])
def test_a_bad_results_file_is_a_clear_error(case, good, tmp_path):
    text, needle = _bad_files(good)[case]
    path = tmp_path / "results.json"
    path.write_text(text)
    with pytest.raises(ValueError, match=needle) as err:
        vhfit.Calibration.load(path)
    assert str(path) in str(err.value) and "\n" not in str(err.value)


@pytest.mark.parametrize("case", ["truncated", "other version", "unknown formulation"])
@pytest.mark.parametrize("command", [["export", "{p}", "--to", "json", "--out", "{o}"],
                                     ["simulate", "--results", "{p}", "--rate", "-1",
                                      "--out", "{o}"],
                                     ["check", "{p}"]])
def test_a_bad_results_file_is_one_line_and_exit_2(case, command, good, tmp_path, capsys):
    text, needle = _bad_files(good)[case]
    path, out = tmp_path / "results.json", tmp_path / "out.txt"
    path.write_text(text)
    argv = [a.format(p=path, o=out) for a in command]
    assert cli.main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and needle in err and "Traceback" not in err
    assert not out.exists()
