"""The finite-strain check of one design and its files: ``fem.json``, the sweep CSV, VTU series, PNGs.

:func:`run_check` runs :func:`~softcath.fem.nonlinear.bend.bend_curve` for one
:class:`NonlinearSettings` and writes, into one folder, ``fem.json`` (with the
linear check's keys), ``pressure_sweep.csv``, ``tip_series.pvd`` +
``vtu/step_XXX.vtu`` (ParaView opens the .pvd as an animation over pressure),
``deformed_tip.png`` and ``bend_curve.png``. ``softcath fem --nonlinear`` is
its command line (:mod:`softcath.cli.fem`).
"""

from __future__ import annotations

import csv
import json
import logging
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softcath import analytic
from softcath.core.plotting import pyplot
from softcath.fem.export import render_grid_png
from softcath.fem.nonlinear.convergence import MIN_ESTIMATE_LAYERS
from softcath.fem.nonlinear.errors import SettingError
from softcath.fem.nonlinear.post import max_principal_strain
from softcath.fem.nonlinear.reference import StatedError, estimate_section, reference_curve
from softcath.fem.nonlinear.study import convergence_study, write_study

__all__ = ["NonlinearSettings", "run_check", "write_outputs"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, kw_only=True)
class NonlinearSettings:
    """One finite-strain check: the pressure sweep and the mesh (defaults as in docs/nonlinear.md).

    Parameters
    ----------
    pressure : float
        Largest pressure [MPa]; the sweep is ``pressure * (1..steps) / steps``.
    steps : int
        Pressure steps of the sweep.
    load : {"lumen", "cap"}
        Lumen wall + sealed cap (the real load) or the cap force alone (the paper's formula).
    mesh_size : float
        Largest section triangle edge [mm].
    layers : int or None
        Element layers along the bending length; None: chosen from the expected bend
        (:func:`~softcath.fem.nonlinear.convergence.default_layers`).
    curvature_points : int
        Mesh segments per full circle.
    true_area : bool
        Area-true section polygons (``bend_curve``'s ``true_area``); default: plain inscribed ones.
    mixed : bool or None
        Mixed u-p (P2-P0) formulation for the silicones; None: when they are
        near-incompressible (:func:`~softcath.fem.nonlinear.bend.needs_mixed`).
    compare_linear : bool
        Report where the linear FEM and the analytic model depart from it by 5 %.
    convergence : bool
        Run the three-mesh study (L/2, L, 2L layers; :mod:`softcath.fem.nonlinear.study`)
        instead of the two-mesh error estimate.
    """

    pressure: float = 1.0
    steps: int = 8
    load: str = "lumen"
    mesh_size: float = 0.15
    layers: int | None = None
    curvature_points: int = 12
    true_area: bool = False
    mixed: bool | None = None
    compare_linear: bool = False
    convergence: bool = False

    def __post_init__(self) -> None:
        if not (math.isfinite(self.pressure) and self.pressure > 0):
            raise SettingError("pressure", self.pressure, "must be a finite pressure > 0 MPa")
        if not (isinstance(self.steps, int) and 1 <= self.steps <= 1000):
            raise SettingError("steps", self.steps, "must be an integer in [1, 1000]")
        if self.load not in ("lumen", "cap"):
            raise SettingError("load", self.load, "must be 'lumen' or 'cap'")
        if not (math.isfinite(self.mesh_size) and self.mesh_size > 0):
            raise SettingError("mesh_size", self.mesh_size, "must be > 0 mm")
        if self.layers is not None and not (isinstance(self.layers, int) and self.layers >= 1):
            raise SettingError("layers", self.layers, "must be an integer >= 1")
        if self.convergence and self.layers is not None and self.layers < MIN_ESTIMATE_LAYERS:
            raise SettingError(
                "layers", self.layers, f"must be >= {MIN_ESTIMATE_LAYERS} for a convergence study"
            )
        if self.curvature_points < 6:
            raise SettingError("curvature_points", self.curvature_points, "must be >= 6")

    @property
    def pressures(self) -> np.ndarray:
        """The sweep's pressures [MPa]."""
        return self.pressure * np.arange(1, self.steps + 1) / self.steps


