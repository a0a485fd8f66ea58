"""Constants that end on a bound no widening moves are named (issue: bounds named).

A relaxation time or a modulus on a bound the user gave, and a relaxation time on an end
of the automatic τ range, each get one WARNING line naming the constant, the bound and a
wider interval to try; an optimum inside its bounds gets none.

The data: two triangles (loading-unloading) at the nominal rates 0.05 and 0.5 /s, so that
the automatic τ range of Eq. 22 with calibrate's defaults (one decade above the slowest
time scale, three below the fastest) is [1e-3 / 0.5, 10 / 0.05] = [0.002, 200] s.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import vhfit
from vhfit import cli

#: The automatic τ range of the data of :func:`_curves` (Eq. 22, see above), s.
TAU_LOW, TAU_HIGH = 1e-3 / 0.5, 10.0 / 0.05


def _curves(tau1=2.0, tau2=None):
    """Loading-unloading of a neo-Hooke material with one Prony term (τ1 = ``tau1``), or
    two (G2 = 0.2, τ2 = ``tau2``)."""
    p = dict(C10=0.1, G1=0.3, tau1=tau1) | ({} if tau2 is None else dict(G2=0.2, tau2=tau2))
    m = vhfit.ViscoHyperelastic("neo_hooke", 1 if tau2 is None else 2)
    out = []
    for r in (0.05, 0.5):
        tmax = 1.0 / r
        t = np.linspace(0.0, 2 * tmax, 41)
        e = 1.0 - np.abs(t - tmax) * r
        s = m.stress(p, strain=e, time=t, measure="engineering")
        out.append(vhfit.Curve(strain=e[1:-1], stress=s[1:-1], time=t[1:-1],
                               measure="engineering"))
    return out


def _fit(tau1=2.0, tau2=None, n_prony=1, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return vhfit.calibrate(_curves(tau1, tau2), hyperelastic="neo_hooke",
                               n_prony=n_prony, seed=0, **kw)


def _tau_lines(cal, name="tau1"):
    """The summary's WARNING lines about ``name`` (a bound or a time window)."""
    return [w for w in cal.summary().splitlines() if "WARNING" in w and f"{name} = " in w]


def _on(value, bound, decades):
    """Whether ``value`` is within HIT_MARGIN (0.1 %) of a τ range ``decades`` wide from
    ``bound``, in log10."""
    return abs(np.log10(value / bound)) <= 1e-3 * decades


def _pinned(cal, name):
    return [w for w in cal.summary().splitlines()
            if "WARNING" in w and f"{name} = " in w and "search bound" in w]


def test_a_user_bound_that_binds_tau_is_named_with_the_bound_and_a_wider_interval():
    cal = _fit(bounds={"tau1": (0.1, 0.5)})  # the material's τ1 is 2
    assert abs(cal.params["tau1"] - 0.5) < 1e-3 * 0.5
    [line] = _pinned(cal, "tau1")
    assert "tau1 <= 0.5" in line and "given in bounds=" in line
    assert "--bounds tau1=0.1:" in line


def test_a_user_bound_that_binds_a_modulus_is_named():
    cal = _fit(bounds={"G1": (0.0, 0.1)})  # the material's G1 is 0.3
    assert cal.params["G1"] <= 0.1 * (1 + 1e-9)
    [line] = _pinned(cal, "G1")
    assert "G1 <= 0.1" in line


def test_an_interior_optimum_names_no_bound():
    cal = _fit(bounds={"tau1": (0.1, 50.0)})
    assert abs(cal.params["tau1"] - 2.0) < 0.02
    assert cal.rmsape < 0.1
    assert _pinned(cal, "tau1") == [] and _pinned(cal, "G1") == []


