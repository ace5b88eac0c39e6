"""``softcath optimise`` as a function: search, record every evaluation, re-check the winners, write."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from softcath import design
from softcath.core.atomic import write_json
from softcath.design.errors import DesignError
from softcath.studies.optimise.backend import Backend
from softcath.studies.optimise.evaluate import (
    Robustness,
    Scores,
    check_work,
    evaluate_parameters,
    make_robustness,
)
from softcath.studies.optimise.problem import Problem
from softcath.studies.optimise.recheck import fem_recheck
from softcath.studies.optimise.result import Optimum, Winner
from softcath.studies.optimise.search import search
from softcath.studies.sweep.variants import build_variant

__all__ = ["check_search", "optimise", "write_optimum"]


class _Recorder:
    """Evaluates batches of unit coordinates and keeps every evaluation (the history)."""

    def __init__(self, problem: Problem, backend: Backend, robust: Robustness | None, bar) -> None:
        self.problem, self.backend, self.robust, self.bar = problem, backend, robust, bar
        self.rows: list[dict] = []
        self.batches = 0

    def __call__(self, unit: np.ndarray) -> Scores:
        params = [self.problem.parameters(u) for u in np.clip(unit, 0.0, 1.0)]
        scores = evaluate_parameters(self.problem, params, self.backend, self.robust)
        for i, p in enumerate(params):
            self.rows.append(self._row(p, scores, i))
        self.batches += 1
        self.bar.update(len(params))
        return scores

    def _row(self, p: dict, s: Scores, i: int) -> dict:
        pr = self.problem
        row = {"evaluation": len(self.rows), "batch": self.batches, **p}
        for j, o in enumerate(pr.objectives):
            row[o.text] = float(s.objectives[i, j])
            if s.percentiles is not None:
                row[f"p5 {o.text}"], row[f"p95 {o.text}"] = (float(s.percentiles[i, j, q]) for q in (0, 2))
        for j, c in enumerate(pr.constraints):
            row[f"margin {c.text}"] = float(s.margins[i, j])
            if s.probabilities is not None:
                row[f"probability {c.text}"] = float(s.probabilities[i, j])
        if s.samples_ok is not None:
            row["buildable samples"] = int(s.samples_ok[i])
        row["ok"] = bool(s.ok[i])
        row["feasible"] = bool(s.ok[i] and np.all(s.margins[i] >= 0) and np.all(np.isfinite(s.objectives[i])))
        row["reason"] = s.reasons[i] if s.reasons else ""
        return row


def _winner(problem: Problem, name: str, row: dict, robust: bool) -> Winner:
    def num(v):
        return float(v) if np.isfinite(v) else None

    return Winner(
        name=name,
        reason=_reason(problem, row),
        parameters={p: float(row[p]) for p in problem.paths},
        objectives={o.text: num(row[o.text]) for o in problem.objectives},
        constraints={c.text: num(row[f"margin {c.text}"]) for c in problem.constraints},
        feasible=bool(row["feasible"]),
        percentiles={
            o.text: {
                "p5": num(row[f"p5 {o.text}"]),
                "p50": num(row[o.text]),
                "p95": num(row[f"p95 {o.text}"]),
            }
            for o in problem.objectives
        }
        if robust
        else None,
        probabilities={c.text: float(row[f"probability {c.text}"]) for c in problem.constraints}
        if robust
        else None,
        at_bounds=at_bounds(problem, {p: float(row[p]) for p in problem.paths}),
    )


#: A variable within this fraction of its range from an end is "at" that end.
BOUND_TOLERANCE = 1e-3


def at_bounds(problem: Problem, parameters: dict[str, float]) -> dict[str, str]:
    """``{path: "low" | "high"}`` of the variables of ``parameters`` at an end of their range."""
    out = {}
    for v in problem.variables:
        x, tol = parameters[v.path], BOUND_TOLERANCE * (v.high - v.low)
        if x <= v.low + tol:
            out[v.path] = "low"
        elif x >= v.high - tol:
            out[v.path] = "high"
    return out


def _reason(problem: Problem, row: dict) -> str:
    """Why the history row ``row`` is not a feasible design ("" when it is)."""
    if row["feasible"]:
        return ""
    if not row["ok"]:
        return str(row.get("reason") or "the model could not evaluate it")
    missed = [
        f"'{c.text}' missed by {-float(row[f'margin {c.text}']):.4g}"
        for c in problem.constraints
        if not float(row[f"margin {c.text}"]) >= 0
    ]
    if missed:
        return "constraint " + "; ".join(missed)
    return "an objective is not a finite number there"


def check_search(problem: Problem, *, budget: int, seed: int = 0, robust: Robustness | None = None) -> None:
    """Refuse a budget or seed that cannot work, or a search estimated beyond two hours, before any run.

    Raises
    ------
    DesignError
        Naming ``budget`` or ``seed`` with its bound.
    """

    if isinstance(budget, bool) or not isinstance(budget, int) or budget < 10:
        raise DesignError("budget", budget, "must be an integer >= 10")
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= 2**32 - 1:
        raise DesignError("seed", seed, "must be an integer in [0, 4294967295]")
    runs = budget * (robust.samples if robust is not None else 1)
    check_work(
        problem.model,
        problem.base_table,
        runs,
        param="budget",
        value=budget,
        mesh_size=problem.section_options.get("mesh_size"),
    )


def optimise(
    problem: Problem,
    *,
    budget: int = 200,
    seed: int = 0,
    robust: Robustness | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    client=None,
    fem_check: bool = False,
    progress: bool = True,
) -> Optimum:
    """Search ``problem``'s variables for its best design(s).

    Parameters
    ----------
    problem
        From :func:`softcath.studies.optimise.make_problem`.
    budget
        Candidate designs to evaluate (robust: each costs ``robust.samples`` model runs).
    seed
        Seeds the search (and nothing else: the robust sample has its own seed).
    robust
        Optimise the objectives' p50 under constraints met with probability ≥ P (a range on a
        design variable is left out: the optimiser chooses that value).
    workers, scheduler, client
        Local processes, a Dask scheduler address, or a Dask client (one at most).
    fem_check
        Re-check the winners with the 3-D linear FEM (~10 s a design).
    progress
        Show a progress bar on stderr.
    """
    from tqdm import tqdm

    check_search(problem, budget=budget, seed=seed, robust=robust)
    t0 = time.perf_counter()
    if robust is not None and {r.path for r in robust.ranges} & set(problem.paths):
        # a design variable is the optimiser's to choose, not uncertain: its range is left out
        kept = [r for r in robust.ranges if r.path not in problem.paths]
        robust = make_robustness(robust.probability, kept, samples=robust.samples, seed=robust.seed)
    signs = np.array([o.sign for o in problem.objectives])
    with (
        Backend(workers=workers, scheduler=scheduler, client=client) as backend,
        tqdm(total=budget, desc="optimise", unit="design", disable=not progress, dynamic_ncols=True) as bar,
    ):
        rec = _Recorder(problem, backend, robust, bar)
        outcome = search(rec, n_var=len(problem.variables), signs=signs, budget=budget, seed=seed)
        import pandas as pd

        history = pd.DataFrame(rec.rows)
        winners = _pick(problem, history, outcome.unit, robust is not None)
        if fem_check:
            checks = fem_recheck(problem, [w.parameters for w in winners], backend)
            winners = [Winner(**{**w.__dict__, "fem_check": c}) for w, c in zip(winners, checks, strict=True)]
        name = backend.name
    algorithm = "DE + COBYLA (pymoo, scipy)" if len(signs) == 1 else "NSGA-II (pymoo)"
    return Optimum(
        model=problem.model,
        load=problem.load,
        algorithm=algorithm,
        evaluations=len(history),
        model_runs=len(history) * (robust.samples if robust else 1),
        seed=seed,
        budget=budget,
        backend=name,
        variables=tuple({"path": v.path, "low": v.low, "high": v.high} for v in problem.variables),
        objectives=tuple(o.text for o in problem.objectives),
        constraints=tuple(c.text for c in problem.constraints),
        pressures=problem.pressures,
        best=tuple(winners),
        seconds=time.perf_counter() - t0,
        robust=robust.to_json() if robust else None,
        history=history,
        model_options=dict(problem.options),
    )


def _pick(problem: Problem, history, unit: np.ndarray, robust: bool) -> list[Winner]:
    """Winners as evaluated: the history's rows of the search's final points (duplicates once)."""
    paths = list(problem.paths)
    values = history[paths].to_numpy(float)
    rows, seen = [], set()
    for u in unit:
        x = np.array([v.value(c) for v, c in zip(problem.variables, np.clip(u, 0, 1), strict=True)])
        i = int(np.argmin(np.abs(values - x).max(axis=1)))
        if i not in seen:
            seen.add(i)
            rows.append(history.iloc[i].to_dict())
    if len(rows) == 1:
        return [_winner(problem, "best", rows[0], robust)]
    return [_winner(problem, f"pareto_{k:02d}", r, robust) for k, r in enumerate(rows, start=1)]


def write_optimum(optimum: Optimum, problem: Problem, out_dir: str | Path) -> dict[str, Path]:
    """Write ``optimum.json``, ``history.parquet`` and ``designs/<name>.toml`` into ``out_dir``.

    Only feasible winners get a design file; an infeasible search writes its reason
    (``optimum.json``: ``feasible`` false, ``reason``) and the history, no design.
    """

    out = Path(out_dir)
    (out / "designs").mkdir(parents=True, exist_ok=True)
    paths = {"optimum": write_json(out / "optimum.json", optimum.to_json(), indent=1)}
    tmp = out / ".history.parquet.tmp"
    optimum.history.to_parquet(tmp, index=False)
    tmp.replace(out / "history.parquet")
    paths["history"] = out / "history.parquet"
    for w in optimum.best:
        if not w.feasible:
            continue  # an infeasible winner is no design: optimum.json says why, no TOML is written
        try:
            d = build_variant(problem.base_table, w.parameters, name=w.name)
        except DesignError:
            continue
        header = f"softcath optimise ({optimum.model} model): {w.name}\n" + "\n".join(
            f"{k} = {v:.6g}" for k, v in w.parameters.items()
        )
        paths[f"design {w.name}"] = design.save(d, out / "designs" / f"{w.name}.toml", header=header)
    return paths
