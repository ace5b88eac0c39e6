"""The outcome of an optimisation: winners with parameters, objectives and margins; the JSON it writes."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from softcath.core.deprecation import renamed_keyword

__all__ = ["Winner", "Optimum"]


@dataclass(frozen=True)
class Winner:
    """One winning design.

    Attributes
    ----------
    name
        File stem of its design TOML (``best``, or ``pareto_01``…).
    parameters
        ``{path: value}`` of the design variables.
    objectives
        ``{objective text: value}`` (robust: the p50).
    constraints
        ``{constraint text: margin}``, ≥ 0 when met (robust: at probability P); written to
        ``optimum.json`` as ``margins`` (and, for older readers, ``constraints``).
    percentiles
        Robust only: ``{objective text: {"p5", "p50", "p95"}}``.
    probabilities
        Robust only: ``{constraint text: probability of meeting it}``.
    fem_check
        The 3-D linear FEM's re-check (``None`` when skipped).
    at_bounds
        ``{path: "low" or "high"}`` of the variables at an end of their ``--vary`` range (the
        optimum may lie beyond it).
    reason
        Why an infeasible winner is not a design ("" when feasible): the constraints it
        misses and by how much, or why the model could not evaluate it.
    """

    name: str
    parameters: dict[str, float]
    objectives: dict[str, float]
    constraints: dict[str, float]
    feasible: bool
    percentiles: dict[str, dict[str, float]] | None = None
    probabilities: dict[str, float] | None = None
    fem_check: dict[str, Any] | None = None
    reason: str = ""
    at_bounds: dict[str, str] = field(default_factory=dict)

    def to_json(self) -> dict:
        out = {
            "name": self.name,
            "parameters": self.parameters,
            "objectives": self.objectives,
            "margins": self.constraints,
            "constraints": self.constraints,  # the margins' old key, kept for earlier readers
            "feasible": self.feasible,
            "at_bounds": self.at_bounds,
        }
        if not self.feasible:
            out["reason"] = self.reason
        if self.percentiles is not None:
            out["percentiles"] = self.percentiles
            out["probabilities"] = self.probabilities
        if self.fem_check is not None:
            out["fem_check"] = self.fem_check
        return out


@renamed_keyword(old="pressures_MPa", new="pressures")
@dataclass(frozen=True)
class Optimum:
    """What :func:`softcath.studies.optimise.optimise` found (``optimum.json``'s content).

    Its field ``pressures`` holds the pressures every design was evaluated at [MPa] (written as
    ``pressures_MPa`` in ``optimum.json``; that spelling of the attribute is deprecated).
    """

    model: str
    load: str
    algorithm: str
    evaluations: int
    model_runs: int
    seed: int
    budget: int
    backend: str
    variables: tuple[dict, ...]
    objectives: tuple[str, ...]
    constraints: tuple[str, ...]
    pressures: tuple[float, ...]
    best: tuple[Winner, ...]
    seconds: float
    robust: dict | None = None
    history: Any = field(default=None, repr=False, compare=False)
    validity: dict | None = None
    model_options: dict = field(default_factory=dict)

    @property
    def feasible(self) -> bool:
        """True when at least one winner meets every constraint (and so has a design file)."""
        return any(w.feasible for w in self.best)

    @property
    def reason(self) -> str | None:
        """Why the search found no feasible design (None when it did): its closest candidate's reason."""
        if self.feasible:
            return None
        why = self.best[0].reason if self.best else "no candidate was evaluated"
        return f"none of the {self.evaluations} designs evaluated is feasible; the closest: {why}"

    def to_json(self) -> dict:
        return {
            "feasible": self.feasible,
            "reason": self.reason,
            "model": self.model,
            "load": self.load,
            **({"model_options": self.model_options} if self.model_options else {}),
            "algorithm": self.algorithm,
            "evaluations": self.evaluations,
            "model_runs": self.model_runs,
            "budget": self.budget,
            "seed": self.seed,
            "backend": self.backend,
            "variables": list(self.variables),
            "objectives": list(self.objectives),
            "constraints": list(self.constraints),
            "pressures_MPa": list(self.pressures),
            "robust": self.robust,
            **({"validity": self.validity} if self.validity is not None else {}),
            "best": [w.to_json() for w in self.best],
            "seconds": self.seconds,
        }
