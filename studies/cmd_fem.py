"""Run one FEM bending check of a design and compare it with the analytic model.

Writes DIR/fem.json (curvature, elongation, tip pose, strain, run facts and
the analytic values for the same design, pressure and load model), DIR/tip.vtu
(open in ParaView) and DIR/tip.png (deformed tip coloured by strain).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

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


def run(args: argparse.Namespace) -> int:
    import fem
    from fem.export import render_png, write_vtu

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    stages = iter(range(1, 5))

    def status(stage: str) -> None:
        print(f"[{next(stages, 4)}/4] {stage} ...", file=sys.stderr, flush=True)

    result = fem.check(
        args.design,
        pressures=[args.pressure],
        loads=(args.load,),
        mesh_size=args.mesh_size,
        mesher=args.mesher,
        coil_modulus=args.coil_modulus,
        use_cache=not args.no_cache,
        progress=status,
    )
    doc = result.to_json(args.load, args.pressure)
    (out / "fem.json").write_text(json.dumps(doc, indent=2) + "\n")
    write_vtu(result.solution, args.load, args.pressure, out / "tip.vtu")
    if not args.no_png:
        render_png(result.solution, args.load, args.pressure, out / "tip.png")
    c = result.case(args.load, args.pressure)
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
