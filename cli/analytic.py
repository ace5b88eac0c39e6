"""Curvature, elongation and tip pose of a design over a pressure range.

``--model paper`` (default) is the paper's formula (eqs. 4, 7, 9), kept as the
reference; ``--model section`` is the 2-D section model (``softcath.fem.section_model``,
3-D-FEM-grade curvature in a fraction of a second). Both write the same
``analytic.csv`` columns and ``analytic.png``.
"""

from __future__ import annotations

import argparse
import csv

from softcath.cli.options import (
    add_assembly,
    add_design,
    add_out,
    add_pressure_range,
    model_name,
    parse_pressure_range,
    resolve_design,
)

HELP = "curvature, elongation, tip pose over a pressure range"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_design(p)
    add_pressure_range(p, default="0:3:31")
    p.add_argument(
        "--load", choices=("cap", "lumen"), default="cap", help="load model (default: cap, the paper's)"
    )
    p.add_argument(
        "--model",
        type=model_name,
        choices=("paper", "section"),
        default="paper",
        help="paper: the paper's formula (default, the reference); section: the 2-D section model",
    )
    add_assembly(p)
    add_out(p)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from softcath import analytic
    from softcath.studies.atomic import Outputs, prepare_out_dir
    from softcath.studies.model_validity import check_finite_columns, warn_linear_range
    from softcath.studies.plots import analytic_plot
    from softcath.studies.tiers import check_assembly

    p = parse_pressure_range(args.pressure)  # checked before the output folder is made
    d = resolve_design(args)
    check_assembly("section" if args.model == "section" else "paper", d.assembly)
    out = prepare_out_dir(args.out)
    if args.model == "section":
        from softcath.fem.section_model import section_model

        sm = section_model(d, loads=(args.load,))
        r = sm.response(p, args.load)
        what = f"section model ({args.load} load, {sm.fem_formula_ratio[args.load]:.3g}x the paper's formula)"
    else:
        r = analytic.response(d, p, load=args.load)
        what = f"paper's formula ({args.load} load)"
    columns = {
        "pressure_MPa": r.pressure,
        "curvature_per_mm": r.curvature,
        "elongation": r.elongation,
        "bend_angle_rad": r.bend_angle,
        "tip_x_mm": r.tip_x,
        "tip_y_mm": r.tip_y,
    }
    check_finite_columns(columns, param="--pressure", value=args.pressure)
    warn_linear_range(p, r.bend_angle, elongation=r.elongation, model=f"the {what.split(' (')[0]} (linear)")
    path = out / "analytic.csv"
    with Outputs(out) as o:
        with o.path("analytic.csv").open("w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(list(columns))
            for row in zip(*columns.values(), strict=True):
                w.writerow([f"{v:.10g}" for v in row])
        analytic_plot(o.path("analytic.png"), r, title=f"{d.name}: {what}")
    i = int(np.argmax(np.abs(p)))
    print(
        f"{d.name}, {what}: {p.size} pressures {p.min():g}..{p.max():g} MPa; at {p[i]:g} MPa: "
        f"curvature {r.curvature[i]:.4g} 1/mm, bend {np.degrees(r.bend_angle[i]):.1f} deg, "
        f"tip ({r.tip_x[i]:.3f}, {r.tip_y[i]:.3f}) mm"
    )
    print(f"wrote {path} and {out / 'analytic.png'}")
    return 0
