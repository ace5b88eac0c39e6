"""The ``section`` tier's evaluator: the 2-D section model (``softcath.fem.section_model``) as sweep columns.

The tier (:mod:`softcath.models.section`) and the sweep's results (its column names) share it.

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

from softcath.analytic import response_from_gains
from softcath.core.interrupts import raise_pending_stop
from softcath.fem.section_model import batch, section_model
from softcath.fem.section_model.end_zones import tip_pose_arrays
from softcath.fem.section_model.strain import silicone_strain_range

__all__ = [
    "SECTION_KEYS",
    "SECTION_OPTIONS",
    "section_blocks_many",
    "section_columns",
    "section_result",
]

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
    t0 = time.perf_counter()
    r = section_result(design, loads, options, keep_fields=True)
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


def section_result(design, loads: tuple[str, ...], options: dict | None = None, *, keep_fields: bool = False):
    """The section model of one design with the tier's ``options`` (those set: ``None`` is the default).

    The one way the tier's options reach :func:`~softcath.fem.section_model.section_model`: the
    columns above and the tier's record (:meth:`softcath.models.section.SectionTier.record`) use it.
    """
    opts = {k: v for k, v in (options or {}).items() if v is not None}
    return section_model(design, loads=loads, keep_fields=keep_fields, **opts)


def section_blocks_many(
    designs: list, pressures: np.ndarray, loads: tuple[str, ...], options: dict | None = None
) -> tuple[dict, dict[int, Exception]]:
    """The section columns of many designs as blocks, and the designs' failures.

    Returns
    -------
    cols
        ``{load: {column: array (n_designs, n_pressures)}}``, NaN rows for the failed designs.
    errors
        ``{design index: the exception it raised}``, in design order.

    With the template mesher (the default) the designs go through the batched section
    models (``softcath.fem.section_model.batch``: one kernel per template, factorisations
    reused), whose answers are the section model's on the same meshes; with
    ``mesher = "gmsh"`` each design is solved alone by :func:`section_columns`.
    """
    opts = {k: v for k, v in (options or {}).items() if v is not None}
    cols = {ld: {k: np.full((len(designs), pressures.size), np.nan) for k in SECTION_KEYS} for ld in loads}
    errors: dict[int, Exception] = {}
    if opts.pop("mesher", "template") == "gmsh":
        for j, d in enumerate(designs):
            try:
                values = section_columns(d, pressures, loads, {**opts, "mesher": "gmsh"})
            except Exception as exc:  # reported per design by the caller
                raise_pending_stop()
                errors[j] = exc
                continue
            for ld, block in cols.items():
                for k, v in values[ld].items():
                    block[k][j] = v
        return cols, errors

    items = batch.section_models(designs, loads=loads, **opts)
    errors = {j: item for j, item in enumerate(items) if isinstance(item, Exception)}
    good = [j for j in range(len(items)) if j not in errors]
    if good:
        for ld, block in _response_blocks([items[j] for j in good], pressures, loads).items():
            for k, v in block.items():
                cols[ld][k][good] = v
    return cols, errors


def _response_blocks(items: list, pressures: np.ndarray, loads: tuple[str, ...]) -> dict:
    """:func:`section_columns`' columns of batched section models, over all designs at once.

    One :func:`~softcath.analytic.response_from_gains` on (designs, pressures) arrays, the
    computation of :meth:`SectionResult.response`: ~250 designs a task would otherwise make
    2 x 250 response objects of 3 values each.
    """
    p = np.asarray(pressures, dtype=float)[None, :]
    results = [it.result for it in items]
    length0 = np.array([[r.length_mm] for r in results], dtype=float)
    seconds = np.array([[r.seconds] for r in results], dtype=float)
    # the tip's angle and pose: the end zones of each design (the gains are mid-span)
    plug = np.array([[r.end_zones.plug_mm] for r in results], dtype=float)
    sv = np.array([[r.end_zones.saint_venant_mm] for r in results], dtype=float)
    out = {}
    for ld in loads:
        gains = np.array([r.gains(ld) for r in results], dtype=float).reshape(-1, 2)
        low, high = np.array([it.strain_range[ld] for it in items], dtype=float).reshape(-1, 2).T
        r = response_from_gains(gains[:, :1], gains[:, 1:], length0, p)
        tip_x, tip_y, angle = tip_pose_arrays(
            r.curvature, r.elongation, length=length0, plug=plug, saint_venant=sv
        )
        ratio = np.array([[r_.fem_formula_ratio[ld]] for r_ in results], dtype=float)
        out[ld] = {
            "curvature_section_per_mm": r.curvature,
            "elongation_section": r.elongation,
            "bend_angle_section_rad": angle,
            "tip_x_section_mm": tip_x,
            "tip_y_section_mm": tip_y,
            "max_strain_section": np.where(p >= 0, p * high[:, None], p * low[:, None]),
            "section_formula_ratio": np.broadcast_to(ratio, r.curvature.shape),
            "section_seconds": np.broadcast_to(seconds, r.curvature.shape),
        }
    return out
