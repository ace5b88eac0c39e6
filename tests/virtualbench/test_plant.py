"""The truth plant: the linear model and eq. 9 with no effect, input checks, gains from the design."""

import numpy as np
import pytest

from softcath.design.errors import DataError, DesignError
from softcath.virtualbench.plant import Plant
from softcath.virtualbench.truth_effects import make_effect
from tests.virtualbench._plants import plant_with, sine


def test_no_effect_is_the_linear_model_and_eq9_pose():
    t, p = sine()
    r = plant_with().simulate(t, p)
    np.testing.assert_allclose(r.curvature_per_mm, 2.0 * p, rtol=0, atol=1e-15)
    np.testing.assert_allclose(r.arc_length_mm, 5.0 * (1 + 0.3 * p), rtol=1e-15)
    i = np.argmax(p)
    theta = 2.0 * p[i] * 5.0 * (1 + 0.3 * p[i])
    ell = 5.0 * (1 + 0.3 * p[i])
    # eq. 9 written out independently
    assert r.bend_angle_rad[i] == pytest.approx(theta, rel=1e-14)
    assert r.tip_x_mm[i] == pytest.approx(ell * (1 - np.cos(theta)) / theta, rel=1e-12)
    assert r.tip_y_mm[i] == pytest.approx(ell * np.sin(theta) / theta, rel=1e-12)


def test_bad_plant_input_names_parameter_value_and_bound():
    with pytest.raises(DesignError, match=r"plant.length_mm = 0: must be in \(0"):
        plant_with(length=0.0)
    with pytest.raises(DesignError, match="each effect name at most once"):
        plant_with(make_effect("lag"), make_effect("lag"))
    with pytest.raises(DataError, match="strictly increasing"):
        plant_with().simulate(np.array([0.0, 0.0, 1.0]), np.zeros(3))


def test_from_design_uses_the_analytic_gains():
    from softcath import analytic, design

    d = design.preset("paper")
    for load in ("cap", "lumen"):
        plant = Plant.from_design(d, load=load)
        k, e = analytic.gains(d, load)
        assert plant.curvature_per_mpa == pytest.approx(k, rel=1e-12)
        assert plant.elongation_per_mpa == pytest.approx(e, rel=1e-12)
        assert plant.length_mm == d.tip.bending_length
