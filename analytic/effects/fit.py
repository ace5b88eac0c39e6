"""Fit the model plus a chain of candidate effects to filtered data (variable projection).

The model curvature is ``gain * chain(p)`` plus linear terms of ``column``
effects, shifted by ``output`` effects and then passed through the SAME
low-pass filter as the data (``output_filter``: an unfiltered model against
filtered data makes the filter's delay look like a missing delay). The gain and other linear
coefficients are solved exactly for every trial of the nonlinear parameters
(variable projection), the nonlinear ones by bounded least squares from a few
starts.

Uncertainties: residuals of low-passed data are strongly autocorrelated, so
the usual ``s^2 (J^T J)^-1`` is inflated by ``n / n_eff`` with ``n_eff`` the
number of independent samples the caller states (about ``2 B T`` for a
bandwidth B over a duration T).
"""

from __future__ import annotations

import functools
import itertools
import logging
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from softcath.analytic.effects import get
from softcath.analytic.effects.base import STAGE_ORDER, Scales
from softcath.core.errors import DesignError

__all__ = ["Segment", "ChainFit", "fit_chain", "predict_chain", "simulate_columns"]

log = logging.getLogger(__name__)

Filter = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Segment:
    """One uniformly sampled stretch of data (a run, or a block of cycles).

    Parameters
    ----------
    dt_s
        Sample interval (s).
    pressure_MPa
        Model input: the measured pressure, denoised but not band-limited to the
        data filter (MPa).
    target
        The filtered measured curvature (1/mm); same length.
    mask
        Samples that count in fits and scores (filter edge transients trimmed).
    label
        Run name, for reports.
    """

    dt_s: float
    pressure_MPa: np.ndarray
    target: np.ndarray
    mask: np.ndarray
    label: str = ""


@dataclass(frozen=True)
class ChainFit:
    """Fitted model + effects: parameter values and 1-sigma uncertainties.

    ``params[effect][name]`` are the nonlinear physical parameters; ``gain`` is
    the calibrated curvature per unit effective pressure (1/(mm MPa));
    ``coefficients[effect]`` the linear coefficient of each column effect.
    """

    effects: tuple[str, ...]
    params: dict[str, dict[str, float]]
    stderr: dict[str, dict[str, float]]
    gain: float
    gain_stderr: float
    coefficients: dict[str, float]
    coefficient_stderr: dict[str, float]
    rmse: float
    fixed_gain: bool = False
    context: dict[str, float] = field(default_factory=dict)

    def as_dict(self) -> dict[str, object]:
        """Plain JSON-ready record."""
        return {
            "effects": list(self.effects),
            "params": self.params,
            "stderr": self.stderr,
            "gain_per_mm_MPa": self.gain,
            "gain_stderr": self.gain_stderr,
            "coefficients": self.coefficients,
            "coefficient_stderr": self.coefficient_stderr,
            "train_rmse_per_mm": self.rmse,
            "gain_fixed": self.fixed_gain,
        }


def _ordered(effects: Sequence[str]) -> tuple[str, ...]:
    for e in effects:
        get(e)  # raises on an unknown name
    if len(set(effects)) != len(effects):
        raise DesignError("effects", list(effects), "each effect at most once")
    return tuple(sorted(effects, key=STAGE_ORDER.index))


def simulate_columns(
    effects: Sequence[str],
    params: Mapping[str, Mapping[str, float]],
    dt_s: float,
    pressure_MPa: np.ndarray,
    context: Mapping[str, float] | None = None,
) -> tuple[np.ndarray, list[str]]:
    """Unfiltered regressors of the chain: the effective pressure and column terms.

    Returns the matrix (samples x columns) and the column names (``"gain"``
    first, then each column effect); the output is ``columns @ coefficients``.
    """
    ctx = dict(context or {})
    x = np.asarray(pressure_MPa, dtype=float)
    p = x
    cols, names = [], []
    outputs = []
    for name in _ordered(list(effects)):
        cand = get(name)
        if cand.kind == "pressure":
            x = cand.apply(dt_s, x, **params.get(name, {}))
        elif cand.kind == "column":
            cols.append(cand.column(dt_s, p, **ctx))
            names.append(name)
        else:
            outputs.append(cand)
    cols.insert(0, x)
    names.insert(0, "gain")
    for cand in outputs:
        cols = [cand.apply(dt_s, c, **params.get(cand.name, {})) for c in cols]
    return np.column_stack(cols), names


