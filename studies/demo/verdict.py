"""Demo section 7: which design to build, from what the earlier sections left in ``ctx.shared``."""

from __future__ import annotations

import numpy as np

from softcath.models import TIERS
from softcath.studies.demo.context import DEMO_MAX_STRAIN, DemoContext, SectionOutput, unavailable
from softcath.studies.report.html_blocks import esc, fmt

__all__ = ["section_verdict"]


def section_verdict(ctx: DemoContext) -> SectionOutput:
    sel = ctx.shared.get("selection")
    lines = []
    gains = ctx.shared.get("analytic_gains")
    if gains:
        lines.append(
            f"The paper's model gives {fmt(np.degrees(gains['cap'][0] * ctx.design.tip.bending_length))} "
            "deg/MPa of bend for the nominal squeezed shape."
        )
    tiers = ctx.shared.get("tiers")
    if tiers:
        lines.append(
            "Section model (2-D, FEM-grade): κ/p = "
            + ", ".join(
                f"{fmt(k, 3)} ({ld} load, {fmt(k / tiers['formula'], 3)}× the formula)"
                for ld, k in tiers["section"].items()
            )
            + " 1/(mm MPa)."
        )
    fem_ratios = ctx.shared.get("fem")
    if fem_ratios:
        lines.append(
            "FEM curvature / the paper's formula: "
            + ", ".join(f"{load} load {fmt(r, 3)}" for load, r in fem_ratios.items())
            + "."
        )
    big = ctx.shared.get("large_bends")
    if big:
        lines.append(
            f"Finite strain: {fmt(big['angle_deg'], 3)}° at {fmt(big['pressure'])} MPa, "
            f"{fmt(big['ratio'], 3)}× the linear FEM"
            + (
                f"; silicone strain above {fmt(DEMO_MAX_STRAIN)} from {fmt(big['strain_over_at'])} MPa"
                if big["strain_over_at"] is not None
                else ""
            )
            + "."
        )
    cal = ctx.shared.get("calibration")
    if cal is not None:
        lines.append(f"Calibration to the bench data cuts the curvature error {fmt(cal.ratio)}-fold.")
    eff = ctx.shared.get("effects")
    if eff is not None:
        lines.append(
            "Missing effect named in the bench data: "
            + (", ".join(esc(e) for e in eff.named) if eff.named else "none beyond the noise")
            + f" (held-out NRMSE {fmt(eff.nrmse_before)} → {fmt(eff.nrmse_after)})."
        )
    if sel is not None and sel.ranked:
        best = sel.ranked[0]
        params = ", ".join(f"{esc(k)} = {fmt(v)}" for k, v in best["parameters"].items())
        lines.append(
            f"<b>Build design {best['design_id']}</b> ({params}): best of {sel.n_feasible} designs that meet "
            f"{', '.join(esc(c) for c in sel.constraints)}, ranked by "
            f"{', '.join(esc(o) for o in sel.objectives)} "
            f"({TIERS[sel.model].label if sel.model in TIERS else esc(sel.model)}, {esc(sel.load)} load)."
        )
        chk = ctx.shared.get("chosen_check")
        if chk and chk["rows"]:
            lines.append(
                "The 3-D FEM confirms it: FEM / section model − 1 = "
                + ", ".join(f"{fmt(100 * r[3], 2)} % ({r[0]})" for r in chk["rows"])
                + "."
            )
    elif sel is not None:
        lines.append("No design of the sweep meets the constraints: relax them or widen the sweep.")
    if not lines:
        return unavailable("the verdict", "no earlier section produced results")
    return SectionOutput("<ul>" + "".join(f"<li>{x}</li>" for x in lines) + "</ul>")
