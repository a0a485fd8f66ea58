"""The protocol of test items (vhfit.data.TestItem): curves, frequency sweeps and
relaxation tests answer the same questions, and consumers ask them, not their types."""

from __future__ import annotations

import typing

import numpy as np
import pytest

import vhfit
from vhfit.data import is_moduli


def items():
    curve = vhfit.Curve(strain=[-0.1, -0.2, -0.3], stress=[-0.1, -0.25, -0.4],
                        strain_rate=-1.0, name="ramp")
    sweep = vhfit.FrequencySweep(frequency=[0.1, 1.0], storage=[2.0, 3.0], loss=[0.5, 0.4],
                                 name="dma")
    relax = vhfit.Relaxation(time=[0.0, 1.0, 10.0], modulus=[3.0, 2.0, 1.5], name="relax")
    return curve, sweep, relax


def test_every_item_satisfies_the_protocol_with_every_member():
    proto = vhfit.data.TestItem
    members = sorted(set(proto.__annotations__) | {n for n in vars(proto)
                                                    if not n.startswith("_")})
    assert {"name", "is_moduli", "deformation", "measure", "history", "target_stress",
            "target_weights", "target_scale", "weight", "strain_rate"} <= set(members)
    for item in items():
        assert isinstance(item, vhfit.data.TestItem)
        for n in members:
            getattr(item, n)  # present, no default needed
    assert not isinstance(np.zeros(3), vhfit.data.TestItem)


def test_items_say_what_they_are():
    curve, sweep, relax = items()
    assert [it.is_moduli for it in items()] == [False, True, True]
    assert [is_moduli(it) for it in items()] == [False, True, True]
    # small-strain tests: uniaxial (E-type), no rate, one segment, no point weights
    for it in (sweep, relax):
        assert (it.deformation, it.measure, it.strain_rate, it.n_segments) == (
            "uniaxial", "true", None, 1)
        assert not it.is_equilibrium and not it.is_constant_rate
        assert it.target_weights is None
        assert it.target_scale.shape == it.target_stress.shape
    # a curve's relative errors are scaled by the curve's RMS (paper Eq. 20), not per point
    assert curve.target_scale is None
    assert curve.deformation == "uniaxial" and curve.is_constant_rate


def test_calibrate_refuses_what_is_not_a_test_item():
    class HalfItem:  # a history and targets, but none of the rest of the protocol
        history = vhfit.History.constant_rate([-0.1, -0.2], -1.0)
        target_stress = np.array([-0.1])

    with pytest.raises(ValueError, match=r"curves\[0\] is a HalfItem"):
        vhfit.calibrate([HalfItem()], n_prony=0)


def test_the_protocol_is_typed():
    hints = typing.get_type_hints(vhfit.data.TestItem)
    assert hints["is_moduli"] is bool and hints["name"] is str


def test_a_master_curve_refuses_a_stress_strain_curve_with_the_fix():
    curve, _, _ = items()
    sweep = vhfit.FrequencySweep(frequency=[0.1, 1.0], storage=[2.0, 3.0], loss=[0.5, 0.4],
                                 temperature=20.0)
    with pytest.raises(vhfit.data.DataError, match="item 2 is a Curve: give vhfit.FrequencySweep"):
        vhfit.tts.master_curve([sweep, curve])


def test_objective_reads_weights_and_point_scales_of_items_only():
    curve, sweep, _ = items()
    obj = vhfit.objective.Objective([curve.replace(weight=3.0), sweep])
    np.testing.assert_array_equal(obj.weights[: curve.n_points], 3.0)
    # arrays of targets carry no weights: all alike
    bare = vhfit.objective.Objective([curve.target_stress, sweep.target_stress])
    np.testing.assert_array_equal(bare.weights, 1.0)


def test_temperature_is_one_member_for_curves_and_moduli():
    """A curve's temperature comes from its metadata, a sweep's from its own field."""
    c = vhfit.Curve(strain=[-0.1, -0.2], stress=[-0.1, -0.2], strain_rate=-1.0,
                    metadata={"temperature": "40"})
    s = vhfit.FrequencySweep(frequency=[1.0, 2.0], storage=[1.0, 2.0], loss=[0.1, 0.2],
                             temperature=25.0)
    bare = vhfit.Curve(strain=[-0.1, -0.2], stress=[-0.1, -0.2], strain_rate=-1.0)
    assert (c.temperature, s.temperature, bare.temperature) == (40.0, 25.0, None)
    assert c.shifted(10.0).temperature is None  # at the reference: nothing left to shift
