"""``softcath fem --nonlinear``: the finite-strain bending check of one design.

``studies/cmd_fem.py`` (owned by the linear FEM) wires this in with::

    from softcath.fem.nonlinear import add_cli_arguments, run_cli   # in add_arguments / run
    add_cli_arguments(parser)                              # in add_arguments(parser)
    if args.nonlinear: return run_cli(args, echo=print)    # first line of run(args)

Outputs in ``--out DIR``: ``fem.json``, ``pressure_sweep.csv``,
``tip_series.pvd`` + ``vtu/step_XXX.vtu`` (ParaView opens the .pvd as an
animation over pressure), ``deformed_tip.png`` and ``bend_curve.png``.
"""

from __future__ import annotations

import argparse
import csv
import json
import logging
import time
from pathlib import Path

import numpy as np

from softcath.fem.nonlinear.errors import NonlinearError

__all__ = ["add_cli_arguments", "run_cli", "write_outputs"]

log = logging.getLogger(__name__)


def add_cli_arguments(parser: argparse.ArgumentParser) -> None:
    """Add the ``--nonlinear`` options (the design positional and ``--out`` belong to ``softcath fem``).

    Options the parser already has (e.g. the linear check's ``--pressure`` or
    ``--load``) are left alone and shared.
    """
    g = parser.add_argument_group("finite strain (--nonlinear)")
    existing = set(parser._option_string_actions)

    def add(flag, **kw):
        if flag not in existing:
            g.add_argument(flag, **kw)

    add("--nonlinear", action="store_true", help="geometrically nonlinear FEM with hyperelastic silicone")
    add("--pressure", type=float, default=None, help="largest pressure [MPa] (nonlinear: default 1.0)")
    add("--steps", type=int, default=8, help="pressure steps of the sweep (default 8)")
    add(
        "--load",
        choices=("lumen", "cap"),
        default="lumen",
        help="pressure on lumen wall + cap (real load) or cap only (paper's formula)",
    )
    add("--mesh-size", type=float, default=0.15, help="largest section triangle edge [mm]")
    add("--layers", type=int, default=4, help="element layers along the bending length (default 4)")
    add("--curvature-points", type=int, default=12, help="mesh segments per full circle (default 12)")
    add("--mixed", action="store_true", help="mixed u-p (P2-P0) formulation for the silicones")
    add(
        "--compare-linear",
        action="store_true",
        help="report the bend angle where linear FEM / analytic depart from nonlinear by 5%%",
    )


def _get(args, name, default=None):
    return getattr(args, name, default)


def run_cli(args: argparse.Namespace, echo=None) -> int:
    """Run the nonlinear check for ``args.design`` and write outputs to ``args.out``.

    ``echo`` receives the human summary line by line (``print`` from the command
    line); by default the lines go to the log.
    """
    echo = echo or log.info
    from softcath import design as design_mod
    from softcath.fem.nonlinear.bend import bend_curve

    d = design_mod.resolve(_get(args, "design", "paper") or "paper")
    p_max = _get(args, "pressure")
    if isinstance(p_max, (list, tuple, np.ndarray)):  # a linear check's pressure list: sweep to its largest
        p_max = max(p_max) if len(p_max) else None
    p_max = 1.0 if p_max is None else float(p_max)
    steps = int(_get(args, "steps", 8))
    if not (np.isfinite(p_max) and p_max > 0):
        raise NonlinearError(f"--pressure = {p_max!r}: must be a finite pressure > 0 MPa")
    if steps < 1:
        raise NonlinearError(f"--steps = {steps!r}: must be >= 1")
    out = Path(_get(args, "out", None) or "fem_nonlinear_out")
    out.mkdir(parents=True, exist_ok=True)
    pressures = p_max * np.arange(1, steps + 1) / steps
    t_start = time.perf_counter()
    curve = bend_curve(
        d,
        pressures,
        load=_get(args, "load", "lumen"),
        size=float(_get(args, "mesh_size", 0.15)),
        layers=int(_get(args, "layers", 4)),
        curvature_points=int(_get(args, "curvature_points", 12)),
        mixed=bool(_get(args, "mixed", False)),
        progress=True,
    )
    seconds = time.perf_counter() - t_start
    summary = write_outputs(
        curve, out, design_name=d.name, compare_linear=bool(_get(args, "compare_linear", False))
    )
    _add_linear_check_keys(out / "fem.json", curve, d, seconds)
    echo(
        f"softcath fem --nonlinear: {d.name}, {curve.load} load, {curve.ndofs} DOFs, "
        f"{len(curve.result.steps)} steps, {curve.result.newton_iterations} Newton iterations"
    )
    echo(
        f"  at {p_max:g} MPa: bend angle {np.degrees(curve.bend_angle[-1]):.2f} deg nonlinear, "
        f"{np.degrees(curve.linear_bend_angle[-1]):.2f} deg linear FEM, "
        f"{np.degrees(curve.analytic_bend_angle[-1]):.2f} deg analytic"
    )
    if "departure_5pct_deg" in summary:
        for k, v in summary["departure_5pct_deg"].items():
            echo(f"  {k} departs by 5 %: " + ("not within the sweep" if v is None else f"at {v:.1f} deg"))
    echo(f"  wrote {out}/fem.json, pressure_sweep.csv, tip_series.pvd, deformed_tip.png")
    return 0


