"""``softcath predict`` as a function: resolve the ranges, run each tier, assemble prediction.json."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from softcath import design
from softcath.design.errors import DesignError
from softcath.fem.limits import check_section_budget, estimate_section_seconds
from softcath.fem.section_model.mesh import MESH_SIZE
from softcath.models import check_tier_options, get
from softcath.studies.predict.propagate import DEFAULT_LOAD, TIERS
from softcath.studies.predict.ranges import (
    Range,
    base_table,
    chosen_ranges,
)
from softcath.studies.predict.tier import TierPrediction, predict_tier
from softcath.studies.tiers import check_assembly, tier_name

__all__ = [
    "DEFAULT_SAMPLES",
    "MAX_SAMPLES",
    "MAX_SEED",
    "MAX_GAIN",
    "check_predict_inputs",
    "resolve_ranges",
    "predict",
]

#: Samples per tier unless told: the formula is free, the section model ~0.25 s, the 3-D FEM ~10 s.
DEFAULT_SAMPLES = {"paper": 4096, "section": 512, "fem": 8}
#: Most samples per tier: about an hour of work at the per-sample times above (the formula's
#: ~10 ms per variant is spent building and checking the design), and every variant is kept
#: in memory; 10⁷ formula samples grew to gigabytes.
MAX_SAMPLES = {"paper": 200_000, "section": 10_000, "fem": 256}
#: Longest estimated work of a section tier, s (10⁴ paper-sized variants take ~45 min).
MAX_WORK_SECONDS = 2 * 3600.0
#: Largest seed numpy's generators take.
MAX_SEED = 2**32 - 1
#: Largest measured gain ``|κ/p|`` [1/(mm MPa)] accepted: 10³ bends a 0.1 mm radius tip a full turn
#: per 0.06 MPa; the paper's tip reaches 0.2 and larger values are a unit error.
MAX_GAIN = 1e3


def check_predict_inputs(
    *,
    samples: int | None = None,
    fem_samples: int | None = None,
    seed: int = 0,
    measured_gain: float | None = None,
    tiers: Sequence[str] = TIERS,
) -> None:
    """Refuse sample sizes, a seed or a measured gain that cannot work, before any work.

    Raises
    ------
    DesignError
        Naming ``samples``, ``fem_samples``, ``seed`` or ``measured_gain`` with its bound.
    """
    for name, value, tier_names in (
        ("samples", samples, [t for t in tiers if not get(t).slow]),
        ("fem_samples", fem_samples, [t for t in tiers if get(t).slow]),
    ):
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise DesignError(name, value, "must be an integer >= 1")
        for tier in tier_names:
            if value > MAX_SAMPLES[tier]:
                raise DesignError(
                    name,
                    value,
                    f"must be <= {MAX_SAMPLES[tier]} for the {tier} tier "
                    f"(about an hour of work; every variant is kept in memory)",
                )
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
        raise DesignError("seed", seed, f"must be an integer in [0, {MAX_SEED}]")
    if measured_gain is not None:
        if not math.isfinite(measured_gain):
            raise DesignError("measured_gain", measured_gain, "must be finite")
        if abs(measured_gain) > MAX_GAIN:
            raise DesignError(
                "measured_gain",
                measured_gain,
                f"|gain| must be <= {MAX_GAIN:g} 1/(mm MPa) (curvature per pressure; check the units)",
            )


def resolve_ranges(
    design_ref, vary: Sequence[str] = (), ranges_file: str | Path | None = None
) -> list[Range]:
    """The ranges to vary: each ``--vary`` item, or (none given) the ranges file's defaults."""
    ranges = chosen_ranges(design_ref, base_table(design_ref), vary, ranges_file)
    if ranges is None:
        raise DesignError(
            "vary", [], f"no ranges file for design {design_ref!s}: give ranges to vary or a ranges file"
        )
    return ranges


def _check_section_work(table: dict, samples: int) -> None:
    """Refuse a section tier whose estimated time (samples x one solve of the nominal section) is too long."""

    d = design.from_dict(table)
    dofs = check_section_budget(coil_outer_radius=d.coil.outer_diameter / 2, mesh_size=MESH_SIZE)
    seconds = samples * estimate_section_seconds(dofs)
    if seconds > MAX_WORK_SECONDS:
        raise DesignError(
            "samples",
            samples,
            f"would take about {seconds / 3600:.3g} h with the section model "
            f"({dofs:.3g} DOFs per variant, ~{estimate_section_seconds(dofs):.2g} s each); at most "
            f"{MAX_WORK_SECONDS / 3600:g} h: use fewer samples",
        )


def predict(
    design_ref,
    *,
    model: str = "section",
    compare: Sequence[str] = (),
    load: str | None = None,
    vary: Sequence[str] = (),
    ranges_file: str | Path | None = None,
    samples: int | None = None,
    fem_samples: int | None = None,
    seed: int = 0,
    measured_gain: float | None = None,
    progress: bool = False,
    options: Mapping[str, Mapping[str, Any]] | None = None,
) -> tuple[dict, list[TierPrediction]]:
    """Bands of ``model`` (and the ``compare`` tiers) for a design; returns (prediction.json, tiers).

    ``load`` ``None`` gives each tier its own (cap for the paper's formula,
    lumen otherwise); ``samples`` sets the paper and section tiers'
    sample size, ``fem_samples`` the 3-D FEM's (defaults: :data:`DEFAULT_SAMPLES`).
    ``options`` (tier name -> options, :attr:`softcath.models.Tier.options`) go to those
    tiers' runs, under the sampled ``model.*`` ranges, and are recorded as ``model_options``.
    """
    model = tier_name(model, allowed=TIERS)
    compare = tuple(tier_name(name, allowed=TIERS) for name in compare)
    check_predict_inputs(
        samples=samples,
        fem_samples=fem_samples,
        seed=seed,
        measured_gain=measured_gain,
        tiers=(model, *compare),
    )
    opts = check_tier_options(options, parameter="options", tiers=(model, *compare))
    table = base_table(design_ref)
    for name in (model, *compare):
        check_assembly(name, table.get("assembly"))
    ranges = resolve_ranges(design_ref, vary, ranges_file)
    order = [model] + [t for t in TIERS if t in compare and t != model]
    for tier in order:
        if get(tier).dof_seconds:  # a section tier: its work is estimated from the section's size
            _check_section_work(table, samples or DEFAULT_SAMPLES[tier])
    tiers = []
    for tier in order:
        n = (fem_samples if get(tier).slow else samples) or DEFAULT_SAMPLES[tier]
        tiers.append(
            predict_tier(
                table,
                tier,
                ranges,
                load=load or DEFAULT_LOAD[tier],
                samples=n,
                seed=seed,
                measured_gain=measured_gain,
                progress=progress,
                options=opts.get(tier),
            )
        )
    doc = {"design": table.get("name", str(design_ref)), **tiers[0].to_json()}
    if len(tiers) > 1:
        doc["compare"] = {t.model: t.to_json() for t in tiers}
    return doc, tiers
