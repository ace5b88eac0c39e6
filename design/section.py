r"""The as-assembled cross-section of the tip.

The catalogue parts do not fit: a Ø0.6 mm tube beside a Ø0.3 mm channel
needs a Ø0.9 mm enclosure, and the coil's ID is 0.6 mm. As assembled, the
tube is squeezed between the coil wall and the channel, which is why the
paper fixes the ellipse's vertical semi-axis b and optimises the rest
(x = [a, a_int, b_int, h], eq. 8).

Frame and symbols (mm)::

                 y
                 ^        coil ID circle, radius R = ID/2, centre (0, 0)
           ______|______
         /   ____|____   \
        /   / .--|--. \   \      outer ellipse: semi-axes a (x), b (y),
       |   | (   +   ) |   |     centre (0, y_t), y_t = R - b
       |   |  '--|--'  |   |     lumen ellipse: semi-axes a_int, b_int,
       |    \____|____/    |     centre (0, y_t + h)      <- h is measured
       |       .-+-.       |                                from the outer
       |      (  o  )      |     channel: radius r_c, centre (0, -(R - r_c))
        \      '---'      /
         \_______________/  ---> x

- b = (coil ID − channel OD)/2: the tube touches the coil at (0, R) and the
  channel at (0, y_t − b), both tangent contacts on the y axis;
- h is the offset of the lumen centre from the outer-ellipse centre,
  positive toward the coil wall (away from the channel);
- the outer ellipse stays inside the coil iff a² ≤ R·b (proved in
  :func:`max_outer_semi_axis`); it never overlaps the channel, because the
  two touch at a horizontal tangent line y = y_t − b.

The paper's reported optimum x° = [0.23, 0.12, 0.12, 0.55] mm cannot be read
in this frame: |h| ≤ b − b_int − wall = 0.03 − wall. Nor in a frame centred on
the coil (0.55 > R = 0.3). It fits in exactly one natural frame: h measured
from the bottom of the catheter's outer surface (y = −OD/2 = −0.4), where
0.55 puts the lumen centre at y = 0.15 = y_t, i.e. a lumen concentric with
the outer ellipse (local h = 0). Even then a = 0.23 exceeds the inscribed
bound √(R b) = 0.212 mm by 8 %, so the ellipse would poke 3.4 µm into the
coil wire. :func:`paper_frame_reading` computes this.

Nominal rule (when the design does not fix the shape): the tube's wall area
cannot be preserved — the catalogue wall is 0.212 mm² and the largest
admissible ellipse has 0.100 mm² in all — so we keep what can be kept: the
squeezed tube fills the width available (a = √(R b), the largest inscribed
ellipse) and keeps the catalogue's lumen-to-outer proportion
(a_int = a·ID/OD, b_int = b·ID/OD, concentric, h = 0). The silicone that does
not fit is the model's first stated gap with reality.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from softcath.core.errors import DesignError

__all__ = [
    "AssembledSection",
    "max_outer_semi_axis",
    "nominal_tube_shape",
    "paper_frame_reading",
    "wall_thickness",
]


@dataclass(frozen=True, kw_only=True)
class AssembledSection:
    """Positions and sizes of every part of the cross-section [mm] (frame: module docstring)."""

    coil_outer_radius: float
    coil_inner_radius: float
    channel_outer_radius: float
    channel_inner_radius: float
    channel_center_y: float
    tube_center_y: float
    a: float
    b: float
    a_int: float
    b_int: float
    h: float

    @property
    def lumen_center_y(self) -> float:
        return self.tube_center_y + self.h

    @property
    def shape(self) -> dict[str, float]:
        """The paper's x = [a, a_int, b_int, h] as a mapping."""
        return {"a": self.a, "a_int": self.a_int, "b_int": self.b_int, "h": self.h}

    @property
    def min_wall(self) -> float:
        """Smallest tube wall thickness, measured along the ellipse axes [mm]."""
        return float(wall_thickness(self.a, self.b, self.a_int, self.b_int, self.h))


def vertical_semi_axis(*, coil_inner_diameter: float, channel_outer_diameter: float) -> float:
    """b = (coil ID − channel OD)/2, the height left for the tube [mm]."""
    return (coil_inner_diameter - channel_outer_diameter) / 2


def max_outer_semi_axis(*, coil_inner_radius: float, b: float) -> float:
    """Largest a for which the ellipse (a, b) centred at (0, R − b) stays inside the circle R.

    With s = sin φ, |point|² − R² = a²(1 − s²) + (R − b + b s)² − R²
    = (s − 1)·((b² − a²) s + (2Rb − b² − a²)), which is ≤ 0 on [−1, 1] iff
    the linear factor is ≥ 0 at both ends: at s = −1 it is 2b(R − b) ≥ 0, at
    s = 1 it is 2(Rb − a²). Hence a² ≤ R·b.
    """
    return math.sqrt(coil_inner_radius * b)


