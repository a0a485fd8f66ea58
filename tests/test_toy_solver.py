"""A solver is one record: a toy solver registered here, and nowhere else, gets fitted for,
written, checked, exported and recognised by every part of vhfit.

The toy card is a plain text format of vhfit's own constants (``HYPER name C10 C01``,
``PRONY G tau`` lines, ``%`` comments). Its solver integrates the Prony series in the
``lsdyna_deviatoric`` formulation (one that no built-in solver uses), so that
``vhfit fit --for toy`` must fit in that formulation, and the card check must simulate
the card in it. The data are noise-free ramps of Mooney–Rivlin + 1 term in that
formulation: the fit reproduces them, and the card reproduces the fit to its digits.
"""

from __future__ import annotations

import dataclasses
import json

import pytest

import vhfit
from vhfit import cli
from vhfit.export import (
    FORMATS,
    Solver,
    export,
    get_solver,
    parse,
    register_solver,
    solvers,
    unregister_solver,
)
from vhfit.export.shift import SHIFT_TARGETS, wlf_constants, wlf_number
from vhfit.formulations import SOLVER_FORMULATIONS
from vhfit.tts import WLF

P = dict(C10=0.2, C01=0.1, G1=1.8, tau1=0.01)
FORM = "lsdyna_deviatoric"


def write_toy(model, params=None, *, name="VHFIT_MATERIAL", density=None, verbose=False,
              notes=(), comments=()) -> str:
    lines = [f"% toy card of {name}", *(f"% WARNING: {n}" for n in notes),
             *(f"% {c}" for c in comments)]
    if verbose:
        lines.append("% every constant in full")
    hyper = [k for k in model.param_names if not k.startswith(("G", "tau"))]
    lines.append("HYPER " + model.hyperelastic.name + " "
                 + " ".join(repr(float(params[k])) for k in hyper))
    for i in range(1, model.n_prony + 1):
        lines.append(f"PRONY {float(params[f'G{i}'])!r} {float(params[f'tau{i}'])!r}")
    if density is not None:
        lines.append(f"DENSITY {density!r}")
    return "\n".join(lines) + "\n"


def read_toy(text: str):
    rows = [ln.split() for ln in text.splitlines() if ln.strip() and not ln.startswith("%")]
    hyper = next(r for r in rows if r[0] == "HYPER")
    prony = [r for r in rows if r[0] == "PRONY"]
    model = vhfit.ViscoHyperelastic(hyper[1], len(prony))
    values = [float(v) for v in hyper[2:]] + [float(v) for r in prony for v in r[1:]]
    return model, model.as_dict(values)


def shift_toy(card: str, law, mat: int = 1) -> str:
    T, c1, c2 = wlf_constants(law)
    return card + f"SHIFT WLF {wlf_number(T)} {wlf_number(c1)} {wlf_number(c2)}\n"


TOY = Solver(name="toy", label="Toy", suffix=".toy", formulation=FORM, write=write_toy,
             read=read_toy, sniff=lambda body: body.startswith("HYPER "),
             laws=("neo_hooke", "mooney_rivlin", "arruda_boyce"), comment="%", aliases=("toy-fe",),
             shift=shift_toy, density=True, bulk_modulus=False,
             variants={"verbose": ("Toy (verbose)", "every constant in full")})


@pytest.fixture(scope="module")
def toy():
    register_solver(TOY)
    try:
        yield TOY
    finally:
        unregister_solver("toy")


@pytest.fixture(scope="module")
def data(tmp_path_factory, write_ramps) -> list[str]:
    model = vhfit.ViscoHyperelastic("mooney_rivlin", 1, formulation=FORM)
    return write_ramps(tmp_path_factory.mktemp("toy-data"), model, P)


@pytest.fixture(scope="module")
def toy_run(toy, data, tmp_path_factory):
    out = tmp_path_factory.mktemp("toy") / "o"
    argv = ["fit", *data, "--prony", "1", "--seed", "0", "--no-plot", "-q", "--out", str(out),
            "--for", "toy-fe", "--toy-verbose", "--density", "1e-9", "--poisson", "0.49"]
    assert cli.main(argv) == 0
    return out, json.loads((out / "results.json").read_text())


def test_fit_for_the_toy_solver_fits_in_its_formulation(toy_run):
    out, res = toy_run
    assert res["formulation"] == FORM
    assert res["card_fits"] == {"toy": FORM, "toy_verbose": FORM}
    assert res["cards"] == {"toy": "toy.toy", "toy_verbose": "toy_verbose.toy",
                            "json": "material.json"}
    assert res["rmsape"] < 1e-3


