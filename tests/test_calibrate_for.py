"""``vhfit.calibrate_for``: one fit per formulation the solvers integrate, each further
fit started from the first (``start_options``), reaching what a separate
``calibrate(..., formulation=)`` reaches.

Data: noise-free compression ramps of Mooney-Rivlin + 1 Prony term generated in the
hereditary formulation, and the same constants generated in LS-DYNA's: each fit in the
data's own formulation is exact (RMSAPE ~0), the other is not — so the two fits are
distinguishable and the exact one is a reference independent of the search.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import vhfit
from vhfit.calibration import plan_formulations, start_options

P = dict(C10=0.2, C01=0.1, G1=1.8, tau1=0.01)
RATES = (-1.0, -30.0, -1000.0)


def ramps(formulation: str) -> list:
    m = vhfit.ViscoHyperelastic("mooney_rivlin", 1, formulation=formulation)
    eps = np.linspace(0.0, -0.5, 21)
    return [vhfit.Curve(strain=eps, strain_rate=r, measure="engineering",
                        stress=m.stress(P, strain=eps, strain_rate=r, measure="engineering"))
            for r in RATES]


def quiet(fn, *a, **k):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*a, **k)


def test_plan_formulations_groups_solvers_by_their_formulation():
    # the solver records of vhfit.export fill the registry (vhfit.calibrate_for loads it)
    import vhfit.export  # noqa: F401

    assert plan_formulations(["lsdyna", "abaqus", "ansys", "abaqus"]) == {
        "lsdyna": ["lsdyna"], "hereditary": ["abaqus", "ansys"]}
    assert plan_formulations("ansys") == {"hereditary": ["ansys"]}
    with pytest.raises(ValueError, match="solver 'radioss': unknown; choose among abaqus"):
        plan_formulations(["radioss"])
    with pytest.raises(ValueError, match="at least one solver"):
        plan_formulations([])


@pytest.mark.parametrize("data_form", ["hereditary", "lsdyna"])
def test_each_fit_equals_a_separate_calibrate_in_its_formulation(data_form):
    curves = ramps(data_form)
    kw = dict(n_prony=1, seed=3, uncertainty=False)
    fits = quiet(vhfit.calibrate_for, ["abaqus", "lsdyna", "ansys"], curves, **kw)
    assert list(fits) == ["hereditary", "lsdyna"]
    for form, cal in fits.items():
        assert cal.model.formulation == form
        alone = quiet(vhfit.calibrate, curves, formulation=form, **kw)
        # the data's own formulation: exact (both reach the generating constants);
        # the other: the same optimum, to the search's tolerance and the polish's
        assert cal.rmsape == pytest.approx(alone.rmsape, rel=1e-6, abs=1e-8)
        if form == data_form:
            assert cal.rmsape < 1e-6
            for k, v in P.items():
                assert cal.params[k] == pytest.approx(v, rel=1e-6)
        else:
            assert cal.rmsape > 0.1  # the other law cannot reproduce these data
            for k in P:
                assert cal.params[k] == pytest.approx(alone.params[k], rel=1e-4)
    # the seeded second search used 3/8 of the population, and stopped at a gap of 1e-4
    assert fits["lsdyna"].options["popsize"] == 24 and fits["hereditary"].options[
        "popsize"] == 64
    assert fits["lsdyna"].options["tol"] == 1e-4 and fits["hereditary"].options["tol"] == 1e-6


def test_start_options_seed_half_the_population_around_the_first_fit():
    curves = ramps("hereditary")
    first = quiet(vhfit.calibrate, curves, n_prony=1, seed=0, uncertainty=False)
    opts = start_options(first, curves, formulation="lsdyna", n_prony=1, seed=0)
    init = opts["de_options"]["init"]
    # (direction θ of (C10, C01), log10 tau1): the first fit's θ and τ, then the cloud
    assert opts["popsize"] == 24 and init.shape == (24, 2)
    assert opts["tol"] == 1e-4  # its search stops at a wider gap; the polish finishes
    assert start_options(first, curves, formulation="lsdyna", n_prony=1, tol=1e-2)[
        "tol"] == 1e-2  # a looser tol of the caller's stays
    z0 = [np.arctan2(first.params["C01"], first.params["C10"]),
          np.log10(first.params["tau1"])]
    np.testing.assert_allclose(init[0], z0, rtol=1e-12)
    # every direction seeded keeps a positive initial modulus, 2 (C10 + C01) > 0
    assert np.all(np.cos(init[:, 0]) + np.sin(init[:, 0]) > 0)
    near = np.abs(init[:, 1] - z0[1]) < 1.0
    assert near[:12].mean() > near[12:].mean()  # the cloud, then the Sobol half
    assert start_options(first, curves, formulation="lsdyna", n_prony="auto") == {}
    assert start_options(first, curves, formulation="lsdyna", n_prony=1,
                         de_options={"init": "sobol"}) == {}


def test_solver_records_are_accepted_as_well_as_names():
    """A solver record (vhfit.export.Solver) stands for its solver: registered, as its
    name; not registered, by its own name and formulation."""
    import dataclasses

    from vhfit.export import get_solver

    lsdyna = get_solver("lsdyna")
    assert plan_formulations([lsdyna, "abaqus", get_solver("ansys")]) == {
        "lsdyna": ["lsdyna"], "hereditary": ["abaqus", "ansys"]}
    mine = dataclasses.replace(get_solver("abaqus"), name="mine",
                               formulation="lsdyna_deviatoric")  # never registered
    assert plan_formulations(mine) == {"lsdyna_deviatoric": ["mine"]}
    curves = ramps("lsdyna")
    fits = quiet(vhfit.calibrate_for, [lsdyna], curves, n_prony=1, seed=0,
                 uncertainty=False)
    alone = quiet(vhfit.calibrate, curves, n_prony=1, seed=0, uncertainty=False,
                  formulation="lsdyna")
    assert list(fits) == ["lsdyna"] and fits["lsdyna"].params == alone.params
    with pytest.raises(ValueError, match="give a solver record"):
        plan_formulations([dataclasses.replace(mine, formulation="nonesuch")])


def test_bad_arguments_are_refused():
    curves = ramps("hereditary")
    with pytest.raises(ValueError, match="drop formulation="):
        vhfit.calibrate_for(["abaqus"], curves, formulation="lsdyna")
    with pytest.raises(ValueError, match="solver 'radioss'"):
        vhfit.calibrate_for(["radioss"], curves)


def test_a_pruned_first_fit_seeds_each_tau_in_the_slot_whose_range_holds_it():
    """semifree τ ranges: one per term. A first fit with one term (as after pruning) puts
    its τ into the slot whose range holds it, the other slot at the middle of its own."""
    curves = ramps("hereditary")
    first = quiet(vhfit.calibrate, curves, n_prony=1, seed=0, uncertainty=False)
    kw = dict(formulation="lsdyna", n_prony=2, tau_strategy="semifree", seed=0)
    init = start_options(first, curves, **kw)["de_options"]["init"]
    spread = init[12:]  # the Sobol half covers each coordinate's range
    lo, hi = spread.min(axis=0), spread.max(axis=0)
    assert hi[1] <= lo[2] + 1e-9  # two ranges of log10 τ, the second above the first
    for slot in (1, 2):  # put the first fit's τ inside each range in turn
        t = lo[slot] + 0.3 * (hi[slot] - lo[slot])
        first.params["tau1"] = 10.0 ** t
        z0 = start_options(first, curves, **kw)["de_options"]["init"][0]
        assert z0[slot] == pytest.approx(t, rel=1e-12)
        other = 3 - slot
        assert lo[other] < z0[other] < hi[other] and z0[other] != pytest.approx(t)


def test_a_first_fit_merged_into_fewer_like_terms_seeds_the_law_asked_for():
    """An ogden2 fit whose two terms were merged into ogden (tests/test_degenerate.py)
    seeds the next formulation's ogden2 search with the merged term and an empty one
    of the same exponent; a first fit of an unrelated law seeds nothing."""
    curves = ramps("hereditary")
    first = vhfit.Calibration(model=vhfit.ViscoHyperelastic("ogden", 1),
                              params=dict(mu1=0.5, alpha1=3.0, G1=1.0, tau1=0.02),
                              rmsape=1.0, per_curve_rmsape=[1.0] * 3, nit=1, nfev=1,
                              wall_time=0.0, stop_reason="converged")
    kw = dict(hyperelastic="ogden2", formulation="lsdyna", n_prony=1, seed=0)
    z0 = start_options(first, curves, **kw)["de_options"]["init"][0]
    # (the direction of (mu1, mu2) as its place on the admissible arc, alpha1, alpha2,
    # log10 tau1): with equal exponents the law is one term, admissible for mu1 + mu2 > 0,
    # so the arc is θ in (-π/4, 3π/4) and mu2 = 0 (θ = 0) a quarter of the way along it
    np.testing.assert_allclose(z0[1:], [3.0, 3.0, np.log10(0.02)], rtol=1e-12, atol=0)
    assert z0[0] == pytest.approx(0.25, abs=1e-5)
    assert start_options(first, curves, **dict(kw, hyperelastic="yeoh")) == {}


def test_after_an_order_scan_the_next_fit_is_made_at_the_n_it_chose():
    """``n_prony="auto"``: the further formulation's fit is one fit at the N the first
    fit's scan chose (not a scan of its own): the search a separate calibrate at that N
    runs (the scan in that formulation would run it too)."""
    import dataclasses

    curves = ramps("lsdyna")
    kw = dict(n_prony="auto", max_prony=2, seed=0, uncertainty=False)
    fits = quiet(vhfit.calibrate_for, ["abaqus", "lsdyna"], curves, **kw)
    first, second = fits["hereditary"], fits["lsdyna"]
    n = first.options["n_prony_chosen"]
    assert first.order_scan and first.options["n_prony"] == "auto"
    assert second.order_scan == [] and second.options["n_prony"] == n
    alone = quiet(vhfit.calibrate, curves, formulation="lsdyna", n_prony=n, seed=0,
                  uncertainty=False)
    assert second.params == alone.params and second.options["popsize"] == 64
    assert second.rmsape < 1e-6  # the data's own law: exact, the generating constants
    for k, v in P.items():
        assert second.params[k] == pytest.approx(v, rel=1e-6)
    # the N comes from the scan's choice, whatever it was
    two = dataclasses.replace(first, options={**first.options, "n_prony_chosen": 2})
    assert start_options(two, curves, formulation="lsdyna", **kw) == {"n_prony": 2}
    # a scan that chose nothing (interrupted before a result): nothing to start from
    none = dataclasses.replace(first, options={**first.options, "n_prony_chosen": None})
    assert start_options(none, curves, formulation="lsdyna", **kw) == {}


def test_without_prony_terms_the_further_fit_is_the_first_in_its_formulation():
    """No Prony terms: every formulation has the law's long-term stress (σ = σ_h), so the
    further fit is the first's constants with no search of its own (``same_fit``); with
    terms, or other keywords than the first's, it is a fit of its own."""
    from vhfit.calibration import same_fit

    curves = ramps("hereditary")
    kw = dict(n_prony=0, seed=0, uncertainty=False)
    fits = quiet(vhfit.calibrate_for, ["abaqus", "lsdyna"], curves, **kw)
    first, second = fits["hereditary"], fits["lsdyna"]
    assert second.model.formulation == "lsdyna" and second.nfev == 0
    assert second.params == first.params and second.rmsape == first.rmsape
    assert "same_as" in second.options and second.settings.formulation == "lsdyna"
    # the reason, checked independently: both models give the same stresses
    for c in curves:
        s1 = first.model.stress(first.params, strain=c.strain, strain_rate=c.strain_rate,
                                measure="engineering")
        s2 = second.model.stress(second.params, strain=c.strain, strain_rate=c.strain_rate,
                                 measure="engineering")
        np.testing.assert_allclose(s2, s1, rtol=1e-12, atol=0)
    assert same_fit(first, curves, **dict(kw, formulation="lsdyna", seed=1)) is None
    assert same_fit(first, curves, **dict(kw, formulation="lsdyna", n_prony=1)) is None
    viscous = quiet(vhfit.calibrate, curves, n_prony=1, seed=0, uncertainty=False)
    assert same_fit(viscous, curves, n_prony=1, seed=0, uncertainty=False,
                    formulation="lsdyna") is None


