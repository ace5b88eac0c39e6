"""The section mesh of a design: the gmsh mesh of its section's topology morphed to it, or its own.

:func:`catheter_section_mesh` checks the mesh size and the work it makes
(:func:`softcath.fem.limits.check_section_budget`), then takes the morphed template
(:mod:`softcath.fem.section_model.template`), or a fresh gmsh mesh
(:mod:`softcath.fem.section_model.triangles`) when the morph is refused or asked against.
The mesh type, the disc-and-ellipse meshes of the closed-form checks and the size bounds are
re-exported here, where the section model's callers look for them.
"""

from __future__ import annotations

from softcath.core.errors import DesignError
from softcath.fem.geometry import TipGeometry
from softcath.fem.limits import check_section_budget
from softcath.fem.section_mesh_size import MESH_SIZE, SEGMENTS, check_size
from softcath.fem.section_model.template import template_mesh
from softcath.fem.section_model.triangles import SectionMesh, _catheter_cached, disk_section_mesh

__all__ = [
    "SectionMesh",
    "catheter_section_mesh",
    "check_size",
    "disk_section_mesh",
    "MESH_SIZE",
    "MESHERS",
    "SEGMENTS",
]

#: ``template``: the gmsh mesh of the section's topology morphed to the geometry
#: (``softcath.fem.section_model.template``; gmsh when the morph is refused or fails);
#: ``gmsh``: a fresh gmsh mesh of the geometry.
MESHERS = ("template", "gmsh")


def catheter_section_mesh(
    geometry: TipGeometry,
    *,
    mesh_size: float = MESH_SIZE,
    segments: int = SEGMENTS,
    mesher: str = "template",
) -> SectionMesh:
    """The as-assembled catheter section of ``geometry`` (regions of ``softcath.fem.geometry``).

    Parameters
    ----------
    geometry
        The tip geometry (its section at z = 0, the lumen part).
    mesh_size
        Largest element size, mm.
    segments
        Boundary points per full turn of every circle and ellipse.
    mesher
        One of :data:`MESHERS`. The morphed template's section-model answers are
        within 0.2 % of a fresh gmsh mesh's (tests/fem/section_model/test_template.py).
    """
    if mesher not in MESHERS:
        raise DesignError("mesher", mesher, f"must be one of {MESHERS}")
    check_size(mesh_size, segments)
    check_section_budget(coil_outer_radius=geometry.coil_outer_radius, mesh_size=mesh_size)
    if mesher == "template":
        mesh = template_mesh(geometry, mesh_size=mesh_size, segments=segments)
        if mesh is not None:
            return mesh
    info = _catheter_cached.cache_info()
    mesh = _catheter_cached(geometry, float(mesh_size), int(segments))
    if _catheter_cached.cache_info().hits > info.hits:
        return SectionMesh(**{**mesh.__dict__, "seconds": 0.0})
    return mesh
