"""CadQuery solids of the as-assembled tip, and STEP / STL export.

One solid per component, in the section frame of :mod:`softcath.design.section` with
the catheter axis along z (base at z = 0, tip end at z = L):

- ``coil``: the outer coil as a homogenised annulus (default), or the resolved
  helical wire (``coil="helix"``, for fidelity studies and pictures);
- ``tube``: the squeezed silicone tube (outer ellipse, offset lumen) with its
  sealed cap over the last ``cap_thickness``;
- ``channel``: the hollow-channel coil (annulus, lumen open through the tip);
- ``filler``: the dip-coat silicone filling the coil around tube and channel
  (only if the design has a filler).

Tangent contacts (tube-coil at the top, tube-channel and channel-coil at the
bottom) are where CAD booleans and meshers fail. They get a **bonded land**:
the gap between two touching bodies is filled over ``|x| < x_land``, where
``x_land`` is the first abscissa at which the vertical gap reaches
``land_gap`` (default 0.01 mm), so no zero-thickness wedge is left. The
tube-coil and tube-channel lands are part of the tube (the squeezed silicone
conforms); the channel-coil land is part of the coil (< 0.5 % of its area).
The FEM (``softcath.fem.geometry``) meshes exactly these solids.

CadQuery is imported inside the functions (it is slow to import).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from softcath.core.errors import DesignError
from softcath.design.tip import TipDesign

__all__ = [
    "LAND_GAP",
    "land_half_widths",
    "build_solids",
    "solid_volumes",
    "export_step",
    "export_stl",
]

#: Default bonded-land threshold (mm): contact gaps thinner than this are filled.
LAND_GAP = 0.01


def land_half_widths(
    *,
    coil_inner_radius: float,
    channel_outer_radius: float,
    channel_y: float,
    tube_a: float,
    tube_b: float,
    tube_y: float,
    land_gap: float = LAND_GAP,
) -> dict[str, float]:
    """Half-widths x_land (mm) of the tube-coil, tube-channel and channel-coil lands.

    The first x >= 0 (sampled every R/6000) at which the vertical gap between
    the two touching boundaries reaches ``land_gap``.
    """
    x = np.linspace(0.0, coil_inner_radius, 6001)
    r_ci, r_co = coil_inner_radius, channel_outer_radius
    # Each gap is finite only where its boundaries exist (x below the tube's or the channel's
    # half-width, a prefix of the samples) and counts as reached beyond: it is evaluated on
    # that prefix alone (a morph asks for every design's lands).
    n_tube, n_chan = int(np.count_nonzero(x < tube_a)), int(np.count_nonzero(x < r_co))
    xx = x[: max(n_tube, n_chan)] ** 2
    ell = tube_b * np.sqrt(np.maximum(1 - (x[:n_tube] / tube_a) ** 2, 0))
    circ = np.sqrt(np.maximum(r_ci**2 - xx, 0))
    chan = np.sqrt(np.maximum(r_co**2 - xx[:n_chan], 0))
    n_both = min(n_tube, n_chan)
    gaps = {
        "tube_coil": circ[:n_tube] - (tube_y + ell),
        "tube_channel": (tube_y - ell[:n_both]) - (channel_y + chan[:n_both]),
        "channel_coil": (channel_y - chan) + circ[:n_chan],
    }
    beyond_reached = bool(np.inf >= land_gap)
    out = {}
    for name, gap in gaps.items():
        ok = gap >= land_gap
        first = int(np.argmax(ok)) if ok.size else 0
        if ok.size and ok[first]:
            out[name] = float(x[first])
        else:
            out[name] = float(x[gap.size]) if beyond_reached and gap.size < x.size else float(x[-1])
    return out


def _ellipse_prism(cq, a: float, b: float, yc: float, z0: float, height: float):
    return cq.Workplane("XY").workplane(offset=z0).center(0, yc).ellipse(a, b).extrude(height)


def _circle_prism(cq, r: float, yc: float, z0: float, height: float):
    return cq.Workplane("XY").workplane(offset=z0).center(0, yc).circle(r).extrude(height)


def _box(cq, x0: float, x1: float, y0: float, y1: float, height: float):
    return cq.Workplane("XY").center(0.5 * (x0 + x1), 0.5 * (y0 + y1)).rect(x1 - x0, y1 - y0).extrude(height)


def build_solids(design: TipDesign, *, coil: str = "annulus", land_gap: float = LAND_GAP) -> dict:
    """CadQuery ``Workplane`` solids of each component, keyed by name (mm).

    Parameters
    ----------
    design
        The tip.
    coil
        ``"annulus"`` (homogenised, what the FEM meshes) or ``"helix"`` (the
        resolved wire: a circle of the wire diameter swept along a helix of the
        coil's pitch, turns not fused; for pictures and fidelity studies).
    land_gap
        Bonded-land threshold (mm).
    """
    import cadquery as cq

    if coil not in ("annulus", "helix"):
        raise DesignError("coil", coil, "must be 'annulus' or 'helix'")
    s = design.section
    length, cap = design.tip.bending_length, design.tip.cap_thickness
    ro, ri = s.coil_outer_radius, s.coil_inner_radius
    yc, rco, rci = s.channel_center_y, s.channel_outer_radius, s.channel_inner_radius
    lands = land_half_widths(
        coil_inner_radius=ri,
        channel_outer_radius=rco,
        channel_y=yc,
        tube_a=s.a,
        tube_b=s.b,
        tube_y=s.tube_center_y,
        land_gap=land_gap,
    )
    inner = _circle_prism(cq, ri, 0.0, 0.0, length)
    chan_outer = _circle_prism(cq, rco, yc, 0.0, length)
    # tube outer with lands: (ellipse U strips) inside the coil ID, outside the channel
    xt, xb = lands["tube_coil"], lands["tube_channel"]
    tube_outer = (
        _ellipse_prism(cq, s.a, s.b, s.tube_center_y, 0.0, length)
        .union(_box(cq, -xt, xt, s.tube_center_y, ri + 0.5 * (ro - ri), length))
        .union(_box(cq, -xb, xb, yc, s.tube_center_y, length))
        .intersect(inner)
        .cut(chan_outer)
    )
    lumen = _ellipse_prism(cq, s.a_int, s.b_int, s.lumen_center_y, 0.0, length - cap)
    solids = {
        "tube": tube_outer.cut(lumen),
        "channel": chan_outer.cut(_circle_prism(cq, rci, yc, 0.0, length)),
    }
    xc = lands["channel_coil"]
    if coil == "annulus":
        solids["coil"] = (
            _circle_prism(cq, ro, 0.0, 0.0, length)
            .cut(inner)
            .union(_box(cq, -xc, xc, -ro, yc, length).intersect(_circle_prism(cq, ro, 0, 0, length)))
            .cut(chan_outer)
        )
    else:
        c = design.coil
        helix = cq.Wire.makeHelix(pitch=c.pitch, height=length, radius=c.mean_radius)
        solids["coil"] = (
            cq.Workplane("XZ")
            .center(c.mean_radius, 0)
            .circle(0.999 * c.wire_diameter / 2)  # 0.1 % clearance: neighbouring turns do not fuse
            .sweep(cq.Workplane("XY").add(helix), isFrenet=True)
        )
    if design.filler is not None:
        land = _box(cq, -xc, xc, -ro, yc, length).intersect(inner).cut(chan_outer)
        solids["filler"] = inner.cut(tube_outer).cut(chan_outer).cut(land)
    return solids


def solid_volumes(design: TipDesign, **kwargs) -> dict[str, float]:
    """Volume (mm^3) of each CAD solid."""
    return {k: float(v.val().Volume()) for k, v in build_solids(design, **kwargs).items()}


def export_step(design: TipDesign, path: str | Path, **kwargs) -> Path:
    """Write a STEP file with one named solid per component (mm)."""
    import cadquery as cq

    path = Path(path)
    assy = cq.Assembly(name=design.name)
    colours = {"coil": "gray", "tube": "orange", "channel": "blue", "filler": "lightblue"}
    for name, solid in build_solids(design, **kwargs).items():
        assy.add(solid, name=name, color=cq.Color(colours.get(name, "gray")))
    assy.export(str(path), exportType="STEP")
    return path


def export_stl(design: TipDesign, path: str | Path, *, tolerance: float = 0.002, **kwargs) -> Path:
    """Write an STL of the whole assembly (all components, mm); ``tolerance`` in mm."""
    import cadquery as cq

    path = Path(path)
    parts = [s.val() for s in build_solids(design, **kwargs).values()]
    compound = cq.Compound.makeCompound(parts)
    cq.exporters.export(
        compound,
        str(path),
        exportType="STL",
        tolerance=tolerance,
        angularTolerance=math.radians(5),
    )
    return path
