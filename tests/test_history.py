"""Tests of vhfit.history: stretch histories, their validation and the integration grid."""

from __future__ import annotations

import numpy as np
import pytest
from _budget import accuracy
from hypothesis import given
from hypothesis import strategies as st

from vhfit.history import DEFORMATIONS, History, from_rest

# ----------------------------------------------------------------- strategies


@st.composite
def piecewise_histories(draw) -> History:
    """Random loading-unloading / ramp-hold histories with outputs anywhere inside.

    Stretches from 0.05 to 20 and pieces from 1 µs to 3 h long: rates over 10 decades.
    """
    k = draw(st.integers(2, 6))
    steps = draw(st.lists(st.floats(1e-6, 1e4), min_size=k - 1, max_size=k - 1))
    time = np.concatenate([[0.0], np.cumsum(steps)])
    strain = [0.0]
    for _ in range(k - 1):
        hold = draw(st.booleans())
        strain.append(strain[-1] if hold else draw(st.floats(-0.95, 19.0)))
    n_out = draw(st.integers(1, 8))
    frac = draw(st.lists(st.floats(0.0, 1.0), min_size=n_out, max_size=n_out))
    out = np.clip(np.asarray(frac) * time[-1], 0.0, time[-1])
    return History.piecewise_linear(time, strain, out)


# ------------------------------------------------------------------ builders


def test_constant_rate_outputs_at_strain_over_rate():
    h = History.constant_rate([-0.1, -0.25, -0.5], strain_rate=-100.0)
    np.testing.assert_allclose(h.out_time, [0.001, 0.0025, 0.005], rtol=1e-15)
    np.testing.assert_array_equal(h.time, [0.0, 0.005])
    np.testing.assert_allclose(h.stretch, [1.0, 0.5], rtol=1e-15)
    np.testing.assert_allclose(h.out_strain, [-0.1, -0.25, -0.5], rtol=1e-14)


def test_constant_rate_tension_is_positive_and_linear_in_time():
    h = History.constant_rate(np.linspace(0.0, 1.0, 6), strain_rate=0.5)
    assert h.duration == pytest.approx(2.0)
    np.testing.assert_allclose(h.stretch_at(h.out_time), 1.0 + 0.5 * h.out_time, rtol=1e-15)


def test_constant_rate_zero_strain_only_is_a_zero_length_history():
    h = History.constant_rate([0.0, 0.0], strain_rate=-1.0)
    assert h.duration == 0.0
    np.testing.assert_array_equal(h.out_stretch, [1.0, 1.0])
    t, lam, idx = h.grid(0.01)
    np.testing.assert_array_equal(t, [0.0])
    np.testing.assert_array_equal(idx, [0, 0])


def test_piecewise_linear_defaults_outputs_to_sample_times():
    h = History.piecewise_linear([0.0, 1.0, 2.0, 5.0], [0.0, -0.3, -0.3, 0.0])
    np.testing.assert_array_equal(h.out_time, h.time)
    np.testing.assert_allclose(h.stretch, [1.0, 0.7, 0.7, 1.0])
    assert h.stretch_at(1.5) == pytest.approx(0.7)
    assert h.stretch_at(3.5) == pytest.approx(0.85)


def test_with_outputs_keeps_the_path():
    h = History.piecewise_linear([0.0, 1.0], [0.0, 0.5]).with_outputs([0.25, 0.5])
    np.testing.assert_allclose(h.out_strain, [0.125, 0.25])
    np.testing.assert_array_equal(h.time, [0.0, 1.0])


# ---------------------------------------------------------------- bad input


@pytest.mark.parametrize("rate", [0.0, np.nan, np.inf, -np.inf])
def test_constant_rate_rejects_zero_or_non_finite_rate(rate):
    with pytest.raises(ValueError, match=r"strain_rate = .* finite, non-zero"):
        History.constant_rate([-0.1], strain_rate=rate)


def test_constant_rate_rejects_non_numeric_rate():
    with pytest.raises(ValueError, match="strain_rate must be a number"):
        History.constant_rate([-0.1], strain_rate="fast")


def test_constant_rate_rejects_strain_of_opposite_sign_to_rate():
    with pytest.raises(ValueError, match=r"strain\[1\] = 0.1 has the opposite sign"):
        History.constant_rate([-0.1, 0.1], strain_rate=-1.0)


