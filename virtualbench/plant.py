"""The TRUTH plant: pressure in, tip curvature, elongation and pose out, with hidden effects.

This is the physical stand-in that the virtual bench measures and that the
hidden-effect generator (``softcath.virtualbench.hidden_effects``) hides effects in;
the effects themselves (written independently of the candidate library
``softcath.analytic.effects``) are in :mod:`softcath.virtualbench.truth_effects`.

Signal chain (fixed order, physical reading in brackets)::

    p --lag--> --dead_zone--> --nonlinear_gain--> --hysteresis--> --viscoelastic--> p_eff
    curvature = curvature_per_mpa * p_eff + offset;  elongation = elongation_per_mpa * p_eff
    every output --delay--> measured

The tip pose is the paper's eq. 9 (:func:`softcath.analytic.pose.tip_pose`).

Units: pressure MPa, time s, curvature 1/mm, lengths mm, angles rad.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from softcath import analytic
from softcath.analytic.pose import tip_pose
from softcath.core.errors import DataError, DesignError
from softcath.virtualbench.truth_effects import TruthEffect, check_range

__all__ = ["Plant", "PlantResponse"]


@dataclass(frozen=True)
class PlantResponse:
    """Noise-free tip response of the plant (arrays over the input time base)."""

    t_s: np.ndarray
    pressure_MPa: np.ndarray
    effective_pressure_MPa: np.ndarray
    curvature_per_mm: np.ndarray
    elongation: np.ndarray
    bend_angle_rad: np.ndarray
    arc_length_mm: np.ndarray
    tip_x_mm: np.ndarray
    tip_y_mm: np.ndarray


@dataclass(frozen=True)
class Plant:
    """Truth plant: linear gains of the analytic model plus hidden effects.

    Parameters
    ----------
    curvature_per_mpa
        Curvature per unit effective pressure, 1/(mm MPa).
    elongation_per_mpa
        Axial strain per unit effective pressure, 1/MPa.
    length_mm
        Unpressurised bending length L0 (mm).
    effects
        Truth effects (from :func:`make_effect`), applied in the fixed chain order
        whatever order they are given in; at most one of each name.
    """

    curvature_per_mpa: float
    elongation_per_mpa: float
    length_mm: float
    effects: tuple[TruthEffect, ...] = field(default=())

    def __post_init__(self) -> None:
        check_range("plant.curvature_per_mpa", self.curvature_per_mpa, -1e6, 1e6)
        check_range("plant.elongation_per_mpa", self.elongation_per_mpa, -1e6, 1e6)
        check_range("plant.length_mm", self.length_mm, 0.0, 1e4, lo_open=True)
        names = [e.name for e in self.effects]
        for e in self.effects:
            if not isinstance(e, TruthEffect):
                raise DesignError("plant.effects", e, "must be made by make_effect(...)")
        if len(set(names)) != len(names):
            raise DesignError("plant.effects", names, "each effect name at most once")
        ordered = tuple(sorted(self.effects, key=lambda e: e.stage))
        object.__setattr__(self, "effects", ordered)

    @classmethod
    def from_design(cls, design: Any, *, effects: tuple[TruthEffect, ...] = (), load: str = "cap") -> Plant:
        """Plant whose gains are the analytic model's response of ``design`` at 1 MPa.

        The analytic model is linear in pressure, so its response at 1 MPa is the gain.
        """
        r = analytic.response(design, np.array([1.0]), load=load)
        return cls(
            curvature_per_mpa=float(np.ravel(r.curvature)[0]),
            elongation_per_mpa=float(np.ravel(r.elongation)[0]),
            length_mm=float(design.tip.bending_length),
            effects=tuple(effects),
        )

    def simulate(self, t_s: np.ndarray, pressure_MPa: np.ndarray) -> PlantResponse:
        """Noise-free response to a pressure history.

        Parameters
        ----------
        t_s
            Strictly increasing sample times (s); uniform sampling is fastest.
        pressure_MPa
            Pressure at the catheter inlet (MPa), same length.
        """
        t = np.asarray(t_s, dtype=float)
        p = np.asarray(pressure_MPa, dtype=float)
        if t.ndim != 1 or t.shape != p.shape or t.size < 2:
            raise DataError(
                f"plant.simulate: t_s and pressure_MPa must be equal 1-D, got {t.shape} and {p.shape}"
            )
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(p))):
            raise DataError("plant.simulate: t_s and pressure_MPa must be finite")
        if np.any(np.diff(t) <= 0):
            raise DataError("plant.simulate: t_s must be strictly increasing")
        x = p.copy()
        offset = 0.0
        outputs = []
        for e in self.effects:
            if e.kind == "pressure":
                x = e.apply(t, x)
            elif e.kind == "curvature":
                offset += e.curvature_per_mm
            else:
                outputs.append(e)
        kappa = self.curvature_per_mpa * x + offset
        eps = self.elongation_per_mpa * x
        x_eff = x
        for e in outputs:
            kappa = e.apply(t, kappa)
            eps = e.apply(t, eps)
            x_eff = e.apply(t, x_eff)
        arc = self.length_mm * (1 + eps)
        tx, ty, theta = tip_pose(kappa, arc)
        return PlantResponse(
            t_s=t,
            pressure_MPa=p,
            effective_pressure_MPa=x_eff,
            curvature_per_mm=kappa,
            elongation=eps,
            bend_angle_rad=theta,
            arc_length_mm=arc,
            tip_x_mm=tx,
            tip_y_mm=ty,
        )
