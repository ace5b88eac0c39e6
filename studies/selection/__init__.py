"""Design selection before fabrication: readable constraints and objectives over result columns.

Expressions
-----------
A constraint compares two arithmetic expressions over result columns::

    bend_angle_deg >= 90 at p_max
    max_strain <= 0.3
    outer_diameter_mm <= 0.8
    abs(rel_diff_curvature) < 0.2 at p=0.5

An objective names a direction and an expression::

    maximise bend_per_MPa_deg
    minimise elongation at p_max
    minimise abs_rel_diff_curvature

Columns are those of ``results.csv`` (swept parameters by their dotted path,
e.g. ``tube.h``). Allowed: numbers, ``+ - * /``, unary minus, ``abs()``, and
the comparisons ``< <= > >= == !=``. ``at p_max``, ``at p_min`` or ``at p=NUM``
picks the pressure row; without it a constraint must hold at every pressure
and an objective is taken at p_max. Rows where an expression is undefined
(NaN, e.g. a per-MPa value at 0 MPa, or FEM columns of an analytic-only
sweep) are skipped; a design with no defined row fails the constraint.

Model and load: the best-estimate columns ``curvature_per_mm``,
``elongation``, ``bend_angle_deg``, ``max_strain`` and ``bend_per_MPa_deg``
resolve to one model's columns (:func:`softcath.studies.sweep.results.model_columns`). By
default that is the finite-strain section model when the sweep ran it (valid
at every bend), else the section model under the lumen load (the real load)
when the sweep has section-model columns, else the paper's formula (analytic
model) under the cap load, with a note saying so; ``model`` and ``load``
choose explicitly (``paper``, ``section``, ``section-nonlinear`` or ``fem``;
``cap`` or ``lumen``). A bend constraint ranked on a linear tier whose designs
bend past its validity is re-checked with the finite-strain section model
(:func:`recheck_large_bends`).

Ranking: designs that fail (status) or break a constraint are dropped; the
rest are ordered Pareto front first (no other design is at least as good in
every objective and better in one), each group by the first objective.

Robust selection (:func:`robust_select`): the ranked designs are re-evaluated
over material and manufacturing ranges and kept when every constraint holds
with probability ≥ P, ranked on the objectives' p50.
"""

from __future__ import annotations

from softcath.studies.criteria import Constraint, Objective, parse_constraint, parse_objective
from softcath.studies.criteria.expressions import SelectionError
from softcath.studies.selection.large_bends import (
    LINEAR_BEND_LIMIT_DEG,
    large_bend_constraints,
    recheck_large_bends,
)
from softcath.studies.selection.models import MODEL_NAMES, resolve_model
from softcath.studies.selection.output import write_selection
from softcath.studies.selection.ranking import MAX_POINTS, Selection, pareto_front, select
from softcath.studies.selection.robust import robust_select, sweep_ranges

__all__ = [
    "Constraint",
    "Objective",
    "Selection",
    "SelectionError",
    "MAX_POINTS",
    "MODEL_NAMES",
    "parse_constraint",
    "parse_objective",
    "pareto_front",
    "resolve_model",
    "large_bend_constraints",
    "recheck_large_bends",
    "LINEAR_BEND_LIMIT_DEG",
    "robust_select",
    "select",
    "sweep_ranges",
    "write_selection",
]