@pytest.mark.parametrize("bad", [-1.0, -1.5])
def test_constant_rate_rejects_non_positive_stretch(bad):
    with pytest.raises(ValueError, match=r"strain\[1\] = .* non-positive stretch"):
        History.constant_rate([-0.5, bad], strain_rate=-1.0)


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_strain_is_named_with_its_index(bad):
    with pytest.raises(ValueError, match=r"strain\[2\] = .* is not finite"):
        History.constant_rate([-0.1, -0.2, bad], strain_rate=-1.0)
    with pytest.raises(ValueError, match=r"strain\[2\] = .* is not finite"):
        History.piecewise_linear([0.0, 1.0, 2.0], [0.0, 0.1, bad])


def test_non_finite_time_is_named_with_its_index():
    with pytest.raises(ValueError, match=r"time\[1\] = nan is not finite"):
        History.piecewise_linear([0.0, np.nan], [0.0, 0.1])


def test_piecewise_linear_rejects_mismatched_lengths():
    with pytest.raises(ValueError, match="time and strain must have the same length, got 3 and 2"):
        History.piecewise_linear([0.0, 1.0, 2.0], [0.0, 0.1])


def test_piecewise_linear_rejects_late_start():
    with pytest.raises(ValueError, match=r"time\[0\] = 0.5: histories start at t = 0"):
        History.piecewise_linear([0.5, 1.0], [0.0, 0.1])


@pytest.mark.parametrize("time", [[0.0, 1.0, 1.0], [0.0, 2.0, 1.0]])
def test_piecewise_linear_rejects_non_increasing_time(time):
    with pytest.raises(ValueError, match=r"time must be strictly increasing, but time\[2\]"):
        History.piecewise_linear(time, [0.0, 0.1, 0.2])


def test_piecewise_linear_rejects_non_positive_stretch():
    with pytest.raises(ValueError, match=r"strain\[1\] = -1 gives a non-positive stretch"):
        History.piecewise_linear([0.0, 1.0], [0.0, -1.0])


@pytest.mark.parametrize("out", [[-0.1], [2.5]])
def test_out_time_outside_history_is_rejected(out):
    h = History.piecewise_linear([0.0, 2.0], [0.0, 0.1])
    with pytest.raises(ValueError, match=r"out_time must lie within the history \[0, 2\] s"):
        History.piecewise_linear([0.0, 2.0], [0.0, 0.1], out_time=out)
    with pytest.raises(ValueError, match="out_time must lie within"):
        h.with_outputs(out)


def test_two_dimensional_and_empty_input_is_rejected():
    with pytest.raises(ValueError, match=r"strain must be a 1-D array, got shape \(2, 1\)"):
        History.constant_rate([[-0.1], [-0.2]], strain_rate=-1.0)
    with pytest.raises(ValueError, match="strain is empty"):
        History.constant_rate([], strain_rate=-1.0)


# --------------------------------------------------------------------- grid


def test_grid_of_a_ramp_is_uniform_in_log_stretch():
    h = History.constant_rate([-0.5], strain_rate=-1.0)
    t, lam, idx = h.grid(0.01)
    steps = np.diff(np.log(lam))
    n = int(np.ceil(np.log(2.0) / 0.01))
    assert steps.size == n
    np.testing.assert_allclose(steps, -np.log(2.0) / n, rtol=1e-9)
    np.testing.assert_array_equal(idx, [n])


def test_grid_hold_needs_a_single_step():
    h = History.piecewise_linear([0.0, 1.0, 100.0], [0.0, -0.2, -0.2])
    t, lam, _ = h.grid(0.05)
    assert np.count_nonzero(t > 1.0) == 1


@accuracy
@given(piecewise_histories(), st.sampled_from([0.1, 0.02, 0.005]))
def test_grid_contains_breakpoints_and_outputs_and_bounds_the_step(h, dlog):
    t, lam, idx = h.grid(dlog)
    assert t[0] == 0.0 and t[-1] == h.duration
    assert np.all(np.diff(t) > 0)
    # every breakpoint is a node, exactly (turning points are never clipped)
    assert np.isin(h.time, t).all()
    # every output time is a node and idx points at it
    np.testing.assert_array_equal(t[idx], h.out_time)
    # node stretches lie on the path
    np.testing.assert_allclose(lam, h.stretch_at(t), rtol=1e-15)
    # ln λ changes by at most dlog per step, up to the snap onto outputs: each end of a
    # step may move outwards by a quarter of its neighbouring step, whose length in t
    # differs from this one's by at most a factor e^dlog (λ is linear in t along a piece
    # and the steps are uniform in ln λ): 1 + 2 · 0.25 · e^dlog.
    bound = dlog * (1 + 0.5 * np.exp(dlog))
    assert np.max(np.abs(np.diff(np.log(lam)))) <= bound * (1 + 1e-9)


