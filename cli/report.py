"""Write DIR/report/index.html for a sweep: parity, error vs parameters, heat maps, sensitivity,
renders, failed designs and the selection. Static HTML with PNGs beside it; opens offline."""

from __future__ import annotations

import argparse

from softcath.cli.options import add_model_option, add_out, refuse_model_options
from softcath.core.atomic import prepare_out_dir
from softcath.core.errors import DataError
from softcath.studies.report import write_report

HELP = "write a static HTML report of a sweep directory"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("dir", help="sweep directory (from `softcath sweep`)")
    add_out(parser, required=False, what="report folder (default: DIR/report)")
    add_model_option(
        parser,
        where=": refused, the report draws the sweep's stored results, computed with the sweep's own options "
        "(its [sweep.options.<tier>] tables, listed in the report)",
    )


def run(args: argparse.Namespace) -> int:
    import re
    from pathlib import Path

    refuse_model_options(
        args,
        "is not taken by report: it draws the sweep's stored results, which hold the sweep's tier options "
        "(give them to the sweep, as --model-option or [sweep.options.<tier>]; the report lists them)",
    )
    if not Path(args.dir).is_dir():
        raise DataError(f"{args.dir}: not a sweep directory (run `softcath sweep SPEC --out DIR` first)")

    out = None
    if args.out is not None:
        out = prepare_out_dir(args.out)
    path, _ = write_report(args.dir, out=out)
    # the report's figures, not other PNGs the folder holds
    n = len(set(re.findall(r'<img src="([^"]+)"', path.read_text(encoding="utf-8"))))
    print(f"report: {path} ({n} figures)")
    return 0
