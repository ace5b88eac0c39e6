"""Optimise a design over dotted design paths, with `select`'s expressions as objectives and constraints.

Example: softcath optimise paper --vary tube.h=-0.04:0.04 --vary tube.a_int=0.07:0.13
--objective "maximise bend_angle_deg at p=0.5" --constraint "max_strain <= 0.3" --out out/opt.
One objective: differential evolution (pymoo) then a COBYLA polish; several: NSGA-II (pymoo), the
Pareto set. --robust P optimises the objectives' p50 over the design's material/manufacturing ranges
(those of `softcath predict`) with every constraint met with probability >= P. Writes
DIR/optimum.json, DIR/history.parquet, DIR/designs/*.toml and the report DIR/index.html.

The files are written by the library: :func:`softcath.studies.outputs.optimum.optimum_run`.
"""

from __future__ import annotations

import argparse
import contextlib
from pathlib import Path

from softcath import models
from softcath.cli.options import (
    add_design,
    add_model_option,
    add_out,
    add_pressure_list,
    add_progress,
    add_seed,
    model_name,
    parse_pressure_list,
)
from softcath.core.atomic import prepare_out_dir
from softcath.design.errors import DesignError
from softcath.design.reference import unit_of
from softcath.fem.limits import check_workers
from softcath.studies.optimise import MODELS, check_search, make_problem, make_robustness
from softcath.studies.outputs.optimum import optimum_run
from softcath.studies.predict import resolve_ranges
from softcath.studies.predict.ranges import base_table

HELP = "optimise a design (DE or NSGA-II) under select-style objectives and constraints"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_design(p)
    p.add_argument(
        "--vary",
        action="append",
        default=[],
        metavar="PATH=LO:HI",
        required=True,
        help="a design variable: dotted design path and bounds (repeatable)",
    )
    p.add_argument(
        "--objective",
        action="append",
        default=[],
        metavar="EXPR",
        required=True,
        help="e.g. 'maximise bend_angle_deg at p=0.5' (repeat for a Pareto set)",
    )
    p.add_argument(
        "--constraint", action="append", default=[], metavar="EXPR", help="e.g. 'max_strain <= 0.3'"
    )
    p.add_argument(
        "--model",
        default="section",
        type=model_name,
        choices=MODELS,
        help="model tier evaluating every candidate (default section)",
    )
    p.add_argument(
        "--load",
        default=None,
        choices=("cap", "lumen"),
        help="load case (default: lumen; cap for the paper's formula)",
    )
    add_pressure_list(p, default="0.5")
    p.add_argument(
        "--robust",
        type=float,
        default=None,
        metavar="P",
        help="meet every constraint with probability >= P over the material ranges",
    )
    p.add_argument(
        "--robust-vary",
        action="append",
        default=[],
        metavar="PATH=LO:HI",
        help="uncertain parameter for --robust (default: the design's ranges file)",
    )
    p.add_argument("--ranges", type=Path, default=None, help="ranges TOML for --robust")
    p.add_argument("--samples", type=int, default=16, help="robust samples per candidate (default 16)")
    p.add_argument("--budget", type=int, default=200, help="candidate designs to evaluate (default 200)")
    add_seed(p, what="seed of the search and of the robust sample")
    backend = p.add_mutually_exclusive_group()
    backend.add_argument("--workers", type=int, default=None, help="local worker processes (default 1)")
    backend.add_argument(
        "--scheduler", default=None, metavar="tcp://HOST:PORT", help="an existing Dask scheduler"
    )
    p.add_argument("--no-fem-check", action="store_true", help="skip the 3-D FEM re-check of the winners")
    add_model_option(
        p, tiers=tuple(models.get(n) for n in MODELS), where=" (the --model tier and the paper's formula)"
    )
    add_progress(p)
    add_out(p)


