"""The ``section-nonlinear`` tier's options reach the finite-strain model, and a stalled walk
keeps the pressures it reached.

The options are :func:`~softcath.fem.section_model.finite_strain.section_curve`'s keywords of
the same names, so the tier's answer must be the curve's to round-off; the outer coil's
``coil_axial_scale`` must equal the laws built by hand (the discrepancy model bank's former
construction) and, at large scale, the coil's stiffness dominates the bend: the small-load gain
falls as 1/s.
"""

from __future__ import annotations

import inspect
from dataclasses import replace

import numpy as np
import pytest

from softcath import design, models
from softcath.core.errors import DesignError
from softcath.fem.adapter import coil_law
from softcath.fem.geometry import COIL
from softcath.fem.hyperelastic.laws import AnisotropicSVK
from softcath.fem.section_model import section_model
from softcath.fem.section_model.finite_strain import SectionConvergenceError, section_curve, section_laws
from softcath.models.section_nonlinear import SECTION_NONLINEAR

P = [0.0, 0.2, 0.4]


@pytest.fixture(scope="module")
def paper():
    return design.preset("paper")


def _curvature(d, **options):
    return SECTION_NONLINEAR.response(d, P, load="lumen", options=options).curvature_per_mm


def test_every_option_is_a_section_curve_keyword_with_its_default_or_the_designs():
    """One table: each option reaches section_curve by its name, with no second list to edit."""
    keywords = inspect.signature(section_curve).parameters
    for name, default in SECTION_NONLINEAR.options.items():
        assert keywords[name].kind is inspect.Parameter.KEYWORD_ONLY
        assert default is None or default == keywords[name].default


def test_silicone_poisson_is_the_curves(paper):
    got = _curvature(paper, silicone_poisson=0.45)
    want = section_curve(paper, P, silicone_poisson=0.45, linear_gain=False).curvature_per_mm
    np.testing.assert_array_equal(got, want)
    # a more compressible silicone bends differently: the option is not ignored
    assert abs(got[-1] - _curvature(paper)[-1]) > 1e-3 * abs(got[-1])


def test_coil_axial_scale_equals_the_coil_law_scaled_by_hand(paper):
    s = 0.64
    laws = section_laws(paper)
    law = coil_law(paper.coil, "tension")
    law = replace(law, axial_modulus=law.axial_modulus * s, axial_shear_modulus=law.axial_shear_modulus * s)
    laws[COIL] = AnisotropicSVK(law.tensor())
    want = section_curve(paper, P, laws=laws, linear_gain=False).curvature_per_mm
    # the same laws on the same path: equal to round-off
    np.testing.assert_allclose(_curvature(paper, coil_axial_scale=s), want, rtol=1e-12, atol=0)
    np.testing.assert_array_equal(_curvature(paper, coil_axial_scale=1.0), _curvature(paper))


def test_a_stiffer_coil_spring_bends_less_and_at_large_scale_as_one_over_the_scale(paper):
    p = 0.01  # the small-load gain (the linear section model's, to 1e-5 at this load)
    gain = {
        s: section_curve(paper, [p], coil_axial_scale=s, linear_gain=False).curvature_per_mm[0] / p
        for s in (0.5, 1.0, 2.0, 50.0, 100.0)
    }
    assert gain[0.5] > gain[1.0] > gain[2.0] > gain[50.0] > gain[100.0] > 0
    # the coil's axial stiffness dominates the bending stiffness (EI ~ s EI_coil): gain ~ 1/s;
    # the silicone's share and the stiffness centroid's shift to the coil leave 3 % (measured 2.064)
    assert gain[50.0] / gain[100.0] == pytest.approx(2.0, rel=0.05)


@pytest.mark.parametrize(
    ("options", "match"),
    [
        ({"coil_axial_scale": 0.0}, r"options\.coil_axial_scale = 0: must be in \(0, 100\]"),
        ({"coil_axial_scale": 150.0}, r"options\.coil_axial_scale = 150: must be in \(0, 100\]"),
        ({"silicone_poisson": 0.6}, r"options\.silicone_poisson = 0\.6: must be in \[0, 0\.49999\]"),
        ({"tube_prestretch": 0.9}, r"options\.tube_prestretch = 0\.9: must be in \[1, 4\]"),
    ],
)
def test_an_option_out_of_its_bound_is_refused_before_any_solve(paper, options, match):
    with pytest.raises(DesignError, match=match):
        SECTION_NONLINEAR.responses([paper], P, options=options)


