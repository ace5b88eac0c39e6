"""One tier's prediction band: sample, propagate, take percentiles, locate the measurement, rank
parameters."""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from softcath.design.errors import DesignError
from softcath.models import get
from softcath.studies.predict.band import measured_position, percentiles
from softcath.studies.predict.propagate import TIER_OPTIONS, propagate
from softcath.studies.predict.ranges import Range
from softcath.studies.predict.sampling import sample_values, unit_sample
from softcath.studies.predict.sensitivity import first_order

__all__ = ["TierPrediction", "predict_tier", "applicable"]


@dataclass(frozen=True)
class TierPrediction:
    """The band of one model tier (gains per MPa; see ``softcath.studies.predict`` for the JSON keys)."""

    model: str
    load: str
    samples: int
    seed: int
    feasible_samples: int
    gain_percentiles: dict[str, float]
    elongation_percentiles: dict[str, float]
    nominal_gain: float
    nominal_elongation: float
    measured_gain: float | None
    measured: dict[str, Any] | None
    sensitivity: dict
    ranges: tuple[Range, ...]
    not_applicable: tuple[str, ...]
    notes: tuple[str, ...]
    infeasible_examples: tuple[str, ...]
    seconds: float
    gains: np.ndarray = field(repr=False, compare=False)
    elongations: np.ndarray = field(repr=False, compare=False)
    values: tuple[dict[str, Any], ...] = field(repr=False, compare=False)
    options: Mapping[str, Any] = field(default_factory=dict)

    def to_json(self) -> dict:
        m = self.measured or {}
        return {
            "model": self.model,
            **({"model_options": dict(self.options)} if self.options else {}),
            "load": self.load,
            "samples": self.samples,
            "seed": self.seed,
            "feasible_samples": self.feasible_samples,
            "gain_percentiles": self.gain_percentiles,
            "elongation_percentiles": self.elongation_percentiles,
            "nominal_gain": self.nominal_gain,
            "nominal_elongation": self.nominal_elongation,
            "measured_gain": self.measured_gain,
            "measured_percentile": m.get("measured_percentile"),
            "measured_in_band": m.get("measured_in_band"),
            "measured_outside": m.get("measured_outside"),
            "measured_over_p50": m.get("measured_over_p50"),
            "sensitivity": self.sensitivity,
            "ranges": [r.to_json() for r in self.ranges],
            "not_applicable": list(self.not_applicable),
            "notes": list(self.notes),
            "infeasible_examples": list(self.infeasible_examples),
            "seconds": self.seconds,
        }


def applicable(tier: str, ranges: list[Range]) -> tuple[list[Range], list[str]]:
    """(ranges the tier can use, paths of model options it does not have)."""
    use, skip = [], []
    for r in ranges:
        if r.path.startswith("model.") and r.path.removeprefix("model.") not in TIER_OPTIONS[tier]:
            skip.append(r.path)
        else:
            use.append(r)
    return use, skip


def predict_tier(
    table: Mapping[str, Any],
    tier: str,
    ranges: list[Range],
    *,
    load: str,
    samples: int,
    seed: int,
    measured_gain: float | None = None,
    progress: bool = False,
    options: Mapping[str, Any] | None = None,
) -> TierPrediction:
    """The band of ``tier`` over a seeded Latin-hypercube sample of ``ranges`` around the base ``table``.

    ``options`` are the tier's fixed options (under the sampled ``model.*`` ranges).
    """
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
        raise DesignError("samples", samples, "must be an integer >= 1")
    t0 = time.perf_counter()
    use, skip = applicable(tier, ranges)
    unit = unit_sample(samples, len(use), seed)
    values = sample_values(unit, use)
    result = propagate(tier, table, values, load=load, progress=progress, options=options)
    if not result.feasible.any():
        raise DesignError("samples", samples, f"no feasible variant; e.g. {result.errors[0]}")
    nominal = propagate(tier, table, [{}], load=load, options=options)
    notes = []
    model = get(tier)
    for suffix, note in model.range_notes.items():  # how the tier treats a sampled parameter
        if any(r.path.endswith(suffix) for r in use):
            notes.append(note)
    if load in model.load_notes:  # what the tier's answer under this load means
        notes.append(model.load_notes[load])
    n_bad = int((~result.feasible).sum())
    if n_bad:
        notes.append(f"{n_bad} of {samples} variants infeasible (design checks) and left out")
    return TierPrediction(
        model=tier,
        load=load,
        samples=samples,
        seed=seed,
        feasible_samples=int(result.feasible.sum()),
        gain_percentiles=percentiles(result.gain),
        elongation_percentiles=percentiles(result.elongation),
        nominal_gain=float(nominal.gain[0]),
        nominal_elongation=float(nominal.elongation[0]),
        measured_gain=None if measured_gain is None else float(measured_gain),
        measured=None if measured_gain is None else measured_position(result.gain, measured_gain),
        sensitivity=first_order(unit, result.gain, [r.path for r in use], seed=seed),
        ranges=tuple(use),
        not_applicable=tuple(skip),
        notes=tuple(notes),
        infeasible_examples=result.errors,
        seconds=float(time.perf_counter() - t0),
        gains=result.gain,
        elongations=result.elongation,
        values=tuple(values),
        options=dict(options or {}),
    )
