r"""Elongation, curvature and tip pose of the composite beam under pressure.

Two load models, always both available:

- ``load="cap"`` — the paper's model (eqs. 4 and 7): only the end-cap force
  F = p·A_p acts, at the lumen centre y_p:
  ε = p A_p / ΣEA,  κ = p A_p (y_p − ȳ) / ΣEI.
- ``load="lumen"`` — the pressure also pushes on the lumen wall. For a bonded
  section whose materials share one Poisson ratio ν, equilibrium of the
  closed-end pressurised section (Lamé, generalised to an eccentric lumen)
  multiplies both by (1 − 2ν): the wall pressure's Poisson contraction
  cancels most of the cap force. We use the tube's ν. The formula is exact for
  one bonded material (the FEM reproduces it to 0.2 %), but it does **not**
  survive confinement: in the paper's catheter the coil's hoop stiffness boxes
  the near-incompressible silicone in, and the FEM's lumen load bends the tip
  3.1× *more* than the cap-only model (154× this formula; docs/fem.md). Use
  ``"lumen"`` for unconfined sections only; for the catheter it names the
  effect (the lumen-wall load) whose size only the FEM can give.

Both are linear in p, so a design is summarised by two gains (κ/p, ε/p).
The arc length is L = L₀(1 + ε) and θ = κL (eq. 9 with L° = L(p)).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.analytic.pose import tip_pose
from softcath.analytic.section import design_inputs, section_arrays
from softcath.core.errors import DesignError
from softcath.core.limits import MAX_PRESSURE_MPA, check_pressure
from softcath.design import TipDesign
from softcath.design.load_cases import LOADS

__all__ = [
    "LOADS",
    "BeamResponse",
    "gains",
    "gains_arrays",
    "response",
    "response_arrays",
    "response_from_gains",
]


def _check_load(load: str) -> None:
    if load not in LOADS:
        raise DesignError("load", load, f"must be one of {', '.join(LOADS)}")


def gains_arrays(inp: dict, load: str = "cap") -> tuple[np.ndarray, np.ndarray]:
    """(κ/p [1/(mm MPa)], ε/p [1/MPa]) for arrays of design inputs."""
    _check_load(load)
    s = section_arrays(inp)
    factor = 1.0 if load == "cap" else 1.0 - 2.0 * np.asarray(inp["tube_nu"], float)
    k = factor * s["pressure_area"] * s["eccentricity"] / s["EI"]
    e = factor * s["pressure_area"] / s["EA"]
    return k, e


def gains(design: TipDesign, load: str = "cap") -> tuple[float, float]:
    """(κ/p [1/(mm MPa)], ε/p [1/MPa]) of one design."""
    k, e = gains_arrays(design_inputs(design), load)
    return float(k), float(e)


@dataclass(frozen=True)
class BeamResponse:
    """Analytic response at each pressure (arrays of one shape).

    Attributes
    ----------
    pressure
        p [MPa].
    curvature
        κ [1/mm], positive toward the channel side.
    elongation
        ε [-].
    arc_length
        L = L₀(1 + ε) [mm].
    bend_angle
        θ = κL [rad].
    tip_x, tip_y
        Tip position in the bending plane [mm] (eq. 9).
    """

    pressure: np.ndarray
    curvature: np.ndarray
    elongation: np.ndarray
    arc_length: np.ndarray
    bend_angle: np.ndarray
    tip_x: np.ndarray
    tip_y: np.ndarray


def _checked_pressure(pressure) -> np.ndarray:
    """``pressure`` as a float array of its own shape, within :func:`softcath.core.limits.check_pressure`."""
    p = np.asarray(pressure, dtype=float)
    # One vectorised test first: check_pressure walks the values one by one, and a batch may
    # hold a million pressures; only a refusal takes the walk (for its message).
    if not (np.all(np.isfinite(p)) and np.all(np.abs(p) <= MAX_PRESSURE_MPA)):
        check_pressure(p)
    return p


def response_from_gains(curvature_gain, elongation_gain, length, pressure) -> BeamResponse:
    """The response of a beam linear in pressure, from its gains (any model's), all broadcast together.

    Parameters
    ----------
    curvature_gain, elongation_gain
        κ/p [1/(mm MPa)] and ε/p [1/MPa].
    length
        Unloaded bending length L₀ [mm].
    pressure
        p [MPa].
    """
    p = _checked_pressure(pressure)
    kappa = np.asarray(curvature_gain, float) * p
    eps = np.asarray(elongation_gain, float) * p
    arc = np.asarray(length, float) * (1 + eps)
    tip_x, tip_y, theta = tip_pose(kappa, arc)
    return BeamResponse(p * np.ones_like(kappa), kappa, eps, arc, theta, tip_x, tip_y)


def response_arrays(inp: dict, pressure, load: str = "cap") -> BeamResponse:
    """Vectorised response: design inputs and pressures broadcast together."""
    _checked_pressure(pressure)
    k_gain, e_gain = gains_arrays(inp, load)
    return response_from_gains(k_gain, e_gain, inp["length"], pressure)


def response(design: TipDesign, pressure, load: str = "cap") -> BeamResponse:
    """Curvature, elongation and tip pose of ``design`` at ``pressure`` [MPa] (scalar or array)."""
    return response_arrays(design_inputs(design), pressure, load)
