r"""Which model ingredients explain a measured prototype: hypotheses scored by their bands.

A measured curvature-vs-pressure curve of a built design is compared with the
model's *tip-level* curvature (the prototype's circle fit spans the visible
tip, end zones included: the section model's uniform curvature times the
3-D FEM's ratio of end-face rotation to mid-span curvature, ``tip_factor``).
Each ingredient is a switch of the model:

``nu_0.4999``
    Silicone Poisson ratio 0.4999 (real rubber) instead of the design's.
``coil_resolved``
    The coils' EA and open-coil EI of the resolved wire instead of the annulus.
the as-built switches
    ``tube_coil_sliding``, ``tube_channel_sliding``, ``channel_coil_sliding``,
    ``filler_coil_sliding``, ``filler_coat``, ``filler_none``, ``tube_free``: the as-built
    options (:class:`softcath.design.assembly.Assembly`; ``tube_free``: the tube tied to the
    coil at the tip only, free at the base).
``vision_bias``
    The paper's edge pipeline reads curvature 18-40 % low: the band is
    multiplied by [0.60, 0.82].
``finite_strain``
    The finite-strain section model. The hypotheses here are not scored
    with it, so it is always skipped and the reason recorded.

A *hypothesis* is a set of ingredients (at most one per family: Poisson, coil
law, assembly, vision). Its band at pressure p is
:math:`p\,[g_\min, g_\max]` where g runs over the traced material ranges
(tube and filler moduli at their range ends, as ``softcath predict`` ranges
them). Scoring: the profile log-likelihood of the measured points under the
best gain inside the band with Gaussian noise :math:`\sigma` (the scatter of
the points about their own best line through the origin; a measured elongation
column adds its own term alike, against the elongation band),

.. math::

    \ell = -\tfrac12 \sum_i (\kappa_i - g^* p_i)^2/\sigma^2 - n \ln(\sigma\sqrt{2\pi}),

and a hypothesis *fits* when :math:`\ell_\text{best} - \ell \le 2` (the 95 %
likelihood-ratio bound for one parameter, 1.92, rounded). Ingredients are named
only when needed: the baseline (no ingredient) first; then every single
ingredient; then pairs. The smallest size at which anything fits decides; if
several hypotheses of that size fit they are reported as equally good and only
the ingredients common to all are named.
"""

from __future__ import annotations

import csv
import itertools
import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from softcath.design.errors import DataError

__all__ = ["INGREDIENTS", "FAMILIES", "hypothesis_gains", "load_prototype_csv", "explain_prototype"]

log = logging.getLogger(__name__)

FAMILIES = {
    "poisson": ("nu_0.4999",),
    "coil": ("coil_resolved",),
    "assembly": (
        "tube_coil_sliding",
        "tube_channel_sliding",
        "channel_coil_sliding",
        "filler_coil_sliding",
        "filler_coat",
        "filler_none",
        "tube_free",
    ),
    "vision": ("vision_bias",),
    "strain": ("finite_strain",),
}
INGREDIENTS = tuple(i for fam in FAMILIES.values() for i in fam)
_ASSEMBLY = {
    "tube_coil_sliding": {"tube_coil": "sliding"},
    "tube_channel_sliding": {"tube_channel": "sliding"},
    "channel_coil_sliding": {"channel_coil": "sliding"},
    "filler_coil_sliding": {"filler_coil": "sliding"},
    "filler_coat": {"filler": "coat"},
    "filler_none": {"filler": "none"},
    "tube_free": {"tube_coil": "tied-at-tip", "proximal": "tube-free"},
}
VISION = (0.60, 0.82)  # measured / true for an 18-40 % under-read
FIT_DELTA = 2.0
#: Material range ends traced (the ``softcath predict`` paper ranges of the moduli).
MODULUS_RANGES = {"tube": (1.648, 4.43), "filler": (0.069, 0.118)}


