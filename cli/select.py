"""Pick a design before fabrication: constraints and objectives over a sweep's result columns.

Examples: --constraint "bend_angle_deg >= 90 at p_max" --constraint "max_strain <= 0.3"
--objective "maximise bend_per_MPa_deg" --objective "minimise elongation at p_max".
Columns such as bend_angle_deg, bend_per_MPa_deg, max_strain resolve to one model: by default the
finite-strain section model when the sweep ran it, else the section model under the lumen load when
the sweep has section-model columns, else the paper's formula (cap load); --model and --load choose.
A bend constraint ranked on a linear model whose designs bend past its validity (5 deg) is re-checked
with the finite-strain section model (--no-recheck keeps the linear ranking). Writes DIR/selection.json
(ranked list, Pareto front, model and load) and the first ranked designs as design files,
DIR/designs/design_ID.toml, which `softcath design validate`, `section` and `fem` take as they are;
`softcath report DIR` shows them.

The files are written by the library: :func:`softcath.studies.outputs.selection.selection_run`.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from softcath import models
from softcath.cli.options import (
    add_model_option,
    add_out,
    add_seed,
    as_options,
    model_name,
    refuse_model_options,
)
from softcath.design.errors import DesignError
from softcath.design.reference import unit_of
from softcath.fem.limits import check_workers
from softcath.studies.criteria import parse_constraint, parse_objective, without_text
from softcath.studies.optimise import MODELS as SEARCH_MODELS
from softcath.studies.outputs.selection import RobustSettings, selection_run
from softcath.studies.selection import MODEL_NAMES, SelectionError

#: The robust ranking's settings as this command's options.
_ROBUST_OPTIONS = {
    "robust.probability": "--robust",
    "robust.samples": "--samples",
    "robust.seed": "--seed",
    "robust.ranges": "--vary/--ranges",
    "robust.model": "--robust-model",
    "robust.vary": "--vary",
    "workers": "--workers",
}

HELP = "rank a sweep's designs by constraints and objectives (Pareto front)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("dir", help="sweep directory (with results.parquet or results.csv)")
    add_out(
        parser, required=False, what="where selection.json goes (default: DIR, where the report finds it)"
    )
    parser.add_argument(
        "--constraint", action="append", default=[], metavar="EXPR", help="e.g. 'max_strain <= 0.3'"
    )
    parser.add_argument(
        "--objective", action="append", default=[], metavar="EXPR", help="e.g. 'maximise bend_per_MPa_deg'"
    )
    parser.add_argument(
        "--model",
        default=None,
        type=model_name,
        choices=tuple(n for n in models.names() if n in MODEL_NAMES),
        help="model behind bend_angle_deg, max_strain, ... (default: section-nonlinear, then section, if the "
        "sweep has it, else paper)",
    )
    parser.add_argument(
        "--no-recheck",
        action="store_true",
        help="keep a linear model's ranking even where a bend constraint is beyond its validity",
    )
    parser.add_argument(
        "--load",
        default=None,
        choices=("cap", "lumen"),
        help=(
            "load case to select on "
            "(default: lumen for the section model and FEM, cap for the paper's formula)"
        ),
    )
    parser.add_argument("--top", type=int, default=50, help="designs kept in the ranked list (default 50)")
    parser.add_argument(
        "--designs",
        type=int,
        default=5,
        metavar="N",
        help="write the first N ranked designs as DIR/designs/design_ID.toml (default 5; 0: none)",
    )
    robust = parser.add_argument_group(
        "robust selection (re-evaluates the ranked designs over material ranges)"
    )
    robust.add_argument(
        "--robust",
        type=float,
        default=None,
        metavar="P",
        help="keep designs meeting every constraint with probability >= P (e.g. 0.95)",
    )
    robust.add_argument(
        "--vary",
        action="append",
        default=[],
        metavar="PATH=LO:HI",
        help="uncertain parameter (repeatable; default: the base design's ranges file)",
    )
    robust.add_argument("--ranges", default=None, metavar="FILE", help="ranges TOML (as softcath predict's)")
    robust.add_argument("--samples", type=int, default=32, help="samples per design (default 32)")
    add_seed(robust, what="seed of the sample")
    robust.add_argument(
        "--robust-model",
        default=None,
        type=model_name,
        choices=SEARCH_MODELS,
        help="model of the re-evaluation (default: section; paper for a paper selection)",
    )
    robust.add_argument("--workers", type=int, default=None, help="local worker processes (default 1)")
    robust.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    add_model_option(
        robust,
        tiers=tuple(models.get(n) for n in SEARCH_MODELS),
        where=" of the re-evaluation (--robust-model and the paper's formula)",
    )


def run(args: argparse.Namespace) -> int:
    if args.top < 1:
        raise SelectionError(f"--top = {args.top}: must be >= 1")
    if args.designs < 0:
        raise DesignError("--designs", args.designs, "must be >= 0")
    check_workers(args.workers, param="--workers")
    _check_expressions(args)
    robust = None
    if args.robust is None:
        refuse_model_options(
            args,
            "has no effect without --robust: select ranks the sweep's stored results, which hold the "
            "sweep's own options ([sweep.options.<tier>]); --robust re-evaluates them and takes tier options",
        )
    else:
        tiers = (args.robust_model,) if args.robust_model else SEARCH_MODELS
        robust = RobustSettings(
            options=models.parse_tier_options(args.model_option, tiers=(*tiers, "paper")),
            probability=args.robust,
            vary=args.vary,
            ranges=args.ranges,
            samples=args.samples,
            seed=args.seed,
            model=args.robust_model,
            progress=not args.no_progress,
        )
    with as_options(_ROBUST_OPTIONS):
        result = selection_run(
            args.dir,
            constraints=args.constraint,
            objectives=args.objective,
            load=args.load,
            top=args.top,
            model=args.model,
            recheck=not args.no_recheck,
            robust=robust,
            designs=args.designs,
            workers=args.workers,
            out=args.out,
        )
    sel, path, out = result.selection, result.path, result.out
    print(f"model: {MODEL_NAMES.get(sel.model, 'the table as given')} ({sel.model}), {sel.load} load")
    if sel.note:
        print(f"note: {sel.note}")
    if sel.recheck is not None:
        rc = sel.recheck
        print(
            f"{sel.n_feasible} of {sel.n_designs} designs meet the constraints on {rc['linear_model']} "
            f"({sel.load} load); re-checked on {sel.model}: {rc['n_passing']} of {rc['n_rechecked']} still "
            f"pass; Pareto front on {sel.model}: {len(sel.pareto_front)} of them"
        )
    else:
        print(
            f"{sel.n_feasible} of {sel.n_designs} designs meet the constraints ({sel.model}, "
            f"{sel.load} load); Pareto front: {len(sel.pareto_front)} designs"
        )
    for name, n in sel.rejected.items():
        if n:
            print(f"  removed {n}: {name}")
    for r in sel.ranked[:5]:
        objs = ", ".join(f"{k.split(None, 1)[-1]} = {v:.4g}" for k, v in r["objectives"].items())
        params = ", ".join(_parameter(k, v) for k, v in r["parameters"].items())
        print(
            f"  #{r['rank']} design {r['design_id']}{' (Pareto)' if r['pareto'] else ''}: {objs} "
            f"[{_source(sel)}]; {params}"
        )
        if "design_file" in r:
            print(f"    design file: {Path(out) / r['design_file']}")
    if sel.robust is not None:
        rb = sel.robust
        print(
            f"robust ({rb['model']} model, P = {rb['P']:g}, {rb['samples']} samples of "
            f"{', '.join(r['path'] for r in rb['ranges'])}): {rb['n_passing']} of {rb['n_evaluated']} pass"
        )
        if rb["left_out"]:
            print(f"  ranges left out (swept by the sweep): {', '.join(rb['left_out'])}")
        for r in sel.ranked[:5]:
            pct = "; ".join(
                f"{k.split(None, 1)[-1]}: {v['p5']:.4g}/{v['p50']:.4g}/{v['p95']:.4g}"
                for k, v in r["percentiles"].items()
            )
            prob = ", ".join(f"P({k}) = {v:.2f}" for k, v in r["probabilities"].items())
            print(
                f"  #{r['rank']} design {r['design_id']} (nominal #{r['nominal_rank']}): p5/p50/p95 {pct}; "
                f"{prob}"
            )
    print(f"selection: {path}")
    return 0


def _source(sel) -> str:
    """``section, lumen load`` (robust: ``section p50, lumen load``): where a ranked value comes from."""
    src = sel.source
    return f"{src['tier']}{' ' + src['statistic'] if 'statistic' in src else ''}, {src['load']} load"


def _parameter(path: str, value) -> str:
    """``tube.h=0.02 mm``: a swept value with its unit."""
    unit = unit_of(path)
    text = f"{value:.4g}" if isinstance(value, float) else str(value)
    return f"{path}={text}{' ' + unit if unit not in ('', '-') else ''}"


def _check_expressions(args: argparse.Namespace) -> None:
    """Parse every --constraint and --objective before any work; a refusal names the option."""
    for option, texts, parse in (
        ("--constraint", args.constraint, parse_constraint),
        ("--objective", args.objective, parse_objective),
    ):
        for text in texts:
            try:
                parse(text)
            except SelectionError as exc:
                raise DesignError(option, text, without_text(str(exc), text)) from None
