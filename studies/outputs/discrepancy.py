"""The missing-effect workflows' runs and records: ``discrepancy.json`` (and ``report.html``).

:func:`discrepancy_run` runs the missing-effect workflow against a measurement or the
3-D FEM, going on to the physical ingredients when asked; :func:`write_discrepancy`
writes its record and page together. :func:`prototype_run` asks which model
ingredients explain a measured curve of a built design; :func:`write_prototype_record`
writes its ``discrepancy.json``. These are the files ``softcath discrepancy`` writes.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path

from softcath import design as design_room
from softcath import models
from softcath.core.atomic import Outputs, prepare_out_dir, staged_dir, unstage
from softcath.design.errors import DataError
from softcath.studies.discrepancy import DiscrepancyResult, run_workflow, write_report
from softcath.studies.discrepancy.prototype import explain_prototype, load_prototype_csv, tip_level_factor
from softcath.studies.discrepancy.to_physics import physical_step
from softcath.studies.discrepancy.workflow import fem_reference

__all__ = ["discrepancy_run", "prototype_run", "write_discrepancy", "write_prototype_record"]


def discrepancy_run(
    data,
    design,
    *,
    reference: str = "measured",
    margin: float | None = None,
    max_effects: int = 3,
    candidates: Sequence[str] | None = None,
    excitation: str = "auto",
    physical: bool = False,
    progress: bool = False,
    options=None,
) -> DiscrepancyResult:
    """The missing-effect workflow of ``design`` against ``data``.

    The keywords are :func:`softcath.studies.discrepancy.run_workflow`'s. With
    ``reference="fem"`` and no ``data`` the 3-D FEM is solved as the reference.
    ``physical`` (measured time series only) adds the physical step
    (:func:`~softcath.studies.discrepancy.to_physics.physical_step`). ``options`` (tier name ->
    options) go to the paper's formula and to the 3-D FEM solved as the reference.

    Raises
    ------
    DataError
        No data where the reference needs it.
    """
    fem_fn = None
    if data is None and reference in models.TIERS:  # a model as the reference (the 3-D FEM) is solved
        fem_fn = fem_reference(models.options_of(options, "fem"))
        if fem_fn is None:
            raise DataError(
                "--reference fem: no FEM table given and fem.check is not "
                "available; pass a CSV with pressure_MPa, curvature_per_mm"
            )
    if reference == "measured" and data is None:
        raise DataError("a measurement CSV is required")
    result = run_workflow(
        data,
        design,
        reference=reference,
        fem=fem_fn,
        margin=margin,
        max_effects=max_effects,
        candidates=None if candidates is None else tuple(candidates),
        progress=progress,
        excitation=excitation,
        options=options,
    )
    if reference == "measured" and physical and "quasi-static" not in {r["kind"] for r in result.runs}:
        result = dataclasses.replace(result, physical=physical_step(result, design_room.resolve(design)))
    return result


def write_discrepancy(result: DiscrepancyResult, folder: str | Path) -> Path:
    """Write ``discrepancy.json``, ``report.html`` and its figures; they replace earlier ones together.

    Returns the page's path.
    """
    out = Path(folder)
    with staged_dir(out) as stage:
        return unstage(write_report(result, stage), stage, out)


def prototype_run(
    design,
    measured_csv: str | Path,
    *,
    tip_factor: float | None = None,
    candidates: Sequence[str] | None = None,
    workers: int = 1,
    progress: bool = False,
) -> dict:
    """Which model ingredients explain the curve measured on the built ``design``.

    ``measured_csv`` holds pressure_MPa, curvature_per_mm[, elongation];
    ``tip_factor`` (tip-level over mid-span curvature) defaults to the 3-D FEM's
    (:func:`~softcath.studies.discrepancy.prototype.tip_level_factor`). Returns the
    ``discrepancy.json`` record of
    :func:`~softcath.studies.discrepancy.prototype.explain_prototype`.
    """
    measured = load_prototype_csv(measured_csv)
    d = design_room.resolve(design)
    factor = tip_level_factor(d) if tip_factor is None else tip_factor
    return explain_prototype(
        d,
        measured,
        tip_factor=factor,
        candidates=None if candidates is None else tuple(candidates),
        workers=workers,
        progress=progress,
    )


def write_prototype_record(record: dict, folder: str | Path) -> Path:
    """Write the prototype explanation's ``discrepancy.json`` into ``folder``; return its path."""
    with Outputs(prepare_out_dir(folder, param="folder")) as o:
        o.json("discrepancy.json", record)
    return Path(folder) / "discrepancy.json"
