"""The reference section a design's template mesh is made for (its sizes snapped to a grid).

Designs of one section topology share a template mesh when their free sizes
snap to the same point of a geometric grid of ratio 1 + :data:`TEMPLATE_STEP`
(:func:`reference_geometry`); the template morph
(:mod:`softcath.fem.section_model.template`) then moves that mesh to the design.
"""

from __future__ import annotations

import dataclasses
import functools
import math

from softcath import design
from softcath.core.errors import DesignError
from softcath.fem.adapter import geometry_from_design
from softcath.fem.geometry import TipGeometry

__all__ = ["TEMPLATE_STEP", "reference_geometry"]

#: Relative step of the reference sizes' grid (:func:`reference_geometry`).
TEMPLATE_STEP = 0.15

_FREE = (
    "coil_outer_radius",
    "coil_inner_radius",
    "channel_outer_radius",
    "channel_inner_radius",
    "tube_a",
    "lumen_a",
    "lumen_b",
)


@functools.lru_cache(maxsize=1)
def _grid_origin() -> dict[str, float]:
    """The ``paper`` section's free sizes: grid points, so its reference is itself."""
    g = geometry_from_design(design.resolve("paper"))
    return {name: getattr(g, name) for name in _FREE}


def _snap(name: str, value: float) -> float:
    origin, step = _grid_origin()[name], math.log1p(TEMPLATE_STEP)
    return origin * math.exp(round(math.log(value / origin) / step) * step)


def reference_geometry(geometry: TipGeometry) -> TipGeometry:
    """The reference section whose gmsh mesh is morphed to ``geometry``.

    The as-assembled section has seven free sizes (coil and channel radii, tube
    width, lumen semi-axes); the rest follows from the tangencies (channel on
    the coil ID, tube squeezed between them, lumen centred in the tube). Each
    free size is snapped to a geometric grid of ratio 1 + :data:`TEMPLATE_STEP`
    through the ``paper`` section's (which is thus its own reference), so the
    morph changes no size by more than about half a step, and the reference
    (hence the answer) depends on the geometry alone. A geometry not
    of this form is its own reference (its template is its gmsh mesh). Length and
    cap, which the section does not see, are normalised.
    """
    g = geometry
    ri, rco = g.coil_inner_radius, g.channel_outer_radius
    tied = max(
        abs(g.channel_y + ri - rco),
        abs(g.tube_b - (ri - rco)),
        abs(g.tube_y - rco),
        abs(g.lumen_y - g.tube_y),
    )
    section_only = {"length": 1.0, "cap_thickness": 0.1}  # the section alone
    if tied > 1e-9:
        return dataclasses.replace(g, **section_only)
    snapped = _snapped(tuple(_snap(name, getattr(g, name)) for name in _FREE), g.filled, g.land_gap)
    return dataclasses.replace(g, **section_only) if snapped is None else snapped


@functools.lru_cache(maxsize=1024)
def _snapped(free: tuple[float, ...], filled: bool, land_gap: float) -> TipGeometry | None:
    """The reference section of snapped free sizes (None if they make no valid section)."""
    f = dict(zip(_FREE, free, strict=True))
    ri, rco = f["coil_inner_radius"], f["channel_outer_radius"]
    try:
        return TipGeometry(
            **f,
            channel_y=-(ri - rco),
            tube_b=ri - rco,
            tube_y=rco,
            lumen_y=rco,
            length=1.0,
            cap_thickness=0.1,
            filled=filled,
            land_gap=land_gap,
        )
    except DesignError:
        return None
