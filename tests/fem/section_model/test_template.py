"""Template section meshes: the morphed mesh against a fresh gmsh mesh, and the morph's bounds."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from softcath import design
from softcath.design.errors import DesignError
from softcath.fem.adapter import geometry_from_design
from softcath.fem.section_model import section_model
from softcath.fem.section_model.mesh import catheter_section_mesh
from softcath.fem.section_model.template import (
    QUALITY_RATIO,
    MorphError,
    _quality,
    morph,
    reference_geometry,
    section_template,
)
from softcath.studies.sweep.random_designs import random_designs

QUANTITIES = ("curvature_per_mm_per_MPa", "elongation_per_MPa", "lumen_area_change_mm2_per_MPa")


def test_morphed_section_model_within_0p2_percent_of_fresh_gmsh_on_20_random_designs():
    worst = 0.0
    for d in random_designs(20, seed=23):
        fresh = section_model(d, mesher="gmsh")
        morphed = section_model(d, mesher="template")
        for name in QUANTITIES:
            for load in ("cap", "lumen"):
                a, b = getattr(fresh, name)[load], getattr(morphed, name)[load]
                worst = max(worst, abs(b / a - 1))
        for name in ("EA_N", "EI_N_mm2", "EI_lateral_N_mm2"):
            worst = max(worst, abs(getattr(morphed, name) / getattr(fresh, name) - 1))
    assert worst < 2e-3  # measured 4e-4


def test_morphed_meshes_keep_quality_curves_and_regions():
    for d in random_designs(6, seed=29):
        g = geometry_from_design(d)
        t = section_template(g, mesh_size=0.08, segments=20)
        m = catheter_section_mesh(g)
        assert m.key.endswith("|template")
        ratio = _quality(m.points, m.triangles) / t.quality
        assert ratio.min() >= QUALITY_RATIO
        # Curved midpoints lie on their new curves; the triangles and regions are the template's.
        mid = m.curved_midpoints
        r = np.hypot(mid[:, 0], mid[:, 1])
        on_coil = np.isclose(r, g.coil_outer_radius, atol=1e-12) | np.isclose(
            r, g.coil_inner_radius, atol=1e-12
        )
        assert on_coil.sum() > 10
        np.testing.assert_array_equal(m.triangles, t.mesh.triangles)
        np.testing.assert_array_equal(
            m.labels, geometry_from_design(d).classify(*m.points[m.triangles].mean(1).T)
        )


def test_reference_section_morphs_onto_its_own_gmsh_mesh():
    g = geometry_from_design(design.resolve("paper"))
    assert reference_geometry(g) == dataclasses.replace(g, length=1.0, cap_thickness=0.1)
    fresh = catheter_section_mesh(g, mesher="gmsh")
    m = catheter_section_mesh(g, mesher="template")
    np.testing.assert_allclose(m.points, fresh.points, atol=1e-13)
    np.testing.assert_allclose(m.curved_midpoints, fresh.curved_midpoints, atol=1e-13)


def test_a_degrading_morph_is_refused():
    g0 = geometry_from_design(design.resolve("paper"))
    t = section_template(g0, mesh_size=0.08, segments=20)
    far = dataclasses.replace(g0, lumen_a=0.05, lumen_b=0.05)
    with pytest.raises(MorphError, match="quality_ratio"):
        morph(t, far)


def test_unknown_mesher_is_refused():
    g = geometry_from_design(design.resolve("paper"))
    with pytest.raises(DesignError, match="mesher"):
        catheter_section_mesh(g, mesher="delaunay")


@pytest.mark.parametrize(
    "fault, level",
    [
        (MorphError("morph.quality_ratio", 0.1, "must be >= 0.5"), "INFO"),
        (RuntimeError("gmsh: no mesh"), "WARNING"),
    ],
)
def test_a_refused_or_failed_template_falls_back_to_gmsh_and_says_so(monkeypatch, caplog, fault, level):
    """The template is a speed-up, never a new way to fail: the per-design mesh and the batched
    models both mesh such a design afresh with gmsh, and the log says why."""
    import logging

    from softcath.fem.section_model import template
    from softcath.fem.section_model.batch import section_models

    def broken(*args, **kwargs):
        raise fault

    d = random_designs(1, seed=31)[0]
    g = geometry_from_design(d)
    monkeypatch.setattr(template, "section_template", broken)
    with caplog.at_level(logging.INFO, logger=template.__name__):
        m = catheter_section_mesh(g, mesher="template")
        (item,) = section_models([d], loads=("lumen",))
    assert not m.key.endswith("|template")
    np.testing.assert_array_equal(m.points, catheter_section_mesh(g, mesher="gmsh").points)
    fresh = section_model(d, loads=("lumen",), mesher="gmsh")
    assert item.result.curvature_per_mm_per_MPa["lumen"] == pytest.approx(
        fresh.curvature_per_mm_per_MPa["lumen"], rel=1e-12
    )
    refusals = [r for r in caplog.records if "meshing with gmsh" in r.getMessage()]
    assert len(refusals) == 2 and {r.levelname for r in refusals} == {level}


def test_a_stop_swallowed_by_ctypes_is_not_taken_for_a_template_failure(monkeypatch):
    """A signal landing inside a gmsh (ctypes) call reaches Python as ``ctypes.ArgumentError``;
    with a stop recorded, the fallback must stop instead of meshing on with gmsh."""
    import ctypes

    from softcath.fem.section_model import template
    from softcath.interrupts import clear_stop, request_stop

    class Stop(KeyboardInterrupt):
        pass

    def interrupted(*args, **kwargs):
        request_stop(Stop)
        raise ctypes.ArgumentError("argument 1: Stop: ")

    g = geometry_from_design(random_designs(1, seed=31)[0])
    monkeypatch.setattr(template, "section_template", interrupted)
    try:
        with pytest.raises(Stop):
            catheter_section_mesh(g, mesher="template")
    finally:
        clear_stop()


def test_as_built_sections_on_the_template_agree_with_fresh_gmsh():
    """Sliding interfaces split the morphed mesh as they split gmsh's (within the template's
    0.2 %); a coat filler, whose circle no template carries, is meshed by gmsh."""
    from softcath.design.assembly import Assembly

    d = random_designs(1, seed=37)[0]
    sliding = dataclasses.replace(d, assembly=Assembly(tube_coil="sliding", tube_channel="sliding"))
    fresh = section_model(sliding, mesher="gmsh")
    morphed = section_model(sliding, mesher="template")
    assert morphed.axial_groups == fresh.axial_groups
    for name in QUANTITIES:
        for load in ("cap", "lumen"):
            assert getattr(morphed, name)[load] == pytest.approx(getattr(fresh, name)[load], rel=2e-3)
    coat = geometry_from_design(dataclasses.replace(d, assembly=Assembly(filler="coat")))
    with pytest.raises(MorphError, match="filler_coat"):
        section_template(coat, mesh_size=0.08, segments=20)
    assert not catheter_section_mesh(coat).key.endswith("|template")
