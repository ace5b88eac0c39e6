"""Several designs' bend curves overlaid: ``softcath section A.toml B.toml ...``.

Each design is solved as ``softcath section`` solves one (the linear section model, or the
finite-strain one with ``--nonlinear``) by :func:`softcath.studies.outputs.overlay.overlay`,
which writes DIR/overlay.csv (one row per design and pressure: design, tier, load and the
``section.csv`` columns with ``bend_angle_deg``), DIR/overlay.json (the designs, their tier,
load and source) and DIR/overlay.png (curvature and bend angle against pressure, one labelled
curve per design).
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from softcath.cli.options import as_options, parse_pressures, resolve_design
from softcath.cli.section_nonlinear import check_cost
from softcath.cli.section_options import SECTION_OPTIONS, coil_options
from softcath.core.atomic import prepare_out_dir
from softcath.design.errors import DesignError
from softcath.studies.outputs.overlay import COLUMNS, TIER_LABEL, Overlay, overlay

__all__ = ["COLUMNS", "run_overlay"]

#: Single-design options the overlay does not take, and why.
_SINGLE_ONLY = (
    ("coil_bound", "--coil-bound"),
    ("initial_tension", "--initial-tension"),
    ("measured", "--measured"),
)


def run_overlay(args: argparse.Namespace) -> int:
    """Solve every design of ``args.design`` as ``softcath section`` does and write the overlay."""
    for dest, flag in _SINGLE_ONLY:
        value = getattr(args, dest, None)
        if value not in (None, False):
            raise DesignError(flag, value, "is taken with one design only (several designs given)")
    pressures = parse_pressures(args.pressure)  # options first, then the designs, the folder, the work
    tier = "section-nonlinear" if args.nonlinear else "section"
    if args.nonlinear and (pressures < 0).any():
        raise DesignError("--pressure", args.pressure, "must be >= 0 MPa with --nonlinear")
    designs = _designs(args)
    if args.nonlinear:
        walk = sorted({float(p) for p in pressures})
        for d in designs:
            check_cost(d, len(walk), args)
    coil = None if args.nonlinear else coil_options(args)[0]
    out = prepare_out_dir(args.out)
    with as_options({} if args.nonlinear else SECTION_OPTIONS):
        result = overlay(
            designs,
            pressures,
            sources=args.design,
            tier=tier,
            load=args.load,
            mesh_size=args.mesh_size,
            segments=args.segments,
            silicone_poisson=args.poisson,
            mesher=args.mesher,
            hoop_cap=args.hoop_cap,
            coil_options=coil,
            progress=True,
        )
    wrote = result.write(out, picture=not args.no_png)
    _print_table(result)
    print(f"wrote {out}/{', '.join(wrote)}")
    return 0


def _designs(args: argparse.Namespace) -> list:
    """The design of each DESIGN argument; the same argument twice is refused."""
    for i, src in enumerate(args.design):
        if src in args.design[:i]:
            raise DesignError("DESIGN", src, "is given twice; overlay different designs")
    return [resolve_design(argparse.Namespace(**{**vars(args), "design": src})) for src in args.design]


def _print_table(result: Overlay) -> None:
    """Bend angle [deg] per pressure, one column per design, and each design's curvature at the top."""
    tier, load, curves = result.tier, result.load, result.curves
    print(f"{len(curves)} designs on the {TIER_LABEL[tier]} ({tier}), {load} load: bend angle [deg]")
    width = max(12, *(len(c.label) for c in curves))
    print("  " + "pressure [MPa]".ljust(16) + "".join(c.label.rjust(width + 2) for c in curves))
    for i, p in enumerate(curves[0].columns["pressure_MPa"]):
        angles = (math.degrees(c.columns["bend_angle_rad"][i]) for c in curves)
        cells = "".join(f"{a:.4g}".rjust(width + 2) for a in angles)
        print("  " + f"{p:g}".ljust(16) + cells)
    for c in curves:
        k = c.columns
        i = int(np.argmax(np.abs(k["pressure_MPa"])))
        print(
            f"  {c.label} [{tier}, {load} load]: at {k['pressure_MPa'][i]:g} MPa curvature "
            f"{k['curvature_per_mm'][i]:.4g} 1/mm, bend {math.degrees(k['bend_angle_rad'][i]):.1f} deg, "
            f"elongation {k['elongation'][i]:.3g}"
        )
