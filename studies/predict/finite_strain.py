"""One nominal point of the finite-strain FEM at the measured pressures, fitted as the prototype's data were.

The prototype's 0.388 mm⁻¹/MPa is the slope of a straight line (with
intercept) through curvature against pressure; the finite-strain FEM's bend
curve (``softcath.fem.nonlinear.bend_curve``, about a minute or three) is reduced the
same way: curvature = bend angle / arc length at each pressure, then the
least-squares line's slope.
"""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np

from softcath import design
from softcath.design.errors import DesignError
from softcath.fem.nonlinear import bend_curve

__all__ = ["line_fit", "finite_strain_point"]


def line_fit(pressure: Sequence[float], curvature: Sequence[float]) -> tuple[float, float]:
    """(slope [1/(mm MPa)], intercept [1/mm]) of the least-squares line κ = slope·p + intercept."""
    p, k = np.asarray(pressure, float), np.asarray(curvature, float)
    if p.size < 2 or p.shape != k.shape or np.ptp(p) == 0:
        raise DesignError("pressures", p.tolist(), "need two or more distinct pressures for a line fit")
    slope, intercept = np.polyfit(p, k, 1)
    return float(slope), float(intercept)


def finite_strain_point(
    design_ref,
    pressures: Sequence[float],
    *,
    load: str = "lumen",
    measured_gain: float | None = None,
    progress: bool = False,
) -> dict:
    """The nominal design's finite-strain bend curve at ``pressures`` [MPa] and its line-fit gain
    (JSON-ready)."""

    t0 = time.perf_counter()
    c = bend_curve(design.resolve(design_ref), list(pressures), load=load, progress=progress)
    slope, intercept = line_fit(c.pressure, c.curvature)
    return {
        "model": "finite-strain FEM (fem.nonlinear.bend_curve), nominal design",
        "load": load,
        "pressures_MPa": [float(v) for v in c.pressure],
        "bend_angle_rad": [float(v) for v in c.bend_angle],
        "curvature_per_mm": [float(v) for v in c.curvature],
        "curvature_per_pressure": [float(k / p) for k, p in zip(c.curvature, c.pressure, strict=True)],
        "linear_bend_angle_rad": [float(v) for v in c.linear_bend_angle],
        "length_mm": float(design.resolve(design_ref).tip.bending_length),
        "gain_line_fit": slope,
        "intercept_per_mm": intercept,
        "measured_over_gain": None if measured_gain is None else float(measured_gain / slope),
        "seconds": float(time.perf_counter() - t0),
    }