def test_the_command_line_reads_and_bounds_the_new_options():
    got = models.parse_tier_options(
        ["coil_axial_scale=2", "silicone_poisson=0.45"], tiers=["section-nonlinear"]
    )
    assert got == {"section-nonlinear": {"coil_axial_scale": 2.0, "silicone_poisson": 0.45}}
    # the linear section tier takes silicone_poisson as well, with the same bound
    assert models.parse_tier_options(["silicone_poisson=0.45"], tiers=["section"]) == {
        "section": {"silicone_poisson": 0.45}
    }
    with pytest.raises(DesignError, match=r"--model-option coil_axial_scale = -1: must be in \(0, 100\]"):
        models.parse_tier_options(["coil_axial_scale=-1"], tiers=["section-nonlinear"])
    with pytest.raises(DesignError, match=r"silicone_poisson = 0\.5: must be in \[0, 0\.49999\]"):
        models.parse_tier_options(["silicone_poisson=0.5"], tiers=["section"])


@pytest.mark.slow
def test_a_stalled_walk_keeps_the_pressures_it_reached(paper):
    """100 MPa is past what the paper section carries: the design is failed (NaN rows, its
    error kept), and its partial response is the curve up to the last pressure reached."""
    batch = SECTION_NONLINEAR.responses([paper], [0.0, 0.3, 100.0], loads=("lumen",))["lumen"]
    assert isinstance(batch.errors[0], SectionConvergenceError)
    assert np.isnan(batch.curvature_per_mm).all()
    with pytest.raises(SectionConvergenceError, match=r"pressure = 100: not reached"):
        batch[0]
    r = batch.partial_response(0)
    reached = section_curve(paper, [0.0, 0.3], linear_gain=False)
    # the walk toward 100 MPa takes other load steps to 0.3 MPa: equal to the Newton tolerance
    np.testing.assert_allclose(r.curvature_per_mm[:2], reached.curvature_per_mm, rtol=1e-5, atol=1e-12)
    np.testing.assert_allclose(r.bend_angle_rad[:2], reached.bend_angle_rad, rtol=1e-5, atol=1e-12)
    assert np.isnan(r.curvature_per_mm[2]) and np.isnan(r.elongation[2])
    assert r.tier == "section-nonlinear" and any("stopped short" in w for w in r.warnings)


def test_partial_response_of_a_solved_design_is_its_response(paper):
    batch = SECTION_NONLINEAR.responses([paper], [0.0, 0.2], loads=("lumen",))["lumen"]
    assert batch.partial == {}
    np.testing.assert_array_equal(batch.partial_response(0).curvature_per_mm, batch[0].curvature_per_mm)


def test_the_section_tier_takes_silicone_poisson_to_the_section_model(paper):
    got = models.get("section").response(paper, [0.3], load="lumen", options={"silicone_poisson": 0.45})
    lin = section_model(paper, loads=("lumen",), silicone_poisson=0.45)
    # linear in pressure: the tier's curvature is the model's gain times the pressure
    assert got.curvature_per_mm[0] == pytest.approx(0.3 * lin.curvature_per_mm_per_MPa["lumen"], rel=1e-12)
    assert got.parameters["silicone_poisson"] == 0.45


def test_coil_bound_is_the_curves_with_the_designs_initial_tension(paper):
    """The option reaches section_curve with F0 the design's coil.initial_tension (the model's own
    checks of the coil-bound law: tests/fem/section_model/finite_strain/test_coil_bound.py)."""
    tight = replace(paper, coil=replace(paper.coil, initial_tension=0.005))
    got = SECTION_NONLINEAR.response(tight, P, load="lumen", options={"coil_bound": True}).curvature_per_mm
    want = section_curve(paper, P, coil_bound=True, initial_tension=0.005, linear_gain=False)
    np.testing.assert_array_equal(got, want.curvature_per_mm)
    # coil-bound turns stiffen the bend: the option is not ignored
    assert got[-1] < 0.9 * _curvature(tight)[-1]
    np.testing.assert_array_equal(_curvature(paper, coil_bound=False), _curvature(paper))
    assert models.parse_tier_options(["coil_bound=true"], tiers=["section-nonlinear"]) == {
        "section-nonlinear": {"coil_bound": True}
    }
    with pytest.raises(DesignError, match="coil_bound"):
        SECTION_NONLINEAR.responses([paper], P, options={"coil_bound": "yes"})