def nominal_tube_shape(
    *, coil_inner_radius: float, b: float, catalogue_outer_diameter: float, catalogue_inner_diameter: float
) -> dict[str, float]:
    """The nominal as-assembled shape (rule in the module docstring)."""
    a = max_outer_semi_axis(coil_inner_radius=coil_inner_radius, b=b)
    ratio = catalogue_inner_diameter / catalogue_outer_diameter
    return {"a": a, "a_int": a * ratio, "b_int": b * ratio, "h": 0.0}


def wall_thickness(a, b, a_int, b_int, h):
    """Smallest wall along the axes: min(b − b_int − |h|, a − a_int) [mm] (numpy-broadcast)."""
    return np.minimum(np.asarray(b) - np.asarray(b_int) - np.abs(h), np.asarray(a) - np.asarray(a_int))


def lumen_containment(a, b, a_int, b_int, h, wall, *, n: int = 2001):
    """Max over the lumen boundary of ((x/(a−t))² + (y/(b−t))²); ≤ 1 means the lumen fits with wall t.

    The lumen point at parameter s = sin φ gives the quadratic
    q(s) = (B² − A²)s² + 2HBs + A² + H² with A = a_int/(a − t), B = b_int/(b − t),
    H = h/(b − t); its maximum on [−1, 1] is taken exactly (endpoints and vertex).
    """
    a, b, a_int, b_int, h = (np.asarray(v, dtype=float) for v in (a, b, a_int, b_int, h))
    with np.errstate(divide="ignore", invalid="ignore"):
        aa = a_int / (a - wall)
        bb = b_int / (b - wall)
        hh = h / (b - wall)
        c2 = bb**2 - aa**2
        c1 = 2 * hh * bb
        c0 = aa**2 + hh**2
        q_pos = c2 + c1 + c0
        q_neg = c2 - c1 + c0
        s_star = np.where(c2 < 0, np.clip(-c1 / (2 * np.where(c2 == 0, 1, c2)), -1, 1), 1.0)
        q_star = c2 * s_star**2 + c1 * s_star + c0
    out = np.maximum(np.maximum(q_pos, q_neg), q_star)
    bad = (a - wall <= 0) | (b - wall <= 0)
    return np.where(bad, np.inf, out)


def check_shape(*, coil_inner_radius: float, b: float, shape: dict[str, float], min_wall: float) -> None:
    """Raise :class:`DesignError` naming the first violated bound of an as-assembled tube shape."""
    a, a_int, b_int, h = shape["a"], shape["a_int"], shape["b_int"], shape["h"]
    a_max = max_outer_semi_axis(coil_inner_radius=coil_inner_radius, b=b)
    if a > a_max * (1 + 1e-12):
        raise DesignError(
            "tube.a", a, f"must be <= sqrt(R_coil_ID * b) = {a_max:.6g} mm (outer ellipse inside the coil)"
        )
    if a_int > a - min_wall:
        raise DesignError("tube.a_int", a_int, f"must be <= a - min_wall = {a - min_wall:.6g} mm")
    if b_int > b - min_wall:
        raise DesignError("tube.b_int", b_int, f"must be <= b - min_wall = {b - min_wall:.6g} mm")
    h_max = b - min_wall - b_int
    if abs(h) > h_max:
        raise DesignError("tube.h", h, f"|h| must be <= b - min_wall - b_int = {h_max:.6g} mm")
    if float(lumen_containment(a, b, a_int, b_int, h, min_wall)) > 1 + 1e-12:
        raise DesignError(
            "tube.a_int",
            a_int,
            f"lumen must lie inside the outer ellipse shrunk by min_wall = {min_wall:g} mm",
        )


def paper_frame_reading(
    x_paper=(0.23, 0.12, 0.12, 0.55),
    *,
    coil_outer_diameter: float = 0.8,
    coil_inner_diameter: float = 0.6,
    channel_outer_diameter: float = 0.3,
) -> dict[str, float]:
    """Read the paper's x° in the frame where it fits: h measured from the catheter's bottom.

    Returns the local shape (h relative to the outer-ellipse centre), the
    inscribed bound on a, by how much a exceeds it, and how far the ellipse
    pokes outside the coil ID [mm].
    """
    a, a_int, b_int, h_paper = x_paper
    radius = coil_inner_diameter / 2
    b = vertical_semi_axis(
        coil_inner_diameter=coil_inner_diameter, channel_outer_diameter=channel_outer_diameter
    )
    y_t = radius - b
    lumen_y = -coil_outer_diameter / 2 + h_paper
    s = np.linspace(-1, 1, 200001)
    r = np.sqrt(a**2 * (1 - s**2) + (y_t + b * s) ** 2)
    a_max = max_outer_semi_axis(coil_inner_radius=radius, b=b)
    return {
        "a": a,
        "a_int": a_int,
        "b_int": b_int,
        "h_local": lumen_y - y_t,
        "lumen_center_y": lumen_y,
        "b": b,
        "a_max": a_max,
        "a_excess_fraction": a / a_max - 1,
        "protrusion_mm": float(r.max() - radius),
    }