# ------------------------------------------------------------------ from rest
def test_from_rest_prepends_the_rest_point_only_when_the_record_starts_later():
    t, e = from_rest([0.5, 1.0, 2.0], [-0.1, -0.2, -0.1])
    np.testing.assert_array_equal(t, [0.0, 0.5, 1.0, 2.0])
    np.testing.assert_array_equal(e, [0.0, -0.1, -0.2, -0.1])
    t0, e0 = np.array([0.0, 1.0]), np.array([0.05, 0.3])  # a jump at t = 0 stays a jump
    t, e = from_rest(t0, e0)
    assert t is t0 and e is e0  # float arrays pass through untouched (no copy)
    t, e = from_rest([0, 2], [0, 1])  # integers come back as floats
    assert t.dtype == e.dtype == np.float64


def test_from_rest_feeds_piecewise_linear():
    h = History.piecewise_linear(*from_rest([1.0, 3.0], [-0.2, -0.2]))
    np.testing.assert_array_equal(h.time, [0.0, 1.0, 3.0])
    np.testing.assert_allclose(h.stretch, [1.0, 0.8, 0.8])


@pytest.mark.parametrize("t, e", [([], []), ([0.0, 1.0], [0.0]), ([[0.0, 1.0]], [[0.0, 1.0]])])
def test_from_rest_rejects_mismatched_or_empty_paths(t, e):
    with pytest.raises(ValueError, match="from_rest: t has shape .* same, non-zero length"):
        from_rest(t, e)


# ------------------------------------------------------------ every test mode
def test_deformations_are_the_five_homogeneous_tests():
    assert DEFORMATIONS == ("uniaxial", "equibiaxial", "planar", "biaxial", "simple_shear")
    h = History.constant_rate([0.1], 1.0)
    assert h.deformation == "uniaxial" and h.stretch2 is None and not h.is_equilibrium
    np.testing.assert_array_equal(h.out_direction, [1])


def test_simple_shear_paths_carry_the_amount_of_shear_of_either_sign():
    h = History.piecewise_linear([0.0, 1.0, 2.0], [0.0, -2.5, 1.5], deformation="simple_shear")
    np.testing.assert_array_equal(h.stretch, [0.0, -2.5, 1.5])   # γ, not 1 + γ
    np.testing.assert_allclose(h.out_strain, [0.0, -2.5, 1.5])
    np.testing.assert_array_equal(h.out_loaded_stretch, [1.0, 1.0, 1.0])
    r = History.constant_rate([-1.5, -3.0], -3.0, deformation="simple_shear")
    np.testing.assert_allclose(r.out_time, [0.5, 1.0])
    np.testing.assert_array_equal(r.stretch, [0.0, -3.0])


def test_biaxial_paths_carry_both_stretches_and_both_directions():
    h = History.piecewise_linear([0.0, 1.0, 2.0], [0.0, 0.5, 0.5], deformation="biaxial",
                                 strain2=[0.0, 0.1, 0.8])
    np.testing.assert_allclose(h.stretch2, [1.0, 1.1, 1.8])
    assert h.stretch2_at(1.5) == pytest.approx(1.45)
    h2 = h.with_outputs([0.5, 1.5], [2, 1])
    np.testing.assert_array_equal(h2.out_direction, [2, 1])
    np.testing.assert_allclose(h2.out_loaded_stretch, [1.05, 1.5])   # λ2(0.5), λ1(1.5)
    # a constant-rate biaxial ramp: λ2 at a constant rate too
    r = History.constant_rate([0.1, 0.2], 0.1, deformation="biaxial", strain2=[0.05, 0.1])
    np.testing.assert_allclose(r.stretch2, [1.0, 1.1])
    with pytest.raises(ValueError, match="strain2 of a constant-rate biaxial ramp must be "
                                         "proportional to strain"):
        History.constant_rate([0.1, 0.2], 0.1, deformation="biaxial", strain2=[0.05, 0.05])


