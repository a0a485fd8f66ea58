"""A calibration's settings: one frozen, checked object, recorded in its results file.

``calibrate``'s keywords build a :class:`CalibrationSettings` (checked there, once); the
result carries it, cannot be changed afterwards, and ``save``/``load`` keep it.
"""

from __future__ import annotations

import dataclasses
import inspect
import json

import numpy as np
import pytest

import vhfit
from vhfit import CalibrationSettings
from vhfit.calibration import RecordedCallable
from vhfit.tts import WLF

TRUE = dict(C10=0.02, G1=0.5, tau1=0.01)


def curves():
    m = vhfit.ViscoHyperelastic("neo_hooke", 1)
    eps = np.linspace(-0.05, -0.4, 8)
    return [vhfit.Curve(strain=eps, stress=m.stress(TRUE, strain=eps, strain_rate=r,
                                                    measure="engineering"), strain_rate=r)
            for r in (-1.0, -100.0)]


def quick(**kw):
    return vhfit.calibrate(curves(), "neo_hooke", n_prony=1, seed=0, uncertainty=False,
                           maxiter=30, **kw)


def test_fields_are_calibrates_keywords_with_the_same_defaults():
    params = list(inspect.signature(vhfit.calibrate).parameters.values())[1:]
    fields = dataclasses.fields(CalibrationSettings)
    assert [p.name for p in params] == [f.name for f in fields]
    assert [p.default for p in params] == [f.default for f in fields]


def test_the_result_carries_the_settings_it_was_made_with():
    cal = quick(stall=(0.01, 50))
    assert cal.settings == CalibrationSettings("neo_hooke", 1, seed=0, uncertainty=False,
                                               maxiter=30, stall=(0.01, 50))
    assert cal.settings.keywords()["stall"] == (0.01, 50)


def test_bad_settings_are_the_same_one_line_errors_as_calibrates():
    for kw, msg in ((dict(popsize=3), "popsize = 3: give a whole number >= 5 or None"),
                    (dict(resume=True), "resume = True: resuming needs checkpoint=PATH"),
                    (dict(g_inf_min=1.0), "g_inf_min = 1.0: give a finite number >= 0 and < 1")):
        with pytest.raises(ValueError) as direct:
            CalibrationSettings(**kw)
        with pytest.raises(ValueError) as via:
            vhfit.calibrate(curves(), **kw)
        assert str(direct.value) == str(via.value)
        assert str(direct.value).startswith(msg)


def test_settings_and_result_are_frozen():
    s = CalibrationSettings()
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.seed = 1
    cal = quick()
    with pytest.raises(dataclasses.FrozenInstanceError):
        cal.rmsape = 0.0
    other = dataclasses.replace(cal, stop_reason="by hand")
    assert str(other.stop_reason) == "by hand" and str(cal.stop_reason) != "by hand"
    with pytest.raises(ValueError, match="^popsize = 4: "):  # replace checks again
        dataclasses.replace(s, popsize=4)


def test_full_method_default_tol_is_the_papers():
    # the paper's best-mean gap, 0.001 %, unless the user gives tol
    assert CalibrationSettings(method="full").effective_tol == 1e-5
    assert CalibrationSettings(method="full", tol=1e-3).effective_tol == 1e-3
    assert CalibrationSettings().effective_tol == 1e-6


def my_objective(stress, target):
    return 0.0


