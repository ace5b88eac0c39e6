"""The tip vision's former module path: re-exports :mod:`softcath.hardware.vision`.

Kept so that ``from softcath.hardware.tipvision import Calibration, measure`` keeps working.
"""

from __future__ import annotations

from softcath.hardware.vision import (
    METHODS,
    Calibration,
    TipMeasurement,
    draw_overlay,
    find_red_tip,
    measure,
    track_centre_line,
)

__all__ = [
    "Calibration",
    "TipMeasurement",
    "measure",
    "draw_overlay",
    "METHODS",
    "find_red_tip",
    "track_centre_line",
]
