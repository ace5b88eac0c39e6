"""Candidate ``delay``: a pure time delay of the measured output (camera latency)."""

from __future__ import annotations

import numpy as np

from softcath.analytic.effects.base import Candidate, Param


class Delay(Candidate):
    """``y(t) = model(t - d)``: latency of the camera, frame grabber or recorder."""

    name = "delay"
    kind = "output"
    meaning = "pure time delay between pressure and measured shape (camera/recorder latency)"
    params = (Param("delay_s", "s", 0.0, 2.0, "latency of the measured output"),)
    starts = (0.0, 0.03, 0.08, 0.2, 0.5)

    def apply(self, dt_s: float, x: np.ndarray, *, delay_s: float) -> np.ndarray:
        # cubic-spline fractional delay: linear interpolation of a 0.2 Hz sine at
        # 10-20 Hz low-passes it by (w h)^2/8 ~ 1e-3, comparable with the filtered
        # noise; the spline's error is O((w h)^4). Before t = 0 the tip was at rest.
        from scipy.interpolate import CubicSpline

        t = np.arange(x.size) * dt_s
        tq = np.clip(t - delay_s, 0.0, None)
        return CubicSpline(t, x)(tq)


CANDIDATE = Delay()
