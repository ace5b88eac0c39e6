"""``softcath section A.toml B.toml ...``: several designs' bend curves in one picture and one table.

Each design runs exactly as ``softcath section DESIGN`` would with the same options (the
linear section model, or the finite-strain one with ``--nonlinear``), so every value of the
overlay is the single-design run's. Writes DIR/overlay.csv (one row per design and pressure:
``design, tier, load`` and the ``section.csv`` columns plus ``bend_angle_deg``),
DIR/overlay.json (the designs, their tier, load and source) and DIR/overlay.png (curvature
and bend angle against pressure, one curve per design labelled with its name, tier and load).
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path

import numpy as np

from softcath.design.errors import DesignError

#: The overlay table's columns (units in the names; ``bend_angle_deg`` beside the radians).
COLUMNS = (
    "design",
    "tier",
    "load",
    "pressure_MPa",
    "curvature_per_mm",
    "elongation",
    "bend_angle_rad",
    "bend_angle_deg",
    "tip_x_mm",
    "tip_y_mm",
)
#: Single-design options the overlay does not take, and why.
_SINGLE_ONLY = (
    ("coil_bound", "--coil-bound"),
    ("initial_tension", "--initial-tension"),
    ("measured", "--measured"),
)
_TIER_LABEL = {"section": "linear section model", "section-nonlinear": "finite-strain section model"}


def run_overlay(args: argparse.Namespace) -> int:
    """Solve every design of ``args.design`` as ``softcath section`` does and write the overlay."""
    from softcath.cli.options import parse_pressures
    from softcath.studies.atomic import Outputs, prepare_out_dir

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
        from softcath.cli.section_nonlinear import check_cost

        walk = sorted({float(p) for p in pressures})
        for _, d in designs:
            if not d.assembly.is_default:
                raise DesignError("--assembly", d.assembly.to_dict(), "is not taken by --nonlinear")
            check_cost(d, len(walk), args)
    out = prepare_out_dir(args.out)
    curves = [(label, _curve(args, d, pressures, tier)) for label, d in designs]
    _warn(curves, tier)
    rows = [row for label, c in curves for row in _rows(label, tier, args.load, c)]
    with Outputs(out) as o:  # all files or none, only on success
        with o.path("overlay.csv").open("w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(COLUMNS))
            w.writeheader()
            for r in rows:
                w.writerow({k: v if isinstance(v, str) else f"{v:.10g}" for k, v in r.items()})
        o.json(
            "overlay.json",
            {
                "tier": tier,
                "load": args.load,
                "designs": [
                    {"label": label, "name": d.name, "source": src, "tier": tier, "load": args.load}
                    for (label, d), src in zip(designs, args.design, strict=True)
                ],
                "csv": "overlay.csv",
            },
        )
        if not args.no_png:
            _picture(curves, tier, args.load, o.path("overlay.png"))
    _print_table(curves, tier, args.load)
    print(f"wrote {out}/overlay.csv, overlay.json" + ("" if args.no_png else ", overlay.png"))
    return 0


def _designs(args: argparse.Namespace) -> list[tuple[str, object]]:
    """(label, design) per DESIGN argument; a name given twice is told apart by its argument."""
    from softcath.cli.options import resolve_design

    for i, src in enumerate(args.design):
        if src in args.design[:i]:
            raise DesignError("DESIGN", src, "is given twice; overlay different designs")
    designs = [resolve_design(argparse.Namespace(**{**vars(args), "design": src})) for src in args.design]
    names = [d.name for d in designs]
    return [
        (d.name if names.count(d.name) == 1 else f"{d.name} ({src})", d)
        for d, src in zip(designs, args.design, strict=True)
    ]


def _curve(args: argparse.Namespace, d, pressures: np.ndarray, tier: str) -> dict[str, np.ndarray]:
    """The design's curve as ``softcath section`` computes it: the ``section.csv`` columns."""
    from softcath.cli.options import as_options
    from softcath.cli.section import _OPTIONS, _coil_options

    if tier == "section-nonlinear":
        from softcath.studies.sweep.section_nonlinear_eval import curve_with_rest

        c = curve_with_rest(
            d,
            sorted({float(p) for p in pressures}),
            load=args.load,
            mesh_size=args.mesh_size,
            segments=args.segments,
            silicone_poisson=args.poisson,
            hoop_cap=args.hoop_cap,
            mesher=args.mesher,
            progress=True,
        )
        return {k: np.array([r[k] for r in c.rows()]) for k in COLUMNS[3:] if k != "bend_angle_deg"}
    from softcath.fem.section_model import section_model
    from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS

    coil_opts, _, _ = _coil_options(args)
    mesh = {
        "mesh_size": MESH_SIZE if args.mesh_size is None else args.mesh_size,
        "segments": SEGMENTS if args.segments is None else args.segments,
    }
    with as_options(_OPTIONS):
        r = section_model(d, silicone_poisson=args.poisson, mesher=args.mesher, **mesh, **coil_opts)
        resp = r.response(pressures, args.load)
    return {
        "pressure_MPa": resp.pressure,
        "curvature_per_mm": resp.curvature,
        "elongation": resp.elongation,
        "bend_angle_rad": resp.bend_angle,
        "tip_x_mm": resp.tip_x,
        "tip_y_mm": resp.tip_y,
    }


