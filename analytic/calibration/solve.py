"""Solving eq. 8: all multistarts in one IPOPT run, the feasible optima, the one closest to nominal.

The Opti problem stacks the starts as columns of a decision matrix and sums their
(independent) objectives, so each column converges to its own local optimum while
the solver's set-up cost is paid once; if the batch fails, the starts are solved one
at a time.
"""

from __future__ import annotations

import logging

import numpy as np

from softcath.analytic.calibration.problem import (
    SHAPE_KEYS,
    ShapeProblem,
    _inside,
    build_problem,
    fit_data,
    multistart,
)
from softcath.analytic.calibration.result import CalibrationResult, describe_fit
from softcath.core.errors import DesignError
from softcath.design import TipDesign
from softcath.design.measurement import Measurement

__all__ = ["IPOPT_OPTIONS", "calibrate"]

log = logging.getLogger(__name__)

IPOPT_OPTIONS = {
    # no "expand": the per-start block is already an SX Function, mapped over the starts; expanding
    # the Opti graph to SX costs more to build (70 ms) than it saves in evaluation
    "expand": False,
    "print_time": False,
    "ipopt.print_level": 0,
    "ipopt.sb": "yes",
    "ipopt.tol": 1e-12,
    "ipopt.acceptable_tol": 1e-10,
    "ipopt.max_iter": 300,
    # honour the bounds of X exactly: IPOPT relaxes them by 1e-8 by default
    "ipopt.bound_relax_factor": 0.0,
}


def calibrate(
    measurement: Measurement,
    design: TipDesign,
    *,
    free: tuple[str, ...] = SHAPE_KEYS,
    load: str = "cap",
    weights: tuple[float, float] | None = None,
    grid: int = 3,
    use_elongation: bool = True,
    gain_scale: tuple[float, float] = (1.0, 1.0),
) -> CalibrationResult:
    """Fit the tube shape x to a measured series (paper eq. 8).

    Parameters
    ----------
    measurement
        Pressure, curvature and (optionally) arc length over time; elongation is
        arc_length / L0 − 1 with L0 the design's bending length.
    design
        The design whose tube shape is calibrated; its current shape is the nominal one.
    free
        Which of ``("a", "a_int", "b_int", "h")`` to optimise; the others stay at the design's value.
    load
        ``"cap"`` (the paper's model) or ``"lumen"``.
    weights
        (w_ε, w_κ); default (1/Σε², 1/Σκ²), i.e. relative errors.
    grid
        Grid points per free parameter for the multistart (interior points of X).
    use_elongation
        Fit elongation too when the measurement has arc length.
    gain_scale
        (f_κ, f_ε): the model's gains are the formula's times these factors
        (Opti parameters, so a new scale costs no rebuild of the problem's
        expressions). A model whose gains differ from the formula's by
        slowly varying factors (the section model) is fitted by iterating
        on them (:func:`softcath.fem.section_model.calibration.calibrate_section`).
        All reported gains and NRMSEs include the scale.
    """
    import casadi as ca

    free, factors = _check_options(free, grid, load, gain_scale)
    data = fit_data(measurement, design, weights=weights, use_elongation=use_elongation)
    x_nom = dict(design.tube_shape)
    problem = build_problem(ca, design, free, load)
    params = (data.stats, data.weights, [x_nom[k] for k in SHAPE_KEYS], factors)
    starts = multistart(design, free, grid, problem.r_in)
    results = _feasible_optima(problem, design, solve_starts(ca, problem, starts, params), params)
    optimal, best = _closest_to_nominal(problem, x_nom, results)
    return describe_fit(
        problem=problem,
        design=design,
        measurement=measurement,
        data=data,
        load=load,
        factors=factors,
        best=best,
        n_starts=len(starts),
        n_solved=len(results),
        n_optimal=len(optimal),
    )


