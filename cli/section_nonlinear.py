"""``softcath section --nonlinear``: the finite-strain section model's bend curve.

Writes DIR/section.csv (the ``analytic.csv`` columns, then the bend rate,
lumen area, ``lumen_volume_change_mm3``, ``max_strain``, Newton iterations and
residual per pressure), DIR/section.json (``"nonlinear": true``, the curve,
``seconds``, ``dofs``, per-pressure Newton counts, the linear gain on the same
laws and the pressure for 90 degrees) and DIR/section_curve.png (the linear
and finite-strain curves, and a measured curve given with ``--measured``).
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path

from softcath.cli.options import parse_pressure_range, resolve_design
from softcath.core.atomic import Outputs, prepare_out_dir
from softcath.core.errors import DesignError
from softcath.core.output_ledger import check_replace
from softcath.core.plotting import pyplot
from softcath.design.measurement import read_measurement_csv
from softcath.fem.limits import check_work_seconds, finite_strain_curve_seconds
from softcath.fem.section_model.finite_strain.curve import CSV_COLUMNS
from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS, check_size
from softcath.models.section_nonlinear_eval import curve_with_rest
from softcath.studies.model_validity import SELF_CONTACT_DEG, check_measured_pressures, warn_self_contact

#: Options of the linear section model that the finite-strain model does not take.
LINEAR_ONLY = ("coil_model", "coil_bound", "initial_tension", "coil_modulus", "coil_bending")


def check_options(args: argparse.Namespace) -> None:
    """Refuse linear-only options with ``--nonlinear`` and nonlinear-only ones without it."""
    if not args.nonlinear:
        for flag, value in (("--measured", args.measured), ("--hoop-cap", args.hoop_cap)):
            if value is not None:
                raise DesignError(flag, str(value), "needs --nonlinear")
        return
    if args.hoop_cap is not None and not (math.isfinite(args.hoop_cap) and args.hoop_cap > 0):
        raise DesignError("--hoop-cap", args.hoop_cap, "must be finite and > 0 (leave it out for no cap)")
    for name in LINEAR_ONLY:
        value = getattr(args, name, None)
        if value not in (None, False):
            flag = "--" + name.replace("_", "-")
            raise DesignError(flag, value, "is a linear section model option; not with --nonlinear")


def check_cost(d, n_pressures: int, args: argparse.Namespace) -> float:
    """Refuse a curve estimated beyond the work limit (warn above a minute); the estimate in s."""
    mesh_size = MESH_SIZE if args.mesh_size is None else args.mesh_size
    check_size(mesh_size, SEGMENTS if args.segments is None else args.segments)  # named by the library
    return check_work_seconds(
        finite_strain_curve_seconds(d, n_pressures, mesh_size=args.mesh_size, param="--mesh-size"),
        param="--pressure",
        value=args.pressure,
        what=f"the finite-strain curve through {n_pressures} pressures",
        hint="give fewer pressures (START:STOP:N with a smaller N)",
    )


def run_nonlinear(args: argparse.Namespace) -> int:
    check_options(args)
    pressures = parse_pressure_range(args.pressure)  # options first, then the folder, then the work
    if (pressures < 0).any():
        raise DesignError(
            "--pressure",
            args.pressure,
            "must be >= 0 MPa with --nonlinear (the finite-strain model inflates the lumen; suction "
            "is not modelled)",
        )
    walk = sorted({float(p) for p in pressures})
    d = resolve_design(args)
    check_cost(d, len(walk), args)
    measured = None
    if args.measured is not None:
        measured = read_measurement_csv(args.measured, missing="drop")
        check_measured_pressures(
            measured.pressure_MPa, max(walk), param="--measured", value=str(args.measured)
        )
    out = prepare_out_dir(args.out)
    check_replace(out, [out / n for n in ("section.json", "section.csv", "section_curve.png")])
    c = curve_with_rest(
        d,
        walk,
        load=args.load,
        mesh_size=args.mesh_size,
        segments=args.segments,
        silicone_poisson=args.poisson,
        hoop_cap=args.hoop_cap,
        mesher=args.mesher,
        progress=True,
    )
    contact = warn_self_contact(c.pressure, c.bend_angle_rad, model="the finite-strain section model")
    p90 = c.pressure_for_angle(math.pi / 2)
    doc = {
        "design": c.design_name,
        **c.to_json(),
        "pressure_for_90_deg_MPa": None if math.isnan(p90) else p90,
        "self_contact_from_MPa": _self_contact_from(c) if contact else None,
        "assembly": d.assembly.to_dict(),
    }
    wrote = "section.json, section.csv"
    with Outputs(out) as o:  # all files or none, only on success
        o.json("section.json", doc)
        with o.path("section.csv").open("w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(CSV_COLUMNS))
            w.writeheader()
            for r in c.rows():
                w.writerow({k: f"{v:.10g}" for k, v in r.items()})
        if not args.no_png:
            curve_picture(c, o.path("section_curve.png"), measured=measured)
            wrote += ", section_curve.png"
    top = c.pressure[-1]
    print(
        f"{c.design_name}: finite-strain section, {c.load} load, silicone nu {c.poisson_ratio_silicone:g}: "
        f"at {top:g} MPa curvature {c.curvature_per_mm[-1]:.4g} 1/mm (linear "
        f"{c.linear_curvature_per_mm_per_MPa * top:.4g}), "
        f"bend {math.degrees(c.bend_angle_rad[-1]):.1f} deg, elongation {c.elongation[-1]:.3g}, "
        f"lumen volume +{c.lumen_volume_change_mm3[-1]:.3g} mm^3, max silicone strain {c.max_strain[-1]:.3g}"
    )
    if not math.isnan(p90):
        print(f"90 deg of uniform-arc bend at {p90:.3g} MPa")
    if c.interface_slip_per_element is not None:  # the tip as built: its small-sliding measure
        print(
            f"as built ({', '.join(f'{k}={v}' for k, v in d.assembly.to_dict().items())}): "
            f"largest interface slip {c.interface_slip_per_element.max():.3g} element sizes"
        )
    print(
        f"{c.dofs} dofs, {int(c.newton_iterations.sum())} Newton iterations, {c.seconds:.2f} s; wrote "
        f"{out}/{wrote}"
    )
    return 0


def _self_contact_from(c) -> float:
    """The first pressure of ``c`` whose bend passes a full turn (the tip through itself)."""
    past = [
        p
        for p, a in zip(c.pressure, c.bend_angle_rad, strict=True)
        if abs(math.degrees(a)) > SELF_CONTACT_DEG
    ]
    return float(past[0])


def curve_picture(c, path: Path, *, measured=None) -> None:
    """Curvature and bend angle against pressure: finite-strain, linear and measured."""
    plt = pyplot()
    import numpy as np

    p = np.linspace(0.0, float(c.pressure.max()), 50)
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10, 4.2))
    ax.plot(c.pressure, c.curvature_per_mm, "o-", label="finite-strain section")
    ax.plot(p, c.linear_curvature_per_mm_per_MPa * p, "--", label="linear section")
    if measured is not None:
        ax.plot(
            measured.pressure_MPa,
            measured.curvature_per_mm,
            ".",
            ms=2,
            alpha=0.4,
            color="0.3",
            label="measured",
        )
    ax.set_xlabel("pressure [MPa]")
    ax.set_ylabel("curvature [1/mm]")
    ax.legend(fontsize=8)
    ax2.plot(c.pressure, np.degrees(c.bend_angle_rad), "o-", label="finite-strain section (uniform arc)")
    ax2.plot(p, np.degrees(c.linear_curvature_per_mm_per_MPa * p * c.length_mm), "--", label="linear section")
    ax2.axhline(90.0, color="0.6", lw=0.8)
    ax2.set_xlabel("pressure [MPa]")
    ax2.set_ylabel("bend angle [deg]")
    ax2.legend(fontsize=8)
    fig.suptitle(f"{c.design_name}, {c.load} load, nu = {c.poisson_ratio_silicone:g}")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
