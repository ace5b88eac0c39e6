"""Evaluate a batch of candidate designs: nominal, or robustly over material/manufacturing ranges.

Nominal: one model run per candidate. Robust: every candidate is combined
with the same seeded Latin-hypercube sample of the uncertain parameters
(:mod:`softcath.studies.predict` ranges; common random numbers, so candidates
are compared on equal terms); objectives are then the sample's p50 and a
constraint's margin the (1 − P) quantile of its per-sample margins, which is
≥ 0 exactly when the constraint holds with probability ≥ P.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from softcath import design
from softcath.design.errors import DesignError
from softcath.fem.limits import check_section_budget
from softcath.fem.section_model.mesh import MESH_SIZE
from softcath.models import get
from softcath.studies.criteria import check_columns
from softcath.studies.model_validity import fail_self_contact
from softcath.studies.optimise.backend import Backend
from softcath.studies.optimise.problem import Problem
from softcath.studies.optimise.scoring import score_table
from softcath.studies.predict.sampling import sample_values, unit_sample
from softcath.studies.sweep.results import add_derived_columns, model_columns

__all__ = [
    "MAX_ROBUST_SAMPLES",
    "MAX_WORK_SECONDS",
    "Robustness",
    "Scores",
    "check_work",
    "estimate_run_seconds",
    "evaluate_parameters",
    "make_robustness",
]

#: Most robust samples per candidate (as ``predict``'s section tier: every variant is built and
#: kept in memory; 10⁹ would never finish drawing the sample).
MAX_ROBUST_SAMPLES = 10_000
#: Longest estimated work of an optimisation or a robust selection, s (``predict``'s bound).
MAX_WORK_SECONDS = 2 * 3600.0
#: One formula run, s: building and checking the variant's design dominates (``predict``: ~10 ms).
_FORMULA_SECONDS = 0.01


def estimate_run_seconds(model: str, base_table: dict, *, mesh_size: float | None = None) -> float:
    """Estimated seconds of one model run of the base design (the section tiers by its section's DOFs).

    A tier's :attr:`~softcath.models.Tier.dof_seconds` is its cost per estimated section DOF
    (0 for a closed form, which costs building the design: :data:`_FORMULA_SECONDS`).

    Raises
    ------
    DesignError
        From :func:`softcath.fem.limits.check_section_budget` when one section does not fit at all.
    """
    per_dof = get(model).dof_seconds
    if not per_dof:
        return _FORMULA_SECONDS

    d = design.from_dict(base_table)
    h = MESH_SIZE if mesh_size is None else mesh_size
    dofs = check_section_budget(coil_outer_radius=d.coil.outer_diameter / 2, mesh_size=h)
    return _FORMULA_SECONDS + per_dof * dofs


def check_work(model: str, base_table: dict, runs: int, *, param: str, value, mesh_size=None) -> float:
    """Refuse ``runs`` model runs whose estimated time is above :data:`MAX_WORK_SECONDS`; return it.

    ``param`` and ``value`` name the input that set the count (``budget``, ``samples``).
    """
    each = estimate_run_seconds(model, base_table, mesh_size=mesh_size)
    seconds = runs * each
    if seconds > MAX_WORK_SECONDS:
        raise DesignError(
            param,
            value,
            f"{runs} {model}-model runs would take about {seconds / 3600:.3g} h (~{each:.2g} s "
            f"each); at most {MAX_WORK_SECONDS / 3600:g} h: evaluate fewer designs or samples",
        )
    return seconds


@dataclass(frozen=True)
class Robustness:
    """Robust evaluation settings: probability ``probability``, ``samples`` variants of ``ranges``,
    ``seed``."""

    probability: float
    samples: int
    seed: int
    ranges: tuple = ()
    values: tuple[dict[str, Any], ...] = field(default=(), repr=False, compare=False)

    def to_json(self) -> dict:
        return {
            "P": self.probability,
            "samples": self.samples,
            "seed": self.seed,
            "ranges": [r.to_json() for r in self.ranges],
        }


def make_robustness(probability: float, ranges: Sequence, *, samples: int = 32, seed: int = 0) -> Robustness:
    """Checked :class:`Robustness`; model-option ranges (``model.*``) are left out (sweep models have
    none)."""

    if isinstance(probability, bool) or not isinstance(probability, (int, float)) or not 0 < probability < 1:
        raise DesignError("robust", probability, "must be a probability in (0, 1), e.g. 0.95")
    if isinstance(samples, bool) or not isinstance(samples, int) or not 2 <= samples <= MAX_ROBUST_SAMPLES:
        raise DesignError("samples", samples, f"must be an integer in [2, {MAX_ROBUST_SAMPLES}]")
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= 2**32 - 1:
        raise DesignError("seed", seed, "must be an integer in [0, 4294967295]")
    use = tuple(r for r in ranges if not r.path.startswith("model."))
    if not use:
        raise DesignError("ranges", [r.path for r in ranges], "need at least one design or material range")
    values = tuple(sample_values(unit_sample(samples, len(use), seed), list(use)))
    return Robustness(float(probability), samples, seed, use, values)


@dataclass(frozen=True)
class Scores:
    """Scores of a batch of ``n`` candidates (``k`` objectives, ``m`` constraints).

    Attributes
    ----------
    objectives
        (n, k) raw objective values (robust: the p50).
    margins
        (n, m) constraint margins (≥ 0 when met; robust: at probability P).
    ok
        (n,) whether the candidate could be built and evaluated.
    percentiles
        (n, k, 3) p5/p50/p95 of each objective (robust only, else ``None``).
    probabilities
        (n, m) probability of meeting each constraint (robust only, else ``None``).
    reasons
        The first failure reason of each failed candidate (else empty).
    samples_ok
        (n,) robust only: buildable variants of each candidate (the others are left out).
    """

    objectives: np.ndarray
    margins: np.ndarray
    ok: np.ndarray
    percentiles: np.ndarray | None = None
    probabilities: np.ndarray | None = None
    reasons: tuple[str, ...] = ()
    samples_ok: np.ndarray | None = None


def _tasks(problem: Problem, variants: list[dict], slots: int, evaluators: Sequence[str]) -> list[dict]:
    # closed forms only (the paper's formula): one task, a pool's start-up would cost more than the work
    instant = all(get(e).seconds_per_design <= _FORMULA_SECONDS for e in evaluators)
    n_tasks = 1 if instant else max(1, min(slots, len(variants)))
    size = max(1, math.ceil(len(variants) / n_tasks))
    paths = sorted({p for v in variants for p in v})
    return [
        {
            "task_id": t,
            "design_ids": list(range(start, min(start + size, len(variants)))),
            "variants": variants[start : start + size],
            "param_paths": paths,
            "base_table": problem.base_table,
            "pressures_MPa": list(problem.pressures),
            "loads": [problem.load],
            "evaluators": list(evaluators),
            "mesh_size": None,
            "max_strain": math.inf,
            "section": dict(problem.section_options),
            "options": dict(problem.options),
        }
        for t, start in enumerate(range(0, len(variants), size))
    ]


def run_variants(problem: Problem, variants: list[dict], backend: Backend, evaluators=None, model=None):
    """The merged results table of ``variants`` (design ids 0..n−1) with ``model``'s columns.

    ``evaluators`` default to the paper's formula and ``problem``'s; ``model`` to ``problem.model``.
    """
    import pandas as pd

    evaluators = evaluators or sorted({"paper", problem.evaluator})
    frames = backend.map(_tasks(problem, variants, backend.slots, evaluators))
    df = pd.concat(frames, ignore_index=True)
    df = add_derived_columns(df, max_strain=math.inf, p_max=max(problem.pressures))
    # a design bending past a full turn passes through itself: no tier models it, none ranks it
    return fail_self_contact(model_columns(df, model or problem.model))


def evaluate_parameters(
    problem: Problem, params: Sequence[dict[str, float]], backend: Backend, robust: Robustness | None = None
) -> Scores:
    """Scores of the candidates ``params`` (one ``{path: value}`` each)."""
    n = len(params)
    k, m = len(problem.objectives), len(problem.constraints)
    if n == 0:
        return Scores(np.zeros((0, k)), np.zeros((0, m)), np.zeros(0, bool))
    s = robust.samples if robust else 1
    variants = (
        [dict(p) for p in params]
        if robust is None
        else [{**sample, **p} for p in params for sample in robust.values]
    )
    df = run_variants(problem, variants, backend)
    check_columns([*problem.objectives, *problem.constraints], df.columns)
    objs, margins, ok = score_table(df, range(len(variants)), problem.objectives, problem.constraints)
    first = df.drop_duplicates("design_id").set_index("design_id")["reason"]
    reasons = tuple(str(first.get(i * s, "")) if not ok[i * s] else "" for i in range(n))
    if robust is None:
        return Scores(objs, margins, ok, reasons=reasons)
    objs = objs.reshape(n, s, k)
    oks = ok.reshape(n, s)
    # Variants the design checks reject (e.g. a wall the sampled shape leaves too thin) are left out,
    # as in `predict`, and counted; a candidate with no buildable variant is invalid.
    margins = np.where(oks[:, :, None], margins.reshape(n, s, m), np.nan)
    n_ok = oks.sum(axis=1)
    import warnings

    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows of an invalid candidate
        pct = np.nanpercentile(np.where(oks[:, :, None], objs, np.nan), [5, 50, 95], axis=1).transpose(
            1, 2, 0
        )
        quant = np.nanquantile(margins, 1.0 - robust.probability, axis=1, method="inverted_cdf")
        prob = (margins >= 0).sum(axis=1) / np.maximum(n_ok, 1)[:, None]
    quant = np.where(n_ok[:, None] > 0, quant, -np.inf)
    return Scores(pct[:, :, 1], quant, n_ok > 0, pct, prob, reasons, n_ok)
