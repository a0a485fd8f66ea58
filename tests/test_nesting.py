"""A law fits data at least as well as the laws it contains (issue: nesting).

Yeoh and the reduced polynomial of order 3 contain neo-Hooke (their higher constants
zero), polynomial 3 contains it too: on data a contained law generated, the bigger law's
default search must end no worse. The cases have a point at a very small strain, as
digitized records do: there a higher-order term (I1 − 3)^k all but vanishes, so the
constants' own search ranges are enormous (one term alone must reach each target), and
a search that drew shapes in those ranges found only shapes ruled by the highest term.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import vhfit

#: the tolerance of a nesting violation: err(bigger) > 1.02 err(contained) + 0.02 points
REL, ABS = 1.02, 0.02


def _curves(C10, G1, tau1, noise, seed, rates=(0.01, 0.05)):
    """Loading-unloading to λ = 2.5 of a neo-Hooke material with one Prony term; each
    curve has a point at 0.2 % strain; relative noise of ``noise``."""
    m = vhfit.ViscoHyperelastic("neo_hooke", 1)
    rng = np.random.default_rng(seed)
    out = []
    for r in rates:
        tmax = 1.5 / r
        t = np.concatenate([[0.0, 0.002 / r], np.linspace(0.1 * tmax, 2 * tmax, 24)])
        e = 1.5 - np.abs(t - tmax) * r
        e[0] = 0.0
        s = m.stress(dict(C10=C10, G1=G1, tau1=tau1), strain=e, time=t,
                     measure="engineering")
        s = s * (1 + noise * rng.standard_normal(s.size))
        out.append(vhfit.Curve(strain=e[1:], stress=s[1:], time=t[1:],
                               measure="engineering"))
    return out


def _err(curves, law):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return vhfit.calibrate(curves, hyperelastic=law, n_prony=1, seed=0).rmsape


@pytest.mark.parametrize("law", ["yeoh", "reduced_polynomial3", "polynomial3"])
def test_a_cubic_law_fits_neo_hooke_data_with_a_small_strain_point_as_well(law):
    # kPa-level stresses as VHB 4910: before the search drew shapes in term units,
    # Yeoh ended at 45 % and polynomial 3 at 23 % where neo-Hooke fits 2.2 %
    curves = _curves(0.01, 0.05, 20.0, 0.03, 1)
    small = _err(curves, "neo_hooke")
    assert small < 3.0
    assert _err(curves, law) <= REL * small + ABS


@pytest.mark.parametrize("law", ["yeoh", "polynomial3"])
def test_the_search_alone_fits_a_cubic_law_where_the_contained_law_fits(law):
    """The cause, not the floor: a bound on C10 leaves the fit unseeded by neo-Hooke
    (no nesting; its settings differ), and the search's own shapes, drawn in term units,
    reach neo-Hooke's error (in the constants' own search ranges they end at 41 %/23 %)."""
    curves = _curves(0.01, 0.05, 20.0, 0.03, 1)
    small = _err(curves, "neo_hooke")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = vhfit.calibrate(curves, hyperelastic=law, n_prony=1, seed=0,
                              bounds={"C10": (0.0, 10.0)})
    assert "nested" not in cal.options
    assert cal.rmsape <= REL * small + ABS


@settings(max_examples=4, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(C10=st.floats(1e-3, 1.0), g=st.floats(0.5, 10.0), log_tau=st.floats(0.5, 2.0),
       noise=st.sampled_from([0.0, 0.02]), seed=st.integers(0, 100))
def test_yeoh_fits_neo_hooke_data_at_least_as_well(C10, g, log_tau, noise, seed):
    curves = _curves(C10, g * C10, 10.0**log_tau, noise, seed)
    assert _err(curves, "yeoh") <= REL * _err(curves, "neo_hooke") + ABS
