"""Pixel-to-millimetre scale from a chessboard or two points a known distance apart.

Usual practice: calibrate the lens with
OpenCV (>= 10 chessboard views, :func:`camera_intrinsics`), undistort, then
take the scale from a target lying in the bending plane. The bending angle
does not depend on the scale; curvature and arc length do.
"""

from __future__ import annotations

import math

import numpy as np

from softcath.core.errors import DesignError
from softcath.hardware.errors import FrameSourceError

__all__ = ["scale_from_points", "scale_from_chessboard", "camera_intrinsics"]


def scale_from_points(p1_px, p2_px, distance_mm: float) -> float:
    """Scale (px/mm) from two image points ``distance_mm`` apart in the bending plane."""
    if not (math.isfinite(distance_mm) and distance_mm > 0):
        raise DesignError("distance_mm", distance_mm, "must be > 0")
    d = math.dist(tuple(map(float, p1_px)), tuple(map(float, p2_px)))
    if d <= 0:
        raise DesignError("p2_px", tuple(p2_px), "must differ from p1_px")
    return d / distance_mm


def _corners(image: np.ndarray, pattern: tuple[int, int]) -> np.ndarray:
    import cv2

    gray = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY) if image.ndim == 3 else image
    found, corners = cv2.findChessboardCorners(gray, pattern)
    if not found:
        raise FrameSourceError(
            f"chessboard with {pattern[0]}x{pattern[1]} inner corners: not found in the image"
        )
    crit = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 50, 1e-4)
    return cv2.cornerSubPix(gray, corners, (5, 5), (-1, -1), crit).reshape(pattern[1], pattern[0], 2)


def scale_from_chessboard(image: np.ndarray, *, pattern: tuple[int, int], square_mm: float) -> float:
    """Scale (px/mm) from a fronto-parallel chessboard in the bending plane.

    Parameters
    ----------
    image
        BGR or grey image of the board.
    pattern
        Inner corners per row and column, e.g. ``(9, 6)``.
    square_mm
        Side of one square, mm.
    """
    if not (math.isfinite(square_mm) and square_mm > 0):
        raise DesignError("square_mm", square_mm, "must be > 0")
    c = _corners(image, pattern)
    d_row = np.linalg.norm(np.diff(c, axis=1), axis=2)
    d_col = np.linalg.norm(np.diff(c, axis=0), axis=2)
    return float(np.concatenate([d_row.ravel(), d_col.ravel()]).mean() / square_mm)


def camera_intrinsics(images, *, pattern: tuple[int, int], square_mm: float):
    """OpenCV camera calibration from chessboard views: ``(camera_matrix, dist_coeffs, rms_px)``."""
    import cv2

    images = list(images)
    if len(images) < 3:
        raise DesignError("images", len(images), "must hold >= 3 chessboard views (10+ advised)")
    obj = np.zeros((pattern[0] * pattern[1], 3), np.float32)
    obj[:, :2] = np.mgrid[0 : pattern[0], 0 : pattern[1]].T.reshape(-1, 2) * square_mm
    img_pts = [_corners(im, pattern).reshape(-1, 1, 2).astype(np.float32) for im in images]
    h, w = images[0].shape[:2]
    rms, k, dist, _, _ = cv2.calibrateCamera([obj] * len(images), img_pts, (w, h), None, None)
    return k, dist, float(rms)
