"""The tetwild back-end: pytetwild on the embedded interface surface of every region."""

from __future__ import annotations

import os
import tempfile

import numpy as np

from softcath.fem.geometry import VOID, TipGeometry
from softcath.fem.mesh.extrusion import extruded_gmsh
from softcath.fem.mesh.quality import compact


def interface_surface(g: TipGeometry, mesh_size: float) -> tuple[np.ndarray, np.ndarray]:
    """Triangulated surface of every region boundary and interface of the tip.

    Made from the exact section (gmsh) extruded along z: the outer skin, the
    lumens, the cap and every material interface, as one (non-manifold)
    surface, so a volume mesher keeps the interfaces embedded.
    """
    # Straight facets here (no curved edges): 64 segments per turn keep the
    # faceting area error at (2 pi/64)^2/6 = 0.16 %.
    points, tets, _, _, labels = extruded_gmsh(g, mesh_size, axial_ratio=2.0, segments_per_turn=64)
    keep = labels != VOID
    points, tets, _ = compact(points, tets[keep])
    labels = labels[keep]
    faces = np.vstack([tets[:, [1, 2, 3]], tets[:, [0, 2, 3]], tets[:, [0, 1, 3]], tets[:, [0, 1, 2]]])
    owner = np.tile(labels, 4)
    key = np.sort(faces, axis=1)
    _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    inv = inv.ravel()
    # A face is kept if it is on the boundary (seen once) or between two regions.
    lab_min = np.full(counts.size, 99)
    lab_max = np.full(counts.size, -1)
    np.minimum.at(lab_min, inv, owner)
    np.maximum.at(lab_max, inv, owner)
    first = np.zeros(counts.size, dtype=np.int64)
    first[inv[::-1]] = np.arange(len(inv))[::-1]
    wanted = (counts == 1) | (lab_min != lab_max)
    return points, faces[first[wanted]]


def tetwild_mesh(g: TipGeometry, mesh_size: float):
    """pytetwild on the interface surface; run in a temporary directory (stray file).

    All tets of fTetWild's box are kept and labelled by centroid; those outside
    the tip (or in a lumen) are dropped by the caller.

    The envelope (how far fTetWild may move the surface) is 2 % of the mesh
    size: tight enough for region volumes within 1 % (checked), loose enough to
    finish (a 1 um envelope on the 0.075 mm channel wall ran past 12 minutes).
    """
    import warnings

    import pytetwild
    import pyvista as pv

    pts, tris = interface_surface(g, mesh_size)
    diagonal = float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))
    epsilon = 0.02 * mesh_size / diagonal  # relative to the bounding-box diagonal
    surface = pv.PolyData(pts, np.column_stack([np.full(len(tris), 3), tris]).ravel())
    cwd = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="softcath-tetwild-") as tmp:
        os.chdir(tmp)  # fTetWild writes __tracked_surface.stl into the working directory
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # pytetwild uses a deprecated pyvista accessor
                grid = pytetwild.tetrahedralize_pv(
                    surface,
                    edge_length_abs=mesh_size,
                    epsilon=epsilon,
                    num_threads=1,
                    quiet=True,
                    # Interfaces make the surface non-manifold, which confuses the
                    # winding-number filter: keep every tet, label by centroid.
                    disable_filtering=True,
                )
        finally:
            os.chdir(cwd)
    tets = np.asarray(grid.cells_dict[pv.CellType.TETRA], dtype=np.int64)
    return np.asarray(grid.points, dtype=float), tets
