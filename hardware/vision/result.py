"""From pixels to the measurement: world coordinates, the arc length to the tip, the record."""

from __future__ import annotations

import math

import numpy as np

from softcath.hardware.vision.types import TipMeasurement


def to_world(pts_px: np.ndarray, base: tuple[float, float], s: float) -> np.ndarray:
    pts_px = np.asarray(pts_px, float).reshape(-1, 2)
    return np.column_stack([(pts_px[:, 0] - base[0]) / s, -(pts_px[:, 1] - base[1]) / s])


def arc_to_tip(k_ccw: float, tip: np.ndarray, heading: float) -> float:
    """Arc length (mm) from the base to the tip's projection on the fitted circle."""
    c, s = math.cos(heading), math.sin(heading)
    a = tip[0] * c + tip[1] * s
    b = -tip[0] * s + tip[1] * c
    if abs(k_ccw * math.hypot(a, b)) < 1e-9:
        return a
    phi = math.atan2(k_ccw * a, 1 - k_ccw * b)
    if k_ccw > 0 and phi < 0:
        phi += 2 * math.pi
    elif k_ccw < 0 and phi > 0:
        phi -= 2 * math.pi
    return phi / k_ccw


def arc_result(k_cw, base, heading_deg, tip_px, pts, s, *, reason=""):
    if tip_px is None:
        return TipMeasurement(
            ok=False,
            curvature_per_mm=k_cw,
            base_px=base,
            base_angle_deg=heading_deg,
            points_px=pts,
            reason=reason or "no red tip found",
        )
    tip = to_world(np.array([tip_px]), base, s)[0]
    length = arc_to_tip(-k_cw, tip, math.radians(heading_deg))
    return TipMeasurement(
        ok=True,
        curvature_per_mm=float(k_cw),
        arc_length_mm=float(length),
        bend_angle_rad=float(k_cw * length),
        tip_x_mm=float(tip[0]),
        tip_y_mm=float(tip[1]),
        base_px=(float(base[0]), float(base[1])),
        base_angle_deg=float(heading_deg),
        tip_px=(float(tip_px[0]), float(tip_px[1])),
        points_px=pts,
    )
