"""Each tier's response is the tier's own computation: the same numbers as a direct call."""

from __future__ import annotations

import numpy as np
import pytest

from softcath import analytic, design, models
from softcath.fem.section_model.end_zones import end_zones
from softcath.studies.predict.ranges import base_table
from softcath.studies.sweep.variants import build_variant

PAPER = design.preset("paper")
P = np.array([0.0, 0.05, 0.1])


OTHER = build_variant(base_table("paper"), {"tip.bending_length": 6.0, "tube.a_int": 0.1})


@pytest.mark.parametrize("load", ["cap", "lumen"])
def test_paper_response_is_the_formula(load):
    r = models.response(PAPER, P, tier="paper", load=load)
    direct = analytic.response(PAPER, P, load)
    # the same computation: equal to rounding
    for mine, theirs in (
        (r.curvature_per_mm, direct.curvature),
        (r.elongation, direct.elongation),
        (r.bend_angle_rad, direct.bend_angle),
        (r.tip_x_mm, direct.tip_x),
        (r.tip_y_mm, direct.tip_y),
    ):
        np.testing.assert_allclose(mine, theirs, rtol=1e-12, atol=0)
    # a uniform arc: the tip-level curvature (bend angle over the deformed length) is the arc's
    np.testing.assert_allclose(r.tip_curvature_per_mm, r.curvature_per_mm, rtol=1e-12, atol=1e-18)
    assert np.isnan(r.lumen_volume_change_mm3).all()
    assert (r.tier, r.load, r.parameters["design"]) == ("paper", load, "paper")


def test_paper_max_strain_is_the_outer_fibre_strain_of_the_composite_beam():
    # independent check of the Euler-Bernoulli strain: at the tube's top/bottom fibres
    # eps + kappa (y - ybar); one design, recomputed from the section's numbers
    from softcath.analytic.section import section_arrays

    r = models.response(PAPER, [0.1], tier="paper", load="cap")
    s = section_arrays(analytic.design_inputs_many([PAPER]))
    top = float(s["tube_centre_y"][0] + s["b"][0] - s["neutral_axis_y"][0])
    bot = float(s["tube_centre_y"][0] - s["b"][0] - s["neutral_axis_y"][0])
    k, e = r.curvature_per_mm[0], r.elongation[0]
    assert r.max_strain[0] == pytest.approx(max(abs(e + k * top), abs(e + k * bot)), rel=1e-12)


def test_paper_batch_equals_each_design_alone():
    batch = models.responses([PAPER, OTHER], P, tier="paper", loads=("cap", "lumen"))
    for load, b in batch.items():
        for i, d in enumerate((PAPER, OTHER)):
            one = models.response(d, P, tier="paper", load=load)
            np.testing.assert_allclose(b.curvature_per_mm[i], one.curvature_per_mm, rtol=1e-12, atol=0)
            np.testing.assert_allclose(b.tip_x_mm[i], one.tip_x_mm, rtol=1e-12, atol=0)
            np.testing.assert_allclose(b[i].bend_angle_rad, one.bend_angle_rad, rtol=1e-12, atol=0)


def test_section_response_is_the_sweep_batch_and_the_section_model():
    from softcath.fem.section_model import section_model
    from softcath.models.section_eval import section_blocks_many

    r = models.response(PAPER, P, tier="section", load="lumen")
    cols, errors = section_blocks_many([PAPER], P, ("lumen",))
    assert not errors
    # the tier is the sweep's batched path: the same numbers
    np.testing.assert_array_equal(r.curvature_per_mm, cols["lumen"]["curvature_section_per_mm"][0])
    np.testing.assert_array_equal(r.max_strain, cols["lumen"]["max_strain_section"][0])
    # and the single-design section model on the same mesh (another factorisation: rounding, ~1e-12 measured)
    direct = section_model(PAPER, loads=("lumen",)).response(P, "lumen")
    np.testing.assert_allclose(r.curvature_per_mm, direct.curvature, rtol=1e-9, atol=0)
    np.testing.assert_allclose(r.elongation, direct.elongation, rtol=1e-9, atol=0)
    np.testing.assert_allclose(r.bend_angle_rad, direct.bend_angle, rtol=1e-9, atol=0)
    # the tip-level curvature is the tip's angle over the stretched length: its end zones' share
    factor = end_zones(PAPER).factor
    np.testing.assert_allclose(r.tip_curvature_per_mm[1:], factor * r.curvature_per_mm[1:], rtol=1e-12)