def _warn(curves: list[tuple[str, dict]], tier: str) -> None:
    """The single-design run's validity warnings, each naming its design."""
    from softcath.studies.model_validity import warn_linear_range, warn_self_contact

    for label, c in curves:
        if tier == "section":
            model = f"the section model (linear) on {label}"
            warn_linear_range(c["pressure_MPa"], c["bend_angle_rad"], elongation=c["elongation"], model=model)
        else:
            model = f"the finite-strain section model on {label}"
            warn_self_contact(c["pressure_MPa"], c["bend_angle_rad"], model=model)


def _rows(label: str, tier: str, load: str, c: dict[str, np.ndarray]) -> list[dict]:
    n = c["pressure_MPa"].size
    return [
        {
            "design": label,
            "tier": tier,
            "load": load,
            **{k: float(c[k][i]) for k in COLUMNS[3:] if k != "bend_angle_deg"},
            "bend_angle_deg": math.degrees(float(c["bend_angle_rad"][i])),
        }
        for i in range(n)
    ]


def _print_table(curves: list[tuple[str, dict]], tier: str, load: str) -> None:
    """Bend angle [deg] per pressure, one column per design, and each design's curvature at the top."""
    print(f"{len(curves)} designs on the {_TIER_LABEL[tier]} ({tier}), {load} load: bend angle [deg]")
    width = max(12, *(len(label) for label, _ in curves))
    print("  " + "pressure [MPa]".ljust(16) + "".join(label.rjust(width + 2) for label, _ in curves))
    pressures = curves[0][1]["pressure_MPa"]
    for i, p in enumerate(pressures):
        cells = "".join(f"{math.degrees(c['bend_angle_rad'][i]):.4g}".rjust(width + 2) for _, c in curves)
        print("  " + f"{p:g}".ljust(16) + cells)
    for label, c in curves:
        k = int(np.argmax(np.abs(c["pressure_MPa"])))
        print(
            f"  {label} [{tier}, {load} load]: at {c['pressure_MPa'][k]:g} MPa curvature "
            f"{c['curvature_per_mm'][k]:.4g} 1/mm, bend {math.degrees(c['bend_angle_rad'][k]):.1f} deg, "
            f"elongation {c['elongation'][k]:.3g}"
        )


def _picture(curves: list[tuple[str, dict]], tier: str, load: str, path: Path) -> None:
    """Curvature and bend angle against pressure, one labelled curve per design."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_k, ax_t) = plt.subplots(1, 2, figsize=(10, 4.2))
    for label, c in curves:
        order = np.argsort(c["pressure_MPa"])
        p = c["pressure_MPa"][order]
        name = f"{label} ({tier}, {load} load)"
        ax_k.plot(p, c["curvature_per_mm"][order], "o-", ms=3, label=name)
        ax_t.plot(p, np.degrees(c["bend_angle_rad"][order]), "o-", ms=3, label=name)
    ax_k.set_ylabel("curvature [1/mm]")
    ax_t.set_ylabel("bend angle [deg]")
    for ax in (ax_k, ax_t):
        ax.set_xlabel("pressure [MPa]")
        ax.grid(alpha=0.3)
    ax_t.legend(fontsize=8)
    fig.suptitle(f"bend curves: {_TIER_LABEL[tier]}, {load} load")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
