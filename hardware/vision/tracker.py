"""Following the dark tube along its centre line: sub-pixel profiles across the body, step by step.

:func:`track_centre_line` walks from a start point; :func:`find_base` walks from the red tip
back to the clamp and returns the base pose.
"""

from __future__ import annotations

import math

import numpy as np

from softcath.hardware.circlefit import geometric_fit

_BGR_TO_GREY = np.array([0.114, 0.587, 0.299])  # OpenCV's BGR2GRAY weights


def bilinear(img: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Bilinear samples of a grey image, or of the grey value of a BGR image.

    Sampling the colour frame directly (grey = OpenCV's weights) avoids
    converting the whole full-HD frame when only a few profiles are read.
    """
    u0 = np.floor(u).astype(np.intp)
    v0 = np.floor(v).astype(np.intp)
    fu = u - u0
    fv = v - v0
    a = img[v0, u0].astype(float)
    b = img[v0, u0 + 1].astype(float)
    c = img[v0 + 1, u0].astype(float)
    d = img[v0 + 1, u0 + 1].astype(float)
    if img.ndim == 3:
        a, b, c, d = (x @ _BGR_TO_GREY for x in (a, b, c, d))
    return (a * (1 - fu) + b * fu) * (1 - fv) + (c * (1 - fu) + d * fu) * fv


def _profile_centre(prof: np.ndarray, offsets: np.ndarray, min_contrast: float):
    """Sub-pixel centre and width of the dark run nearest the profile middle (None if absent)."""
    lo, hi = float(prof.min()), float(prof.max())
    if hi - lo < min_contrast:
        return None
    t = 0.5 * (lo + hi)
    dark = prof < t
    mid = len(prof) // 2
    idx = np.flatnonzero(dark)
    if idx.size == 0:
        return None
    j = idx[np.argmin(np.abs(idx - mid))]
    # walk to both ends of the run containing j
    left = j
    while left > 0 and dark[left - 1]:
        left -= 1
    right = j
    n = len(prof)
    while right < n - 1 and dark[right + 1]:
        right += 1
    if left == 0 or right == n - 1:
        return None  # run touches the profile end: not a tube cross-section
    # linear interpolation of the crossings at level t
    el = offsets[left - 1] + (prof[left - 1] - t) / (prof[left - 1] - prof[left]) * (
        offsets[left] - offsets[left - 1]
    )
    er = offsets[right] + (prof[right] - t) / (prof[right] - prof[right + 1]) * (
        offsets[right + 1] - offsets[right]
    )
    return 0.5 * (el + er), er - el


def track_centre_line(
    gray: np.ndarray,
    start: tuple[float, float],
    direction: tuple[float, float],
    width_px: float,
    *,
    stop_at: tuple[float, float] | None = None,
    stop_radius: float = 0.0,
    max_length_px: float = 1e5,
    min_contrast: float = 25.0,
):
    """Follow a dark tube from ``start`` along ``direction`` (image px); return centre points.

    ``gray`` is a grey image or a BGR frame (sampled as grey).

    Returns ``(points, widths, last_direction)``: ``(n, 2)`` sub-pixel centre
    points in pixels, their measured widths and the direction at the end.
    """
    h, w = gray.shape[:2]
    step = max(2.0, width_px / 3.0)
    ds = 1.0  # profile spacing, px: the edge crossing is interpolated between samples
    half = 1.5 * width_px
    offsets = np.arange(-half, half + ds / 2, ds)
    d = np.asarray(direction, float)
    d = d / np.hypot(*d)
    p = np.asarray(start, float)
    pts: list[np.ndarray] = []
    widths: list[float] = []
    prev_nd = None
    travelled = 0.0
    first = True
    while travelled < max_length_px:
        q = p if first else p + step * d
        n = np.array([-d[1], d[0]])
        us = q[0] + offsets * n[0]
        vs = q[1] + offsets * n[1]
        if us.min() < 0 or vs.min() < 0 or us.max() >= w - 1 or vs.max() >= h - 1:
            break
        if stop_at is not None and math.hypot(q[0] - stop_at[0], q[1] - stop_at[1]) < stop_radius:
            break
        found = _profile_centre(bilinear(gray, us, vs), offsets, min_contrast)
        if found is None:
            break
        c, wid = found
        if not 0.6 * width_px <= wid <= 1.45 * width_px:
            break
        new = q + c * n
        if not first:
            move = new - p
            norm = math.hypot(*move)
            if norm < 1e-6:
                break
            nd = move / norm
            # predict the next heading with the turn between the last two chords (constant
            # curvature); the first chord has no predecessor (the start direction is a guess)
            turn = 0.0
            if prev_nd is not None:
                turn = math.atan2(prev_nd[0] * nd[1] - prev_nd[1] * nd[0], prev_nd @ nd)
            prev_nd = nd
            cs, sn = math.cos(turn), math.sin(turn)
            d = np.array([cs * nd[0] - sn * nd[1], sn * nd[0] + cs * nd[1]])
            travelled += norm
        first = False
        p = new
        pts.append(new)
        widths.append(wid)
    return np.array(pts).reshape(-1, 2), np.array(widths), d


def find_base(gray: np.ndarray, tip_px, wpx: float):
    """Track from the red tip back to the clamp; return base, heading (deg) and points."""
    # direction into the body: the darkest direction on a ring around the tip
    ang = np.linspace(0, 2 * np.pi, 180, endpoint=False)
    r = 1.6 * wpx
    us = np.clip(tip_px[0] + r * np.cos(ang), 0, gray.shape[1] - 2)
    vs = np.clip(tip_px[1] + r * np.sin(ang), 0, gray.shape[0] - 2)
    ring = bilinear(gray, us, vs)
    dark = ring < 0.5 * (ring.min() + ring.max())
    if not dark.any():
        return None
    # circular mean of the dark directions
    a0 = math.atan2(np.sin(ang[dark]).sum(), np.cos(ang[dark]).sum())
    start = (tip_px[0] + r * math.cos(a0), tip_px[1] + r * math.sin(a0))
    pts, _, d = track_centre_line(gray, start, (math.cos(a0), math.sin(a0)), wpx)
    if len(pts) < 6:
        return None
    # the clamp end: the butt end's round cap lies half a width beyond the last centre point
    end = pts[-1]
    offsets = np.arange(0, 2 * wpx, 0.25)
    pu = np.clip(end[0] + offsets * d[0], 0, gray.shape[1] - 2)
    pv = np.clip(end[1] + offsets * d[1], 0, gray.shape[0] - 2)
    prof = bilinear(gray, pu, pv)
    t = 0.5 * (prof.min() + prof.max())
    above = np.flatnonzero(prof > t)
    cap = offsets[above[0]] if above.size else 0.5 * wpx
    base = end + (cap - 0.5 * wpx) * d  # the cap is a half-disc of radius w/2 around the base
    pts = pts[::-1]
    world = np.column_stack([pts[:, 0] - base[0], -(pts[:, 1] - base[1])])
    circ = geometric_fit(world)
    if np.isfinite(circ.radius):
        # tangent at the base, oriented toward the body
        rvec = np.array([-circ.xc, -circ.yc])
        tan = np.array([-rvec[1], rvec[0]])
        if tan @ (world[-1] - world[0]) < 0:
            tan = -tan
    else:
        tan = world[-1] - world[0]
    heading_deg = math.degrees(math.atan2(tan[1], tan[0]))
    return (float(base[0]), float(base[1])), heading_deg, pts
