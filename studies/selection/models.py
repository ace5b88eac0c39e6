"""Which model's columns the best-estimate columns mean, and under which load (see the package docstring)."""

from __future__ import annotations

from softcath.studies.criteria.expressions import SelectionError
from softcath.studies.sweep.results import MODEL_COLUMNS, has_model, model_columns
from softcath.studies.tiers import ALIASES, TIERS, tier_name

__all__ = ["MODEL_NAMES", "resolve_model"]

#: The tiers a sweep's results have best-estimate columns of (:data:`MODEL_COLUMNS`) -> their labels.
MODEL_NAMES = {n: TIERS[n].label for n in MODEL_COLUMNS}


def resolve_model(df, model: str | None = None, load: str | None = None):
    """``(table, model, load, note)``: the results with their best-estimate columns from one model.

    See the module docstring for the defaults; ``note`` says what was chosen
    for the user when it was not asked for.
    """
    loads = sorted(set(df["load"]))
    notes = []
    if model in ALIASES:
        model = tier_name(model)
    if model is None:
        if has_model(df, "section-nonlinear"):  # valid at every bend, small or large
            model = "section-nonlinear"
        elif has_model(df, "section"):
            model = "section"
        elif "curvature_analytic_per_mm" in df.columns:
            model = "paper"
            notes.append(
                "this sweep has no section-model results: ranked on the paper's formula (analytic model); "
                'add "section" to the sweep\'s evaluators for 3-D-FEM-grade curvature'
            )
    elif model not in MODEL_NAMES:
        raise SelectionError(f"model '{model}' is unknown; choose from {', '.join(MODEL_NAMES)}")
    elif not has_model(df, model):
        raise SelectionError(f"model '{model}': this sweep has no results of {MODEL_NAMES[model]}")
    if load is None:
        load = TIERS[model].default_load if model is not None else "cap"  # a plain table: the cap load
        if load not in loads:
            notes.append(f"the sweep has no {load} load: used {loads[0]}")
            load = loads[0]
    if model is not None:
        df = model_columns(df, model)
    return df, (model or "table"), load, "; ".join(notes)