def _filtered_design(effects, params, segments, output_filter, context):
    blocks, targets = [], []
    for s in segments:
        cols, names = simulate_columns(effects, params, s.dt_s, s.pressure_MPa, context)
        f = output_filter(cols)  # the filter works along axis 0, column by column
        blocks.append(f[s.mask])
        targets.append(s.target[s.mask])
    return np.vstack(blocks), np.concatenate(targets), names


def _solve(phi, y, fixed_gain):
    """Linear coefficients; with a fixed gain the first column is known."""
    if fixed_gain is not None:
        rest = y - fixed_gain * phi[:, 0]
        if phi.shape[1] == 1:
            return np.array([fixed_gain]), rest
        c, *_ = np.linalg.lstsq(phi[:, 1:], rest, rcond=None)
        return np.concatenate([[fixed_gain], c]), rest - phi[:, 1:] @ c
    c, *_ = np.linalg.lstsq(phi, y, rcond=None)
    return c, y - phi @ c


def fit_chain(
    effects: Sequence[str],
    segments: Sequence[Segment],
    *,
    output_filter: Filter,
    scales: Scales,
    fixed_gain: float | None = None,
    context: Mapping[str, float] | None = None,
    start: Mapping[str, Mapping[str, float]] | None = None,
    n_eff: float | None = None,
    max_nfev: int = 40,
) -> ChainFit:
    """Fit gain, column coefficients and every nonlinear parameter of a chain.

    Parameters
    ----------
    effects
        Candidate names (any order; evaluated in ``STAGE_ORDER``). Empty: gain only.
    segments
        Training data.
    output_filter
        The low-pass applied to the data; applied to every model column (it must
        filter along axis 0 and accept 1-D and 2-D arrays).
    scales
        Data scales that make the parameter bounds absolute.
    fixed_gain
        Curvature gain 1/(mm MPa) to hold fixed (FEM reference: the design is known,
        so the gain is not calibrated); None fits it.
    context
        Extra numbers column effects need (``lumen_minus_cap_gain_per_mm_MPa``).
    start
        Starting values for some effects' parameters (e.g. from the previous step);
        effects without one are started from their ``starts`` grid.
    n_eff
        Effective number of independent samples for the uncertainties (default: n).
    max_nfev
        Cap on model evaluations of the local refinement.
    """
    effects = _ordered(list(effects))
    ctx = dict(context or {})
    start = start or {}
    free = [(e, q) for e in effects for q in get(e).params]
    resid = functools.partial(
        _residual,
        effects=effects,
        free=free,
        scales=scales,
        segments=segments,
        output_filter=output_filter,
        ctx=ctx,
        fixed_gain=fixed_gain,
    )
    z, best = _fit_nonlinear(resid, free, start, scales, max_nfev)
    params = _unpack(effects, free, z, scales)
    phi, y, names = _filtered_design(effects, params, segments, output_filter, ctx)
    coef, res = _solve(phi, y, fixed_gain)
    lin_se, stderr = _uncertainties(
        effects, free, z, best, phi, res, fixed_gain=fixed_gain, n_eff=n_eff, scales=scales
    )
    gain_se = 0.0 if fixed_gain is not None else float(lin_se[0])
    col_se = lin_se if fixed_gain is not None else lin_se[1:]
    coefficients = {nm: float(c) for nm, c in zip(names[1:], coef[1:], strict=True)}
    coef_se = {nm: float(s) for nm, s in zip(names[1:], col_se, strict=True)}
    return ChainFit(
        effects=effects,
        params={e: v for e, v in params.items() if v},
        stderr={e: v for e, v in stderr.items() if v},
        gain=float(coef[0]),
        gain_stderr=gain_se,
        coefficients=coefficients,
        coefficient_stderr=coef_se,
        rmse=float(np.sqrt(np.mean(res**2))),
        fixed_gain=fixed_gain is not None,
        context=ctx,
    )


