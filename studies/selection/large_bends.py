"""Bend constraints beyond the linear tiers' validity, re-checked with the finite-strain section model.

The linear tiers (the paper's formula, the linear section model, the linear
3-D FEM) are small-rotation models: against the finite-strain section model
they are 5 % off by about 5 degrees of bend and 20-30 % off at the 45-90
degrees a tip is chosen for. When a selection ranked on a linear tier has a
constraint on the bend (``bend_angle_deg``, ``bend_per_MPa_deg``,
``curvature_per_mm``) and its ranked designs bend past
:data:`LINEAR_BEND_LIMIT_DEG`, the ranked designs are re-evaluated with the
finite-strain section model at the sweep's pressures; those that still meet
every constraint are ranked on their finite-strain objectives (Pareto front
first, then the first objective). The selection's ``points`` (the report's Pareto
plot) become the re-checked designs' finite-strain values; the linear ones stay in
``recheck["linear_points"]``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from softcath.core.deprecation import renamed_keyword
from softcath.studies.criteria import parse_constraint, parse_objective, rows_at
from softcath.studies.model_validity import LINEAR_BEND_LIMIT_DEG as _LIMIT
from softcath.studies.model_validity import LINEAR_TIERS, linear_tier_warning
from softcath.studies.optimise import Backend, Problem, evaluate_parameters
from softcath.studies.selection.ranking import Selection, pareto_front

__all__ = [
    "LINEAR_BEND_LIMIT_DEG",
    "LINEAR_MODELS",
    "large_bend_constraints",
    "linear_validity_warning",
    "recheck_large_bends",
]

#: Bend [deg] past which a linear tier's bend is off by more than ~5 % (one rule: model_validity's).
LINEAR_BEND_LIMIT_DEG = _LIMIT
#: The small-rotation tiers of a selection.
LINEAR_MODELS = LINEAR_TIERS
_BEND_COLUMNS = {"bend_angle_deg", "bend_per_MPa_deg", "curvature_per_mm"}


def large_bend_constraints(selection: Selection, df) -> list[str]:
    """The bend constraints of ``selection`` whose ranked designs bend past the linear validity.

    ``df`` is the results table with the selection model's best-estimate columns.
    """
    if selection.model not in LINEAR_MODELS or not selection.ranked:
        return []
    ids = {r["design_id"] for r in selection.ranked}
    sub = df[(df["load"] == selection.load) & df["design_id"].isin(ids)]
    out = []
    for text in selection.constraints:
        c = parse_constraint(text)
        if not c.columns() & _BEND_COLUMNS:
            continue
        rows = sub[rows_at(sub, c.where, default_all=True)]
        bend = np.abs(rows["bend_angle_deg"].to_numpy(float))
        if bend.size and np.nanmax(bend, initial=0.0) > LINEAR_BEND_LIMIT_DEG:
            out.append(text)
    return out


def linear_validity_warning(selection: Selection, df, *, rechecked: bool) -> str | None:
    """The warning when ``selection`` ranked on a linear tier whose ranked designs bend past its validity.

    ``df`` is the results table with the selection model's best-estimate columns; ``rechecked``
    whether the finite-strain re-check of the bend constraints runs (it does not re-check
    other columns such as ``max_strain``).
    """
    if selection.model not in LINEAR_MODELS or not selection.ranked:
        return None
    ids = {r["design_id"] for r in selection.ranked}
    sub = df[(df["load"] == selection.load) & df["design_id"].isin(ids)]
    bend = np.abs(sub["bend_angle_deg"].to_numpy(float))
    if not bend.size or not np.isfinite(bend).any():
        return None
    i = int(np.nanargmax(bend))
    way_out = (
        "its bend constraints are re-checked with the finite-strain section model, its other values are not; "
        if rechecked
        else ""
    ) + "rank on the finite-strain tier with --model section-nonlinear (a sweep with that evaluator)"
    return linear_tier_warning(
        selection.model,
        float(bend[i]),
        float(sub["pressure_MPa"].to_numpy(float)[i]),
        how=f"the {len(ids)} ranked designs ({selection.load} load)",
        way_out=way_out,
    )


@renamed_keyword(old="pressures_MPa", new="pressures")
def recheck_large_bends(
    selection: Selection,
    *,
    base_table: Mapping[str, Any],
    pressures: Sequence[float],
    constraints: Sequence[str],
    workers: int | None = None,
) -> Selection:
    """``selection`` with its ranked designs re-evaluated by the finite-strain section model.

    ``constraints`` are the large-bend constraints that asked for it (reported in ``recheck``).
    """
    objs = tuple(parse_objective(o) for o in selection.objectives)
    cons = tuple(parse_constraint(c) for c in selection.constraints)
    problem = Problem(
        base_table=base_table,
        variables=(),
        objectives=objs,
        constraints=cons,
        model="section-nonlinear",
        load=selection.load,
        pressures=tuple(sorted(set(pressures))),
    )
    swept = {p for r in selection.ranked for p in r["parameters"]}
    params = [
        {k: v for k, v in r["parameters"].items() if k in swept and k != "outer_diameter_mm"}
        for r in selection.ranked
    ]
    with Backend(workers=workers) as backend:
        s = evaluate_parameters(problem, params, backend)
    passing = [
        (r, s.objectives[i])
        for i, r in enumerate(selection.ranked)
        if s.ok[i] and np.all(s.margins[i] >= 0) and np.all(np.isfinite(s.objectives[i]))
    ]
    matrix = np.array([[o.sign * v for o, v in zip(objs, vals, strict=True)] for _, vals in passing], float)
    matrix = matrix.reshape(len(passing), len(objs))
    front = pareto_front(matrix)
    order = sorted(
        range(len(passing)), key=lambda k: (not front[k], matrix[k, 0], passing[k][0]["design_id"])
    )
    ranked = _rechecked_ranking(passing, order, front, objs)
    dropped = [r["design_id"] for i, r in enumerate(selection.ranked) if r not in [p[0] for p in passing]]
    note = (
        f"{'; '.join(constraints)}: bends past {LINEAR_BEND_LIMIT_DEG:g} deg are beyond the "
        f"{selection.model} model's validity; the {len(selection.ranked)} ranked designs were re-checked "
        f"with the finite-strain section model ({len(passing)} still pass)"
    )
    recheck = {
        "model": "section-nonlinear",
        "linear_model": selection.model,
        "constraints": list(constraints),
        "limit_deg": LINEAR_BEND_LIMIT_DEG,
        "n_rechecked": len(selection.ranked),
        "n_passing": len(passing),
        "dropped": dropped,
        "linear_points": selection.points,
        "reasons": {
            str(r["design_id"]): s.reasons[i]
            for i, r in enumerate(selection.ranked)
            if s.reasons and s.reasons[i]
        },
    }
    return dataclasses.replace(
        selection,
        ranked=ranked,
        model="section-nonlinear",
        recheck=recheck,
        note="; ".join(x for x in (selection.note, note) if x),
        pareto_front=sorted(int(passing[k][0]["design_id"]) for k in range(len(passing)) if front[k]),
        # the report's Pareto plot: the re-checked designs on the values they were ranked by
        points=[[int(r["design_id"]), int(r["pareto"]), *r["objectives"].values()] for r in ranked],
    )


def _rechecked_ranking(passing: list, order: list[int], front, objs) -> list[dict]:
    """The passing designs in ``order``, with the finite-strain objectives and their linear rank and
    objectives."""
    ranked = []
    for rank, k in enumerate(order, start=1):
        r, vals = passing[k]
        linear = dict(r["objectives"])
        ranked.append(
            {
                **r,
                "rank": rank,
                "pareto": bool(front[k]),
                "linear_rank": r["rank"],
                "objectives": {o.text: float(v) for o, v in zip(objs, vals, strict=True)},
                "linear_objectives": linear,
            }
        )
    return ranked
