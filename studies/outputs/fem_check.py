"""The FEM bending check's result files, with the paper's formula beside the 3-D answer.

:func:`fem_check` runs the linear 3-D check of one design at one pressure and load
and returns a :class:`FemCheck`, whose :meth:`~FemCheck.write` writes what
``softcath fem`` writes: ``fem.json`` (the check's keys, the as-built options, the
analytic values under the same load and ``paper_formula``), ``tip.vtu`` and, with
pictures, ``tip.png`` and ``tip.html``; with ``convergence`` the three-mesh study's
``convergence.csv``, ``convergence.json`` and ``convergence.png``
(:mod:`softcath.fem.mesh_study`). :func:`nonlinear_fem_check` runs the
finite-strain sweep (:func:`softcath.fem.nonlinear.outputs.run_check`) and gives its
``fem.json`` the same ``paper_formula`` block.

The paper's formula is the cap-load composite beam by definition (its lumen variant
is the wall effect alone, not the paper's prediction), so it is shown under the cap
load whatever load the FEM ran, as ``softcath analytic`` does.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

from softcath import analytic
from softcath.core.atomic import Outputs, prepare_out_dir, staged_dir
from softcath.core.errors import DataError
from softcath.design import TipDesign
from softcath.fem.api import FemCase, FemResult, check
from softcath.fem.export import render_png, write_vtu
from softcath.fem.html_view import write_tip_html
from softcath.fem.mesh_study import MeshStudy, mesh_study
from softcath.fem.nonlinear.outputs import NonlinearSettings, run_check
from softcath.fem.nonlinear.study import plot_study, write_study_csv
from softcath.studies.model_validity import warn_linear_range

__all__ = ["FemCheck", "fem_check", "nonlinear_fem_check", "paper_formula"]


@dataclass(frozen=True)
class FemCheck:
    """One linear FEM check: the design, its result and the load and pressure it ran at, and
    the three-mesh study it came from (None: one mesh and its companion)."""

    design: TipDesign
    result: FemResult
    load: str
    pressure: float
    study: MeshStudy | None = None

    @property
    def case(self) -> FemCase:
        """The check's answer at its load and pressure."""
        return self.result.case(self.load, self.pressure)

    def paper_formula(self) -> dict:
        """The paper's formula beside the check's curvature (see :func:`paper_formula`)."""
        return paper_formula(self.design, self.pressure, self.case.curvature_per_mm)

    def to_json(self) -> dict:
        """``fem.json``: the check's keys, the as-built options, the analytic and the paper's formula."""
        doc = self.result.to_json(self.load, self.pressure)
        doc["assembly"] = self.design.assembly.to_dict()
        doc["analytic"]["load"] = self.load  # the library's comparison is the formula under the same load
        doc["paper_formula"] = self.paper_formula()
        return doc

    def write(self, folder: str | Path, *, picture: bool = True) -> tuple[str, ...]:
        """Write ``fem.json``, ``tip.vtu``, (``picture``) ``tip.png``, ``tip.html`` and (a study)
        ``convergence.csv/.json/.png``, all or none."""
        names = ["fem.json", "tip.vtu"]
        sol, ld, p = self.result.solution, self.load, self.pressure
        if sol is None:  # a result read back from fem.json has numbers, no fields
            raise DataError("the FEM result keeps no solution fields: tip.vtu needs the check's own result")
        with Outputs(prepare_out_dir(folder, param="folder")) as o:
            o.json("fem.json", self.to_json())
            write_vtu(sol, ld, p, o.path("tip.vtu"))
            if picture:
                render_png(sol, ld, p, o.path("tip.png"))
                write_tip_html(sol, ld, p, o.path("tip.html"))
                names += ["tip.png", "tip.html"]
            if self.study is not None:
                write_study_csv(self.study, o.path("convergence.csv"))
                o.json("convergence.json", self.study.to_json())
                plot_study(self.study, o.path("convergence.png"))
                names += ["convergence.csv", "convergence.json", "convergence.png"]
        return tuple(names)


def fem_check(
    design,
    pressure: float,
    *,
    load: str = "lumen",
    mesh_size: float = 0.16,
    mesher: str = "gmsh",
    coil_modulus: str = "tension",
    use_cache: bool = True,
    progress=None,
    convergence: bool = False,
) -> FemCheck:
    """Run the linear FEM check of ``design`` at ``pressure`` [MPa] under ``load``.

    The keywords are :func:`softcath.fem.check`'s; ``convergence`` runs the three-mesh study
    (:func:`softcath.fem.mesh_study.mesh_study`, ``mesh_size`` in the middle) and answers with
    its middle mesh. Warns (log) when the answer leaves the linear range (bend angle, strain).
    """
    options = {"mesher": mesher, "coil_modulus": coil_modulus, "use_cache": use_cache, "progress": progress}
    study = None
    if convergence:
        study = mesh_study(design, [pressure], load=load, mesh_size=mesh_size, **options)
        result = study.result
    else:
        result = check(design, pressures=[pressure], loads=(load,), mesh_size=mesh_size, **options)
    c = result.case(load, pressure)
    warn_linear_range(pressure, c.bend_angle_rad, max_strain=c.max_strain, model="the linear FEM")
    return FemCheck(design=design, result=result, load=load, pressure=pressure, study=study)


def nonlinear_fem_check(design, settings: NonlinearSettings, folder: str | Path) -> tuple[dict, list[str]]:
    """The finite-strain sweep's files in ``folder``, its ``fem.json`` with ``paper_formula``.

    Every file appears only if the whole run succeeded. Returns the ``paper_formula``
    block and the sweep's summary lines (naming ``folder``).
    """
    out = Path(folder)
    with staged_dir(out) as stage:
        _, lines = run_check(design, settings, stage)
        path = stage / "fem.json"
        doc = json.loads(path.read_text(encoding="utf-8"))
        formula = {
            "pressure_MPa": doc["pressure_MPa"],
            **paper_formula(design, doc["pressure_MPa"], doc["curvature_per_mm"]),
        }
        doc["paper_formula"] = formula
        path.write_text(json.dumps(doc, indent=2), encoding="utf-8")
    return formula, [line.replace(str(stage), str(out)) for line in lines]


def paper_formula(design, pressure: float, curvature_per_mm: float) -> dict:
    """The paper's formula at ``pressure`` [MPa] beside a 3-D curvature [1/mm], under the cap load.

    Returns
    -------
    dict
        ``load`` ("cap"), ``curvature_per_mm``, ``elongation``, ``bend_angle_rad``,
        ``bend_angle_deg`` and ``ratio_fem_over_formula`` (None when the formula's
        curvature is 0).
    """
    ref = analytic.response(design, pressure, load="cap")
    k = float(ref.curvature)
    return {
        "load": "cap",
        "curvature_per_mm": k,
        "elongation": float(ref.elongation),
        "bend_angle_rad": float(ref.bend_angle),
        "bend_angle_deg": math.degrees(float(ref.bend_angle)),
        "ratio_fem_over_formula": curvature_per_mm / k if k else None,
    }