def run(args: argparse.Namespace) -> int:
    # Everything that can be checked is checked before the output folder or any run.
    check_workers(args.workers, param="--workers")
    pressures = parse_pressure_list(args.pressures, param="--pressures")
    table = base_table(args.design)
    load = args.load or models.get(args.model).default_load
    with _as_options():
        problem = make_problem(
            table,
            variables=args.vary,
            objectives=args.objective,
            constraints=args.constraint,
            model=args.model,
            load=load,
            pressures=pressures,
            options=models.parse_tier_options(args.model_option, tiers=sorted({args.model, "paper"})),
        )
        robust = None
        if args.robust is not None:
            ranges = resolve_ranges(args.design, args.robust_vary, args.ranges)
            robust = make_robustness(args.robust, ranges, samples=args.samples, seed=args.seed)
        check_search(problem, budget=args.budget, seed=args.seed, robust=robust)
    out = prepare_out_dir(args.out)
    with _as_options():
        result = optimum_run(
            problem,
            out,
            budget=args.budget,
            seed=args.seed,
            robust=robust,
            workers=args.workers,
            scheduler=args.scheduler,
            fem_check=not args.no_fem_check,
            progress=not args.no_progress,
        )
    opt, paths, report = result.optimum, result.paths, result.report
    print(
        f"{opt.algorithm} on the {opt.model} model ({opt.load} load), {opt.backend}: "
        f"{opt.evaluations} designs ({opt.model_runs} model runs) in {opt.seconds:.1f} s"
    )
    for w in opt.best[:5]:
        objs = ", ".join(f"{k} = {v:.4g}" for k, v in w.objectives.items() if v is not None)
        objs += f" [{opt.model}, {opt.load} load]"
        params = ", ".join(f"{k}={v:.4g}{_unit(k)}" for k, v in w.parameters.items())
        print(f"  {w.name}{'' if w.feasible else ' (INFEASIBLE)'}: {objs}; {params}")
        if w.at_bounds:
            ends = ", ".join(f"{path} at its {end} bound" for path, end in w.at_bounds.items())
            print(
                f"    at the edge of the --vary range: {ends} (the optimum may lie beyond; widen the range)"
            )
        if w.probabilities is not None:
            pct = "; ".join(
                f"{k.split(None, 1)[-1]}: {_g(v['p5'])}/{_g(v['p50'])}/{_g(v['p95'])}"
                for k, v in w.percentiles.items()
            )
            prob = ", ".join(f"P({k}) = {v:.2f}" for k, v in w.probabilities.items())
            print(f"    p5/p50/p95 {pct}{'; ' + prob if prob else ''}")
        if w.fem_check:
            print(f"    {_fem_line(w.fem_check, opt.load)}")
    if len(opt.best) > 5:
        print(f"  ... {len(opt.best) - 5} more on the Pareto front")
    print(f"optimum: {paths['optimum']}; report: {report}")
    if not opt.feasible:
        given = ("--constraint", args.constraint) if args.constraint else ("--vary", args.vary)
        raise DesignError(
            given[0],
            given[1][0] if len(given[1]) == 1 else given[1],
            f"{opt.reason}; no design written ({paths['optimum']} records the search and why)",
        )
    return 0


def _flag(parameter: str) -> str:
    """The command-line option behind a library parameter name."""
    if parameter.partition(" ")[0] == "vary":  # a robust range: "vary PATH [low|high]"
        return f"--robust-vary{parameter[4:]}"
    head, _, rest = parameter.partition(".")
    flag = {
        "vary": "--vary",
        "objectives": "--objective",
        "constraints": "--constraint",
        "pressures": "--pressures",
        "model": "--model",
        "load": "--load",
        "budget": "--budget",
        "samples": "--samples",
        "seed": "--seed",
        "robust": "--robust",
        "workers": "--workers",
        "ranges": "--robust-vary/--ranges",
        "backend": "--workers/--scheduler",
    }.get(head)
    return f"{flag} {rest}".strip() if flag else parameter


@contextlib.contextmanager
def _as_options():
    """A library refusal in this command's terms (:func:`_flag`), value and bound kept."""
    try:
        yield
    except DesignError as exc:
        raise DesignError(_flag(exc.parameter), exc.value, exc.bound) from None


def _fem_line(check: dict, load: str | None = None) -> str:
    """The 3-D FEM re-check of one winner, with the tier and load its values come from."""
    where = f" [fem, {load} load]" if load else " [fem]"  # the re-check runs under the search's load
    if check["status"] != "ok":
        return f"3-D FEM re-check failed{where}: {check['reason']}"
    rd = check["curvature_rel_diff"]
    agree = f"; its curvature differs from the model's by {rd:.2%}" if rd is not None else ""
    if check["feasible"]:
        return f"3-D FEM: meets the constraints{where}{agree}"
    missed = check.get("missed") or {}
    which = "; ".join(
        f"{text} (undefined)" if m is None else f"{text} by {-m:.4g} (margin {m:.4g})"
        for text, m in missed.items()
    )
    return f"3-D FEM: MISSES {which or 'the constraints'}{where}{agree}"


def _unit(path: str) -> str:
    """`` mm`` after a value of a length path (nothing for a dimensionless or unknown one)."""
    unit = unit_of(path)
    return f" {unit}" if unit not in ("", "-") else ""


def _g(v) -> str:
    return "—" if v is None else f"{v:.4g}"
