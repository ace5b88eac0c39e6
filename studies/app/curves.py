"""The bend curves the app draws: one per model tier, each with its tier, load and units.

The paper's formula is the cap load by definition (eq. 7 puts the pressure on
the end cap alone); the section models take the lumen load (wall and cap, the
real load). The formula and the linear section model are linear in pressure
and cost microseconds and ~15 ms; the finite-strain section model costs ~1 s
and runs in the background (:mod:`softcath.studies.app.jobs`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from softcath import analytic
from softcath.core.errors import DesignError
from softcath.fem.section_model import section_model
from softcath.fem.section_model.finite_strain import section_curve
from softcath.fem.section_model.finite_strain.newton import SectionConvergenceError
from softcath.fem.section_model.strain import silicone_strain_range
from softcath.studies.tiers import TIERS

__all__ = [
    "LOAD_NOTE",
    "TierCurve",
    "finite_strain_curve",
    "formula_curve",
    "linear_section_curve",
    "pressure_for_angle",
]

#: Each tier's load as the app states it.
LOAD_NOTE = {
    "paper": "cap load (the formula's load by definition)",
    "section": "lumen load",
    "section-nonlinear": "lumen load",
}


@dataclass(frozen=True)
class TierCurve:
    """One tier's response of one design over pressure (arrays of one length).

    Attributes
    ----------
    tier
        The tier's name (:data:`softcath.studies.tiers.TIERS`).
    load
        ``"cap"`` or ``"lumen"``.
    pressure_MPa, curvature_per_mm, elongation, bend_angle_rad, tip_x_mm, tip_y_mm
        Per pressure: p [MPa], κ [1/mm], ε [-], θ [rad], tip position [mm] (eq. 9 frame).
    max_strain
        Largest principal silicone strain [-] per pressure, or ``None`` (the formula gives none).
    gains
        (κ/p [1/(mm MPa)], ε/p [1/MPa]) of a tier linear in pressure, else ``None``.
    length_mm
        The unloaded bending length L0 [mm].
    message
        Why the curve stops short of the last pressure (empty when it does not).
    """

    tier: str
    load: str
    pressure_MPa: np.ndarray
    curvature_per_mm: np.ndarray
    elongation: np.ndarray
    bend_angle_rad: np.ndarray
    tip_x_mm: np.ndarray
    tip_y_mm: np.ndarray
    max_strain: np.ndarray | None
    gains: tuple[float, float] | None
    length_mm: float
    message: str = ""

    @property
    def label(self) -> str:
        """Legend text: tier and load, e.g. ``"section model (2-D GPS), lumen load"``."""
        return f"{TIERS[self.tier].short_label}, {self.load} load"

    def at(self, pressure: float, column: str) -> float:
        """``column`` at ``pressure`` [MPa] (interpolated; NaN outside the computed range)."""
        values = getattr(self, column)
        if values is None or self.pressure_MPa.size == 0:
            return math.nan
        p = self.pressure_MPa
        if not p[0] - 1e-12 <= pressure <= p[-1] + 1e-12:
            return math.nan
        return float(np.interp(pressure, p, values))


def _linear(
    tier: str, load: str, gains: tuple[float, float], length: float, pressures: ArrayLike, strain_gain=None
):
    r = analytic.response_from_gains(gains[0], gains[1], length, pressures)
    strain = None if strain_gain is None else np.abs(r.pressure) * strain_gain
    return TierCurve(
        tier=tier,
        load=load,
        pressure_MPa=r.pressure,
        curvature_per_mm=r.curvature,
        elongation=r.elongation,
        bend_angle_rad=r.bend_angle,
        tip_x_mm=r.tip_x,
        tip_y_mm=r.tip_y,
        max_strain=strain,
        gains=gains,
        length_mm=length,
    )


def formula_curve(design, pressures: ArrayLike) -> TierCurve:
    """The paper's formula (eq. 7) under its cap load, at ``pressures`` [MPa]."""
    gains = analytic.gains(design, "cap")
    return _linear("paper", "cap", gains, design.tip.bending_length, pressures)


def linear_section_curve(design, pressures: ArrayLike) -> TierCurve:
    """The linear section model under the lumen load, with its largest silicone strain."""
    r = section_model(design, loads=("lumen",), keep_fields=True)
    _, high = silicone_strain_range(r, "lumen")
    return _linear("section", "lumen", r.gains("lumen"), design.tip.bending_length, pressures, high)


def finite_strain_curve(
    design, pressures: ArrayLike, *, on_pressure: Callable[[int, int], None] | None = None
) -> TierCurve:
    """The finite-strain section model under the lumen load (~1 s); a curve that stops short
    (Newton fails at some pressure) is returned as far as it got, with ``message`` saying so.

    ``on_pressure(done, total)`` is called after each pressure; an exception it raises stops
    the computation (how superseded work is cancelled).
    """
    p = np.asarray(pressures, dtype=float)
    message = ""
    try:
        c = section_curve(design, p.tolist(), load="lumen", linear_gain=False, on_pressure=on_pressure)
    except SectionConvergenceError as exc:
        c = getattr(exc, "curve", None)  # the converged part
        if c is None:
            raise
        message = " ".join(str(exc).split())
    return TierCurve(
        tier="section-nonlinear",
        load="lumen",
        pressure_MPa=c.pressure,
        curvature_per_mm=c.curvature_per_mm,
        elongation=c.elongation,
        bend_angle_rad=c.bend_angle_rad,
        tip_x_mm=c.tip_x_mm,
        tip_y_mm=c.tip_y_mm,
        max_strain=c.max_strain,
        gains=None,
        length_mm=c.length_mm,
        message=message,
    )


def pressure_for_angle(curve: TierCurve, angle_rad: float) -> float:
    """Pressure [MPa] at which ``curve`` bends by ``angle_rad``: exact for a tier linear in
    pressure (θ = κ_p p L0 (1 + ε_p p)), interpolated otherwise; NaN where it never does."""
    if not math.isfinite(angle_rad) or angle_rad <= 0:
        raise DesignError("angle_rad", angle_rad, "must be a finite angle > 0 rad")
    if curve.gains is not None:
        k, e = curve.gains
        a, b = k * e * curve.length_mm, k * curve.length_mm  # a p^2 + b p = angle
        if b <= 0:
            return math.nan
        if abs(a) < 1e-15 * b:
            return angle_rad / b
        disc = b * b + 4 * a * angle_rad
        return (-b + math.sqrt(disc)) / (2 * a) if disc >= 0 else math.nan
    keep = curve.pressure_MPa > 0
    theta = np.concatenate([[0.0], curve.bend_angle_rad[keep]])
    p = np.concatenate([[0.0], curve.pressure_MPa[keep]])
    if theta.size < 2 or not np.all(np.diff(theta) > 0) or angle_rad > theta[-1]:
        return math.nan
    return float(np.interp(angle_rad, theta, p))
