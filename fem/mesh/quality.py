"""Element checks of a tet mesh: signed volumes, scaled Jacobian, orientation, exact region volumes.

:func:`checked_mesh` turns raw arrays into a :class:`~softcath.fem.mesh.model.TipMesh`, refusing
inverted elements and region volumes off the exact geometry by more than :data:`VOLUME_TOL`.
"""

from __future__ import annotations

import math

import numpy as np

from softcath.fem.errors import MeshError
from softcath.fem.geometry import REGIONS, TipGeometry
from softcath.fem.mesh.model import MeshQuality, TipMesh, curved_volumes, skfem_mesh

#: Region volumes must match the exact geometry within this (a relative tolerance).
VOLUME_TOL = 0.01


def checked_mesh(geometry, arrays, mesher, mesh_size, seconds, key, *, cached=False):
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
    """Min over the corners of ``det[e1 e2 e3] / (|e1| |e2| |e3|)``, scaled: regular tet = 1."""
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


def compact(points: np.ndarray, tets: np.ndarray):
    used = np.unique(tets)
    remap = np.full(points.shape[0], -1, dtype=np.int64)
    remap[used] = np.arange(used.size)
    return points[used], remap[tets], remap


def label_by_centroid(geometry: TipGeometry, points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    c = points[tets].mean(axis=1)
    return geometry.classify(c[:, 0], c[:, 1], c[:, 2])
