"""Run one FEM bending check of a design and compare it with the analytic model.

Linear (default): writes DIR/fem.json (curvature, elongation, tip pose,
strain, run facts and the analytic values for the same design, pressure and
load model), DIR/tip.vtu (open in ParaView), DIR/tip.png (deformed tip
coloured by strain) and DIR/tip.html (the same, rotatable in a browser, offline;
skipped with --no-png like tip.png). fem.json states the curvature's discretisation error
(``discretisation_error_estimate`` from a second solve at twice the mesh size, Richardson);
``--convergence`` adds convergence.csv/.json/.png (mesh sizes 2h, h, h/2).

``--nonlinear``: the finite-strain pressure sweep (docs/nonlinear.md), writing
DIR/fem.json (the linear check's keys plus steps and Newton iterations),
pressure_sweep.csv (per pressure: pressure_MPa, bend_angle_rad, bend_angle_deg,
curvature_per_mm (theta/s of the whole tip), curvature_mid_per_mm and
bend_rate_mid_per_mm (d theta/ds and d theta/dZ over the mid-span), elongation,
tip_x_mm, tip_y_mm, newton_iterations, linear_fem_bend_angle_rad,
analytic_bend_angle_rad, discretisation_error_estimate and its two parts
discretisation_error_layers, discretisation_error_section), tip_series.pvd + vtu/,
deformed_tip.png and bend_curve.png. The element layers default to the expected
bend and every run states its discretisation error: a half-layer solve (the layers
part) plus two small-load solves on a refined section (the section part);
``--convergence`` adds convergence.csv/.json/.png (L/2, L, 2L layers).

Both modes take the real load (lumen wall + cap) unless ``--load cap`` asks for the
paper's end-cap force; the summary and ``fem.json`` (``paper_formula``) give the paper's
formula beside the answer, under the cap load it is defined for. The modes' documented
defaults:

==================  ==========  ==============
option              linear      ``--nonlinear``
==================  ==========  ==============
``--pressure``      required    0.6 MPa (the paper's bench range)
``--load``          lumen       lumen
``--mesh-size``     0.16 mm     0.15 mm
==================  ==========  ==============

The files are written by the library: :func:`softcath.studies.outputs.fem_check.fem_check` and its
``write``; :func:`softcath.studies.outputs.fem_check.nonlinear_fem_check` with ``--nonlinear``.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass

from softcath.cli.options import add_assembly, add_design, add_out, resolve_design
from softcath.core.atomic import prepare_out_dir
from softcath.design.errors import DesignError
from softcath.fem.api import check_assembly
from softcath.fem.limits import check_fem_budget
from softcath.fem.nonlinear.errors import SettingError
from softcath.fem.nonlinear.outputs import NonlinearSettings
from softcath.studies.model_validity import check_pressure
from softcath.studies.outputs.fem_check import fem_check, nonlinear_fem_check

HELP = "one FEM bending check (mesh, solve, compare with the analytic model); --nonlinear for finite strain"

# (linear, nonlinear) defaults, as documented above and in docs/fem.md / docs/nonlinear.md.
# One load for both: the real one; the paper's cap force only when asked for.
DEFAULT_LOAD = {"linear": "lumen", "nonlinear": "lumen"}
DEFAULT_MESH_SIZE = {"linear": 0.16, "nonlinear": 0.15}
# The paper's bench range. At 1 MPa the paper tip's silicone passes 100 % strain (beyond its fits) and the
# walk on the default mesh cuts back from its first step and has stalled near 0.75 MPa: a bare command
# would run for many minutes and fail.
DEFAULT_NONLINEAR_PRESSURE = 0.6
DEFAULT_STEPS = 8
DEFAULT_CURVATURE_POINTS = 12


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design(parser)
    parser.add_argument(
        "--pressure",
        type=float,
        default=None,
        help=f"lumen pressure [MPa]; linear: required; --nonlinear: the top of the sweep "
        f"(default {DEFAULT_NONLINEAR_PRESSURE:g}, the paper's bench range)",
    )
    parser.add_argument(
        "--load",
        choices=("cap", "lumen"),
        default=None,
        help="cap: end-cap force only (the paper's model); lumen: wall + cap (the real load). "
        "Default: lumen (both modes)",
    )
    add_assembly(parser)
    add_out(parser)
    parser.add_argument(
        "--mesh-size",
        type=float,
        default=None,
        help="section element size [mm] (default 0.16 linear, 0.15 --nonlinear)",
    )
    lin = parser.add_argument_group("linear check")
    lin.add_argument(
        "--mesher",
        choices=("gmsh", "tetwild"),
        default="gmsh",
        help="gmsh: 2-D section + extrusion, seconds (default); tetwild: pytetwild, minutes",
    )
    lin.add_argument(
        "--coil-modulus",
        choices=("tension", "bending"),
        default="tension",
        help="homogenised coil axial modulus: spring tension (paper's E_eq) or Wahl bending",
    )
    lin.add_argument("--no-cache", action="store_true", help="do not read/write the mesh cache")
    lin.add_argument("--no-png", action="store_true", help="skip the PNG rendering")
    nl = parser.add_argument_group("finite strain (--nonlinear)")
    nl.add_argument(
        "--nonlinear", action="store_true", help="geometrically nonlinear FEM, hyperelastic silicone"
    )
    nl.add_argument(
        "--steps",
        type=int,
        default=DEFAULT_STEPS,
        help=f"pressure steps of the sweep (default {DEFAULT_STEPS})",
    )
    nl.add_argument(
        "--layers",
        type=int,
        default=None,
        help="element layers along the bending length (default: from the bend the finite-strain "
        "section model expects at the top pressure, <= 5 deg per layer, 8 to 16)",
    )
    nl.add_argument(
        "--curvature-points",
        type=int,
        default=DEFAULT_CURVATURE_POINTS,
        help=f"mesh segments per full circle (default {DEFAULT_CURVATURE_POINTS})",
    )
    nl.add_argument(
        "--area-true-section",
        action="store_true",
        help="move the section polygons' vertices so that each holds its curve's area (default: "
        "plain inscribed polygons; on the paper's design the plain section bends ~2 %% stiff, on "
        "thick-wire coils the area-true one ~3 %% soft)",
    )
    nl.add_argument(
        "--mixed",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="mixed u-p (P2-P0) formulation for the silicones (default: when their Poisson ratio >= 0.45)",
    )
    nl.add_argument(
        "--convergence",
        action="store_true",
        help="three-mesh study (linear: mesh sizes 2h, h, h/2; --nonlinear: L/2, L, 2L layers): "
        "observed order, extrapolated curvature, convergence.csv/.json/.png",
    )
    nl.add_argument(
        "--compare-linear",
        action="store_true",
        help="report the bend angle where linear FEM / analytic depart from nonlinear by 5%%",
    )


@dataclass(frozen=True)
class LinearSettings:
    """The linear check's settings after the mode's defaults are applied."""

    pressure: float
    load: str
    mesh_size: float
    convergence: bool = False


def linear_settings(args: argparse.Namespace) -> LinearSettings:
    """The linear check's pressure, load and mesh size from the parsed options."""
    if args.pressure is None:
        raise DesignError("--pressure", None, "is required for the linear check (e.g. --pressure 0.1)")
    return LinearSettings(
        pressure=args.pressure,
        load=args.load or DEFAULT_LOAD["linear"],
        mesh_size=args.mesh_size if args.mesh_size is not None else DEFAULT_MESH_SIZE["linear"],
        convergence=bool(args.convergence),
    )


