"""Small verification meshes with closed-form answers (shared by the fem tests)."""

from __future__ import annotations

import numpy as np

from softcath.fem.mesh import _gmsh_session, extrude, skfem_mesh


def quarter_annulus(r_in: float, r_out: float, size: float, length: float, layers: int):
    """Quarter of a thick cylinder (x, y >= 0), curved P2 geometry, as a scikit-fem mesh."""
    with _gmsh_session() as gmsh:
        occ = gmsh.model.occ
        outer = occ.addDisk(0, 0, 0, r_out, r_out)
        inner = occ.addDisk(0, 0, 0, r_in, r_in)
        box = occ.addRectangle(0, 0, 0, 2 * r_out, 2 * r_out)
        ring, _ = occ.cut([(2, outer)], [(2, inner)])
        occ.intersect(ring, [(2, box)])
        occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", size)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        xy = coords.reshape(-1, 3)[:, :2]
        index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
        index[tags.astype(np.int64)] = np.arange(tags.size)
        _, _, enodes = gmsh.model.mesh.getElements(2)
        tri6 = index[np.concatenate(enodes).astype(np.int64)].reshape(-1, 6)
    corner = np.unique(tri6[:, :3])
    remap = np.full(xy.shape[0], -1, dtype=np.int64)
    remap[corner] = np.arange(corner.size)
    tri = remap[tri6[:, :3]]
    ends = np.vstack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    mids = np.vstack([xy[tri6[:, 3]], xy[tri6[:, 4]], xy[tri6[:, 5]]])
    points, tets, ce, cm = extrude(xy[corner], tri, np.linspace(0, length, layers + 1), None, ends, mids)
    tets = _orient(points, tets)
    return skfem_mesh(points, tets, ce, cm)


def _orient(points, tets):
    from softcath.fem.mesh import tet_volumes

    tets = tets.copy()
    neg = tet_volumes(points, tets) < 0
    tets[neg, 2], tets[neg, 3] = tets[neg, 3], tets[neg, 2].copy()
    return tets


def facets_where(mesh, predicate):
    """Boundary facets whose centroid satisfies ``predicate(x, y, z)``."""
    bf = mesh.boundary_facets()
    nv = mesh.t.max() + 1
    c = np.asarray(mesh.doflocs)[:, :nv][:, mesh.facets[:, bf]].mean(axis=1)
    return bf[predicate(*c)]
