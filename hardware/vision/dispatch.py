"""One entry point for both methods: :func:`measure` checks the frame and dispatches."""

from __future__ import annotations

import numpy as np

from softcath.core.errors import DesignError
from softcath.hardware.vision.centreline import measure_centre_line
from softcath.hardware.vision.paper import measure_paper
from softcath.hardware.vision.types import METHODS, Calibration, TipMeasurement


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
        return measure_paper(frame, cal, dy_px)
    return measure_centre_line(frame, cal)
