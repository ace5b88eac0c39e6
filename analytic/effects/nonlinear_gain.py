"""Candidate ``nonlinear_gain``: stiffening or softening with pressure."""

from __future__ import annotations

import numpy as np

from softcath.analytic.effects.base import Candidate, Param


class NonlinearGain(Candidate):
    """``x = p + beta p^2 / 2``: the incremental gain changes by ``beta`` per MPa.

    Positive ``beta`` softens (gain grows with pressure), negative stiffens
    (geometric stiffening, ovalisation of the cross-section).
    """

    name = "nonlinear_gain"
    kind = "pressure"
    meaning = "pressure-dependent gain: stiffening (beta < 0) or softening (beta > 0)"
    params = (
        Param(
            "beta_per_MPa",
            "1/MPa",
            -3.0,
            3.0,
            "relative change of incremental gain per MPa (bounds times 1/P)",
            relative_to="inverse_pressure",
        ),
    )
    starts = (0.2, 0.4, 0.5, 0.6, 0.8)

    def apply(self, dt_s: float, x: np.ndarray, *, beta_per_MPa: float) -> np.ndarray:
        return x + 0.5 * beta_per_MPa * x**2


CANDIDATE = NonlinearGain()
