"""Extrusion of the section mesh along z into a conforming, labelled tet mesh (the gmsh back-end)."""

from __future__ import annotations

import math

import numpy as np

from softcath.fem.geometry import VOID, TipGeometry
from softcath.fem.mesh.gmsh_section import section_triangles


def extruded_gmsh(g: TipGeometry, mesh_size: float, axial_ratio: float, segments_per_turn=0):
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
