"""Find where model and measurement disagree, name the missing effect, show the gap shrink.

Calibrates the model's gain, maps the residual over pressure, rate, direction,
frequency and time, fits every candidate effect (hysteresis, lag, delay,
dead_zone, viscoelastic, offset, nonlinear_gain) on training runs, scores it on
held-out runs, and names an effect only if it beats the model by the margin.
Writes DIR/discrepancy.json and DIR/report.html.

The files are written by the library: :mod:`softcath.studies.outputs.discrepancy`.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from softcath import models
from softcath.cli.options import add_design, add_model_option, add_out, design_or_data, refuse_model_options
from softcath.core.atomic import prepare_out_dir
from softcath.design.errors import DataError, DesignError
from softcath.studies.discrepancy.design_workflow import load_sweep_cases, run_design_workflow
from softcath.studies.discrepancy.design_workflow_report import write_design_report
from softcath.studies.discrepancy.prototype import hypotheses_table
from softcath.studies.outputs.discrepancy import (
    discrepancy_run,
    prototype_run,
    write_discrepancy,
    write_prototype_record,
)

HELP = "name the effect the model is missing (hysteresis, lag, ...) and show the gap shrink"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design(parser, optional=True)
    parser.add_argument(
        "measured",
        nargs="?",
        type=Path,
        help="measurement CSV (time_s, pressure_MPa, curvature_per_mm[, run]); "
        "with --reference fem: a CSV of pressure_MPa, curvature_per_mm "
        "from the FEM, or a sweep directory with analytic and 3-D FEM results "
        "(names which section-model ingredients the paper's formula lacks); with --reference prototype: "
        "a CSV of pressure_MPa, curvature_per_mm[, elongation] measured on the built DESIGN",
    )
    add_out(parser)
    parser.add_argument(
        "--reference",
        choices=("measured", "fem", "prototype"),
        default="measured",
        help="what the model is compared with (default: measured); prototype: which model ingredients "
        "(tube modulus, tube pre-stretch, filler, nu, coil initial tension, pressure offset, rest "
        "curvature, vision bias) explain a measured curve of a built design, on the finite-strain "
        "section model",
    )
    parser.add_argument(
        "--tip-factor",
        type=float,
        default=None,
        help="with --reference prototype: tip-level over mid-span curvature (default: from the 3-D FEM)",
    )
    parser.add_argument(
        "--margin",
        type=float,
        default=None,
        help="required held-out improvement to name an effect "
        "(default 0.05; 0.12 on quasi-static points, which have few samples)",
    )
    parser.add_argument(
        "--max-effects", type=int, default=3, help="stop after naming this many effects (default 3)"
    )
    parser.add_argument(
        "--excitation",
        choices=("auto", "time-series", "quasi-static"),
        default="auto",
        help="what the measurement is: auto (default) recognises quasi-static points "
        "(time_s a step index 0, 1, 2, ...) from sine and step-and-hold time series",
    )
    parser.add_argument(
        "--workers",
        type=int,
        default=2,
        help="with --reference prototype: processes for the finite-strain solves (default 2)",
    )
    parser.add_argument(
        "--physical",
        action="store_true",
        help="on a measured time series, go on from the named terms to the physical ingredients "
        "(the finite-strain section model fitted to the delay-corrected curve's first half, scored "
        "on its second; tens of seconds to minutes)",
    )
    parser.add_argument(
        "--candidates",
        help="comma-separated candidate effects to try (default: all that the data can judge)",
    )
    add_model_option(
        parser,
        tiers=(models.get("paper"), models.get("fem")),
        where=" (the paper's formula; the 3-D FEM as --reference fem without data)",
    )


def run(args: argparse.Namespace) -> int:
    out = prepare_out_dir(args.out)
    if args.margin is not None and not (math.isfinite(args.margin) and 0 <= args.margin < 1):
        raise DesignError("--margin", args.margin, "must be a fraction in [0, 1)")
    if not 1 <= args.max_effects <= 10:
        raise DesignError("--max-effects", args.max_effects, "must be an integer in [1, 10]")

    args.design, args.measured = design_or_data(args.design, args.measured)
    data = args.measured
    if args.reference == "prototype" or (data is not None and data.is_dir()):
        refuse_model_options(
            args,
            "is not taken with --reference prototype or a sweep folder: the prototype's ingredients set the "
            "finite-strain section model's laws themselves, and a sweep folder holds its results with the "
            "sweep's own options",
        )
    if args.reference == "prototype":
        return _run_prototype(args, out)
    if data is not None and data.is_dir():
        return _run_designs(args)
    solved = args.reference in models.TIERS and data is None  # a model as the reference (the 3-D FEM)
    tiers = ("paper", *((args.reference,) if solved else ()))
    result = discrepancy_run(
        data,
        args.design,
        options=models.parse_tier_options(args.model_option, tiers=tiers),
        reference=args.reference,
        margin=args.margin,
        max_effects=args.max_effects,
        candidates=_candidates(args),
        excitation=args.excitation,
        physical=args.physical,
        progress=True,
    )
    html = write_discrepancy(result, out)
    named = " + ".join(result.named) if result.named else "nothing"
    print(f"named: {named}")
    print(
        f"held-out NRMSE {result.nrmse_before:.4g} -> {result.nrmse_after:.4g} "
        f"(noise floor {result.noise_floor_nrmse:.3g}, "
        f"{result.excess_removed:.0%} of excess removed)"
    )
    kinds = sorted({r["kind"] for r in result.runs})
    print(f"excitation: {', '.join(kinds)} ({len(result.runs)} run(s))")
    cal = result.calibration
    if cal.get("gain_stderr") is not None:
        print(f"calibrated gain {cal['gain_per_mm_MPa']:.4g} ± {cal['gain_stderr']:.2g} 1/(mm MPa)")
    for step in result.steps:
        est = ", ".join(
            f"{k} {v:.3g}" + (f" ± {step['params_stderr'][k]:.2g}" if step["params_stderr"].get(k) else "")
            for k, v in step["params"].items()
        )
        if step.get("coefficient") is not None:
            se = step.get("coefficient_stderr")
            est = f"coefficient {step['coefficient']:.3g}" + (f" ± {se:.2g}" if se else "")
        print(f"  {step['effect']}: {est}")
    for note in result.notes:
        print(f"note: {note}")
    if result.physical is not None:
        _print_physical(result.physical)
    print(f"wrote {out / 'discrepancy.json'} and {html}")
    return 0


def _print_physical(phys: dict) -> None:
    """The physical step's summary: what produces the terms, and the held-out gap."""
    chosen = " + ".join(phys["chosen"]) or "nothing"
    verdict = "fits" if phys["explained"] else "best, does not fit"
    print(f"physical (finite-strain section, lumen load): {chosen} ({verdict})")
    for term, causes in phys["terms_produced_by"].items():
        print(f"  {term}: {' + '.join(causes) if causes else 'no physical ingredient among those chosen'}")
    print(
        f"  held-out NRMSE (second half of each run) {phys['nrmse_before']:.4g} -> {phys['nrmse_after']:.4g}"
    )


