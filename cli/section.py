"""The 2-D section model of a design: 3-D-FEM-grade gains in a fraction of a second.

Writes DIR/section.json (gains per MPa for the chosen load, section stiffness,
neutral axis, lumen-area change, the ratio to the paper's formula, run facts,
and both loads under ``loads``), DIR/section.csv (the ``analytic.csv``
columns over the pressure range) and DIR/section.png (the section deformed at
the highest pressure, coloured by axial stress).

``--coil-model`` chooses the coils' homogenisation (``annulus``, the 3-D FEM's
and the default; ``annulus-bending``; ``wahl``; ``resolved``, the resolved
wire's EA and EI). ``--coil-bound`` makes the coils' axial law bilinear
(coil-bound in compression, optional ``--initial-tension``): the response is
then nonlinear in pressure, section.csv holds the bilinear curve,
section.json a ``coil_bound`` block (threshold pressure, curve) and
DIR/section_curve.png the curvature against pressure.

``--nonlinear`` runs the finite-strain section model instead (large bends;
``softcath.cli.section_nonlinear``): the bend curve through every pressure of
the range, with DIR/section_curve.png against the linear model and, with
``--measured CSV``, a measured curve.

Several designs (``softcath section A.toml B.toml ...``) overlay their bend curves
(``softcath.cli.section_overlay``): DIR/overlay.csv, overlay.json and overlay.png, each
curve labelled with its design, tier and load, each value the single-design run's.

The files are written by the library: :func:`softcath.studies.outputs.section.section_run` and
its ``write``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from softcath.cli.options import (
    DESIGN_HELP,
    add_assembly,
    add_out,
    add_pressure_range,
    as_options,
    parse_pressure_range,
    resolve_design,
)
from softcath.cli.section_nonlinear import check_options, run_nonlinear
from softcath.cli.section_options import SECTION_OPTIONS, coil_options
from softcath.cli.section_overlay import run_overlay
from softcath.core.atomic import prepare_out_dir
from softcath.fem.limits import check_work_seconds
from softcath.studies.outputs.section import section_run

HELP = "2-D section model: FEM-grade curvature per MPa in milliseconds"

#: The coil-bound (bilinear) curve's cost, s: 3.9 s for 10^4 pressures of the paper section, 13 s for 10^5.
_BILINEAR_SECONDS = 3.0
_BILINEAR_SECONDS_PER_PRESSURE = 1.0e-4


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "design",
        nargs="+",
        metavar="DESIGN",
        help=f"{DESIGN_HELP}; several: their bend curves overlaid in one picture and one table",
    )
    add_pressure_range(p, default="0:0.6:13")
    p.add_argument(
        "--load",
        choices=("cap", "lumen"),
        default="lumen",
        help="lumen: wall pressure + cap force (the real load, default); cap: the paper's cap force only",
    )
    p.add_argument("--mesh-size", type=float, default=None, help="section element size [mm] (default 0.08)")
    p.add_argument("--segments", type=int, default=None, help="boundary points per full turn (default 20)")
    p.add_argument(
        "--mesher",
        choices=("template", "gmsh"),
        default="template",
        help="template: the section topology's mesh morphed to the design (default, within 0.2 %% of "
        "gmsh); gmsh: a fresh mesh",
    )
    p.add_argument(
        "--poisson",
        type=float,
        default=None,
        help="silicone Poisson ratio (tube and filler) instead of the design's, up to 0.49999",
    )
    p.add_argument(
        "--coil-model",
        choices=("annulus", "annulus-bending", "wahl", "resolved"),
        default=None,
        help="coil homogenisation: annulus (3-D FEM, default), annulus-bending, wahl (+ helical-spring EI), "
        "resolved (the resolved wire's EA and EI); replaces --coil-modulus/--coil-bending",
    )
    p.add_argument(
        "--coil-bound",
        action="store_true",
        help="bilinear coils: coil-bound (E·phi) in compression, spring in tension; with --coil-model "
        "annulus (bimodular annulus) or resolved (ring at the wire radius, default with this flag)",
    )
    p.add_argument(
        "--initial-tension",
        default=None,
        metavar="F0[,F0_CHANNEL]",
        help="coils' initial tension [N] (outer coil, channel; default the design's); implies --coil-bound",
    )
    p.add_argument(
        "--coil-modulus",
        choices=("tension", "bending"),
        default=None,
        help="homogenised coil axial modulus (default tension, as the 3-D FEM)",
    )
    p.add_argument(
        "--coil-bending",
        choices=("annulus", "wahl", "resolved"),
        default=None,
        help="annulus: coils bend as their annuli (3-D FEM, default); wahl: + helical-spring EI; "
        "resolved: the resolved wire's EA and EI",
    )
    add_assembly(p)
    p.add_argument(
        "--nonlinear",
        action="store_true",
        help="finite-strain section model: the bend curve at large bends (lumen area, volume, strain)",
    )
    p.add_argument(
        "--hoop-cap",
        type=float,
        default=None,
        metavar="X",
        help="with --nonlinear: cap the coils' hoop modulus at X times the stiffest silicone's E, as the "
        "3-D finite-strain FEM does (default: no cap)",
    )
    p.add_argument(
        "--measured",
        type=Path,
        default=None,
        metavar="CSV",
        help="with --nonlinear: a measurement CSV whose curvature is drawn against pressure",
    )
    p.add_argument("--no-png", action="store_true", help="skip the PNG")
    add_out(p)


def run(args: argparse.Namespace) -> int:
    check_options(args)
    if isinstance(args.design, list) and len(args.design) > 1:
        return run_overlay(args)
    if isinstance(args.design, list):
        args.design = args.design[0]
    if args.nonlinear:
        return run_nonlinear(args)
    pressures = parse_pressure_range(args.pressure)  # options first, then the folder, then the work
    coil_opts, placement, f0 = coil_options(args)
    if placement is not None:  # the bilinear curve is solved pressure by pressure
        check_work_seconds(
            _BILINEAR_SECONDS + _BILINEAR_SECONDS_PER_PRESSURE * len(pressures),
            param="--pressure",
            value=args.pressure,
            what=f"the coil-bound curve through {len(pressures)} pressures",
            hint="give fewer pressures",
        )
    d = resolve_design(args)
    out = prepare_out_dir(args.out)
    with as_options({**SECTION_OPTIONS, "pressures": "--pressure"}):
        s = section_run(
            d,
            pressures,
            load=args.load,
            silicone_poisson=args.poisson,
            mesher=args.mesher,
            mesh_size=args.mesh_size,
            segments=args.segments,
            coil_options=coil_opts,
            coil_bound=placement,
            initial_tension=f0,
            keep_fields=not args.no_png,
        )
    wrote = s.write(out, picture=not args.no_png)
    _print_summary(s.result, args.load, s.curve, placement)
    print(f"{s.result.dofs} dofs, {s.result.seconds * 1000:.0f} ms; wrote {out}/{', '.join(wrote)}")
    return 0


def _print_summary(r, ld: str, curve, placement) -> None:
    """The gains, stiffness and, for a coil-bound tip, its threshold and gains, on stdout."""
    print(
        f"{r.design_name}: {ld} load, silicone nu {r.poisson_ratio_silicone:g} -> curvature "
        f"{r.curvature_per_mm_per_MPa[ld]:.4g} 1/mm per MPa ({r.fem_formula_ratio[ld]:.3g}x the paper's "
        f"formula), elongation {r.elongation_per_MPa[ld]:.3g} per MPa; EA {r.EA_N:.4g} N, "
        f"EI {r.EI_N_mm2:.4g} N mm^2, neutral axis y = {r.neutral_axis_mm:.4g} mm"
    )
    if curve is not None:
        print(
            f"coil-bound ({placement}), initial tension "
            f"{curve.initial_tension[0]:g}/{curve.initial_tension[1]:g} N: "
            f"threshold {curve.threshold_pressure:.4g} MPa, then {curve.gain_pivoting:.4g} 1/mm per MPa "
            f"(linear {curve.gain_linear:.4g})"
        )
