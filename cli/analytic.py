"""Curvature, elongation and tip pose of a design over a pressure range.

``--model paper`` (default) is the paper's formula (eqs. 4, 7, 9), kept as the
reference; ``--model section`` is the 2-D section model (``softcath.fem.section_model``,
3-D-FEM-grade curvature in a fraction of a second). Both write the same
``analytic.csv`` columns, ``analytic.png`` and ``analytic.json`` (the model, its tier, its
load and why that load).

The load: the paper's formula is defined for the cap load (the end-cap force on the
composite beam), so ``--model paper`` takes the cap load and says so; the section model
takes the real load (lumen wall + cap), as every other command does. ``--load`` overrides.

The files are written by the library: :func:`softcath.studies.outputs.analytic.analytic_run` and
its ``write``.
"""

from __future__ import annotations

import argparse

import numpy as np

from softcath import models
from softcath.cli.options import (
    add_assembly,
    add_design,
    add_out,
    add_pressure_range,
    as_options,
    model_name,
    parse_pressure_range,
    resolve_design,
)
from softcath.core.atomic import prepare_out_dir
from softcath.studies.outputs.analytic import MODELS, analytic_run

HELP = "curvature, elongation, tip pose over a pressure range"


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
        choices=MODELS,
        default="paper",
        help="paper: the paper's formula (default, the reference); section: the 2-D section model",
    )
    add_assembly(p)
    add_out(p)


def run(args: argparse.Namespace) -> int:
    p = parse_pressure_range(args.pressure)  # checked before the output folder is made
    d = resolve_design(args)
    models.get(args.model).check_assembly(d.assembly)  # before the folder
    out = prepare_out_dir(args.out)
    with as_options({"pressures": "--pressure"}):
        a = analytic_run(d, p, model=args.model, load=args.load)
    a.write(out)
    r = a.response
    i = int(np.argmax(np.abs(p)))
    print(
        f"{d.name}, {a.what}: {p.size} pressures {p.min():g}..{p.max():g} MPa; at {p[i]:g} MPa: "
        f"curvature {r.curvature[i]:.4g} 1/mm, bend {np.degrees(r.bend_angle[i]):.1f} deg, "
        f"tip ({r.tip_x[i]:.3f}, {r.tip_y[i]:.3f}) mm"
    )
    print(f"load: {a.load}: {a.load_reason}")
    print(f"wrote {out / 'analytic.csv'}, {out / 'analytic.png'} and {out / 'analytic.json'}")
    return 0
