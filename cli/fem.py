"""Run one FEM bending check of a design and compare it with the analytic model.

Writes DIR/fem.json (curvature, elongation, tip pose, strain, run facts and
the analytic values for the same design, pressure and load model), DIR/tip.vtu
(open in ParaView) and DIR/tip.png (deformed tip coloured by strain).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from softcath.design.errors import DataError, DesignError

HELP = "one FEM bending check (mesh, solve, compare with the analytic model)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("design", help="preset name (e.g. paper) or path to a design .toml")
    parser.add_argument("--pressure", type=float, required=True, help="lumen pressure [MPa] (e.g. 0.1)")
    parser.add_argument(
        "--load",
        choices=("cap", "lumen"),
        default="cap",
        help="cap: end-cap force only (the paper's model); lumen: wall + cap (the real load)",
    )
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument(
        "--mesh-size", type=float, default=0.16, help="section element size [mm] (default 0.16)"
    )
    parser.add_argument(
        "--mesher",
        choices=("gmsh", "tetwild"),
        default="gmsh",
        help="gmsh: 2-D section + extrusion, seconds (default); tetwild: pytetwild, minutes",
    )
    parser.add_argument(
        "--coil-modulus",
        choices=("tension", "bending"),
        default="tension",
        help="homogenised coil axial modulus: spring tension (paper's E_eq) or Wahl bending",
    )
    parser.add_argument("--no-cache", action="store_true", help="do not read/write the mesh cache")
    parser.add_argument("--no-png", action="store_true", help="skip the PNG rendering")
    from softcath.fem.nonlinear import add_cli_arguments  # --nonlinear, --steps, --mixed, --compare-linear

    add_cli_arguments(parser)


def _run_nonlinear(args: argparse.Namespace) -> int:
    import copy

    from softcath.fem.nonlinear import run_cli
    from softcath.studies.atomic import staged_dir

    out = Path(args.out)
    lines: list[str] = []
    with staged_dir(out) as stage:  # every output appears only if the whole run succeeded
        staged = copy.copy(args)
        staged.out = str(stage)
        status = run_cli(staged, echo=lines.append)
        if status:
            raise DataError(f"the finite-strain check stopped with status {status}; nothing written")
    for line in lines:
        print(line.replace(str(stage), str(out)))
    return 0


def run(args: argparse.Namespace) -> int:
    from softcath import design
    from softcath.fem.limits import check_fem_budget
    from softcath.studies.atomic import Outputs, prepare_out_dir
    from softcath.studies.validity import check_pressure, warn_linear_range

    out = prepare_out_dir(args.out)
    check_pressure(args.pressure)
    d = design.resolve(args.design)
    check_fem_budget(d, mesh_size=args.mesh_size)  # before minutes of meshing, not after
    if getattr(args, "nonlinear", False):
        if args.pressure <= 0:
            raise DesignError("--pressure", args.pressure, "must be > 0 MPa for --nonlinear")
        if not 1 <= args.steps <= 1000:
            raise DesignError("--steps", args.steps, "must be an integer in [1, 1000]")
        return _run_nonlinear(args)
    from softcath import fem
    from softcath.fem.export import render_png, write_vtu

    stages = iter(range(1, 5))

    def status(stage: str) -> None:
        print(f"[{next(stages, 4)}/4] {stage} ...", file=sys.stderr, flush=True)

    result = fem.check(
        d,
        pressures=[args.pressure],
        loads=(args.load,),
        mesh_size=args.mesh_size,
        mesher=args.mesher,
        coil_modulus=args.coil_modulus,
        use_cache=not args.no_cache,
        progress=status,
    )
    c = result.case(args.load, args.pressure)
    doc = result.to_json(args.load, args.pressure)
    with Outputs(out) as o:
        o.json("fem.json", doc)
        write_vtu(result.solution, args.load, args.pressure, o.path("tip.vtu"))
        if not args.no_png:
            render_png(result.solution, args.load, args.pressure, o.path("tip.png"))
    warn_linear_range(args.pressure, c.bend_angle_rad, max_strain=c.max_strain, model="the linear FEM")
    ratio = c.ratio_fem_over_analytic["curvature_per_mm"]
    print(
        f"{result.design_name}: {args.load} load at {args.pressure:g} MPa -> "
        f"curvature {c.curvature_per_mm:.4g} 1/mm (analytic {c.analytic['curvature_per_mm']:.4g}, "
        f"ratio {ratio:.3g}), elongation {c.elongation:.3g}, bend {c.bend_angle_rad:.3g} rad, "
        f"max silicone strain {c.max_strain:.3g}"
    )
    print(
        f"mesh {result.n_elements} tets ({result.mesher}, "
        f"{'cached' if result.mesh_cached else f'{result.mesh_seconds:.1f} s'}), "
        f"{result.dofs} dofs, solve {result.solve_seconds:.1f} s, "
        f"backward error {result.residual:.1e}; wrote {out}/fem.json, tip.vtu"
        + ("" if args.no_png else ", tip.png")
    )
    return 0
