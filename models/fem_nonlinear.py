"""The ``fem-nonlinear`` tier: the 3-D finite-strain FEM (hyperelastic silicone), design by design and load.

The slowest tier, valid at every bend. Each load walks once through the positive
pressures (:func:`softcath.fem.nonlinear.bend_curve`); 0 MPa is the rest state (no bend,
no strain, the tip at its unloaded length) and a negative pressure, which the walk does not
take, is NaN. Its mid-span curvature is the curve's ``curvature_mid`` (dθ/ds over the middle
of the tip) and its tip-level curvature the curve's θ / s.
"""

from __future__ import annotations

import numpy as np

from softcath.analytic.pose import tip_pose
from softcath.core.interrupts import raise_pending_stop
from softcath.fem.api import check_assembly
from softcath.fem.nonlinear import bend_curve
from softcath.models.tier import Tier

__all__ = ["FEM_NONLINEAR", "FemNonlinearTier"]

#: The response fields the tier takes from each curve's ``to_response``
#: (:class:`~softcath.fem.nonlinear.bend.NonlinearFemCurve`); the lumen volume change, which it
#: does not compute, stays NaN (at rest too).
_CURVE = (
    "curvature_per_mm",
    "tip_curvature_per_mm",
    "elongation",
    "bend_angle_rad",
    "tip_x_mm",
    "tip_y_mm",
    "max_strain",
)


class FemNonlinearTier(Tier):
    """The finite-strain 3-D FEM; it meshes the filler as built but fuses every interface."""

    def check_assembly(self, assembly, *, parameter: str = "assembly") -> None:
        """Refuse the sliding interfaces and free base it does not model (the filler it meshes as built)."""

        check_assembly(self._assembly(assembly))

    def record(self, design, pressures, *, load: str | None = None, options=None):
        """The finite-strain bend curve of one design, walked with this tier's ``options`` as its
        responses are: a :class:`~softcath.fem.nonlinear.bend.NonlinearFemCurve` (the deformed
        mesh, the linear FEM beside it, Newton's record).

        Raises
        ------
        DesignError
            A load or option the tier does not take; the solver's own errors propagate.
        """
        load = self.check_load(self.default_load if load is None else load)
        return bend_curve(design, pressures, load=load, **self.check_options(options))

    def _solve(self, designs, pressures, loads, options):
        import time

        n = len(designs)
        positive = np.unique(pressures[pressures > 0])
        idx = np.searchsorted(positive, pressures)
        pos, rest = pressures > 0, pressures == 0
        out = {}
        for load in loads:
            values = {f: np.full((n, pressures.size), np.nan) for f in _CURVE}
            seconds = np.full(n, np.nan)
            errors: dict[int, Exception] = {}
            for i, d in enumerate(designs):
                t0 = time.perf_counter()
                length = float(d.tip.bending_length)
                x0, y0, _ = tip_pose(0.0, length)
                for f in _CURVE:
                    values[f][i, rest] = {"tip_x_mm": x0, "tip_y_mm": y0}.get(f, 0.0)
                if positive.size:
                    try:
                        curve = self.record(d, positive, load=load, options=options).to_response(
                            tier=self.name
                        )
                    except Exception as exc:  # a failed Newton walk is this design's error
                        raise_pending_stop()
                        errors[i] = exc
                        for f in _CURVE:
                            values[f][i] = np.nan
                        continue
                    for f in _CURVE:
                        values[f][i, pos] = np.asarray(getattr(curve, f), float)[idx[pos]]
                seconds[i] = time.perf_counter() - t0
            out[load] = self._batch(
                designs, pressures, load, values, seconds=seconds, options=options, errors=errors
            )
        return out


#: The 3-D finite-strain FEM.
FEM_NONLINEAR = FemNonlinearTier(
    "fem-nonlinear",
    "the 3-D finite-strain FEM",
    "3-D finite-strain FEM",
    "3-D finite-strain FEM, hyperelastic silicone: the slowest tier",
    "nonlinear",
    options={"size": 0.15, "layers": None, "curvature_points": 12, "substeps": 1, "max_iter": 20},
    seconds_per_design=600.0,
)
