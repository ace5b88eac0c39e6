"""Synthetic camera frames of the bent tip: the virtual camera, and ground truth for vision tests.

The tip is a constant-curvature arc (the paper's model) drawn as a dark tube
of the catheter's diameter with a red painted end (a disc centred on the
arc's end, so the red centroid is the tip position), on a lit background
with an illumination gradient, optical blur and sensor noise: fresh noise
in a box around the tube every frame, a fixed noise pattern elsewhere
(rendering only that box keeps the virtual camera fast).

Conventions (shared by :mod:`softcath.hardware.vision`): image pixels ``(u, v)``
with the origin top-left and ``v`` down; world millimetres ``(x, y)`` with
the origin at the base, ``x`` right, ``y`` up. The base direction is an
angle counter-clockwise from the image's +x axis (90 degrees: pointing
up). Positive curvature turns the tip clockwise as seen in the image (to
the right of its direction of travel), so with the base pointing up a
positive curvature gives ``tip_x = L (1 - cos(theta)) / theta > 0``,
the paper's eq. 9.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from softcath.core.errors import DesignError

__all__ = ["Scene", "arc_points", "arc_end_pose", "render_frame", "render_chessboard"]


def arc_points(curvature_per_mm: float, s_mm, heading_rad: float = np.pi / 2) -> np.ndarray:
    """Points (mm, x right, y up, base at origin) at arc lengths ``s_mm`` of the tip.

    ``curvature_per_mm > 0`` turns clockwise; ``heading_rad`` is the base direction.
    """
    s = np.asarray(s_mm, dtype=float)
    k = float(curvature_per_mm)
    phi = heading_rad - k * s
    if abs(k) * float(np.max(np.abs(s), initial=0.0)) < 1e-9:
        return np.stack([s * np.cos(heading_rad), s * np.sin(heading_rad)], axis=-1)
    x = -(np.sin(phi) - np.sin(heading_rad)) / k
    y = (np.cos(phi) - np.cos(heading_rad)) / k
    return np.stack([x, y], axis=-1)


def arc_end_pose(curvature_per_mm: float, arc_length_mm: float, heading_rad: float = np.pi / 2):
    """``(tip_x_mm, tip_y_mm, bend_angle_rad)`` of the drawn arc's end, the scene's ground truth.

    Eq. 9 (:func:`softcath.analytic.pose.tip_pose`, same order: position, then
    angle) for a base pointing along ``heading_rad``; with the default heading
    (up) the two agree.
    """
    x, y = arc_points(curvature_per_mm, arc_length_mm, heading_rad)
    return float(x), float(y), float(curvature_per_mm * arc_length_mm)


@dataclass(frozen=True)
class Scene:
    """Camera and look of the virtual rig.

    Parameters
    ----------
    width_px, height_px
        Frame size in pixels.
    px_per_mm
        Image scale, px/mm.
    base_px
        Base position ``(u, v)`` in pixels (origin top-left, v down); default:
        centred horizontally, 15 % above the bottom edge.
    base_angle_deg
        Base direction, counter-clockwise from the image +x axis, degrees.
    diameter_mm
        Tube diameter drawn, mm (the paper's OD 0.8 mm).
    tip_diameter_mm
        Diameter of the red painted end, mm.
    blur_px
        Optical blur (Gaussian sigma), px.
    noise
        Sensor noise (Gaussian sigma), grey levels of 255.
    """

    width_px: int = 640
    height_px: int = 480
    px_per_mm: float = 40.0
    base_px: tuple[float, float] | None = None
    base_angle_deg: float = 90.0
    diameter_mm: float = 0.8
    tip_diameter_mm: float = 1.0
    blur_px: float = 1.0
    noise: float = 2.0
    body_grey: float = 45.0
    background_grey: float = 205.0

    def __post_init__(self) -> None:
        for name in ("width_px", "height_px"):
            if not 16 <= getattr(self, name) <= 10000:
                raise DesignError(f"scene.{name}", getattr(self, name), "must be in [16, 10000]")
        if not self.px_per_mm > 0:
            raise DesignError("scene.px_per_mm", self.px_per_mm, "must be > 0")
        if self.noise < 0:
            raise DesignError("scene.noise", self.noise, "must be >= 0")

    @property
    def base(self) -> tuple[float, float]:
        """Base position in pixels."""
        if self.base_px is not None:
            return (float(self.base_px[0]), float(self.base_px[1]))
        return (self.width_px / 2.0, self.height_px * 0.85)


def _distance_to_arc(uu, vv, base, heading, k_px, length_px):
    """Distance (px) from pixel centres to a constant-curvature arc in image coordinates."""
    # work in y-up coordinates so the world conventions apply
    x = uu - base[0]
    y = -(vv - base[1])
    c, s = np.cos(heading), np.sin(heading)
    a = x * c + y * s  # along the base direction
    b = -x * s + y * c  # to the left
    end = arc_points(k_px, length_px, 0.0)
    d_end = np.hypot(a - end[0], b - end[1])
    d_base = np.hypot(a, b)
    caps = np.minimum(d_end, d_base)
    if abs(k_px) * length_px < 1e-9:
        inside = (a >= 0) & (a <= length_px)
        return np.where(inside, np.abs(b), caps)
    r = 1.0 / abs(k_px)
    cy = -np.sign(k_px) * r  # centre on the right for clockwise (k > 0)
    rho = np.hypot(a, b - cy)
    ang = np.arctan2(b - cy, a)  # base is at angle +90 deg (k>0) or -90 deg (k<0)
    start = np.pi / 2 if k_px > 0 else -np.pi / 2
    swept = (start - ang) if k_px > 0 else (ang - start)
    swept = np.mod(swept, 2 * np.pi)
    on_arc = swept <= abs(k_px) * length_px
    return np.where(on_arc, np.abs(rho - r), caps)


def render_frame(
    scene: Scene,
    *,
    curvature_per_mm: float,
    arc_length_mm: float,
    rng: np.random.Generator | None = None,
) -> np.ndarray:
    """Render one BGR ``uint8`` frame of the tip.

    Parameters
    ----------
    scene
        Camera and look.
    curvature_per_mm
        Signed curvature, 1/mm (positive: clockwise in the image).
    arc_length_mm
        Length of the bending section, mm.
    rng
        Noise generator (seeded for reproducible frames); no noise if None.
    """
    import cv2

    if not arc_length_mm > 0:
        raise DesignError("arc_length_mm", arc_length_mm, "must be > 0")
    h, w = scene.height_px, scene.width_px
    s = scene.px_per_mm
    base = scene.base
    heading = np.deg2rad(scene.base_angle_deg)
    noisy = rng is not None and scene.noise > 0
    img = _background(scene, noisy).copy()
    # only a box around the tube changes from frame to frame: draw, blur and add fresh
    # noise there (the rest keeps the fixed sensor pattern of the cached background)
    pts = arc_points(curvature_per_mm, np.linspace(0, arc_length_mm, 64), heading) * s
    us = base[0] + pts[:, 0]
    vs = base[1] - pts[:, 1]
    margin = scene.tip_diameter_mm * s + 4 * scene.blur_px + 4
    u0, u1 = int(max(0, np.floor(us.min() - margin))), int(min(w, np.ceil(us.max() + margin)))
    v0, v1 = int(max(0, np.floor(vs.min() - margin))), int(min(h, np.ceil(vs.max() + margin)))
    if u1 <= u0 or v1 <= v0:
        return img
    roi = _gradient(scene)[v0:v1, u0:u1].copy()
    vv, uu = np.mgrid[v0:v1, u0:u1].astype(np.float64)
    k_px = curvature_per_mm / s
    d = _distance_to_arc(uu, vv, base, heading, k_px, arc_length_mm * s)
    half = scene.diameter_mm * s / 2
    body = np.clip(half + 0.5 - d, 0.0, 1.0).astype(np.float32)  # 1-px anti-aliasing ramp
    ex, ey = arc_points(curvature_per_mm, arc_length_mm, heading) * s
    dt = np.hypot(uu - (base[0] + ex), vv - (base[1] - ey))
    tip = np.clip(scene.tip_diameter_mm * s / 2 + 0.5 - dt, 0.0, 1.0).astype(np.float32)
    body_col = np.array([scene.body_grey] * 3, np.float32)
    red = np.array([40.0, 35.0, 200.0], np.float32)  # BGR
    roi = roi * (1 - body[..., None]) + body_col * body[..., None]
    roi = roi * (1 - tip[..., None]) + red * tip[..., None]
    if scene.blur_px > 0:
        roi = cv2.GaussianBlur(roi, (0, 0), scene.blur_px, borderType=cv2.BORDER_REPLICATE)
    if noisy:
        roi += rng.standard_normal(roi.shape, dtype=np.float32) * np.float32(scene.noise)
    img[v0:v1, u0:u1] = np.clip(roi + 0.5, 0, 255).astype(np.uint8)
    return img


@functools.lru_cache(maxsize=8)
def _gradient(scene: Scene) -> np.ndarray:
    """Lit background: a gentle left-to-right illumination gradient (float32 BGR)."""
    grad = np.linspace(-12.0, 12.0, scene.width_px, dtype=np.float32)
    img = np.empty((scene.height_px, scene.width_px, 3), np.float32)
    img[:] = (scene.background_grey + grad)[None, :, None]
    img.setflags(write=False)
    return img


@functools.lru_cache(maxsize=8)
def _background(scene: Scene, noisy: bool) -> np.ndarray:
    """Background frame (uint8) with, if ``noisy``, a fixed sensor noise pattern (seed 0)."""
    img = _gradient(scene).copy()
    if noisy:
        img += np.random.default_rng(0).standard_normal(img.shape, dtype=np.float32) * np.float32(scene.noise)
    out = np.clip(img + 0.5, 0, 255).astype(np.uint8)
    out.setflags(write=False)
    return out


def render_chessboard(
    *, squares=(10, 7), square_px: float = 30.0, size=(640, 480), origin=(40.0, 40.0)
) -> np.ndarray:
    """A fronto-parallel chessboard image (BGR) with ``squares`` squares of ``square_px`` pixels."""
    import cv2

    w, h = size
    img = np.full((h, w), 230, np.uint8)
    for i in range(squares[0]):
        for j in range(squares[1]):
            if (i + j) % 2 == 0:
                x0 = origin[0] + i * square_px
                y0 = origin[1] + j * square_px
                pts = np.array(
                    [
                        [x0, y0],
                        [x0 + square_px, y0],
                        [x0 + square_px, y0 + square_px],
                        [x0, y0 + square_px],
                    ]
                )
                cv2.fillConvexPoly(img, np.round(pts * 16).astype(np.int32), 20, cv2.LINE_AA, 4)
    return cv2.cvtColor(img, cv2.COLOR_GRAY2BGR)
