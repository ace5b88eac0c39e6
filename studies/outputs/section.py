"""The 2-D section model's result files: ``section.json``, ``section.csv`` and the figures.

:func:`section_run` solves a design's section (and, for coil-bound coils, its
bilinear bend curve) through a pressure range and returns a :class:`SectionRun`;
:func:`write_section_result` (or :meth:`SectionRun.write`) writes the files
``softcath section`` writes, all or none:

- ``section.json``: the gains per MPa under the chosen load, the section stiffness,
  neutral axis, lumen-area change, the ratio to the paper's formula, run facts, every
  load's gains under ``loads`` and, for coil-bound coils, a ``coil_bound`` block;
- ``section.csv``: pressure, curvature, elongation, bend angle and tip pose (eq. 9);
- ``section.png``: the section deformed at the highest pressure (when fields were kept);
- ``section_curve.png``: the coil-bound curve against the linear model.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softcath.analytic import BeamResponse
from softcath.core.atomic import Outputs, prepare_out_dir
from softcath.core.plotting import pyplot
from softcath.fem.section_model import BilinearCoilCurve, SectionResult, bend_curve, section_model
from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS
from softcath.fem.section_model.picture import section_picture
from softcath.studies.model_validity import check_finite_columns, warn_linear_range
from softcath.studies.outputs.tables import range_text, write_rows

__all__ = ["CSV_COLUMNS", "SectionRun", "curve_response", "section_run", "write_section_result"]

#: ``section.csv``'s columns (the ``analytic.csv`` columns).
CSV_COLUMNS = ("pressure_MPa", "curvature_per_mm", "elongation", "bend_angle_rad", "tip_x_mm", "tip_y_mm")
#: ``section.json``'s run facts, copied from :meth:`SectionResult.to_json`.
_FACTS = (
    "EA_N",
    "EI_N_mm2",
    "EI_lateral_N_mm2",
    "coupling_N_mm",
    "neutral_axis_mm",
    "axial_centroid_mm",
    "lumen_area_mm2",
    "poisson_ratio_silicone",
    "coil_modulus",
    "coil_bending",
    "mesh_size_mm",
    "segments",
    "dofs",
    "n_triangles",
    "seconds",
    "mesh_seconds",
    "backward_error",
    "stiffness",
)
#: The per-load gains ``section.json`` lists under ``loads``.
_PER_LOAD = (
    "curvature_per_mm_per_MPa",
    "elongation_per_MPa",
    "lumen_area_change_mm2_per_MPa",
    "fem_formula_ratio",
)


@dataclass(frozen=True)
class SectionRun:
    """A design's section through a pressure range: what ``softcath section`` writes.

    Attributes
    ----------
    result
        The linear section model (its gains, stiffness and, if kept, fields).
    load
        ``"lumen"`` or ``"cap"``.
    pressures
        The pressures [MPa] of the table.
    response
        Curvature, elongation, bend angle and tip pose at each pressure (the bilinear
        curve's when ``curve`` is given).
    curve
        The coil-bound (bilinear) curve, or None for linear coils.
    """

    result: SectionResult
    load: str
    pressures: np.ndarray
    response: BeamResponse
    curve: BilinearCoilCurve | None = None

    def to_json(self) -> dict:
        """``section.json``: the gains under the load, stiffness and mesh facts, every load's gains."""
        r, ld = self.result, self.load
        full = r.to_json()
        doc = {
            "design": r.design_name,
            "load": ld,
            "curvature_per_mm_per_MPa": r.curvature_per_mm_per_MPa[ld],
            "elongation_per_MPa": r.elongation_per_MPa[ld],
            "lumen_area_change_mm2_per_MPa": r.lumen_area_change_mm2_per_MPa[ld],
            "fem_formula_ratio": r.fem_formula_ratio[ld],
            **{k: full[k] for k in _FACTS},
            "assembly": full["assembly"],
            "axial_groups": full["axial_groups"],
            "loads": {k: full[k] for k in _PER_LOAD},
        }
        if self.curve is not None:
            doc["coil_bound"] = self.curve.to_json()
        return doc

    def to_table(self) -> list[tuple[float, ...]]:
        """``section.csv``'s rows, one per pressure, in :data:`CSV_COLUMNS` order."""
        s = self.response
        return list(zip(s.pressure, s.curvature, s.elongation, s.bend_angle, s.tip_x, s.tip_y, strict=True))

    def write(self, folder: str | Path, *, picture: bool = True) -> tuple[str, ...]:
        """Write the result files into ``folder``; return their names (see :func:`write_section_result`)."""
        return write_section_result(self, folder, picture=picture)


def section_run(
    design,
    pressures,
    *,
    load: str = "lumen",
    silicone_poisson: float | None = None,
    mesher: str = "template",
    mesh_size: float | None = None,
    segments: int | None = None,
    coil_options: dict | None = None,
    coil_bound: str | None = None,
    initial_tension: tuple[float, float] | None = None,
    keep_fields: bool = True,
) -> SectionRun:
    """Solve ``design``'s section and its response at ``pressures`` [MPa].

    Warns (log) when the response leaves the linear model's range.

    Parameters
    ----------
    design
        A :class:`~softcath.design.TipDesign`.
    pressures
        The table's pressures [MPa].
    load
        ``"lumen"`` (wall + cap, the real load) or ``"cap"`` (the paper's cap force).
    silicone_poisson, mesher, mesh_size, segments, coil_options
        Passed to :func:`~softcath.fem.section_model.section_model` (``coil_options``:
        its ``coil_modulus``/``coil_bending`` keywords); the mesh defaults are the model's.
    coil_bound
        ``"annulus"`` or ``"resolved"``: solve the coils' bilinear (coil-bound) curve with
        that placement (:func:`~softcath.fem.section_model.bend_curve`); None: linear coils.
    initial_tension
        The coils' initial tension [N] (outer coil, channel) for the bilinear curve.
    keep_fields
        Keep the section's fields (needed for ``section.png``).

    Raises
    ------
    DesignError
        ``pressures`` give a non-finite response (named ``pressures``).
    """
    p = np.asarray(pressures, dtype=float)
    mesh = {
        "mesh_size": MESH_SIZE if mesh_size is None else mesh_size,
        "segments": SEGMENTS if segments is None else segments,
    }
    r = section_model(
        design,
        silicone_poisson=silicone_poisson,
        keep_fields=keep_fields,
        mesher=mesher,
        **mesh,
        **(coil_options or {}),
    )
    curve = None
    if coil_bound is not None:
        curve = bend_curve(
            design,
            p.tolist(),
            load=load,
            coil_model=coil_bound,
            initial_tension=initial_tension,
            silicone_poisson=silicone_poisson,
            **mesh,
        )
    resp = r.response(p, load) if curve is None else curve_response(curve, r.length_mm)
    columns = {
        "curvature_per_mm": resp.curvature,
        "elongation": resp.elongation,
        "bend_angle_rad": resp.bend_angle,
    }
    check_finite_columns(columns, param="pressures", value=range_text(p))
    model = "the section model (linear)" if curve is None else "the bilinear section model"
    warn_linear_range(p, resp.bend_angle, elongation=resp.elongation, model=model)
    return SectionRun(result=r, load=load, pressures=p, response=resp, curve=curve)


def write_section_result(run: SectionRun, folder: str | Path, *, picture: bool = True) -> tuple[str, ...]:
    """Write ``section.json``, ``section.csv`` and the figures of ``run`` into ``folder``.

    All files or none (:class:`~softcath.core.atomic.Outputs`). ``section.png`` needs the
    section's fields (``section_run(..., keep_fields=True)``); ``section_curve.png`` is
    drawn for a coil-bound curve. ``picture=False`` writes no figure.

    Returns
    -------
    tuple of str
        The names written, in order.
    """
    names = ["section.json", "section.csv"]
    with Outputs(prepare_out_dir(folder, param="folder")) as o:
        o.json("section.json", run.to_json())
        write_rows(o.path("section.csv"), CSV_COLUMNS, run.to_table())
        if picture:
            p = run.pressures
            p_show = float(max(abs(p.max()), abs(p.min()))) or 0.1
            section_picture(run.result, o.path("section.png"), load=run.load, pressure=p_show)
            names.append("section.png")
            if run.curve is not None:
                curve_picture(run.curve, run.result, o.path("section_curve.png"))
                names.append("section_curve.png")
    return tuple(names)


def curve_response(curve: BilinearCoilCurve, length_mm: float) -> BeamResponse:
    """The bilinear curve as a :class:`~softcath.analytic.BeamResponse`: its tip pose by eq. 9.

    The arc is the bending length ``length_mm`` stretched by the curve's elongation.
    """
    r = curve.to_response(length_mm=length_mm)
    length = length_mm * (1 + curve.elongation)
    return BeamResponse(
        curve.pressure, curve.curvature, curve.elongation, length, r.bend_angle_rad, r.tip_x_mm, r.tip_y_mm
    )


def curve_picture(curve: BilinearCoilCurve, result: SectionResult, path: str | Path) -> None:
    """Curvature against pressure: the bilinear curve, its threshold and the linear model."""
    plt = pyplot()
    p = np.sort(curve.pressure)
    order = np.argsort(curve.pressure)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.plot(p, curve.curvature[order], "o-", label=f"coil-bound ({curve.coil_model})")
    ax.plot(p, result.curvature_per_mm_per_MPa[curve.load] * p, "--", label=f"linear, {result.coil_bending}")
    if curve.threshold_pressure > 0:
        ax.axvline(curve.threshold_pressure, color="0.6", lw=0.8)
        ax.annotate(
            f"threshold {curve.threshold_pressure:.3g} MPa", (curve.threshold_pressure, 0), fontsize=8
        )
    ax.set_xlabel("pressure [MPa]")
    ax.set_ylabel("curvature [1/mm]")
    ax.set_title(f"{curve.design_name}, {curve.load} load, F0 = {curve.initial_tension[0]:g} N")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
