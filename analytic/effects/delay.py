"""Candidate ``delay``: a pure time delay of the measured output (camera latency)."""

from __future__ import annotations

import numpy as np

from analytic.effects.base import Candidate, Param


class Delay(Candidate):
    """``y(t) = model(t - d)``: latency of the camera, frame grabber or recorder."""

    name = "delay"
    kind = "output"
    meaning = "pure time delay between pressure and measured shape (camera/recorder latency)"
    params = (Param("delay_s", "s", 0.0, 2.0, "latency of the measured output"),)
    starts = (0.0, 0.03, 0.08, 0.2, 0.5)

    def apply(self, dt_s: float, x: np.ndarray, *, delay_s: float) -> np.ndarray:
        t = np.arange(x.size) * dt_s
        return np.interp(t - delay_s, t, x)


CANDIDATE = Delay()