def run_check(design, settings: NonlinearSettings, out: Path) -> tuple[dict, list[str]]:
    """Run the finite-strain sweep of ``design`` and write its files into ``out``.

    Returns the ``fem.json`` document and the human summary, line by line.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    s = settings
    t_start = time.perf_counter()
    curve, error, study_lines, tip = _solve_with_error(design, s, out)
    seconds = time.perf_counter() - t_start
    summary = write_outputs(curve, out, design_name=design.name, compare_linear=s.compare_linear, error=error)
    add_linear_check_keys(out / "fem.json", curve, design, seconds)
    _add_tip_estimate(out / "fem.json", tip)
    lines = [
        f"softcath fem --nonlinear: {design.name}, {curve.load} load, {curve.ndofs} DOFs, "
        f"{len(curve.result.steps)} steps, {curve.result.newton_iterations} Newton iterations",
        f"  at {s.pressure:g} MPa: bend angle {np.degrees(curve.bend_angle[-1]):.2f} deg nonlinear, "
        f"{np.degrees(curve.linear_bend_angle[-1]):.2f} deg linear FEM, "
        f"{np.degrees(curve.analytic_bend_angle[-1]):.2f} deg analytic",
    ]
    k_mid = curve.curvature_mid[-1]
    if np.isfinite(k_mid):
        w0, w1 = curve.midspan
        lines.append(
            f"  mid-span (Z/L {w0:g}-{w1:g}): curvature dtheta/ds {k_mid:.4g} 1/mm "
            f"(theta/s of the whole tip {curve.curvature[-1]:.4g}), "
            f"bend rate dtheta/dZ {curve.bend_rate_mid[-1]:.4g} rad/mm"
        )
    for k, v in summary.get("departure_5pct_deg", {}).items():
        lines.append(f"  {k} departs by 5 %: " + ("not within the sweep" if v is None else f"at {v:.1f} deg"))
    if error is not None and np.isfinite(error.relative[-1]):
        lines.append(_error_line(curve, error))
    if tip is not None and np.isfinite(tip.relative[-1]):
        lines.append(
            f"  tip angle: estimated discretisation error {100 * tip.relative[-1]:.2g} %, extrapolated "
            f"{np.degrees(tip.extrapolated[-1]):.2f} deg (end-zone deficit {tip.deficit[-1]:.3g} mm)"
        )
    lines.extend(study_lines)
    lines.append(f"  wrote {out}/fem.json, pressure_sweep.csv, tip_series.pvd, deformed_tip.png")
    return summary, lines


def _error_line(curve, error) -> str:
    """The summary line of the stated error: the total and its parts."""
    lay = error.layers_part
    line = (
        f"  {curve.layers} layers: estimated discretisation error of the mid-span curvature "
        f"{100 * error.relative[-1]:.2g} %: layers {100 * lay.relative[-1]:.2g} % (vs "
        f"{lay.coarse_layers} layers, order {lay.order:.2g} {lay.order_source})"
    )
    sec = error.section_part
    if sec is None:
        return line + ", section not estimated"
    (s1, n1) = sec.refined_section
    return line + (
        f" + section {100 * sec.relative:.2g} % (vs size {s1:.3g} mm, {n1} segments at "
        f"{sec.pressure:.2g} MPa, order {sec.order:g} {sec.order_source})"
    )


def _solve_with_error(design, s: NonlinearSettings, out: Path):
    """The sweep's curve, its error estimate (None below ``MIN_ESTIMATE_LAYERS`` layers), the study's
    summary lines and the tip angle's estimate (None from a three-mesh study or without a companion)."""

    opts = {
        "load": s.load,
        "size": s.mesh_size,
        "curvature_points": s.curvature_points,
        "true_area": s.true_area,
        "mixed": s.mixed,
        "progress": True,
    }
    if s.convergence:
        study = convergence_study(design, s.pressures, layers=s.layers, **opts)
        names = write_study(study, out)
        q, k = study.order[-1], study.extrapolated[-1]
        line = (
            f"  convergence ({'/'.join(map(str, study.layers))} layers): observed order {q:.3g}, "
            f"extrapolated mid-span curvature {k:.4g} 1/mm; wrote {', '.join(names)}"
        )
        curve = study.curves[1]
        stated = StatedError(study.error_estimate(), estimate_section(design, curve, **opts))
        return curve, stated, [line], None
    ref = reference_curve(design, s.pressures, layers=s.layers, **opts)
    return ref.curve, ref.stated, [], ref.tip


