"""The section model's principal strains against the Lamé thick cylinder (closed ends)."""

from __future__ import annotations

import numpy as np
import pytest

from softcath.fem.section_model.element import assemble
from softcath.fem.section_model.laws import isotropic
from softcath.fem.section_model.mesh import disk_section_mesh
from softcath.fem.section_model.solve import solve
from softcath.fem.section_model.strain import principal_strain_range


@pytest.mark.parametrize("nu", [0.3, 0.49])
def test_principal_strains_of_a_pressurised_closed_tube_are_lames(nu):
    """Largest: hoop strain at the bore; smallest: radial strain at the bore.

    Both vary as 1/r^2 and are sampled at quadrature points, the nearest about
    0.12 h inside the bore: with h = 0.03 mm and a = 0.3 mm that is 2 * 0.12 h / a
    = 0.8 % low (measured 0.79 %, and 0.42 % at h = 0.015), so 2 % bounds the
    sampling error; a wrong Poisson or axial term is off by tens of percent.
    """
    a, b, E, p = 0.3, 1.0, 2.0, 1.0
    mesh = disk_section_mesh(
        [(0.0, 0.0, b, b), (0.0, 0.0, a, a)],
        lambda x, y: np.where((x**2 + y**2 < b**2) & (x**2 + y**2 > a**2), 2, 0),
        lambda x, y: x**2 + y**2 < a**2 * (1 + 1e-9),
        mesh_size=0.03,
        segments=64,
    )
    op = assemble(mesh, {2: isotropic(E, nu)})
    sol = solve(op, ("lumen",))
    low, high = principal_strain_range(op, sol.loads["lumen"], np.ones(len(mesh.labels), bool))
    s_z = p * a**2 / (b**2 - a**2)
    s_r, s_t = -p, s_z + p * a**2 * b**2 / (b**2 - a**2) / a**2
    hoop = (s_t - nu * (s_r + s_z)) / E
    radial = (s_r - nu * (s_t + s_z)) / E
    assert high == pytest.approx(hoop, rel=0.02)
    assert high <= hoop * (1 + 1e-3)  # sampled inside the bore: never above the peak
    assert low == pytest.approx(radial, rel=0.02)
