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
    K_CAP_TILT,
    EndZones,
    end_zones,
    tip_angle,
    tip_pose,
    tip_pose_arrays,
)
from softcath.studies.sweep.random_designs import random_designs


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


@pytest.mark.parametrize(("kappa", "pressure"), [(0.02, None), (0.3, None), (0.6, None), (0.3, 0.8)])
def test_pose_equals_the_integrated_centreline(kappa, pressure):
    """The tip position is ∫ (sin θ, cos θ) ds along the piecewise centreline: θ growing at κ over the
    stretched arc, constant over the Saint-Venant deficit, then the plug turned on by its tilt
    (quadrature, an independent route to the closed form)."""
    zones = EndZones(length_mm=5.0, plug_mm=0.3, saint_venant_mm=0.07, cap_modulus_mpa=1.5)
    eps = 0.015
    lam = 1 + eps
    s2 = zones.effective_length_mm * lam
    s_plug = s2 + zones.saint_venant_mm * lam
    s3 = s_plug + zones.plug_mm
    tilt = 0.0 if pressure is None else K_CAP_TILT * (pressure / 1.5) ** 2

    def theta(s):
        return kappa * min(s, s2) + (tilt if s > s_plug else 0.0)

    pts = [s2, s_plug]
    xq = quad(lambda s: np.sin(theta(s)), 0, s3, points=pts, epsabs=1e-13)[0]
    yq = quad(lambda s: np.cos(theta(s)), 0, s3, points=pts, epsabs=1e-13)[0]
    x, y, th = tip_pose(kappa, eps, zones, pressure=pressure)
    assert th == pytest.approx(theta(s3), rel=1e-14)
    assert (x, y) == pytest.approx((xq, yq), abs=1e-11)


def test_the_cap_tilt_is_k_times_the_squared_pressure_over_the_cap_modulus():
    d = design.preset("paper")
    z = end_zones(d)
    assert z.cap_modulus_mpa == d.tube.material.youngs_modulus  # the plug is the tube's sealed end
    p = np.array([0.0, 0.3, 0.7])
    np.testing.assert_allclose(z.cap_tilt(p), K_CAP_TILT * (p / 2.46) ** 2, rtol=1e-15)
    rate = np.array([0.0, 0.08, 0.25])
    np.testing.assert_allclose(tip_angle(rate, z, pressure=p), tip_angle(rate, z) + z.cap_tilt(p), rtol=1e-15)
    # without a pressure (the linear tiers) or a modulus (a rigid plug) there is no tilt
    assert tip_pose(0.1, 0.01, z)[2] == tip_angle(0.1 * 1.01, z)
    rigid = replace(z, cap_modulus_mpa=None)
    np.testing.assert_array_equal(rigid.cap_tilt(p), 0.0)
    with pytest.raises(DesignError, match="pressure"):
        z.cap_tilt(-0.1)


#: The converged 3-D tips of docs/validation.md ("The tip's angle": lumen load, mixed u-p, size 0.15 mm,
#: 12 segments per circle, 16 layers with the 8-layer companion, extrapolated by
#: ``fem.nonlinear.reference.estimate_tip``): (design, p [MPa], extrapolated tip angle [deg], its
#: extrapolated deficit δ∞ [mm]). The 3-D's own extrapolated bend rate is tip / (L − δ∞).
CONVERGED_3D_TIPS = [
    ("paper", 0.1, 6.5, 0.305),
    ("paper", 0.2, 14.0, 0.302),
    ("paper", 0.3, 22.5, 0.297),
    ("paper", 0.6, 54.7, 0.278),
    ("paper", 0.7, 67.8, 0.268),
    ("seed 2 #1", 0.05, 7.8, 0.319),
    ("seed 2 #1", 0.1, 16.4, 0.314),
    ("seed 2 #1", 0.2, 36.4, 0.299),
    ("seed 2 #1", 0.3, 60.3, 0.280),
    ("seed 2 #1", 0.35, 73.5, 0.271),
    ("seed 2 #1", 0.4, 87.6, 0.260),
    ("seed 2 #1", 0.45, 102.3, 0.245),
    ("seed 2 #0", 0.2, 12.1, 0.304),
    ("seed 2 #0", 0.4, 27.3, 0.290),
]


