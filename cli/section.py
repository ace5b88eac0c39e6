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
"""

from __future__ import annotations

import argparse
import csv
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

#: The section model's parameter names as this command's options.
_OPTIONS = {
    "silicone_poisson": "--poisson",
    "mesh_size": "--mesh-size",
    "segments": "--segments",
    "initial_tension (coil)": "--initial-tension (outer coil)",
    "initial_tension (channel)": "--initial-tension (channel)",
}

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


def _coil_options(args: argparse.Namespace) -> tuple[dict, str | None, tuple[float, float] | None]:
    """(section_model coil keywords, bilinear placement or None, initial tension override)."""
    from softcath.design.errors import DesignError
    from softcath.fem.section_model.coil_models import model_options

    if args.coil_model is not None:
        if args.coil_modulus is not None or args.coil_bending is not None:
            raise DesignError(
                "--coil-model", args.coil_model, "replaces --coil-modulus/--coil-bending: give one"
            )
        opts = model_options(args.coil_model)
    else:
        opts = {
            "coil_modulus": args.coil_modulus or "tension",
            "coil_bending": args.coil_bending or "annulus",
        }
    f0 = None
    if args.initial_tension is not None:
        try:
            f0 = tuple(float(v) for v in args.initial_tension.split(","))
        except ValueError:
            f0 = ()
        if len(f0) == 1:
            f0 = (f0[0], 0.0)
        if len(f0) != 2:
            raise DesignError("--initial-tension", args.initial_tension, "must be F0 or F0,F0_CHANNEL in N")
    if not (args.coil_bound or f0 is not None):
        return opts, None, None
    if args.coil_model is None and args.coil_modulus is None and args.coil_bending is None:
        opts = model_options("resolved")
    placement = {("tension", "annulus"): "annulus", ("tension", "resolved"): "resolved"}.get(
        (opts["coil_modulus"], opts["coil_bending"])
    )
    if placement is None:
        if args.coil_model is not None:
            given = ("--coil-model", args.coil_model)
        elif opts["coil_modulus"] != "tension":
            given = ("--coil-modulus", opts["coil_modulus"])
        else:
            given = ("--coil-bending", opts["coil_bending"])
        what = "--coil-bound" if args.coil_bound else "--initial-tension"
        raise DesignError(
            given[0], given[1], f"cannot be used with {what}: give --coil-model annulus or resolved"
        )
    return opts, placement, f0


def run(args: argparse.Namespace) -> int:
    from softcath.cli.section_nonlinear import check_options, run_nonlinear

    check_options(args)
    if isinstance(args.design, list) and len(args.design) > 1:
        from softcath.cli.section_overlay import run_overlay

        return run_overlay(args)
    if isinstance(args.design, list):
        args.design = args.design[0]
    if args.nonlinear:
        return run_nonlinear(args)
    from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS
    from softcath.studies.atomic import prepare_out_dir

    pressures = parse_pressure_range(args.pressure)  # options first, then the folder, then the work
    coil_opts, placement, f0 = _coil_options(args)
    if placement is not None:  # the bilinear curve is solved pressure by pressure
        from softcath.fem.limits import check_work_seconds

        check_work_seconds(
            _BILINEAR_SECONDS + _BILINEAR_SECONDS_PER_PRESSURE * len(pressures),
            param="--pressure",
            value=args.pressure,
            what=f"the coil-bound curve through {len(pressures)} pressures",
            hint="give fewer pressures",
        )
    d = resolve_design(args)
    out = prepare_out_dir(args.out)
    mesh = {
        "mesh_size": MESH_SIZE if args.mesh_size is None else args.mesh_size,
        "segments": SEGMENTS if args.segments is None else args.segments,
    }
    with as_options(_OPTIONS):
        return _solve_and_write(args, d, out, pressures, coil_opts, placement, f0, mesh)


def _solve_and_write(args, d, out, pressures, coil_opts, placement, f0, mesh) -> int:
    from softcath.fem.section_model import section_model
    from softcath.fem.section_model.picture import section_picture
    from softcath.studies.atomic import Outputs
    from softcath.studies.model_validity import check_finite_columns, warn_linear_range

    r = section_model(
        d,
        silicone_poisson=args.poisson,
        keep_fields=not args.no_png,
        mesher=args.mesher,
        **mesh,
        **coil_opts,
    )
    ld = args.load
    doc = _section_doc(r, ld)
    curve = None
    if placement is not None:
        from softcath.fem.section_model.bilinear import bend_curve

        curve = bend_curve(
            d,
            pressures,
            load=ld,
            coil_model=placement,
            initial_tension=f0,
            silicone_poisson=args.poisson,
            **mesh,
        )
        doc["coil_bound"] = curve.to_json()
    resp = r.response(pressures, ld) if curve is None else _curve_response(curve, r.length_mm)
    columns = {
        "curvature_per_mm": resp.curvature,
        "elongation": resp.elongation,
        "bend_angle_rad": resp.bend_angle,
    }
    check_finite_columns(columns, param="--pressure", value=args.pressure)
    model = "the section model (linear)" if curve is None else "the bilinear section model"
    warn_linear_range(pressures, resp.bend_angle, elongation=resp.elongation, model=model)
    wrote = "section.json, section.csv"
    with Outputs(out) as o:  # all files or none, only on success
        o.json("section.json", doc)
        _write_section_csv(o.path("section.csv"), resp)
        if not args.no_png:
            p_show = float(max(abs(pressures.max()), abs(pressures.min()))) or 0.1
            section_picture(r, o.path("section.png"), load=ld, pressure=p_show)
            wrote += ", section.png"
            if curve is not None:
                _curve_picture(curve, r, o.path("section_curve.png"))
                wrote += ", section_curve.png"
    _print_summary(r, ld, curve, placement)
    print(f"{r.dofs} dofs, {r.seconds * 1000:.0f} ms; wrote {out}/{wrote}")
    return 0


def _section_doc(r, ld: str) -> dict:
    """``section.json``: the gains under load ``ld``, the stiffness and mesh facts, every load's gains."""
    full = r.to_json()
    return {
        "design": r.design_name,
        "load": ld,
        "curvature_per_mm_per_MPa": r.curvature_per_mm_per_MPa[ld],
        "elongation_per_MPa": r.elongation_per_MPa[ld],
        "lumen_area_change_mm2_per_MPa": r.lumen_area_change_mm2_per_MPa[ld],
        "fem_formula_ratio": r.fem_formula_ratio[ld],
        **{
            k: full[k]
            for k in (
                "EA_N",
                "EI_N_mm2",
                "EI_lateral_N_mm2",
                "coupling_N_mm",
                "neutral_axis_mm",
                "axial_centroid_mm",
                "lumen_area_mm2",
                "poisson_ratio_silicone",
                "coil_modulus",
                "coil_bending",
                "mesh_size_mm",
                "segments",
                "dofs",
                "n_triangles",
                "seconds",
                "mesh_seconds",
                "backward_error",
                "stiffness",
            )
        },
        "assembly": full["assembly"],
        "axial_groups": full["axial_groups"],
        "loads": {
            k: full[k]
            for k in (
                "curvature_per_mm_per_MPa",
                "elongation_per_MPa",
                "lumen_area_change_mm2_per_MPa",
                "fem_formula_ratio",
            )
        },
    }


