"""Re-check winners with the 3-D linear FEM: the same expressions on the FEM's columns, and the agreement."""

from __future__ import annotations

import math

import numpy as np

from softcath.studies.optimise.backend import Backend
from softcath.studies.optimise.evaluate import run_variants
from softcath.studies.optimise.problem import Problem
from softcath.studies.optimise.scoring import score_table
from softcath.studies.sweep.results import MODEL_COLUMNS

__all__ = ["fem_recheck"]


def _clean(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


def fem_recheck(problem: Problem, params: list[dict[str, float]], backend: Backend) -> list[dict]:
    """Per winner: the FEM's objectives and margins, and its curvature against the optimised model's.

    ``curvature_rel_diff`` is the largest ``|(FEM − model)/model|`` of the
    curvature over the positive pressures; ``margins`` the FEM's margin of each constraint
    (``constraints``: the same, the old key); ``missed`` the constraints it misses with their
    margins (``None``: undefined); ``feasible`` whether the FEM's values meet every constraint;
    ``status``/``reason`` report a FEM failure.
    """
    if not params:
        return []
    evaluators = sorted({"paper", problem.evaluator, "fem"})
    df = run_variants(problem, [dict(p) for p in params], backend, evaluators=evaluators, model="fem")
    ids = list(range(len(params)))
    objs, margins, ok = score_table(df, ids, problem.objectives, problem.constraints)

    own = MODEL_COLUMNS.get(problem.model, {}).get("curvature_per_mm", "curvature_analytic_per_mm")
    out = []
    for i in ids:
        rows = df[(df["design_id"] == i) & (df["pressure_MPa"] > 0)]
        fem_k = rows["curvature_fem_per_mm"].to_numpy(float)
        mod_k = rows[own].to_numpy(float) if own in rows else np.full(len(rows), np.nan)
        with np.errstate(all="ignore"):
            rel = np.abs((fem_k - mod_k) / np.abs(mod_k))
        finite = rel[np.isfinite(rel)]
        out.append(
            {
                "model": "fem",
                "status": "ok" if ok[i] else "failed",
                "reason": "" if ok[i] else str(rows["reason"].iloc[0] if len(rows) else ""),
                "objectives": {o.text: _clean(objs[i, j]) for j, o in enumerate(problem.objectives)},
                "margins": {c.text: _clean(margins[i, j]) for j, c in enumerate(problem.constraints)},
                "constraints": {c.text: _clean(margins[i, j]) for j, c in enumerate(problem.constraints)},
                "missed": {
                    c.text: _clean(margins[i, j])
                    for j, c in enumerate(problem.constraints)
                    if not margins[i, j] >= 0
                },
                "feasible": bool(ok[i] and np.all(margins[i] >= 0)),
                "curvature_rel_diff": _clean(float(finite.max())) if finite.size else None,
            }
        )
    return out
