"""Candidate ``dead_zone``: no bending below a threshold pressure."""

from __future__ import annotations

import numpy as np

from softcath.analytic.effects.base import Candidate, Param


class DeadZone(Candidate):
    """``x = max(p - p0, 0)``: pre-stress or friction to overcome before the tip moves."""

    name = "dead_zone"
    kind = "pressure"
    meaning = "threshold pressure below which the tip does not bend (pre-stress, friction)"
    params = (
        Param(
            "threshold_MPa", "MPa", 0.0, 0.5, "pressure needed before bending starts", relative_to="pressure"
        ),
    )
    starts = (0.02, 0.1, 0.25, 0.5, 0.8)

    def apply(self, dt_s: float, x: np.ndarray, *, threshold_MPa: float) -> np.ndarray:
        return np.maximum(x - threshold_MPa, 0.0)


CANDIDATE = DeadZone()