def _write_section_csv(path: Path, resp) -> None:
    """``section.csv``: curvature, elongation, bend angle and tip position per pressure."""
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            ["pressure_MPa", "curvature_per_mm", "elongation", "bend_angle_rad", "tip_x_mm", "tip_y_mm"]
        )
        for row in zip(
            resp.pressure,
            resp.curvature,
            resp.elongation,
            resp.bend_angle,
            resp.tip_x,
            resp.tip_y,
            strict=True,
        ):
            w.writerow([f"{v:.10g}" for v in row])


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


def _curve_response(curve, length_mm: float):
    """The bilinear curve as an ``analytic.BeamResponse`` (eq. 9 pose)."""
    from softcath.analytic import BeamResponse
    from softcath.analytic.pose import tip_pose

    length = length_mm * (1 + curve.elongation)
    tip_x, tip_y, theta = tip_pose(curve.curvature, length)
    return BeamResponse(curve.pressure, curve.curvature, curve.elongation, length, theta, tip_x, tip_y)


def _curve_picture(curve, result, path: Path) -> None:
    """Curvature against pressure: the bilinear curve, its asymptote and the linear model."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    p = np.sort(curve.pressure)
    order = np.argsort(curve.pressure)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.plot(p, curve.curvature[order], "o-", label=f"coil-bound ({curve.coil_model})")
    ax.plot(p, result.curvature_per_mm_per_MPa[curve.load] * p, "--", label=f"linear, {result.coil_bending}")
    if curve.threshold_pressure > 0:
        ax.axvline(curve.threshold_pressure, color="0.6", lw=0.8)
        ax.annotate(
            f"threshold {curve.threshold_pressure:.3g} MPa", (curve.threshold_pressure, 0), fontsize=8
        )
    ax.set_xlabel("pressure [MPa]")
    ax.set_ylabel("curvature [1/mm]")
    ax.set_title(f"{curve.design_name}, {curve.load} load, F0 = {curve.initial_tension[0]:g} N")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
