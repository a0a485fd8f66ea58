"""Degenerate fits are flagged: terms the data cannot tell apart, constants that are
effectively zero, intervals wider than their value (docs/reliability.md).

Every case is built so that the answer is known: data made by a law with fewer terms
than the one fitted, data without a relaxation the fit has room for, or constructed
parameter vectors, intervals and covariances; the negative cases are well-posed fits of
the law and N that made the data.
"""

from __future__ import annotations

import json
import time
import warnings

import numpy as np
import pytest

import vhfit
from vhfit.calibration import CalibrationSettings
from vhfit.calibration._report import (
    CORRELATION_TOL,
    NEGLIGIBLE,
    covariance,
    degenerate_warnings,
    finish,
)
from vhfit.calibration._result import Calibration
from vhfit.calibration._search import Search
from vhfit.calibration._space import Problem

EPS = np.linspace(-0.05, -0.5, 10)
THREE = (-1.0, -10.0, -100.0)
FOUR = (-1.0, -10.0, -100.0, -1000.0)
MR2_TRUE = dict(C10=0.2, C01=0.1, G1=1.0, tau1=1e-3, G2=2.0, tau2=1e-1)
OGDEN1_TRUE = dict(mu1=0.3, alpha1=2.5, G1=1.0, tau1=1e-2)


def ramps(law, params, rates, noise=0.0, seed=0):
    n = sum(1 for k in params if k.startswith("tau"))
    m = vhfit.ViscoHyperelastic(law, n)
    rng = np.random.default_rng(seed)
    out = []
    for r in rates:
        s = m.stress(params, strain=EPS, strain_rate=r, measure="engineering")
        out.append(vhfit.Curve(strain=EPS, stress=s * (1 + noise * rng.standard_normal(s.size)),
                               strain_rate=r, measure="engineering", name=f"rate {r:g}"))
    return out


