"""The 2-D section mesh by gmsh: OCC regions fragmented into a conforming partition, second order."""

from __future__ import annotations

import contextlib
import logging
import math
import os

import numpy as np

from softcath.fem.errors import MeshError
from softcath.fem.geometry import TipGeometry

log = logging.getLogger(__name__)

#: Curvature sizing of the section mesh (elements per full turn of a boundary).
#: With the midside nodes on the exact curves the faceting error is O(theta^4),
#: so 16 segments keep region volumes within 0.02 % (tests/fem/mesh/test_fem_mesh.py).
_SEGMENTS_PER_TURN = 16


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


def initialize_gmsh(gmsh) -> None:
    """``gmsh.initialize()`` that leaves every signal's C-level disposition as it found it.

    gmsh installs its own handlers (or the default, terminate) for SIGTERM, SIGINT, SIGPIPE
    and others behind Python's back. A command that meshed would then die of SIGTERM at
    once, exit status 143, without its clean-up (temporary files left behind), and of
    SIGPIPE on a write to a dead worker's pipe. The dispositions are saved with
    ``sigaction`` before and put back after, from any thread (``signal.signal`` works only
    in the main thread and would not see the change anyway).
    """
    saved = _save_signal_actions()
    gmsh.initialize(interruptible=False)
    _restore_signal_actions(saved)
    restore_sigpipe_ignored()


# struct sigaction is 152 bytes on Linux x86-64 and smaller elsewhere; the buffer is opaque.
_SIGACTION_BYTES = 512


def _libc():
    import ctypes

    libc = ctypes.CDLL(None, use_errno=True)
    libc.sigaction.argtypes = (ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p)
    libc.sigaction.restype = ctypes.c_int
    return libc


def _save_signal_actions() -> dict:
    if os.name != "posix":
        return {}
    import ctypes
    import signal

    libc, saved = _libc(), {}
    for sig in signal.valid_signals():
        if sig in (signal.SIGKILL, signal.SIGSTOP) or not 0 < int(sig) < 32:
            continue
        buf = ctypes.create_string_buffer(_SIGACTION_BYTES)
        if libc.sigaction(int(sig), None, buf) == 0:
            saved[int(sig)] = buf
    return saved


def _restore_signal_actions(saved: dict) -> None:
    if not saved:
        return
    libc = _libc()
    for sig, buf in saved.items():
        libc.sigaction(sig, buf, None)


@contextlib.contextmanager
def _gmsh_session():
    import gmsh

    initialize_gmsh(gmsh)
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
        if g.filled and g.filler_coat > 0:  # the as-built coat: its outer circle is a region edge
            coat, _ = occ.intersect(occ.copy(rest), disk(0, yc, rco + g.filler_coat))
            rest, _ = occ.cut(rest, occ.copy(coat))
            rest = rest + coat
        pieces = coil + channel + channel_lumen + tube + lumen + rest
        occ.fragment(pieces[:1], pieces[1:])
        occ.synchronize()
        _grade_at_land_corners(gmsh, g, lands, mesh_size)
        _set_sizing(gmsh, mesh_size, segments_per_turn, fast)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)  # midside nodes on the exact curves
        return p2_triangles(gmsh)


def _grade_at_land_corners(gmsh, g: TipGeometry, lands: dict[str, float], mesh_size: float) -> None:
    """A background size field that refines the section mesh around the land corners."""
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


def _set_sizing(gmsh, mesh_size: float, segments_per_turn: int, fast: bool) -> None:
    """Mesh size and algorithm options of the section mesh (see :func:`section_triangles`)."""
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


def _p2_jacobian_rows() -> np.ndarray:
    """(14, 6): dN/dr then dN/ds of the 6 P2 shape functions at the 7 check points of
    :func:`_p2_triangles_valid` (its 6 nodes and centroid)."""
    rows_r, rows_s = [], []
    for r, s in ((0, 0), (1, 0), (0, 1), (0.5, 0), (0.5, 0.5), (0, 0.5), (1 / 3, 1 / 3)):
        lam = 1 - r - s
        rows_r.append([1 - 4 * lam, 4 * r - 1, 0, 4 * (lam - r), 4 * s, -4 * s])
        rows_s.append([1 - 4 * lam, 0, 4 * s - 1, -4 * r, 4 * r, 4 * (lam - s)])
    return np.array(rows_r + rows_s, dtype=float)


_P2_JACOBIAN_ROWS = _p2_jacobian_rows()


def _p2_triangles_valid(x6: np.ndarray) -> np.ndarray:
    """True where a 6-node triangle's Jacobian keeps the sign of its straight version.

    ``x6`` (m, 6, 2): corners then midsides (01, 12, 20). The Jacobian of a P2
    triangle is quadratic; it is checked at the 6 nodes and the centroid.
    """
    x6 = np.asarray(x6, dtype=float)
    m = len(x6)
    e1, e2 = x6[:, 1] - x6[:, 0], x6[:, 2] - x6[:, 0]
    lin = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    # All 7 points' dx/dr, dx/ds at once: one (14, 6) x (6, 2m) product (a morph checks every
    # design's curved triangles, and 14 small products cost more than the arithmetic).
    jac = (_P2_JACOBIAN_ROWS @ x6.transpose(1, 0, 2).reshape(6, 2 * m)).reshape(2, 7, m, 2)
    jr, js = jac[0], jac[1]
    det = jr[..., 0] * js[..., 1] - jr[..., 1] * js[..., 0]
    return (det * np.sign(lin) > 0.05 * np.abs(lin)).all(axis=0)


def _ellipse(occ, xc: float, yc: float, a: float, b: float) -> int:
    if a >= b:
        return occ.addDisk(xc, yc, 0, a, b)
    tag = occ.addDisk(xc, yc, 0, b, a)  # OCC wants rx >= ry: build lying, stand it up
    occ.rotate([(2, tag)], xc, yc, 0, 0, 0, 1, math.pi / 2)
    return tag
