"""The paper's edge pipeline (section IV.1), kept for comparison.

Grayscale, Gaussian blur, binary threshold, Canny, horizontal slices of height
``dy_px`` reduced to their mean x, a least-squares (geometric) circle fit,
``kappa = 1/r``, the tip as the centroid of the HSV red mask and
``L = r |theta_t - theta_b|``.
"""

from __future__ import annotations

import math

import numpy as np

from softcath.hardware.circlefit import geometric_fit, kasa_fit
from softcath.hardware.vision.redtip import find_red_tip
from softcath.hardware.vision.result import to_world
from softcath.hardware.vision.types import Calibration, TipMeasurement


def measure_paper(frame: np.ndarray, cal: Calibration, dy_px: float) -> TipMeasurement:
    import cv2

    gray = cv2.cvtColor(frame, cv2.COLOR_BGR2GRAY)
    blur = cv2.GaussianBlur(gray, (5, 5), 0)
    _, binary = cv2.threshold(blur, 0, 255, cv2.THRESH_BINARY_INV + cv2.THRESH_OTSU)
    edges = cv2.Canny(binary, 50, 150)
    nz = cv2.findNonZero(edges)
    if nz is None or len(nz) < 6:
        return TipMeasurement(ok=False, reason="no edges found")
    p = nz.reshape(-1, 2).astype(float)
    # the paper's point reduction: mean x per horizontal slice of height dy
    sl = np.floor(p[:, 1] / dy_px).astype(np.intp)
    sl -= sl.min()
    cnt = np.bincount(sl)
    keep = cnt > 0
    mx = np.bincount(sl, weights=p[:, 0])[keep] / cnt[keep]
    my = np.bincount(sl, weights=p[:, 1])[keep] / cnt[keep]
    red = find_red_tip(frame)
    if len(mx) < 3:
        return TipMeasurement(ok=False, reason="too few slices")
    circ = geometric_fit(np.column_stack([mx, my]), kasa_fit(np.column_stack([mx, my])))
    if cal.base_px is not None:
        base = (float(cal.base_px[0]), float(cal.base_px[1]))
    else:
        j = int(np.argmax(my))  # the lowest reduced point: the base at the bottom, as in Fig. 3a
        base = (float(mx[j]), float(my[j]))
    heading_deg = cal.base_angle_deg
    pts = np.column_stack([mx, my])
    edges = p[:: max(1, len(p) // 3000)]  # the Canny edge points, thinned for display
    if not np.isfinite(circ.radius) or red is None:
        return TipMeasurement(ok=False, points_px=pts, edges_px=edges, reason="no circle or no red tip")
    s = cal.px_per_mm
    a = math.radians(heading_deg)
    dvec = np.array([math.cos(a), -math.sin(a)])  # image coordinates
    cvec = np.array([circ.xc - base[0], circ.yc - base[1]])
    # centre to the right of the heading (image coords, v down): clockwise, positive
    side = dvec[0] * cvec[1] - dvec[1] * cvec[0]
    sign = 1.0 if side > 0 else -1.0
    r_mm = circ.radius / s
    tb = math.atan2(base[1] - circ.yc, base[0] - circ.xc)
    tt = math.atan2(red[1] - circ.yc, red[0] - circ.xc)
    dth = abs((tt - tb + math.pi) % (2 * math.pi) - math.pi)
    length = r_mm * dth
    tip = to_world(np.array([red]), base, s)[0]
    return TipMeasurement(
        ok=True,
        curvature_per_mm=sign / r_mm,
        arc_length_mm=length,
        bend_angle_rad=sign * dth,
        tip_x_mm=float(tip[0]),
        tip_y_mm=float(tip[1]),
        base_px=base,
        base_angle_deg=heading_deg,
        tip_px=red,
        points_px=pts,
        edges_px=edges,
        circle_px=(circ.xc, circ.yc, circ.radius),
    )