def test_a_hossain_like_user_bound_on_tau_is_named():
    """Issue case: neo-Hooke, N = 1, bounds={"tau1": (0.5, 1.0)} with the material's τ1
    at 5 s: τ1 ends on 1.0 and one line names it, given by the user."""
    cal = _fit(tau1=5.0, bounds={"tau1": (0.5, 1.0)})
    assert _on(cal.params["tau1"], 1.0, np.log10(2.0))
    [line] = _tau_lines(cal)
    assert "tau1 <= 1 s (given in bounds=)" in line
    assert "--bounds tau1=0.5:100" in line  # two decades beyond the bound hit


def test_a_user_bound_on_a_term_keeps_its_name_and_is_named_as_given():
    """Free strategy, N = 2, τ2 held to [0.01, 0.05] s while the material's τ are 2 and
    20 s: the bounded term ends on 0.05 s, the faster of the two, and keeps its name τ2
    (terms bounded by name are not re-sorted); its line says the bound was given, not
    that it is the automatic range's."""
    cal = _fit(tau1=2.0, tau2=20.0, n_prony=2, bounds={"tau2": (0.01, 0.05)})
    assert _on(cal.params["tau2"], 0.05, np.log10(5.0))
    [line] = [w for w in _tau_lines(cal, "tau2") if "search bound" in w]
    assert "tau2 <= 0.05 s (given in bounds=)" in line and "automatic" not in line


def test_a_tau_beyond_the_automatic_upper_end_is_named_once_with_its_remedies():
    """τ1 = 2000 s is ten times the automatic upper end (200 s): the fit ends there, and
    one line says so, the range's origin, a wider bounds= and a slower test. 200 s is
    below 10x every curve's duration (400 s): no time-window fact."""
    cal = _fit(tau1=2000.0)
    decades = np.log10(TAU_HIGH / TAU_LOW)
    assert _on(cal.params["tau1"], TAU_HIGH, decades)
    [line] = _tau_lines(cal)
    assert "tau1 <= 200 s (the end of the automatic τ range, set by the data's time " in line
    assert "bounds={'tau1': (0.002, 20000)}" in line and "--bounds tau1=0.002:20000" in line
    assert line.endswith("or add a slower test or a relaxation hold that identifies it")
    assert "longer than 10x" not in line
    assert line[len("WARNING: "):] in cal.headlines
    assert sum("tau1 = " in w for w in cal.warnings) == 1


def test_a_tau_below_the_automatic_lower_end_is_named_with_a_faster_test():
    """τ1 = 1e-4 s, below the lower end 0.002 s (itself above 0.01x the first objective
    time, 0.1 s: no time-window fact)."""
    cal = _fit(tau1=1e-4)
    assert _on(cal.params["tau1"], TAU_LOW, np.log10(TAU_HIGH / TAU_LOW))
    [line] = _tau_lines(cal)
    assert "tau1 >= 0.002 s (the end of the automatic τ range" in line
    assert "--bounds tau1=2e-05:200" in line
    assert line.endswith("or add a faster test that identifies it")


def test_a_tau_on_the_bound_and_outside_the_time_window_gets_one_merged_line():
    """decades_above=2 moves the upper end to 2000 s, beyond 10x every curve's duration
    (390 s: the curves run 39 s at most): the bound and the time window are one line."""
    cal = _fit(tau1=1e5, decades_above=2)
    assert _on(cal.params["tau1"], 2000.0, np.log10(2000.0 / TAU_LOW))
    [line] = _tau_lines(cal)
    assert "tau1 <= 2000 s (the end of the automatic τ range" in line
    assert ("; it is longer than 10x every curve's duration (longest 39 s): the data cannot "
            "tell it from a stiffer elastic law; add a slower test or a relaxation hold to "
            "identify it") in line
    assert sum("tau1 = " in w for w in cal.warnings) == 1


def test_a_tau_inside_its_automatic_range_is_not_named():
    cal = _fit(tau1=2.0)
    assert abs(cal.params["tau1"] - 2.0) < 0.02
    assert _tau_lines(cal) == []