def _candidates(args: argparse.Namespace) -> tuple[str, ...] | None:
    """``--candidates a,b``: the effects or ingredients to try, or None for all."""
    if not args.candidates:
        return None
    return tuple(c.strip() for c in args.candidates.split(",") if c.strip())


def _run_prototype(args: argparse.Namespace, out: Path) -> int:
    if args.measured is None:
        raise DataError("--reference prototype: a CSV of pressure_MPa, curvature_per_mm is required")
    factor = args.tip_factor
    if factor is not None and not (math.isfinite(factor) and 0.2 <= factor <= 5):
        raise DesignError("--tip-factor", factor, "must be in [0.2, 5]")
    record = prototype_run(
        args.design,
        args.measured,
        tip_factor=factor,
        candidates=_candidates(args),
        workers=args.workers,
        progress=True,
    )
    write_prototype_record(record, out)
    for line in hypotheses_table(record):
        print(line)
    base, best = record["nrmse_before"], record["best_nrmse"]
    if record["explained"]:
        print(f"named: {' + '.join(record['named']) if record['named'] else 'nothing'}")
        print(f"NRMSE {base:.3f} (baseline) -> {record['nrmse_after']:.3f} ({record['tier']})")
    else:
        print("named: nothing: no hypothesis inside the sourced ranges follows the curve")
        print(f"NRMSE {base:.3f} (baseline); best {best:.3f} with {' + '.join(record['best']) or 'baseline'}")
    if len(record["equally_good"]) > 1:
        print(f"equally good: {record['equally_good']}; to separate them: {record['separating_measurement']}")
    for note in record["notes"]:
        print(f"note: {note}")
    print(f"wrote {out / 'discrepancy.json'}")
    return 0


def _run_designs(args: argparse.Namespace) -> int:
    cases = load_sweep_cases(args.measured, reference="fem")  # a sweep holds no measurement
    margin = 0.05 if args.margin is None else args.margin
    result = run_design_workflow(cases, margin=margin, max_steps=args.max_effects + 1, progress=True)
    html = write_design_report(result, args.out)
    print(f"named: {' + '.join(result.named) if result.named else 'nothing'}")
    print(
        f"held-out gap (median |FEM/model - 1|) {result.gap_before:.4g} -> {result.gap_after:.4g} over "
        f"{result.n_heldout} held-out of {result.n_designs} designs"
    )
    for note in result.notes:
        print(f"note: {note}")
    print(f"wrote {args.out}/discrepancy.json and {html}")
    return 0