def test_section_batch_equals_each_design_alone():
    b = models.responses([PAPER, OTHER], P, tier="section", loads=("cap",))["cap"]
    for i, d in enumerate((PAPER, OTHER)):
        one = models.response(d, P, tier="section", load="cap")
        # one template batch or another: the same mesh and equations, factorised apart
        np.testing.assert_allclose(b.curvature_per_mm[i], one.curvature_per_mm, rtol=1e-9, atol=0)
        np.testing.assert_allclose(b.elongation[i], one.elongation, rtol=1e-9, atol=0)


def test_section_nonlinear_response_is_the_finite_strain_curve():
    from softcath.fem.section_model.finite_strain import section_curve

    p = [0.0, 0.1]
    r = models.response(PAPER, p, tier="section-nonlinear", load="lumen")
    c = section_curve(PAPER, p, load="lumen", linear_gain=False)
    # the same walk: equal to rounding
    np.testing.assert_allclose(r.curvature_per_mm, c.curvature_per_mm, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(r.bend_angle_rad, c.bend_angle_rad, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(r.lumen_volume_change_mm3, c.lumen_volume_change_mm3, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(r.max_strain, c.max_strain, rtol=1e-12, atol=1e-15)
    assert r.warnings == ()  # valid at every bend short of a full turn


@pytest.mark.slow
def test_fem_response_is_fem_check():
    from softcath import fem

    r = models.response(PAPER, [0.1], tier="fem", load="cap", options={"mesh_size": 0.25})
    case = fem.check(PAPER, pressures=[0.1], loads=("cap",), mesh_size=0.25).cases[0]
    assert r.curvature_per_mm[0] == pytest.approx(case.curvature_per_mm, rel=1e-12)
    assert r.bend_angle_rad[0] == pytest.approx(case.bend_angle_rad, rel=1e-12)
    assert r.max_strain[0] == pytest.approx(case.max_strain, rel=1e-12)
    # its tip-level curvature is its own second estimate: the end section's rotation over L
    assert r.tip_curvature_per_mm[0] == pytest.approx(case.curvature_rotation_per_mm, rel=1e-12)
    assert r.parameters["mesh_size"] == 0.25 and r.extras["dofs"][0] > 0
    # no companion solve unless asked for: the stated error is NaN by default
    assert np.isnan(r.extras["discretisation_error_estimate"][0])
    asked = models.response(
        PAPER, [0.1], tier="fem", load="cap", options={"mesh_size": 0.25, "error_estimate": True}
    )
    stated = fem.check(PAPER, pressures=[0.1], loads=("cap",), mesh_size=0.25, error_estimate=True)
    # each call meshes the companion afresh, and two meshes of one size differ at the mesher's round-off:
    # the coarse curvature moves by ~1e-6 of itself and the stated error, a difference of near-equal
    # curvatures (0.45 %), by up to 2e-4 of itself (measured over repeated calls in one process)
    assert asked.extras["discretisation_error_estimate"][0] == pytest.approx(
        stated.cases[0].discretisation_error_estimate, rel=1e-3
    )
    assert 0 < asked.extras["discretisation_error_estimate"][0] < 0.1


@pytest.mark.slow
def test_fem_nonlinear_response_is_the_bend_curve():
    from softcath.fem.nonlinear import bend_curve

    opts = {"size": 0.3, "layers": 4}
    r = models.response(PAPER, [0.0, 0.02], tier="fem-nonlinear", load="cap", options=opts)
    c = bend_curve(PAPER, [0.02], load="cap", **opts)
    assert r.bend_angle_rad[1] == pytest.approx(c.bend_angle[0], rel=1e-12)
    assert r.curvature_per_mm[1] == pytest.approx(c.curvature_mid[0], rel=1e-12, nan_ok=True)
    assert r.tip_curvature_per_mm[1] == pytest.approx(c.curvature[0], rel=1e-12)
    assert (r.bend_angle_rad[0], r.max_strain[0]) == (0.0, 0.0)  # the rest state
