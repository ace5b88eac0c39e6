"""The boundary curves of a tip's section, and the shape quality of its triangles.

A section's boundary is a set of curves: circles and ellipses, conics
``(xc + a cos t, yc + b sin t)``, and the lands' vertical lines. Each is a row
``(kind, xc, yc, a, b)``; the functions here evaluate a point's implicit
residual on a curve, its parameter, the point at a parameter and the corner
where two curves meet, all vectorised over rows. The template morph
(:mod:`softcath.fem.section_model.template`) moves nodes along them.
"""

from __future__ import annotations

import math

import numpy as np

from softcath.fem.geometry import TipGeometry

__all__: list[str] = []  # the morph's own vocabulary (its names are private to the section model)

#: A node is on a curve when its implicit-function residual (scaled to mm) is below this.
_ON_CURVE_MM = 1e-8
_CONIC, _VLINE = 0, 1


def _curves(g: TipGeometry) -> np.ndarray:
    """Boundary curves of a section, rows ``(kind, xc, yc, a, b)`` in a fixed order."""
    lands = g.lands()
    rows = [
        (_CONIC, 0.0, 0.0, g.coil_outer_radius, g.coil_outer_radius),
        (_CONIC, 0.0, 0.0, g.coil_inner_radius, g.coil_inner_radius),
        (_CONIC, 0.0, g.channel_y, g.channel_outer_radius, g.channel_outer_radius),
        (_CONIC, 0.0, g.channel_y, g.channel_inner_radius, g.channel_inner_radius),
        (_CONIC, 0.0, g.tube_y, g.tube_a, g.tube_b),
        (_CONIC, 0.0, g.lumen_y, g.lumen_a, g.lumen_b),
    ]
    for name in ("tube_coil", "tube_channel", "channel_coil"):
        rows += [(_VLINE, lands[name], 0.0, 1.0, 1.0), (_VLINE, -lands[name], 0.0, 1.0, 1.0)]
    return np.array(rows, dtype=float)


def _residual(c: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Implicit-function residual of points on curves ``c`` (rows broadcast), in mm."""
    kind, xc, yc, a, b = c.T
    conic = np.sqrt(((x - xc) / a) ** 2 + ((y - yc) / b) ** 2) - 1.0
    return np.where(kind == _CONIC, conic * np.minimum(a, b), x - xc)


def _param(c: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    kind, xc, yc, a, b = c.T
    return np.where(kind == _CONIC, np.arctan2((y - yc) / b, (x - xc) / a), y)


def _point(c: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    kind, xc, yc, a, b = c.T
    conic = kind == _CONIC
    return np.where(conic, xc + a * np.cos(t), xc), np.where(conic, yc + b * np.sin(t), t)


def _intersect(c1: np.ndarray, c2: np.ndarray, t0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points of curves ``c1`` (parameter from ``t0``) on curves ``c2``: Newton's limit on ``c1``'s parameter.

    A land line (``x = xc``, parameter y) meets a conic where
    ``y = yc + b sqrt(1 - ((xc - x_conic) / a)^2)`` on the side of ``t0``: the root Newton
    converges to from ``t0`` (on a convex quadratic it never crosses the vertex), in closed
    form. The few other corners (conic on conic) run Newton one by one in scalar arithmetic:
    a numpy call on a handful of numbers costs more than its arithmetic.
    """
    t = np.array(t0, dtype=float)
    kind1, xc1 = c1[:, 0], c1[:, 1]
    kind2, xc2, yc2, a2, b2 = c2.T
    line = (kind1 == _VLINE) & (kind2 == _CONIC)
    if line.any():
        u = (xc1[line] - xc2[line]) / a2[line]
        side = np.sign(t[line] - yc2[line])
        with np.errstate(invalid="ignore"):  # NaN where they do not meet: the caller refuses it
            t[line] = yc2[line] + side * b2[line] * np.sqrt(1.0 - u**2)
    for i in np.flatnonzero(~line):
        t[i] = _newton(c1[i].tolist(), c2[i].tolist(), float(t[i]))
    return _point(c1, t)


def _newton(c1: list[float], c2: list[float], t: float) -> float:
    """Newton on curve ``c1``'s parameter ``t`` for a point on curve ``c2`` (rows ``(kind, xc, yc, a, b)``).

    The arithmetic of the vectorised Newton, per corner (``t`` stops moving by 1e-15).
    """
    kind1, xc1, yc1, a1, b1 = c1
    kind2, xc2, yc2, a2, b2 = c2
    for _ in range(30):
        if not math.isfinite(t):  # diverged: no intersection (math.cos would raise)
            return math.nan
        if kind1 == _CONIC:
            cos, sin = math.cos(t), math.sin(t)
            x, y, dx, dy = xc1 + a1 * cos, yc1 + b1 * sin, -a1 * sin, b1 * cos
        else:
            x, y, dx, dy = xc1, t, 0.0, 1.0
        ex, ey = x - xc2, y - yc2
        if kind2 == _CONIC:
            p, q = ex / a2, ey / b2  # squares by products: ** raises OverflowError on floats
            f = p * p + q * q - 1.0
            df = 2 * ex / (a2 * a2) * dx + 2 * ey / (b2 * b2) * dy
        else:
            f, df = ex, dx
        step = f / (df if abs(df) > 1e-300 else 1e-300)
        t -= step
        if abs(step) < 1e-15:
            break
    return t


def _quality(p: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Shape quality 4 sqrt(3) A / sum of squared edge lengths (1 for equilateral), signed."""
    return _corner_quality(p[:, 0][tri], p[:, 1][tri])


def _corner_quality(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """:func:`_quality` of triangles given by their corners' coordinates ``x``, ``y`` (m, 3).

    Coordinates apart, not (m, 3, 2) corners: every operation then runs on contiguous
    columns (3x faster for a morph's ~700 triangles).
    """
    e1x, e1y = x[:, 1] - x[:, 0], y[:, 1] - y[:, 0]
    e2x, e2y = x[:, 2] - x[:, 1], y[:, 2] - y[:, 1]
    e3x, e3y = x[:, 0] - x[:, 2], y[:, 0] - y[:, 2]
    area = 0.5 * (e1x * (-e3y) - e1y * (-e3x))
    return 4 * np.sqrt(3) * area / ((e1x**2 + e1y**2) + (e2x**2 + e2y**2) + (e3x**2 + e3y**2))
