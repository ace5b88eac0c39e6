"""The calibration's outcome: NRMSE, gains of data and model, reachability, identifiability, message."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcath.analytic.beam import gains_arrays
from softcath.analytic.calibration.problem import SHAPE_KEYS, FitData, ShapeProblem
from softcath.analytic.data_gain import data_gain
from softcath.analytic.section import design_inputs
from softcath.core.errors import DataError
from softcath.design import TipDesign
from softcath.design.measurement import Measurement

__all__ = ["CalibrationResult", "nrmse", "describe_fit"]


def nrmse(model: np.ndarray, data: np.ndarray) -> float:
    """Root-mean-square error normalised by the data's range (max − min)."""
    data = np.asarray(data, float)
    span = float(np.ptp(data))
    if span == 0:
        raise DataError("nrmse: the data series is constant; its range is zero")
    return float(np.sqrt(np.mean((np.asarray(model, float) - data) ** 2)) / span)


@dataclass(frozen=True, kw_only=True)
class CalibrationResult:
    """Outcome of :func:`calibrate` (mm, MPa).

    Attributes
    ----------
    x_opt, x_nominal
        Shape {a, a_int, b_int, h} after and before.
    free
        The shape parameters that were optimised.
    objective
        Eq. 8 objective at the optimum (weighted, relative).
    nrmse_nominal, nrmse_optimized
        Curvature NRMSE (range-normalised) of the nominal and optimised model.
    ratio
        nrmse_nominal / nrmse_optimized (the paper reports 20.1371).
    nrmse_elongation_nominal, nrmse_elongation_optimized
        The same for elongation, or None without arc-length data.
    gains_data, gains_model
        Least-squares gains of the data and the optimised model's gains:
        ``{"curvature_per_mm_per_MPa", "elongation_per_MPa"}``.
    gain_data_stderr, gain_data_method, gain_data_by_group
        Standard error of the data's curvature gain from the spread of per-run
        (or per-block) gains, how the groups were formed, and each group's gain
        (``softcath.analytic.data_gain``).
    reachable
        False when the model family cannot reach the data's gains inside X.
    identifiable
        True when the data determine the free parameters (locally).
    starts, starts_at_optimum
        Multistart starts tried and how many reached the best objective.
    message
        A plain statement of the outcome.
    design
        The calibrated design (the input design with x_opt as its tube shape).
    """

    x_opt: dict[str, float]
    x_nominal: dict[str, float]
    free: tuple[str, ...]
    objective: float
    nrmse_nominal: float
    nrmse_optimized: float
    ratio: float
    nrmse_elongation_nominal: float | None
    nrmse_elongation_optimized: float | None
    gains_data: dict[str, float | None]
    gains_model: dict[str, float]
    reachable: bool
    identifiable: bool
    starts: int
    starts_at_optimum: int
    message: str
    design: TipDesign
    gain_data_stderr: float | None = None
    gain_data_method: str = ""
    gain_data_by_group: dict[str, float] | None = None

    def to_json(self) -> dict:
        """The JSON document ``softcath calibrate`` writes."""
        return {
            "x_opt": self.x_opt,
            "x_nominal": self.x_nominal,
            "free": list(self.free),
            "nrmse_nominal": self.nrmse_nominal,
            "nrmse_optimized": self.nrmse_optimized,
            "ratio": self.ratio,
            "nrmse_elongation_nominal": self.nrmse_elongation_nominal,
            "nrmse_elongation_optimized": self.nrmse_elongation_optimized,
            "objective": self.objective,
            "starts": self.starts,
            "starts_at_optimum": self.starts_at_optimum,
            "gains_data": self.gains_data,
            "gains_model": self.gains_model,
            "reachable": self.reachable,
            "identifiable": self.identifiable,
            "message": self.message,
            "gain_data_uncertainty": {
                "curvature_per_mm_per_MPa_stderr": self.gain_data_stderr,
                "method": self.gain_data_method,
                "by_group": self.gain_data_by_group,
            },
            "units": {"x_opt": "mm", "gains": "per MPa"},
        }


