"""The paper's visual feedback drawn on a frame: detected points, fitted arc, base, tip and numbers."""

from __future__ import annotations

import math

import numpy as np

from softcath.hardware.vision.types import Calibration, TipMeasurement


def draw_overlay(frame: np.ndarray, m: TipMeasurement, cal: Calibration) -> np.ndarray:
    """The paper's visual feedback: detected points, fitted arc, base, tip and numbers."""
    import cv2

    out = frame.copy()
    if m.edges_px is not None and len(m.edges_px):
        e = np.round(np.asarray(m.edges_px)).astype(np.intp)
        h, w = out.shape[:2]
        e = e[(e[:, 0] >= 0) & (e[:, 0] < w) & (e[:, 1] >= 0) & (e[:, 1] < h)]
        for u, v in e[:: max(1, len(e) // 400)]:
            cv2.circle(out, (int(u), int(v)), 1, (0, 140, 255), -1)  # edges in orange
    if m.points_px is not None and len(m.points_px):
        for u, v in np.asarray(m.points_px):
            cv2.circle(out, (int(round(u)), int(round(v))), 2, (255, 200, 0), -1, cv2.LINE_AA)
    if m.ok and m.base_px is not None:
        if m.circle_px is not None and m.tip_px is not None:
            xc, yc, r = m.circle_px
            if r < 4 * max(out.shape[:2]):  # the whole fitted circle, thin and grey
                cv2.circle(
                    out, (round(xc * 16), round(yc * 16)), round(r * 16), (160, 160, 160), 1, cv2.LINE_AA, 4
                )
            # the fitted arc from the base to the tip (green)
            tb = math.atan2(m.base_px[1] - yc, m.base_px[0] - xc)
            tt = math.atan2(m.tip_px[1] - yc, m.tip_px[0] - xc)
            sweep = (tt - tb + math.pi) % (2 * math.pi) - math.pi
            if abs(m.bend_angle_rad) > math.pi:  # past half a turn: go the long way
                sweep += -2 * math.pi * math.copysign(1.0, sweep)
            ang = tb + np.linspace(0.0, sweep, 90)
            poly = np.column_stack([xc + r * np.cos(ang), yc + r * np.sin(ang)])
        else:  # straight: the base-to-tip line
            poly = np.array([m.base_px, m.tip_px if m.tip_px is not None else m.base_px])
        cv2.polylines(out, [np.round(poly * 16).astype(np.int32)], False, (0, 220, 0), 2, cv2.LINE_AA, 4)
        cv2.drawMarker(out, tuple(int(round(c)) for c in m.base_px), (255, 0, 255), cv2.MARKER_CROSS, 12, 2)
        if m.tip_px is not None:
            cv2.drawMarker(
                out, tuple(int(round(c)) for c in m.tip_px), (0, 255, 255), cv2.MARKER_TILTED_CROSS, 12, 2
            )
        text = (
            f"k={m.curvature_per_mm:+.4f}/mm  L={m.arc_length_mm:.2f}mm  "
            f"theta={math.degrees(m.bend_angle_rad):+.1f}deg"
        )
    else:
        text = f"no tip: {m.reason}"
    # white text on a dark box (Hershey glyph advance grows with thickness: no outline trick)
    (tw, th), base_line = cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, 0.6, 1)
    cv2.rectangle(out, (4, 4), (16 + tw, 14 + th + base_line), (30, 30, 30), -1)
    cv2.putText(out, text, (10, 24), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (255, 255, 255), 1, cv2.LINE_AA)
    return out
