"""The end-zone correction's closed form: its limits, an independent integration of its centreline,
its input checks, and the section model's response that applies it."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import quad

from softcath import analytic, design
from softcath.design.errors import DesignError
from softcath.fem.section_model import section_model
from softcath.fem.section_model.end_zones import (
    C_SAINT_VENANT,
    EndZones,
    end_zones,
    tip_angle,
    tip_pose,
    tip_pose_arrays,
)


def test_zero_length_end_zones_give_the_uniform_arc_of_eq9():
    zones = EndZones(length_mm=5.0, plug_mm=0.0, saint_venant_mm=0.0)
    k = np.array([0.0, 0.05, 0.2, 0.35])
    e = np.array([0.0, 0.004, 0.02, 0.03])
    x, y, th = tip_pose(k, e, zones)
    xa, ya, tha = analytic.tip_pose(k, 5.0 * (1 + e))
    np.testing.assert_allclose(np.c_[x, y, th], np.c_[xa, ya, tha], rtol=1e-14, atol=1e-15)
    assert zones.factor == 1.0


def test_straight_tip_is_as_long_as_its_stretched_zones_and_unstretched_plug():
    zones = EndZones(length_mm=6.0, plug_mm=0.3, saint_venant_mm=0.15)
    x, y, th = tip_pose(0.0, 0.02, zones)
    assert x == 0.0 and th == 0.0
    assert y == pytest.approx((6.0 - 0.3) * 1.02 + 0.3, rel=1e-14)


@pytest.mark.parametrize("kappa", [0.02, 0.3, 0.6])
def test_pose_equals_the_integrated_centreline(kappa):
    """The tip position is ∫ (sin θ, cos θ) ds along the piecewise centreline: θ growing at κ over the
    stretched arc, then constant over the Saint-Venant deficit and the plug (quadrature, an independent
    route to the closed form)."""
    zones = EndZones(length_mm=5.0, plug_mm=0.3, saint_venant_mm=0.07)
    eps = 0.015
    lam = 1 + eps
    s2 = zones.effective_length_mm * lam
    s3 = s2 + zones.saint_venant_mm * lam + zones.plug_mm

    def theta(s):
        return kappa * min(s, s2)

    pts = [s2]
    xq = quad(lambda s: np.sin(theta(s)), 0, s3, points=pts, epsabs=1e-13)[0]
    yq = quad(lambda s: np.cos(theta(s)), 0, s3, points=pts, epsabs=1e-13)[0]
    x, y, th = tip_pose(kappa, eps, zones)
    assert th == pytest.approx(theta(s3), rel=1e-14)
    assert (x, y) == pytest.approx((xq, yq), abs=1e-11)


def test_tip_angle_is_the_bend_rate_over_the_effective_length():
    d = design.preset("paper")
    z = end_zones(d)
    diameter = d.coil.outer_diameter
    assert z.plug_mm == d.tip.cap_thickness
    assert z.deficit_mm == pytest.approx(d.tip.cap_thickness + C_SAINT_VENANT * diameter, rel=1e-14)
    assert z.factor == pytest.approx((5.0 - z.deficit_mm) / 5.0, rel=1e-14)
    rate = np.array([0.01, 0.2])
    np.testing.assert_allclose(tip_angle(rate, z), rate * z.effective_length_mm, rtol=1e-15)
    # κ(1 + ε) is the bend rate: the pose's angle is the same number
    assert tip_pose(0.2 / 1.01, 0.01, z)[2] == pytest.approx(tip_angle(0.2, z), rel=1e-14)


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"length_mm": 0.0}, "length_mm = 0: must be > 0"),
        ({"plug_mm": -0.1}, "plug_mm = -0.1: must be >= 0"),
        ({"plug_mm": 5.0}, "deficit_mm"),
        ({"saint_venant_mm": 2.6}, "saint_venant_mm = 2.6"),
        ({"saint_venant_mm": float("nan")}, "saint_venant_mm = nan: must be finite"),
    ],
)
def test_bad_end_zones_name_the_parameter(kw, match):
    base = {"length_mm": 5.0, "plug_mm": 0.3, "saint_venant_mm": 0.01}
    with pytest.raises(DesignError, match=match):
        EndZones(**{**base, **kw})


def test_section_response_reports_the_tips_angle_and_keeps_the_mid_span_curvature():
    r = section_model("paper", loads=("lumen",))
    p = np.linspace(0, 0.6, 4)
    out = r.response(p, "lumen")
    k, e = r.gains("lumen")
    np.testing.assert_allclose(out.curvature, k * p)  # mid-span curvature as it was
    x, y, th = tip_pose(k * p, e * p, end_zones("paper"))
    np.testing.assert_allclose(np.c_[out.tip_x, out.tip_y, out.bend_angle], np.c_[x, y, th])
    uniform = replace(r, end_zones=None).response(p, "lumen")
    np.testing.assert_allclose(uniform.bend_angle, k * p * 5.0 * (1 + e * p))
    assert out.bend_angle[-1] == pytest.approx(uniform.bend_angle[-1] * r.end_zones.factor, rel=1e-12)
    assert r.to_json()["end_zones"]["deficit_mm"] == pytest.approx(r.end_zones.deficit_mm)


def test_the_array_form_is_the_scalar_form_design_by_design():
    zs = [EndZones(length_mm=5.0, plug_mm=0.3, saint_venant_mm=0.02), EndZones(length_mm=7.0, plug_mm=0.2)]
    k = np.array([[0.1, 0.2], [0.05, 0.3]])
    e = np.array([[0.01, 0.02], [0.0, 0.03]])
    col = {f: np.array([[getattr(z, f)] for z in zs]) for f in ("length_mm", "plug_mm", "saint_venant_mm")}
    got = tip_pose_arrays(
        k, e, length=col["length_mm"], plug=col["plug_mm"], saint_venant=col["saint_venant_mm"]
    )
    for i, z in enumerate(zs):
        np.testing.assert_allclose([g[i] for g in got], tip_pose(k[i], e[i], z), rtol=1e-15)
