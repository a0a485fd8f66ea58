"""Stability kept: every fit is Drucker-stable over the range it states, or says first
that no stable law was found (issue: a Gent fit to λ = 8 reported instability inside
its own range, its Jm bound too low for stability).

The stated range bounds every principal stretch of the checked states: each mode is
checked over the loaded stretches λ whose principal stretches stay within it. For the
three one-stretch modes these are, with the range [a, b] (a < 1 < b), by hand:

    uniaxial     (λ, λ^-1/2, λ^-1/2):  max(a, b^-2)   <= λ <= min(b, a^-2)
    equibiaxial  (λ, λ, λ^-2):         max(a, b^-1/2) <= λ <= min(b, a^-1/2)
    planar       (λ, 1, 1/λ):          max(a, 1/b)    <= λ <= min(b, 1/a)

The checks below sample these intervals on their own grids and take the tangent
d(σ1 − σ3)/d ln λ by central differences of :func:`vhfit.stability.principal_difference`
(whose values tests/test_stability.py checks against closed forms).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import vhfit
from vhfit import hyperelastic as hyp
from vhfit.calibration._admissible import Admissible
from vhfit.stability import mode_range, principal_difference


def hand_ranges(a: float, b: float) -> dict[str, tuple[float, float]]:
    return {"uniaxial": (max(a, b**-2), min(b, a**-2)),
            "equibiaxial": (max(a, b**-0.5), min(b, a**-0.5)),
            "planar": (max(a, 1 / b), min(b, 1 / a))}


STRETCHES = {"uniaxial": lambda x: (x, x**-0.5, x**-0.5),
             "equibiaxial": lambda x: (x, x, x**-2.0),
             "planar": lambda x: (x, np.ones_like(x), 1 / x)}


def stable_by_hand(hm, params, a: float, b: float, n: int = 400) -> bool:
    """Positive tangent of every mode over its hand range (the law defined everywhere),
    on n log-spaced stretches: the check's own sampling (a dip narrower than a step of
    ln λ is not seen, by this or by the check: docs/theory.md §11)."""
    d = 1e-5
    for mode, (lo, hi) in hand_ranges(a, b).items():
        lam = np.exp(np.linspace(math.log(lo), math.log(hi), n))
        with np.errstate(all="ignore"):
            up = principal_difference(hm, params, *STRETCHES[mode](lam * math.exp(d)))
            dn = principal_difference(hm, params, *STRETCHES[mode](lam * math.exp(-d)))
        if not np.all((up - dn) / (2 * d) > 0):
            return False
    return True


@pytest.mark.parametrize("rng", [(0.3, 8.8), (0.0459, 8.36), (0.5, 1.2), (0.9, 30.0)])
def test_mode_ranges_are_the_hand_values(rng):
    for mode, want in hand_ranges(*rng).items():
        assert mode_range(mode, rng) == pytest.approx(want, rel=1e-9), mode


def test_treloar_like_range_keeps_equibiaxial_within_the_data():
    # equibiaxial tension to 4.4 reaches λ3 = 0.052: principal stretches in [0.047, 8.4]
    # bound equibiaxial compression at 8.4^(-1/2), where λ3 = 8.4 (not 0.047, λ3 = 453)
    lo, hi = mode_range("equibiaxial", (0.0472, 8.4))
    assert lo == pytest.approx(8.4**-0.5) and hi == pytest.approx(0.0472**-0.5)


def test_a_law_undefined_within_the_range_is_not_admissible():
    """Gent with Jm below I1 − 3 at the range's end is undefined there: inadmissible (as
    the final check says); just above it is admissible."""
    gent = hyp.get("gent")
    a, b = 0.3, 8.8
    # the largest I1 − 3 over the hand ranges: uniaxial tension at b
    jm_edge = b**2 + 2 / b - 3
    adm = Admissible(gent, (a, b))
    ok = adm(np.array([[0.3, 0.98 * jm_edge], [0.3, 1.02 * jm_edge]]))
    assert ok.tolist() == [False, True]
    assert not vhfit.stability.drucker(gent, [0.3, 0.98 * jm_edge], (a, b),
                                       principal=True).stable
    assert stable_by_hand(gent, [0.3, 1.02 * jm_edge], a, b)


def _tension(law_truth, lam_max, n=30):
    lam = np.linspace(1.03, lam_max, n) if lam_max > 1 else np.linspace(0.97, lam_max, n)
    m = vhfit.ViscoHyperelastic(law_truth[0], 0)
    s = m.stress(law_truth[1], strain=lam - 1, measure="engineering")
    return vhfit.Curve(strain=lam - 1, stress=s, name=f"to {lam_max}")


#: a stiffening rubber (Gent, Jm = 70: it locks before the stretch range checked, 8.8)
STIFFENING = _tension(("gent", dict(mu=0.3, Jm=70.0)), 8.0)
#: a compression to λ = 0.3 of a stiffening solid (Yeoh with a positive cubic term)
COMPRESSION = _tension(("yeoh", dict(C10=0.2, C20=0.01, C30=0.002)), 0.3)


@pytest.mark.parametrize("curve", [STIFFENING, COMPRESSION], ids=["tension8", "compression03"])
@pytest.mark.parametrize("law", vhfit.hyperelastic.available())
def test_every_law_is_stable_over_its_stated_range_or_says_it_is_not(law, curve):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate([curve], hyperelastic=law, n_prony=0, seed=0, popsize=12,
                              maxiter=15, uncertainty=False, polish=False)
    a, b = cal.options["stability_range"]
    assert (a, b) == cal.stability.stretch_range
    hm = cal.model.hyperelastic
    x = np.array([cal.params[n] for n in hm.param_names])
    if cal.options.get("no_stable_law"):  # the explicit outcome, first line first
        assert not cal.stability.stable
        assert cal.summary().startswith("NO STABLE LAW: ")
        assert cal.headlines[0].startswith("NO STABLE LAW: ")
    else:
        assert cal.stability.stable, cal.stability.describe()
        assert stable_by_hand(hm, x, a, b), law
        assert not cal.summary().startswith("NO STABLE LAW")


def test_the_issue_gent_case_is_stable_up_to_its_stated_range():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate([STIFFENING], hyperelastic="gent", n_prony=0, seed=0)
    a, b = cal.options["stability_range"]
    assert b == pytest.approx(8.0 * 1.1)
    assert cal.stability.stable
    assert cal.params["Jm"] > b**2 + 2 / b - 3  # defined up to uniaxial tension at b
    assert stable_by_hand(cal.model.hyperelastic, [cal.params["mu"], cal.params["Jm"]], a, b)


def _fit(**kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return vhfit.calibrate([STIFFENING], hyperelastic="gent", n_prony=0, seed=0,
                               maxiter=60, **kw)


def test_jm_is_widened_when_no_stable_gent_law_is_in_its_automatic_bounds():
    """Stable up to principal stretches of 20 needs Jm > 20² + 2/20 − 3 = 397.1, beyond
    the automatic Jm <= 100: doublings reach 400 (stable), the bound goes to
    100 + 2 (400 − 100) = 700, named in a note; the fit is stable."""
    cal = _fit(stability_range=(0.1, 20.0))
    assert cal.options["widened_for_stability"] == {"Jm": [0.1, 700.0]}
    assert cal.bounds["Jm"] == (0.1, 700.0)
    assert any(w == "no gent law of the automatic bounds is Drucker-stable over 0.1 <= λ <= 20:"
               " widened Jm to (0.1, 700)" for w in cal.warnings)
    assert 397.1 < cal.params["Jm"] <= 700.0
    assert cal.stability.stable and not cal.options.get("no_stable_law")


def test_van_der_waals_lambda_m_is_widened_too():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate([STIFFENING], hyperelastic="van_der_waals", n_prony=0, seed=0,
                              maxiter=30, stability_range=(0.05, 25.0))
    w = cal.options.get("widened_for_stability", {})
    assert list(w) == ["lambda_m"] and w["lambda_m"][1] > 10.0
    assert cal.stability.stable


def test_no_stable_law_is_said_first_in_summary_and_report():
    """The user's Jm <= 100 cannot hold a law stable to principal stretches of 20: the fit
    is made without the admissible set and says so first, in the summary, its WARNING,
    and the report's verdict (red)."""
    cal = _fit(stability_range=(0.1, 20.0), bounds={"Jm": (1.0, 100.0)})
    assert cal.options["no_stable_law"] is True and not cal.stability.stable
    first = cal.summary().splitlines()[0]
    assert first.startswith("NO STABLE LAW: Drucker-UNSTABLE in ")
    assert "--stability-range" in first and "--bounds" in first
    assert cal.headlines[0].startswith(
        "NO STABLE LAW: no gent law within the search bounds is Drucker-stable over "
        "0.1 <= λ <= 20 (every principal stretch)")
    assert "widen the bounds given on Jm" in cal.headlines[0]
    from vhfit.report import build_report, verdict
    assert verdict(cal).startswith("NO STABLE LAW: ")
    html = build_report(cal, [STIFFENING], figures=False)
    assert '<div class="verdict bad" id="verdict">' in html


