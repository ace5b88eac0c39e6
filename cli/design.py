"""Show, validate or export a catheter-tip design (a preset name or a TOML path)."""

from __future__ import annotations

import argparse
from pathlib import Path

from softcath import design
from softcath.analytic import composite_section, gains
from softcath.cli.options import add_design, add_out
from softcath.core.atomic import Outputs, atomic_path, check_outputs, check_parent, prepare_out_dir
from softcath.design import cad  # CadQuery: lazily, only for export
from softcath.studies.plots import section_plot

HELP = "show / validate / export (STEP, STL) a design"


def add_arguments(p: argparse.ArgumentParser) -> None:
    sub = p.add_subparsers(dest="action", required=True, metavar="ACTION")
    show = sub.add_parser("show", help="print a design, its as-assembled section and stiffness")
    add_design(show)
    show.add_argument("--toml", action="store_true", help="print the design as TOML instead")
    add_out(show, required=False, what="also write section.png and design.json here")
    val = sub.add_parser("validate", help="check a design file; exit non-zero with the reason if impossible")
    add_design(val)
    exp = sub.add_parser("export", help="write CAD solids (STEP: one solid per component; STL: the assembly)")
    add_design(exp)
    add_out(exp, required=False, what="write NAME.step and NAME.stl here (or the --step / --stl files)")
    exp.add_argument("--step", type=Path, help="STEP output path (relative: inside --out)")
    exp.add_argument("--stl", type=Path, help="STL output path (relative: inside --out)")


def run(args: argparse.Namespace) -> int:
    d = design.resolve(args.design)
    if args.action == "validate":
        squeezed = "" if d.catalogue_fits else "; note: the catalogue tube is squeezed to fit"
        print(f"{args.design}: valid design '{d.name}'{squeezed}")
        print(d.fit_report())
        return 0
    if args.action == "export":
        if not (args.step or args.stl or args.out):
            raise design.DesignError("export", None, "give --out DIR, --step PATH and/or --stl PATH")

        step, stl = args.step, args.stl
        if args.out and not (step or stl):
            step, stl = Path(f"{d.name}.step"), Path(f"{d.name}.stl")
        # Outputs never collide with each other or the input design, and stay inside --out.
        paths = check_outputs({"--step": step, "--stl": stl}, inside=args.out, inputs=[Path(args.design)])
        step, stl = paths.get("--step"), paths.get("--stl")
        if args.out:
            prepare_out_dir(args.out)
        targets = [(step, "--step", cad.export_step), (stl, "--stl", cad.export_stl)]
        targets = [(check_parent(path, param=param), param, fn) for path, param, fn in targets if path]
        for path, _param, fn in targets:
            with atomic_path(path) as tmp:
                fn(d, tmp)
            print(f"wrote {path} ({path.stat().st_size} bytes)")
        return 0
    if args.toml:
        print(design.dumps(d), end="")
        return 0
    out = None
    if args.out:
        out = prepare_out_dir(args.out)
    cs = composite_section(d)
    kc, ec = gains(d, "cap")
    kl, el = gains(d, "lumen")
    coil, chan = design.coil_stiffness(d.coil), design.coil_stiffness(d.channel)
    print(f"design '{d.name}'  (lengths mm, moduli MPa)")
    print(d.fit_report())
    print(
        f"coil: OD {d.coil.outer_diameter:g} ID {d.coil.inner_diameter:g} wire {d.coil.wire_diameter:g} "
        f"pitch {d.coil.pitch:g}; E_tension {coil.axial_modulus_tension:.4g}, E_compression "
        f"{coil.axial_modulus_compression:.4g}, EI {coil.bending_stiffness:.4g} N mm^2"
    )
    print(
        f"channel: OD {d.channel.outer_diameter:g} ID {d.channel.inner_diameter:g}; E_tension "
        f"{chan.axial_modulus_tension:.4g}, EI {chan.bending_stiffness:.4g} N mm^2"
    )
    print(f"filler: {d.filler.name if d.filler else 'void'};  tip L0 = {d.tip.bending_length:g} mm")
    print(
        f"composite: EA {cs.EA:.4g} N, EI {cs.EI:.4g} N mm^2, neutral axis y {cs.neutral_axis_y:.4g}, "
        f"pressure centre y {cs.pressure_centre_y:.4g}, A_p {cs.pressure_area:.4g} mm^2"
    )
    print(f"gains (cap load): {kc:.4g} 1/(mm MPa), {ec:.4g} 1/MPa;  (lumen load): {kl:.4g}, {el:.4g}")
    if out is not None:
        doc = {
            "name": d.name,
            "section_mm": d.section.__dict__ | {"lumen_center_y": d.section.lumen_center_y},
            "composite": {k: v for k, v in composite_section(d).__dict__.items()},
            "gains": {"cap": [kc, ec], "lumen": [kl, el]},
        }
        with Outputs(out) as o:
            section_plot(o.path("section.png"), d)
            o.json("design.json", doc, default=float)
        print(f"wrote {out / 'section.png'} and {out / 'design.json'}")
    return 0
