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
    seconds to minutes on thin walls, notes/fem.md), so it runs in a
    temporary directory (it writes a stray file) and its result is cached.

Both return a :class:`TipMesh` whose region volumes are checked against the
exact geometry (within 1 %) and whose elements are checked for inversion.
"""

from __future__ import annotations

import contextlib
import logging
import math
import os
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from softcath.fem.errors import MeshError
from softcath.fem.section import REGIONS, VOID, TipGeometry

__all__ = ["TipMesh", "MeshQuality", "mesh_tip", "cache_dir", "MESHERS", "scaled_jacobian"]

log = logging.getLogger(__name__)

MESHERS = ("gmsh", "tetwild")
#: Bumped whenever the meshing recipe changes, so stale cache entries are ignored.
_RECIPE = "fem-mesh-v2"
#: Region volumes must match the exact geometry within this (issue 3 §2).
VOLUME_TOL = 0.01
#: Curvature sizing of the section mesh (elements per full turn of a boundary).
#: With the midside nodes on the exact curves the faceting error is O(theta^4),
#: so 16 segments keep region volumes within 0.02 % (tests/fem/test_fem_mesh.py).
_SEGMENTS_PER_TURN = 16


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
        Region label per tet (``softcath.fem.section`` constants).
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


def cache_dir() -> Path:
    """Mesh cache folder: ``$SOFTCATH_CACHE/fem-mesh`` or ``~/.cache/softcath/fem-mesh``."""
    root = os.environ.get("SOFTCATH_CACHE")
    base = Path(root) if root else Path.home() / ".cache" / "softcath"
    return base / "fem-mesh"


def mesh_tip(
    geometry: TipGeometry,
    *,
    mesh_size: float = 0.04,
    mesher: str = "gmsh",
    axial_ratio: float = 5.0,
    use_cache: bool = True,
    cache: Path | None = None,
) -> TipMesh:
    """Mesh the tip, or load the identical mesh from the cache.

    Parameters
    ----------
    geometry
        The tip (mm).
    mesh_size
        Target element size across the section, mm (> 0). Curved boundaries are
        refined further (>= 40 segments per full turn).
    mesher
        ``"gmsh"`` (fast, default) or ``"tetwild"``.
    axial_ratio
        gmsh back-end: layer thickness along z = ``axial_ratio * mesh_size``.
    use_cache, cache
        Read/write the on-disk cache (folder; default :func:`cache_dir`).

    Raises
    ------
    MeshError
        Inverted elements, or a region volume off the exact one by more than 1 %.
    """
    from softcath.design.errors import DesignError

    if mesher not in MESHERS:
        raise DesignError("mesher", mesher, f"must be one of {MESHERS}")
    if not (math.isfinite(mesh_size) and 0.005 <= mesh_size <= 0.5):
        raise DesignError("mesh_size", mesh_size, "must be in [0.005, 0.5] mm")
    if not (math.isfinite(axial_ratio) and 0.5 <= axial_ratio <= 10):
        raise DesignError("axial_ratio", axial_ratio, "must be in [0.5, 10]")
    import hashlib

    key = hashlib.sha256(
        f"{_RECIPE}|{geometry.digest()}|{mesher}|{mesh_size:.6g}|{axial_ratio:.6g}".encode()
    ).hexdigest()[:20]
    folder = cache or cache_dir()
    path = folder / f"{key}.npz"
    if use_cache and path.exists():
        try:
            return _load(path, geometry, mesher, mesh_size, key)
        except (OSError, KeyError, ValueError) as exc:  # a corrupt entry is re-made
            log.warning("ignoring unreadable mesh cache entry %s: %s", path, exc)
    t0 = time.perf_counter()
    if mesher == "gmsh":
        points, tets, cedges, cmid, labels = _extruded_gmsh(geometry, mesh_size, axial_ratio)
    else:
        points, tets = _tetwild(geometry, mesh_size)
        cedges, cmid = np.zeros((0, 2), dtype=np.int64), np.zeros((0, 3))
        labels = _label(geometry, points, tets)
    keep = labels != VOID
    points, tets, remap = _compact(points, tets[keep])
    labels = labels[keep]
    tets = _orient(points, tets)
    cedges = remap[cedges]
    ok = (cedges >= 0).all(axis=1)
    cedges, cmid = cedges[ok], cmid[ok]
    seconds = time.perf_counter() - t0
    arrays = dict(points=points, tets=tets, labels=labels, curved_edges=cedges, curved_midpoints=cmid)
    mesh = _finish(geometry, arrays, mesher, mesh_size, seconds, key)
    if use_cache:
        folder.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(".tmp.npz")
        np.savez_compressed(tmp, seconds=np.array(seconds), **arrays)
        os.replace(tmp, path)  # atomic: parallel sweeps never read half a file
    return mesh


# ----------------------------------------------------------------------------
def _finish(geometry, arrays, mesher, mesh_size, seconds, key, cached=False):
    points, tets, labels = arrays["points"], arrays["tets"], arrays["labels"]
    vol = tet_volumes(points, tets)
    if (vol <= 0).any():
        raise MeshError(f"mesh has {(vol <= 0).sum()} inverted or flat tetrahedra; refused")
    if arrays["curved_edges"].size:
        vol = curved_volumes(skfem_mesh(points, tets, arrays["curved_edges"], arrays["curved_midpoints"]))
        if (vol <= 0).any():
            raise MeshError(f"{(vol <= 0).sum()} curved tetrahedra are inverted; refused")
    region_volumes = {
        name: float(vol[labels == k].sum()) for k, name in REGIONS.items() if (labels == k).any()
    }
    exact = exact_volumes(geometry)
    sj = scaled_jacobian(points, tets)
    quality = MeshQuality(
        n_tets=int(tets.shape[0]),
        n_vertices=int(points.shape[0]),
        min_scaled_jacobian=float(sj.min()),
        p01_scaled_jacobian=float(np.percentile(sj, 1)),
        n_below_0_1=int((sj < 0.1).sum()),
    )
    mesh = TipMesh(
        points=points,
        tets=tets,
        labels=labels,
        geometry=geometry,
        mesher=mesher,
        mesh_size=mesh_size,
        region_volumes=region_volumes,
        exact_volumes=exact,
        quality=quality,
        seconds=seconds,
        cached=cached,
        key=key,
        curved_edges=arrays["curved_edges"],
        curved_midpoints=arrays["curved_midpoints"],
    )
    bad = {k: e for k, e in mesh.volume_errors().items() if abs(e) > VOLUME_TOL}
    if bad:
        text = ", ".join(f"{k} {100 * e:+.2f} %" for k, e in bad.items())
        raise MeshError(f"region volumes off the exact geometry by more than 1 %: {text}")
    return mesh


def _load(path, geometry, mesher, mesh_size, key) -> TipMesh:
    names = ("points", "tets", "labels", "curved_edges", "curved_midpoints")
    with np.load(path) as data:
        arrays = {k: data[k] for k in names}
        seconds = float(data["seconds"])
    log.info("mesh cache hit %s", path.name)
    return _finish(geometry, arrays, mesher, mesh_size, seconds, key, cached=True)


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


def exact_volumes(geometry: TipGeometry) -> dict[str, float]:
    """Exact region volumes (mm^3): lumen-part areas over the length, plus the cap."""
    g = geometry
    body = g.exact_areas()
    full = TipGeometry(**{**g.__dict__, "lumen_a": g.lumen_a, "lumen_b": g.lumen_b})
    cap_area = _cap_areas(full)
    lb = g.length - g.cap_thickness
    return {k: body[k] * lb + cap_area[k] * g.cap_thickness for k in body}


def _cap_areas(g: TipGeometry) -> dict[str, float]:
    # In the cap the lumen is tube material: classify at a z inside the cap.
    n = 2000
    r = g.coil_outer_radius
    s = (np.arange(n) + 0.5) / n * 2 * r - r
    xx, yy = np.meshgrid(s, s)
    lab = g.classify(xx.ravel(), yy.ravel(), np.full(xx.size, g.length))
    da = (2 * r / n) ** 2
    return {name: float((lab == k).sum() * da) for k, name in REGIONS.items()}


def tet_volumes(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Signed volumes (mm^3) of tetrahedra."""
    p = points[tets]
    return np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6