def _add_tip_estimate(path: Path, tip) -> None:
    """fem.json's ``tip_angle_error_estimate`` (relative, final pressure) and ``tip_angle_discretisation``
    (per pressure: the extrapolated tip angle, the end-zone deficit and the method), null without one."""
    doc = json.loads(path.read_text(encoding="utf-8"))
    doc["tip_angle_error_estimate"] = None if tip is None else _finite_or_none(tip.relative[-1])
    doc["tip_angle_discretisation"] = None if tip is None else tip.to_json()
    path.write_text(json.dumps(doc, indent=2), encoding="utf-8")


def _finite_or_none(x) -> float | None:
    x = float(x)
    return x if np.isfinite(x) else None


def add_linear_check_keys(path: Path, curve, design, seconds: float) -> None:
    """Give fem.json the keys of the linear check (``softcath fem``) at the final pressure."""

    doc = json.loads(path.read_text(encoding="utf-8"))
    p = float(curve.pressure[-1])
    ref = analytic.response(design, p, "cap")  # the paper's formula (eq. 7, cap load), as `softcath analytic`
    k_ref = float(ref.curvature)
    last = curve.result.steps[-1]
    doc.update(
        {
            "n_elements": int(curve.n_tets),
            "dofs": int(curve.ndofs),
            "residual": float(last.residuals[-1]) if len(last.residuals) else None,
            "solve_seconds": seconds,
            "analytic": {"curvature_per_mm": k_ref, "elongation": float(ref.elongation), "load": "cap"},
            "ratio_fem_over_analytic": float(curve.curvature[-1]) / k_ref if k_ref else None,
            # finite-strain counterparts: section-rotation profile, principal stretch strain
            "curvature_variation": _finite_or_none(curve.curvature_variation[-1]),
            "max_strain": _finite_or_none(curve.max_strain[-1]),
            "n_nodes": int(curve.n_nodes),
            "mesh_seconds": float(curve.mesh_seconds),
        }
    )
    path.write_text(json.dumps(doc, indent=2), encoding="utf-8")


