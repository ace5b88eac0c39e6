"""Measuring the tip from camera frames: the paper's edge pipeline and a centre-line default.

Both return a :class:`TipMeasurement` in the conventions of
:mod:`softcath.virtualbench.render` (mm relative to the base, x right, y up; positive
curvature turns clockwise in the image).

``method="paper"`` is what the paper describes (section IV.1): grayscale,
Gaussian blur, binary threshold, Canny, horizontal slices of height
``dy_px`` reduced to their mean x, a least-squares (geometric) circle fit,
``kappa = 1/r``, the tip as the centroid of the HSV red mask and
``L = r |theta_t - theta_b|``. On synthetic renders it underestimates
curvature badly and fails past about 90-120 degrees (slices cut the tube
twice; shared/notes/vision-and-bench.md); it is kept for comparison.

``method="default"`` follows the tube's centre line: from the base, it
steps along the body and, on a profile across it, finds both edges with
sub-pixel interpolation at the local half level; the midpoints are the
centre line (an equivalent of skeletonising the mask that is exact for a
blurred tube and cheap: only ~2 profiles per millimetre are read). A
Hyper-initialised geometric fit constrained to the known base position and
direction (:func:`softcath.hardware.circlefit.fit_with_base`) gives the signed
curvature; it works from a straight tip to beyond 180 degrees. Without a
given base the track starts at the red tip and runs back to the clamp,
and the base pose is taken from a free geometric fit.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, replace

import numpy as np

from softcath.design.errors import DesignError
from softcath.hardware.circlefit import fit_with_base, geometric_fit, kasa_fit

__all__ = ["Calibration", "TipMeasurement", "measure", "draw_overlay", "METHODS"]

log = logging.getLogger(__name__)

METHODS = ("default", "paper")


@dataclass(frozen=True)
class Calibration:
    """Image scale and (optionally) base pose.

    Parameters
    ----------
    px_per_mm
        Image scale in the bending plane, px/mm.
    base_px
        Base position ``(u, v)`` in pixels, origin top-left, v down; None: find it.
    base_angle_deg
        Base direction, counter-clockwise from the image +x axis, degrees (90: up).
    diameter_mm
        Expected tube diameter, mm (sets profile lengths and width checks).
    """

    px_per_mm: float
    base_px: tuple[float, float] | None = None
    base_angle_deg: float = 90.0
    diameter_mm: float = 0.8

    def __post_init__(self) -> None:
        if not (math.isfinite(self.px_per_mm) and self.px_per_mm > 0):
            raise DesignError("px_per_mm", self.px_per_mm, "must be a finite number > 0")
        if not (math.isfinite(self.base_angle_deg)):
            raise DesignError("base_angle_deg", self.base_angle_deg, "must be finite")
        if not self.diameter_mm * self.px_per_mm >= 3:
            raise DesignError(
                "px_per_mm",
                self.px_per_mm,
                f"must resolve the {self.diameter_mm} mm tube with >= 3 px "
                f"(>= {3 / self.diameter_mm:.3g} px/mm)",
            )


@dataclass(frozen=True)
class TipMeasurement:
    """One frame's result; ``ok`` is False (and numbers NaN) when no tip was found."""

    ok: bool
    curvature_per_mm: float = float("nan")
    arc_length_mm: float = float("nan")
    bend_angle_rad: float = float("nan")
    tip_x_mm: float = float("nan")
    tip_y_mm: float = float("nan")
    base_px: tuple[float, float] | None = None
    base_angle_deg: float = float("nan")
    tip_px: tuple[float, float] | None = None
    points_px: np.ndarray | None = None
    edges_px: np.ndarray | None = None
    circle_px: tuple[float, float, float] | None = None
    reason: str = ""

    def row(self) -> dict[str, float]:
        """The measurement-CSV columns of this frame."""
        return {
            "curvature_per_mm": self.curvature_per_mm,
            "arc_length_mm": self.arc_length_mm,
            "bend_angle_rad": self.bend_angle_rad,
            "tip_x_mm": self.tip_x_mm,
            "tip_y_mm": self.tip_y_mm,
        }