def _unpack(effects, free, z, scales) -> dict[str, dict[str, float]]:
    """Physical parameter values of every effect from the unit-box vector ``z``."""
    out: dict[str, dict[str, float]] = {e: {} for e in effects}
    for (e, q), zi in zip(free, z, strict=True):
        out[e][q.name] = q.to_value(float(zi), scales)
    return out


def _residual(z, *, effects, free, scales, segments, output_filter, ctx, fixed_gain) -> np.ndarray:
    """Residual of the variable-projection fit at the nonlinear parameters ``z``."""
    phi, y, _ = _filtered_design(effects, _unpack(effects, free, z, scales), segments, output_filter, ctx)
    return _solve(phi, y, fixed_gain)[1]


def _fit_nonlinear(resid, free, start, scales, max_nfev):
    """Best start of the grid refined by bounded least squares; returns (z, least-squares result)."""
    if not free:
        return np.zeros(0), None
    grids = []
    for e, q in free:
        if e in start and q.name in start[e]:
            grids.append((q.to_unit(start[e][q.name], scales),))
        else:
            grids.append(get(e).starts)
    # scan the start grid with one evaluation each, then refine the best start:
    # far cheaper than a full local search from every start, and the grid is
    # dense enough (4-5 points per parameter) to land in the right basin
    z0 = min(
        (np.array(z, dtype=float) for z in itertools.product(*grids)),
        key=lambda z: float(np.sum(resid(z) ** 2)),
    )
    best = least_squares(
        resid, z0, bounds=(0.0, 1.0), diff_step=1e-4, x_scale=1.0, max_nfev=max_nfev, xtol=1e-6, ftol=1e-8
    )
    return best.x, best


def _uncertainties(effects, free, z, best, phi, res, *, fixed_gain, n_eff, scales):
    """1-sigma errors: of the linear coefficients (array) and of the nonlinear parameters (dict)."""
    n = res.size
    k = len(free) + phi.shape[1] - (fixed_gain is not None)
    inflate = n / n_eff if n_eff else 1.0
    s2 = float(res @ res) / max(n - k, 1)
    # linear coefficients: s^2 (Phi^T Phi)^-1, inflated for autocorrelation
    lin_cols = phi if fixed_gain is None else phi[:, 1:]
    cov_lin = np.linalg.pinv(lin_cols.T @ lin_cols) * s2 * inflate if lin_cols.shape[1] else None
    lin_se = np.sqrt(np.diag(cov_lin)) if cov_lin is not None else np.zeros(0)
    stderr: dict[str, dict[str, float]] = {e: {} for e in effects}
    if free:
        jac = best.jac
        cov_z = np.linalg.pinv(jac.T @ jac) * s2 * inflate
        for i, (e, q) in enumerate(free):
            zi = float(z[i])
            h = 1e-6
            dv = (q.to_value(min(zi + h, 1.0), scales) - q.to_value(max(zi - h, 0.0), scales)) / (
                min(zi + h, 1.0) - max(zi - h, 0.0)
            )
            stderr[e][q.name] = float(abs(dv) * np.sqrt(max(cov_z[i, i], 0.0)))
    return lin_se, stderr


def predict_chain(fit: ChainFit, segment: Segment, *, output_filter: Filter) -> np.ndarray:
    """Filtered model curvature (1/mm) of a fitted chain on one segment (all samples)."""
    cols, names = simulate_columns(fit.effects, fit.params, segment.dt_s, segment.pressure_MPa, fit.context)
    coef = np.array([fit.gain] + [fit.coefficients[n] for n in names[1:]])
    return output_filter(cols @ coef)
