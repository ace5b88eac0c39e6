"""Candidate ``lumen_poisson``: the lumen-wall pressure term (reference = FEM).

The cap-load model lets pressure act only on the sealed cap. Pressure on the
lumen wall also strains the tube axially through Poisson's ratio, a
``(1 - 2 nu)`` term (see ``analytic.response(..., load="lumen")``). Its
curvature is linear in pressure, so against measured data it is
indistinguishable from a gain error (calibration absorbs it); against the FEM,
where the gain is not calibrated, it is a named effect. Its regressor is the
difference between the lumen-load and cap-load curvature per MPa,
``lumen_minus_cap_gain_per_mm_MPa`` times p (from ``analytic.gains``), with a
free coefficient ``scale``: 1 when the reference behaves exactly as the
lumen-load model, 0 when it behaves as the cap-load model.
"""

from __future__ import annotations

import numpy as np

from analytic.effects.base import Candidate


class LumenPoisson(Candidate):
    name = "lumen_poisson"
    kind = "column"
    meaning = "pressure on the lumen wall, (1 - 2 nu) axial term (FEM reference only)"
    coefficient = "scale"

    def column(self, dt_s: float, p: np.ndarray, **context: float) -> np.ndarray:
        g = context.get("lumen_minus_cap_gain_per_mm_MPa", 0.0)
        return g * p


CANDIDATE = LumenPoisson()
