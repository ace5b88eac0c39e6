"""The main job on the embedded default: the paper's design and bundled bench data through the
analytic model, FEM check (both loads), calibration (eq. 8), the missing-effect workflow and a small
sweep, ending in DIR/index.html."""

from __future__ import annotations

import argparse

from softcath import design, models
from softcath.cli.options import add_design, add_model_option, add_out
from softcath.core.atomic import prepare_out_dir
from softcath.core.errors import DataError, DesignError
from softcath.design.measurement import read_measurement_csv
from softcath.studies.demo import SECTIONS, run_demo
from softcath.studies.demo.runner import OPTION_TIERS

HELP = "run the whole story on the paper's design and write DIR/index.html"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design(parser, optional=True)
    add_out(parser)
    parser.add_argument(
        "--data", default=None, help="measurement CSV (default: the bundled bench_hysteresis.csv)"
    )
    parser.add_argument("--workers", type=int, default=2, help="processes for the sweep (default 2)")
    parser.add_argument("--only", default=None, help="comma-separated section keys to run (default: all)")
    parser.add_argument("--no-fem", action="store_true", help="skip the FEM (a quick look in seconds)")
    add_model_option(
        parser,
        tiers=tuple(models.get(n) for n in OPTION_TIERS),
        where=" (every number of that tier in the demo; the sweep takes the paper's and the section's)",
    )


def run(args: argparse.Namespace) -> int:
    keys = [k for k, _, _ in SECTIONS]
    only = None
    if args.only:
        only = tuple(s.strip() for s in args.only.split(",") if s.strip())
        bad = [s for s in only if s not in keys]
        if bad:
            raise DesignError("only", bad[0], f"unknown section; choose from {', '.join(keys)}")
    if args.workers < 1:
        raise DesignError("workers", args.workers, "must be an integer >= 1")
    options = models.parse_tier_options(args.model_option, tiers=OPTION_TIERS)

    out = prepare_out_dir(args.out)
    design.resolve(args.design)  # a bad design is refused before any section runs
    if args.data is not None:
        read_measurement_csv(args.data)  # so is a bad data file (the sections would each fail on it)
    res = run_demo(
        out,
        design_ref=args.design,
        data_csv=args.data,
        workers=args.workers,
        only=only,
        fem=not args.no_fem,
        options=options,
    )
    for s in res.sections:
        print(f"  {s['status']:<11} {s['seconds']:7.1f} s  {s['title']}")
    print(f"demo: {res.index_html} ({res.seconds:.0f} s)")
    failed = [s["key"] for s in res.sections if s["status"] == "failed"]
    if failed:
        raise DataError(
            f"{len(failed)} section(s) failed: {', '.join(failed)} (reasons in {res.index_html}; "
            "rerun with --debug --only KEY for the traceback)"
        )
    return 0
