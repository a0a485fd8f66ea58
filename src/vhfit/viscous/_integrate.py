"""The integrator of the viscous networks (in progress)."""

from __future__ import annotations


def model_stress(model, time, stretch, *, deformation, stretch2, measure):
    raise NotImplementedError("the network integrator is not written yet")


def model_creep(model, stress, time, *, deformation, measure):
    raise NotImplementedError("the network integrator is not written yet")
