"""Curvature, elongation and tip pose of a design over a pressure range.

``--model paper`` (default) is the paper's formula (eqs. 4, 7, 9), kept as the
reference; ``--model section`` is the 2-D section model (``softcath.fem.section_model``,
3-D-FEM-grade curvature in a fraction of a second). Both write the same
``analytic.csv`` columns, ``analytic.png`` and ``analytic.json`` (the model, its tier, its
load and why that load).

The load: the paper's formula is defined for the cap load (the end-cap force on the
composite beam), so ``--model paper`` takes the cap load and says so; the section model
takes the real load (lumen wall + cap), as every other command does. ``--load`` overrides.
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

#: The load each model takes unless ``--load`` is given, and why (printed and written to analytic.json).
DEFAULT_LOAD = {
    "paper": ("cap", "the paper's formula is defined for the cap load, the end-cap force"),
    "section": ("lumen", "the real load, lumen wall + cap"),
}


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_design(p)
    add_pressure_range(p, default="0:3:31")
    p.add_argument(
        "--load",
        choices=("cap", "lumen"),
        default=None,
        help="load model; default: cap for --model paper (the load the paper's formula is defined "
        "for), lumen for --model section (the real load: lumen wall + cap)",
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
    load, why = load_and_reason(args.model, args.load)
    if args.model == "section":
        from softcath.fem.section_model import section_model

        sm = section_model(d, loads=(load,))
        r = sm.response(p, load)
        what = f"section model ({load} load, {sm.fem_formula_ratio[load]:.3g}x the paper's formula)"
    else:
        r = analytic.response(d, p, load=load)
        what = f"paper's formula ({load} load)"
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
        o.json(
            "analytic.json",
            {
                "design": d.name,
                "model": args.model,
                "tier": "paper" if args.model == "paper" else "section",
                "load": load,
                "load_reason": why,
                "columns": {
                    "pressure_MPa": "MPa",
                    "curvature_per_mm": "1/mm",
                    "elongation": "-",
                    "bend_angle_rad": "rad",
                    "tip_x_mm": "mm",
                    "tip_y_mm": "mm",
                },
                "csv": "analytic.csv",
            },
        )
    i = int(np.argmax(np.abs(p)))
    print(
        f"{d.name}, {what}: {p.size} pressures {p.min():g}..{p.max():g} MPa; at {p[i]:g} MPa: "
        f"curvature {r.curvature[i]:.4g} 1/mm, bend {np.degrees(r.bend_angle[i]):.1f} deg, "
        f"tip ({r.tip_x[i]:.3f}, {r.tip_y[i]:.3f}) mm"
    )
    print(f"load: {load}: {why}")
    print(f"wrote {path}, {out / 'analytic.png'} and {out / 'analytic.json'}")
    return 0


def load_and_reason(model: str, given: str | None) -> tuple[str, str]:
    """The load ``model`` runs under and why: the one asked for, else the model's own."""
    if given is None:
        return DEFAULT_LOAD[model]
    default, why = DEFAULT_LOAD[model]
    if given == default:
        return given, why
    if model == "paper":  # the formula's lumen variant is the wall effect alone
        return given, (
            "as asked; the paper's formula is defined for the cap load, its lumen variant is the "
            "wall effect alone"
        )
    return given, "as asked: the paper's end-cap force alone"
