"""Run a design sweep from a TOML specification (grids, lists or a seeded Latin hypercube).

Each finished design is saved as it completes; run the same command again to
resume a killed sweep without recomputing finished designs. Results:
DIR/results.csv and DIR/results.parquet (one row per design x pressure x load).
"""

from __future__ import annotations

import argparse
import dataclasses

from softcath import models
from softcath.cli.options import add_model_option, add_out, add_progress, as_options
from softcath.core.atomic import folder_lock, prepare_out_dir
from softcath.studies.sweep import load_spec, run_sweep

HELP = "run a design sweep (local processes or Dask), resumable"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("spec", help="sweep specification TOML (see examples/sweeps/)")
    add_out(parser, what="sweep directory (created, or resumed)")
    backend = parser.add_mutually_exclusive_group()
    backend.add_argument("--workers", type=int, default=None, help="local worker processes (default: CPUs)")
    backend.add_argument(
        "--dask-local", type=int, default=None, metavar="N", help="run on a Dask LocalCluster of N workers"
    )
    backend.add_argument(
        "--scheduler", default=None, metavar="tcp://HOST:PORT", help="run on an existing Dask scheduler"
    )
    add_model_option(
        parser,
        tiers=models.tiers(),
        where=" of the spec's evaluators (over its [sweep.options.<tier>] tables)",
    )
    add_progress(parser)


def run(args: argparse.Namespace) -> int:
    spec = load_spec(args.spec)
    given = models.parse_tier_options(args.model_option, tiers=spec.evaluators)
    if given:  # over the spec's own tables; the fingerprint then tells the two option sets apart
        merged = {t: {**spec.options.get(t, {}), **given.get(t, {})} for t in {*spec.options, *given}}
        spec = dataclasses.replace(spec, options=models.check_tier_options(merged, tiers=spec.evaluators))
    out = prepare_out_dir(args.out)
    options = {"workers": "--workers", "dask_local": "--dask-local", "scheduler": "--scheduler"}
    with folder_lock(out, what="sweep"), as_options(options):  # a second sweep into the folder is refused
        s = run_sweep(
            spec,
            out,
            workers=args.workers,
            dask_local=args.dask_local,
            scheduler=args.scheduler,
            progress=not args.no_progress,
        )
    print(
        f"sweep {spec.name}: {s.n_designs} designs ({s.ok_designs} ok, {s.failed_designs} failed) "
        f"x {len(spec.pressures)} pressures x {len(spec.loads)} loads on {s.backend}; "
        f"evaluated {s.evaluated_designs} designs, {s.skipped_tasks} of {s.n_tasks} tasks already done; "
        f"{s.seconds:.1f} s"
    )
    if s.lost_tasks:
        print(f"{s.lost_tasks} tasks were lost to worker crashes: run the same command again to retry them")
    print(f"results: {s.results_csv} and {s.results_parquet.name}")
    return 0
