"""Boundary facet tags of a tip mesh, found geometrically.

Tags: ``base`` (z = 0, clamped), ``end`` (z = L), ``cap`` (the inner face of
the tube's sealed cap, z = L - cap, inside the lumen), ``lumen`` (the tube's
lumen wall), ``channel`` (the open channel's lumen wall) and ``outer``
(everything else). The lumen test uses a generous margin (half the thinnest
lumen wall): a tight band misses facets whose vertices a mesher moved
(it missed 18 of ~4,600 lumen facets), and no other boundary comes that close.
"""

from __future__ import annotations

import numpy as np

from softcath.fem.geometry import TipGeometry

__all__ = ["tag_facets", "TAGS"]

TAGS = ("base", "end", "cap", "lumen", "channel", "outer")


def tag_facets(mesh, geometry: TipGeometry) -> dict[str, np.ndarray]:
    """Boundary facet indices of a scikit-fem tet mesh, per tag.

    Parameters
    ----------
    mesh
        scikit-fem ``MeshTet``/``MeshTet2`` of the tip.
    geometry
        The geometry it was made from.
    """
    g = geometry
    bf = mesh.boundary_facets()
    nv = mesh.t.max() + 1
    p = np.asarray(mesh.doflocs)[:, :nv]
    c = p[:, mesh.facets[:, bf]].mean(axis=1)
    x, y, z = c
    ztol = 1e-6 * g.length
    lb = g.length - g.cap_thickness
    margin = 0.5 * g.min_lumen_wall()
    in_lumen = g.in_lumen(x, y, margin)
    rc = np.hypot(x, y - g.channel_y)
    in_channel = rc < 0.5 * (g.channel_inner_radius + g.channel_outer_radius)
    base = z < ztol
    end = z > g.length - ztol
    cap = ~base & ~end & in_lumen & (np.abs(z - lb) < 1e-3 * g.length)
    lumen = ~base & ~end & ~cap & in_lumen & (z < lb)
    channel = ~base & ~end & in_channel
    outer = ~(base | end | cap | lumen | channel)
    return {
        "base": bf[base],
        "end": bf[end],
        "cap": bf[cap],
        "lumen": bf[lumen],
        "channel": bf[channel],
        "outer": bf[outer],
    }
