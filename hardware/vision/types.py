"""The vision's inputs and outputs: the image calibration and one frame's tip measurement.

Conventions of :mod:`softcath.virtualbench.render`: mm relative to the base, x right, y up;
positive curvature turns clockwise in the image.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from softcath.core.errors import DesignError

__all__ = ["Calibration", "TipMeasurement", "METHODS"]

METHODS = ("default", "paper")


@dataclass(frozen=True)
class Calibration:
    """Image scale and (optionally) base pose.

    Parameters
    ----------
    px_per_mm
        Image scale in the bending plane, px/mm.
    base_px
        Base position ``(u, v)`` in pixels, origin top-left, v down; None: find it.
    base_angle_deg
        Base direction, counter-clockwise from the image +x axis, degrees (90: up).
    diameter_mm
        Expected tube diameter, mm (sets profile lengths and width checks).
    """

    px_per_mm: float
    base_px: tuple[float, float] | None = None
    base_angle_deg: float = 90.0
    diameter_mm: float = 0.8

    def __post_init__(self) -> None:
        if not (math.isfinite(self.px_per_mm) and self.px_per_mm > 0):
            raise DesignError("px_per_mm", self.px_per_mm, "must be a finite number > 0")
        if not (math.isfinite(self.base_angle_deg)):
            raise DesignError("base_angle_deg", self.base_angle_deg, "must be finite")
        if not self.diameter_mm * self.px_per_mm >= 3:
            raise DesignError(
                "px_per_mm",
                self.px_per_mm,
                f"must resolve the {self.diameter_mm} mm tube with >= 3 px "
                f"(>= {3 / self.diameter_mm:.3g} px/mm)",
            )


@dataclass(frozen=True)
class TipMeasurement:
    """One frame's result; ``ok`` is False (and numbers NaN) when no tip was found."""

    ok: bool
    curvature_per_mm: float = float("nan")
    arc_length_mm: float = float("nan")
    bend_angle_rad: float = float("nan")
    tip_x_mm: float = float("nan")
    tip_y_mm: float = float("nan")
    base_px: tuple[float, float] | None = None
    base_angle_deg: float = float("nan")
    tip_px: tuple[float, float] | None = None
    points_px: np.ndarray | None = None
    edges_px: np.ndarray | None = None
    circle_px: tuple[float, float, float] | None = None
    reason: str = ""

    def row(self) -> dict[str, float]:
        """The measurement-CSV columns of this frame."""
        return {
            "curvature_per_mm": self.curvature_per_mm,
            "arc_length_mm": self.arc_length_mm,
            "bend_angle_rad": self.bend_angle_rad,
            "tip_x_mm": self.tip_x_mm,
            "tip_y_mm": self.tip_y_mm,
        }
