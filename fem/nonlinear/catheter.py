"""The catheter tip as a finite-strain FEM model: mesh, regions, laws, loads.

Mesh: the as-assembled cross-section (``softcath.design.section``) is triangulated
with gmsh (OpenCASCADE fragments, so every material interface is a mesh
edge), each triangle is classified by its centroid (coil, tube, lumen,
channel wall, channel bore, filler), and the section is extruded in numpy
into ``layers`` prism layers along z, each prism split into three
tetrahedra with the vertex-index rule that keeps neighbouring splits
conforming. Layers give the long, thin tip a mesh that is fine across the
section and coarse along the axis, which an isotropic 3-D mesher cannot.
The lumen is void up to the sealed cap (last ``cap_thickness``), which is
tube silicone; the channel bore is void throughout.

The squeezed tube touches the coil ID and the channel tangentially; OCC
booleans dislike tangency, so the tube's outer ellipse is grown by
``contact`` (default 3 % of b) and clipped by the coil ID and the channel:
the contact becomes a short flat patch — what a squeezed tube makes.

Laws (finite strain): silicones (tube, filler) are Yeoh when the material
has Yeoh coefficients (Ecoflex), else neo-Hookean from E and ν; coils are
transversely isotropic Saint Venant–Kirchhoff (``laws.AnisotropicSVK``)
with the homogenised moduli of :func:`design.coil_stiffness`: axial E_L =
the spring-like tension modulus (as the analytic model), transverse E_T =
the hoop modulus, G_L = E_L / (2 (1 + 0.3)), ν_TT = 0.3 and no axial/hoop
coupling (a spring's stretch does not change its diameter to first order).

Labels: 1 coil, 2 tube (incl. the cap plug), 3 channel, 4 filler.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from softcath.design import coil_stiffness
from softcath.fem.hyperelastic.laws import (
    AnisotropicSVK,
    isotropic_from_young,
    transversely_isotropic,
    yeoh_at_modulus,
)
from softcath.fem.mesh import initialize_gmsh
from softcath.fem.nonlinear.errors import NonlinearError, SettingError
from softcath.fem.nonlinear.true_area import area_true, section_curves
from softcath.fem.tags import tag_facets

if TYPE_CHECKING:  # scikit-fem loads with the first mesh; named here for the checker
    from skfem import Mesh

__all__ = [
    "REGIONS",
    "CatheterMesh",
    "mesh_catheter",
    "catheter_laws",
    "capped_hoop_modulus",
    "from_tip_mesh",
]

log = logging.getLogger(__name__)

REGIONS = {"coil": 1, "tube": 2, "channel": 3, "filler": 4}
_LUMEN, _BORE = -1, -2


@dataclass(frozen=True)
class CatheterMesh:
    """A tetrahedral catheter tip and its tags.

    Attributes
    ----------
    mesh
        ``skfem.MeshTet`` [mm], base at z = 0, tip end at z = L.
    labels
        Region label per tetrahedron (:data:`REGIONS`).
    base_facets
        Boundary facets on z = 0 (clamped).
    lumen_facets
        Boundary facets of the pressurised lumen: its wall and the cap's inner face.
    cap_facets
        The subset of ``lumen_facets`` on the cap's inner face (z = L − cap).
    length
        Bending length L [mm].
    """

    mesh: Mesh
    labels: np.ndarray
    base_facets: np.ndarray
    lumen_facets: np.ndarray
    cap_facets: np.ndarray
    length: float

    @property
    def end_vertices(self) -> np.ndarray:
        """Boolean mask of vertices on the tip end z = L."""
        return np.isclose(self.mesh.p[2], self.length)


def _section_triangles(section, *, size: float, contact: float, curvature_points: int = 24):
    """Triangulate the section with gmsh; returns (points (n, 2), triangles (m, 3), class per triangle)."""
    import gmsh

    s = section
    init_here = not gmsh.isInitialized()
    if init_here:
        initialize_gmsh(gmsh)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("softcath_section")
        occ = gmsh.model.occ

        def ellipse(xc, yc, rx, ry):
            if rx >= ry:
                return occ.addDisk(xc, yc, 0, rx, ry)
            tag = occ.addDisk(xc, yc, 0, ry, rx)
            occ.rotate([(2, tag)], xc, yc, 0, 0, 0, 1, np.pi / 2)
            return tag

        outer = occ.addDisk(0, 0, 0, s.coil_outer_radius, s.coil_outer_radius)
        inner = occ.addDisk(0, 0, 0, s.coil_inner_radius, s.coil_inner_radius)
        ch_out = occ.addDisk(0, s.channel_center_y, 0, s.channel_outer_radius, s.channel_outer_radius)
        ch_in = occ.addDisk(0, s.channel_center_y, 0, s.channel_inner_radius, s.channel_inner_radius)
        tube = ellipse(0, s.tube_center_y, s.a * (1 + contact), s.b * (1 + contact))
        lumen = ellipse(0, s.tube_center_y + s.h, s.a_int, s.b_int)
        occ.fragment([(2, outer)], [(2, t) for t in (inner, ch_out, ch_in, tube, lumen)])
        occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", size / 4)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", curvature_points)
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        types, _, nodes = gmsh.model.mesh.getElements(2)
    finally:
        gmsh.model.remove() if gmsh.isInitialized() else None
        if init_here:
            gmsh.finalize()
    tri_nodes = np.concatenate([n for t, n in zip(types, nodes, strict=True) if t == 2]).reshape(-1, 3)
    index = np.full(int(tags.max()) + 1, -1)
    index[tags.astype(int)] = np.arange(tags.size)
    pts = coords.reshape(-1, 3)[:, :2]
    tri = index[tri_nodes.astype(int)]
    c = pts[tri].mean(axis=1)
    x, y = c[:, 0], c[:, 1]
    r = np.hypot(x, y)
    cls = np.full(tri.shape[0], REGIONS["filler"])
    in_tube = (x / (s.a * (1 + contact))) ** 2 + ((y - s.tube_center_y) / (s.b * (1 + contact))) ** 2 < 1
    cls[in_tube] = REGIONS["tube"]
    cls[(x / s.a_int) ** 2 + ((y - s.tube_center_y - s.h) / s.b_int) ** 2 < 1] = _LUMEN
    rc = np.hypot(x, y - s.channel_center_y)
    cls[rc < s.channel_outer_radius] = REGIONS["channel"]
    cls[rc < s.channel_inner_radius] = _BORE
    cls[r > s.coil_inner_radius] = REGIONS["coil"]
    # orient counter-clockwise so extruded tets have positive volume
    e1, e2 = pts[tri[:, 1]] - pts[tri[:, 0]], pts[tri[:, 2]] - pts[tri[:, 0]]
    cw = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] < 0
    tri[cw] = tri[cw][:, [0, 2, 1]]
    return pts, tri, cls


def _extrude(pts2, tri, cls, z_levels, keep):
    """Prism layers split into tets (vertex-index rule); ``keep(cls, layer) -> label or 0`` per prism."""
    n2 = pts2.shape[0]
    nz = z_levels.size
    points = np.column_stack([np.tile(pts2, (nz, 1)), np.repeat(z_levels, n2)])
    tets, labels = [], []
    for k in range(nz - 1):
        lab = keep(cls, 0.5 * (z_levels[k] + z_levels[k + 1]))
        sel = lab > 0
        t = tri[sel]
        # sort each triangle's vertices by global index: the diagonal on every quad side then goes
        # from the lower-index bottom vertex to the higher-index top vertex, on both neighbours
        order = np.argsort(t, axis=1)
        a, b, c = (np.take_along_axis(t, order[:, [i]], 1)[:, 0] for i in range(3))
        lo, hi = k * n2, (k + 1) * n2
        prism_tets = [
            np.column_stack([a + lo, b + lo, c + lo, c + hi]),
            np.column_stack([a + lo, b + lo, b + hi, c + hi]),
            np.column_stack([a + lo, a + hi, b + hi, c + hi]),
        ]
        for pt in prism_tets:
            tets.append(pt)
            labels.append(lab[sel])
    tets = np.vstack(tets)
    labels = np.concatenate(labels)
    # fix orientation (positive volume)
    v = points[tets]
    vol = np.einsum("ij,ij->i", np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), v[:, 3] - v[:, 0])
    neg = vol < 0
    tets[neg] = tets[neg][:, [0, 2, 1, 3]]
    used = np.unique(tets)
    renum = np.full(points.shape[0], -1)
    renum[used] = np.arange(used.size)
    return points[used], renum[tets], labels


def mesh_catheter(
    design,
    *,
    size: float = 0.15,
    layers: int = 6,
    contact: float = 0.03,
    curvature_points: int = 24,
    true_area: bool = False,
) -> CatheterMesh:
    """Tetrahedral mesh of the tip of ``design`` (see module docstring).

    Parameters
    ----------
    design
        A ``design.TipDesign``.
    size
        Largest triangle edge in the cross-section [mm].
    layers
        Prism layers along the bending length (the cap gets at least one of its own).
    contact
        Relative growth of the tube's outer ellipse that turns its tangent contacts into
        short flat patches.
    curvature_points
        Segments per full circle on curved boundaries: polygon area error 1.1 % at 24
        (1 − sin(2π/n) n/2π), which the coil's r⁴ bending stiffness doubles.
    true_area
        Move the vertices inside each curve's arcs outward so that every polygon holds its
        curve's area (:func:`~softcath.fem.nonlinear.true_area.area_true`); off by default. On
        the paper design (0.02 MPa, 4 layers) it takes the size 0.15 mm, 12-segment section's
        mid-span curvature from 2.2 % to 0.5 % under a converged section's, at no cost in
        unknowns; on designs with thick coil wire it overshoots (docs/nonlinear.md).
    """
    from skfem import MeshTet

    if not (np.isfinite(size) and 0 < size <= design.coil.outer_diameter / 2):
        raise NonlinearError(
            f"size = {size!r}: must be in (0, coil outer radius = {design.coil.outer_diameter / 2:g}] mm"
        )
    if not (isinstance(layers, (int, np.integer)) and layers >= 2):
        raise SettingError("layers", layers, "must be an integer >= 2")
    if not (0 <= contact < 0.2):
        raise SettingError("contact", contact, "must be in [0, 0.2)")
    length = design.tip.bending_length
    cap = design.tip.cap_thickness
    z_body = np.linspace(0.0, length - cap, layers + 1)
    n_cap = max(1, int(round(cap / (z_body[1] - z_body[0]))))
    z = np.concatenate([z_body, np.linspace(length - cap, length, n_cap + 1)[1:]])
    if not (isinstance(curvature_points, (int, np.integer)) and curvature_points >= 8):
        raise SettingError("curvature_points", curvature_points, "must be an integer >= 8")
    if not isinstance(true_area, bool):
        raise SettingError("true_area", true_area, "must be True or False")
    pts2, tri, cls = _section_triangles(
        design.section, size=size, contact=contact, curvature_points=int(curvature_points)
    )
    if true_area:
        pts2 = area_true(pts2, tri, section_curves(design.section, contact=contact))
    has_filler = design.filler is not None

    def keep(c, zmid):
        lab = c.copy()
        lab[c == _BORE] = 0
        lab[c == _LUMEN] = REGIONS["tube"] if zmid > length - cap else 0
        if not has_filler:
            lab[c == REGIONS["filler"]] = 0
        return lab

    points, tets, labels = _extrude(pts2, tri, cls, z, keep)
    mesh = MeshTet(np.ascontiguousarray(points.T), np.ascontiguousarray(tets.T))
    bfac = mesh.boundary_facets()
    fc = mesh.p[:, mesh.facets[:, bfac]].mean(axis=1)
    s = design.section
    base = bfac[np.abs(fc[2]) < 1e-9]
    in_lumen = (fc[0] / s.a_int) ** 2 + ((fc[1] - s.tube_center_y - s.h) / s.b_int) ** 2 < 1.0 + 1e-6
    lumen = bfac[in_lumen & (fc[2] > 1e-9) & (fc[2] < length - cap + 1e-9)]
    cap_f = bfac[in_lumen & np.isclose(fc[2], length - cap)]
    if lumen.size == 0 or cap_f.size == 0:
        raise NonlinearError("mesh: no lumen facets found; refine size")
    log.info(
        "catheter mesh: %d vertices, %d tets, %d lumen facets", mesh.p.shape[1], mesh.t.shape[1], lumen.size
    )
    return CatheterMesh(
        mesh=mesh, labels=labels, base_facets=base, lumen_facets=lumen, cap_facets=cap_f, length=length
    )


#: The coils' transverse (hoop) modulus is capped at this multiple of the stiffest silicone.
HOOP_CAP = 1000.0


def capped_hoop_modulus(design, coil, hoop_cap: float | None = HOOP_CAP) -> float:
    """The hoop modulus [MPa] the model gives ``coil``: its homogenised steel value, capped at
    ``hoop_cap`` times the stiffest silicone's E (tube, filler); ``None`` leaves it uncapped."""
    steel = coil_stiffness(coil).hoop_modulus
    if hoop_cap is None:
        return steel
    silicones = [design.tube.material] + ([design.filler] if design.filler is not None else [])
    return min(steel, hoop_cap * max(m.youngs_modulus for m in silicones))


