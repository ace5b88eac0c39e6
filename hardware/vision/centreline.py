"""The default method: the tube's centre line and a geometric circle fit constrained to the base pose.

From the base (given, or found by tracking back from the red tip) it follows the
tube's centre line (:mod:`softcath.hardware.vision.tracker`); a Hyper-initialised
geometric fit constrained to the known base position and direction
(:func:`softcath.hardware.circlefit.fit_with_base`) gives the signed curvature.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from softcath.hardware.circlefit import fit_with_base
from softcath.hardware.vision.redtip import find_red_tip
from softcath.hardware.vision.result import arc_result, to_world
from softcath.hardware.vision.tracker import find_base, track_centre_line
from softcath.hardware.vision.types import Calibration, TipMeasurement


def measure_centre_line(frame: np.ndarray, cal: Calibration) -> TipMeasurement:
    gray = frame  # sampled as grey where needed (see tracker.bilinear)
    s = cal.px_per_mm
    wpx = cal.diameter_mm * s
    tip_px = find_red_tip(frame)
    # the red disc is wider than the tube: stop tracking a tube width before it
    stop_r = 1.2 * wpx
    if cal.base_px is not None:
        base = (float(cal.base_px[0]), float(cal.base_px[1]))
        heading_deg = cal.base_angle_deg
        a = math.radians(heading_deg)
        pts, widths, _ = track_centre_line(
            gray, base, (math.cos(a), -math.sin(a)), wpx, stop_at=tip_px, stop_radius=stop_r
        )
        if len(pts) < 4:
            return TipMeasurement(ok=False, reason="no tube found at the base")
    else:
        if tip_px is None:
            return TipMeasurement(ok=False, reason="no red tip found (needed to find the base)")
        got = find_base(gray, tip_px, wpx)
        if got is None:
            return TipMeasurement(ok=False, reason="could not follow the tube from the red tip")
        base, heading_deg, pts = got
        widths = np.full(len(pts), wpx)
    world = to_world(pts, base, s)
    k_ccw, _ = fit_with_base(world, (0.0, 0.0), math.radians(heading_deg))
    m = arc_result(-k_ccw, base, heading_deg, tip_px, pts, s)
    circle = None
    if abs(k_ccw) > 1e-9:
        # centre on the right of travel for clockwise (k_ccw < 0); image v points down
        a = math.radians(heading_deg)
        dx, dy = math.cos(a), -math.sin(a)
        r_px = s / abs(k_ccw)
        side = 1.0 if k_ccw < 0 else -1.0
        circle = (base[0] - side * dy * r_px, base[1] + side * dx * r_px, r_px)
    return replace(m, edges_px=_edges(pts, widths), circle_px=circle)


def _edges(pts: np.ndarray, widths: np.ndarray) -> np.ndarray:
    """Both tube edges at each centre point (for the overlay), px."""
    tan = np.gradient(pts, axis=0)
    tan /= np.maximum(np.hypot(tan[:, 0], tan[:, 1]), 1e-12)[:, None]
    nrm = np.column_stack([-tan[:, 1], tan[:, 0]]) * (widths / 2)[:, None]
    return np.vstack([pts + nrm, pts - nrm])
