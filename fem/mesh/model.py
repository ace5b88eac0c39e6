"""The labelled tip mesh and its quality summary, and scikit-fem meshes from vertex/tet arrays."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from softcath.fem.geometry import TipGeometry


@dataclass(frozen=True)
class MeshQuality:
    """Element quality summary (the scaled Jacobian is 1 for a regular tet)."""

    n_tets: int
    n_vertices: int
    min_scaled_jacobian: float
    p01_scaled_jacobian: float
    n_below_0_1: int


@dataclass(frozen=True)
class TipMesh:
    """A labelled linear tet mesh of the tip (P2 nodes are added by the solver).

    Attributes
    ----------
    points
        Vertex coordinates (n, 3), mm.
    tets
        Positively oriented tetrahedra (m, 4).
    labels
        Region label per tet (``softcath.fem.geometry`` constants).
    geometry
        The geometry meshed.
    mesher, mesh_size
        Back-end and target size (mm) used.
    region_volumes, exact_volumes
        Per region name, mm^3 (mesh vs exact geometry).
    quality
        :class:`MeshQuality`.
    seconds
        Wall time of meshing (0 if it came from the cache; see ``cached``).
    cached
        True if loaded from the on-disk cache.
    """

    points: np.ndarray
    tets: np.ndarray
    labels: np.ndarray
    geometry: TipGeometry
    mesher: str
    mesh_size: float
    region_volumes: dict[str, float]
    exact_volumes: dict[str, float]
    quality: MeshQuality
    seconds: float
    cached: bool = False
    key: str = field(default="")
    curved_edges: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))
    curved_midpoints: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    def skfem_mesh(self):
        """The scikit-fem mesh: quadratic (``MeshTet2``, edges on curved boundaries
        bent onto the exact surfaces) if the back-end supplied curved edges,
        else linear ``MeshTet``."""
        return skfem_mesh(self.points, self.tets, self.curved_edges, self.curved_midpoints)

    def volume_errors(self) -> dict[str, float]:
        """Relative volume error per region (mesh / exact - 1)."""
        return {k: self.region_volumes.get(k, 0.0) / v - 1.0 for k, v in self.exact_volumes.items() if v > 0}


def skfem_mesh(points, tets, curved_edges=None, curved_midpoints=None):
    """Build a scikit-fem mesh; quadratic geometry where curved edge midpoints are given."""
    from skfem import MeshTet, MeshTet2

    lin = MeshTet(np.ascontiguousarray(points.T, float), np.ascontiguousarray(tets.T))
    if curved_edges is None or len(curved_edges) == 0:
        return lin
    quad = MeshTet2.from_mesh(lin)
    nv = lin.p.shape[1]
    e = np.sort(lin.edges, axis=0)
    key_mesh = e[0].astype(np.int64) * nv + e[1]
    ce = np.sort(np.asarray(curved_edges), axis=1)
    key_curved = ce[:, 0].astype(np.int64) * nv + ce[:, 1]
    order = np.argsort(key_mesh)
    pos = np.searchsorted(key_mesh[order], key_curved)
    pos = np.clip(pos, 0, key_mesh.size - 1)
    hit = key_mesh[order][pos] == key_curved
    doflocs = quad.doflocs.copy()
    doflocs[:, nv + order[pos[hit]]] = np.asarray(curved_midpoints)[hit].T
    return MeshTet2(doflocs, quad.t.copy())


def curved_volumes(mesh) -> np.ndarray:
    """Per-element volumes (mm^3) of a (possibly curved) scikit-fem mesh."""
    from skfem import CellBasis, ElementTetP0

    return CellBasis(mesh, ElementTetP0(), intorder=4).dx.sum(axis=1)
