"""The records of a workflow run: per named step, the calibration, the filter, the runs, the notes.

Plain dicts and tuples for :class:`~softcath.studies.discrepancy.workflow.DiscrepancyResult`
(and so for ``discrepancy.json``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from softcath.analytic.effects import get
from softcath.analytic.effects.fit import ChainFit
from softcath.studies.discrepancy.naming import RATE_FAMILY, Step
from softcath.studies.discrepancy.prepare import Prepared

__all__ = [
    "excess",
    "step_records",
    "decision_notes",
    "separability_notes",
    "calibration_record",
    "filter_record",
    "run_records",
    "candidate_table",
]


def excess(before: float, after: float, floor: float) -> float:
    """Share of the excess error power above ``floor`` removed: (before² − after²)/(before² − floor²)."""
    den = before**2 - floor**2
    if den <= 0:
        return 0.0
    return float(np.clip((before**2 - after**2) / den, -1.0, 1.0))


def step_records(steps: Sequence[Step], floor: float) -> tuple[list[dict], list[str]]:
    """One record per named step, and the notes they call for (joint naming, loose parameters, ambiguity)."""
    records: list[dict] = []
    notes: list[str] = []
    for s in steps:
        if s.named is None:
            continue
        sc = s.candidates[s.named]
        records.append(
            {
                "effect": s.named,
                "meaning": get(s.named).meaning,
                "params": s.fit.params.get(s.named, {}),
                "params_stderr": s.fit.stderr.get(s.named, {}),
                "coefficient": s.fit.coefficients.get(s.named),
                "coefficient_stderr": s.fit.coefficient_stderr.get(s.named),
                "nrmse_before": s.baseline.nrmse,
                "nrmse_after": sc.nrmse,
                "excess_removed": excess(s.baseline.rmse_per_mm, sc.rmse_per_mm, floor),
                "ambiguous_with": list(s.ambiguous_with),
                "separating_experiment": s.separating_experiment,
            }
        )
        notes += _step_notes(s, len(records))
    return records, notes


def _step_notes(s: Step, n: int) -> list[str]:
    """The notes of the ``n``-th named step."""
    notes = []
    if s.extra.get("joint_with") and s.baseline is not s.candidates[s.named]:
        notes.append(
            f"step {n}: {s.named} and {s.extra['joint_with']} were named together: "
            "neither alone cleared the margin, both together do (their signatures partly cancel)"
        )
    for k, v in s.fit.params.get(s.named, {}).items():
        se = s.fit.stderr.get(s.named, {}).get(k)
        if se is not None and math.isfinite(se) and se >= abs(v):
            notes.append(
                f"step {n}: the data do not pin {s.named}'s {k} "
                f"({v:.3g} ± {se:.2g}): its size is uncertain, only its presence is supported"
            )
    if s.ambiguous_with:
        notes.append(
            f"step {n}: the data cannot tell {s.named} from "
            f"{', '.join(s.ambiguous_with)}"
            + (f"; to separate them, {s.separating_experiment}" if s.separating_experiment else "")
        )
    return notes


def decision_notes(
    steps: Sequence[Step], named: tuple[str, ...], min_share: float, floor: float
) -> list[str]:
    """Notes on the stop: candidates held back by ``min_share``, or nothing named at all."""
    notes = []
    for c, sh in steps[-1].extra.get("below_min_share", {}).items():
        gain = 1 - steps[-1].candidates[c].rmse_per_mm / steps[-1].baseline.rmse_per_mm
        notes.append(
            f"{c} would lower the held-out RMSE by a further {gain:.0%} but removes only "
            f"{sh:.2%} of the original excess error power (< {min_share:.0%}): read as the "
            "named effects' form error, not as another missing effect"
        )
    if not named:
        notes.append(
            "no candidate beat the calibrated model by the margin on held-out data: "
            + ("nothing is missing at this noise level" if floor > 0 else "none is supported by these points")
        )
    return notes


def separability_notes(prep: Prepared, named: tuple[str, ...]) -> list[str]:
    """A note when one excitation cannot separate the rate family among the named effects."""
    if prep.distinct_frequencies() < 2 and not prep.static and set(named) & set(RATE_FAMILY):
        return [
            "one excitation only: rate-independent hysteresis, lag, delay and creep "
            "are not separable from these data (see the separating experiment)"
        ]
    return []


def calibration_record(
    baseline_fit: ChainFit,
    final_fit: ChainFit,
    *,
    fixed_gain: float | None,
    nominal: float | None,
    shape_cal: dict | None,
) -> dict:
    """How the model's gain was calibrated, and the eq. 8 shape optimisation for the record."""
    calib = {
        "used": "explicit gain: least squares on the filtered series (refitted in every model)"
        if fixed_gain is None
        else "none: gain fixed to the design's analytic cap-load gain",
        "gain_per_mm_MPa": baseline_fit.gain,
        "gain_stderr": baseline_fit.gain_stderr,
        "final_gain_per_mm_MPa": final_fit.gain,
    }
    if nominal is not None:
        calib["nominal_gain_per_mm_MPa"] = nominal
        calib["gain_over_nominal"] = baseline_fit.gain / nominal if nominal else None
    if shape_cal is not None:
        calib["shape_optimisation"] = shape_cal
        g_shape = shape_cal.get("gains_model", {}).get("curvature_per_mm_per_MPa")
        if g_shape:
            # the explicit gain is what the workflow relies on; this says how far the
            # shape family alone got
            calib["explicit_gain_over_shape_gain"] = baseline_fit.gain / g_shape
    elif fixed_gain is None:
        calib["shape_optimisation"] = "not run (no design given)"
    return calib


def filter_record(prep: Prepared) -> dict:
    """The data filter (applied to data and model output alike), or none for quasi-static points."""
    if prep.static:
        return {"family": "none (quasi-static reference)"}
    return {
        "family": prep.data_filter.family,
        "passband_hz": prep.data_filter.passband_hz,
        "stopband_hz": prep.data_filter.stopband_hz,
        "ripple_db": prep.data_filter.ripple_db,
        "attenuation_db": prep.data_filter.attenuation_db,
        "decimated_rate_hz": prep.fs_hz,
        "applied_to": "data and model output alike (zero-phase)",
    }


def run_records(prep: Prepared) -> tuple[dict, ...]:
    """One record per run of the data: label, kind, frequency, duration, noise."""
    return tuple(
        {
            "run": r.label,
            "kind": r.kind,
            "frequency_hz": r.frequency_hz,
            "duration_s": r.duration_s,
            "noise_sd_per_mm": r.noise_sd_per_mm,
        }
        for r in prep.runs
    )


def candidate_table(steps: Sequence[Step]) -> tuple[dict, ...]:
    """Per step: candidate -> held-out NRMSE, and the current model's as ``(current)``."""
    return tuple(
        {c: sc.nrmse for c, sc in s.candidates.items()} | {"(current)": s.baseline.nrmse} for s in steps
    )