def test_record_round_trip_of_every_kind_of_value(tmp_path):
    s = CalibrationSettings(
        "mooney_rivlin", "auto", bounds={"C10": (0.0, 1.0)}, objective=my_objective,
        stall=[0.01, 40], stability_range=(0.5, 2.0), de_options={"strategy": "rand1bin"},
        checkpoint=tmp_path / "ck.json", shift_factors=WLF(17.4, 51.6, 20.0), T_ref=20.0)
    d = json.loads(json.dumps(s.to_dict()))  # JSON through and through
    assert d["objective"] == {"callable": f"{__name__}.my_objective"}
    assert d["shift_factors"] == {"law": "wlf",
                                  "constants": {"C1": 17.4, "C2": 51.6, "T_ref": 20.0}}
    assert d["checkpoint"] == str(tmp_path / "ck.json") and d["stall"] == [0.01, 40]
    back = CalibrationSettings.from_dict(d)
    assert back.objective == RecordedCallable(f"{__name__}.my_objective")
    with pytest.raises(TypeError, match="recorded by name only"):
        back.objective(None, None)
    assert back.shift_factors == WLF(17.4, 51.6, 20.0)
    assert back.bounds == {"C10": (0.0, 1.0)} and back.stall == (0.01, 40)
    assert back.stability_range == (0.5, 2.0) and back.n_prony == "auto"
    assert CalibrationSettings.from_dict(back.to_dict()) == back
    for given in ({20.0: 0.0, 40.0: -1.5}, ([20.0, 40.0], [0.0, -1.5])):
        t = CalibrationSettings(shift_factors=given)
        assert CalibrationSettings.from_dict(json.loads(json.dumps(t.to_dict()))
                                             ).shift_factors == (given if isinstance(given, dict)
                                                                 else tuple(given))


def test_results_file_says_how_it_was_made(tmp_path):
    cal = quick(target=1e-3)
    path = tmp_path / "results.json"
    cal.save(path)
    rec = json.loads(path.read_text())["settings"]
    assert rec["hyperelastic"] == "neo_hooke" and rec["n_prony"] == 1 and rec["seed"] == 0
    assert rec["target"] == 1e-3 and rec["maxiter"] == 30 and rec["uncertainty"] is False
    back = vhfit.Calibration.load(path)
    assert back.settings == cal.settings
    assert back.fits[back.model.formulation] is back


def test_results_file_without_settings_still_loads(tmp_path):
    cal = quick()
    path = tmp_path / "results.json"
    cal.save(path)
    res = json.loads(path.read_text())
    del res["settings"]
    path.write_text(json.dumps(res))
    back = vhfit.Calibration.load(path)
    assert back.settings is None and back.params == cal.params


def test_a_bad_settings_entry_is_a_one_line_error(tmp_path):
    cal = quick()
    path = tmp_path / "results.json"
    cal.save(path)
    res = json.loads(path.read_text())
    res["settings"]["popsize"] = 2
    path.write_text(json.dumps(res))
    with pytest.raises(ValueError, match=r"results.json: popsize = 2: .*give the results.json"):
        vhfit.Calibration.load(path)


def test_cli_records_its_options_as_settings(tmp_path):
    from vhfit.cli._parser import build_parser

    files = []
    for i, c in enumerate(curves()):
        p = tmp_path / f"r{i}.csv"
        rows = "\n".join(f"{e!r},{s!r}" for e, s in zip(c.strain.tolist(), c.stress.tolist()))
        p.write_text(f"# strain_rate: {c.strain_rate!r}\nstrain,stress_MPa\n{rows}\n")
        files.append(str(p))
    out = tmp_path / "out"
    argv = ["fit", *files, "--model", "neo_hooke", "--prony", "1", "--seed", "3",
            "--maxiter", "20", "--no-plot", "--quiet", "--out", str(out)]
    args = build_parser().parse_args(argv)
    assert args.func(args, argv) == 0
    # the options stay as parsed: the run keeps its own values out of the namespace
    assert not [k for k in vars(args) if k.startswith("_")]
    res = json.loads((out / "results.json").read_text())
    rec = res["settings"]
    assert (rec["hyperelastic"], rec["n_prony"], rec["seed"], rec["maxiter"]) == (
        "neo_hooke", 1, 3, 20)
    assert rec["checkpoint"] == str(out / "checkpoint.json")
    assert set(rec["callback"]) == {"callable"}
    assert res["command"] == ["vhfit", *argv]
    assert vhfit.Calibration.load(out / "results.json").settings.seed == 3