def catheter_laws(design, *, hoop_cap: float | None = HOOP_CAP) -> dict[int, object]:
    """Finite-strain law per region label for ``design`` (module docstring).

    The coils' hoop modulus (steel, ~1.5e5 MPa) is capped at ``hoop_cap`` times the
    stiffest silicone's E: at that contrast the hoop strain is already below 0.1 % of
    the silicone's strain, while Newton's convergence radius — which shrinks with
    the stiffness contrast through the Green-strain terms of the coil — stays
    usable. The cap is a model change: on the paper's design it turns the
    lumen-loaded tip 0.64 % less in the linear range (−0.21 % at 3000, −2.1 % at
    300; :func:`~softcath.fem.nonlinear.hoop_cap.hoop_cap_effect` measures it on any
    mesh). ``hoop_cap=None`` keeps the steel value.
    """

    def coil_law(coil):
        e_l = coil_stiffness(coil).axial_modulus_tension
        e_t = capped_hoop_modulus(design, coil, hoop_cap)
        return AnisotropicSVK(
            transversely_isotropic(
                axial_modulus=e_l,
                transverse_modulus=e_t,
                axial_shear_modulus=e_l / (2 * 1.3),
                transverse_poisson=0.3,
                coupling_poisson=0.0,
            )
        )

    def silicone(m):
        yeoh = yeoh_at_modulus(m.yeoh, youngs_modulus=m.youngs_modulus, poisson_ratio=m.poisson_ratio)
        return isotropic_from_young(youngs_modulus=m.youngs_modulus, poisson_ratio=m.poisson_ratio, yeoh=yeoh)

    laws = {
        REGIONS["coil"]: coil_law(design.coil),
        REGIONS["tube"]: silicone(design.tube.material),
        REGIONS["channel"]: coil_law(design.channel),
    }
    if design.filler is not None:
        laws[REGIONS["filler"]] = silicone(design.filler)
    return laws


def from_tip_mesh(tip_mesh) -> CatheterMesh:
    """A :class:`CatheterMesh` from the linear FEM's ``softcath.fem.mesh.TipMesh`` (same labels 1–4, its facet
    tags).

    Lets the finite-strain solver run on exactly the mesh of the linear check
    (quadratic ``MeshTet2`` with curved boundary edges when the mesher made them).
    """

    mesh = tip_mesh.skfem_mesh()
    tags = tag_facets(mesh, tip_mesh.geometry)
    lumen = np.union1d(tags["lumen"], tags["cap"])
    if lumen.size == 0 or tags["cap"].size == 0 or tags["base"].size == 0:
        raise NonlinearError("tip mesh: no base, lumen or cap facets tagged")
    labels = np.asarray(tip_mesh.labels)
    unknown = sorted(set(np.unique(labels).tolist()) - set(REGIONS.values()))
    if unknown:
        raise NonlinearError(f"tip mesh labels {unknown}: not coil/tube/channel/filler (1-4)")
    return CatheterMesh(
        mesh=mesh,
        labels=labels,
        base_facets=tags["base"],
        lumen_facets=lumen,
        cap_facets=tags["cap"],
        length=float(tip_mesh.geometry.length),
    )
