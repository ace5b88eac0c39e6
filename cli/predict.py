"""Prediction bands of a design's bending gain under parameter uncertainty, against a measured gain.

Samples the uncertain parameters on a seeded Latin hypercube (default: the
ranges shipped for the design, each with its source; or ``--vary`` items),
pushes every variant through a model tier (``paper``: the paper's formula;
``section``: the 2-D section model; ``fem``: the 3-D linear FEM, a small
sample) and writes DIR/prediction.json (p5/p50/p95 of κ/p and ε/p, where the
measured gain falls, RBD-FAST sensitivity indices, the ranges and their
sources), DIR/samples.csv (every variant: tier, parameter values, κ/p, ε/p;
empty gains for variants the design checks reject) and DIR/prediction.png
(the band of each tier and the measured line).

``--nonlinear`` (with ``--model section``) adds the finite-strain section
model's bands at ``--pressures``: per pressure p5/p50/p95 of the curvature
and bend angle (``nonlinear`` in prediction.json, DIR/curve_band.png), and
``--measured CSV`` places a measured curve in them pressure by pressure, not
only its line-fit slope.

The files are written by the library: :func:`softcath.studies.outputs.predict.prediction_run` and
its ``write``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from softcath import design, models
from softcath.cli.options import (
    PRESSURE_SYNTAX,
    add_design,
    add_model_option,
    add_out,
    add_progress,
    add_seed,
    as_options,
    model_name,
    parse_pressure_list,
)
from softcath.core.atomic import prepare_out_dir
from softcath.design.errors import DesignError
from softcath.design.measurement import read_measurement_csv
from softcath.fem.limits import check_work_seconds, finite_strain_curve_seconds
from softcath.studies.model_validity import check_measured_pressures
from softcath.studies.outputs.predict import prediction_run
from softcath.studies.predict.curve_band import MAX_CURVE_SAMPLES
from softcath.studies.predict.propagate import TIERS
from softcath.studies.predict.workflow import check_predict_inputs

#: The library's parameter names as this command's options.
_OPTIONS = {
    "samples": "--samples",
    "fem_samples": "--fem-samples",
    "seed": "--seed",
    "measured_gain": "--measured-gain",
    "ranges": "--ranges",
    "model": "--model",
    "vary": "--vary",
}

HELP = "prediction bands of the bending gain under parameter uncertainty, vs a measurement"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_design(p)
    p.add_argument(
        "--model",
        type=model_name,
        choices=TIERS,
        default="section",
        help="model tier (default section)",
    )
    p.add_argument(
        "--compare",
        default="",
        metavar="TIER,TIER",
        help="also run these tiers (e.g. paper,section,fem) and draw them in one picture",
    )
    p.add_argument(
        "--load",
        choices=("cap", "lumen"),
        default=None,
        help="load case (default: cap for the paper's formula, lumen for section and fem)",
    )
    p.add_argument(
        "--vary",
        action="append",
        default=[],
        metavar="PATH=LO:HI",
        help="vary a dotted design path: PATH=LO:HI[:uniform|nu-log], model.coil_modulus=tension,bending, "
        "or PATH alone for the ranges file's range (repeatable; default: the file's default ranges)",
    )
    p.add_argument(
        "--ranges", type=Path, default=None, help="ranges TOML (default: the one shipped for a preset)"
    )
    p.add_argument(
        "--samples",
        type=int,
        default=None,
        help="samples of the paper and section tiers (default 4096 and 512)",
    )
    p.add_argument("--fem-samples", type=int, default=None, help="samples of the 3-D FEM tier (default 8)")
    add_seed(p, what="seed of the sample and the bootstrap")
    p.add_argument(
        "--measured-gain",
        type=float,
        default=None,
        metavar="K",
        help="measured curvature per pressure [1/(mm MPa)] to place in the bands",
    )
    p.add_argument(
        "--finite-strain",
        action="store_true",
        help="add the finite-strain FEM of the nominal design at --pressures (one point, minutes)",
    )
    p.add_argument(
        "--pressures",
        default="0.1,0.3,0.6",
        metavar=PRESSURE_SYNTAX,
        help="pressures of --finite-strain and --nonlinear [MPa], increasing (default 0.1,0.3,0.6, "
        "the prototype's)",
    )
    p.add_argument(
        "--nonlinear",
        action="store_true",
        help="with --model section: bands of the finite-strain section model's curve at --pressures",
    )
    p.add_argument(
        "--curve-samples",
        type=int,
        default=64,
        help="samples of --nonlinear (about a second each; default 64)",
    )
    p.add_argument(
        "--measured",
        type=Path,
        default=None,
        metavar="CSV",
        help="with --nonlinear: a measurement CSV compared with the bands pressure by pressure",
    )
    add_model_option(
        p,
        tiers=tuple(models.get(n) for n in TIERS),
        where=" (--model and --compare; the bands' tiers, not the finite-strain curves)",
    )
    add_progress(p)
    add_out(p)


def run(args: argparse.Namespace) -> int:
    compare = _compare(args.compare)
    # Everything that can be checked is checked before the output folder or any run.
    pressures = _pressures(args.pressures) if (args.finite_strain or args.nonlinear) else None
    measured = _nonlinear_inputs(args, pressures)
    with as_options(_OPTIONS):
        check_predict_inputs(
            samples=args.samples,
            fem_samples=args.fem_samples,
            seed=args.seed,
            measured_gain=args.measured_gain,
            tiers=(args.model, *compare),
        )
    options = models.parse_tier_options(args.model_option, tiers=(args.model, *compare))
    out = prepare_out_dir(args.out)
    with as_options({**_OPTIONS, "curve_samples": "--curve-samples"}):
        result = prediction_run(
            args.design,
            model=args.model,
            compare=compare,
            load=args.load,
            vary=args.vary,
            ranges_file=args.ranges,
            samples=args.samples,
            fem_samples=args.fem_samples,
            seed=args.seed,
            measured_gain=args.measured_gain,
            finite_strain_pressures=pressures if args.finite_strain else None,
            curve_pressures=pressures if args.nonlinear else None,
            curve_samples=args.curve_samples,
            measured=measured,
            progress=not args.no_progress,
            options=options,
        )
    wrote = result.write(out)
    _print_tiers(result.tiers, result.doc)
    if "nonlinear" in result.doc:
        _print_nonlinear(result.doc["nonlinear"])
    print(f"wrote {out}/{', '.join(wrote)}")
    return 0


def _print_tiers(tiers, doc: dict) -> None:
    """Each tier's gain band, measurement and sensitivity, and the finite-strain point, on stdout."""
    for t in tiers:
        p = t.gain_percentiles
        line = (
            f"{t.model} ({t.load} load, {t.feasible_samples}/{t.samples} variants): kappa/p p5 "
            f"{p['p5']:.4g}, p50 {p['p50']:.4g}, p95 {p['p95']:.4g} 1/(mm MPa); nominal {t.nominal_gain:.4g}"
        )
        if t.measured is not None:
            m = t.measured
            where = "inside the band" if m["measured_in_band"] else m["measured_outside"]
            line += f"; measured {t.measured_gain:g} at percentile {m['measured_percentile']:.1f} ({where})"
        print(line)
        rank = t.sensitivity.get("ranking", [])
        if rank:
            idx = t.sensitivity["indices"]
            print("  sensitivity S1: " + ", ".join(f"{n} {idx[n]['S1']:.2f}" for n in rank))
        elif "skipped" in t.sensitivity:
            print(f"  sensitivity: {t.sensitivity['skipped']}")
    if "finite_strain" in doc:
        fs = doc["finite_strain"]
        print(
            f"finite-strain FEM ({fs['load']} load, nominal design, p = {fs['pressures_MPa']} MPa): line-fit "
            f"kappa/p {fs['gain_line_fit']:.4g} 1/(mm MPa), intercept {fs['intercept_per_mm']:.3g} 1/mm"
        )


