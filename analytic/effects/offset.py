"""Candidate ``offset``: pre-curvature at zero pressure."""

from __future__ import annotations

import numpy as np

from softcath.analytic.effects.base import Candidate


class Offset(Candidate):
    """``curvature += kappa0``: residual bend from fabrication, or gravity sag.

    A linear term: its coefficient ``curvature_per_mm`` is solved exactly.
    """

    name = "offset"
    kind = "column"
    meaning = "pre-curvature at zero pressure (fabrication, gravity sag)"
    coefficient = "curvature_per_mm"

    def column(self, dt_s: float, p: np.ndarray, **context: float) -> np.ndarray:
        return np.ones_like(p)


CANDIDATE = Offset()