# --- red tip -------------------------------------------------------------------------------------
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


# --- centre-line tracker -------------------------------------------------------------------------
_BGR_TO_GREY = np.array([0.114, 0.587, 0.299])  # OpenCV's BGR2GRAY weights


def _bilinear(img: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
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
        found = _profile_centre(_bilinear(gray, us, vs), offsets, min_contrast)
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


def _to_world(pts_px: np.ndarray, base: tuple[float, float], s: float) -> np.ndarray:
    pts_px = np.asarray(pts_px, float).reshape(-1, 2)
    return np.column_stack([(pts_px[:, 0] - base[0]) / s, -(pts_px[:, 1] - base[1]) / s])


def _arc_to_tip(k_ccw: float, tip: np.ndarray, heading: float) -> float:
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


def _result(k_cw, base, heading_deg, tip_px, pts, s, reason=""):
    if tip_px is None:
        return TipMeasurement(
            ok=False,
            curvature_per_mm=k_cw,
            base_px=base,
            base_angle_deg=heading_deg,
            points_px=pts,
            reason=reason or "no red tip found",
        )
    tip = _to_world(np.array([tip_px]), base, s)[0]
    length = _arc_to_tip(-k_cw, tip, math.radians(heading_deg))
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


def _measure_default(frame: np.ndarray, cal: Calibration) -> TipMeasurement:
    gray = frame  # sampled as grey where needed (see _bilinear)
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
        got = _find_base(gray, tip_px, wpx)
        if got is None:
            return TipMeasurement(ok=False, reason="could not follow the tube from the red tip")
        base, heading_deg, pts = got
        widths = np.full(len(pts), wpx)
    world = _to_world(pts, base, s)
    k_ccw, _ = fit_with_base(world, (0.0, 0.0), math.radians(heading_deg))
    m = _result(-k_ccw, base, heading_deg, tip_px, pts, s)
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


def _find_base(gray: np.ndarray, tip_px, wpx: float):
    """Track from the red tip back to the clamp; return base, heading (deg) and points."""
    # direction into the body: the darkest direction on a ring around the tip
    ang = np.linspace(0, 2 * np.pi, 180, endpoint=False)
    r = 1.6 * wpx
    us = np.clip(tip_px[0] + r * np.cos(ang), 0, gray.shape[1] - 2)
    vs = np.clip(tip_px[1] + r * np.sin(ang), 0, gray.shape[0] - 2)
    ring = _bilinear(gray, us, vs)
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
    prof = _bilinear(gray, pu, pv)
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


def _measure_paper(frame: np.ndarray, cal: Calibration, dy_px: float) -> TipMeasurement:
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
    tip = _to_world(np.array([red]), base, s)[0]
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


def measure(
    frame: np.ndarray, cal: Calibration, *, method: str = "default", dy_px: float = 10.0
) -> TipMeasurement:
    """Measure curvature, arc length, bend angle and tip position in one BGR frame.

    Parameters
    ----------
    frame
        ``(h, w, 3)`` uint8 BGR image.
    cal
        Scale and base pose.
    method
        ``"default"`` (centre line + base-constrained fit) or ``"paper"``.
    dy_px
        Slice height of the paper's point reduction, px (paper method only).
    """
    if method not in METHODS:
        raise DesignError("method", method, f"must be one of {', '.join(METHODS)}")
    if frame is None or frame.ndim != 3 or frame.shape[2] != 3:
        shape = None if frame is None else frame.shape
        raise DesignError("frame", shape, "must be an (h, w, 3) BGR image")
    if method == "paper":
        if not dy_px > 0:
            raise DesignError("dy_px", dy_px, "must be > 0")
        return _measure_paper(frame, cal, dy_px)
    return _measure_default(frame, cal)


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


__all__ += ["find_red_tip", "track_centre_line"]