def test_no_stable_law_comes_before_every_other_warning_and_keeps_the_grade():
    """With a second warning (μ pinned on the user's bound) the NO STABLE LAW line is
    still the first, and the verdict keeps the error and its grade after it."""
    cal = _fit(stability_range=(0.1, 20.0), bounds={"Jm": (1.0, 100.0), "mu": (0.01, 0.2)})
    assert len(cal.headlines) >= 2
    assert cal.headlines[0].startswith("NO STABLE LAW: ")
    assert any(h.startswith("mu = 0.2 ended on its search bound mu <= 0.2")
               for h in cal.headlines[1:])
    v = cal.verdict()
    head, sep, rest = v.partition("or another law. ")
    assert head.startswith("NO STABLE LAW: ") and sep
    assert rest.startswith("RMSAPE ") and " %: " in rest


def test_a_stable_fit_has_a_plain_first_line():
    cal = _fit()
    assert cal.stability.stable and cal.summary().startswith("RMSAPE ")


def _csv(tmp_path):
    f = tmp_path / "t.csv"
    lam = np.linspace(1.03, 8.0, 30)
    s = vhfit.ViscoHyperelastic("gent", 0).stress(dict(mu=0.3, Jm=90.0), strain=lam - 1,
                                                  measure="engineering")
    f.write_text("strain,stress_MPa\n" + "".join(f"{float(e)!r},{float(v)!r}\n"
                                                  for e, v in zip(lam - 1, s)))
    return f


def test_cli_exit_code_is_one_without_a_stable_law(tmp_path, monkeypatch, capsys):
    from vhfit import cli

    monkeypatch.chdir(tmp_path)
    f = _csv(tmp_path)
    code = cli.main(["fit", str(f), "--model", "gent", "--prony", "0", "--no-plot", "-q",
                     "--stability-range", "0.1:20", "--bounds", "Jm=1:100", "--maxiter", "40",
                     "--out", "o"])
    out = capsys.readouterr()
    assert code == 1
    assert out.out.startswith("NO STABLE LAW: ")
    assert "vhfit: error: no Drucker-stable law was found" in out.err
    assert (tmp_path / "o" / "results.json").exists()  # written, and marked
    # the same data with a range the law can keep: exit 0
    code = cli.main(["fit", str(f), "--model", "gent", "--prony", "0", "--no-plot", "-q",
                     "--maxiter", "40", "--out", "o2"])
    assert code == 0
