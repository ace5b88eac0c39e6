"""Candidate ``lag``: a first-order lag of the pressure (the supply line as one RC)."""

from __future__ import annotations

import numpy as np

from softcath.analytic.effects.base import Candidate, Param, first_order


class Lag(Candidate):
    """``tau x' = p - x``: the tube sees the inlet pressure through one time constant.

    A long thin transmission line has ``tau ~ R_hyd C``; its loop area grows with
    the excitation frequency, unlike rate-independent hysteresis.
    """

    name = "lag"
    kind = "pressure"
    meaning = "first-order lag of the pressure reaching the tip (supply line R_hyd*C)"
    params = (Param("tau_s", "s", 1e-3, 30.0, "time constant of the lag", log=True),)
    starts = (0.1, 0.3, 0.5, 0.7, 0.9)

    def apply(self, dt_s: float, x: np.ndarray, *, tau_s: float) -> np.ndarray:
        return first_order(dt_s, x, tau_s)


CANDIDATE = Lag()
