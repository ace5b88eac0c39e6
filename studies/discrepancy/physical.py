r"""Physical hypotheses fitted to a measured curve, point by point, on the finite-strain tier.

A *hypothesis* is a set of ingredients (:mod:`.ingredients`). Its prediction
at each measured pressure p is

.. math::

    \kappa(p) = f\,\bigl(t\,\kappa_\text{FS}(p - p_0; E, \text{filler}, \nu, F_0, \dots)
    + \kappa_0\bigr)

with :math:`\kappa_\text{FS}` the finite-strain section curve (mid-span; with the
coils' initial tension F0 the model with coil-bound coils, :mod:`.model_bank`), t the
tip-level factor, p0 a pressure offset, kappa0 a rest
curvature and f the vision's under-read; an ingredient left out holds its
neutral value (the design's modulus and filler, coils without the coil-bound law,
t as given, p0 = 0, kappa0 = 0, f = 1). The hypothesis's parameters are fitted inside their
sourced ranges by bounded least squares (several starts), weighted by the
measurement noise estimated from the data (:mod:`.noise`).

It *fits* when its chi-square per degree of freedom (points - parameters) is
below the 95 % quantile of the F distribution with the noise estimate's
degrees of freedom (the noise is itself estimated from the data; with no
such estimate, the chi-square quantile). The fewest
ingredients that fit decide; all that fit at that size are equally good, and
what fits only with more ingredients is listed as not needed.

Coverage: a point is covered when it lies inside the prediction's 95 % band
(Student's t on the estimated noise); a hypothesis covers the measurement when
no more points lie outside than a 95 % band misses by chance (the binomial 95 %
quantile: 2 of 13).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares
from scipy.stats import binom, chi2, f, t

from softcath.studies.discrepancy.ingredients import INGREDIENTS, SEPARATING
from softcath.studies.discrepancy.model_bank import MODEL_PARAMETERS, TENSION, ModelBank
from softcath.studies.discrepancy.noise import NoiseEstimate, data_noise

__all__ = ["Measured", "score_hypotheses", "decide", "FIT_QUANTILE"]

FIT_QUANTILE = 0.95
#: A prediction the model cannot make (Newton stopped short) counts this many noise sigmas.
_MISS = 30.0


@dataclass(frozen=True)
class Measured:
    """The measured points and their noise."""

    pressure: np.ndarray
    curvature: np.ndarray
    noise: NoiseEstimate
    elongation: np.ndarray | None = None
    elongation_noise: NoiseEstimate | None = None

    @classmethod
    def from_columns(cls, columns: dict[str, np.ndarray]) -> Measured:
        p = np.asarray(columns["pressure_MPa"], float)
        k = np.asarray(columns["curvature_per_mm"], float)
        e = columns.get("elongation")
        if e is None:
            return cls(pressure=p, curvature=k, noise=data_noise(p, k))
        e = np.asarray(e, float)
        return cls(
            pressure=p, curvature=k, noise=data_noise(p, k), elongation=e, elongation_noise=data_noise(p, e)
        )

    @property
    def n_residuals(self) -> int:
        return self.pressure.size * (1 if self.elongation is None else 2)

    def nrmse(self, predicted: np.ndarray) -> float:
        return nrmse(predicted, self.curvature)


def nrmse(predicted: np.ndarray, measured: np.ndarray) -> float:
    """RMS of ``predicted - measured`` over the measured range (a missing prediction counts the range)."""
    span = float(np.ptp(measured))
    r = np.nan_to_num(predicted - measured, nan=span)
    return float(np.sqrt(np.mean(r**2)) / (span or 1.0))


def _parameters(ingredients: Sequence[str]) -> list[str]:
    return [i for i in ingredients if INGREDIENTS[i].parameter is not None]


def predict(bank: ModelBank, ingredients: Sequence[str], values: dict[str, float], pressure, tip_factor):
    """(curvature, elongation) of a hypothesis with parameter ``values`` at ``pressure``."""
    q = np.asarray(pressure, float) - values.get("pressure_offset", 0.0)
    filler_none = "filler_none" in ingredients
    nu = 0.4999 if "nu_0.4999" in ingredients else None
    continuous = {n: values[n] for n in (*MODEL_PARAMETERS, TENSION) if n in ingredients}
    k, e = bank.at_values(continuous, filler_none, nu, q)
    k = values.get("vision_bias", 1.0) * (tip_factor * k + values.get("rest_curvature", 0.0))
    return k, e


def _residuals(m: Measured, k: np.ndarray, e: np.ndarray) -> np.ndarray:
    r = (k - m.curvature) / m.noise.sigma
    if m.elongation is not None and m.elongation_noise is not None:
        r = np.concatenate([r, (e - m.elongation) / m.elongation_noise.sigma])
    return np.nan_to_num(r, nan=_MISS)


def _starts(bank: ModelBank, names: list[str]) -> list[np.ndarray]:
    """A few starting points inside the ranges: the centre, and each parameter near either end."""
    lo = np.array([bank.range_of(n)[0] for n in names])
    hi = np.array([bank.range_of(n)[1] for n in names])
    out = [lo + 0.5 * (hi - lo)]
    for j in range(len(names)):
        for share in (0.1, 0.9):
            x = lo + 0.5 * (hi - lo)
            x[j] = lo[j] + share * (hi[j] - lo[j])
            out.append(x)
    return out


def fit_hypothesis(bank: ModelBank, m: Measured, ingredients: Sequence[str], tip_factor: float) -> dict:
    """The best parameters of one hypothesis inside their ranges, and its record."""
    names = _parameters(ingredients)
    p = m.pressure

    def res(x):
        k, e = predict(bank, ingredients, dict(zip(names, x, strict=True)), p, tip_factor)
        return _residuals(m, k, e)

    if names:
        lo = [bank.range_of(n)[0] for n in names]
        hi = [bank.range_of(n)[1] for n in names]
        fits = [
            least_squares(res, x0, bounds=(lo, hi), method="trf", x_scale="jac")
            for x0 in _starts(bank, names)
        ]
        x = min(fits, key=lambda f: f.cost).x
    else:
        x = np.zeros(0)
    values = {n: float(v) for n, v in zip(names, x, strict=True)}
    k, e = predict(bank, ingredients, values, p, tip_factor)
    r = _residuals(m, k, e)
    chisq = float(r @ r)
    dof = max(m.n_residuals - len(names), 1)
    sigma = m.noise.sigma
    half = band_half_width(m.noise)
    covered = np.abs(np.nan_to_num(k - m.curvature, nan=np.inf)) <= half
    allowed = int(binom.ppf(FIT_QUANTILE, covered.size, 1 - FIT_QUANTILE))
    loglik = -0.5 * chisq - m.pressure.size * math.log(sigma * math.sqrt(2 * math.pi))
    return {
        "ingredients": list(ingredients),
        "parameters": {
            n: {
                "value": values[n],
                "unit": INGREDIENTS[n].unit,
                "range": list(bank.range_of(n)),
                "at_range_end": bool(any(np.isclose(values[n], e) for e in bank.range_of(n))),
                "source": bank.ingredient(n).source,
            }
            for n in names
        },
        "predicted": {
            "curvature_per_mm": [_num(v) for v in k],
            "elongation": [_num(v) for v in e],
        },
        "nrmse": m.nrmse(k),
        "chi_square": chisq,
        "dof": dof,
        "band": [[_num(v - half), _num(v + half)] for v in k],
        "covered": covered.tolist(),
        "points_outside": int(np.sum(~covered)),
        "covers_measurement": bool(np.sum(~covered) <= allowed),
        "log_likelihood": loglik,
        "fits": bool(chisq <= fit_bound(dof, m.noise.dof)),
    }


def band_half_width(noise: NoiseEstimate) -> float:
    """Half-width of a point's 95 % band: Student's t on the estimated noise (normal without one)."""
    q = 0.5 + FIT_QUANTILE / 2
    return float(noise.sigma * (t.ppf(q, noise.dof) if noise.dof > 0 else 1.959964))


def fit_bound(dof: int, noise_dof: int) -> float:
    """Largest chi-square that fits: the F quantile when the noise itself was estimated
    (its estimate has ``noise_dof`` degrees of freedom), the chi-square quantile otherwise."""
    if noise_dof > 0:
        return float(dof * f.ppf(FIT_QUANTILE, dof, noise_dof))
    return float(chi2.ppf(FIT_QUANTILE, dof))


def _num(v) -> float | None:
    return float(v) if np.isfinite(v) else None


def hypotheses(candidates: Sequence[str], max_size: int) -> list[tuple[str, ...]]:
    """The baseline, then every set of up to ``max_size`` candidates."""
    out: list[tuple[str, ...]] = [()]
    for size in range(1, max_size + 1):
        out.extend(itertools.combinations(candidates, size))
    return out


def score_hypotheses(
    bank: ModelBank, m: Measured, candidates: Sequence[str], *, max_size: int, tip_factor: float
) -> list[dict]:
    """Every hypothesis fitted and scored (the baseline first)."""
    return [fit_hypothesis(bank, m, h, tip_factor) for h in hypotheses(candidates, max_size)]


def decide(hyps: list[dict]) -> dict:
    """The fewest ingredients that fit: named, equally good, not needed, and what separates them."""
    fitting = [h for h in hyps if h["fits"]]
    if not fitting:
        return {"named": [], "equally_good": [], "also_fit": [], "separating_measurement": None}
    size = min(len(h["ingredients"]) for h in fitting)
    good = [h for h in fitting if len(h["ingredients"]) == size]
    common = set(good[0]["ingredients"]).intersection(*[set(h["ingredients"]) for h in good[1:]])
    return {
        "named": sorted(common),
        "equally_good": [h["ingredients"] for h in good],
        "also_fit": [h["ingredients"] for h in fitting if len(h["ingredients"]) > size],
        "separating_measurement": separating_measurement([h["ingredients"] for h in good]),
    }


def separating_measurement(good: list[list[str]]) -> str | None:
    """The bench measurements that tell equally good hypotheses apart (None for one or none)."""
    if len(good) < 2:
        return None
    differing = sorted(set().union(*map(set, good)) - set(good[0]).intersection(*map(set, good[1:])))
    return "; ".join(f"{i}: {SEPARATING[i]}" for i in differing)
