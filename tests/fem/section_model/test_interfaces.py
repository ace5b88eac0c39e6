"""Sliding interfaces against closed forms: layered beams and a tube in a rigid ring."""

from __future__ import annotations

import math

import numpy as np
import pytest

from softcath.design.assembly import Assembly
from softcath.fem.geometry import COIL, TUBE, VOID
from softcath.fem.section_model.as_built import (
    AxialPlan,
    as_built_operator,
    axial_plan,
    solve_as_built,
    summary,
)
from softcath.fem.section_model.element import assemble
from softcath.fem.section_model.interfaces import split_interfaces, tie_projection
from softcath.fem.section_model.laws import isotropic
from softcath.fem.section_model.mesh import SectionMesh, disk_section_mesh
from softcath.fem.section_model.solve import solve


def layers(heights, *, width=1.0, nx=8, ny=4):
    """Stacked rectangles (structured, ``ny`` rows per layer), labelled 1, 2, ... from the bottom.

    The "lumen" is the left side of the bottom layer: its load is not used here.
    """
    ys = [0.0]
    for h in heights:
        ys += list(ys[-1] + np.linspace(0, h, ny + 1)[1:])
    x = np.linspace(-width / 2, width / 2, nx + 1)
    xx, yy = np.meshgrid(x, np.array(ys))
    pts = np.column_stack([xx.ravel(), yy.ravel() - sum(heights) / 2])
    tri, lab = [], []
    for j in range(len(ys) - 1):
        for i in range(nx):
            a, b, c, d = (
                j * (nx + 1) + i,
                j * (nx + 1) + i + 1,
                (j + 1) * (nx + 1) + i + 1,
                (j + 1) * (nx + 1) + i,
            )
            tri += [(a, b, c), (a, c, d)]
            lab += [1 + j // ny] * 2
    lumen = np.array([[0, nx + 1]])
    e0 = np.zeros((0, 2), dtype=np.int64)
    return SectionMesh(pts, np.array(tri), np.array(lab, np.int8), e0, np.zeros((0, 2)), lumen)


def solve_split(mesh, laws, *, groups, tie=None, slip_modulus=1e-12):
    """Split every region boundary, normal ties (or full where ``tie`` is False)."""
    split = split_interfaces(mesh, mesh.labels.astype(np.int64))
    g = np.array([groups[int(k)] for k in mesh.labels])
    op = assemble(split.mesh, laws, axial_groups=g)
    ties = tie_projection(split, op.basis, tie=tie)
    ng = max(groups.values()) + 1
    plan = AxialPlan(group=groups, cap_share=np.eye(ng)[0])
    return op, solve_as_built(op, ties, plan, ("cap",), slip_modulus=slip_modulus)


# Quadratic elements represent the Saint-Venant bending field of each layer exactly (its
# in-plane anticlastic displacement is quadratic, and with equal nu the layers' fields are
# compatible along the interface), so the only error is round-off: 1e-9.
@pytest.mark.parametrize("nu", [0.0, 0.3])
def test_two_unbonded_layers_bend_about_their_own_axes(nu):
    h1, h2, E1, E2, w = 0.3, 0.5, 2.0, 7.0, 1.0
    laws = {1: isotropic(E1, nu), 2: isotropic(E2, nu)}
    mesh = layers([h1, h2], width=w)
    op, sol = solve_split(mesh, laws, groups={1: 0, 2: 1})
    ei = summary(op, sol)["EI"]
    exact = w * (E1 * h1**3 + E2 * h2**3) / 12
    assert ei == pytest.approx(exact, rel=1e-9)
    # Each layer's axial force vanishes under the moment: the layers slip, not stretch.
    assert sol.plan.n_groups == 2


def test_bonded_layers_kept_split_are_the_composite_beam():
    h1, h2, E1, E2, w = 0.3, 0.5, 2.0, 7.0, 1.0
    laws = {1: isotropic(E1, 0.0), 2: isotropic(E2, 0.0)}
    mesh = layers([h1, h2], width=w)
    op, sol = solve_split(mesh, laws, groups={1: 0, 2: 0}, tie=np.zeros(8, bool))
    ybar = (E1 * h1 * (h1 / 2) + E2 * h2 * (h1 + h2 / 2)) / (E1 * h1 + E2 * h2)
    exact = w * (
        E1 * (h1**3 / 12 + h1 * (h1 / 2 - ybar) ** 2) + E2 * (h2**3 / 12 + h2 * (h1 + h2 / 2 - ybar) ** 2)
    )
    assert summary(op, sol)["EI"] == pytest.approx(exact, rel=1e-9)
    # ... and the same as the unsplit operator (bit-level agreement up to round-off).
    ref = solve(assemble(mesh, laws), ("cap",)).stiffness
    assert sol.stiffness == pytest.approx(ref, rel=1e-9, abs=1e-12 * abs(ref).max())


def test_sliding_tube_in_a_rigid_ring_under_internal_pressure():
    """Lamé tube (a, b) in a rigid, frictionless ring; closed ends, free to stretch.

    u_r = C1 r + C2 / r with sigma_r(a) = -p, u_r(b) = 0 (the ring) and the axial force
    N = p pi a^2 (the cap) carried by the tube alone (its own axial group).
    """
    a, b, c, E, nu, p = 0.3, 0.6, 0.8, 2.0, 0.45, 1.0
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))

    def classify(x, y):
        r2 = x**2 + y**2
        return np.where(r2 < a**2, VOID, np.where(r2 < b**2, TUBE, np.where(r2 < c**2, COIL, VOID)))

    mesh = disk_section_mesh(
        [(0, 0, c, c), (0, 0, b, b), (0, 0, a, a)],
        classify,
        lambda x, y: x**2 + y**2 < a**2 * (1 + 1e-9),
        mesh_size=0.05,
        segments=96,
    )
    laws = {TUBE: isotropic(E, nu), COIL: isotropic(1e6 * E, 0.3)}
    _, op, sol = as_built_operator(mesh, laws, Assembly(tube_coil="sliding"), ("lumen",))
    assert axial_plan(Assembly(tube_coil="sliding"), [COIL, TUBE]).n_groups == 2
    # Unknowns C1, C2, eps_z.
    A = np.array(
        [
            [2 * (lam + mu), -2 * mu / a**2, lam],
            [b, 1 / b, 0.0],
            [2 * lam * math.pi * (b**2 - a**2), 0.0, (lam + 2 * mu) * math.pi * (b**2 - a**2)],
        ]
    )
    c1, c2, ez = np.linalg.solve(A, [-p, 0.0, p * math.pi * a**2])
    dA = 2 * math.pi * a * (c1 * a + c2 / a)
    s = sol.loads["lumen"]
    tube_group = sol.plan.group[TUBE]
    # Curved P2 edges on 96 points per turn carry the exact circles to ~1e-6; the tie's
    # nodal normals are radial to the same order. Measured 4e-6 on both; 1e-4 bounds it.
    assert s.lumen_area_change == pytest.approx(dA, rel=1e-4)
    assert s.strains[tube_group] == pytest.approx(ez, rel=1e-4)
    # Bonded to the ring instead, the tube cannot stretch: eps_z ~ 0 (the ring is 1e6 x stiffer).
    _, _, bonded = as_built_operator(mesh, laws, Assembly(proximal="tube-free"), ("lumen",))
    assert abs(bonded.loads["lumen"].strains[0]) < 1e-4 * ez


