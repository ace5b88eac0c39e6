"""Ranking: drop failed and infeasible designs, order the rest Pareto front first.

Each group (front, then the rest) is ordered by the first objective; ties by design id.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from softcath.studies.criteria import check_columns, parse_constraint, parse_objective, rows_at
from softcath.studies.criteria.expressions import SelectionError
from softcath.studies.model_validity import self_contact_reasons
from softcath.studies.selection.models import resolve_model

__all__ = ["MAX_POINTS", "Selection", "pareto_front", "select"]

MAX_POINTS = 5000


def pareto_front(values: np.ndarray) -> np.ndarray:
    """Boolean mask of the non-dominated rows of ``values`` (n × k, every column minimised)."""
    values = np.asarray(values, dtype=float)
    n = len(values)
    on = np.zeros(n, bool)
    if n == 0:
        return on
    order = np.lexsort(values.T[::-1])  # lexicographic: a dominating point always comes first
    front: list[np.ndarray] = []
    for i in order:
        f = values[i]
        if front:
            fr = np.asarray(front)
            if np.any(np.all(fr <= f, axis=1) & np.any(fr < f, axis=1)):
                continue
        front.append(f)
        on[i] = True
    return on


@dataclass(frozen=True)
class Selection:
    """Result of :func:`select`.

    Attributes
    ----------
    load
        The load case whose rows were used.
    model
        Which model the best-estimate columns came from (``paper``, ``section``,
        ``fem``), or ``table`` when the results carry no model columns.
    note
        Why that model or load was used when it was not asked for (else empty).
    recheck
        Large-bend re-check (:func:`softcath.studies.selection.large_bends.recheck_large_bends`): the
        finite-strain section model's verdict on designs ranked by a linear tier; ``None`` if not run.
    warnings
        What the command warned before ranking (e.g. a linear tier past its validity).
    robust
        Robust re-evaluation (:func:`softcath.studies.selection.robust.robust_select`): P, samples,
        ranges, model, per-design probabilities and percentiles; ``None`` for a nominal selection.
    constraints, objectives
        The expressions as given.
    n_designs, n_feasible
        Designs in the sweep, and designs that passed status and every constraint.
    rejected
        Per constraint (and ``"status failed"``): how many designs it removed.
    ranked
        Feasible designs, best first: ``design_id``, ``rank``, ``pareto``, ``objectives``, ``parameters``
        (in the JSON each also names the ``tier`` and ``load`` its values come from).
    pareto_front
        Design ids on the Pareto front.
    points
        ``[design_id, pareto (0/1), objective values...]`` of up to :data:`MAX_POINTS`
        feasible designs (the report's Pareto plot).
    """

    load: str
    constraints: tuple[str, ...]
    objectives: tuple[str, ...]
    n_designs: int
    n_feasible: int
    rejected: dict[str, int]
    ranked: list[dict] = field(default_factory=list)
    pareto_front: list[int] = field(default_factory=list)
    points: list[list[float]] = field(default_factory=list)
    model: str = "table"
    note: str = ""
    robust: dict | None = None
    recheck: dict | None = None
    warnings: tuple[str, ...] = ()

    @property
    def source(self) -> dict:
        """Where the ranked objective values come from: ``tier`` and ``load`` (robust: the p50 of
        the robust model's sample, ``statistic`` ``"p50"``)."""
        if self.robust is not None:
            return {"tier": self.robust["model"], "load": self.load, "statistic": "p50"}
        return {"tier": self.model, "load": self.load}

    def to_json(self) -> dict:
        return {
            "load": self.load,
            "model": self.model,
            "note": self.note,
            "constraints": list(self.constraints),
            "objectives": list(self.objectives),
            "n_designs": self.n_designs,
            "n_feasible": self.n_feasible,
            "rejected": self.rejected,
            "pareto_front": self.pareto_front,
            "ranked": [{**r, **self.source} for r in self.ranked],
            "points": self.points,
            **({"robust": self.robust} if self.robust is not None else {}),
            **({"recheck": self.recheck} if self.recheck is not None else {}),
            **({"warnings": list(self.warnings)} if self.warnings else {}),
        }


def select(
    df,
    *,
    constraints=(),
    objectives=(),
    load: str | None = None,
    top: int | None = None,
    parameters=(),
    model: str | None = None,
) -> Selection:
    """Rank the designs of a results table (see :mod:`softcath.studies.selection`).

    Parameters
    ----------
    df
        The results table (:func:`softcath.studies.sweep.results.read_results`).
    constraints, objectives
        Expression strings.
    load
        Load case to select on (``cap`` or ``lumen``); default: see :func:`resolve_model`.
    model
        ``paper``, ``section`` or ``fem``; default: see :func:`resolve_model`.
    top
        Keep only the best ``top`` designs in ``ranked`` (the counts cover all).
    parameters
        Column names reported for each ranked design (default: swept parameters + outer diameter).
    """
    cons = [parse_constraint(c) for c in constraints]
    objs = [parse_objective(o) for o in objectives]
    if not objs:
        raise SelectionError("give at least one objective, e.g. 'maximise bend_per_MPa_deg'")
    df, model, load, note = resolve_model(df, model, load)
    check_columns([*cons, *objs], df.columns)
    sub = _load_rows(df, load)
    ids = sub["design_id"].to_numpy()
    all_ids = np.unique(ids)
    alive, rejected = _feasible(sub, ids, all_ids, cons)
    obj_vals = _objective_values(sub, ids, objs)
    undefined = {i for i in alive if any(i not in vals for vals in obj_vals.values())}
    if undefined:
        rejected["objective undefined"] = len(undefined)
    alive -= undefined
    feasible = sorted(alive)
    matrix = np.array([[o.sign * obj_vals[o.text][i] for o in objs] for i in feasible]).reshape(
        len(feasible), len(objs)
    )
    on_front = pareto_front(matrix)
    order = sorted(range(len(feasible)), key=lambda k: (not on_front[k], matrix[k, 0], feasible[k]))
    if not parameters:
        parameters = _default_parameters(df)
    ranked = _ranked(
        sub, feasible, order[: top if top else None], on_front, objs, obj_vals, parameters=parameters
    )
    keep = order[:MAX_POINTS]
    points = [
        [int(feasible[k]), int(on_front[k]), *(float(obj_vals[o.text][feasible[k]]) for o in objs)]
        for k in keep
    ]
    return Selection(
        points=points,
        load=load,
        model=model,
        note=note,
        constraints=tuple(constraints),
        objectives=tuple(objectives),
        n_designs=len(all_ids),
        n_feasible=len(feasible),
        rejected=rejected,
        ranked=ranked,
        pareto_front=sorted(int(feasible[k]) for k in range(len(feasible)) if on_front[k]),
    )


def _load_rows(df, load: str):
    """The rows of ``load``; :class:`SelectionError` if the results do not have it."""
    loads = sorted(set(df["load"]))
    if load not in loads:
        raise SelectionError(f"load '{load}' is not in the results; available: {', '.join(loads)}")
    return df[df["load"] == load].reset_index(drop=True)


def _ranked(
    sub, feasible: list, order: list[int], on_front, objs, obj_vals: dict, *, parameters
) -> list[dict]:
    """The ranked designs (in ``order``): rank, id, Pareto membership, objective and parameter values."""
    first = sub.drop_duplicates("design_id").set_index("design_id")
    ranked = []
    for rank, k in enumerate(order, start=1):
        did = feasible[k]
        ranked.append(
            {
                "rank": rank,
                "design_id": int(did),
                "pareto": bool(on_front[k]),
                "objectives": {o.text: obj_vals[o.text][did] for o in objs},
                "parameters": {p: _jsonable(first.at[did, p]) for p in parameters if p in first.columns},
            }
        )
    return ranked


def _feasible(sub, ids, all_ids, cons) -> tuple[set[int], dict[str, int]]:
    """Designs that passed (status ok) and meet every constraint, and how many each check removed."""
    alive = {int(i) for i in all_ids}
    rejected: dict[str, int] = {}
    failed = {int(i) for i in np.unique(ids[(sub["status"] != "ok").to_numpy()])}
    rejected["status failed"] = len(failed & alive)
    alive -= failed
    past = set(self_contact_reasons(sub)) & alive
    if past:
        rejected["bend past 360 deg at a swept pressure (the tip passes through itself; not modelled)"] = len(
            past
        )
        alive -= past
    for c in cons:
        mask = rows_at(sub, c.where, default_all=True)
        lv, rv = c.left.evaluate(sub), c.right.evaluate(sub)
        with np.errstate(invalid="ignore"):
            ok = {"<": lv < rv, "<=": lv <= rv, ">": lv > rv, ">=": lv >= rv, "==": lv == rv, "!=": lv != rv}[
                c.op
            ]
        defined = mask & np.isfinite(lv) & np.isfinite(rv)
        bad_ids = set(ids[defined & ~ok].tolist())
        good_ids = set(ids[defined].tolist())
        drop = (bad_ids | (alive - good_ids)) & alive
        rejected[c.text] = len(drop)
        alive -= drop
    return alive, rejected


def _objective_values(sub, ids, objs) -> dict[str, dict[int, float]]:
    """Per objective text: design id -> value at the objective's pressure (defined rows only)."""
    obj_vals = {}
    for o in objs:
        mask = rows_at(sub, o.where, default_all=False)
        v = o.expr.evaluate(sub)
        rows = mask & np.isfinite(v)
        obj_vals[o.text] = dict(zip(ids[rows].tolist(), v[rows].tolist(), strict=True))
    return obj_vals


def _default_parameters(df) -> list[str]:
    """The swept parameters and the outer diameter: the columns up to ``outer_diameter_mm``."""
    skip = {"design_id", "task_id"}
    return [c for c in df.columns[: list(df.columns).index("outer_diameter_mm") + 1] if c not in skip]


def _jsonable(v):
    if hasattr(v, "item"):
        v = v.item()
    if isinstance(v, float) and not np.isfinite(v):
        return None
    return v
