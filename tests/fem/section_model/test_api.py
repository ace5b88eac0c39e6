"""The section model's API: gains, pose, options and errors."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from softcath import analytic, design
from softcath.fem.section_model import section_model, section_response


@pytest.fixture(scope="module")
def paper():
    return section_model("paper", keep_fields=True)


def test_response_is_linear_and_uses_eq9(paper):
    p = np.linspace(0, 0.6, 7)
    r = paper.response(p, "lumen")
    k, e = paper.gains("lumen")
    np.testing.assert_allclose(r.curvature, k * p)
    np.testing.assert_allclose(r.elongation, e * p)
    # eq. 9 is the uniform arc without end zones; with them, the tip angle is a fixed fraction of it
    u = replace(paper, end_zones=None).response(p, "lumen")
    x, y, th = analytic.tip_pose(u.curvature, 5.0 * (1 + u.elongation))
    np.testing.assert_allclose(u.tip_x, x)
    np.testing.assert_allclose(u.bend_angle, th)
    np.testing.assert_allclose(r.bend_angle, th * paper.end_zones.factor)
    same = section_response("paper", p, load="lumen")
    np.testing.assert_allclose(same.curvature, r.curvature)


def test_formula_ratio_and_neutral_axis(paper):
    k_formula, _ = analytic.gains(design.preset("paper"), "cap")
    assert paper.fem_formula_ratio["lumen"] == pytest.approx(
        paper.curvature_per_mm_per_MPa["lumen"] / k_formula
    )
    k = np.array(paper.stiffness)
    assert paper.neutral_axis_mm == pytest.approx(k[0, 2] / k[0, 0])
    # symmetric section: no lateral curvature, no coupling across
    assert abs(k[0, 1]) < 1e-4 * k[0, 0]


def test_wahl_coils_stiffen_bending_only():
    a = section_model("paper", loads=("cap",))
    w = section_model("paper", loads=("cap",), coil_bending="wahl")
    assert w.EA_N == pytest.approx(a.EA_N)
    assert w.EI_N_mm2 > a.EI_N_mm2
    extra = sum(
        design.coil_stiffness(c).bending_stiffness
        - design.coil_stiffness(c).axial_modulus_tension * design.coil_stiffness(c).second_moment
        for c in (design.preset("paper").coil, design.preset("paper").channel)
    )
    assert w.stiffness[2][2] - a.stiffness[2][2] == pytest.approx(extra, rel=1e-9)


def test_picture(tmp_path, paper):
    from softcath.fem.section_model.picture import axial_stress, section_picture

    path = section_picture(paper, tmp_path / "s.png", pressure=0.3)
    assert path.stat().st_size > 10_000
    mesh, op, sol = paper.fields
    s = axial_stress(op, sol.loads["cap"])
    # The axial stresses carry the cap force: their resultant is p A_lumen.
    areas = op.basis.dx.sum(axis=1)
    assert float((s * areas).sum()) == pytest.approx(op.lumen_area, rel=1e-3)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"coil_bending": "stiff"}, "coil_bending"),
        ({"silicone_poisson": 0.5}, "silicone_poisson"),
        ({"loads": ("side",)}, "load"),
        ({"mesh_size": 0.0001}, "mesh_size"),
        ({"coil_modulus": "shear"}, "coil_modulus"),
    ],
)
def test_bad_options_name_the_parameter(kwargs, match):
    with pytest.raises(design.DesignError, match=match):
        section_model("paper", **kwargs)


def test_gains_of_a_load_not_computed():
    r = section_model("paper", loads=("cap",))
    with pytest.raises(design.DesignError, match="load"):
        r.gains("lumen")
