r"""Area-true section boundaries: straight-sided triangles that hold each curve's area.

A polygon inscribed in a circle with vertices :math:`\alpha` apart holds
:math:`\sin\alpha/\alpha` of the area between its chords and the centre (12 segments per
circle: 95.5 %). The finite-strain 3-D body uses straight-sided tetrahedra, so its
pressurised lumen, the tube's wall and the coil's ring are each short by that much, and
the lumen load with them: on the paper design this, not the triangle size, is most of the
section's discretisation error (docs/nonlinear.md, "Where the section's error lives").

:func:`area_true` moves every vertex that lies inside an arc of a section curve (the coil's
two circles, the channel's two, the tube's outer ellipse as meshed and the lumen's ellipse)
outward along its ray from the curve's centre by :math:`\sqrt{\bar\alpha/\sin\bar\alpha}`,
:math:`\bar\alpha` the mean parametric angle of its two chords on that curve, which makes a
polygon of equal chords hold the curve's area exactly. An ellipse is an affine image of a
circle and the affine map keeps area ratios, so the same factor holds in its normalised
coordinates. The ends of an arc (where two curves meet: the tube's contact flats, the
channel's tangency) stay where they are.
"""

from __future__ import annotations

import numpy as np

__all__ = ["section_curves", "area_true"]

#: A vertex lies on a curve when its normalised radius is 1 within this (gmsh puts them on the curve).
ON_CURVE = 1e-7


def section_curves(section, *, contact: float) -> list[tuple[float, float, float, float]]:
    """The section's curves as (centre x, centre y, semi-axis x, semi-axis y) [mm], as meshed
    by the catheter mesher (the tube's outer ellipse grown by ``contact``)."""
    s = section
    return [
        (0.0, 0.0, s.coil_outer_radius, s.coil_outer_radius),
        (0.0, 0.0, s.coil_inner_radius, s.coil_inner_radius),
        (0.0, s.channel_center_y, s.channel_outer_radius, s.channel_outer_radius),
        (0.0, s.channel_center_y, s.channel_inner_radius, s.channel_inner_radius),
        (0.0, s.tube_center_y, s.a * (1 + contact), s.b * (1 + contact)),
        (0.0, s.tube_center_y + s.h, s.a_int, s.b_int),
    ]


def area_true(points: np.ndarray, triangles: np.ndarray, curves) -> np.ndarray:
    """``points`` (n, 2) with each inner arc vertex of ``curves`` moved to make its polygon area-true.

    Parameters
    ----------
    points
        Section vertices [mm], (n, 2).
    triangles
        Vertex indices, (m, 3); only the edges along a curve are used.
    curves
        (centre x, centre y, semi-axis x, semi-axis y) per curve, e.g. :func:`section_curves`.

    Returns
    -------
    numpy.ndarray
        The moved vertices (a copy); vertices on no curve, or at an arc's end, unchanged.
    """
    pts = np.array(points, dtype=float, copy=True)
    tri = np.asarray(triangles)
    edges = np.unique(np.sort(np.vstack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1), axis=0)
    base = np.asarray(points, dtype=float)
    for cx, cy, rx, ry in curves:
        u, v = (base[:, 0] - cx) / rx, (base[:, 1] - cy) / ry
        on = np.abs(np.hypot(u, v) - 1.0) < ON_CURVE
        along = edges[on[edges[:, 0]] & on[edges[:, 1]]]
        if along.size == 0:
            continue
        theta = np.arctan2(v, u)
        chord = np.abs(np.angle(np.exp(1j * (theta[along[:, 0]] - theta[along[:, 1]]))))
        count = np.bincount(along.ravel(), minlength=pts.shape[0])
        total = np.bincount(along.ravel(), weights=np.repeat(chord, 2), minlength=pts.shape[0])
        inner = np.flatnonzero(count == 2)  # one chord only: an arc's end
        mean = total[inner] / 2
        factor = np.sqrt(mean / np.sin(mean))
        pts[inner, 0] = cx + factor * (base[inner, 0] - cx)
        pts[inner, 1] = cy + factor * (base[inner, 1] - cy)
    return pts