def load_prototype_csv(path: str | Path) -> dict[str, np.ndarray]:
    """Read ``pressure_MPa, curvature_per_mm[, elongation]`` (one row per measured point)."""
    path = Path(path)
    try:
        with path.open(newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
    except FileNotFoundError:
        raise DataError(f"{path}: does not exist") from None
    for col in ("pressure_MPa", "curvature_per_mm"):
        if not rows or col not in rows[0]:
            raise DataError(
                f"{path}: column {col} is required (pressure_MPa, curvature_per_mm[, elongation])"
            )
    out = {}
    for col in ("pressure_MPa", "curvature_per_mm", "elongation"):
        if col not in rows[0]:
            continue
        try:
            out[col] = np.array([float(r[col]) for r in rows])
        except ValueError as exc:
            raise DataError(f"{path}: column {col}: {exc}") from None
        if not np.all(np.isfinite(out[col])):
            raise DataError(f"{path}: column {col}: must be finite")
    if out["pressure_MPa"].size < 2:
        raise DataError(f"{path}: needs at least 2 measured points")
    return out


#: Why the ``finite_strain`` ingredient is skipped: the hypotheses' bands come from the linear
#: section model only.
_FINITE_STRAIN_SKIP = "the hypotheses' bands come from the linear section model only"


def _variant(design, ingredients: Sequence[str], e_tube: float, e_fill: float):
    a = design.assembly
    for ing in ingredients:
        if ing in _ASSEMBLY:
            a = replace(a, **_ASSEMBLY[ing])
    tube = replace(design.tube, material=replace(design.tube.material, youngs_modulus=e_tube))
    filler = design.filler
    if filler is not None:
        filler = replace(filler, youngs_modulus=e_fill)
    return replace(design, tube=tube, filler=filler, assembly=a)


def hypothesis_gains(design, ingredients: Sequence[str], *, load: str = "lumen", cache=None):
    """(curvature gains, elongation gains) of ``ingredients`` over the traced material corners."""
    from softcath.fem.section_model import section_model
    from softcath.fem.section_model.coil_models import model_options

    model = tuple(sorted(i for i in ingredients if i not in ("vision_bias",)))
    cache = {} if cache is None else cache
    if model in cache:
        return cache[model]
    opts = model_options("resolved") if "coil_resolved" in model else {}
    if "nu_0.4999" in model:
        opts["silicone_poisson"] = 0.4999
    gains, elong = [], []
    for e_t, e_f in itertools.product(MODULUS_RANGES["tube"], MODULUS_RANGES["filler"]):
        r = section_model(_variant(design, model, e_t, e_f), loads=(load,), **opts)
        gains.append(r.curvature_per_mm_per_MPa[load])
        elong.append(r.elongation_per_MPa[load])
    cache[model] = (np.array(gains), np.array(elong))
    return cache[model]


def _hypotheses(max_size: int, candidates: Sequence[str]):
    fam_of = {i: f for f, ings in FAMILIES.items() for i in ings}
    out = [()]
    for size in range(1, max_size + 1):
        for combo in itertools.combinations(candidates, size):
            if len({fam_of[i] for i in combo}) == size:
                out.append(combo)
    return out


def explain_prototype(
    design,
    measured: dict[str, np.ndarray],
    *,
    load: str = "lumen",
    tip_factor: float = 1.0,
    candidates: Sequence[str] | None = None,
    max_size: int = 2,
) -> dict:
    """Score every hypothesis against the measured points; the ``discrepancy.json`` record.

    Parameters
    ----------
    design
        The built design (a :class:`design.TipDesign`).
    measured
        From :func:`load_prototype_csv`.
    load
        Model load (``"lumen"``: the real one).
    tip_factor
        Tip-level over mid-span curvature of the baseline (1: mid-span).
    candidates
        Ingredients to try (default all available).
    max_size
        Largest number of ingredients in one hypothesis.
    """
    pts = _points(measured)
    p, k, g_free, sigma = pts.p, pts.k, pts.g_free, pts.sigma
    cands, notes = _candidates(candidates)
    hyps = _score_hypotheses(design, cands, pts, load=load, tip_factor=tip_factor, max_size=max_size)
    named, equally_good = _decide(hyps, max_size, notes)
    separate = _separating_measurement([h for h in hyps if h["ingredients"] in equally_good])
    base = hyps[0]
    return {
        "reference": "prototype",
        "named": named,
        "steps": [],
        "nrmse_before": _nrmse(k, p, base["gain_band_per_mm_MPa"], g_free),
        "nrmse_after": _nrmse(k, p, _band_of(hyps, equally_good), g_free),
        "ambiguous_with": equally_good if len(equally_good) > 1 else [],
        "noise_floor_nrmse": float(sigma / (np.ptp(k) or 1.0)),
        "notes": notes,
        "decision_rule": {
            "fit_delta_log_likelihood": FIT_DELTA,
            "text": "a hypothesis fits when its best gain inside the traced band is within "
            f"{FIT_DELTA:g} log-likelihood of the unconstrained best line; the fewest ingredients "
            "that fit decide; ingredients are named only if every equally good hypothesis has them",
        },
        "measured_gain_per_mm_MPa": g_free,
        "noise_sigma_per_mm": sigma,
        "load": load,
        "tip_factor": tip_factor,
        "equally_good": equally_good,
        "separating_measurement": separate,
        "hypotheses": hyps,
    }


def _loglik(y: np.ndarray, p: np.ndarray, g: float, sigma: float) -> float:
    """Gaussian log-likelihood of the points ``y`` about the line ``g p``."""
    r = y - g * p
    return float(-0.5 * (r @ r) / sigma**2 - p.size * math.log(sigma * math.sqrt(2 * math.pi)))


@dataclass(frozen=True)
class _Points:
    """The measured points, their unconstrained best lines, scatter and best log-likelihood."""

    p: np.ndarray
    k: np.ndarray
    g_free: float
    sigma: float
    best: float
    e: np.ndarray | None = None
    ge_free: float = math.nan
    sigma_e: float = math.nan


def _points(measured: dict[str, np.ndarray]) -> _Points:
    """Best lines through the origin and scatter of the curvature (and elongation, if measured)."""
    p = np.asarray(measured["pressure_MPa"], float)
    k = np.asarray(measured["curvature_per_mm"], float)
    g_free = float(p @ k / (p @ p))
    resid = k - g_free * p
    sigma = max(float(np.sqrt(resid @ resid / max(p.size - 1, 1))), 1e-3 * float(np.abs(k).max()))
    n = p.size
    best = _loglik(k, p, g_free, sigma)
    e = measured.get("elongation")
    if e is None:
        return _Points(p=p, k=k, g_free=g_free, sigma=sigma, best=best)
    # the elongation scored alike (its own line and scatter), added to the log-likelihood
    e = np.asarray(e, float)
    ge_free = float(p @ e / (p @ p))
    re = e - ge_free * p
    sigma_e = max(float(np.sqrt(re @ re / max(n - 1, 1))), 1e-3 * float(np.abs(e).max() or 1.0))
    best += _loglik(e, p, ge_free, sigma_e)
    return _Points(p=p, k=k, g_free=g_free, sigma=sigma, best=best, e=e, ge_free=ge_free, sigma_e=sigma_e)


def _candidates(candidates: Sequence[str] | None) -> tuple[list[str], list[str]]:
    """The ingredients to try, and the notes on those skipped."""
    notes = []
    cands = [c for c in (candidates or INGREDIENTS) if c in INGREDIENTS]
    if "finite_strain" in cands:
        cands.remove("finite_strain")
        notes.append(f"finite_strain skipped: {_FINITE_STRAIN_SKIP}")
    return cands, notes


def _score_hypotheses(design, cands, pts: _Points, *, load, tip_factor, max_size) -> list[dict]:
    """Band, best log-likelihood and fit of every hypothesis."""
    p, k, sigma = pts.p, pts.k, pts.sigma
    cache: dict = {}
    hyps = []
    for combo in _hypotheses(max_size, cands):
        gains, elong = hypothesis_gains(design, combo, load=load, cache=cache)
        lo, hi = float(gains.min()) * tip_factor, float(gains.max()) * tip_factor
        if "vision_bias" in combo:
            lo, hi = lo * VISION[0], hi * VISION[1]
        g_star = min(max(pts.g_free, lo), hi)
        ll = _loglik(k, p, g_star, sigma)
        if pts.e is not None:
            ll += _loglik(
                pts.e, p, min(max(pts.ge_free, float(elong.min())), float(elong.max())), pts.sigma_e
            )
        band = [[float(lo * pi), float(hi * pi)] for pi in p]
        covers = bool(np.all((k >= p * lo - 2 * sigma) & (k <= p * hi + 2 * sigma)))
        hyps.append(
            {
                "ingredients": list(combo),
                "gain_band_per_mm_MPa": [lo, hi],
                "elongation_band_per_MPa": [float(elong.min()), float(elong.max())],
                "band": band,
                "covers_measurement": covers,
                "log_likelihood": ll,
                "fits": bool(pts.best - ll <= FIT_DELTA),
            }
        )
    return hyps


def _decide(hyps: list[dict], max_size: int, notes: list[str]) -> tuple[list[str], list[list[str]]]:
    """The fewest ingredients that fit: (named ingredients, equally good hypotheses); notes a miss."""
    named: list[str] = []
    equally_good: list[list[str]] = []
    for size in range(0, max_size + 1):
        fit = [h for h in hyps if len(h["ingredients"]) == size and h["fits"]]
        if fit:
            equally_good = [h["ingredients"] for h in fit]
            common = set(fit[0]["ingredients"]).intersection(*[set(h["ingredients"]) for h in fit[1:]])
            named = sorted(common)
            break
    else:
        notes.append(f"no hypothesis of up to {max_size} ingredients fits the measurement")
    return named, equally_good


def _band_of(hyps, equally_good):
    if not equally_good:
        return hyps[0]["gain_band_per_mm_MPa"]
    h = next(h for h in hyps if h["ingredients"] == equally_good[0])
    return h["gain_band_per_mm_MPa"]


def _nrmse(k, p, band, g_free) -> float:
    g = min(max(g_free, band[0]), band[1])
    r = k - g * p
    return float(np.sqrt(np.mean(r**2)) / (np.ptp(k) or 1.0))


def _separating_measurement(fit: list[dict]) -> str | None:
    """What would tell equally good hypotheses apart (None when one or none fits)."""
    if len(fit) < 2:
        return None
    for a, b in itertools.combinations(fit, 2):
        ea, eb = a["elongation_band_per_MPa"], b["elongation_band_per_MPa"]
        if ea[1] < eb[0] or eb[1] < ea[0]:
            return "elongation (their elongation bands do not overlap)"
    if any("vision_bias" in h["ingredients"] for h in fit):
        return (
            "an independent curvature reading (a calibrated arc or a second camera) to settle the vision bias"
        )
    return "a blocked-tip force or a second design (their curvature and elongation bands overlap)"


def tip_level_factor(design, *, load: str = "lumen") -> float:
    """Tip-level over mid-span curvature of ``design`` from the 3-D linear FEM (bonded tip).

    The end-face rotation over the length (what a circle fit over the whole tip
    sees, end zones included) divided by the mid-span fit.
    """
    from dataclasses import replace as _replace

    from softcath import fem
    from softcath.design.assembly import Assembly

    r = fem.check(_replace(design, assembly=Assembly()), pressures=[0.1], loads=(load,))
    c = r.case(load, 0.1)
    return float(c.curvature_rotation_per_mm / c.curvature_per_mm)


def hypotheses_table(record: dict) -> list[str]:
    """Plain-text lines: each hypothesis's band against the measured gain."""
    lines = [f"measured gain {record['measured_gain_per_mm_MPa']:.4g} 1/(mm MPa) (line through the origin)"]
    for h in sorted(record["hypotheses"], key=lambda h: -h["log_likelihood"]):
        lo, hi = h["gain_band_per_mm_MPa"]
        name = " + ".join(h["ingredients"]) or "baseline (bonded, nominal ranges)"
        verdict = "fits" if h["fits"] else "cannot"
        lines.append(
            f"  {name}: band {lo:.3g}-{hi:.3g} -> {verdict} (log-likelihood {h['log_likelihood']:.1f})"
        )
    return lines
