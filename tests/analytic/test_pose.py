"""Tip pose (eq. 9), its θ → 0 limit, and the inverse kinematics."""

import numpy as np
import pytest

from softcath import analytic, design


def test_pose_closed_form_and_zero_limit():
    x, y, th = analytic.tip_pose(np.array([0.0, 1e-12, np.pi / 10, -np.pi / 10]), 5.0)
    assert x[0] == 0.0 and y[0] == 5.0 and np.all(np.isfinite(x))
    assert x[1] == pytest.approx(5.0 * 5e-12 / 2, rel=1e-9)  # x ≈ Lθ/2 for small θ
    th2 = th[2]
    assert x[2] == pytest.approx(5.0 * (1 - np.cos(th2)) / th2, rel=1e-14)
    assert y[2] == pytest.approx(5.0 * np.sin(th2) / th2, rel=1e-14)
    assert x[3] == pytest.approx(-x[2]) and y[3] == pytest.approx(y[2])


def test_quarter_circle_and_pose_matrix():
    length = 5.0
    kappa = np.pi / 2 / length
    x, y, th = analytic.tip_pose(kappa, length)
    r = 1 / kappa
    assert float(x) == pytest.approx(r, rel=1e-14) and float(y) == pytest.approx(r, rel=1e-14)
    t = analytic.pose_matrix(kappa, length)
    assert t[:2, 3] == pytest.approx([r, r])
    assert np.allclose(t[:3, :3] @ t[:3, :3].T, np.eye(3))


def test_pressure_for_bend_angle_round_trip():
    d = design.preset("paper")
    targets = np.radians([5.0, 45.0, 90.0, 150.0])
    p = analytic.pressure_for_bend_angle(d, targets)
    assert np.allclose(analytic.response(d, p).bend_angle, targets, rtol=1e-12)


def test_pressure_for_tip_round_trip():
    d = design.preset("paper")
    r = analytic.response(d, 1.7)
    p, miss = analytic.pressure_for_tip(d, tip_x=float(r.tip_x))
    assert p == pytest.approx(1.7, rel=1e-9) and miss < 1e-9
    p2, miss2 = analytic.pressure_for_tip(d, tip_x=float(r.tip_x), tip_y=float(r.tip_y))
    assert p2 == pytest.approx(1.7, rel=1e-6) and miss2 < 1e-6
    with pytest.raises(design.DesignError, match="tip_x = 50: exceeds the reach"):
        analytic.pressure_for_tip(d, tip_x=50.0)


def test_non_finite_pressure_is_rejected():
    with pytest.raises(design.DesignError, match="pressure = nan: must be a finite pressure in MPa"):
        analytic.response(design.preset("paper"), [1.0, np.nan])
    with pytest.raises(design.DesignError, match="pressure = 1e\\+300: must be within ±100 MPa"):
        analytic.response(design.preset("paper"), [1e300])
    with pytest.raises(design.DesignError, match="pressure = -101: must be within ±100 MPa"):
        analytic.response(design.preset("paper"), np.array([[0.5], [-101.0]]))
    assert analytic.response(design.preset("paper"), 100.0).curvature.shape == ()  # the bound itself passes