def test_after_a_spectrum_scan_the_next_fit_starts_its_tau_from_the_first():
    """Sweeps alone (the per-decade spectrum, whose moduli are the same in every
    formulation): after ``n_prony="auto"`` the next fit is at the first's N with its τ
    seeded from the first fit, and reaches the same moduli."""
    f = np.logspace(-2, 2, 41)
    w = 2 * np.pi * f
    E0, G, tau = 3.0, np.array([4.0, 2.0]), np.array([0.1, 10.0])
    wt = np.outer(w, tau)
    e1 = E0 + (G * wt**2 / (1 + wt**2)).sum(axis=1)  # a Maxwell series: exact for N = 2
    e2 = (G * wt / (1 + wt**2)).sum(axis=1)
    curves = [vhfit.FrequencySweep(frequency=f, storage=e1, loss=e2)]
    kw = dict(n_prony="auto", seed=0, uncertainty=False)
    first = quiet(vhfit.calibrate, curves, **kw)
    n = first.options["n_prony_chosen"]
    opts = start_options(first, curves, formulation="lsdyna", **kw)
    assert opts["n_prony"] == n and opts["de_options"]["init"].shape[1] >= n
    second = quiet(vhfit.calibrate_for, ["abaqus", "lsdyna"], curves, **kw)["lsdyna"]
    assert second.order_scan == [] and second.n_prony <= n
    assert second.rmsape == pytest.approx(first.rmsape, rel=1e-6, abs=1e-8)


def test_vhfit_fit_without_prony_terms_makes_one_search(tmp_path):
    """The command line, equilibrium curves (no Prony terms by default): the LS-DYNA
    fit is the first fit in its formulation, with no search of its own."""
    from vhfit.cli import main

    m = vhfit.ViscoHyperelastic("mooney_rivlin", 0)
    eps = np.linspace(0.0, 0.6, 13)
    sig = m.stress(dict(C10=0.2, C01=0.1), strain=eps, strain_rate=1.0, measure="engineering")
    csv = tmp_path / "eq.csv"
    csv.write_text("strain,stress_MPa\n"
                   + "\n".join(f"{float(e)!r},{float(s)!r}" for e, s in zip(eps, sig)))
    out = tmp_path / "out"
    code = quiet(main, ["fit", str(csv), "--no-plot", "--quiet", "--out", str(out)])
    assert code == 0
    cal = vhfit.Calibration.load(out / "results.json")
    lsd = cal.fits["lsdyna"]
    assert lsd.model.formulation == "lsdyna" and lsd.model.n_prony == 0
    assert lsd.nfev == 0 and "same_as" in lsd.options
    assert lsd.params == cal.fits["hereditary"].params
