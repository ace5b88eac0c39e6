"""Outlines the app draws: the as-assembled section's parts and the bent tip's centre line (mm).

Plain polygons, so the live page (Bokeh) and the PNG export (Matplotlib)
draw the same shapes. The section's parts are filled in order, each over the
ones before it (coil, filler, tube, lumen, channel, its bore).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.analytic import composite_section
from softcath.studies.app.curves import TierCurve

__all__ = ["Outline", "bent_tip", "section_shapes", "section_marks"]

_N = 120
COLORS = {
    "coil": "#8a8f98",
    "filler": "#f4e9c8",
    "void": "#ffffff",
    "tube": "#d95f5f",
    "channel": "#5a6270",
}


@dataclass(frozen=True)
class Outline:
    """One filled closed polygon of the section: ``x``, ``y`` [mm], its colour and legend label."""

    x: np.ndarray
    y: np.ndarray
    color: str
    label: str


def _ellipse(a: float, b: float, yc: float) -> tuple[np.ndarray, np.ndarray]:
    t = np.linspace(0.0, 2 * np.pi, _N)
    return a * np.cos(t), yc + b * np.sin(t)


def section_shapes(design) -> list[Outline]:
    """The as-assembled section of ``design`` as filled outlines, drawn in list order."""
    s = design.section
    filler = design.filler is not None and design.assembly.filler != "none"
    coat = filler and design.assembly.filler == "coat"
    out = [Outline(*_ellipse(s.coil_outer_radius, s.coil_outer_radius, 0.0), COLORS["coil"], "coil")]
    inside = "filler" if filler and not coat else "void"
    out.append(
        Outline(
            *_ellipse(s.coil_inner_radius, s.coil_inner_radius, 0.0), COLORS[inside], f"{inside} (in coil)"
        )
    )
    if coat:
        r = s.channel_outer_radius + design.assembly.filler_coat_thickness
        out.append(Outline(*_ellipse(r, r, s.channel_center_y), COLORS["filler"], "filler coat"))
    out.append(Outline(*_ellipse(s.a, s.b, s.tube_center_y), COLORS["tube"], "silicone tube"))
    out.append(Outline(*_ellipse(s.a_int, s.b_int, s.lumen_center_y), COLORS["void"], "lumen"))
    r = s.channel_outer_radius
    out.append(Outline(*_ellipse(r, r, s.channel_center_y), COLORS["channel"], "channel coil"))
    r = s.channel_inner_radius
    out.append(Outline(*_ellipse(r, r, s.channel_center_y), COLORS["void"], "channel bore"))
    return out


def section_marks(design) -> dict[str, float]:
    """The composite neutral axis ȳ and the pressure centre y_p of the formula [mm]."""
    cs = composite_section(design)
    return {
        "neutral_axis_y_mm": float(cs.neutral_axis_y),
        "pressure_centre_y_mm": float(cs.pressure_centre_y),
    }


def bent_tip(curve: TierCurve, pressure: float, n: int = 60) -> tuple[np.ndarray, np.ndarray]:
    """Centre line (x toward the channel side, z along the unbent tip) [mm] of a constant-curvature
    tip at ``pressure`` [MPa], over its stretched length; empty where the tier has no value there."""
    k, eps = curve.at(pressure, "curvature_per_mm"), curve.at(pressure, "elongation")
    if not (np.isfinite(k) and np.isfinite(eps)):
        return np.zeros(0), np.zeros(0)
    s = np.linspace(0.0, curve.length_mm * (1.0 + eps), n)
    if abs(k) < 1e-12:
        return np.zeros_like(s), s
    return (1.0 - np.cos(k * s)) / k, np.sin(k * s) / k