def _finite_or_none(x) -> float | None:
    x = float(x)
    return x if np.isfinite(x) else None


def _add_linear_check_keys(path: Path, curve, design, seconds: float) -> None:
    """Give fem.json the keys of the linear check (``softcath fem``) at the final pressure."""
    from softcath import analytic

    doc = json.loads(path.read_text(encoding="utf-8"))
    p = float(curve.pressure[-1])
    ref = analytic.response(design, p, curve.load)
    k_ref = float(ref.curvature)
    last = curve.result.steps[-1]
    doc.update(
        {
            "n_elements": int(curve.n_tets),
            "dofs": int(curve.ndofs),
            "residual": float(last.residuals[-1]) if len(last.residuals) else None,
            "solve_seconds": seconds,
            "analytic": {"curvature_per_mm": k_ref, "elongation": float(ref.elongation)},
            "ratio_fem_over_analytic": float(curve.curvature[-1]) / k_ref if k_ref else None,
            # finite-strain counterparts: section-rotation profile, principal stretch strain
            "curvature_variation": _finite_or_none(curve.curvature_variation[-1]),
            "max_strain": _finite_or_none(curve.max_strain[-1]),
            "n_nodes": int(curve.n_nodes),
            "mesh_seconds": float(curve.mesh_seconds),
        }
    )
    path.write_text(json.dumps(doc, indent=2), encoding="utf-8")


def write_outputs(curve, out: Path, *, design_name: str = "design", compare_linear: bool = False) -> dict:
    """Write fem.json, pressure_sweep.csv, the VTU series and the PNGs of ``curve`` into ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    k = -1
    summary = {
        "design": design_name,
        "nonlinear": True,
        "load": curve.load,
        "pressure_MPa": float(curve.pressure[k]),
        "bend_angle_rad": float(curve.bend_angle[k]),
        "curvature_per_mm": float(curve.curvature[k]),
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
        "pressure_sweep_csv": "pressure_sweep.csv",
    }
    if compare_linear:
        dep = curve.departure(0.05)
        summary["departure_5pct_rad"] = dep
        summary["departure_5pct_deg"] = {
            kk: (None if v is None else float(np.degrees(v))) for kk, v in dep.items()
        }
    (out / "fem.json").write_text(json.dumps(summary, indent=2))
    with open(out / "pressure_sweep.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                "pressure_MPa",
                "bend_angle_rad",
                "bend_angle_deg",
                "curvature_per_mm",
                "elongation",
                "tip_x_mm",
                "tip_y_mm",
                "newton_iterations",
                "linear_fem_bend_angle_rad",
                "analytic_bend_angle_rad",
            ]
        )
        for i in range(curve.pressure.size):
            w.writerow(
                [
                    f"{curve.pressure[i]:.9g}",
                    f"{curve.bend_angle[i]:.9g}",
                    f"{np.degrees(curve.bend_angle[i]):.6g}",
                    f"{curve.curvature[i]:.9g}",
                    f"{curve.elongation[i]:.9g}",
                    f"{curve.tip_x[i]:.9g}",
                    f"{curve.tip_y[i]:.9g}",
                    int(curve.newton_iterations[i]),
                    f"{curve.linear_bend_angle[i]:.9g}",
                    f"{curve.analytic_bend_angle[i]:.9g}",
                ]
            )
    if curve.model is not None:
        write_vtu_series(curve, out)
        plot_deformed(curve, out / "deformed_tip.png")
    plot_curve(curve, out / "bend_curve.png")
    return summary


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


def plot_deformed(curve, path: Path) -> None:
    """Side view (y–z plane) of the tip at full pressure over the undeformed outline."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model = curve.model
    mesh = model.cmesh.mesh
    nv = mesh.p.shape[1]
    u = curve.result.displacements[-1][:nv]
    x0 = mesh.p.T
    x1 = x0 + u
    colours = {1: "tab:grey", 2: "tab:blue", 3: "tab:orange", 4: "tab:green"}
    names = {1: "coil", 2: "tube", 3: "channel", 4: "filler"}
    fig, ax = plt.subplots(figsize=(5, 6))
    ax.scatter(x0[:, 1], x0[:, 2], s=1, c="lightgrey", label="undeformed")
    for lab, col in colours.items():
        verts = np.unique(mesh.t[:, model.cmesh.labels == lab])
        if verts.size:
            ax.scatter(x1[verts, 1], x1[verts, 2], s=2, c=col, label=names[lab])
    ax.set_aspect("equal")
    ax.set_xlabel("y [mm] (channel side negative)")
    ax.set_ylabel("z [mm]")
    ax.set_title(f"{curve.load} load {curve.pressure[-1]:g} MPa: {np.degrees(curve.bend_angle[-1]):.1f} deg")
    ax.legend(loc="best", fontsize=7, markerscale=4)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_curve(curve, path: Path) -> None:
    """Bend angle vs pressure: nonlinear FEM, linear FEM, analytic."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

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