def _closed_form_over_3d(c_sv=None, k_tilt=None) -> np.ndarray:
    """The closed form on each recorded tip's own 3-D bend rate over that tip (default C, K: the module's)."""
    seed2 = random_designs(2, seed=2)
    designs = {"paper": design.preset("paper"), "seed 2 #0": seed2[0], "seed 2 #1": seed2[1]}
    out = []
    for name, p, tip_deg, deficit in CONVERGED_3D_TIPS:
        d = designs[name]
        z = end_zones(d)
        if c_sv is not None:
            z = replace(z, saint_venant_mm=c_sv * d.coil.outer_diameter)
        tip = np.radians(tip_deg)
        rate = tip / (d.tip.bending_length - deficit)
        if k_tilt is None:
            tilt = z.cap_tilt(p)
        else:
            assert z.cap_modulus_mpa is not None
            tilt = k_tilt * (p / z.cap_modulus_mpa) ** 2
        out.append((rate * z.effective_length_mm + tilt) / tip)
    return np.array(out)


def test_the_correction_gives_the_converged_3d_tips_on_their_own_bend_rate():
    """C and K were fitted on these 14 tips (residuals ≤ 0.27 %). Bound 0.5 %: the fit's residual
    with the records' rounding (0.001 mm of deficit is 0.02 %; 0.05° of angle moves only the tilt's
    share, < 0.1 %). The former rule (C = −0.012, no tilt) misses them by up to 0.7 %, so the bound
    tells the two apart."""
    ratio = _closed_form_over_3d()
    assert np.all(np.abs(ratio - 1.0) < 0.005), ratio
    former = _closed_form_over_3d(c_sv=-0.012, k_tilt=0.0)
    assert np.max(np.abs(former - 1.0)) > 0.006, former


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
        ({"cap_modulus_mpa": 0.0}, "cap_modulus_mpa = 0: must be finite and > 0"),
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
    assert r.end_zones is not None
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


#: Held out (not in the fit): the 3-D tips of ``random_designs(5, seed=4)`` #0-#3 walked toward 90° in
#: docs/validation.md ("Random valid designs walked up to 90°": lumen load, mixed u-p, default section,
#: 9 layers (#1: 16) with the half-layer companion, extrapolated by ``estimate_tip``): (design index,
#: p [MPa], extrapolated tip [deg], its stated error). Three of the four have the 0.89-0.90 mm coils
#: the former rule missed by up to 10 %.
HELD_OUT_3D_TIPS = [
    (0, 0.333, 11.7, 0.021),
    (0, 0.667, 26.3, 0.032),
    (0, 1.0, 43.1, 0.040),
    (1, 0.188, 23.3, 0.011),
    (1, 0.377, 53.0, 0.016),
    (1, 0.565, 88.9, 0.020),
    (2, 0.333, 13.9, 0.019),
    (2, 0.667, 29.5, 0.029),
    (2, 1.0, 45.7, 0.036),
    (3, 0.333, 10.5, 0.021),
    (3, 0.667, 25.2, 0.032),
    (3, 1.0, 43.3, 0.041),
]


def test_the_finite_strain_tier_gives_the_held_out_3d_tips():
    """The finite-strain section model's tip (its mid-span rate with the correction and the plug's
    tilt) against held-out 3-D tips, to p / E_cap = 0.74. Bound: the tiers' 3 % mid-span target plus
    each 3-D tip's stated error. Measured 0.979-1.029; the former rule gave 0.895 on #2 at 1 MPa,
    outside its 6.6 % bound."""
    from softcath.fem.section_model.finite_strain import section_curve

    designs = random_designs(4, seed=4)
    for i in range(4):
        rows = [r for r in HELD_OUT_3D_TIPS if r[0] == i]
        curve = section_curve(designs[i], [r[1] for r in rows], load="lumen", linear_gain=False)
        tips, errors = np.radians([r[2] for r in rows]), np.array([r[3] for r in rows])
        ratio = np.asarray(curve.bend_angle_rad) / tips
        assert np.all(np.abs(ratio - 1.0) < 0.03 + errors), (i, ratio)
