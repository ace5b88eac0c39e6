"""Simple structured tetrahedral meshes for verification cases (mm).

These are design-independent: boxes (cantilevers) and sectors of hollow
cylinders (pressurised tubes). The catheter mesh comes from
:mod:`softcath.fem.nonlinear.catheter`.
"""

from __future__ import annotations

import numpy as np

__all__ = ["box", "hollow_cylinder", "facets_where", "dofs_of_facets"]


def box(*, size: tuple[float, float, float], cells: tuple[int, int, int], centre_xy: bool = True):
    """A ``skfem.MeshTet`` box [0..lx] x [0..ly] x [0..lz] (x, y centred on 0 by default)."""
    from skfem import MeshTet

    lx, ly, lz = size
    nx, ny, nz = cells
    x = np.linspace(-lx / 2, lx / 2, nx + 1) if centre_xy else np.linspace(0, lx, nx + 1)
    y = np.linspace(-ly / 2, ly / 2, ny + 1) if centre_xy else np.linspace(0, ly, ny + 1)
    return MeshTet.init_tensor(x, y, np.linspace(0, lz, nz + 1))


def hollow_cylinder(
    *,
    inner_radius: float,
    outer_radius: float,
    length: float,
    cells: tuple[int, int, int],
    angle: float = np.pi / 2,
):
    """A sector (0..angle) of a hollow cylinder along z, ``cells`` = (radial, circumferential, axial).

    Vertices on r = inner/outer radius lie exactly on the circles (facets are flat).
    """
    from skfem import MeshTet

    nr, nt, nz = cells
    m = MeshTet.init_tensor(
        np.linspace(inner_radius, outer_radius, nr + 1),
        np.linspace(0, angle, nt + 1),
        np.linspace(0, length, nz + 1),
    )
    r, t, z = m.p
    return MeshTet(np.vstack([r * np.cos(t), r * np.sin(t), z]), m.t)


def facets_where(mesh, predicate, *, boundary_only: bool = True) -> np.ndarray:
    """Indices of (boundary) facets whose three vertices all satisfy ``predicate(x (3, n)) -> (n,) bool``."""
    facets = mesh.boundary_facets() if boundary_only else np.arange(mesh.facets.shape[1])
    ok = np.ones(facets.size, bool)
    for k in range(3):
        ok &= np.asarray(predicate(mesh.p[:, mesh.facets[k, facets]]), bool)
    return facets[ok]


def dofs_of_facets(basis, facets: np.ndarray, components=(0, 1, 2)) -> np.ndarray:
    """Vector DOFs (``3 node + c``) of the P2 nodes on ``facets`` for the given components."""
    nodes = basis.get_dofs(np.asarray(facets)).all()
    return (3 * nodes[:, None] + np.asarray(components)[None, :]).ravel()
