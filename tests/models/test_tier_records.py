"""Each tier's detailed record converts itself into the one result type, ``TipResponse``.

Three records, one name each: :class:`NonlinearFemCurve` (3-D finite-strain FEM),
:class:`BilinearCoilCurve` (section model with bilinear coils) and :class:`SectionCurve`
(finite-strain section model). ``to_response`` copies the record's values: exact equality,
no tolerance, except where the response derives a quantity (then checked against its closed form).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from softcath import design, models
from softcath.core.response import TipResponse
from softcath.design.errors import DesignError
from softcath.fem.nonlinear.bend import NonlinearFemCurve
from softcath.fem.section_model import section_model
from softcath.fem.section_model.bilinear import BilinearCoilCurve, bend_curve
from softcath.fem.section_model.finite_strain import SectionCurve, section_curve
from softcath.models.section import SECTION
from softcath.models.section_nonlinear import SECTION_NONLINEAR
from softcath.studies.outputs.section import curve_response

PAPER = design.preset("paper")
LENGTH = float(PAPER.tip.bending_length)


def _fem_curve() -> NonlinearFemCurve:
    """A record with a distinct random array in every per-pressure field (a swapped field shows)."""
    rng = np.random.default_rng(7)
    n = 3
    arrays = {
        f.name: rng.uniform(0.01, 1.0, n)
        for f in dataclasses.fields(NonlinearFemCurve)
        if f.type in ("np.ndarray",)
    }
    arrays["pressure"] = np.array([0.05, 0.1, 0.2])
    return NonlinearFemCurve(
        **arrays,  # pyright: ignore[reportArgumentType]  # the record's array fields, drawn at random
        midspan=(0.25, 0.75),
        midspan_axis=(0.0, 0.1),
        load="cap",
        ndofs=10,
        n_tets=2,
        n_nodes=5,
        mesh_seconds=0.5,
        result=None,  # pyright: ignore[reportArgumentType]  # a record without its solve
    )


def test_nonlinear_fem_curve_to_response_is_its_fields():
    c = _fem_curve()
    r = c.to_response(seconds=12.5, parameters={"size": 0.3})
    assert isinstance(r, TipResponse)
    assert (r.tier, r.load, r.seconds, dict(r.parameters)) == ("fem-nonlinear", "cap", 12.5, {"size": 0.3})
    pairs = {
        "pressures": c.pressure,
        "curvature_per_mm": c.curvature_mid,
        "tip_curvature_per_mm": c.curvature,
        "elongation": c.elongation,
        "bend_angle_rad": c.bend_angle,
        "tip_x_mm": c.tip_x,
        "tip_y_mm": c.tip_y,
        "max_strain": c.max_strain,
    }
    for name, value in pairs.items():
        np.testing.assert_array_equal(getattr(r, name), value, err_msg=name)
    assert np.isnan(r.lumen_volume_change_mm3).all()  # the 3-D FEM does not compute it
    np.testing.assert_array_equal(r.extras["linear_bend_angle_rad"], c.linear_bend_angle)
    np.testing.assert_array_equal(r.extras["analytic_bend_angle_rad"], c.analytic_bend_angle)
    np.testing.assert_array_equal(r.extras["newton_iterations"], c.newton_iterations)
    np.testing.assert_array_equal(r.extras["curvature_variation"], c.curvature_variation)


@pytest.fixture(scope="module")
def bilinear() -> BilinearCoilCurve:
    return bend_curve(PAPER, [0.1, 0.2, 0.4], load="cap", initial_tension=(0.005, 0.0))


def test_bilinear_coil_curve_to_response_is_its_fields(bilinear):
    c = bilinear
    r = c.to_response(length_mm=LENGTH)
    assert (r.tier, r.load, r.seconds) == ("section", "cap", c.seconds)
    for name, value in {
        "pressures": c.pressure,
        "curvature_per_mm": c.curvature,
        "tip_curvature_per_mm": c.curvature,  # a uniform arc: one curvature
        "elongation": c.elongation,
    }.items():
        np.testing.assert_array_equal(getattr(r, name), value, err_msg=name)
    np.testing.assert_array_equal(r.extras["lateral_curvature_per_mm"], c.lateral_curvature)
    np.testing.assert_array_equal(r.extras["closed_fraction_coil"], c.closed_fraction["coil"])
    assert r.parameters["coil_model"] == c.coil_model and r.parameters["bending_length_mm"] == LENGTH
    assert np.isnan(r.max_strain).all() and np.isnan(r.lumen_volume_change_mm3).all()


def test_bilinear_coil_curve_response_is_a_uniform_arc(bilinear):
    c = bilinear
    r = c.to_response(length_mm=LENGTH)
    arc = LENGTH * (1 + c.elongation)
    k = c.curvature
    np.testing.assert_allclose(r.bend_angle_rad, k * arc, rtol=1e-15, atol=0)
    # the arc's end (eq. 9): (1 - cos θ)/κ = 2 sin²(θ/2)/κ across (no cancellation at small θ),
    # sin θ/κ along; the package evaluates it through sinc, so the two agree to rounding
    np.testing.assert_allclose(r.tip_x_mm, 2 * np.sin(k * arc / 2) ** 2 / k, rtol=1e-12, atol=0)
    np.testing.assert_allclose(r.tip_y_mm, np.sin(k * arc) / k, rtol=1e-12, atol=0)
    # the section command's table is the same conversion
    beam = curve_response(c, LENGTH)
    np.testing.assert_array_equal(beam.bend_angle, r.bend_angle_rad)
    np.testing.assert_array_equal(beam.tip_x, r.tip_x_mm)
    np.testing.assert_array_equal(beam.tip_y, r.tip_y_mm)


@pytest.mark.parametrize("length", [0.0, -1.0, math.nan])
def test_bilinear_coil_curve_refuses_a_bad_length(bilinear, length):
    with pytest.raises(DesignError, match="length_mm"):
        bilinear.to_response(length_mm=length)


def test_section_curve_to_response_is_its_fields():
    c = section_curve(PAPER, [0.05, 0.1], load="lumen", linear_gain=False)
    assert isinstance(c, SectionCurve)
    r = c.to_response()
    assert (r.tier, r.load, r.seconds) == ("section-nonlinear", "lumen", c.seconds)
    for name, value in {
        "pressures": c.pressure,
        "curvature_per_mm": c.curvature_per_mm,
        "elongation": c.elongation,
        "bend_angle_rad": c.bend_angle_rad,
        "tip_x_mm": c.tip_x_mm,
        "tip_y_mm": c.tip_y_mm,
        "lumen_volume_change_mm3": c.lumen_volume_change_mm3,
        "max_strain": c.max_strain,
    }.items():
        np.testing.assert_array_equal(getattr(r, name), value, err_msg=name)
    for name in ("bend_rate_per_mm", "lumen_area_mm2", "newton_iterations", "residual"):
        np.testing.assert_array_equal(r.extras[name], getattr(c, name), err_msg=name)
    # the tip-level curvature: the tip's angle over the stretched bending length
    np.testing.assert_allclose(
        r.tip_curvature_per_mm, c.bend_angle_rad / (c.length_mm * (1 + c.elongation)), rtol=1e-15, atol=0
    )
    assert r.parameters["bending_length_mm"] == c.length_mm == LENGTH


@pytest.mark.parametrize(
    ("module", "new"),
    [
        ("softcath.fem.nonlinear.bend", NonlinearFemCurve),
        ("softcath.fem.section_model.bilinear", BilinearCoilCurve),
        ("softcath.fem.section_model", BilinearCoilCurve),
    ],
)
def test_bend_curve_is_a_deprecated_alias(module, new):
    import importlib

    mod = importlib.import_module(module)
    with pytest.warns(DeprecationWarning, match=f"BendCurve is deprecated: use {new.__name__}"):
        old = mod.BendCurve
    assert old is new
    with pytest.raises(AttributeError, match="NoSuchCurve"):
        mod.NoSuchCurve  # noqa: B018


def test_a_tiers_record_is_solved_with_its_options_as_its_responses_are():
    """``record`` (what a picture needs beyond the response) maps the tier's options as ``response`` does."""
    pressures = [0.2, 0.4]
    opts = {"mesh_size": 0.1}
    curve = SECTION_NONLINEAR.record(PAPER, pressures, load="lumen", options=opts)
    r = models.response(PAPER, pressures, tier="section-nonlinear", load="lumen", options=opts)
    np.testing.assert_array_equal(curve.to_response().bend_angle_rad, r.bend_angle_rad)  # the same walk
    assert curve.dofs != SECTION_NONLINEAR.record(PAPER, pressures, load="lumen").dofs  # the mesh option
    sm = SECTION.record(PAPER, options={"silicone_poisson": 0.45, "poisson_cap": None})
    assert sm.curvature_per_mm_per_MPa == section_model(PAPER, silicone_poisson=0.45).curvature_per_mm_per_MPa
    with pytest.raises(DesignError, match=r"options\.size.*section accepts the options mesh_size"):
        SECTION.record(PAPER, options={"size": 0.1})
    with pytest.raises(DesignError, match=r"load.*section-nonlinear answers the loads cap, lumen"):
        SECTION_NONLINEAR.record(PAPER, pressures, load="wall")
