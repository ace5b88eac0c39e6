"""Where each load step of the 3-D finite-strain walk starts: the predictor and the first-step ramp.

:func:`predict` extrapolates the equilibria already reached to the next load factor
(``newton.solve``); :func:`first_load_steps` splits the walk's first planned step, which has
nothing to extrapolate, into a short doubling ramp (``bend.bend_curve``). Measured on the paper's
tip walked to 54° in 8 steps on 12 layers: 41 tangent factorisations against 90 with the secant
and no ramp, the same answer to 3e-11 (docs/nonlinear.md, ``benchmarks/bench_load_path.py``).
"""

from __future__ import annotations

import math

import numpy as np

from softcath.fem.nonlinear.errors import SettingError

__all__ = ["FIRST_STEP_DEG", "PREDICTORS", "check_predictor", "first_load_steps", "predict"]

#: Largest linear bend [deg] of the walk's first step (:func:`first_load_steps`).
FIRST_STEP_DEG = 2.0
#: The predictors of ``newton.solve``: the secant (two equilibria) and the quadratic (three).
PREDICTORS = ("secant", "quadratic")


def check_predictor(predictor: str) -> int:
    """How many equilibria ``predictor`` (one of :data:`PREDICTORS`) extrapolates; refuses any other name."""
    if predictor not in PREDICTORS:
        raise SettingError("predictor", predictor, f"must be one of {PREDICTORS}")
    return PREDICTORS.index(predictor) + 2


#: Largest |Lagrange weight| of the quadratic predictor; beyond it (uneven steps after cutbacks) the
#: extrapolation amplifies the equilibria's own errors and the secant is used instead. Even steps
#: give (1, −3, 3); a step doubled after a cutback (3, −8, 6); a doubling ramp's third step (8, −14, 7).
_MAX_PREDICTOR_WEIGHT = 16.0


def predict(path, target, free) -> np.ndarray:
    """Starting guess of the step from the last equilibrium of ``path`` to load factor ``target``.

    A bending tip's displacement is a rotation field, far from the tangent's linearised
    rotation: starting Newton there, the coil's stiff hoop turns the linearised-rotation
    error into large spurious stresses. Extrapolating the accepted path puts Newton inside
    its convergence radius: quadratically through the last three equilibria (the rotation's
    curvature along the path included: relative residuals of 1e-3 to 1e-1 after the
    prediction on the paper's tip, against ~1 for the secant), by the secant through two.
    A retried step (after a cutback) extrapolates as well, to its shorter target.
    """
    lam, u = path[-1]
    trial = u.copy()
    if len(path) == 1:
        return trial
    if len(path) == 3:
        lams = [p[0] for p in path]
        w = [
            np.prod([(target - lams[j]) / (lams[i] - lams[j]) for j in range(3) if j != i]) for i in range(3)
        ]
        if max(abs(x) for x in w) <= _MAX_PREDICTOR_WEIGHT:
            trial[free] = sum(wi * p[1][free] for wi, p in zip(w, path, strict=True))
            return trial
    lam_prev, u_prev = path[-2]
    trial[free] += (target - lam) / (lam - lam_prev) * (u[free] - u_prev[free])
    return trial


def first_load_steps(first_target: float, linear_angle: float) -> np.ndarray:
    """Load factors of a ramp to ``first_target``, each step at most :data:`FIRST_STEP_DEG` of linear bend.

    The path's first step has no equilibria to extrapolate from (``newton.solve``'s
    predictor) and starts from the linearised rotation, whose error grows with the
    square of the step's bend: on the paper's tip a first step of 6.7° failed after 20
    iterations, one of 1.7° converged in 7. The ramp halves ``first_target`` until its
    first step bends at most :data:`FIRST_STEP_DEG` (``linear_angle``: the linear FEM's
    bend [rad] at load factor 1) and returns the stops below it, ``first_target / 2**k, …,
    first_target / 2``, so that the doubling steps land on it (empty when no halving is
    needed).
    """
    bend_deg = abs(first_target * math.degrees(linear_angle))
    if not (math.isfinite(bend_deg) and bend_deg > FIRST_STEP_DEG):
        return np.zeros(0)
    halvings = math.ceil(math.log2(bend_deg / FIRST_STEP_DEG))
    return first_target / 2.0 ** np.arange(halvings, 0, -1)