def test_equibiaxial_second_direction_and_planar_loaded_stretch():
    h = History.equilibrium([0.5, -0.2], deformation="equibiaxial").with_outputs([0, 1], [2, 2])
    np.testing.assert_allclose(h.out_loaded_stretch, [1.5, 0.8])
    with pytest.raises(ValueError, match="out_direction 2 needs a second loaded direction: "
                                         "'planar' has none"):
        History.equilibrium([0.5], deformation="planar").with_outputs([0], [2])
    with pytest.raises(ValueError, match="out_direction must give 1 or 2 for each output"):
        History.equilibrium([0.5], deformation="biaxial", strain2=[0.1]).with_outputs([0], [3])


def test_equilibrium_histories_are_unordered_samples_without_time():
    h = History.equilibrium([0.3, -0.1, 0.2, 0.3])
    assert h.is_equilibrium and h.duration == 0.0
    np.testing.assert_allclose(h.out_strain, [0.3, -0.1, 0.2, 0.3])
    np.testing.assert_allclose(h.with_outputs([2, 0]).out_strain, [0.2, 0.3])
    with pytest.raises(ValueError, match="an equilibrium history has no time grid"):
        h.grid(0.01)
    with pytest.raises(ValueError, match="numbers its samples: give whole numbers"):
        h.with_outputs([0.5])
    with pytest.raises(ValueError, match=r"strain\[1\] = -1.2 gives a non-positive stretch"):
        History.equilibrium([0.1, -1.2], deformation="planar")
    # simple shear has no such limit: γ = -1.2 is a shear like any other
    np.testing.assert_allclose(
        History.equilibrium([-1.2], deformation="simple_shear").out_strain, [-1.2])


@pytest.mark.parametrize("build", [
    lambda **kw: History.constant_rate([0.1], 1.0, **kw),
    lambda **kw: History.piecewise_linear([0.0, 1.0], [0.0, 0.1], **kw),
    lambda **kw: History.equilibrium([0.1], **kw),
])
def test_every_builder_checks_the_deformation_and_strain2(build):
    with pytest.raises(ValueError, match="deformation = 'pure_shear' is unknown: choose one "
                                         "of uniaxial, equibiaxial, planar, biaxial, "
                                         "simple_shear"):
        build(deformation="pure_shear")
    with pytest.raises(ValueError, match="deformation='biaxial' needs strain2"):
        build(deformation="biaxial")
    with pytest.raises(ValueError, match="strain2 is only for deformation='biaxial', not "
                                         "'equibiaxial'"):
        build(deformation="equibiaxial", strain2=[0.1])


@st.composite
def mode_histories(draw):
    """Random piecewise histories of every mode but uniaxial (tested above)."""
    mode = draw(st.sampled_from(DEFORMATIONS[1:]))
    k = draw(st.integers(2, 5))
    time = np.concatenate([[0.0], np.cumsum(draw(st.lists(st.floats(1e-6, 1e4), min_size=k - 1,
                                                          max_size=k - 1)))])
    lo, hi = (-5.0, 5.0) if mode == "simple_shear" else (-0.7, 3.0)
    e1 = [0.0] + draw(st.lists(st.floats(lo, hi), min_size=k - 1, max_size=k - 1))
    e2 = [0.0] + draw(st.lists(st.floats(-0.7, 3.0), min_size=k - 1, max_size=k - 1))
    frac = draw(st.lists(st.floats(0.0, 1.0), min_size=1, max_size=6))
    out = np.asarray(frac) * time[-1]
    return History.piecewise_linear(time, e1, out, deformation=mode,
                                    strain2=e2 if mode == "biaxial" else None)


@accuracy
@given(mode_histories(), st.sampled_from([0.1, 0.02, 0.005]))
def test_grid_bounds_every_principal_stretch_or_the_shear_per_step(h, dlog):
    """ln λ1, ln λ2 and ln λ3 (γ in simple shear) change by at most dlog a step (up to
    the snap onto outputs: a factor 1 + 2 · 0.25 · e^(2 dlog))."""
    t, x1, idx = h.grid(dlog)
    assert t[0] == 0.0 and t[-1] == h.duration and np.all(np.diff(t) > 0)
    assert np.isin(h.time, t).all()
    np.testing.assert_array_equal(t[idx], h.out_time)
    bound = dlog * (1 + 0.5 * np.exp(2 * dlog)) * (1 + 1e-9)
    if h.deformation == "simple_shear":
        assert np.max(np.abs(np.diff(x1))) <= bound
        return
    l1 = x1
    l2 = {"equibiaxial": l1, "planar": np.ones_like(l1)}.get(h.deformation,
                                                             h.stretch2_at(t))
    for lam in (l1, l2, 1.0 / (l1 * l2)):
        assert np.max(np.abs(np.diff(np.log(lam)))) <= bound
