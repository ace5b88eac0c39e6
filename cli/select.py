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
"""

from __future__ import annotations

import argparse
from pathlib import Path

from softcath.cli.options import add_out, add_seed, model_name

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
        choices=("paper", "section", "section-nonlinear", "fem"),
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
        choices=("paper", "section", "section-nonlinear"),
        help="model of the re-evaluation (default: section; paper for a paper selection)",
    )
    robust.add_argument("--workers", type=int, default=None, help="local worker processes (default 1)")
    robust.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def run(args: argparse.Namespace) -> int:
    from softcath.fem.limits import check_workers
    from softcath.studies.selection import MODEL_NAMES, SelectionError, select, write_selection
    from softcath.studies.sweep.results import read_results

    if args.top < 1:
        raise SelectionError(f"--top = {args.top}: must be >= 1")
    if args.designs < 0:
        from softcath.design.errors import DesignError

        raise DesignError("--designs", args.designs, "must be >= 0")
    check_workers(args.workers, param="--workers")
    _check_expressions(args)
    from softcath.design.errors import DataError

    if not Path(args.dir).is_dir():
        raise DataError(f"{args.dir}: not a sweep directory (run `softcath sweep SPEC --out DIR` first)")
    df = read_results(args.dir)
    sel = select(
        df,
        constraints=args.constraint,
        objectives=args.objective,
        load=args.load,
        top=args.top,
        model=args.model,
    )
    out = args.dir
    if args.out is not None:
        from softcath.studies.atomic import prepare_out_dir

        out = prepare_out_dir(args.out)
    sel = _validity(args, sel, df)
    if not args.no_recheck:
        sel = _recheck(args, sel, df)
    if args.robust is not None:
        sel = _robust(args, sel)
    from softcath.studies.selection.designs import chosen_design_files

    sel, files = chosen_design_files(sel, args.dir, count=args.designs)
    path = write_selection(sel, out, designs=files)
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
    from softcath.design.reference import unit_of

    unit = unit_of(path)
    text = f"{value:.4g}" if isinstance(value, float) else str(value)
    return f"{path}={text}{' ' + unit if unit not in ('', '-') else ''}"


def _check_expressions(args: argparse.Namespace) -> None:
    """Parse every --constraint and --objective before any work; a refusal names the option."""
    from softcath.design.errors import DesignError
    from softcath.studies.selection import SelectionError
    from softcath.studies.selection.criteria import parse_constraint, parse_objective, without_text

    for option, texts, parse in (
        ("--constraint", args.constraint, parse_constraint),
        ("--objective", args.objective, parse_objective),
    ):
        for text in texts:
            try:
                parse(text)
            except SelectionError as exc:
                raise DesignError(option, text, without_text(str(exc), text)) from None


def _manifest(args: argparse.Namespace, why: str) -> tuple[dict, dict]:
    """(spec, base_table) from the sweep's manifest."""
    import json
    from pathlib import Path

    from softcath.design.errors import DataError

    manifest = Path(args.dir) / "sweep.json"
    try:
        doc = json.loads(manifest.read_text(encoding="utf-8"))
        return doc["spec"], doc["base_table"]
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise DataError(f"{manifest}: cannot read the sweep's manifest ({exc}); {why} needs it") from None


def _validity(args: argparse.Namespace, sel, df):
    """Warn (and record in the selection) when a linear tier ranked designs bending past its validity."""
    import dataclasses
    import logging

    from softcath.studies.selection import large_bend_constraints
    from softcath.studies.selection.large_bends import LINEAR_MODELS, linear_validity_warning
    from softcath.studies.sweep.results import model_columns

    if sel.model not in LINEAR_MODELS:
        return sel
    cols = model_columns(df, sel.model)
    rechecked = not args.no_recheck and bool(large_bend_constraints(sel, cols))
    msg = linear_validity_warning(sel, cols, rechecked=rechecked)
    if not msg:
        return sel
    logging.getLogger("softcath.validity").warning(msg)
    return dataclasses.replace(sel, warnings=(*sel.warnings, msg))


def _recheck(args: argparse.Namespace, sel, df):
    """Re-check with the finite-strain section model a bend constraint beyond a linear model's validity."""
    from softcath.studies.selection import large_bend_constraints, recheck_large_bends
    from softcath.studies.sweep.results import model_columns

    if sel.model not in ("paper", "section", "fem"):
        return sel
    big = large_bend_constraints(sel, model_columns(df, sel.model))
    if not big:
        return sel
    spec, base_table = _manifest(args, "the large-bend re-check (or give --no-recheck)")
    return recheck_large_bends(
        sel, base_table=base_table, pressures=spec["pressures_MPa"], constraints=big, workers=args.workers
    )


def _robust(args: argparse.Namespace, sel):
    """The robust re-evaluation of the nominal ranking."""
    import json
    from pathlib import Path

    from softcath.design.errors import DataError, DesignError
    from softcath.studies.selection import robust_select, sweep_ranges

    manifest = Path(args.dir) / "sweep.json"
    try:
        doc = json.loads(manifest.read_text(encoding="utf-8"))
        spec, base_table = doc["spec"], doc["base_table"]
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise DataError(f"{manifest}: cannot read the sweep's manifest ({exc}); --robust needs it") from None
    try:
        ranges = sweep_ranges(spec.get("base", ""), base_table, args.vary, args.ranges)
        return robust_select(
            sel,
            base_table=base_table,
            pressures=spec["pressures_MPa"],
            probability=args.robust,
            ranges=ranges,
            samples=args.samples,
            seed=args.seed,
            model=args.robust_model,
            workers=args.workers,
            progress=not args.no_progress,
        )
    except DesignError as exc:
        flags = {
            "robust": "--robust",
            "samples": "--samples",
            "seed": "--seed",
            "ranges": "--vary/--ranges",
            "model": "--robust-model",
            "workers": "--workers",
        }
        head, _, rest = exc.parameter.partition(" ")
        if head == "vary":  # a range given with --vary: "vary PATH [low|high]"
            raise DesignError(f"--vary {rest}".strip(), exc.value, exc.bound) from None
        raise DesignError(flags.get(exc.parameter, exc.parameter), exc.value, exc.bound) from None