def _compare(text: str) -> tuple[str, ...]:
    """``--compare TIER,TIER``: each a tier this command runs (the same names as ``--model``)."""
    tiers = tuple(model_name(t.strip()) for t in text.split(",") if t.strip())
    for t in tiers:
        if t not in TIERS:
            raise DesignError(
                "--compare", text, f"{t!r} is not a tier of predict; give some of {', '.join(TIERS)}"
            )
    return tiers


def _nonlinear_inputs(args: argparse.Namespace, pressures=None):
    """Check the --nonlinear options before any work; the measurement read, or None."""
    if args.measured is not None and not args.nonlinear:
        raise DesignError("--measured", str(args.measured), "needs --nonlinear")
    curve_tiers = _curve_tiers()
    if args.nonlinear and args.model not in curve_tiers:
        counterparts = " or ".join(models.get(curve_tiers[n]).label for n in curve_tiers)
        raise DesignError(
            "--model", args.model, f"must be {' or '.join(curve_tiers)} with --nonlinear ({counterparts})"
        )
    if not args.nonlinear:
        return None
    if not 2 <= args.curve_samples <= MAX_CURVE_SAMPLES:
        raise DesignError("--curve-samples", args.curve_samples, f"must be in [2, {MAX_CURVE_SAMPLES}]")
    _check_curve_work(args, pressures)
    if args.measured is None:
        return None
    m = read_measurement_csv(args.measured, missing="drop")
    top = max(pressures or [0.0])
    check_measured_pressures(m.pressure_MPa, top, param="--measured", value=str(args.measured))
    return m


