"""Find where model and measurement disagree, name the missing effect, show the gap shrink.

Calibrates the model's gain, maps the residual over pressure, rate, direction,
frequency and time, fits every candidate effect (hysteresis, lag, delay,
dead_zone, viscoelastic, offset, nonlinear_gain) on training runs, scores it on
held-out runs, and names an effect only if it beats the model by the margin.
Writes DIR/discrepancy.json and DIR/report.html.
"""

from __future__ import annotations

import argparse
from pathlib import Path

HELP = "name the effect the model is missing (hysteresis, lag, ...) and show the gap shrink"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "measured",
        nargs="?",
        type=Path,
        help="measurement CSV (time_s, pressure_MPa, curvature_per_mm[, run]); "
        "with --reference fem: a CSV of pressure_MPa, curvature_per_mm "
        "from the FEM",
    )
    parser.add_argument("--design", default="paper", help="design preset name or TOML file (default: paper)")
    parser.add_argument("--out", type=Path, required=True, help="output directory")
    parser.add_argument(
        "--reference",
        choices=("measured", "fem"),
        default="measured",
        help="what the model is compared with (default: measured)",
    )
    parser.add_argument(
        "--margin",
        type=float,
        default=0.05,
        help="required held-out improvement to name an effect (default 0.05)",
    )
    parser.add_argument(
        "--max-effects", type=int, default=3, help="stop after naming this many effects (default 3)"
    )


def run(args: argparse.Namespace) -> int:
    import math

    from design.errors import DataError, DesignError
    from studies.atomic import prepare_out_dir, staged_dir, unstage
    from studies.discrepancy import run_workflow, write_report
    from studies.discrepancy.result import fem_reference

    out = prepare_out_dir(args.out)
    if not (math.isfinite(args.margin) and 0 <= args.margin < 1):
        raise DesignError("--margin", args.margin, "must be a fraction in [0, 1)")
    if not 1 <= args.max_effects <= 10:
        raise DesignError("--max-effects", args.max_effects, "must be an integer in [1, 10]")

    data = args.measured
    fem_fn = None
    if args.reference == "fem" and data is None:
        fem_fn = fem_reference()
        if fem_fn is None:
            raise DataError(
                "--reference fem: no FEM table given and fem.check is not "
                "available; pass a CSV with pressure_MPa, curvature_per_mm"
            )
    if args.reference == "measured" and data is None:
        raise DataError("a measurement CSV is required")
    result = run_workflow(
        data,
        args.design,
        reference=args.reference,
        fem=fem_fn,
        margin=args.margin,
        max_effects=args.max_effects,
        progress=True,
    )
    with staged_dir(out) as stage:  # the record and its page replace earlier ones only together
        html = unstage(write_report(result, stage), stage, out)
    named = " + ".join(result.named) if result.named else "nothing"
    print(f"named: {named}")
    print(
        f"held-out NRMSE {result.nrmse_before:.4g} -> {result.nrmse_after:.4g} "
        f"(noise floor {result.noise_floor_nrmse:.3g}, "
        f"{result.excess_removed:.0%} of excess removed)"
    )
    for note in result.notes:
        print(f"note: {note}")
    print(f"wrote {out / 'discrepancy.json'} and {html}")
    return 0
