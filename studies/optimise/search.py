"""The search: pymoo's differential evolution (one objective) or NSGA-II (several), then a local polish.

The optimiser works on unit coordinates (each variable's ``[low, high]``
mapped to [0, 1]) and minimises ``sign × objective`` under ``−margin ≤ 0``
plus one validity constraint (a design that cannot be built or evaluated
violates it), so invalid designs steer the search instead of stopping it.
With one objective the best design found is then polished by COBYLA
(scipy, bounded, gradient-free) with what is left of the budget: the
evolution finds the basin, the local search the last digits.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["PENALTY", "SearchOutcome", "search"]

#: Stand-in for an undefined objective or margin (pymoo needs finite numbers).
PENALTY = 1e9


@dataclass(frozen=True)
class SearchOutcome:
    """Unit coordinates of the winners (one row per design: the optimum or the Pareto set)."""

    unit: np.ndarray
    generations: int


def _fg(scores, signs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Minimised objectives F and constraints G (≤ 0 when met) of a batch's scores."""
    f = scores.objectives * signs
    valid = scores.ok & np.all(np.isfinite(f), axis=1)
    f = np.where(np.isfinite(f), f, PENALTY)
    g = np.where(np.isfinite(scores.margins), -scores.margins, PENALTY)
    g = np.column_stack([g, np.where(valid, 0.0, 1.0)])
    return f, g


def search(
    evaluate: Callable[[np.ndarray], object],
    *,
    n_var: int,
    signs: np.ndarray,
    budget: int,
    seed: int,
    pop_size: int | None = None,
    polish: bool = True,
) -> SearchOutcome:
    """Run the search; ``evaluate(unit (n, n_var)) -> Scores`` counts toward ``budget`` per row."""
    from pymoo.core.problem import Problem as PymooProblem
    from pymoo.optimize import minimize

    n_obj = len(signs)
    pop = pop_size or max(8, min(40, 8 * n_var))
    pop = min(pop, max(budget // 2, 4))
    n_con = None

    class _Wrapped(PymooProblem):
        def _evaluate(self, x, out, *args, **kwargs):
            f, g = _fg(evaluate(np.asarray(x, float)), signs)
            out["F"], out["G"] = f, g

    probe_scores = evaluate(np.full((1, n_var), 0.5))
    _, g0 = _fg(probe_scores, signs)
    n_con = g0.shape[1]
    problem = _Wrapped(n_var=n_var, n_obj=n_obj, n_ieq_constr=n_con, xl=0.0, xu=1.0)
    single = n_obj == 1
    evo_budget = budget - 1
    if single and polish:
        evo_budget = max(pop, int(0.75 * evo_budget))
    if single:
        from pymoo.algorithms.soo.nonconvex.de import DE

        algorithm = DE(pop_size=pop, variant="DE/best/1/bin", CR=0.7)
    else:
        from pymoo.algorithms.moo.nsga2 import NSGA2

        algorithm = NSGA2(pop_size=pop)
    # whole generations only, so the budget is never exceeded
    res = minimize(problem, algorithm, ("n_gen", max(1, evo_budget // pop)), seed=seed, verbose=False)
    if single:
        best = _best_of(res)
        if polish and budget - 1 - res.algorithm.evaluator.n_eval > 2:
            best = _polish(evaluate, best, signs, budget - 1 - res.algorithm.evaluator.n_eval)
        return SearchOutcome(best[None, :], int(res.algorithm.n_gen or 0))
    front = _front_of(res)
    return SearchOutcome(front, int(res.algorithm.n_gen or 0))


def _best_of(res) -> np.ndarray:
    """The best individual (feasible first, else the least violating)."""
    if res.X is not None:
        return np.atleast_2d(res.X)[0].astype(float)
    pop = res.pop
    cv = pop.get("CV").ravel()
    return pop.get("X")[int(np.argmin(cv))].astype(float)


def _front_of(res) -> np.ndarray:
    if res.X is None:
        return _best_of(res)[None, :]
    x = np.atleast_2d(res.X).astype(float)
    f = np.atleast_2d(res.F)
    order = np.lexsort(f.T[::-1])
    return x[order]


def _polish(evaluate, x0: np.ndarray, signs: np.ndarray, budget: int) -> np.ndarray:
    """COBYLA from ``x0`` within ``budget`` evaluations; keeps the best feasible point seen."""
    from scipy.optimize import NonlinearConstraint, minimize

    cache: dict[tuple, tuple[float, np.ndarray]] = {}
    best = {"x": x0, "f": math.inf, "cv": math.inf}

    def fg(x):
        key = tuple(np.round(np.clip(x, 0, 1), 15))
        if key not in cache:
            f, g = _fg(evaluate(np.asarray(key)[None, :]), signs)
            cache[key] = (float(f[0, 0]), g[0])
            cv = float(np.maximum(g[0], 0).sum())
            if (cv, float(f[0, 0])) < (best["cv"], best["f"]):  # feasible first, then the lower objective
                best.update(x=np.asarray(key), f=float(f[0, 0]), cv=cv)
        return cache[key]

    fg(x0)
    con = NonlinearConstraint(lambda x: -fg(x)[1], 0.0, np.inf)
    minimize(
        lambda x: fg(x)[0],
        x0,
        method="COBYLA",
        constraints=[con],
        bounds=[(0.0, 1.0)] * len(x0),
        options={"maxiter": budget, "rhobeg": 0.05, "tol": 1e-8},
    )
    return best["x"]
