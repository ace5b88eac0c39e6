"""Tetrahedral meshes of the tip with region labels, cached on disk.

Two back-ends:

``gmsh`` (default)
    The cross-section is meshed in 2-D by gmsh (OCC booleans of circles,
    ellipses and land strips, ``fragment`` so every region boundary is a mesh
    edge, curvature-based sizing with ``MeshSizeFromCurvature``), then extruded
    along z into layers of prisms split into three tetrahedra each with the
    global-index rule, which makes neighbouring prisms agree on their shared
    quad diagonals (a conforming mesh). The tip is a prism, so extrusion puts
    the degrees of freedom where bending needs them: fine across the section,
    coarser along z, which P2 handles well. Seconds, not minutes.
``tetwild``
    pytetwild (the design card's mesher) on the closed boundary surfaces of
    every region, embedded in one surface so the tets conform to the material
    interfaces; labels are assigned per tet by centroid. Slow (tens of
    seconds to minutes on thin walls), so it runs in a
    temporary directory (it writes a stray file) and its result is cached.

Both return a :class:`TipMesh` whose region volumes are checked against the
exact geometry (within 1 %) and whose elements are checked for inversion.
"""

from __future__ import annotations

from softcath.fem.mesh.cache import MESHERS, cache_dir, mesh_tip
from softcath.fem.mesh.extrusion import extrude
from softcath.fem.mesh.gmsh_section import (
    _ellipse,
    _gmsh_session,
    initialize_gmsh,
    p2_triangles,
    restore_sigpipe_ignored,
    section_triangles,
)
from softcath.fem.mesh.model import MeshQuality, TipMesh, curved_volumes, skfem_mesh
from softcath.fem.mesh.quality import VOLUME_TOL, _orient, exact_volumes, scaled_jacobian, tet_volumes
from softcath.fem.mesh.tetwild import interface_surface

__all__ = [
    "TipMesh",
    "MeshQuality",
    "mesh_tip",
    "cache_dir",
    "MESHERS",
    "scaled_jacobian",
    "tet_volumes",
    "skfem_mesh",
    "curved_volumes",
    "exact_volumes",
    "VOLUME_TOL",
    "extrude",
    "section_triangles",
    "p2_triangles",
    "restore_sigpipe_ignored",
    "initialize_gmsh",
    "interface_surface",
    "_ellipse",
    "_gmsh_session",
    "_orient",
]
