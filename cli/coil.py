"""Resolved-wire stiffness of a design's outer coil and channel, against the homogenised models.

Writes DIR/coil.json (per coil: axial stiffness in tension and compression,
bending stiffness of the wire alone, with turns in contact and with turns held
closed, initial tension and the measured threshold, resolved/homogenised
ratios, the homogenised models and closed forms, model size and time) and
DIR/coil.png (the helix bent with contact, coloured by contact force).
Stiffness per unit length: EA = F/ε [N], EI = M/κ [N mm²].
"""

from __future__ import annotations

import argparse

from softcath import design
from softcath.cli.options import add_design, add_out, as_options
from softcath.core.atomic import Outputs, prepare_out_dir
from softcath.fem.coil import closed_forms as cf
from softcath.fem.coil import coil_wire, resolved_coil_stiffness
from softcath.fem.coil.helix import helix_mesh
from softcath.fem.coil.homogenised import homogenised_models
from softcath.fem.coil.picture import bent_coil_picture

HELP = "resolved-wire coil stiffness (tension, compression, bending with contact) vs homogenised models"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design(parser)
    add_out(parser)
    parser.add_argument(
        "--elements-per-turn", type=int, default=48, help="frame elements per turn of wire (default 48, >= 6)"
    )
    parser.add_argument("--no-png", action="store_true", help="skip the picture")


def coil_report(coil, *, elements_per_turn: int = 48) -> dict:
    """The coil.json entry of one coil (resolved wire, ratios, homogenised models, closed forms)."""
    r = resolved_coil_stiffness(coil, elements_per_turn=elements_per_turn)
    models = homogenised_models(coil)
    wire, geo = coil_wire(coil), {"radius": coil.mean_radius, "pitch": coil.pitch}
    spring_ea = models["spring_wahl"]["axial_tension_N"]
    wahl = models["spring_wahl"]["bending_N_mm2"]
    annulus_ei = models["annulus_tension"]["bending_N_mm2"]
    return {
        "axial_tension_N": r.axial_tension,
        "axial_compression_N": r.axial_compression,
        "bending_N_mm2": r.bending,
        "bending_contact_N_mm2": r.bending_contact,
        "bending_closed_N_mm2": r.bending_closed,
        "initial_tension_N": r.initial_tension,
        "tension_threshold_N": r.tension_threshold,
        "contact_moment_N_mm": r.moment,
        "contact_neutral_axis_y_mm": r.neutral_axis_y,
        "contact_fraction": r.contact_fraction,
        "ratios": {
            "axial_tension/spring_rate_EA": r.axial_tension / spring_ea,
            "axial_compression/coil_bound_EA": r.axial_compression
            / models["bimodular_annulus"]["axial_compression_N"],
            "bending/wahl": r.bending / wahl,
            "bending_contact/wahl": r.bending_contact / wahl,
            "bending/annulus_tension_EI": r.bending / annulus_ei,
            "bending_contact/annulus_tension_EI": r.bending_contact / annulus_ei,
            "bending_contact/bimodular_annulus_EI": r.bending_contact
            / models["bimodular_annulus"]["bending_N_mm2"],
        },
        "homogenised": models,
        "closed_forms": {
            "spring_rate_EA_N": cf.spring_rate_axial(wire, **geo),
            "helix_energy_EA_N": cf.helix_axial_energy(wire, **geo),
            "wahl_EI_N_mm2": cf.wahl_bending(wire, **geo),
            "helix_energy_EI_N_mm2": cf.helix_bending_energy(wire, **geo),
            "pivot_EI_N_mm2": cf.pivot_bending(wire, **geo),
        },
        "coil": {
            "outer_diameter_mm": coil.outer_diameter,
            "inner_diameter_mm": coil.inner_diameter,
            "wire_diameter_mm": coil.wire_diameter,
            "pitch_mm": coil.pitch,
            "mean_radius_mm": coil.mean_radius,
        },
        "model": "periodic one-turn cell, Timoshenko frame, frictionless penalty contact",
        "elements_per_turn": r.elements_per_turn,
        "n_elements": r.n_elements,
        "n_dofs": r.n_dofs,
        "seconds": r.seconds,
    }


def run(args: argparse.Namespace) -> int:
    with as_options({"elements_per_turn": "--elements-per-turn"}):  # checked before any work
        helix_mesh(radius=1.0, pitch=1.0, turns=1, elements_per_turn=args.elements_per_turn)
    d = design.resolve(args.design)
    out = prepare_out_dir(args.out)
    coils = {"coil": d.coil, "channel": d.channel}
    doc = {"design": d.name, "units": "N, mm; EA = F/strain [N], EI = M/curvature [N mm^2]"}
    for name, coil in coils.items():
        doc[name] = coil_report(coil, elements_per_turn=args.elements_per_turn)
    with Outputs(out) as o:  # both files or neither
        o.json("coil.json", doc)
        if not args.no_png:
            bent_coil_picture(o.path("coil.png"), {"outer coil": d.coil, "channel": d.channel})
    for name in coils:
        e = doc[name]
        ratio = e["ratios"]
        print(
            f"{name}: EA tension {e['axial_tension_N']:.4g} N ({ratio['axial_tension/spring_rate_EA']:.3f}x "
            f"spring), compression {e['axial_compression_N']:.4g} N; EI wire {e['bending_N_mm2']:.4g} "
            f"({ratio['bending/wahl']:.3f}x Wahl), with contact {e['bending_contact_N_mm2']:.4g} "
            f"({ratio['bending_contact/wahl']:.3f}x Wahl), closed {e['bending_closed_N_mm2']:.4g} N mm^2; "
            f"initial tension {e['initial_tension_N']:g} N"
        )
    print(f"wrote {out / 'coil.json'}" + ("" if args.no_png else f" and {out / 'coil.png'}"))
    return 0