def write_outputs(
    curve, out: Path, *, design_name: str = "design", compare_linear: bool = False, error=None
) -> dict:
    """Write fem.json, pressure_sweep.csv, the VTU series and the PNGs of ``curve`` into ``out``.

    Parameters
    ----------
    curve : softcath.fem.nonlinear.bend.NonlinearFemCurve
        The finite-strain sweep.
    out : pathlib.Path
        Output folder (created if missing).
    design_name : str
        Name written into ``fem.json``.
    compare_linear : bool
        Add the bend angles where the linear FEM and the analytic model depart by 5 %.
    error : softcath.fem.nonlinear.reference.StatedError or ErrorEstimate or None
        The stated discretisation error: ``discretisation_error_estimate`` in fem.json (final
        pressure), ``discretisation_error`` (per pressure, its parts and method) and columns of
        pressure_sweep.csv: the total and its layers and section parts (NaN/null without).

    Returns
    -------
    dict
        The ``fem.json`` document. Besides the final pressure's values it holds
        ``midspan``: the mid-span window (fractions of L), the reference (X, Y) of its
        centroid line (the axial-stiffness centroid) and, per pressure of the
        sweep, ``curvature_mid_per_mm`` (dθ/ds) and ``bend_rate_mid_per_mm`` (dθ/dZ),
        null where the mesh has too few z levels in the window.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    summary = _summary(curve, design_name, compare_linear)
    summary.update(_error_keys(curve, error))
    (out / "fem.json").write_text(json.dumps(summary, indent=2))
    _write_sweep_csv(curve, out / "pressure_sweep.csv", error)
    if curve.model is not None:
        write_vtu_series(curve, out)
        plot_deformed(curve, out / "deformed_tip.png")
    plot_curve(curve, out / "bend_curve.png")
    return summary


def _summary(curve, design_name: str, compare_linear: bool) -> dict:
    """The ``fem.json`` document of ``curve``."""
    k = -1
    summary = {
        "design": design_name,
        "nonlinear": True,
        "load": curve.load,
        "pressure_MPa": float(curve.pressure[k]),
        "bend_angle_rad": float(curve.bend_angle[k]),
        "curvature_per_mm": float(curve.curvature[k]),
        "curvature_mid_per_mm": _finite_or_none(curve.curvature_mid[k]),
        "bend_rate_mid_per_mm": _finite_or_none(curve.bend_rate_mid[k]),
        "elongation": float(curve.elongation[k]),
        "tip_x_mm": float(curve.tip_x[k]),
        "tip_y_mm": float(curve.tip_y[k]),
        "linear_bend_angle_rad": float(curve.linear_bend_angle[k]),
        "analytic_bend_angle_rad": float(curve.analytic_bend_angle[k]),
        "ndofs": int(curve.ndofs),
        "n_tets": int(curve.n_tets),
        "newton_iterations": int(curve.result.newton_iterations),
        "steps": [
            {
                "load_factor": s.load_factor,
                "pressure_MPa": s.pressures[0],
                "iterations": s.iterations,
                "residuals": list(s.residuals),
                "cutbacks": s.cutbacks,
            }
            for s in curve.result.steps
        ],
        "midspan": {
            "window_fraction_of_length": [float(x) for x in curve.midspan],
            "centroid_line_xy_mm": [_finite_or_none(x) for x in curve.midspan_axis],
            "pressure_MPa": [float(x) for x in curve.pressure],
            "curvature_mid_per_mm": [_finite_or_none(x) for x in curve.curvature_mid],
            "bend_rate_mid_per_mm": [_finite_or_none(x) for x in curve.bend_rate_mid],
        },
        "pressure_sweep_csv": "pressure_sweep.csv",
    }
    if compare_linear:
        dep = curve.departure(0.05)
        summary["departure_5pct_rad"] = dep
        summary["departure_5pct_deg"] = {
            kk: (None if v is None else float(np.degrees(v))) for kk, v in dep.items()
        }
    return summary


def _error_keys(curve, error) -> dict:
    """fem.json's ``layers``, ``mixed`` and ``discretisation_error_estimate`` (relative, final pressure)
    with ``discretisation_error`` (per pressure and how it was estimated)."""
    choice = getattr(curve, "layer_choice", None)
    keys = {
        "layers": getattr(curve, "layers", None),
        "layer_choice": None if choice is None else choice.to_json(),
        "mixed": bool(getattr(curve, "mixed", False)),
        "true_area": getattr(curve, "true_area", None),
    }
    if error is None:
        keys["discretisation_error_estimate"] = None
        keys["discretisation_error"] = {
            "method": f"not estimated: fewer than {MIN_ESTIMATE_LAYERS} layers (no half-layer mesh)"
        }
        return keys
    keys["discretisation_error_estimate"] = _finite_or_none(error.relative[-1])
    keys["discretisation_error"] = {"pressure_MPa": [float(x) for x in curve.pressure], **error.to_json()}
    return keys


def _write_sweep_csv(curve, path: Path, error=None) -> None:
    """One row per pressure of the sweep."""
    nan = np.full(curve.pressure.size, np.nan)
    rel = nan if error is None else np.asarray(error.relative, float)
    lay = nan if error is None else np.asarray(getattr(error, "layers_part", error).relative, float)
    sec = getattr(error, "section_part", None)
    sec = nan if sec is None else np.full(curve.pressure.size, sec.relative)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                "pressure_MPa",
                "bend_angle_rad",
                "bend_angle_deg",
                "curvature_per_mm",
                "curvature_mid_per_mm",
                "bend_rate_mid_per_mm",
                "elongation",
                "tip_x_mm",
                "tip_y_mm",
                "newton_iterations",
                "linear_fem_bend_angle_rad",
                "analytic_bend_angle_rad",
                "discretisation_error_estimate",
                "discretisation_error_layers",
                "discretisation_error_section",
            ]
        )
        for i in range(curve.pressure.size):
            w.writerow(
                [
                    f"{curve.pressure[i]:.9g}",
                    f"{curve.bend_angle[i]:.9g}",
                    f"{np.degrees(curve.bend_angle[i]):.6g}",
                    f"{curve.curvature[i]:.9g}",
                    f"{curve.curvature_mid[i]:.9g}",
                    f"{curve.bend_rate_mid[i]:.9g}",
                    f"{curve.elongation[i]:.9g}",
                    f"{curve.tip_x[i]:.9g}",
                    f"{curve.tip_y[i]:.9g}",
                    int(curve.newton_iterations[i]),
                    f"{curve.linear_bend_angle[i]:.9g}",
                    f"{curve.analytic_bend_angle[i]:.9g}",
                    f"{rel[i]:.3g}",
                    f"{lay[i]:.3g}",
                    f"{sec[i]:.3g}",
                ]
            )


def write_vtu_series(curve, out: Path) -> None:
    """One VTU per accepted load step (vertex displacements, region, von Mises) and a .pvd over pressure."""
    import pyvista as pv

    model = curve.model
    mesh = model.cmesh.mesh
    nv = mesh.p.shape[1]  # skfem numbers the P2 vertex DOFs first
    cells = np.hstack([np.full((mesh.t.shape[1], 1), 4), mesh.t.T]).ravel()
    celltypes = np.full(mesh.t.shape[1], pv.CellType.TETRA, dtype=np.uint8)
    (out / "vtu").mkdir(exist_ok=True)
    entries = []
    for i, (s, u) in enumerate(zip(curve.result.steps, curve.result.displacements, strict=True)):
        grid = pv.UnstructuredGrid(cells, celltypes, mesh.p.T.copy())
        grid.point_data["displacement_mm"] = u[:nv]
        grid.cell_data["region"] = model.cmesh.labels
        grid.cell_data["von_mises_MPa"] = model.body.element_stress(u.ravel())
        name = f"vtu/step_{i:03d}.vtu"
        grid.save(str(out / name))
        entries.append(f'    <DataSet timestep="{s.pressures[0]:.9g}" part="0" file="{name}"/>')
    (out / "tip_series.pvd").write_text(
        '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
        + "\n".join(entries)
        + "\n  </Collection>\n</VTKFile>\n"
    )


def deformed_grid(curve, step: int = -1):
    """A pyvista tet grid of ``curve``'s tip at load step ``step``, for pictures.

    Point data ``displacement`` [mm] (vertices); cell data ``region`` and
    ``max_principal_strain``: the largest principal stretch (Biot) strain
    λ_max − 1 of each element, the largest over its quadrature points (the
    measure of ``curve.max_strain``; it equals the linear FEM's principal
    strain to first order, so the two pictures compare).
    """
    import pyvista as pv

    model = curve.model
    mesh = model.cmesh.mesh
    nv = mesh.p.shape[1]  # skfem numbers the P2 vertex DOFs first
    u = np.asarray(curve.result.displacements[step])
    cells = np.hstack([np.full((mesh.t.shape[1], 1), 4), mesh.t.T]).ravel()
    grid = pv.UnstructuredGrid(
        cells, np.full(mesh.t.shape[1], pv.CellType.TETRA, dtype=np.uint8), mesh.p.T.copy()
    )
    grid.point_data["displacement"] = u.reshape(-1, 3)[:nv]
    grid.cell_data["region"] = model.cmesh.labels
    f = model.body.deformation_gradient(u.ravel(), np.arange(mesh.t.shape[1]))
    grid.cell_data["max_principal_strain"] = max_principal_strain(f).max(axis=1)
    return grid


def plot_deformed(curve, path: Path) -> None:
    """The tip at full pressure coloured by the largest principal stretch strain, as the linear FEM's tip.png.

    Rendered by :func:`softcath.fem.export.render_grid_png` (pyvista off-screen): the deformed half
    x >= 0 over the undeformed ghost, seen from +x.
    """

    render_grid_png(
        deformed_grid(curve),
        path,
        title=f"finite strain, {curve.load} load, p = {curve.pressure[-1]:g} MPa: "
        f"{np.degrees(curve.bend_angle[-1]):.1f} deg (true scale)",
        scalar_title="max principal stretch strain",
    )


def plot_curve(curve, path: Path) -> None:
    """Bend angle vs pressure: nonlinear FEM, linear FEM, analytic."""
    plt = pyplot()

    p = np.concatenate([[0.0], curve.pressure])
    fig, ax = plt.subplots(figsize=(5, 3.5))
    for y, lab, st in (
        (curve.bend_angle, "nonlinear FEM", "o-"),
        (curve.linear_bend_angle, "linear FEM", "--"),
        (curve.analytic_bend_angle, "analytic", ":"),
    ):
        ax.plot(p, np.degrees(np.concatenate([[0.0], y])), st, label=lab)
    ax.set_xlabel("pressure [MPa]")
    ax.set_ylabel("bend angle [deg]")
    ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
