"""Robust selection: re-evaluate the nominal passers over material/manufacturing ranges, keep the sure ones.

Each ranked design of a nominal :class:`~softcath.studies.selection.Selection`
is combined with one seeded Latin-hypercube sample of the uncertain
parameters (the ranges of ``softcath predict``; the same sample for every
design) and evaluated by a sweep model tier (the section model unless the
selection was on the paper's formula). A design passes when it meets every
constraint with probability ≥ P; passers are ranked on the objectives' p50
(Pareto front first, then the first objective), and every design reports
p5/p50/p95 of each objective and the probability of each constraint.
Variants the design checks reject (a sampled shape leaving too thin a wall)
are left out of the probabilities, as ``predict`` does, and counted.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from softcath.core.deprecation import renamed_keyword
from softcath.design.errors import DesignError
from softcath.models import tiers
from softcath.models.options import check_tier_options
from softcath.studies.criteria import parse_constraint, parse_objective
from softcath.studies.optimise import MODELS, Backend, Problem, evaluate_parameters, make_robustness
from softcath.studies.optimise.evaluate import check_work
from softcath.studies.predict.ranges import chosen_ranges
from softcath.studies.selection.ranking import Selection, pareto_front

__all__ = ["sweep_ranges", "robust_select"]


def sweep_ranges(
    base: str, base_table: Mapping[str, Any], vary: Sequence[str] = (), ranges_file: str | Path | None = None
) -> list:
    """The uncertain parameters: each ``vary`` item, else the ranges file's (default: the base preset's)
    defaults."""
    ranges = chosen_ranges(base, base_table, vary, ranges_file)
    if ranges is None:
        raise DesignError("ranges", str(base), "the sweep's base design has no ranges file: give ranges")
    return ranges


@renamed_keyword(old="pressures_MPa", new="pressures")
def robust_select(
    selection: Selection,
    *,
    base_table: Mapping[str, Any],
    pressures: Sequence[float],
    probability: float,
    ranges: Sequence,
    samples: int = 32,
    seed: int = 0,
    model: str | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = False,
    options: Mapping[str, Mapping[str, Any]] | None = None,
) -> Selection:
    """``selection`` with its ranked designs re-evaluated robustly (see the module docstring).

    Ranges on a parameter the sweep varied are left out (each design fixes
    that value); the result's ``robust`` records P, the samples, the ranges,
    the model and every design's probabilities and percentiles. ``options`` (tier name ->
    options) go to the tiers the variants run on (``model`` and the paper's formula; those of
    other tiers are not used) and are recorded as ``model_options``.
    """

    # the selection's tier if a search can run it (not the 3-D FEM, not a plain table), else the section model
    model = model or (selection.model if selection.model in MODELS else "section")
    run = {model, *(t.name for t in tiers() if t.closed_form)}  # the formula runs beside every tier
    swept = {p for r in selection.ranked for p in r["parameters"]}
    use = [r for r in ranges if r.path not in swept]
    left_out = [r.path for r in ranges if r.path in swept]
    rob = make_robustness(probability, use, samples=samples, seed=seed)

    # every ranked design's whole sample, estimated before any run
    check_work(model, dict(base_table), len(selection.ranked) * samples, param="samples", value=samples)
    objs = tuple(parse_objective(o) for o in selection.objectives)
    cons = tuple(parse_constraint(c) for c in selection.constraints)
    problem = Problem(
        base_table=base_table,
        variables=(),
        objectives=objs,
        constraints=cons,
        model=model,
        load=selection.load,
        pressures=tuple(sorted(set(pressures))),
        options=check_tier_options(
            {t: o for t, o in (options or {}).items() if t in run}, parameter="options"
        ),
    )
    designs = [
        {k: v for k, v in r["parameters"].items() if k in swept and k != "outer_diameter_mm"}
        for r in selection.ranked
    ]
    scores = _robust_scores(problem, designs, rob, workers, scheduler, progress)
    per_design, passing = _judge_designs(selection.ranked, scores, objs, cons, probability)
    matrix = np.array([v for _, v in passing], float).reshape(len(passing), len(objs))
    front = pareto_front(matrix)
    order = sorted(
        range(len(passing)), key=lambda k: (not front[k], matrix[k, 0], passing[k][0]["design_id"])
    )
    robust = {
        **rob.to_json(),
        "model": model,
        **({"model_options": dict(problem.options)} if problem.options else {}),
        "left_out": left_out,
        "n_evaluated": len(designs),
        "n_passing": len(passing),
        "designs": per_design,
    }
    return dataclasses.replace(
        selection,
        ranked=_robust_ranked(passing, order, front, per_design),
        robust=robust,
        pareto_front=sorted(int(passing[k][0]["design_id"]) for k in range(len(passing)) if front[k]),
    )


def _robust_scores(problem, designs: list[dict], rob, workers, scheduler, progress: bool) -> list:
    """Each design's robust score: its whole sample evaluated in one batch (the bar moves per design)."""
    from tqdm import tqdm

    scores = []
    with (
        Backend(workers=workers, scheduler=scheduler) as backend,
        tqdm(total=len(designs), desc="robust select", unit="design", disable=not progress) as bar,
    ):
        for d in designs:  # one design (its whole sample) per batch: the bar moves as designs finish
            scores.append(evaluate_parameters(problem, [d], backend, rob))
            bar.update()
    return scores


def _judge_designs(ranked: list[dict], scores: list, objs, cons, probability: float):
    """Per design (by id): passes, probabilities, percentiles and buildable samples; and the passing
    designs with their signed median objectives."""
    per_design, passing = {}, []
    for r, s in zip(ranked, scores, strict=True):
        did = r["design_id"]
        probs = {c.text: float(s.probabilities[0, j]) for j, c in enumerate(cons)}
        pct = {
            o.text: dict(zip(("p5", "p50", "p95"), map(_num, s.percentiles[0, j]), strict=True))
            for j, o in enumerate(objs)
        }
        ok = bool(
            s.ok[0]
            and all(p >= probability for p in probs.values())
            and all(v["p50"] is not None for v in pct.values())
        )
        per_design[str(did)] = {
            "passes": ok,
            "probabilities": probs,
            "percentiles": pct,
            "buildable_samples": int(s.samples_ok[0]),
        }
        if ok:
            passing.append((r, [o.sign * pct[o.text]["p50"] for o in objs]))
    return per_design, passing


def _robust_ranked(passing: list, order: list[int], front, per_design: dict) -> list[dict]:
    """The passing designs in robust ``order``, with their nominal rank, medians, percentiles and
    probabilities."""
    ranked = []
    for rank, k in enumerate(order, start=1):
        r = passing[k][0]
        info = per_design[str(r["design_id"])]
        ranked.append(
            {
                **r,
                "rank": rank,
                "pareto": bool(front[k]),
                "nominal_rank": r["rank"],
                "objectives": {t: v["p50"] for t, v in info["percentiles"].items()},
                "percentiles": info["percentiles"],
                "probabilities": info["probabilities"],
            }
        )
    return ranked


def _num(v) -> float | None:
    return float(v) if np.isfinite(v) else None
