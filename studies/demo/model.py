"""Demo section 1: the paper's model (geometry as assembled, composite beam, cap vs lumen load)."""

from __future__ import annotations

import numpy as np

from softcath import analytic
from softcath.studies.demo.context import DEMO_PRESSURES_MPA, DemoContext, SectionOutput
from softcath.studies.demo.paper import paper_gains, paper_pressure_for_bend_angle, paper_response
from softcath.studies.plots import analytic_plot, section_plot
from softcath.studies.report.html_blocks import esc, figure, fmt, table

__all__ = ["section_model"]


def section_model(ctx: DemoContext) -> SectionOutput:

    d = ctx.design
    cs = analytic.composite_section(d)
    p = np.linspace(0.0, max(DEMO_PRESSURES_MPA), 41)
    opts = ctx.options.get("paper")
    cap, lumen = paper_response(d, p, "cap", opts), paper_response(d, p, "lumen", opts)
    f1 = section_plot(ctx.out_dir / "model_section.png", d)
    f2 = analytic_plot(ctx.out_dir / "model_cap.png", cap, title="paper's model (cap load)")
    kc, ec = paper_gains(d, "cap", opts)
    kl, el = paper_gains(d, "lumen", opts)
    parts = [(k, v["EA"], v["EI"], v["y"]) for k, v in cs.parts.items()]
    html = (
        "<p>The paper models the tip as a composite Euler–Bernoulli beam: the pressure p on the sealed "
        "tube's end cap pulls with force p·A_p at the lumen centre y_p, off the composite neutral axis ȳ, "
        "so the tip stretches (ε = p A_p/ΣEA) and bends (κ = p A_p (y_p − ȳ)/ΣEI) into a circular arc.</p>"
        f"<p><b>Geometry as assembled.</b> {esc(d.fit_report()).replace(chr(10), '<br>')}</p>"
        + figure(f1.name, "As-assembled cross-section, neutral axis and pressure centre.")
        + table(["part", "EA [N]", "EI about ȳ [N mm²]", "centroid y [mm]"], parts, left=1)
        + f"<p>Composite: ΣEA = {fmt(cs.EA)} N, ΣEI = {fmt(cs.EI)} N mm², ȳ = {fmt(cs.neutral_axis_y)} mm, "
        f"A_p = {fmt(cs.pressure_area)} mm², y_p = {fmt(cs.pressure_centre_y)} mm.</p>"
        + figure(
            f2.name, "Curvature, elongation, bend angle and tip path (eq. 9) under the paper's cap load."
        )
        + table(
            ["load", "κ/p [1/(mm MPa)]", "ε/p [1/MPa]", f"bend at {fmt(p[-1])} MPa [deg]"],
            [
                ("cap (paper)", kc, ec, np.degrees(cap.bend_angle[-1])),
                ("lumen wall too", kl, el, np.degrees(lumen.bend_angle[-1])),
            ],
            left=1,
        )
        + f"<p>A 90° bend needs {fmt(float(paper_pressure_for_bend_angle(d, np.pi / 2, options=opts)))} MPa "
        "under the cap load and "
        f"{fmt(float(paper_pressure_for_bend_angle(d, np.pi / 2, load='lumen', options=opts)))} MPa if the "
        "lumen-wall term acts unconfined.</p>"
        + "<p>The paper's formulas are the response to the end-cap force alone. Pressure also pushes on "
        "the lumen wall; for a bonded section of one Poisson ratio ν that multiplies both by (1 − 2ν) — "
        f"{fmt(1 - 2 * d.tube.material.poisson_ratio)} for ν = {fmt(d.tube.material.poisson_ratio)}: an "
        "unconfined silicone tube would barely bend. The coil confines the tube; the section model and the "
        "3-D FEM (next section) say how much of the formula survives.</p>"
    )
    ctx.shared["analytic_gains"] = {"cap": (kc, ec), "lumen": (kl, el)}
    return SectionOutput(html, (f1, f2))
