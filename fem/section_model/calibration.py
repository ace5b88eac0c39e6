r"""The paper's shape calibration (eq. 8) through the section model, by space mapping.

The section model's gains are the paper's formula's gains times correction
factors that vary slowly with the tube shape x:

.. math:: \kappa_s(x) = f_\kappa(x)\,\kappa_f(x), \qquad \varepsilon_s(x) = f_\varepsilon(x)\,\varepsilon_f(x)

(f_κ ≈ 1.27 under the cap load and ≈ 3.1 under the lumen load for the paper
design). Each iteration evaluates the section model at x_k, fixes the factors
f(x_k) and solves the existing CasADi calibration (analytic.calibration,
eq. 8 with the formula's closed-form gains scaled by f, exact derivatives,
multistart) for x_{k+1}. At a fixed point x* = x_{k+1} = x_k the scaled
formula gains *are* the section model's gains at x*, so x* is the section
model's own optimum: the formula only supplies the shape dependence and its
derivatives, never the answer. Stops when x changes by less than ``tol``
(relative, with a 0.01 mm floor so h near 0 does not stall it) and the
factors used match the section model's at the new x to ``tol``, or after
``max_iterations``. The plain iteration contracts by about 0.3 per step;
Anderson mixing of depth one on the factors takes it to 1e-4 in 3-5 steps.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any

import numpy as np

from softcath import analytic
from softcath.analytic.calibration import calibrate, nrmse
from softcath.design.errors import DesignError
from softcath.fem.section_model import section_model

__all__ = ["SectionCalibration", "calibrate_section"]

log = logging.getLogger(__name__)

#: Floor of the relative change of a shape number (mm): h is often 0.
SHAPE_FLOOR_MM = 0.01
#: Relative difference of the section model's curvature gain at the result from the data's below
#: which the fit reaches the data (a result even when the shape does not settle: then the free
#: shape numbers are not identifiable from the data, and the result says so).
MATCH_TOL = 1e-3


@dataclass(frozen=True, kw_only=True)
class SectionCalibration:
    """Outcome of :func:`calibrate_section` (mm, MPa).

    Attributes
    ----------
    x_opt, x_nominal
        Shape {a, a_int, b_int, h} after and before.
    free, load
        The optimised shape parameters and the section model's load.
    iterations, converged
        Space-mapping iterations done, and whether x stopped changing (``tol``).
    history
        Per iteration: the factors (f_κ, f_ε) the inner fit used
        (``factors_used``), its shape ``x``, and the section model's ``factors``
        and ``gains`` (κ/p, ε/p) at that shape.
    gains_data, gains_model
        Least-squares gains of the data and the section model's at x_opt
        (``curvature_per_mm_per_MPa``, ``elongation_per_MPa``).
    nrmse_nominal, nrmse_optimized, ratio
        Curvature NRMSE of the section model at the nominal and calibrated
        shapes, and their ratio.
    reachable, identifiable, message
        From the last inner calibration, plus the space-mapping outcome; ``identifiable`` is
        False when the fit reaches the data but its shape did not settle.
    matches_data
        The section model's curvature gain at ``x_opt`` is the data's within :data:`MATCH_TOL`.
    inner
        The last :class:`softcath.analytic.calibration.CalibrationResult`.
    design
        The calibrated design.
    """

    x_opt: dict[str, float]
    x_nominal: dict[str, float]
    free: tuple[str, ...]
    load: str
    iterations: int
    converged: bool
    history: tuple[dict, ...]
    gains_data: dict[str, float | None]
    gains_model: dict[str, float]
    nrmse_nominal: float
    nrmse_optimized: float
    ratio: float
    reachable: bool
    identifiable: bool
    message: str
    inner: object
    design: object
    matches_data: bool = False

    @property
    def usable(self) -> bool:
        """A result to write: converged, or reaching the data with its shape not identifiable."""
        return self.converged or self.matches_data

    def to_json(self) -> dict:
        """The JSON document ``softcath calibrate --model section`` writes."""
        return {
            "model": "section",
            "load": self.load,
            "x_opt": self.x_opt,
            "x_nominal": self.x_nominal,
            "free": list(self.free),
            "iterations": self.iterations,
            "converged": self.converged,
            "history": list(self.history),
            "nrmse_nominal": self.nrmse_nominal,
            "nrmse_optimized": self.nrmse_optimized,
            "ratio": self.ratio,
            "gains_data": self.gains_data,
            "gains_model": self.gains_model,
            "reachable": self.reachable,
            "identifiable": self.identifiable,
            "matches_data": self.matches_data,
            "starts": self.inner.starts,
            "starts_at_optimum": self.inner.starts_at_optimum,
            "message": self.message,
            "units": {"x_opt": "mm", "gains": "per MPa"},
        }


def _anderson(mapped: np.ndarray, residual: np.ndarray, previous) -> tuple[float, float]:
    """Next factors: Anderson mixing of depth one on the factor map f -> f(x(f)) (else plain iteration).

    The plain iteration contracts by ~0.3 per step here (f varies slowly with
    x); mixing with the previous step extrapolates that geometric tail.
    """
    nxt = mapped
    if previous is not None:
        d_res = residual - previous[1]
        denom = float(d_res @ d_res)
        if denom > 0:
            gamma = float(residual @ d_res) / denom
            nxt = mapped - gamma * (mapped - previous[0])
    if not np.all(nxt > 0):
        nxt = mapped
    return float(nxt[0]), float(nxt[1])


def _change(new: dict, old: dict, free) -> float:
    return max(abs(new[k] - old[k]) / max(abs(old[k]), SHAPE_FLOOR_MM) for k in free)


def calibrate_section(
    measurement,
    design,
    *,
    free: tuple[str, ...] = ("a", "a_int", "b_int", "h"),
    load: str = "lumen",
    grid: int = 3,
    tol: float = 1e-4,
    max_iterations: int = 8,
    use_elongation: bool = True,
    **section_options,
) -> SectionCalibration:
    """Fit the tube shape x to a measured series through the section model (eq. 8).

    Parameters
    ----------
    measurement
        An :class:`softcath.design.measurement.Measurement` (pressure, curvature, optional arc length).
    design
        The design whose tube shape is calibrated (its shape is the nominal one).
    free, grid, use_elongation
        As :func:`softcath.analytic.calibration.calibrate`.
    load
        The section model's load: ``lumen`` (the real load, default) or ``cap``.
    tol
        Stop when no free shape number changes by more than this (relative,
        floor 0.01 mm) between iterations.
    max_iterations
        Inner calibrations at most (each followed by a section-model evaluation at its x).
    section_options
        Passed to :func:`softcath.fem.section_model.section_model` (e.g. ``mesh_size``).
    """
    _check_options(load, max_iterations, tol)
    x_nom = dict(design.tube_shape)
    gains_nominal, used = _evaluate(design, dict(x_nom), load, section_options)
    it = _iterate(
        measurement,
        design,
        dict(x_nom),
        used,
        free=free,
        load=load,
        grid=grid,
        tol=tol,
        max_iterations=max_iterations,
        use_elongation=use_elongation,
        section_options=section_options,
    )
    x, gains, inner = it.x, it.gains, it.inner
    p = np.asarray(measurement.pressure_MPa, float)
    kap = np.asarray(measurement.curvature_per_mm, float)
    nr_nom, nr_opt = nrmse(gains_nominal[0] * p, kap), nrmse(gains[0] * p, kap)
    matched = _miss(it) <= MATCH_TOL
    return SectionCalibration(
        x_opt=x,
        x_nominal=x_nom,
        free=tuple(free),
        load=load,
        iterations=len(it.history),
        converged=it.converged,
        history=tuple(it.history),
        gains_data=inner.gains_data,
        gains_model={"curvature_per_mm_per_MPa": gains[0], "elongation_per_MPa": gains[1]},
        nrmse_nominal=nr_nom,
        nrmse_optimized=nr_opt,
        ratio=nr_nom / nr_opt if nr_opt > 0 else float("inf"),
        reachable=inner.reachable,
        identifiable=inner.identifiable and it.converged,
        message=_message(load, tol, it, free),
        inner=inner,
        design=design.with_tube_shape(**x),
        matches_data=matched,
    )


def _check_options(load, max_iterations, tol) -> None:
    """Check the load, the iteration limit and the tolerance."""
    if load not in ("cap", "lumen"):
        raise DesignError("load", load, "must be cap or lumen")
    if not (isinstance(max_iterations, int) and 1 <= max_iterations <= 50):
        raise DesignError("max_iterations", max_iterations, "must be an integer in [1, 50]")
    if not (np.isfinite(tol) and tol > 0):
        raise DesignError("tol", tol, "must be > 0")


def _evaluate(design, shape: dict, load, section_options) -> tuple[tuple[float, float], tuple[float, float]]:
    """Section gains and their factors over the formula's (cap load) at ``shape``."""
    d = design.with_tube_shape(**shape)
    g = section_model(d, loads=(load,), **section_options).gains(load)
    k_f, e_f = analytic.gains(d, "cap")
    return g, (g[0] / k_f, g[1] / e_f)


