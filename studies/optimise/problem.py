"""An optimisation problem: design variables with bounds, objectives, constraints, a model tier, pressures.

Objectives and constraints are :mod:`softcath.studies.selection` expressions
over the sweep's result columns; the model tier names the sweep evaluator that
computes them (``paper`` is the analytic formula every evaluation carries).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from softcath.core.deprecation import renamed_keyword
from softcath.core.limits import MAX_PRESSURE_MPA
from softcath.design.errors import DesignError
from softcath.design.validation import MAX_MAGNITUDE
from softcath.models import check_tier_options, tiers
from softcath.studies.criteria import (
    Constraint,
    Objective,
    at_pressure,
    check_columns,
    parse_constraint,
    parse_objective,
    without_text,
)
from softcath.studies.criteria.expressions import SelectionError
from softcath.studies.sweep.results import COLUMN_UNITS
from softcath.studies.sweep.spec import EVALUATORS
from softcath.studies.sweep.variants import check_path
from softcath.studies.tiers import check_assembly, tier_name

__all__ = ["MODELS", "Variable", "Problem", "parse_variable", "make_problem"]

#: The model tiers a search can run: those that are not slow (:attr:`softcath.models.Tier.slow`;
#: a tier's sweep evaluator has its name).
MODELS = tuple(t.name for t in tiers() if not t.slow)


@dataclass(frozen=True)
class Variable:
    """One design variable: a dotted path of the base design and its bounds ``low < high``."""

    path: str
    low: float
    high: float

    def value(self, u: float) -> float:
        """The value at unit coordinate ``u`` in [0, 1]."""
        return self.low + float(u) * (self.high - self.low)


@renamed_keyword(old="pressures_MPa", new="pressures")
@dataclass(frozen=True)
class Problem:
    """What to optimise (see the module docstring).

    Attributes
    ----------
    base_table
        The base design's TOML tables.
    variables
        The design variables.
    objectives, constraints
        Parsed expressions (one objective: a single-objective search; several: a Pareto set).
    model
        Model tier (one of :data:`MODELS`).
    load
        Load case the expressions read (``cap`` or ``lumen``).
    pressures
        Pressures every design is evaluated at [MPa] (ascending; ``at p=NUM`` pressures
        included). The spelling ``pressures_MPa`` is deprecated.
    section_options
        Options of the section model (``mesh_size``, ``coil_bending``).
    options
        Tier name -> its options (:attr:`softcath.models.Tier.options`), over ``section_options``.
    """

    base_table: Mapping[str, Any]
    variables: tuple[Variable, ...]
    objectives: tuple[Objective, ...]
    constraints: tuple[Constraint, ...]
    model: str
    load: str
    pressures: tuple[float, ...]
    section_options: Mapping[str, Any] = field(default_factory=dict)
    options: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)

    @property
    def evaluator(self) -> str:
        return self.model

    @property
    def paths(self) -> tuple[str, ...]:
        return tuple(v.path for v in self.variables)

    def parameters(self, unit: Sequence[float]) -> dict[str, float]:
        """``{path: value}`` of the design at unit coordinates ``unit``."""
        return {v.path: v.value(u) for v, u in zip(self.variables, unit, strict=True)}


def parse_variable(text: str) -> Variable:
    """``PATH=LO:HI`` -> :class:`Variable` (errors name ``vary.PATH``)."""
    path, sep, spec = text.partition("=")
    path = path.strip()
    if not path or not sep:
        raise DesignError("vary", text, "must be PATH=LO:HI")
    parts = spec.split(":")
    if len(parts) != 2:
        raise DesignError(f"vary.{path}", spec, "must be LO:HI")
    try:
        low, high = float(parts[0]), float(parts[1])
    except ValueError:
        raise DesignError(f"vary.{path}", spec, "LO and HI must be numbers") from None
    if not (math.isfinite(low) and math.isfinite(high)):
        raise DesignError(f"vary.{path}", spec, "LO and HI must be finite")
    if max(abs(low), abs(high)) > MAX_MAGNITUDE:  # the rule of every number of a design
        raise DesignError(f"vary.{path}", spec, f"LO and HI must be within ±{MAX_MAGNITUDE:g} (mm, MPa)")
    if not high > low:
        raise DesignError(f"vary.{path}.high", high, f"must be > low = {low:g}")
    return Variable(path, low, high)


def _available_evaluators() -> tuple[str, ...]:

    return tuple(EVALUATORS)


#: Where a refused column name points the user (optimise writes no columns.json).
_LISTED = (
    "the columns are a sweep's result columns (e.g. bend_angle_deg, curvature_per_mm, elongation, "
    "max_strain, bend_per_MPa_deg) and the --vary paths"
)


def _check_numeric(base_table: Mapping[str, Any], v: Variable) -> None:
    """Refuse a variable whose field is not a number (a material name, a flag): LO:HI means nothing there."""
    node: Any = base_table
    for part in v.path.split("."):
        node = node.get(part) if isinstance(node, Mapping) else None
    if node is not None and (isinstance(node, bool) or not isinstance(node, (int, float))):
        raise DesignError(
            f"vary.{v.path}",
            f"{v.low:g}:{v.high:g}",
            f"{v.path} is {node!r}, not a number: only numeric fields vary between LO and HI "
            "(compare materials with separate runs)",
        )


def _parsed(param: str, text: str, parse):
    """``parse(text)`` with a refusal said as ``param = text: why`` (the option names the expression)."""
    try:
        return parse(text)
    except SelectionError as exc:
        raise DesignError(param, text, without_text(str(exc), text)) from None


def _pressure(param: str, value, p) -> float:
    """One rule for every pressure of a search, from ``pressures`` or an ``at p=`` of ``param``."""
    if (
        isinstance(p, bool)
        or not isinstance(p, (int, float))
        or not math.isfinite(p)
        or not 0 <= p <= MAX_PRESSURE_MPA
    ):
        where = "" if param == "pressures" else f"at p={p:g}: "
        raise DesignError(
            param,
            value,
            f"{where}pressures must be finite and in [0, {MAX_PRESSURE_MPA:g}] MPa (the sweep tiers inflate "
            "the lumen; suction is not modelled)",
        )
    return float(p)


@renamed_keyword(old="pressures_MPa", new="pressures")
def make_problem(
    base_table: Mapping[str, Any],
    *,
    variables: Sequence[Variable | str],
    objectives: Sequence[str],
    constraints: Sequence[str] = (),
    model: str = "section",
    load: str = "lumen",
    pressures: Sequence[float] = (0.5,),
    section_options: Mapping[str, Any] | None = None,
    options: Mapping[str, Mapping[str, Any]] | None = None,
) -> Problem:
    """A checked :class:`Problem`; every error names the parameter, its value and the bound.

    ``options`` are tier name -> options (:func:`softcath.models.check_tier_options`) of the
    tiers the search runs: ``model`` and the paper's formula beside it.
    """

    model = tier_name(model, allowed=MODELS)
    if model not in _available_evaluators():
        raise DesignError(
            "model", model, "this installation's sweep has no such evaluator yet; use section or paper"
        )
    if load not in ("cap", "lumen"):
        raise DesignError("load", load, "must be cap or lumen")
    check_assembly(model, base_table.get("assembly"))
    vs = tuple(v if isinstance(v, Variable) else parse_variable(v) for v in variables)
    if not vs:
        raise DesignError("variables", [], "give at least one design variable PATH=LO:HI")
    seen: set[str] = set()
    for v in vs:
        if v.path in seen:
            raise DesignError(f"vary.{v.path}", v.path, "is given twice")
        seen.add(v.path)
        try:
            check_path(base_table, v.path)
        except DesignError as exc:
            raise DesignError(f"vary.{v.path}", v.path, exc.bound) from None
        _check_numeric(base_table, v)
    if not objectives:
        raise DesignError("objectives", [], "give at least one objective, e.g. 'maximise bend_angle_deg'")
    objs = tuple(_parsed("objectives", o, parse_objective) for o in objectives)
    cons = tuple(_parsed("constraints", c, parse_constraint) for c in constraints)
    ps = set()
    for p in pressures:
        ps.add(_pressure("pressures", p, p))
    for param, items in (("objectives", objs), ("constraints", cons)):
        for item in items:
            if item.where and item.where.startswith("p="):
                ps.add(_pressure(param, item.text, at_pressure(item.where, item.text)))
    known = set(COLUMN_UNITS) | {v.path for v in vs}
    for param, items in (("objectives", objs), ("constraints", cons)):
        for item in items:
            _parsed(param, item.text, lambda _, it=item: check_columns([it], known, listed=_LISTED))
    if not any(p > 0 for p in ps):
        raise DesignError("pressures", sorted(ps), "must include a pressure > 0")
    return Problem(
        base_table=base_table,
        variables=vs,
        objectives=objs,
        constraints=cons,
        model=model,
        load=load,
        pressures=tuple(sorted(ps)),
        section_options=dict(section_options or {}),
        options=check_tier_options(options, parameter="options", tiers=sorted({"paper", model})),
    )
