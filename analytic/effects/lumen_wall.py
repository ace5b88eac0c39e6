"""Candidate ``lumen_wall``: the pressure on the lumen wall (reference = FEM).

The cap-load model lets pressure act only on the sealed cap. Pressure on the
lumen wall also loads the section, and inside a coil it does so with the
opposite sign to the one-material closed form (1 - 2 nu): the coil's hoop
confines the near-incompressible silicone and the wall load bends the tip
~2.4x *more* (docs/section.md). The regressor is therefore the section
model's lumen-minus-cap curvature per MPa, ``lumen_minus_cap_gain_per_mm_MPa``
times p, which the studies layer supplies (analytic does not import fem). Its
curvature is linear in pressure, so against measured data it is
indistinguishable from a gain error (calibration absorbs it); against the FEM,
where the gain is not calibrated, it is a named effect with a free coefficient
``scale``: 1 when the reference behaves as the section model's lumen load.
Over design sweeps the same physics is the ``confinement`` ingredient of
``softcath.studies.discrepancy.design_workflow``.
"""

from __future__ import annotations

import numpy as np

from softcath.analytic.effects.base import Candidate


class LumenWallLoad(Candidate):
    name = "lumen_wall"
    kind = "column"
    meaning = "pressure on the coil-confined lumen wall (section model; FEM reference only)"
    coefficient = "scale"

    def column(self, dt_s: float, p: np.ndarray, **context: float) -> np.ndarray:
        g = context.get("lumen_minus_cap_gain_per_mm_MPa", 0.0)
        return g * p


CANDIDATE = LumenWallLoad()
