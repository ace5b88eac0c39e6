"""Options every command spells the same way: DESIGN, ``--out``, pressures, seeds, progress.

DESIGN is always a command's first positional argument (a preset name such
as ``paper`` or the path of a design ``.toml``); where a command can do
without one it defaults to ``paper``. ``--out DIR`` is the one output
folder of a command that writes files.
"""

from __future__ import annotations

import argparse
from pathlib import Path

DEFAULT_DESIGN = "paper"
DESIGN_HELP = "preset name (e.g. paper) or path to a design .toml"


def add_design(parser: argparse.ArgumentParser, *, optional: bool = False) -> None:
    """DESIGN, the first positional; ``optional`` makes it default to ``paper``."""
    if optional:
        parser.add_argument(
            "design",
            nargs="?",
            default=DEFAULT_DESIGN,
            metavar="DESIGN",
            help=f"{DESIGN_HELP} (default: paper)",
        )
    else:
        parser.add_argument("design", metavar="DESIGN", help=DESIGN_HELP)


def add_out(parser: argparse.ArgumentParser, *, required: bool = True, what: str = "output folder") -> None:
    """``--out DIR``: where the command writes its files (created; refused if it is a file)."""
    parser.add_argument("--out", type=Path, required=required, metavar="DIR", help=what)


def add_pressure_range(parser: argparse.ArgumentParser, *, default: str) -> None:
    """``--pressure START:STOP:N`` (MPa), or one pressure."""
    parser.add_argument(
        "--pressure", default=default, metavar="START:STOP:N", help=f"pressures in MPa (default {default})"
    )


def add_pressure_list(parser: argparse.ArgumentParser, *, default: str) -> None:
    """``--pressures P,P,...`` (MPa)."""
    parser.add_argument(
        "--pressures", default=default, metavar="P,P,...", help=f"pressures in MPa (default {default})"
    )


def add_seed(parser: argparse.ArgumentParser, *, what: str = "random seed") -> None:
    """``--seed N``: one integer makes every random draw of the command reproducible."""
    parser.add_argument("--seed", type=int, default=0, metavar="N", help=f"{what} (default 0)")


def add_progress(parser: argparse.ArgumentParser) -> None:
    """``--no-progress``: hide the progress bar (it goes to stderr)."""
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def design_or_data(design: str, data: Path | None) -> tuple[str, Path | None]:
    """``[DESIGN] [DATA]`` with one positional given: a ``.csv`` file or a folder is DATA, not DESIGN.

    A design is a preset name or a ``.toml`` file, so the two never look alike.
    """
    if data is None and design != DEFAULT_DESIGN:
        candidate = Path(design)
        if candidate.suffix.lower() == ".csv" or candidate.is_dir():
            return DEFAULT_DESIGN, candidate
    return design, data


def add_assembly(parser: argparse.ArgumentParser) -> None:
    """``--assembly KEY=VALUE`` (repeatable): override one key of the design's ``[assembly]``."""
    parser.add_argument(
        "--assembly",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="as-built option overriding the design's [assembly] table, repeatable: tube_coil, tube_channel, "
        "channel_coil, filler_coil = bonded|sliding|tied-at-tip; filler = full|coat|none; "
        "filler_coat_thickness = mm; proximal = clamped|tube-free",
    )


def resolve_design(args: argparse.Namespace):
    """The design of ``args.design`` with ``--assembly`` overrides applied."""
    from dataclasses import replace

    from softcath import design

    d = design.resolve(args.design)
    overrides = getattr(args, "assembly", None) or []
    return replace(d, assembly=d.assembly.with_overrides(overrides)) if overrides else d