def _check_options(free, grid, load, gain_scale) -> tuple[tuple[str, ...], tuple[float, ...]]:
    """The free keys as a tuple and the gain factors, or a DesignError naming the bad option."""
    free = tuple(free)
    bad = [k for k in free if k not in SHAPE_KEYS]
    if bad or not free or len(set(free)) != len(free):
        raise DesignError("free", free, f"must be distinct names from {SHAPE_KEYS}")
    if not isinstance(grid, int) or not 1 <= grid <= 9:
        raise DesignError("grid", grid, "must be an integer in [1, 9]")
    if load not in ("cap", "lumen"):
        raise DesignError("load", load, "must be cap or lumen")
    factors = tuple(float(f) for f in gain_scale)
    if len(factors) != 2 or not all(np.isfinite(f) and f > 0 for f in factors):
        raise DesignError("gain_scale", gain_scale, "must be two finite factors > 0 (curvature, elongation)")
    return free, factors


def _opti_solver(ca, problem: ShapeProblem, n: int):
    """Opti over n independent starts at once: the objective is a sum of separate blocks, so
    its KKT points are each block's own; one IPOPT run pays the solver overhead once."""
    opti = ca.Opti()
    z = opti.variable(len(problem.free), n)
    st, wp, fx, sc = opti.parameter(5), opti.parameter(2), opti.parameter(4), opti.parameter(2)
    objs, res = problem.block.map(n)(z, st, wp, fx, sc)
    opti.minimize(ca.sum2(objs))
    lo, hi = ca.repmat(ca.DM(problem.lo_z), 1, n), ca.repmat(ca.DM(problem.hi_z), 1, n)
    opti.subject_to(opti.bounded(lo, z, hi))
    opti.subject_to(ca.vec(res) <= 0)
    opti.solver("ipopt", IPOPT_OPTIONS)
    return opti.to_function("calibrate_shape", [z, st, wp, fx, sc], [z])


def solve_starts(ca, problem: ShapeProblem, z0s: list[np.ndarray], params) -> list[np.ndarray | None]:
    """The scaled optimum of every start (None where its solve failed); ``params`` as the block's."""
    try:
        z_opt = np.asarray(_opti_solver(ca, problem, len(z0s))(np.column_stack(z0s), *params), float)
        return [z_opt[:, j] for j in range(len(z0s))]
    except RuntimeError as exc:  # the batch failed: solve the starts one by one
        if len(z0s) == 1:
            log.info("calibration start %s failed: %s", z0s[0], exc)
            return [None]
        single = _opti_solver(ca, problem, 1)
        out = []
        for z0 in z0s:
            try:
                out.append(np.asarray(single(z0, *params), float).ravel())
            except RuntimeError as exc1:
                log.info("calibration start %s failed: %s", z0, exc1)
                out.append(None)
        return out


def _feasible_optima(problem: ShapeProblem, design: TipDesign, z_opts, params) -> list[tuple]:
    """``(objective, shape, z)`` of every solved start whose shape lies in X."""
    x_nom = dict(design.tube_shape)
    results = []
    for z_opt in z_opts:
        if z_opt is None:
            continue
        shape = dict(x_nom)
        shape.update({k: float(v * problem.r_in) for k, v in zip(problem.free, z_opt, strict=True)})
        if not _inside(design, shape):
            continue  # never return an x outside X
        f_opt = float(problem.block(z_opt, *params)[0])
        results.append((f_opt, shape, z_opt))
    if not results:
        raise DesignError("free", problem.free, "every multistart solve failed; the data may be degenerate")
    return results


def _closest_to_nominal(problem: ShapeProblem, x_nom: dict[str, float], results: list[tuple]):
    """The optima that tie for the best objective, and among them the one closest to the nominal shape."""
    best_f = min(r[0] for r in results)
    tol = 1e-7 * max(1.0, abs(best_f)) + 1e-12
    optimal = [r for r in results if r[0] <= best_f + tol]
    free, r_in = problem.free, problem.r_in
    scale = np.array([max(abs(x_nom[k]), 0.01) for k in free])
    z_nom = np.array([x_nom[k] for k in free]) / r_in

    def distance(r):
        return float(np.sum(((r[2] - z_nom) * r_in / scale) ** 2))

    return optimal, min(optimal, key=distance)
