"""The 2-D section model of a design: 3-D-FEM-grade gains in a fraction of a second.

Writes DIR/section.json (gains per MPa for the chosen load, section stiffness,
neutral axis, lumen-area change, the ratio to the paper's formula, run facts,
and both loads under ``loads``), DIR/section.csv (the ``analytic.csv``
columns over the pressure range) and DIR/section.png (the section deformed at
the highest pressure, coloured by axial stress).
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

HELP = "2-D section model: FEM-grade curvature per MPa in milliseconds"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("design", help="preset name (e.g. paper) or path to a .toml file")
    p.add_argument("--pressure", default="0:0.6:13", help="START:STOP:N in MPa (default 0:0.6:13)")
    p.add_argument(
        "--load",
        choices=("cap", "lumen"),
        default="lumen",
        help="lumen: wall pressure + cap force (the real load, default); cap: the paper's cap force only",
    )
    p.add_argument("--mesh-size", type=float, default=None, help="section element size [mm] (default 0.08)")
    p.add_argument("--segments", type=int, default=None, help="boundary points per full turn (default 20)")
    p.add_argument(
        "--poisson",
        type=float,
        default=None,
        help="silicone Poisson ratio (tube and filler) instead of the design's, up to 0.49999",
    )
    p.add_argument(
        "--coil-modulus",
        choices=("tension", "bending"),
        default="tension",
        help="homogenised coil axial modulus (default tension, as the 3-D FEM)",
    )
    p.add_argument(
        "--coil-bending",
        choices=("annulus", "wahl"),
        default="annulus",
        help="annulus: coils bend as their annuli (3-D FEM, default); wahl: + helical-spring EI",
    )
    p.add_argument("--no-png", action="store_true", help="skip the PNG")
    p.add_argument("--out", type=Path, required=True, help="output directory")


def run(args: argparse.Namespace) -> int:
    from fem.section_model import section_model
    from fem.section_model.mesh import MESH_SIZE, SEGMENTS
    from fem.section_model.picture import section_picture
    from studies.cmd_analytic import parse_range

    pressures = parse_range(args.pressure)
    r = section_model(
        args.design,
        mesh_size=MESH_SIZE if args.mesh_size is None else args.mesh_size,
        segments=SEGMENTS if args.segments is None else args.segments,
        silicone_poisson=args.poisson,
        coil_modulus=args.coil_modulus,
        coil_bending=args.coil_bending,
        keep_fields=not args.no_png,
    )
    ld = args.load
    full = r.to_json()
    doc = {
        "design": r.design_name,
        "load": ld,
        "curvature_per_mm_per_MPa": r.curvature_per_mm_per_MPa[ld],
        "elongation_per_MPa": r.elongation_per_MPa[ld],
        "lumen_area_change_mm2_per_MPa": r.lumen_area_change_mm2_per_MPa[ld],
        "fem_formula_ratio": r.fem_formula_ratio[ld],
        **{k: full[k] for k in ("EA_N", "EI_N_mm2", "EI_lateral_N_mm2", "coupling_N_mm", "neutral_axis_mm",
                                "axial_centroid_mm", "lumen_area_mm2", "poisson_ratio_silicone",
                                "coil_modulus", "coil_bending", "mesh_size_mm", "segments", "dofs",
                                "n_triangles", "seconds", "mesh_seconds", "backward_error", "stiffness")},
        "loads": {k: full[k] for k in ("curvature_per_mm_per_MPa", "elongation_per_MPa",
                                       "lumen_area_change_mm2_per_MPa", "fem_formula_ratio")},
    }  # fmt: skip
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "section.json").write_text(json.dumps(doc, indent=2) + "\n")
    resp = r.response(pressures, ld)
    with (args.out / "section.csv").open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            ["pressure_MPa", "curvature_per_mm", "elongation", "bend_angle_rad", "tip_x_mm", "tip_y_mm"]
        )
        for row in zip(resp.pressure, resp.curvature, resp.elongation, resp.bend_angle, resp.tip_x,
                       resp.tip_y, strict=True):  # fmt: skip
            w.writerow([f"{v:.10g}" for v in row])
    wrote = "section.json, section.csv"
    if not args.no_png:
        p_show = float(max(abs(pressures.max()), abs(pressures.min()))) or 0.1
        section_picture(r, args.out / "section.png", load=ld, pressure=p_show)
        wrote += ", section.png"
    print(
        f"{r.design_name}: {ld} load, silicone nu {r.poisson_ratio_silicone:g} -> curvature "
        f"{r.curvature_per_mm_per_MPa[ld]:.4g} 1/mm per MPa ({r.fem_formula_ratio[ld]:.3g}x the paper's "
        f"formula), elongation {r.elongation_per_MPa[ld]:.3g} per MPa; EA {r.EA_N:.4g} N, "
        f"EI {r.EI_N_mm2:.4g} N mm^2, neutral axis y = {r.neutral_axis_mm:.4g} mm"
    )
    print(f"{r.dofs} dofs, {r.seconds * 1000:.0f} ms; wrote {args.out}/{wrote}")
    return 0
