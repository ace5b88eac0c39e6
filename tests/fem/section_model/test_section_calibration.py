"""Eq. 8 through the section model (space mapping): recovery of a known shape from its own data."""

from __future__ import annotations

import numpy as np
import pytest

from softcath import design
from softcath.design.errors import DesignError
from softcath.design.measurement import Measurement
from softcath.fem.section_model import section_model
from softcath.fem.section_model.calibration import calibrate_section


def section_series(truth, load="lumen"):
    """20 s of a 0.25 Hz raised-cosine pressure to 2 MPa at 200 Hz, noise-free, from the section model."""
    t = np.arange(0, 20.0, 1 / 200)
    p = 2.0 * (1 - np.cos(2 * np.pi * 0.25 * t)) / 2
    r = section_model(truth, loads=(load,)).response(p, load)
    return Measurement.from_arrays(
        time_s=t, pressure_MPa=p, curvature_per_mm=r.curvature, arc_length_mm=r.arc_length
    )


CASES = [
    (("a_int", "h"), {"a_int": 0.12, "h": 0.015}),
    pytest.param(("b_int", "h"), {"b_int": 0.1, "h": -0.01}, marks=pytest.mark.slow),
]


@pytest.mark.parametrize(("free", "true"), CASES)
def test_recovers_a_known_shape_from_section_model_data(free, true):
    """Two gains, two free shape numbers, noise-free: the section model's own shape comes back.

    Tolerance: the loop stops when x moves < 1e-4 (relative, 0.01 mm floor) and
    the factors the fit used match the section model's at x to 1e-4. A factor
    error delta moves the fitted gain by delta, so x by delta / |d ln(gain) / d ln(x)|;
    for these shapes that slope is above 0.1, so x is within 1e-3 relative
    (1e-5 mm absolute for h near 0). Measured: 3e-6 (a_int, h) and 2e-5 (b_int, h).
    The paper's formula alone would be off by its factor of ~3 in gain, i.e. far outside.
    """
    paper = design.preset("paper")
    shape = dict(paper.tube_shape, **true)
    res = calibrate_section(section_series(paper.with_tube_shape(**shape)), paper, free=free)
    assert res.converged and res.iterations <= 8
    for k in free:
        assert res.x_opt[k] == pytest.approx(shape[k], rel=1e-3, abs=1e-5)
    g, data = res.gains_model, res.gains_data
    assert g["curvature_per_mm_per_MPa"] == pytest.approx(data["curvature_per_mm_per_MPa"], rel=1e-4)
    assert g["elongation_per_MPa"] == pytest.approx(data["elongation_per_MPa"], rel=1e-4)
    # The last fit used the section model's own factors at its answer.
    last = res.history[-1]
    np.testing.assert_allclose(last["factors_used"], last["factors"], rtol=1e-4)
    assert res.ratio > 10 and res.to_json()["model"] == "section"


def test_bad_options_name_the_parameter():
    paper = design.preset("paper")
    m = section_series(paper)
    with pytest.raises(DesignError, match="max_iterations = 0"):
        calibrate_section(m, paper, free=("h",), max_iterations=0)
    with pytest.raises(DesignError, match="load = 'side'"):
        calibrate_section(m, paper, free=("h",), load="side")
