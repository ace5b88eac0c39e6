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
twice); it is kept for comparison.

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

from softcath.hardware.vision.dispatch import measure
from softcath.hardware.vision.overlay import draw_overlay
from softcath.hardware.vision.redtip import find_red_tip
from softcath.hardware.vision.tracker import track_centre_line
from softcath.hardware.vision.types import METHODS, Calibration, TipMeasurement

__all__ = [
    "Calibration",
    "TipMeasurement",
    "measure",
    "draw_overlay",
    "METHODS",
    "find_red_tip",
    "track_centre_line",
]