def fit(curves, law, n, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return vhfit.calibrate(curves, law, n_prony=n, **kw)


def report(law, x, curves, uncertainty=True):
    """The report of a fit at exactly ``x`` (no search): finish() as calibrate calls it."""
    n = (len(x) - vhfit.hyperelastic.get(law).n_params) // 2
    model = vhfit.ViscoHyperelastic(law, n)
    prob = Problem(model, curves, np.array([[-6.0, 3.0]] * n), {}, 0.0)
    x = np.array(x, dtype=float)
    err = float(prob.errors(x[None, :])[0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        found = Search(x, 1, 1, "maxiter", {"nit": [], "best": [], "mean": [], "time": []},
                       time.perf_counter())
        return finish(prob, curves, model, x, err, found, 1,
                      CalibrationSettings(law, prune_tol=0.0, uncertainty=uncertainty), {})


def degenerate(cal):
    """The degeneracy sentences of a result (each is a headline)."""
    keys = ("cannot be told apart", "effectively zero", "not determined by the data")
    return [h for h in cal.headlines if any(k in h for k in keys)]


def head(cal):
    """The summary's lines before the table of constants."""
    lines = cal.summary().splitlines()
    return lines[: lines.index(next(ln for ln in lines if ln.startswith("parameter")))]


# ---------------------------------------------------------- positive cases


def merged(cal):
    """The merge sentences of a result (each is a headline)."""
    return [h for h in cal.headlines if "act as one" in h and "merged into" in h]


def test_ogden2_on_one_term_data_is_merged_into_one_term(tmp_path):
    # the data hold ONE Ogden term: an ogden2 fit that reproduces them puts its two terms
    # at one exponent or leaves one empty; either way the result is the one-term law
    curves = ramps("ogden", OGDEN1_TRUE, THREE)
    cal = fit(curves, "ogden2", 1, seed=0)
    assert cal.rmsape < 1e-3  # it reproduces the one-term data
    assert cal.model.hyperelastic.name == "ogden"
    # the data determine mu and alpha of the one term: the fit's error bounds their error
    assert cal.params["mu1"] == pytest.approx(OGDEN1_TRUE["mu1"], rel=1e-3)
    assert cal.params["alpha1"] == pytest.approx(OGDEN1_TRUE["alpha1"], rel=1e-3)
    msgs = merged(cal)
    assert len(msgs) == 1 and "merged into ogden" in msgs[0], cal.headlines
    assert not [m for m in degenerate(cal) if "cannot be told apart" in m]
    # first lines of the summary, before the constants
    assert f"WARNING: {msgs[0]}" in head(cal)
    # and in results.json "warnings", read back by Calibration.load
    cal.save(tmp_path / "results.json")
    res = json.loads((tmp_path / "results.json").read_text())
    assert res["hyperelastic"] == "ogden"
    assert msgs[0] in res["warnings"] and msgs[0] in res["headlines"]
    back = Calibration.load(tmp_path / "results.json")
    assert back.headlines == cal.headlines and back.params == cal.params


def test_two_ogden_terms_at_one_exponent_are_merged_with_the_sum_of_their_moduli():
    # alpha1 = alpha2 exactly: mu1 and mu2 act as one term with mu = mu1 + mu2, the same
    # stresses (to rounding), so the constants are merged as they are, not refitted
    curves = ramps("ogden", OGDEN1_TRUE, THREE, noise=0.01, seed=3)
    x = [0.2, 2.5, 0.1, 2.5, 1.0, 1e-2]
    cal = report("ogden2", x, curves)
    assert cal.model.hyperelastic.name == "ogden"
    assert cal.params["mu1"] == pytest.approx(0.3, rel=1e-15)
    assert cal.params["alpha1"] == 2.5 and cal.params["G1"] == 1.0
    before = Problem(vhfit.ViscoHyperelastic("ogden2", 1), curves,
                     np.array([[-6.0, 3.0]]), {}, 0.0).errors(np.array([x]))[0]
    assert cal.rmsape == pytest.approx(before, rel=1e-12)
    msgs = merged(cal)
    assert len(msgs) == 1 and "mu1 = 0.2, alpha1 = 2.5, mu2 = 0.1, alpha2 = 2.5" in msgs[0]


def test_an_empty_ogden_term_is_dropped():
    curves = ramps("ogden", OGDEN1_TRUE, THREE)
    cal = report("ogden2", [0.3, 2.5, 1e-20, -3.0, 1.0, 1e-2], curves, uncertainty=False)
    assert cal.model.hyperelastic.name == "ogden"
    assert [cal.params["mu1"], cal.params["alpha1"]] == [0.3, 2.5]
    assert cal.rmsape < 1e-9  # exact data, the true constants


def test_ogden_terms_that_differ_are_not_merged():
    # a real two-term material: the shapes differ and both moduli matter
    true = dict(mu1=0.3, alpha1=2.5, mu2=0.05, alpha2=-2.0, G1=1.0, tau1=1e-2)
    curves = ramps("ogden2", true, THREE)
    cal = report("ogden2", list(true.values()), curves, uncertainty=False)
    assert cal.model.hyperelastic.name == "ogden2" and not merged(cal)


def test_like_terms_whose_merge_changes_the_fit_are_kept():
    # exponents 5e-4 apart (merge candidates) with large moduli of opposite sign: their
    # difference is a term of its own (about mu2 * d(alpha) * df/d(alpha)), which the
    # one-term law cannot follow, so on data made by these very constants the merge
    # (polished) is worse than the exact fit and is refused
    true = dict(mu1=10.0, alpha1=2.5, mu2=-9.7, alpha2=2.5 * (1 + 5e-4), G1=1.0, tau1=1e-2)
    curves = ramps("ogden2", true, THREE)
    cal = report("ogden2", list(true.values()), curves, uncertainty=False)
    assert cal.model.hyperelastic.name == "ogden2" and not merged(cal)
    assert cal.params["mu1"] == 10.0 and cal.params["mu2"] == -9.7


def test_ogden_terms_ten_percent_apart_are_named_by_the_report():
    # exponents 10 % apart are no merge candidates, yet on these ramps the data see one
    # term: the report (not only degenerate_warnings) names the pair
    curves = ramps("ogden", OGDEN1_TRUE, THREE, noise=0.01, seed=3)
    cal = report("ogden2", [0.2, 2.5, 0.1, 2.75, 1.0, 1e-2], curves)
    assert cal.model.hyperelastic.name == "ogden2" and not merged(cal)
    msgs = [m for m in degenerate(cal) if "cannot be told apart" in m]
    assert len(msgs) == 1 and msgs[0].startswith("alpha1 and alpha2 (2.5 vs 2.75)")


def test_two_ogden_terms_at_one_exponent_cannot_be_told_apart():
    # degenerate_warnings names terms whose columns are the same function (what is left
    # when a merge does not hold): only mu1 + mu2 is determined
    curves = ramps("ogden", OGDEN1_TRUE, THREE, noise=0.01, seed=3)
    model = vhfit.ViscoHyperelastic("ogden2", 1)
    prob = Problem(model, curves, np.array([[-6.0, 3.0]]), {}, 0.0)
    x = np.array([0.2, 2.5, 0.1, 2.5, 1.0, 1e-2])
    msgs = [m for m in degenerate_warnings(model, x, {}, covariance(prob, x)[1])
            if "cannot be told apart" in m]
    assert len(msgs) == 1
    assert msgs[0].startswith("alpha1 and alpha2 (2.5 vs 2.5) cannot be told apart")
    assert "use ogden," in msgs[0]


def test_yeoh_on_neo_hookean_data_names_its_empty_terms():
    # neo-Hookean data: C20 = C30 = 0 by construction, so each fitted value is either
    # effectively zero or within the noise of zero (an interval wider than it)
    curves = ramps("yeoh", dict(C10=0.3, C20=0.0, C30=0.0, G1=1.0, tau1=1e-2), THREE,
                   noise=0.01, seed=1)
    cal = fit(curves, "yeoh", 1, seed=0)
    # (each is named with probability ~95 % over noise draws; seed 1 was the first tried)
    text = " ".join(degenerate(cal))
    assert "C20 = " in text and "C30 = " in text, cal.headlines
    assert "C10 = " not in text  # the one term the data hold is determined


def test_extra_prony_terms_without_relaxation_in_the_data_are_named():
    # one relaxation time in the data; N = 3 leaves two terms with nothing to fit. Without
    # pruning, each term beyond the first that is not merged away is effectively zero or
    # undetermined, and named so before the constants
    curves = ramps("mooney_rivlin", dict(C10=0.2, C01=0.1, G1=1.0, tau1=1e-3), FOUR,
                   noise=0.01, seed=2)
    cal = fit(curves, "mooney_rivlin", 3, seed=0, prune_tol=0.0)
    text = " ".join(degenerate(cal))
    named = [i for i in range(1, cal.n_prony + 1) if f"G{i} = " in text or f"tau{i} = " in text]
    assert len(named) >= cal.n_prony - 1, cal.summary()
    assert cal.n_prony > 1  # (the case exercises the check: a term survived the merging)
    assert "C10" not in text and "C01" not in text  # the elastic part is determined


def test_effectively_zero_constants_are_named_by_kind():
    curves = ramps("yeoh", dict(C10=0.3, C20=0.0, C30=0.0, G1=1.0, tau1=1e-2), THREE)
    m = vhfit.ViscoHyperelastic("yeoh", 0)
    # the case: a constant printed as 1.86e-55
    msgs = degenerate_warnings(m, np.array([0.3, 1.86e-55, 0.01]), {})
    assert len(msgs) == 1 and msgs[0].startswith("C20 = 1.86e-55 MPa below 1e-12 of the "
                                                 "largest hyperelastic modulus (0.3 MPa)")
    # just below and just above the threshold (relative to the largest modulus, 0.3)
    assert degenerate_warnings(m, np.array([0.3, 0.3 * NEGLIGIBLE * 0.9, 0.01]), {})
    assert not degenerate_warnings(m, np.array([0.3, 0.3 * NEGLIGIBLE * 1.1, 0.01]), {})
    # a negative constant counts by its size
    assert degenerate_warnings(m, np.array([0.3, -1e-20, 0.01]), {})
    assert not degenerate_warnings(m, np.array([0.3, -1e-3, 0.01]), {})
    # G_i against each other, not against the hyperelastic moduli
    mr2 = vhfit.ViscoHyperelastic("mooney_rivlin", 2)
    msgs = degenerate_warnings(mr2, np.array([0.2, 0.1, 2.0, 1e-3, 1e-13, 0.1]), {})
    assert len(msgs) == 1 and msgs[0].startswith("G2 = 1e-13 MPa below 1e-12 of the largest "
                                                 "Prony modulus G_i (2 MPa)")
    assert not degenerate_warnings(mr2, np.array([0.2, 0.1, 2.0, 1e-3, 1e-11, 0.1]), {})
    # tiny hyperelastic moduli beside large G_i (g_inf near 0): different kinds
    assert not degenerate_warnings(mr2, np.array([1e-14, 2e-14, 2.0, 1e-3, 1.0, 0.1]), {})
    # a single modulus of its kind has nothing to be negligible against
    assert not degenerate_warnings(vhfit.ViscoHyperelastic("neo_hooke", 1),
                                   np.array([0.3, 1e-30, 0.1]), {})
    # through the report, before the constants
    cal = report("yeoh", [0.3, 1.86e-55, 0.0, 1.0, 1e-2], curves, uncertainty=False)
    assert degenerate(cal) and "C20 = 1.86e-55 MPa, C30 = 0 MPa below" in degenerate(cal)[0]
    assert "WARNING: " + degenerate(cal)[0] in head(cal)
    # with intervals too (noisy data: C20's is far wider than 1.86e-55), each constant
    # is named once
    noisy = ramps("yeoh", dict(C10=0.3, C20=0.0, C30=0.0, G1=1.0, tau1=1e-2), THREE,
                  noise=0.01, seed=1)
    cal = report("yeoh", [0.3, 1.86e-55, 0.0, 1.0, 1e-2], noisy)
    assert cal.confidence["C20"][1] - cal.confidence["C20"][0] > 1e-6
    assert sum(m.count("C20 = ") for m in degenerate(cal)) == 1, degenerate(cal)


@pytest.mark.parametrize("lo, hi, named", [
    (-0.1, 2.1, True),  # half-width 1.1 > 1
    (0.1, 1.9, False),  # half-width 0.9 < 1
    (-np.inf, np.inf, True),
    (np.nan, np.nan, True),
])
def test_an_interval_wider_than_its_value_is_named(lo, hi, named):
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1)
    x = np.array([0.2, 0.1, 1.0, 0.5])
    conf = {"C10": (0.19, 0.21), "C01": (0.09, 0.11), "G1": (lo, hi), "tau1": (0.4, 0.6)}
    msgs = degenerate_warnings(m, x, conf)
    assert bool(msgs) is named
    if named:
        assert msgs[0].startswith("not determined by the data (95 % interval wider than the "
                                  "value): G1 = 1 MPa in [")
    # a τ's interval (symmetric in log τ): its half-width in s against τ
    conf = {**conf, "G1": (0.9, 1.1), "tau1": (0.5 / 2.5, 0.5 * 2.5)}  # half 0.525
    assert "tau1 = 0.5 s in [0.2, 1.25]" in degenerate_warnings(m, x, conf)[0]
    conf["tau1"] = (0.5 / 2.2, 0.5 * 2.2)  # half 0.436
    assert not degenerate_warnings(m, x, conf)


@pytest.mark.parametrize("gap, named", [(1e-7, True), (1e-5, False), (0.0, True)])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_moduli_correlated_to_one_are_named(gap, named, sign):
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 0)
    rho = sign * (1.0 - gap)
    cov0 = np.array([[4.0, 2.0 * rho], [2.0 * rho, 1.0]])  # sd 2 and 1
    msgs = degenerate_warnings(m, np.array([0.2, 0.1]), {}, cov0)
    assert bool(msgs) is named
    if named:
        assert msgs[0].startswith(f"C10 and C01 cannot be told apart by the data "
                                  f"(correlation of C10 and C01 {rho:+.9f})")
    assert CORRELATION_TOL == 1.0 - 1e-6


# ---------------------------------------------------------- negative cases


def test_exact_mooney_rivlin_two_prony_fit_gets_no_degeneracy_warning():
    # the law and N that made the data, 4 rates over the decades of both τ
    cal = fit(ramps("mooney_rivlin", MR2_TRUE, FOUR), "mooney_rivlin", 2, seed=0)
    assert cal.rmsape < 1e-3
    assert degenerate(cal) == [] and cal.headlines == []
    assert head(cal)[3:] == [""]  # verdict, title, errors, blank: no WARNING line


def test_well_posed_fits_get_no_degeneracy_warning():
    # 1 % noise on the same well-posed problem: every constant is determined
    cal = fit(ramps("mooney_rivlin", MR2_TRUE, FOUR, noise=0.01, seed=4), "mooney_rivlin",
              2, seed=0)
    assert degenerate(cal) == [], cal.headlines
    # two Ogden terms of opposite exponents, exact data, at the generating constants (no
    # search): distinct terms, not named; (with 1 % noise on these compression ramps
    # alone alpha1 and mu2 are undetermined, and named so)
    og2 = dict(mu1=0.3, alpha1=2.5, mu2=0.1, alpha2=-2.0, G1=1.0, tau1=1e-2)
    curves = ramps("ogden2", og2, THREE)
    cal = report("ogden2", list(og2.values()), curves)
    assert degenerate(cal) == [], cal.headlines


def test_covariance_of_an_exact_fit_still_gives_correlations():
    # s² ~ 0 at an exact fit; the correlation (and so the check) does not depend on it
    curves = ramps("ogden", OGDEN1_TRUE, THREE)
    m = vhfit.ViscoHyperelastic("ogden2", 1)
    prob = Problem(m, curves, np.array([[-6.0, 3.0]]), {}, 0.0)
    x = np.array([0.2, 2.5, 0.1, 2.5, 1.0, 1e-2])
    z, cov0, Vt, tiny, s2, dof = covariance(prob, x)
    assert s2 < 1e-20 and np.all(np.isfinite(cov0))
    msgs = degenerate_warnings(m, x, {}, cov0)
    assert msgs and msgs[0].startswith("alpha1 and alpha2 (2.5 vs 2.5) cannot be told apart")


def test_load_accepts_results_without_warnings(tmp_path):
    cal = report("mooney_rivlin", [0.2, 0.1, 1.0, 1e-3, 2.0, 0.1],
                 ramps("mooney_rivlin", MR2_TRUE, FOUR), uncertainty=False)
    cal.save(tmp_path / "r.json")
    res = json.loads((tmp_path / "r.json").read_text())
    del res["warnings"], res["headlines"]
    (tmp_path / "old.json").write_text(json.dumps(res))
    back = Calibration.load(tmp_path / "old.json")
    assert back.warnings == [] and back.headlines == [] and back.params == cal.params


def test_vhfit_fit_merges_collapsed_ogden_terms_and_says_so_first(tmp_path, monkeypatch,
                                                                    capsys):
    from vhfit import cli

    monkeypatch.chdir(tmp_path)
    m = vhfit.ViscoHyperelastic("ogden", 1)
    files = []
    for r in THREE:
        s = m.stress(OGDEN1_TRUE, strain=EPS, strain_rate=r, measure="engineering")
        path = tmp_path / f"og_{-r:g}.csv"
        path.write_text(f"# strain_rate: {r}\nstrain,stress_MPa\n"
                        + "".join(f"{e:.17g},{v:.17g}\n" for e, v in zip(EPS, s)))
        files.append(str(path))
    assert cli.main(["fit", *files, "--model", "ogden2", "--prony", "1", "--seed", "0",
                     "-q", "--no-plot", "--out", "res"]) == 0
    res = json.loads((tmp_path / "res" / "results.json").read_text())
    assert res["status"] == "complete" and res["hyperelastic"] == "ogden"
    msgs = [w for w in res["warnings"] if "merged into ogden" in w]
    assert len(msgs) == 1 and msgs[0] in res["headlines"]
    summary = (tmp_path / "res" / "summary.txt").read_text().splitlines()
    table = summary.index(next(ln for ln in summary if ln.startswith("parameter")))
    assert all(f"WARNING: {w}" in summary[:table] for w in msgs)
    assert capsys.readouterr().out.splitlines()[: table + 1] == summary[: table + 1]
