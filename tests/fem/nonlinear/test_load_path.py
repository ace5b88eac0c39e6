"""The load path's predictor and first-step ramp: exact where they must be, and the same equilibria."""

import math

import numpy as np
import pytest

from softcath.fem.nonlinear.bend import bend_curve
from softcath.fem.nonlinear.load_path import FIRST_STEP_DEG, first_load_steps, predict

FREE = np.array([0, 2, 3, 5])


def _path(lams, field):
    return [(lam, field(lam)) for lam in lams]


def test_the_predictor_is_exact_on_a_quadratic_path():
    a, b, c = np.arange(6.0), np.linspace(-1, 2, 6), np.cos(np.arange(6.0))

    def u(lam):
        return a + b * lam + c * lam**2

    path = _path([0.1, 0.2, 0.3], u)
    trial = predict(path, 0.45, FREE)
    np.testing.assert_allclose(trial[FREE], u(0.45)[FREE], rtol=1e-12, atol=1e-12)
    # the constrained DOFs stay where the last equilibrium had them (the step moves them itself)
    fixed = np.setdiff1d(np.arange(6), FREE)
    np.testing.assert_array_equal(trial[fixed], u(0.3)[fixed])


def test_the_predictor_falls_back_to_the_secant_when_the_quadratic_would_amplify():
    def u(lam):
        return np.full(6, lam**2)

    # steps of 0.001 and 0.1, then a step of 0.4: Lagrange weights of hundreds
    path = _path([0.2, 0.201, 0.301], u)
    trial = predict(path, 0.701, FREE)
    secant = u(0.301) + (0.701 - 0.301) / 0.1 * (u(0.301) - u(0.201))
    np.testing.assert_allclose(trial[FREE], secant[FREE], rtol=1e-12)


def test_the_first_step_starts_where_the_last_equilibrium_is():
    path = [(0.0, np.ones(6))]
    np.testing.assert_array_equal(predict(path, 0.5, FREE), np.ones(6))


@pytest.mark.parametrize("first_target, bend_deg", [(1.0, 1.5), (0.125, 36.0 * 8), (1.0, 60.0), (0.5, 4.1)])
def test_the_ramp_bends_each_step_by_at_most_its_limit_and_lands_on_the_first_target(first_target, bend_deg):
    ramp = first_load_steps(first_target, math.radians(bend_deg))
    stops = np.concatenate([[0.0], ramp, [first_target]])
    steps = np.diff(stops)
    assert steps[0] * bend_deg <= FIRST_STEP_DEG * (1 + 1e-12)
    # doubling steps: each the sum of all before it, so Newton's growth lands on every stop
    np.testing.assert_allclose(steps[1:], stops[1:-1], rtol=1e-12)
    # no halving more than needed: one fewer would bend the first step past the limit
    if ramp.size:
        assert 2 * steps[0] * bend_deg > FIRST_STEP_DEG
    else:
        assert first_target * bend_deg <= FIRST_STEP_DEG


def test_a_path_of_large_steps_reaches_the_equilibria_of_a_finely_stepped_one():
    from softcath.design import preset

    kw = {"layers": 2, "size": 0.3, "curvature_points": 8}
    design = preset("paper")
    # two requested pressures 0.3 MPa apart: the first is ~14 degrees of bend from the unloaded tip
    coarse = bend_curve(design, [0.3, 0.6], **kw)
    assert np.degrees(coarse.bend_angle[-1]) > 20
    assert coarse.result.steps[0].load_factor < 0.5  # the ramp split the first step
    # the same equilibria reached along a finely stepped path: Newton's tolerance (rtol 1e-8 of the forces
    # in play) leaves ~1e-6 of the angle, far below what a wrong predictor-made equilibrium would show
    fine = bend_curve(design, [0.3, 0.6], substeps=4, **kw)
    np.testing.assert_allclose(coarse.bend_angle, fine.bend_angle, rtol=1e-5)


def test_an_unknown_predictor_is_refused_before_any_meshing():
    from softcath.design import preset
    from softcath.fem.nonlinear.errors import SettingError

    with pytest.raises(SettingError, match=r"predictor.*'cubic'.*must be one of"):
        bend_curve(preset("paper"), [0.1], predictor="cubic")


def test_each_predictor_extrapolates_its_own_number_of_equilibria():
    from softcath.fem.nonlinear.errors import SettingError
    from softcath.fem.nonlinear.load_path import check_predictor

    assert (check_predictor("secant"), check_predictor("quadratic")) == (2, 3)
    with pytest.raises(SettingError, match=r"predictor.*'linear'.*must be one of"):
        check_predictor("linear")