def test_a_semifree_tau_on_the_cut_between_two_terms_is_named_with_the_free_strategy():
    """Semifree, N = 2: τ1's piece is [0.002, √(0.002 · 200)] = [0.002, 0.632] s, the
    material's two τ (2 and 20 s) lie above it: τ1 ends on the cut."""
    cal = _fit(tau1=2.0, tau2=20.0, n_prony=2, tau_strategy="semifree")
    cut = np.sqrt(TAU_LOW * TAU_HIGH)
    assert _on(cal.params["tau1"], cut, np.log10(cut / TAU_LOW))
    [line] = _tau_lines(cal)
    assert "tau1 <= 0.632456 s (its share of the automatic τ range under the tau " in line
    assert line.endswith("or tau_strategy='free' (command line: --strategy free) lets every "
                         "τ span the whole range")
    assert _tau_lines(cal, "tau2") == []


def test_a_fixed_tau_is_never_named():
    """Fixed strategy: τ1 = the middle of the range in log10 (no search, no bound), even
    though the material's τ (2000 s) lies beyond the range."""
    cal = _fit(tau1=2000.0, tau_strategy="fixed")
    assert cal.params["tau1"] == pytest.approx(np.sqrt(TAU_LOW * TAU_HIGH), rel=1e-9)
    assert [w for w in _tau_lines(cal) if "search bound" in w] == []


def test_the_command_line_summary_names_a_tau_on_the_automatic_bound(tmp_path, capsys):
    """The files of the data with τ1 = 2000 s: summary.txt has the one line."""
    paths = []
    for k, c in enumerate(_curves(tau1=2000.0)):
        rows = np.column_stack([c.history.out_time, c.target_strain, c.target_stress])
        paths.append(tmp_path / f"tri_{k}.csv")
        paths[-1].write_text("time_s,strain,stress_MPa\n" + "".join(
            ",".join(repr(float(v)) for v in r) + "\n" for r in rows))
    out = tmp_path / "out"
    assert cli.main(["fit", *map(str, paths), "--model", "neo_hooke", "--prony", "1",
                     "--out", str(out), "--no-plot", "-q"]) == 0
    capsys.readouterr()
    [line] = [w for w in (out / "summary.txt").read_text().splitlines()
              if "WARNING" in w and "tau1 = " in w]
    assert "search bound tau1 <= 200 s (the end of the automatic τ range" in line
    assert "--bounds tau1=0.002:20000" in line


def test_a_bound_given_to_a_term_by_name_holds_for_that_name():
    """bounds={'tau2': ...} with the free strategy: the bounded term keeps its name
    (no re-sort by τ), so the fit's tau2 lies within the limits and no false
    'outside the limits' warning appears; unsorted neighbours are not merged."""
    m = vhfit.ViscoHyperelastic("neo_hooke", 2)
    truth = dict(C10=0.1, G1=0.2, tau1=5.0, G2=0.3, tau2=0.03)
    curves = [vhfit.Curve(strain=np.linspace(0.0125, 0.5, 40),
                          stress=m.stress(truth, strain=np.linspace(0.0125, 0.5, 40),
                                          strain_rate=r, measure="engineering"),
                          strain_rate=r, name=f"r{r}") for r in (0.01, 0.1, 1.0)]
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        cal = vhfit.calibrate(curves, hyperelastic="neo_hooke", n_prony=2, seed=0,
                              bounds={"tau2": (0.01, 0.05)})
    assert 0.01 <= cal.params["tau2"] <= 0.05
    assert cal.params["tau1"] == pytest.approx(5.0, rel=1e-6)
    assert cal.model.n_prony == 2
    assert not [x for x in w if "outside the limits" in str(x.message)]


def test_merging_takes_neighbours_only_in_a_users_order():
    from vhfit.calibration._report import merge_terms

    G, tau, groups = merge_terms(np.array([1.0, 2.0, 3.0]), np.array([5.0, 0.03, 0.03]))
    assert groups == [(0,), (1, 2)] and G.tolist() == [1.0, 5.0]
    assert tau.tolist() == [5.0, pytest.approx(0.03)]