def nonlinear_settings(args: argparse.Namespace) -> NonlinearSettings:
    """The :class:`~softcath.fem.nonlinear.NonlinearSettings` of the parsed options."""
    pressure = DEFAULT_NONLINEAR_PRESSURE if args.pressure is None else args.pressure
    if not pressure > 0:  # said in the command's terms: the linear check accepts 0 MPa
        raise DesignError("--pressure", pressure, "must be > 0 MPa for --nonlinear")
    try:
        return NonlinearSettings(
            pressure=pressure,
            steps=args.steps,
            load=args.load or DEFAULT_LOAD["nonlinear"],
            mesh_size=args.mesh_size if args.mesh_size is not None else DEFAULT_MESH_SIZE["nonlinear"],
            layers=args.layers,
            curvature_points=args.curvature_points,
            true_area=args.area_true_section,
            mixed=args.mixed,
            compare_linear=args.compare_linear,
            convergence=args.convergence,
        )
    except SettingError as exc:  # the settings own the bounds; the option's name is the command's
        raise DesignError("--" + exc.parameter.replace("_", "-"), exc.value, exc.bound) from None


def _run_nonlinear(d, args: argparse.Namespace, out) -> int:
    settings = nonlinear_settings(args)
    check_fem_budget(d, mesh_size=settings.mesh_size, param="--mesh-size")  # before minutes of meshing
    formula, lines = nonlinear_fem_check(d, settings, out)
    for line in lines:
        print(line)
    print(
        f"  paper's formula at {formula['pressure_MPa']:g} MPa, cap load (the load it is defined for): "
        f"{formula['bend_angle_deg']:.2f} deg, curvature {formula['curvature_per_mm']:.4g} 1/mm "
        "(as softcath analytic)"
    )
    return 0


