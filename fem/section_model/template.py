"""Template section meshes: one gmsh mesh per section topology, morphed to each design.

Meshing a new section with gmsh costs ~0.1 s (OCC booleans, then the mesh),
most of a section-model design. Designs of one topology differ only in the
sizes and positions of their circles, ellipses and land lines, so one gmsh
mesh of a reference section (the design's, its sizes snapped to a 15 %
grid: :func:`reference_geometry`) is made per topology and mesh size and morphed to each design:

1. every template node lying on a boundary curve (circles and ellipses are
   conics ``(xc + a cos t, yc + b sin t)``, lands are vertical lines) keeps
   its curve; nodes on two curves (region corners, land corners) are solved
   for afresh by Newton on the new curves;
2. the other nodes of a curve keep their place between the curve's corners
   (piecewise linear in the curve parameter);
3. interior nodes follow by harmonic extension of the boundary displacement
   (the P1 Laplacian of the template, factorised once per template);
4. curved P2 edges get their midpoints on the new curve, at the template's
   fraction of the curve parameter between the edge's ends.

The morph is checked: every triangle's shape quality (4 sqrt(3) A / sum l^2)
must stay above :data:`QUALITY_RATIO` of the template's, every curved P2
triangle's Jacobian must keep its sign, and every triangle's region label at
its centroid must be the template's; otherwise :class:`MorphError` is raised.
:func:`templated` (used by
:func:`~softcath.fem.section_model.mesh.catheter_section_mesh` and the batched
models) logs a refused morph, or a template that could not be built, and the
caller meshes the design with gmsh instead: the template is a speed-up, never a
new way to fail. The reference section morphed onto itself is its gmsh mesh (to
round-off). The template's gmsh meshes are made in the section mesher's gmsh
session (``softcath.fem.mesh.initialize_gmsh``: signal dispositions kept).
"""

from __future__ import annotations

import dataclasses
import functools
import logging
import time
from dataclasses import dataclass
from typing import cast

import numpy as np
from scipy import sparse
from scipy.sparse.linalg import splu

from softcath.core.errors import DesignError
from softcath.core.interrupts import raise_pending_stop
from softcath.fem.geometry import TipGeometry
from softcath.fem.mesh.gmsh_section import _p2_triangles_valid
from softcath.fem.section_model.conics import (
    _CONIC,
    _ON_CURVE_MM,
    _VLINE,
    _corner_quality,
    _curves,
    _intersect,
    _param,
    _point,
    _quality,
    _residual,
)
from softcath.fem.section_model.mesh import SectionMesh, _catheter_cached
from softcath.fem.section_model.reference_section import TEMPLATE_STEP, reference_geometry

__all__ = [
    "QUALITY_RATIO",
    "TEMPLATE_STEP",
    "MorphError",
    "SectionTemplate",
    "morph",
    "reference_geometry",
    "section_template",
    "log_fallback",
    "template_mesh",
    "templated",
]

log = logging.getLogger(__name__)

#: Smallest ratio of a morphed triangle's shape quality to its template's.
QUALITY_RATIO = 0.5


class MorphError(DesignError):
    """The template cannot be morphed to a geometry within the quality bounds."""


@dataclass(frozen=True)
class _MorphPlan:
    """A template's morph bookkeeping that does not depend on the geometry (worked out once).

    Attributes
    ----------
    bad_line
        The first land line with fewer than two corners (the morph refuses it), or -1.
    entry_node, entry_curve, entry_param, entry_conic
        Every (corner, curve) pair of the curves with corners: its template parameter and
        whether the curve is a conic (whose corner parameters shift, wrapped to (-pi, pi]).
    free_node, free_curve, free_base, weights
        The other curve nodes, their curve, their template parameter on a conic (0 on a
        land line) and their linear-interpolation weights over the entries: the new
        parameter is ``free_base + weights @ entry values`` (the template's
        :func:`numpy.interp` between the curve's corners, as a matrix).
    first_curve
        Per boundary node, the first curve it lies on.
    bent_hit
        Rows and midside columns of the bent triangles' curved edges, and those edges.
    """

    bad_line: int
    entry_node: np.ndarray
    entry_curve: np.ndarray
    entry_param: np.ndarray
    entry_conic: np.ndarray
    free_node: np.ndarray
    free_curve: np.ndarray
    free_base: np.ndarray
    weights: np.ndarray
    first_curve: np.ndarray
    bent_hit: tuple[np.ndarray, np.ndarray, np.ndarray]


