"""Bands of the finite-strain bend curve, and a measured curve placed in them point by point.

The linear tiers predict one gain kappa/p; at large bends the curve is not a
line, so the finite-strain section model's curve kappa(p) is sampled over the
same ranges (``softcath.studies.predict.ranges``) and each pressure gets its
own band (p5, p50, p95 of kappa and of the bend angle). A measured curve
(the measurement CSV) is compared pressure by pressure: at each model
pressure, the median of the measured curvatures within half a pressure step,
its percentile in that pressure's band, and its ratio to the p50. The
line-fit gain (the prototype's reported 0.388 mm^-1/MPa is one) is kept
beside it for comparison with the linear tiers.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from softcath.design.errors import DesignError
from softcath.fem.section_model.finite_strain import section_curve
from softcath.studies.predict.band import measured_position, percentiles
from softcath.studies.predict.finite_strain import line_fit
from softcath.studies.predict.ranges import base_table
from softcath.studies.predict.sampling import sample_values, split_overrides, unit_sample
from softcath.studies.predict.workflow import resolve_ranges
from softcath.studies.sweep.variants import VariantBuilder

__all__ = ["curve_bands", "measured_points", "MAX_CURVE_SAMPLES"]

log = logging.getLogger(__name__)

#: Samples above this are refused before any work (about a second each).
MAX_CURVE_SAMPLES = 2000


def measured_points(pressure, curvature, at: Sequence[float]) -> list[dict]:
    """Median measured curvature within half a pressure step of each pressure in ``at``.

    Returns one dict per pressure: ``pressure_MPa``, ``measured_curvature_per_mm`` (None
    when no measured point is that close) and ``points`` (how many were used).
    """
    p, k = np.asarray(pressure, float), np.asarray(curvature, float)
    keep = np.isfinite(p) & np.isfinite(k)
    p, k = p[keep], k[keep]
    at = np.asarray(at, float)
    steps = np.diff(at)
    half = 0.5 * (np.min(steps) if steps.size else max(abs(at[0]), 1e-3))
    out = []
    for q in at:
        near = np.abs(p - q) <= half
        out.append(
            {
                "pressure_MPa": float(q),
                "measured_curvature_per_mm": float(np.median(k[near])) if near.any() else None,
                "points": int(near.sum()),
            }
        )
    return out


def curve_bands(
    design_ref,
    pressures: Sequence[float],
    *,
    vary: Sequence[str] = (),
    ranges_file: str | Path | None = None,
    samples: int = 64,
    seed: int = 0,
    load: str = "lumen",
    measured=None,
    progress: bool = False,
) -> dict:
    """Per-pressure bands of the finite-strain section model's curvature and bend angle (JSON-ready).

    Parameters
    ----------
    design_ref
        Preset name or TOML path.
    pressures
        Increasing pressures [MPa], > 0.
    vary, ranges_file
        The ranges, as ``softcath predict`` takes them (default: the design's traced ranges).
    samples, seed
        Latin-hypercube sample size and seed.
    measured
        A :class:`softcath.design.measurement.Measurement` to place in the bands, or None.
    """

    p = _checked_curve_inputs(samples, pressures)
    t0 = time.perf_counter()
    table = base_table(design_ref)
    given = resolve_ranges(design_ref, vary, ranges_file)
    ranges = [r for r in given if not r.path.startswith("model.")]
    skipped = [r.path for r in given if r.path.startswith("model.")]
    values = sample_values(unit_sample(samples, len(ranges), seed), ranges) if ranges else [{}] * samples
    builder = VariantBuilder(table)
    kappa, angle, errors = _sample_curves(builder, values, p, load, progress)
    nominal = section_curve(builder.build({}), p, load=load, linear_gain=False)
    ok = np.all(np.isfinite(kappa), axis=1)
    if not ok.any():
        raise DesignError(
            "samples", samples, f"no variant converged; first reason: {errors[0] if errors else '?'}"
        )
    gains = np.array([line_fit(p, k)[0] for k in kappa[ok]])
    doc = {
        "model": "finite-strain section model",
        "load": load,
        "samples": int(samples),
        "seed": int(seed),
        "feasible_samples": int(ok.sum()),
        "ranges": [r.to_json() for r in ranges],
        "not_applicable": skipped,
        "infeasible_examples": errors[:5],
        "pressures": _pressure_points(p, kappa[ok], angle[ok], nominal.curvature_per_mm),
        "gain_line_fit_percentiles": percentiles(gains),
        "nominal_gain_line_fit": line_fit(p, nominal.curvature_per_mm)[0],
    }
    if measured is not None:
        doc["measured"] = _place(measured, p, kappa[ok])
    doc["seconds"] = float(time.perf_counter() - t0)
    log.info("curve bands: %d of %d variants in %.1f s", int(ok.sum()), samples, doc["seconds"])
    return doc


def _checked_curve_inputs(samples, pressures: Sequence[float]) -> np.ndarray:
    """The pressures as an array; :class:`DesignError` for a bad sample size or pressures that are not
    two or more increasing values > 0."""
    if not (isinstance(samples, (int, np.integer)) and 2 <= samples <= MAX_CURVE_SAMPLES):
        raise DesignError(
            "samples", samples, f"must be an integer in [2, {MAX_CURVE_SAMPLES}] for curve bands"
        )
    p = np.asarray(pressures, float)
    if p.ndim != 1 or p.size < 2 or not np.all(np.isfinite(p)) or np.any(p <= 0) or np.any(np.diff(p) <= 0):
        raise DesignError("pressures", p.tolist(), "need two or more increasing pressures > 0 MPa")
    return p


def _sample_curves(builder, values: list[dict], p: np.ndarray, load: str, progress: bool):
    """The finite-strain curve of each sampled variant: curvatures and bend angles (NaN rows where a
    variant failed) and the failure reasons."""
    from tqdm import tqdm

    kappa = np.full((len(values), p.size), np.nan)
    angle = np.full((len(values), p.size), np.nan)
    errors: list[str] = []
    for i, row in enumerate(
        tqdm(values, desc="predict curve", unit="variant", leave=False, disable=not progress)
    ):
        overrides, _ = split_overrides(row)
        try:
            c = section_curve(builder.build(overrides), p, load=load, linear_gain=False)
        except DesignError as exc:  # infeasible variant, or Newton stopped short (named pressure)
            errors.append(str(exc))
            continue
        kappa[i], angle[i] = c.curvature_per_mm, c.bend_angle_rad
    return kappa, angle, errors


def _pressure_points(p: np.ndarray, kappa: np.ndarray, angle: np.ndarray, nominal_kappa) -> list[dict]:
    """Per pressure: the percentiles of the feasible variants' curvature and bend angle, and the nominal."""
    points = []
    for j, q in enumerate(p):
        points.append(
            {
                "pressure_MPa": float(q),
                "curvature_percentiles": percentiles(kappa[:, j]),
                "bend_angle_percentiles_rad": percentiles(angle[:, j]),
                "nominal_curvature_per_mm": float(nominal_kappa[j]),
            }
        )
    return points


def _place(measured, p: np.ndarray, kappa: np.ndarray) -> dict:
    """The measured curve point by point in the bands, and its own line fit."""

    pts = measured_points(measured.pressure_MPa, measured.curvature_per_mm, p)
    for j, pt in enumerate(pts):
        m = pt["measured_curvature_per_mm"]
        if m is not None:
            pt.update(measured_position(kappa[:, j], m))
    inside = [pt["measured_in_band"] for pt in pts if pt["measured_curvature_per_mm"] is not None]
    fin = np.isfinite(measured.pressure_MPa) & np.isfinite(measured.curvature_per_mm)
    slope, intercept = line_fit(measured.pressure_MPa[fin], measured.curvature_per_mm[fin])
    return {
        "source": str(measured.source),
        "points": pts,
        "pressures_compared": len(inside),
        "pressures_in_band": int(sum(inside)),
        "gain_line_fit": slope,
        "intercept_per_mm": intercept,
    }