def run(args: argparse.Namespace) -> int:
    out = prepare_out_dir(args.out)
    if args.pressure is not None:
        check_pressure(args.pressure, param="--pressure")
    d = resolve_design(args)
    if args.nonlinear:
        check_assembly(d.assembly)  # the finite-strain FEM fuses every interface
        return _run_nonlinear(d, args, out)
    s = linear_settings(args)
    finest = s.mesh_size / 2 if s.convergence else s.mesh_size  # the study's finest mesh
    check_fem_budget(d, mesh_size=finest, param="--mesh-size")  # before minutes of meshing
    n_stages = 12 if s.convergence else 5  # mesh, assemble, solve, fit (x3 meshes); error estimate
    stages = iter(range(1, n_stages + 1))

    def status(stage: str) -> None:
        print(f"[{next(stages, n_stages)}/{n_stages}] {stage} ...", file=sys.stderr, flush=True)

    fc = fem_check(
        d,
        s.pressure,
        load=s.load,
        mesh_size=s.mesh_size,
        mesher=args.mesher,
        coil_modulus=args.coil_modulus,
        use_cache=not args.no_cache,
        progress=status,
        convergence=s.convergence,
    )
    names = fc.write(out, picture=not args.no_png)
    result, c, formula = fc.result, fc.case, fc.paper_formula()
    ratio = formula["ratio_fem_over_formula"]
    print(
        f"{result.design_name}: linear 3-D FEM, {s.load} load at {s.pressure:g} MPa -> "
        f"curvature {c.curvature_per_mm:.4g} 1/mm (paper's formula, cap load by definition: "
        f"{formula['curvature_per_mm']:.4g}, ratio {'n/a' if ratio is None else f'{ratio:.3g}'}), "
        f"elongation {c.elongation:.3g}, "
        f"bend {math.degrees(c.bend_angle_rad):.3g} deg ({c.bend_angle_rad:.3g} rad), "
        f"max silicone strain {c.max_strain:.3g}"
    )
    print(
        f"mesh {result.n_elements} tets ({result.mesher}, "
        f"{'cached' if result.mesh_cached else f'{result.mesh_seconds:.1f} s'}), "
        f"{result.dofs} dofs, solve {result.solve_seconds:.1f} s, "
        f"backward error {result.residual:.1e}; wrote {out}/{', '.join(names)}"
    )
    for line in _error_lines(fc):
        print(line)
    return 0


def _error_lines(fc) -> list[str]:
    """The summary's lines on the discretisation error (and the three-mesh study's order)."""
    est, c = fc.result.discretisation_error, fc.case
    lines = []
    if fc.study is not None:
        st = fc.study
        q = st.observed_order
        ext = st.extrapolated[-1]
        lines.append(
            f"convergence (mesh {'/'.join(f'{h:g}' for h in st.mesh_size)} mm, "
            f"{'/'.join(str(n) for n in st.ndofs)} dofs): observed order "
            + ("n/a (not monotone)" if not math.isfinite(q) else f"{q:.3g}")
            + ", extrapolated curvature "
            + ("n/a" if not math.isfinite(ext) else f"{ext:.5g} 1/mm")
        )
    if est is not None and math.isfinite(c.discretisation_error_estimate):
        lines.append(
            f"estimated discretisation error of the curvature at mesh {est.mesh_size_mm:g} mm: "
            f"{100 * c.discretisation_error_estimate:.2g} % "
            f"(Richardson vs {est.companion_mesh_size_mm:g} mm, "
            f"order {est.order:.3g} {est.order_source}; {est.companion_seconds:.1f} s more)"
        )
    return lines
