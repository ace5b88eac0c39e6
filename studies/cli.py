"""The ``softcath`` command line.

Each subcommand lives in its own module ``studies/cmd_<name>.py`` exposing
``HELP`` (one line), ``add_arguments(parser)`` and ``run(args) -> int``.
Modules import their heavy dependencies inside ``run`` so that
``softcath --help`` stays fast.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import sys

from design.errors import SoftcathError

# (subcommand, module): a missing module simply means the subcommand has not landed yet.
SUBCOMMANDS: tuple[tuple[str, str], ...] = (
    ("demo", "studies.cmd_demo"),
    ("design", "studies.cmd_design"),
    ("analytic", "studies.cmd_analytic"),
    ("calibrate", "studies.cmd_calibrate"),
    ("fem", "studies.cmd_fem"),
    ("section", "studies.cmd_section"),
    ("sweep", "studies.cmd_sweep"),
    ("report", "studies.cmd_report"),
    ("select", "studies.cmd_select"),
    ("measure", "studies.cmd_measure"),
    ("record", "studies.cmd_record"),
    ("bench", "studies.cmd_bench"),
    ("discrepancy", "studies.cmd_discrepancy"),
    ("coil", "studies.cmd_coil"),
    ("predict", "studies.cmd_predict"),
)


def build_parser() -> argparse.ArgumentParser:
    """Build the argument parser with every subcommand that is installed."""
    parser = argparse.ArgumentParser(
        prog="softcath",
        description="Design, check and measure a hydraulically actuated soft micro-catheter tip. "
        "Units: mm, N, MPa, s.",
    )
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress details")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, module_name in SUBCOMMANDS:
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as exc:
            if exc.name == module_name:
                continue
            raise
        p = sub.add_parser(name, help=module.HELP, description=module.__doc__)
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``softcath`` console script."""
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(
        level=logging.INFO if args.verbose else logging.WARNING,
        format="%(levelname)s %(name)s: %(message)s",
    )
    try:
        return int(args._run(args) or 0)
    except SoftcathError as exc:
        print(f"softcath {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except (FileNotFoundError, IsADirectoryError, PermissionError) as exc:
        print(f"softcath {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"softcath {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
