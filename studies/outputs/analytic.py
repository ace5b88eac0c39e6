"""A design's curvature, elongation and tip pose over a pressure range: ``analytic.csv/.json/.png``.

:func:`analytic_run` answers with the paper's formula (eqs. 4, 7, 9, the reference)
or the 2-D section model and returns an :class:`AnalyticRun`, whose
:meth:`~AnalyticRun.write` writes what ``softcath analytic`` writes: the CSV columns
of :data:`COLUMNS`, the picture and a JSON naming the model, its tier, its load and
why that load.

The load: the paper's formula is defined for the cap load (the end-cap force on the
composite beam), so the paper model takes the cap load and says so; the section model
takes the real load (lumen wall + cap). A load asked for overrides, with the reason.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softcath import analytic, models
from softcath.analytic import BeamResponse
from softcath.core.atomic import Outputs, prepare_out_dir
from softcath.fem.section_model import section_model
from softcath.studies.model_validity import check_finite_columns, warn_linear_range
from softcath.studies.outputs.tables import range_text, write_rows
from softcath.studies.plots import analytic_plot

__all__ = ["COLUMNS", "DEFAULT_LOAD", "MODELS", "AnalyticRun", "analytic_run", "load_and_reason"]

#: The models a run takes: the closed form (the paper's formula) and the linear section model.
MODELS = tuple(t.name for t in models.tiers() if t.closed_form or (t.section_mesh and t.linear))
#: Why a model runs under its own load: the formula's load by definition, or the real one.
_OWN_LOAD_REASON = {
    True: "the paper's formula is defined for the cap load, the end-cap force",
    False: "the real load, lumen wall + cap",
}
#: Why a load other than the model's own, as asked: the formula's lumen variant, or the cap load alone.
_ASKED_LOAD_REASON = {
    True: (
        "as asked; the paper's formula is defined for the cap load, its lumen variant is the "
        "wall effect alone"
    ),
    False: "as asked: the paper's end-cap force alone",
}
#: The load each model takes unless one is asked for, and why (written to ``analytic.json``).
DEFAULT_LOAD = {n: (models.get(n).default_load, _OWN_LOAD_REASON[models.get(n).closed_form]) for n in MODELS}
#: ``analytic.csv``'s columns and their units.
COLUMNS = {
    "pressure_MPa": "MPa",
    "curvature_per_mm": "1/mm",
    "elongation": "-",
    "bend_angle_rad": "rad",
    "tip_x_mm": "mm",
    "tip_y_mm": "mm",
}


@dataclass(frozen=True)
class AnalyticRun:
    """A design's response over a pressure range on the paper's formula or the section model.

    Attributes
    ----------
    design_name, model, load, load_reason
        The design, the model's tier name (one of :data:`MODELS`), the load it ran under and why.
    what
        The model in words, with its load (and, for the section model, its ratio to the formula).
    response
        Curvature, elongation, bend angle and tip pose (eq. 9) at each pressure.
    """

    design_name: str
    model: str
    load: str
    load_reason: str
    what: str
    response: BeamResponse

    def to_table(self) -> list[tuple[float, ...]]:
        """``analytic.csv``'s rows, one per pressure, in :data:`COLUMNS` order."""
        r = self.response
        return list(zip(r.pressure, r.curvature, r.elongation, r.bend_angle, r.tip_x, r.tip_y, strict=True))

    def to_json(self) -> dict:
        """``analytic.json``: the design, model, tier, load and why, the columns' units."""
        return {
            "design": self.design_name,
            "model": self.model,
            "tier": self.model,
            "load": self.load,
            "load_reason": self.load_reason,
            "columns": dict(COLUMNS),
            "csv": "analytic.csv",
        }

    def write(self, folder: str | Path) -> tuple[str, ...]:
        """Write ``analytic.csv``, ``analytic.png`` and ``analytic.json`` into ``folder``, all or none."""
        with Outputs(prepare_out_dir(folder, param="folder")) as o:
            write_rows(o.path("analytic.csv"), list(COLUMNS), self.to_table())
            analytic_plot(o.path("analytic.png"), self.response, title=f"{self.design_name}: {self.what}")
            o.json("analytic.json", self.to_json())
        return ("analytic.csv", "analytic.png", "analytic.json")


def load_and_reason(model: str, given: str | None) -> tuple[str, str]:
    """The load ``model`` runs under and why: the one asked for, else the model's own."""
    tier = models.get(model, allowed=MODELS)
    if given is None or given == tier.default_load:
        return tier.default_load, _OWN_LOAD_REASON[tier.closed_form]
    return given, _ASKED_LOAD_REASON[tier.closed_form]


def analytic_run(design, pressures, *, model: str = "paper", load: str | None = None) -> AnalyticRun:
    """``design``'s response at ``pressures`` [MPa] on ``model`` (one of :data:`MODELS`).

    ``load`` (``"cap"``/``"lumen"``) overrides the model's own (:data:`DEFAULT_LOAD`). Warns
    (log) when the response leaves the linear range.

    Raises
    ------
    DesignError
        A ``model`` not of :data:`MODELS` (``model``), an as-built ``design`` on a tier that
        answers bonded tips only (``assembly``), or
        ``pressures`` that give a non-finite response (``pressures``).
    """
    p = np.asarray(pressures, dtype=float)
    tier = models.get(model, allowed=MODELS)
    model = tier.name
    tier.check_assembly(design.assembly)
    ld, why = load_and_reason(model, load)
    if tier.closed_form:
        r = analytic.response(design, p, load=ld)
        what = f"paper's formula ({ld} load)"
    else:  # the linear section-mesh tier of MODELS: the section model
        sm = section_model(design, loads=(ld,))
        r = sm.response(p, ld)
        what = f"section model ({ld} load, {sm.fem_formula_ratio[ld]:.3g}x the paper's formula)"
    values = (r.pressure, r.curvature, r.elongation, r.bend_angle, r.tip_x, r.tip_y)
    check_finite_columns(dict(zip(COLUMNS, values, strict=True)), param="pressures", value=range_text(p))
    warn_linear_range(p, r.bend_angle, elongation=r.elongation, model=f"the {what.split(' (')[0]} (linear)")
    return AnalyticRun(design_name=design.name, model=model, load=ld, load_reason=why, what=what, response=r)