def test_the_toy_card_is_written_with_its_fields_and_read_back(toy_run):
    out, res = toy_run
    card = (out / "toy.toy").read_text()
    assert "DENSITY 1e-09" in card  # the record declares a density field ...
    assert "every constant in full" not in card  # ... the variant is its own file
    assert "every constant in full" in (out / "toy_verbose.toy").read_text()
    model, params = parse(card)  # recognised by the record's sniff
    assert model.hyperelastic.name == "mooney_rivlin"
    assert params == res["params"]
    assert "Toy integrates 'lsdyna_deviatoric'" in card  # the fit's comment, from the label


def test_the_toy_card_is_checked_in_its_solvers_formulation(toy_run, capsys):
    out, res = toy_run
    check = res["card_check"]["toy"]
    assert check["formulation"] == FORM and check["fit_formulation"] == FORM
    assert check["exceeds"] is False and check["rmsape"] <= check["allowed"]
    summary = (out / "summary.txt").read_text()
    assert "toy -> toy.toy" in summary
    assert cli.main(["check", str(out / "results.json")]) == 0
    table = capsys.readouterr().out
    assert "toy " in table and FORM in table and "EXCEEDS" not in table


def test_export_of_the_results_file_writes_the_toy_card(toy_run, tmp_path):
    out, res = toy_run
    dest = tmp_path / "again.toy"
    assert cli.main(["export", str(out / "results.json"), "--to", "toy", "--density", "1e-9",
                     "--out", str(dest)]) == 0
    assert read_toy(dest.read_text())[1] == res["params"]


def test_the_record_reaches_every_table(toy):
    assert "toy" in solvers() and get_solver("TOY-FE") is toy
    assert FORMATS["toy"] == ".toy" and SOLVER_FORMULATIONS["toy"] == FORM
    assert "toy" in SHIFT_TARGETS and "toy_verbose" in cli.CARD_FILES
    m = vhfit.ViscoHyperelastic("neo_hooke", 1)
    card = export(m, dict(C10=0.5, G1=2.0, tau1=0.1), to="toy",
                  shift=WLF(C1=8.86, C2=101.6, T_ref=25.0))
    assert card.endswith("SHIFT WLF 25.0 8.86 101.6\n")
    assert vhfit.export.supported_laws("toy") == ("neo_hooke", "mooney_rivlin", "arruda_boyce")
    refused = vhfit.ViscoHyperelastic("arruda_boyce", 0)
    with pytest.raises(ValueError, match="export it to .*Toy instead"):  # refusals name it
        export(refused, dict(mu=1.0, lambda_m=5.0), to="lsdyna")


def test_a_law_the_toy_lacks_is_refused_before_fitting(toy, data, tmp_path, capsys):
    out = tmp_path / "o"
    assert cli.main(["fit", *data, "--for", "toy", "--model", "yeoh", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "--for toy: Toy has no card for the hyperelastic law 'yeoh'" in err
    assert not out.exists() or not any(out.iterdir())


def test_registration_refuses_taken_names_and_unknown_formulations(toy):
    with pytest.raises(ValueError, match="taken"):
        register_solver(TOY)
    with pytest.raises(ValueError, match="taken"):
        register_solver(Solver(name="other", label="O", suffix=".o", formulation=FORM,
                               write=write_toy, read=read_toy, sniff=bool,
                               aliases=("toy-fe",)))
    with pytest.raises(ValueError, match="taken"):
        register_solver(Solver(name="json", label="J", suffix=".j", formulation=FORM,
                               write=write_toy, read=read_toy, sniff=bool))
    with pytest.raises(ValueError, match="not registered"):
        register_solver(Solver(name="other", label="O", suffix=".o", formulation="nope",
                               write=write_toy, read=read_toy, sniff=bool))
    with pytest.raises(ValueError, match="lower-case word"):
        register_solver(Solver(name="Other Solver", label="O", suffix=".o", formulation=FORM,
                               write=write_toy, read=read_toy, sniff=bool))
    assert "other" not in solvers()


def test_unregistering_removes_the_solver_everywhere():
    register_solver(dataclasses.replace(TOY, name="toy2", aliases=()))
    assert "toy2" in solvers() and "toy2" in SHIFT_TARGETS
    unregister_solver("toy2")
    assert "toy2" not in solvers() and "toy2" not in FORMATS
    assert "toy2" not in SOLVER_FORMULATIONS and "toy2" not in SHIFT_TARGETS
    assert "toy2" not in cli.CARD_FILES
    with pytest.raises(ValueError, match="unknown solver"):
        get_solver("toy2")