@pytest.mark.parametrize("alpha_l", [0.0, 2.0, 1e4])
def test_partial_interaction_is_newmarks_composite_beam(alpha_l):
    """Two layers with an interface spring layer, end moment M on a cantilever of length L.

    Newmark: EA* = 1/(1/EA_1 + 1/EA_2), EI_0 = EI_1 + EI_2, EI_inf = EI_0 + EA* d^2,
    alpha^2 = k EI_inf / (EA* EI_0), N_inf = M d EA* / EI_inf and the mean curvature
    (M - d N_inf (1 - tanh(alpha L)/(alpha L))) / EI_0. The section model's groups are exact
    for nu = 0 (round-off); the 1-D solution is closed form: 1e-9.
    """
    from softcath.fem.section_model.partial_interaction import tip_strains

    h1, h2, E1, E2, w, L, M = 0.3, 0.5, 2.0, 7.0, 1.0, 5.0, 0.01
    laws = {1: isotropic(E1, 0.0), 2: isotropic(E2, 0.0)}
    op, sol = solve_split(layers([h1, h2], width=w), laws, groups={1: 0, 2: 1})
    ea1, ea2, ei0 = E1 * w * h1, E2 * w * h2, w * (E1 * h1**3 + E2 * h2**3) / 12
    d = (h1 + h2) / 2
    ea_star = 1 / (1 / ea1 + 1 / ea2)
    ei_inf = ei0 + ea_star * d**2
    k = (alpha_l / L) ** 2 * ea_star * ei0 / ei_inf
    n_inf = M * d * ea_star / ei_inf
    shape = 0.0 if alpha_l == 0 else 1 - math.tanh(alpha_l) / alpha_l
    exact = (M - d * n_inf * shape) / ei0
    g = tip_strains(sol.stiffness, np.array([0.0, 0.0, 0.0, M]), slip_modulus=k, length=L)
    assert g[3] == pytest.approx(exact, rel=1e-9)
    # The limits are the sliding and the bonded sections of the section model.
    if alpha_l == 0.0:
        assert g[3] == pytest.approx(M / summary(op, sol)["EI"], rel=1e-12)
    if alpha_l == 1e4:
        bonded = solve(assemble(layers([h1, h2], width=w), laws), ("cap",)).stiffness
        ei_bonded = bonded[2, 2] - bonded[0, 2] ** 2 / bonded[0, 0]
        assert g[3] == pytest.approx(M / ei_bonded, rel=2e-4)  # 1/(alpha L) = 1e-4 of slip left
