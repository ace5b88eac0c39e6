"""Candidate ``viscoelastic``: creep of the silicone as a standard linear solid."""

from __future__ import annotations

import numpy as np

from softcath.analytic.effects.base import Candidate, Param, first_order


class Viscoelastic(Candidate):
    """``x = p + c * lag_tau(p)``: an instantaneous response plus delayed creep.

    The standard linear solid (a spring in series with one Kelvin–Voigt unit):
    after a step the response creeps from 1 to ``1 + c`` with retardation time tau.
    """

    name = "viscoelastic"
    kind = "pressure"
    meaning = "creep of the silicone (standard linear solid, one retardation time)"
    params = (
        Param("creep_fraction", "-", 0.0, 3.0, "delayed over instantaneous compliance"),
        Param("tau_s", "s", 0.02, 1.0, "retardation time", relative_to="time", log=True, upper_cap=300.0),
    )
    starts = (0.1, 0.35, 0.6, 0.85)

    def apply(self, dt_s: float, x: np.ndarray, *, creep_fraction: float, tau_s: float) -> np.ndarray:
        return x + creep_fraction * first_order(dt_s, x, tau_s)


CANDIDATE = Viscoelastic()
