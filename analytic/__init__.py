"""The composite Euler–Bernoulli model of the tip (paper eqs. 1–9) and its calibration (eq. 8).

>>> from softcath import analytic, design
>>> r = analytic.response(design.preset("paper"), [0.0, 1.0])
>>> float(r.curvature[0])
0.0
"""

from __future__ import annotations

from softcath.analytic.beam import (
    LOADS,
    BeamResponse,
    gains,
    gains_arrays,
    response,
    response_arrays,
    response_from_gains,
)
from softcath.analytic.inverse import pressure_for_bend_angle, pressure_for_tip
from softcath.analytic.pose import pose_matrix, tip_pose
from softcath.analytic.section import (
    CompositeSection,
    composite_section,
    design_inputs,
    design_inputs_many,
    section_arrays,
)

__all__ = [
    "LOADS",
    "BeamResponse",
    "CompositeSection",
    "composite_section",
    "design_inputs",
    "design_inputs_many",
    "gains",
    "gains_arrays",
    "pose_matrix",
    "pressure_for_bend_angle",
    "pressure_for_tip",
    "response",
    "response_arrays",
    "response_from_gains",
    "section_arrays",
    "tip_pose",
]

if __name__ != "softcath.analytic":  # the bare folder name would load a second copy of every module
    raise ImportError(
        "import softcath.analytic, not analytic: the top-level folders are rooms of the softcath package"
    )
