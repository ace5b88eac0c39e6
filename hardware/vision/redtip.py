"""The red painted tip: the centroid of the HSV red mask (the paper's tip position)."""

from __future__ import annotations

import numpy as np


def _red_mask(bgr: np.ndarray) -> np.ndarray:
    import cv2

    hsv = cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV)
    # red wraps around hue 0 in OpenCV's 0..180 hue scale
    m1 = cv2.inRange(hsv, (0, 110, 60), (10, 255, 255))
    m2 = cv2.inRange(hsv, (170, 110, 60), (180, 255, 255))
    return cv2.bitwise_or(m1, m2)


def find_red_tip(frame: np.ndarray, *, coarse: int = 4) -> tuple[float, float] | None:
    """Centroid ``(u, v)`` of the red tip in pixels, or None.

    The paper averages the coordinates of the red-masked pixels. To stay
    fast on full-HD frames the mask is first found on a ``coarse``-times
    subsampled image, then the centroid is computed at full resolution in a
    window around it.
    """
    import cv2

    h, w = frame.shape[:2]
    # nearest-neighbour decimation (SIMD in OpenCV; a strided numpy copy is ~10x slower)
    small = cv2.resize(frame, (w // coarse, h // coarse), interpolation=cv2.INTER_NEAREST)
    m = _red_mask(small)
    nz = cv2.findNonZero(m)
    if nz is None or len(nz) < 2:
        return None
    x, y, w, h = cv2.boundingRect(nz)
    pad = 3
    u0, v0 = max(0, (x - pad) * coarse), max(0, (y - pad) * coarse)
    u1 = min(frame.shape[1], (x + w + pad) * coarse)
    v1 = min(frame.shape[0], (y + h + pad) * coarse)
    roi = frame[v0:v1, u0:u1]
    mom = cv2.moments(_red_mask(roi), binaryImage=True)
    if mom["m00"] < 4:
        return None
    return (u0 + mom["m10"] / mom["m00"], v0 + mom["m01"] / mom["m00"])
