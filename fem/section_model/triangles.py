"""Triangle meshes of a cross-section with region labels and a pressurised lumen.

The catheter section comes from the same gmsh recipe as the 3-D FEM's
extruded mesh (:func:`softcath.fem.mesh.section_triangles`: the same regions, bonded
lands and curved P2 edges), so the section model and the 3-D FEM see one
geometry. Meshing dominates the cost of one design, so meshes are kept in a
small per-process cache keyed by the geometry's content hash: a sweep over
moduli or Poisson ratios meshes once.

:func:`disk_section_mesh` meshes sections made of discs and ellipses for
the closed-form checks (eccentric tube, Lamé cylinder, two-material bars).
The mesh a design gets (the morphed template or this gmsh one) is chosen by
:func:`softcath.fem.section_model.mesh.catheter_section_mesh`.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from softcath.core.errors import DesignError
from softcath.fem.geometry import VOID, TipGeometry
from softcath.fem.mesh import _ellipse, _gmsh_session, p2_triangles, section_triangles
from softcath.fem.section_mesh_size import SEGMENTS, check_size

__all__ = ["SectionMesh", "disk_section_mesh"]


@dataclass(frozen=True)
class SectionMesh:
    """A labelled triangle mesh of a section (mm), lumen removed.

    Attributes
    ----------
    points
        Corner vertices (n, 2).
    triangles
        Counter-clockwise triangles (m, 3).
    labels
        Region label per triangle (``softcath.fem.geometry`` constants or caller's ints).
    curved_edges, curved_midpoints
        Edges (k, 2) lying on curved boundaries and their exact midpoints (k, 2).
    lumen_edges
        Boundary edges (j, 2) of the pressurised lumen.
    seconds
        Wall time of meshing (0 on a cache hit).
    """

    points: np.ndarray
    triangles: np.ndarray
    labels: np.ndarray
    curved_edges: np.ndarray
    curved_midpoints: np.ndarray
    lumen_edges: np.ndarray
    seconds: float = 0.0
    key: str = field(default="")

    def skfem_mesh(self):
        """The scikit-fem ``MeshTri2`` (curved edges bent onto the exact curves)."""
        from skfem import MeshTri, MeshTri2

        lin = MeshTri(np.ascontiguousarray(self.points.T), np.ascontiguousarray(self.triangles.T))
        quad = MeshTri2.from_mesh(lin)
        if len(self.curved_edges):
            nv = lin.p.shape[1]
            e = np.sort(lin.facets, axis=0)
            key_mesh = e[0].astype(np.int64) * nv + e[1]
            ce = np.sort(self.curved_edges, axis=1)
            key_curved = ce[:, 0].astype(np.int64) * nv + ce[:, 1]
            order = np.argsort(key_mesh)
            pos = np.clip(np.searchsorted(key_mesh[order], key_curved), 0, key_mesh.size - 1)
            hit = key_mesh[order][pos] == key_curved
            doflocs = quad.doflocs.copy()
            doflocs[:, nv + order[pos[hit]]] = self.curved_midpoints[hit].T
            quad = MeshTri2(doflocs, quad.t.copy())
        return quad

    def lumen_facets(self, mesh) -> np.ndarray:
        """Indices of the lumen edges among ``mesh.facets`` (a mesh from :meth:`skfem_mesh`)."""
        nv = self.points.shape[0]
        e = np.sort(mesh.facets, axis=0)
        key_mesh = e[0].astype(np.int64) * nv + e[1]
        le = np.sort(self.lumen_edges, axis=1)
        key_lumen = le[:, 0].astype(np.int64) * nv + le[:, 1]
        return np.flatnonzero(np.isin(key_mesh, key_lumen))


def _finish(xy, tri, labels, ce, cm, in_lumen: Callable, *, seconds: float, key: str) -> SectionMesh:
    keep = labels != VOID
    tri, labels = tri[keep], labels[keep]
    used = np.unique(tri)
    remap = np.full(xy.shape[0], -1, dtype=np.int64)
    remap[used] = np.arange(used.size)
    xy, tri = xy[used], remap[tri]
    ce = remap[ce]
    ok = (ce >= 0).all(axis=1)
    ce, cm = ce[ok], cm[ok]
    p = xy[tri]
    area2 = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (
        p[:, 2, 0] - p[:, 0, 0]
    )
    tri = np.where((area2 < 0)[:, None], tri[:, [0, 2, 1]], tri)
    # Boundary edges (seen by one triangle) whose chord midpoint is in the lumen.
    edges = np.sort(np.vstack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    nv = np.int64(xy.shape[0])
    keys, counts = np.unique(edges[:, 0] * nv + edges[:, 1], return_counts=True)
    once = keys[counts == 1]
    boundary = np.column_stack([once // nv, once % nv])
    mid = xy[boundary].mean(axis=1)
    lumen = boundary[in_lumen(mid[:, 0], mid[:, 1])]
    if len(lumen) == 0:
        raise DesignError("section.lumen", key, "no lumen boundary found in the section mesh")
    return SectionMesh(xy, tri, labels.astype(np.int8), ce, cm, lumen, seconds, key)


@functools.lru_cache(maxsize=64)
def _catheter_cached(geometry: TipGeometry, mesh_size: float, segments: int) -> SectionMesh:
    t0 = time.perf_counter()
    xy, tri, ce, cm = section_triangles(geometry, mesh_size, segments, fast=True)
    cen = xy[tri].mean(axis=1)
    labels = geometry.classify(cen[:, 0], cen[:, 1], np.zeros(len(cen)))
    g = geometry

    def in_lumen(x, y):
        return (x / g.lumen_a) ** 2 + ((y - g.lumen_y) / g.lumen_b) ** 2 < 1.0 + 1e-9

    key = f"{geometry.digest()}|{mesh_size:.6g}|{segments}"
    return _finish(xy, tri, labels, ce, cm, in_lumen, seconds=time.perf_counter() - t0, key=key)


def disk_section_mesh(
    shapes: Sequence[tuple[float, float, float, float]],
    classify: Callable[[np.ndarray, np.ndarray], np.ndarray],
    in_lumen: Callable[[np.ndarray, np.ndarray], np.ndarray],
    *,
    mesh_size: float,
    segments: int = SEGMENTS,
) -> SectionMesh:
    """Mesh a section bounded by discs and ellipses (verification geometries).

    Parameters
    ----------
    shapes
        ``(xc, yc, rx, ry)`` of every disc or axis-aligned ellipse whose edge is a
        region boundary; the pieces are fragmented into a conforming partition.
    classify
        Region label (``softcath.fem.geometry.VOID`` for holes) at points ``(x, y)``.
    in_lumen
        True at points inside the pressurised lumen.
    mesh_size, segments
        As in :func:`~softcath.fem.section_model.mesh.catheter_section_mesh`.
    """
    check_size(mesh_size, segments)
    t0 = time.perf_counter()
    with _gmsh_session() as gmsh:
        occ = gmsh.model.occ
        gmsh.model.add("shapes")
        pieces = [(2, _ellipse(occ, xc, yc, rx, ry)) for xc, yc, rx, ry in shapes]
        occ.fragment(pieces[:1], pieces[1:])
        occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", mesh_size)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.MinimumCirclePoints", int(segments))
        gmsh.option.setNumber("Mesh.Algorithm", 5)
        gmsh.option.setNumber("Mesh.Smoothing", 0)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        xy, tri, ce, cm = p2_triangles(gmsh)
    cen = xy[tri].mean(axis=1)
    labels = np.asarray(classify(cen[:, 0], cen[:, 1]))
    return _finish(xy, tri, labels, ce, cm, in_lumen, seconds=time.perf_counter() - t0, key="shapes")
