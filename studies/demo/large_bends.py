"""Demo section 3: large bends, the finite-strain FEM against the linear one, and the silicone strain."""

from __future__ import annotations

import numpy as np

from softcath.studies.demo.context import DEMO_MAX_STRAIN, DemoContext, SectionOutput, unavailable
from softcath.studies.report.html import figure, fmt, table

__all__ = ["DEMO_LARGE_BEND_PRESSURES_MPA", "section_large_bends"]

#: Lumen-load pressures of the finite-strain section [MPa]: far enough to see the bend outgrow the linear
#: prediction and the silicone strain approach the demo's limit (0.47 at 0.5 MPa), in ~15 s on the coarse
#: default mesh.
DEMO_LARGE_BEND_PRESSURES_MPA = (0.1, 0.2, 0.3, 0.4, 0.5)


def section_large_bends(ctx: DemoContext) -> SectionOutput:
    if not ctx.fem:
        return unavailable("the finite-strain FEM", "switched off with --no-fem", lead="Not run")
    try:
        from softcath.fem.nonlinear import bend_curve
        from softcath.fem.nonlinear.outputs import plot_curve, plot_deformed
    except ImportError as exc:
        return unavailable("the finite-strain FEM", f"fem.nonlinear is not importable: {exc}")
    d = ctx.design
    c = bend_curve(d, DEMO_LARGE_BEND_PRESSURES_MPA, load="lumen")
    f1, f2 = ctx.out_dir / "large_bends_curve.png", ctx.out_dir / "large_bends_tip.png"
    plot_curve(c, f1)
    plot_deformed(c, f2)
    rows = [
        (p, np.degrees(a), np.degrees(lin), np.degrees(ana), e, int(it))
        for p, a, lin, ana, e, it in zip(
            c.pressure, c.bend_angle, c.linear_bend_angle, c.analytic_bend_angle, c.max_strain,
            c.newton_iterations, strict=True,
        )
    ]  # fmt: skip
    dep = c.departure(0.05)["linear_fem"]
    over = [float(p) for p, e in zip(c.pressure, c.max_strain, strict=True) if e > DEMO_MAX_STRAIN]
    ratio = float(c.bend_angle[-1] / c.linear_bend_angle[-1])
    text = [
        f"Finite-strain FEM of the same tip (follower pressure on the deformed lumen, hyperelastic silicone, "
        f"{c.ndofs} DOFs on the coarse default mesh): at {fmt(c.pressure[-1])} MPa the tip bends "
        f"{fmt(np.degrees(c.bend_angle[-1]), 3)}°, {fmt(ratio, 3)}× what the linear FEM predicts."
    ]
    if dep is not None:
        text.append(
            f"The linear FEM departs from it by 5 % at {fmt(np.degrees(dep), 2)}° of bend: beyond that, "
            "small-rotation answers (linear FEM, Euler–Bernoulli) underestimate the bend."
        )
    if over:
        text.append(
            f"The silicone's largest principal strain passes {fmt(DEMO_MAX_STRAIN)} at {fmt(over[0])} MPa "
            f"(it is {fmt(c.max_strain[-1], 2)} at {fmt(c.pressure[-1])} MPa): for this design the strain "
            "limit, not the bend, is what to design against."
        )
    html = (
        "<p>"
        + " ".join(text)
        + "</p>"
        + figure(
            f1.name, "Bend angle vs lumen pressure: finite-strain FEM, linear FEM, analytic (lumen load)."
        )
        + table(
            [
                "p [MPa]",
                "finite-strain FEM [deg]",
                "linear FEM [deg]",
                "analytic, lumen load [deg]",
                "max silicone strain",
                "Newton iterations",
            ],
            rows,
        )  # fmt: skip
        + figure(
            f2.name,
            f"The tip at {fmt(c.pressure[-1])} MPa (cut along the bending plane, side view) over its undeformed "
            "ghost, coloured by the largest principal stretch strain λ_max − 1.",
        )
    )
    ctx.shared["large_bends"] = {
        "pressure": float(c.pressure[-1]), "angle_deg": float(np.degrees(c.bend_angle[-1])), "ratio": ratio,
        "strain_over_at": over[0] if over else None,
    }  # fmt: skip
    return SectionOutput(html, (f1, f2))
