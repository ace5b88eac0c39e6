"""Verification sections with closed forms: meshes and exact section sums."""

from __future__ import annotations

import math

import numpy as np

from softcath.fem.section_model.element import assemble
from softcath.fem.section_model.laws import isotropic
from softcath.fem.section_model.mesh import disk_section_mesh
from softcath.fem.section_model.solve import solve

SOLID, FILL, STEEL, VOID = 2, 4, 1, 0


def eccentric_tube(*, R=1.0, r=0.35, e=0.3, E=2.0, nu=0.3, mesh_size=0.1, segments=32):
    """One-material tube: outer circle R at the origin, lumen r at (0, e); solved at 1 MPa."""

    def classify(x, y):
        lab = np.where(x**2 + y**2 < R**2, SOLID, VOID)
        return np.where(x**2 + (y - e) ** 2 < r**2, VOID, lab)

    def in_lumen(x, y):
        return x**2 + (y - e) ** 2 < r**2 * (1 + 1e-9)

    mesh = disk_section_mesh(
        [(0.0, 0.0, R, R), (0.0, e, r, r)], classify, in_lumen, mesh_size=mesh_size, segments=segments
    )
    op = assemble(mesh, {SOLID: isotropic(E, nu)})
    return op, solve(op)


def eccentric_tube_exact(*, R=1.0, r=0.35, e=0.3, E=2.0):
    """EA, centroid y, EI about the centroid, lumen area and centroid of :func:`eccentric_tube`."""
    a_o, a_l = math.pi * R**2, math.pi * r**2
    area = a_o - a_l
    ybar = -a_l * e / area
    inertia = math.pi * R**4 / 4 + a_o * ybar**2 - (math.pi * r**4 / 4 + a_l * (e - ybar) ** 2)
    return {"EA": E * area, "ybar": ybar, "EI": E * inertia, "A_L": a_l, "y_L": e}
