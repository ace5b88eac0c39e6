"""The paper's formula as the demo's sections ask for it: through the registry's ``paper`` tier.

Every formula number of the demo comes from :func:`softcath.models.response`, so the tier's
options (``--model-option``) reach each of them; without options the numbers are the
formula's own, bit for bit (:func:`softcath.analytic.response`, :func:`softcath.analytic.gains`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from softcath import models
from softcath.analytic.beam import BeamResponse
from softcath.analytic.inverse import pressure_for_angle_of_gains

__all__ = ["paper_gains", "paper_pressure_for_bend_angle", "paper_response"]

#: The tier every function here asks.
TIER = "paper"


def paper_response(design, pressures, load: str, options: Mapping[str, Any] | None = None) -> BeamResponse:
    """The response at ``pressures`` [MPa] under ``load``, of :func:`softcath.analytic.response`'s type."""
    p = np.asarray(pressures, dtype=float)
    r = models.response(design, p.ravel(), tier=TIER, load=load, options=options)

    def shaped(values):  # a scalar pressure gives scalar values, as the formula's own response does
        return np.asarray(values).reshape(p.shape)

    elongation = shaped(r.elongation)
    return BeamResponse(
        pressure=p,
        curvature=shaped(r.curvature_per_mm),
        elongation=elongation,
        arc_length=design.tip.bending_length * (1.0 + elongation),
        bend_angle=shaped(r.bend_angle_rad),
        tip_x=shaped(r.tip_x_mm),
        tip_y=shaped(r.tip_y_mm),
    )


def paper_gains(design, load: str, options: Mapping[str, Any] | None = None) -> tuple[float, float]:
    """(κ/p [1/(mm MPa)], ε/p [1/MPa]): the formula is linear in p, so its response at 1 MPa."""
    r = models.response(design, [1.0], tier=TIER, load=load, options=options)
    return float(r.curvature_per_mm[0]), float(r.elongation[0])


def paper_pressure_for_bend_angle(design, angle_rad, *, load: str = "cap", options=None) -> np.ndarray:
    """Pressure [MPa] for a bend of ``angle_rad`` (:func:`softcath.analytic.pressure_for_bend_angle`)."""
    k, e = paper_gains(design, load, options)
    return pressure_for_angle_of_gains(k, e, angle_rad, length=design.tip.bending_length, name=design.name)
