"""The on-disk mesh cache and :func:`mesh_tip`, which meshes a tip or loads the identical mesh."""

from __future__ import annotations

import hashlib
import logging
import math
import os
import time
from pathlib import Path

import numpy as np

from softcath.core.atomic import atomic_path
from softcath.core.errors import DesignError
from softcath.fem.geometry import VOID, TipGeometry
from softcath.fem.mesh.extrusion import extruded_gmsh
from softcath.fem.mesh.model import TipMesh
from softcath.fem.mesh.quality import _orient, checked_mesh, compact, label_by_centroid
from softcath.fem.mesh.tetwild import tetwild_mesh

log = logging.getLogger(__name__)

MESHERS = ("gmsh", "tetwild")
#: Bumped whenever the meshing recipe changes, so stale cache entries are ignored.
_RECIPE = "fem-mesh-v2"


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
    if mesher not in MESHERS:
        raise DesignError("mesher", mesher, f"must be one of {MESHERS}")
    if not (math.isfinite(mesh_size) and 0.005 <= mesh_size <= 0.5):
        raise DesignError("mesh_size", mesh_size, "must be in [0.005, 0.5] mm")
    if not (math.isfinite(axial_ratio) and 0.5 <= axial_ratio <= 10):
        raise DesignError("axial_ratio", axial_ratio, "must be in [0.5, 10]")
    key = hashlib.sha256(
        f"{_RECIPE}|{geometry.digest()}|{mesher}|{mesh_size:.6g}|{axial_ratio:.6g}".encode()
    ).hexdigest()[:20]
    folder = cache or cache_dir()
    path = folder / f"{key}.npz"
    if use_cache and path.exists():
        try:
            return load_cached(path, geometry, mesher, mesh_size, key)
        except (OSError, KeyError, ValueError) as exc:  # a corrupt entry is re-made
            log.warning("ignoring unreadable mesh cache entry %s: %s", path, exc)
    t0 = time.perf_counter()
    if mesher == "gmsh":
        points, tets, cedges, cmid, labels = extruded_gmsh(geometry, mesh_size, axial_ratio)
    else:
        points, tets = tetwild_mesh(geometry, mesh_size)
        cedges, cmid = np.zeros((0, 2), dtype=np.int64), np.zeros((0, 3))
        labels = label_by_centroid(geometry, points, tets)
    keep = labels != VOID
    points, tets, remap = compact(points, tets[keep])
    labels = labels[keep]
    tets = _orient(points, tets)
    cedges = remap[cedges]
    ok = (cedges >= 0).all(axis=1)
    cedges, cmid = cedges[ok], cmid[ok]
    seconds = time.perf_counter() - t0
    arrays = dict(points=points, tets=tets, labels=labels, curved_edges=cedges, curved_midpoints=cmid)
    mesh = checked_mesh(geometry, arrays, mesher, mesh_size, seconds, key)
    if use_cache:
        folder.mkdir(parents=True, exist_ok=True)
        with atomic_path(path) as tmp:  # parallel sweeps never read half a file
            np.savez_compressed(tmp, seconds=np.array(seconds), **arrays)
    return mesh


def load_cached(path, geometry, mesher, mesh_size, key) -> TipMesh:
    names = ("points", "tets", "labels", "curved_edges", "curved_midpoints")
    with np.load(path) as data:
        arrays = {k: data[k] for k in names}
        seconds = float(data["seconds"])
    log.info("mesh cache hit %s", path.name)
    return checked_mesh(geometry, arrays, mesher, mesh_size, seconds, key, cached=True)