@dataclass(frozen=True)
class SectionTemplate:
    """A gmsh section mesh with every node's curve membership, ready to morph.

    Attributes
    ----------
    mesh
        The reference section's :class:`~softcath.fem.section_model.mesh.SectionMesh`.
    geometry, curves
        The reference geometry and its boundary curves (rows ``(kind, xc, yc, a, b)``).
    on_curve
        (n, ncurves) True where a node lies on a curve.
    params
        (n, ncurves) the node's parameter on each curve it lies on (NaN elsewhere).
    corners
        (k,) nodes on two curves and (k, 2) their curves.
    edge_curve, edge_frac
        Curve of every curved edge, and where gmsh put its midpoint between its ends
        (fraction of the curve parameter).
    quality
        Template shape quality per triangle.
    triangle_curved_edge, bent_triangles
        Per triangle and local edge (01, 12, 20) the curved edge's index or -1; the
        triangles with a curved edge.
    """

    mesh: object
    geometry: TipGeometry
    curves: np.ndarray
    on_curve: np.ndarray
    params: np.ndarray
    corners: np.ndarray
    corner_curves: np.ndarray
    edge_curve: np.ndarray
    edge_frac: np.ndarray
    quality: np.ndarray
    triangle_curved_edge: np.ndarray
    bent_triangles: np.ndarray
    interior: np.ndarray
    boundary: np.ndarray
    laplace_ib: sparse.csr_matrix
    laplace_ii: object = dataclasses.field(repr=False)

    @functools.cached_property
    def curve_plan(self) -> list[tuple[int, np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
        """Per curve with nodes: (curve, its nodes, its corners, which nodes are not corners,
        the corners' order by template parameter) — the morph's per-curve bookkeeping, once."""
        plan = []
        for c in range(self.on_curve.shape[1]):
            nodes = np.flatnonzero(self.on_curve[:, c])
            if nodes.size == 0:
                continue
            corner = self.corners[np.flatnonzero(self.on_curve[self.corners, c])]
            order = np.argsort(self.params[corner, c])
            plan.append((c, nodes, corner, ~np.isin(nodes, self.corners), order))
        return plan

    @functools.cached_property
    def morph_plan(self) -> _MorphPlan:
        """The morph's geometry-independent bookkeeping (:class:`_MorphPlan`), once per template."""
        return _morph_plan(self)


def _morph_plan(template: SectionTemplate) -> _MorphPlan:
    """Work out :class:`_MorphPlan`: the per-curve interpolation of the morph as one matrix.

    Per curve, the template's :func:`numpy.interp` of a value at the curve's corners
    (sorted by template parameter; periodic on a conic) is linear in those values, so
    interpolating the unit vectors gives its weights.
    """
    params, old = template.params, template.curves
    bad_line, entries, frees, blocks = -1, [], [], []
    for c, nodes, corner, free, order in template.curve_plan:
        conic = old[c, 0] == _CONIC
        if not conic and corner.size < 2:
            bad_line = c if bad_line < 0 else bad_line
            continue
        if corner.size == 0:  # a conic without corners keeps its nodes' parameters
            continue
        ta, t_free = params[corner, c][order], params[nodes[free], c]
        unit = np.eye(corner.size)
        period = 2 * np.pi if conic else None
        blocks.append(np.column_stack([np.interp(t_free, ta, u, period=period) for u in unit]))
        entries += [(k, c, t, conic) for k, t in zip(corner[order], ta, strict=True)]
        frees += [(i, c, t if conic else 0.0) for i, t in zip(nodes[free], t_free, strict=True)]
    weights = np.zeros((len(frees), len(entries)))
    r = q = 0
    for block in blocks:  # block diagonal: a curve's nodes follow that curve's corners only
        weights[r : r + block.shape[0], q : q + block.shape[1]] = block
        r, q = r + block.shape[0], q + block.shape[1]
    e = np.array(entries, dtype=float).reshape(-1, 4)
    f = np.array(frees, dtype=float).reshape(-1, 3)
    first = np.argmax(template.on_curve, axis=1)
    which = template.triangle_curved_edge[template.bent_triangles]
    rows, cols = np.nonzero(which >= 0)
    return _MorphPlan(
        bad_line=int(bad_line),
        entry_node=e[:, 0].astype(np.int64),
        entry_curve=e[:, 1].astype(np.int64),
        entry_param=e[:, 2],
        entry_conic=e[:, 3].astype(bool),
        free_node=f[:, 0].astype(np.int64),
        free_curve=f[:, 1].astype(np.int64),
        free_base=f[:, 2],
        weights=weights,
        first_curve=first[template.boundary],
        bent_hit=(rows, cols + 3, which[rows, cols]),
    )


@functools.lru_cache(maxsize=256)
def _template(reference: TipGeometry, mesh_size: float, segments: int) -> SectionTemplate:
    m = _catheter_cached(reference, mesh_size, segments)
    curves = _curves(reference)
    x, y = m.points[:, 0, None], m.points[:, 1, None]
    on = np.abs(_residual(curves, x, y)) < _ON_CURVE_MM
    # Vertical land lines are segments: a node is on one only between its end corners
    # (the segments are short, so a loose y window suffices).
    params = np.where(on, _param(curves, x, y), np.nan)
    count = on.sum(axis=1)
    if count.max() > 2:
        raise MorphError("template", int(count.max()), "a node lies on more than two curves")
    corners = np.flatnonzero(count == 2)
    corner_curves = np.array([np.flatnonzero(on[i]) for i in corners]).reshape(-1, 2)
    # Newton along the line when one curve is a land line (the line's parameter is y).
    line_first = curves[corner_curves[:, 1], 0] == _VLINE
    corner_curves[line_first] = corner_curves[line_first][:, ::-1]
    ce = m.curved_edges
    both = on[ce[:, 0]] & on[ce[:, 1]]
    mid_res = np.abs(_residual(curves, m.curved_midpoints[:, 0, None], m.curved_midpoints[:, 1, None]))
    edge_curve = np.argmin(np.where(both, mid_res, np.inf), axis=1)
    if not both[np.arange(len(ce)), edge_curve].all():
        raise MorphError("template", len(ce), "a curved edge has no curve through both its ends")
    # Where gmsh put each midpoint between its ends, as a fraction of the curve parameter.
    cc = curves[edge_curve]
    ta, tb = params[ce[:, 0], edge_curve], params[ce[:, 1], edge_curve]
    tm = _param(cc, m.curved_midpoints[:, 0], m.curved_midpoints[:, 1])
    conic = cc[:, 0] == _CONIC
    span = np.where(conic, np.angle(np.exp(1j * (tb - ta))), tb - ta)
    edge_frac = np.where(conic, np.angle(np.exp(1j * (tm - ta))), tm - ta) / span
    nv = np.int64(m.points.shape[0])
    keys = np.sort(ce, axis=1) @ np.array([nv, 1])
    order = np.argsort(keys)
    tri_curved = np.full(m.triangles.shape, -1)
    for j, (a, b) in enumerate(((0, 1), (1, 2), (2, 0))):
        e = np.sort(m.triangles[:, [a, b]], axis=1) @ np.array([nv, 1])
        pos = np.clip(np.searchsorted(keys, e, sorter=order), 0, max(keys.size - 1, 0))
        hit = keys[order[pos]] == e if keys.size else np.zeros(len(e), bool)
        tri_curved[hit, j] = order[pos[hit]]
    # P1 Laplacian (cotangent weights) of the template for the harmonic extension.
    from skfem import Basis, ElementTriP1, MeshTri
    from skfem.models.poisson import laplace

    lap = laplace.assemble(Basis(MeshTri(m.points.T.copy(), m.triangles.T.copy()), ElementTriP1())).tocsr()
    boundary = np.flatnonzero(count > 0)
    interior = np.flatnonzero(count == 0)
    lu = splu(lap[interior][:, interior].tocsc())
    return SectionTemplate(
        mesh=m,
        geometry=reference,
        curves=curves,
        on_curve=on,
        params=params,
        corners=corners,
        corner_curves=corner_curves,
        edge_curve=edge_curve,
        edge_frac=edge_frac,
        quality=_quality(m.points, m.triangles),
        triangle_curved_edge=tri_curved,
        bent_triangles=np.flatnonzero((tri_curved >= 0).any(axis=1)),
        interior=interior,
        boundary=boundary,
        laplace_ib=lap[interior][:, boundary],
        laplace_ii=lu,
    )


def section_template(geometry: TipGeometry, *, mesh_size: float, segments: int) -> SectionTemplate:
    """The template for ``geometry``'s topology at this mesh size (made once per process).

    Raises
    ------
    MorphError
        For an as-built ``coat`` filler (``geometry.filler_coat > 0``): its outer circle is
        a region boundary the templates do not carry, so such a section is meshed by gmsh.
    """
    if geometry.filler_coat > 0:
        raise MorphError(
            "geometry.filler_coat", geometry.filler_coat, "templates carry no coat circle; must be 0"
        )
    return _template(reference_geometry(geometry), float(mesh_size), int(segments))


def templated(geometry: TipGeometry, *, mesh_size: float, segments: int):
    """``(template, morphed mesh)`` for ``geometry``, or ``None`` when the caller should mesh with gmsh.

    A morph beyond the quality bounds (:class:`MorphError`) is logged at INFO; a template
    that could not be built or morphed for any other reason (gmsh failing on the reference
    section, a numerical failure) is logged at WARNING. Neither is an error: the design
    is meshed afresh by gmsh, whose answer the template's approximates.
    """
    try:
        template = section_template(geometry, mesh_size=mesh_size, segments=segments)
        return template, morph(template, geometry)
    except Exception as exc:  # the caller's fallback is the template-free path: nothing is lost
        raise_pending_stop()
        log_fallback(geometry, exc)
    return None


def log_fallback(geometry: TipGeometry, exc: Exception) -> None:
    """Log why ``geometry`` is meshed with gmsh instead of its template (see :func:`templated`)."""
    if isinstance(exc, MorphError):
        log.info("template mesh refused for %s (%s); meshing with gmsh", geometry.digest(), exc)
    else:
        log.warning(
            "template mesh failed for %s (%s: %s); meshing with gmsh",
            geometry.digest(),
            type(exc).__name__,
            exc,
        )


def template_mesh(geometry: TipGeometry, *, mesh_size: float, segments: int):
    """The morphed template mesh of ``geometry`` (a ``SectionMesh``), or ``None`` (see :func:`templated`)."""
    got = templated(geometry, mesh_size=mesh_size, segments=segments)
    return None if got is None else got[1]


def morph(template: SectionTemplate, geometry: TipGeometry):
    """The template's mesh morphed to ``geometry`` (a ``SectionMesh``), or :class:`MorphError`.

    Parameters
    ----------
    template
        From :func:`section_template`.
    geometry
        The design's section geometry.
    """

    t0 = time.perf_counter()
    m, params, new = template.mesh, template.params, _curves(geometry)
    new_params = params.copy()
    # 1. corners: Newton on the first curve's parameter to meet the second curve.
    c1, c2 = template.corner_curves[:, 0], template.corner_curves[:, 1]
    k = template.corners
    n1, n2 = new[c1], new[c2]
    cx, cy = _intersect(n1, n2, params[k, c1])
    miss = np.maximum(np.abs(_residual(n1, cx, cy)), np.abs(_residual(n2, cx, cy)))
    if not (np.isfinite(miss).all() and miss.max() < _ON_CURVE_MM):
        raise MorphError("geometry", geometry.digest(), "a region corner of the template has no counterpart")
    new_params[k, c1] = _param(n1, cx, cy)
    new_params[k, c2] = _param(n2, cx, cy)
    # 2. other curve nodes: parameter shift interpolated between the curve's corners.
    plan = template.morph_plan
    if plan.bad_line >= 0:
        raise MorphError("template", plan.bad_line, "a land line needs two corners")
    value = new_params[plan.entry_node, plan.entry_curve]
    shift = np.angle(np.exp(1j * (value - plan.entry_param)))
    value = np.where(plan.entry_conic, shift, value)  # conics: the shift; lines: the parameter
    new_params[plan.free_node, plan.free_curve] = plan.free_base + plan.weights @ value
    xy = m.points.copy()
    b, first = template.boundary, plan.first_curve
    bx, by = _point(new[first], new_params[b, first])
    xy[b, 0], xy[b, 1] = bx, by
    xy[k, 0], xy[k, 1] = cx, cy
    # 3. interior: harmonic extension of the boundary displacement.
    d_b = xy[b] - m.points[b]
    xy[template.interior] = m.points[template.interior] - template.laplace_ii.solve(template.laplace_ib @ d_b)
    # 4. curved midpoints on the new curve, at the template's parameter fraction.
    ce, ec = m.curved_edges, template.edge_curve
    ta, tb = new_params[ce[:, 0], ec], new_params[ce[:, 1], ec]
    conic = new[ec, 0] == _CONIC
    span = np.where(conic, np.angle(np.exp(1j * (tb - ta))), tb - ta)
    tm = ta + template.edge_frac * span
    mx, my = _point(new[ec], tm)
    mids = np.column_stack([mx, my])
    _check(template, geometry, xy, mids, _p2_triangles_valid)
    return SectionMesh(
        xy,
        m.triangles,
        m.labels,
        ce,
        mids,
        m.lumen_edges,
        time.perf_counter() - t0,
        f"{geometry.digest()}|{m.key.split('|', 1)[1]}|template",
    )


def _check(template: SectionTemplate, geometry: TipGeometry, xy, mids, p2_valid) -> None:
    """Raise :class:`MorphError` if the morph degraded a triangle beyond the bounds."""
    m = cast("SectionMesh", template.mesh)
    x, y = xy[:, 0][m.triangles], xy[:, 1][m.triangles]  # (m, 3) corners, for the three checks
    ratio = _corner_quality(x, y) / template.quality
    if not (np.isfinite(ratio).all() and ratio.min() >= QUALITY_RATIO):
        raise MorphError("morph.quality_ratio", float(np.nanmin(ratio)), f"must be >= {QUALITY_RATIO}")
    # Only triangles with a curved edge can fold by curvature (the others are checked by their area).
    bent = template.bent_triangles
    x6 = np.empty((bent.size, 6, 2))
    for d, corner in enumerate((x[bent], y[bent])):
        x6[:, :3, d] = corner
        x6[:, 3:, d] = 0.5 * (corner + corner[:, [1, 2, 0]])
    rows, cols, edges = template.morph_plan.bent_hit
    x6[rows, cols] = mids[edges]
    valid = p2_valid(x6)
    if not valid.all():
        raise MorphError("morph.p2_jacobian", int((~valid).sum()), "curved triangles folded")
    # At z = 0 (as the section mesh's labels were made): no z tests, they all pass there.
    labels = geometry.classify(x.sum(axis=1) / 3, y.sum(axis=1) / 3)
    bad = int((labels != m.labels).sum())
    if bad:
        raise MorphError("morph.labels", bad, "triangles changed region; must be 0")
