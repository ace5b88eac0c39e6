"""The section commands' shared options: the model's parameters as options, the coil choice."""

from __future__ import annotations

import argparse

from softcath.design.errors import DesignError
from softcath.fem.section_model.coil_models import model_options

__all__ = ["SECTION_OPTIONS", "coil_options"]

#: The section model's parameter names as this command's options.
SECTION_OPTIONS = {
    "silicone_poisson": "--poisson",
    "mesh_size": "--mesh-size",
    "segments": "--segments",
    "initial_tension (coil)": "--initial-tension (outer coil)",
    "initial_tension (channel)": "--initial-tension (channel)",
}


def coil_options(args: argparse.Namespace) -> tuple[dict, str | None, tuple[float, float] | None]:
    """(section_model coil keywords, bilinear placement or None, initial tension override)."""
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