def describe_fit(
    *,
    problem: ShapeProblem,
    design: TipDesign,
    measurement: Measurement,
    data: FitData,
    load: str,
    factors: tuple[float, float],
    best: tuple[float, dict[str, float], np.ndarray],
    n_starts: int,
    n_solved: int,
    n_optimal: int,
) -> CalibrationResult:
    """The :class:`CalibrationResult` of the chosen optimum ``best`` = (objective, shape, z)."""
    f_opt, x_opt, z_best = best
    x_nom = dict(design.tube_shape)
    p_fixed = [x_nom[k] for k in SHAPE_KEYS]
    p, kap, eps = data.p, data.kap, data.eps
    g_k_opt, g_e_opt = (float(v) for v in problem.gain_fn(z_best, p_fixed, factors))
    g_k_nom, g_e_nom = (
        float(v) * f for v, f in zip(gains_arrays(design_inputs(design), load), factors, strict=True)
    )
    n_obs = int(data.w_k > 0) + int(data.w_e > 0)
    identifiable = (
        _rank(problem, data, z_best, p_fixed, factors) == len(problem.free) and len(problem.free) <= n_obs
    )
    data_gk = data.s_pk / data.s_pp
    data_ge = data.s_pe / data.s_pp if eps is not None else None
    miss_k = abs(g_k_opt - data_gk) / max(abs(data_gk), 1e-300) if data.w_k > 0 else 0.0
    miss_e = abs(g_e_opt - data_ge) / max(abs(data_ge), 1e-300) if data.w_e > 0 and data_ge else 0.0
    reachable = max(miss_k, miss_e) <= 1e-3
    nr_nom = nrmse(g_k_nom * p, kap)
    nr_opt = nrmse(g_k_opt * p, kap)
    nre_nom = nre_opt = None
    if eps is not None and np.ptp(eps) > 0:
        nre_nom, nre_opt = nrmse(g_e_nom * p, eps), nrmse(g_e_opt * p, eps)
    dg = data_gain(measurement)
    msg = _message(
        reachable=reachable,
        gains=(g_k_opt, g_e_opt),
        data_gains=(data_gk, data_ge),
        misses=(miss_k, miss_e),
        fits_elongation=data.w_e > 0,
        counts=(n_optimal, n_solved),
    )
    msg += "; " + dg.describe()
    if not identifiable:
        msg += (
            f"; x is not identifiable from {n_obs} gain(s) with {len(problem.free)} free parameter(s): "
            "the optimum is a family, reported at the point closest to the nominal shape"
        )
    return CalibrationResult(
        x_opt=x_opt,
        x_nominal=x_nom,
        free=problem.free,
        objective=f_opt,
        nrmse_nominal=nr_nom,
        nrmse_optimized=nr_opt,
        ratio=nr_nom / nr_opt if nr_opt > 0 else float("inf"),
        nrmse_elongation_nominal=nre_nom,
        nrmse_elongation_optimized=nre_opt,
        gains_data={"curvature_per_mm_per_MPa": data_gk, "elongation_per_MPa": data_ge},
        gains_model={"curvature_per_mm_per_MPa": g_k_opt, "elongation_per_MPa": g_e_opt},
        reachable=reachable,
        identifiable=identifiable,
        starts=n_starts,
        starts_at_optimum=n_optimal,
        message=msg,
        design=design.with_tube_shape(**x_opt),
        gain_data_stderr=dg.stderr,
        gain_data_method=dg.method,
        gain_data_by_group=dg.by_group,
    )


def _rank(problem: ShapeProblem, data: FitData, z_best, p_fixed, factors) -> int:
    """Rank of d(fitted gains)/dz at the optimum (rows of the gains that carry weight)."""
    jac = np.asarray(problem.jac_fn(z_best, p_fixed, factors))
    rows = [0] if data.w_e == 0 else ([1] if data.w_k == 0 else [0, 1])
    return int(np.linalg.matrix_rank(jac[rows, :] / np.maximum(np.abs(jac[rows, :]).max(), 1e-300), tol=1e-8))


def _message(*, reachable: bool, gains, data_gains, misses, fits_elongation: bool, counts) -> str:
    """The outcome in words: the fit reaches the data's gains, or how far short it stays."""
    g_k_opt, g_e_opt = gains
    data_gk, data_ge = data_gains
    miss_k, miss_e = misses
    n_optimal, n_solved = counts
    if reachable:
        return (
            f"fit reaches the data's gains (curvature {g_k_opt:.5g} vs {data_gk:.5g} 1/(mm MPa)); "
            f"{n_optimal} of {n_solved} starts reached the best objective"
        )
    return (
        f"the shape family cannot reach the data's gains inside X: curvature gain "
        f"{g_k_opt:.5g} vs data {data_gk:.5g} 1/(mm MPa) ({100 * miss_k:.2g} % short)"
        + (
            f", elongation {g_e_opt:.5g} vs {data_ge:.5g} 1/MPa ({100 * miss_e:.2g} %)"
            if fits_elongation
            else ""
        )
        + "; this is the best constrained fit"
    )