def scaled_jacobian(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Min over the corners of det[e1 e2 e3] / (|e1| |e2| |e3|), scaled: regular tet = 1."""
    p = points[tets]
    out = np.full(tets.shape[0], np.inf)
    corners = ((0, 1, 2, 3), (1, 2, 0, 3), (2, 0, 1, 3), (3, 0, 2, 1))
    for a, b, c, d in corners:
        e1, e2, e3 = p[:, b] - p[:, a], p[:, c] - p[:, a], p[:, d] - p[:, a]
        det = np.einsum("ij,ij->i", e1, np.cross(e2, e3))
        norm = np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1) * np.linalg.norm(e3, axis=1)
        out = np.minimum(out, det / norm)
    return out * math.sqrt(2.0)


def _orient(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    tets = tets.copy()
    neg = tet_volumes(points, tets) < 0
    tets[neg, 2], tets[neg, 3] = tets[neg, 3], tets[neg, 2].copy()
    return tets


def _compact(points: np.ndarray, tets: np.ndarray):
    used = np.unique(tets)
    remap = np.full(points.shape[0], -1, dtype=np.int64)
    remap[used] = np.arange(used.size)
    return points[used], remap[tets], remap


def _label(geometry: TipGeometry, points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    c = points[tets].mean(axis=1)
    return geometry.classify(c[:, 0], c[:, 1], c[:, 2])


# ---------------------------------------------------------------- gmsh ------
def restore_sigpipe_ignored() -> None:
    """Ignore SIGPIPE again at the C level after ``gmsh.initialize()``.

    gmsh resets SIGPIPE to its default (terminate) behind Python's back, and
    ``finalize`` does not undo it. Python ignores SIGPIPE so that a write to a
    closed pipe raises ``BrokenPipeError``; without this, a later write to a dead
    worker's pipe kills the whole process (it killed a test run of a sweep whose
    worker was SIGKILLed). ``signal.signal`` only works in the main thread and
    believes SIGPIPE is still ignored, so the libc call restores what it believes.
    """
    if os.name != "posix":
        return
    import ctypes
    import signal

    libc = ctypes.CDLL(None, use_errno=True)
    libc.signal.restype = ctypes.c_void_p
    libc.signal.argtypes = (ctypes.c_int, ctypes.c_void_p)
    libc.signal(int(signal.SIGPIPE), ctypes.c_void_p(1))  # 1 = SIG_IGN


@contextlib.contextmanager
def _gmsh_session():
    import gmsh

    gmsh.initialize(interruptible=False)
    restore_sigpipe_ignored()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        yield gmsh
    finally:
        gmsh.finalize()


def section_triangles(
    geometry: TipGeometry, mesh_size: float, segments_per_turn: int = 0, *, fast: bool = False
):
    """2-D mesh of the whole coil disk.

    Every region boundary (including lumens and lands) is a mesh edge.
    ``fast`` sizes curves by a fixed number of points per full turn
    (``Mesh.MinimumCirclePoints``) with gmsh's Delaunay algorithm instead of
    curvature sizing with Frontal-Delaunay: the same boundary resolution, about
    4x less meshing time (47 vs 190 ms for the paper section), for the 2-D
    section model where meshing dominates the cost of a design.

    Returns
    -------
    xy, tri, curved_edges, curved_midpoints
        Vertices (n, 2), triangles (m, 3), and the edges lying on curved
        boundaries (k, 2) with their exact midpoints (k, 2) from gmsh's
        second-order mesh.
    """
    g = geometry
    lands = g.lands()
    with _gmsh_session() as gmsh:
        occ = gmsh.model.occ
        gmsh.model.add("section")
        ro, ri = g.coil_outer_radius, g.coil_inner_radius
        yc, rco, rci = g.channel_y, g.channel_outer_radius, g.channel_inner_radius

        def disk(xc, yc_, r):
            return [(2, occ.addDisk(xc, yc_, 0, r, r))]

        # The regions are built as disjoint pieces (so no tangent curve survives
        # inside a land) and fragmented together for a conforming partition.
        # Tube with its lands: (ellipse U land strips) inside the coil ID, outside the channel.
        tube = [(2, _ellipse(occ, 0.0, g.tube_y, g.tube_a, g.tube_b))]
        x = lands["tube_coil"]
        tools = [(2, occ.addRectangle(-x, g.tube_y, 0, 2 * x, ri + 0.5 * (ro - ri) - g.tube_y))]
        x = lands["tube_channel"]
        tools.append((2, occ.addRectangle(-x, yc, 0, 2 * x, g.tube_y - yc)))
        tube, _ = occ.fuse(tube, tools)
        tube, _ = occ.intersect(tube, disk(0, 0, ri))
        tube, _ = occ.cut(tube, disk(0, yc, rco))
        # Coil with the channel-coil land (the steel-bonded strip under the channel).
        x = lands["channel_coil"]
        coil, _ = occ.cut(disk(0, 0, ro), disk(0, 0, ri))
        strip, _ = occ.intersect([(2, occ.addRectangle(-x, -ro, 0, 2 * x, ro + yc))], disk(0, 0, ro))
        coil, _ = occ.fuse(coil, strip)
        coil, _ = occ.cut(coil, disk(0, yc, rco))
        channel, _ = occ.cut(disk(0, yc, rco), disk(0, yc, rci))
        channel_lumen = disk(0, yc, rci)
        lumen = [(2, _ellipse(occ, 0.0, g.lumen_y, g.lumen_a, g.lumen_b))]
        rest, _ = occ.cut(disk(0, 0, ro), occ.copy(coil) + disk(0, yc, rco) + occ.copy(tube))
        tube, _ = occ.cut(tube, occ.copy(lumen))
        pieces = coil + channel + channel_lumen + tube + lumen + rest
        occ.fragment(pieces[:1], pieces[1:])
        occ.synchronize()
        # Grade the mesh down to ~2 x land_gap around the land corners: the thin
        # cusps beside the lands then get short boundary edges, whose curved
        # midpoints cannot fold the wedge triangles (with 16 segments per turn
        # they did, and straightening them cost the channel 0.6 % of its area).
        corners = []
        for dim, tag in gmsh.model.getEntities(0):
            px, _, _ = gmsh.model.getValue(dim, tag, [])
            if any(abs(abs(px) - xl) < 1e-7 for xl in lands.values() if xl > 0):
                corners.append(tag)
        if corners:
            field = gmsh.model.mesh.field
            dist = field.add("Distance")
            field.setNumbers(dist, "PointsList", corners)
            thr = field.add("Threshold")
            field.setNumber(thr, "InField", dist)
            field.setNumber(thr, "SizeMin", min(mesh_size, 3.0 * g.land_gap))
            field.setNumber(thr, "SizeMax", mesh_size)
            field.setNumber(thr, "DistMin", g.land_gap)
            field.setNumber(thr, "DistMax", 5.0 * g.land_gap)
            field.setAsBackgroundMesh(thr)
        gmsh.option.setNumber("Mesh.MeshSizeMax", mesh_size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
        if fast:
            gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
            gmsh.option.setNumber("Mesh.MinimumCirclePoints", segments_per_turn or _SEGMENTS_PER_TURN)
            gmsh.option.setNumber("Mesh.Algorithm", 5)  # Delaunay
            gmsh.option.setNumber("Mesh.Smoothing", 0)  # half of the meshing time; Delaunay shapes suffice
        else:
            gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", segments_per_turn or _SEGMENTS_PER_TURN)
            gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay: well-shaped triangles
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)  # midside nodes on the exact curves
        return p2_triangles(gmsh)


def p2_triangles(gmsh):
    """The 2-D second-order mesh of an open gmsh session as corner triangles and curved edges.

    Returns
    -------
    xy, tri, curved_edges, curved_midpoints
        Corner vertices (n, 2), triangles (m, 3), the edges lying on curved
        boundaries (k, 2) and their exact midpoints (k, 2).
    """
    tags, coords, _ = gmsh.model.mesh.getNodes()
    xy = coords.reshape(-1, 3)[:, :2]
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(tags.size)
    etypes, _, enodes = gmsh.model.mesh.getElements(2)
    tris = []
    for et, en in zip(etypes, enodes, strict=True):
        if et != 9:
            raise MeshError(f"gmsh returned element type {et}, expected 6-node triangles")
        tris.append(index[en.astype(np.int64)].reshape(-1, 6))
    tri6 = np.vstack(tris)
    corner = np.unique(tri6[:, :3])
    remap = np.full(xy.shape[0], -1, dtype=np.int64)
    remap[corner] = np.arange(corner.size)
    tri = remap[tri6[:, :3]]
    # Edges whose gmsh midside node is off the straight midpoint lie on a curve.
    pairs = ((0, 1, 3), (1, 2, 4), (2, 0, 5))
    ends = np.vstack([tri[:, [i, j]] for i, j, _ in pairs])
    mids = np.vstack([xy[tri6[:, k]] for _, _, k in pairs])
    straight = 0.5 * (xy[corner][ends[:, 0]] + xy[corner][ends[:, 1]])
    bent = np.linalg.norm(mids - straight, axis=1) > 1e-12
    # A thin triangle against a curve (next to a land edge) can fold when its edge
    # is bent; such edges stay straight (their faceting error is local and tiny).
    folded = ~_p2_triangles_valid(xy[tri6])
    bent &= ~np.tile(folded, 3)
    edge_key = np.sort(ends, axis=1)
    if folded.any():
        bad_keys = {tuple(k) for k in edge_key[np.tile(folded, 3)]}
        bent &= np.array([tuple(k) not in bad_keys for k in edge_key])
        log.info("kept %d curved edges straight to avoid folded triangles", len(bad_keys))
    ends, mids = ends[bent], mids[bent]
    ends = np.sort(ends, axis=1)
    _, first = np.unique(ends[:, 0] * np.int64(corner.size) + ends[:, 1], return_index=True)
    return xy[corner], tri, ends[first], mids[first]


def _p2_triangles_valid(x6: np.ndarray) -> np.ndarray:
    """True where a 6-node triangle's Jacobian keeps the sign of its straight version.

    ``x6`` (m, 6, 2): corners then midsides (01, 12, 20). The Jacobian of a P2
    triangle is quadratic; it is checked at the 6 nodes and the centroid.
    """
    pts = [(0, 0), (1, 0), (0, 1), (0.5, 0), (0.5, 0.5), (0, 0.5), (1 / 3, 1 / 3)]
    e1, e2 = x6[:, 1] - x6[:, 0], x6[:, 2] - x6[:, 0]
    lin = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    ok = np.ones(len(x6), bool)
    for r, s in pts:
        lam = 1 - r - s
        # dN/dr, dN/ds of the 6 P2 shape functions at (r, s)
        dr = np.array([1 - 4 * lam, 4 * r - 1, 0, 4 * (lam - r), 4 * s, -4 * s])
        ds = np.array([1 - 4 * lam, 0, 4 * s - 1, -4 * r, 4 * r, 4 * (lam - s)])
        jr = np.einsum("k,mkd->md", dr, x6)
        js = np.einsum("k,mkd->md", ds, x6)
        det = jr[:, 0] * js[:, 1] - jr[:, 1] * js[:, 0]
        ok &= det * np.sign(lin) > 0.05 * np.abs(lin)
    return ok


def _ellipse(occ, xc: float, yc: float, a: float, b: float) -> int:
    if a >= b:
        return occ.addDisk(xc, yc, 0, a, b)
    tag = occ.addDisk(xc, yc, 0, b, a)  # OCC wants rx >= ry: build lying, stand it up
    occ.rotate([(2, tag)], xc, yc, 0, 0, 0, 1, math.pi / 2)
    return tag


def _extruded_gmsh(g: TipGeometry, mesh_size: float, axial_ratio: float, segments_per_turn=0):
    xy, tri, ce2, cm2 = section_triangles(g, mesh_size, segments_per_turn)
    dz = axial_ratio * mesh_size
    lb = g.length - g.cap_thickness
    n1 = max(2, math.ceil(lb / dz))
    n2 = max(1, math.ceil(g.cap_thickness / dz))
    z = np.concatenate([np.linspace(0, lb, n1 + 1), np.linspace(lb, g.length, n2 + 1)[1:]])
    # Label each section triangle by its centroid (safe: it lies a third of the
    # triangle's height from any edge, beyond the circular segment between a
    # boundary chord and its arc) and give its three tets that label. A tet's
    # own centroid is not safe: next to a curved boundary it can fall inside that
    # segment, on the other region's side (24 filler tets became channel so).
    cen = xy[tri].mean(axis=1)
    body = g.classify(cen[:, 0], cen[:, 1], np.zeros(len(cen)))
    cap = g.classify(cen[:, 0], cen[:, 1], np.full(len(cen), g.length))
    per_layer = [cap if z[k] >= lb - 1e-12 else body for k in range(z.size - 1)]
    keep = [lab != VOID for lab in per_layer]
    points, tets, ce3, cm3 = extrude(xy, tri, z, keep, ce2, cm2)
    # extrude() stacks, per layer, the first, second and third tets of all prisms
    labels = np.concatenate([np.tile(lab[k], 3) for lab, k in zip(per_layer, keep, strict=True)])
    return points, tets, ce3, cm3, labels


def extrude(xy, tri, z, keep=None, curved_edges=None, curved_midpoints=None):
    """Extrude a 2-D triangulation along z into a conforming tet mesh.

    Parameters
    ----------
    xy, tri
        Section vertices (n, 2) and triangles (m, 3).
    z
        Increasing layer levels (mm).
    keep
        Per layer, a boolean mask of the triangles to extrude (default: all).
    curved_edges, curved_midpoints
        2-D edges on curved boundaries (k, 2) and their exact midpoints (k, 2).

    Returns
    -------
    points, tets, curved_edges_3d, curved_midpoints_3d
    """
    z = np.asarray(z, float)
    n2d = xy.shape[0]
    points = np.column_stack([np.tile(xy, (z.size, 1)), np.repeat(z, n2d)])
    if keep is None:
        keep = [np.ones(len(tri), bool)] * (z.size - 1)
    if curved_edges is None:
        curved_edges, curved_midpoints = np.zeros((0, 2), np.int64), np.zeros((0, 2))
    ce2, cm2 = np.sort(np.asarray(curved_edges), axis=1), np.asarray(curved_midpoints)
    # Global-index split: order each triangle's vertices ascending, then the
    # three tets below share quad diagonals with every neighbour.
    v = np.sort(tri, axis=1)
    v0, v1, v2 = v[:, 0], v[:, 1], v[:, 2]
    tets = []
    for k in range(z.size - 1):
        b, t = k * n2d, (k + 1) * n2d
        a0, a1, a2 = v0[keep[k]], v1[keep[k]], v2[keep[k]]
        tets.append(np.column_stack([a0 + b, a1 + b, a2 + b, a0 + t]))
        tets.append(np.column_stack([a1 + b, a2 + b, a0 + t, a1 + t]))
        tets.append(np.column_stack([a2 + b, a0 + t, a1 + t, a2 + t]))
    # Curved 3-D edges: each curved 2-D edge (i < j) at every level, and the quad
    # diagonal above it (bottom j to top i, the split rule above), at mid-height.
    i, j = ce2[:, 0], ce2[:, 1]
    cedges, cmid = [], []
    for k in range(z.size):
        b = k * n2d
        cedges.append(np.column_stack([i + b, j + b]))
        cmid.append(np.column_stack([cm2, np.full(len(i), z[k])]))
        if k + 1 < z.size:
            cedges.append(np.column_stack([j + b, i + b + n2d]))
            cmid.append(np.column_stack([cm2, np.full(len(i), 0.5 * (z[k] + z[k + 1]))]))
    return points, np.vstack(tets), np.vstack(cedges), np.vstack(cmid)


# ------------------------------------------------------------- tetwild ------
def interface_surface(g: TipGeometry, mesh_size: float) -> tuple[np.ndarray, np.ndarray]:
    """Triangulated surface of every region boundary and interface of the tip.

    Made from the exact section (gmsh) extruded along z: the outer skin, the
    lumens, the cap and every material interface, as one (non-manifold)
    surface, so a volume mesher keeps the interfaces embedded.
    """
    # Straight facets here (no curved edges): 64 segments per turn keep the
    # faceting area error at (2 pi/64)^2/6 = 0.16 %.
    points, tets, _, _, labels = _extruded_gmsh(g, mesh_size, axial_ratio=2.0, segments_per_turn=64)
    keep = labels != VOID
    points, tets, _ = _compact(points, tets[keep])
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


def _tetwild(g: TipGeometry, mesh_size: float):
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