def _curve_tiers() -> dict[str, str]:
    """Tier -> its finite-strain counterpart, for the tiers whose counterpart gives ``--nonlinear``'s bands.

    The bands are many finite-strain curves: a counterpart fast enough for a sample (not slow).
    """
    pairs = {n: models.get(n).finite_strain_tier for n in TIERS}
    return {n: fs for n, fs in pairs.items() if fs is not None and not models.get(fs).slow}


def _check_curve_work(args: argparse.Namespace, pressures) -> None:
    """Refuse --curve-samples whose curves are estimated beyond the work limit; warn beyond a minute."""
    each = finite_strain_curve_seconds(design.resolve(args.design), len(pressures or ()))
    check_work_seconds(
        (args.curve_samples + 1) * each,
        param="--curve-samples",
        value=args.curve_samples,
        what=f"{args.curve_samples} finite-strain curves through {len(pressures)} pressures",
        hint="use fewer --curve-samples or --pressures",
    )


def _print_nonlinear(nl: dict) -> None:
    print(
        f"finite-strain section model ({nl['load']} load, {nl['feasible_samples']}/{nl['samples']} variants):"
    )
    for pt in nl["pressures"]:
        b = pt["curvature_percentiles"]
        print(
            f"  p = {pt['pressure_MPa']:g} MPa: kappa p5 {b['p5']:.4g}, p50 {b['p50']:.4g}, p95 "
            f"{b['p95']:.4g} 1/mm"
        )
    g = nl["gain_line_fit_percentiles"]
    print(f"  line-fit kappa/p p5 {g['p5']:.4g}, p50 {g['p50']:.4g}, p95 {g['p95']:.4g} 1/(mm MPa)")
    m = nl.get("measured")
    if m:
        for pt in m["points"]:
            if pt["measured_curvature_per_mm"] is None:
                print(f"  measured at {pt['pressure_MPa']:g} MPa: no measured point within half a step")
                continue
            where = "inside the band" if pt["measured_in_band"] else pt["measured_outside"]
            print(
                f"  measured at {pt['pressure_MPa']:g} MPa: {pt['measured_curvature_per_mm']:.4g} 1/mm, "
                f"percentile {pt['measured_percentile']:.1f} ({where}), {pt['measured_over_p50']:.3g}x p50"
            )
        print(
            f"  measured: {m['pressures_in_band']} of {m['pressures_compared']} pressures inside the band; "
            f"its line-fit kappa/p {m['gain_line_fit']:.4g}"
        )


def _pressures(text: str) -> list[float]:
    """The finite-strain pressures: checked (finite, ±100 MPa, > 0, increasing, two or more)."""
    values = parse_pressure_list(text, param="--pressures", increasing=True)
    if values[0] <= 0:
        raise DesignError("--pressures", text, "must be > 0 MPa for the finite-strain models")
    if len(values) < 2:
        raise DesignError("--pressures", text, "needs two or more pressures for the line fit")
    return values