@dataclass(frozen=True)
class _Iteration:
    """Where the space-mapping iteration stopped."""

    x: dict
    gains: Any
    inner: Any
    history: list
    converged: bool
    step: float
    mismatch: float


def _iterate(
    measurement, design, x, used, *, free, load, grid, tol, max_iterations, use_elongation, section_options
) -> _Iteration:
    """Alternate inner calibrations and section-model evaluations until x and the factors settle."""
    history, inner, converged, previous = [], None, False, None
    step = mismatch = np.inf
    gains = None
    for _ in range(max_iterations):
        inner = calibrate(
            measurement,
            design,
            free=free,
            load="cap",
            grid=grid,
            use_elongation=use_elongation,
            gain_scale=used,
        )
        step = _change(inner.x_opt, x, free)
        x = dict(inner.x_opt)
        gains, factors = _evaluate(design, x, load, section_options)
        history.append(
            {"x": dict(x), "factors_used": list(used), "factors": list(factors), "gains": list(gains)}
        )
        # At the answer the factors the fit used are the section model's own there.
        residual = np.subtract(factors, used)
        mismatch = float(np.max(np.abs(residual) / np.abs(factors)))
        log.info("section calibration: step %.3g, factor mismatch %.3g", step, mismatch)
        if step < tol and mismatch < tol:
            converged = True
            break
        used = _anderson(np.asarray(factors), residual, previous)
        previous = (np.asarray(factors), residual)
    return _Iteration(
        x=x, gains=gains, inner=inner, history=history, converged=converged, step=step, mismatch=mismatch
    )


def _miss(it: _Iteration) -> float:
    """Relative difference of the section model's curvature gain at the result from the data's."""
    data = it.inner.gains_data["curvature_per_mm_per_MPa"]
    return abs(it.gains[0] - data) / max(abs(data), 1e-300)


def _message(load, tol, it: _Iteration, free=()) -> str:
    """Summary line of the calibration."""
    gains, data = it.gains, it.inner.gains_data
    miss = _miss(it)
    if it.converged:
        outcome = "converged"
    elif miss <= MATCH_TOL:
        outcome = (
            f"reaches the data, shape not identified: {len(free)} free shape numbers "
            f"({', '.join(free)}) move along shapes of equal gain (last step {it.step:.2g}); "
            "x_opt is one of them, fix all but one with --free to pin it"
        )
    else:
        outcome = f"NOT converged to {tol:g} (last step {it.step:.2g}, factor mismatch {it.mismatch:.2g})"
    return (
        f"section model ({load} load), {len(it.history)} iteration(s), {outcome}"
        + f": curvature gain {gains[0]:.5g} vs data {data['curvature_per_mm_per_MPa']:.5g} 1/(mm MPa)"
        + f" ({100 * miss:.2g} % off); inner fit: {it.inner.message}"
    )
