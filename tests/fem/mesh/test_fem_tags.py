"""Facet tags: the loaded surfaces have the exact areas and resultants."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from softcath import design
from softcath.fem.adapter import fem_laws_from_design, geometry_from_design
from softcath.fem.elasticity import ElasticProblem
from softcath.fem.mesh import mesh_tip
from softcath.fem.tags import tag_facets


def _ellipse_perimeter(a, b):  # Ramanujan II, relative error < 1e-9 here
    h = ((a - b) / (a + b)) ** 2
    return math.pi * (a + b) * (1 + 3 * h / (10 + math.sqrt(4 - 3 * h)))


@pytest.mark.parametrize("filled", [True, False])
def test_loaded_surfaces_and_resultants(filled, tmp_path):
    d = design.preset("paper")
    if not filled:
        d = replace(d, filler=None)
    g = geometry_from_design(d)
    m = mesh_tip(g, mesh_size=0.25, cache=tmp_path)
    sk = m.skfem_mesh()
    tags = tag_facets(sk, g)
    pb = ElasticProblem(sk, m.labels, fem_laws_from_design(d), [(tags["base"], (0, 1, 2))])
    cap = pb.pressure_load(tags["cap"]).reshape(-1, 3).sum(axis=0)
    wall = pb.pressure_load(tags["lumen"]).reshape(-1, 3).sum(axis=0)
    area = math.pi * g.lumen_a * g.lumen_b
    # cap: the fluid pushes the cap toward +z with p A_L (curved P2 faces: 1e-3)
    assert cap[2] == pytest.approx(area, rel=1e-3)
    assert abs(cap[0]) < 1e-9 and abs(cap[1]) < 1e-3 * area
    # lumen wall: a prism, so no net force (its sides are parallel to z)
    assert np.abs(wall).max() < 1e-3 * area
    # the wall's area, from the unit outward-normal force magnitudes: perimeter x length
    from skfem import ElementTetP1, FacetBasis, Functional

    fb = FacetBasis(sk, ElementTetP1(), facets=tags["lumen"], intorder=4)
    wall_area = Functional(lambda w: 1.0 + 0 * w.x[0]).assemble(fb)
    expected = _ellipse_perimeter(g.lumen_a, g.lumen_b) * (g.length - g.cap_thickness)
    assert wall_area == pytest.approx(expected, rel=2e-3)
    # nothing else is tagged lumen: the channel keeps its own tag, the outer skin too
    assert tags["channel"].size > 0 and tags["outer"].size > 0
    assert not np.intersect1d(tags["lumen"], tags["outer"]).size
