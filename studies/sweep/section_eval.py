"""The sweep's ``section`` evaluator: the 2-D section model (``softcath.fem.section_model``) per design.

The section model reproduces the 3-D FEM's mid-span curvature to a fraction of
a percent in ~0.1-0.3 s per design, so a sweep can carry FEM-grade curvature for
thousands of designs. Each design is solved once for every load of the sweep
(the response is linear in pressure); a design the section model cannot solve
is reported with its reason (``section failed: ...``) and never stops the task.
"""

from __future__ import annotations

import logging
import time

import numpy as np

from softcath.interrupts import raise_pending_stop

__all__ = ["SECTION_KEYS", "SECTION_OPTIONS", "section_columns", "section_columns_many"]

log = logging.getLogger(__name__)

#: Result columns of the section evaluator (per design x pressure x load).
SECTION_KEYS = (
    "curvature_section_per_mm",
    "elongation_section",
    "bend_angle_section_rad",
    "tip_x_section_mm",
    "tip_y_section_mm",
    "max_strain_section",
    "section_formula_ratio",
    "section_seconds",
)
#: Options a spec may set under ``[sweep.section]`` (passed to ``softcath.fem.section_model.section_model``).
SECTION_OPTIONS = ("mesh_size", "coil_bending", "mesher")


def section_columns(
    design, pressures: np.ndarray, loads: tuple[str, ...], options: dict | None = None
) -> dict:
    """``{load: {column: array over pressures}}`` of the section model for one design.

    ``section_formula_ratio`` is the section curvature over the paper's formula
    (eq. 7, cap load) of the same design; ``section_seconds`` the wall time of
    the section model for this design (mesh, assembly, solves, all loads);
    ``max_strain_section`` the largest principal strain in the silicone at
    mid-span (:func:`softcath.fem.section_model.strain.silicone_strain_range`).
    """
    from softcath.fem.section_model import section_model
    from softcath.fem.section_model.strain import silicone_strain_range

    opts = {k: v for k, v in (options or {}).items() if v is not None}
    t0 = time.perf_counter()
    r = section_model(design, loads=loads, keep_fields=True, **opts)
    out = {}
    for load in loads:
        resp = r.response(pressures, load)
        low, high = silicone_strain_range(r, load)
        out[load] = {
            "curvature_section_per_mm": np.asarray(resp.curvature, float),
            "elongation_section": np.asarray(resp.elongation, float),
            "bend_angle_section_rad": np.asarray(resp.bend_angle, float),
            "tip_x_section_mm": np.asarray(resp.tip_x, float),
            "tip_y_section_mm": np.asarray(resp.tip_y, float),
            "max_strain_section": np.where(pressures >= 0, pressures * high, pressures * low),
            "section_formula_ratio": np.full(pressures.shape, r.fem_formula_ratio[load]),
        }
    seconds = time.perf_counter() - t0
    for load in loads:
        out[load]["section_seconds"] = np.full(pressures.shape, seconds)
    return out


def section_columns_many(
    designs: list, pressures: np.ndarray, loads: tuple[str, ...], options: dict | None = None
) -> list:
    """:func:`section_columns` of many designs: per design its columns or the exception it raised.

    With the template mesher (the default) the designs go through the batched section
    models (``softcath.fem.section_model.batch``: one kernel per template, factorisations
    reused), whose answers are the section model's on the same meshes; with
    ``mesher = "gmsh"`` each design is solved alone.
    """
    opts = {k: v for k, v in (options or {}).items() if v is not None}
    if opts.pop("mesher", "template") == "gmsh":
        out = []
        for d in designs:
            try:
                out.append(section_columns(d, pressures, loads, {**opts, "mesher": "gmsh"}))
            except Exception as exc:  # reported per design by the caller
                raise_pending_stop()
                out.append(exc)
        return out
    from softcath.fem.section_model.batch import section_models

    out = []
    for item in section_models(designs, loads=loads, **opts):
        if isinstance(item, Exception):
            out.append(item)
            continue
        r = item.result
        cols = {}
        for load in loads:
            resp = r.response(pressures, load)
            low, high = item.strain_range[load]
            cols[load] = {
                "curvature_section_per_mm": np.asarray(resp.curvature, float),
                "elongation_section": np.asarray(resp.elongation, float),
                "bend_angle_section_rad": np.asarray(resp.bend_angle, float),
                "tip_x_section_mm": np.asarray(resp.tip_x, float),
                "tip_y_section_mm": np.asarray(resp.tip_y, float),
                "max_strain_section": np.where(pressures >= 0, pressures * high, pressures * low),
                "section_formula_ratio": np.full(pressures.shape, r.fem_formula_ratio[load]),
                "section_seconds": np.full(pressures.shape, r.seconds),
            }
        out.append(cols)
    return out
