"""Inverse kinematics of the analytic model: the pressure for a target bend or tip position."""

from __future__ import annotations

import numpy as np
from scipy import optimize

from softcath.analytic.beam import gains, response
from softcath.core.errors import DesignError
from softcath.design import TipDesign

__all__ = ["pressure_for_angle_of_gains", "pressure_for_bend_angle", "pressure_for_tip"]


def pressure_for_bend_angle(design: TipDesign, angle_rad, *, load: str = "cap") -> np.ndarray:
    """Pressure [MPa] at which the tip bends by ``angle_rad``.

    θ(p) = κ_p L₀ p (1 + ε_p p) is quadratic in p; the smallest root with the
    sign of θ is taken in the cancellation-free form p = 2θ / (α + √(α² + 4βθ)).
    """
    k, e = gains(design, load)
    return pressure_for_angle_of_gains(k, e, angle_rad, length=design.tip.bending_length, name=design.name)


def pressure_for_angle_of_gains(k: float, e: float, angle_rad, *, length: float, name=None) -> np.ndarray:
    """Pressure [MPa] at which a tip of gains ``k`` [1/(mm MPa)], ``e`` [1/MPa] and ``length`` [mm] bends
    by ``angle_rad`` (see :func:`pressure_for_bend_angle`; ``name`` names the design in a refusal)."""
    theta = np.asarray(angle_rad, dtype=float)
    if k == 0:
        raise DesignError("design", name, "has zero bending gain (symmetric section): no pressure bends it")
    alpha = k * length
    beta = alpha * e
    disc = alpha**2 + 4 * beta * theta
    if np.any(disc < 0):
        raise DesignError("angle_rad", float(np.min(theta)), "is not reachable at any pressure")
    return 2 * theta / (alpha + np.sign(alpha) * np.sqrt(disc))


def pressure_for_tip(
    design: TipDesign,
    *,
    tip_x: float,
    tip_y: float | None = None,
    load: str = "cap",
    max_pressure: float = 50.0,
) -> tuple[float, float]:
    """Pressure [MPa] that brings the tip closest to (tip_x, tip_y) [mm].

    With only ``tip_x`` (lateral reach) the pressure matching it exactly is
    found by bracketing on the rising branch (θ ≤ π); with both coordinates
    the distance is minimised. Returns (pressure, remaining distance [mm]).
    The search stays below ``max_pressure`` [MPa].
    """

    def dist(p: float) -> float:
        r = response(design, p, load)
        dy = 0.0 if tip_y is None else float(r.tip_y) - tip_y
        return float(np.hypot(float(r.tip_x) - tip_x, dy))

    p_pi = float(pressure_for_bend_angle(design, np.pi * np.sign(tip_x or 1.0), load=load))
    hi = min(abs(p_pi), max_pressure) * np.sign(p_pi)
    if tip_y is None:
        x_hi = float(response(design, hi, load).tip_x)
        if abs(tip_x) > abs(x_hi):
            raise DesignError("tip_x", tip_x, f"exceeds the reach {x_hi:.4g} mm at p = {hi:.4g} MPa")
        p = optimize.brentq(lambda q: float(response(design, q, load).tip_x) - tip_x, 0.0, hi, xtol=1e-12)
        return float(p), dist(p)
    res = optimize.minimize_scalar(dist, bounds=sorted((0.0, hi)), method="bounded", options={"xatol": 1e-10})
    return float(res.x), float(res.fun)
