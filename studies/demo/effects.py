"""Demo section 5: the missing effect the bench data point to (the discrepancy workflow)."""

from __future__ import annotations

from pathlib import Path

from softcath.studies.demo.context import DemoContext, SectionOutput
from softcath.studies.discrepancy import run_workflow, write_report
from softcath.studies.report.html_blocks import Markup, esc, fmt, table

__all__ = ["section_effects"]


def section_effects(ctx: DemoContext) -> SectionOutput:
    eff_dir = ctx.out_dir / "effects"
    eff_dir.mkdir(exist_ok=True)
    result = run_workflow(ctx.data_csv, design=ctx.design)
    path = Path(write_report(result, eff_dir))
    rel = path.relative_to(ctx.out_dir).as_posix() if path.is_relative_to(ctx.out_dir) else str(path)
    ctx.shared["effects"] = result
    named = ", ".join(result.named) if result.named else "none (no candidate beat the model by the margin)"
    html = (
        "<p>After calibration, what does the model still miss? The workflow fits each named candidate effect "
        "(hysteresis, lag, delay, dead zone, creep, offset, stiffening, ...) on training segments of the "
        "bench data, scores it on held-out ones, and names it only if it beats the current model by a "
        f"margin of {fmt(result.margin * 100, 2)} %.</p>"
        + table(
            ["named effects", "held-out NRMSE before", "after", "noise floor", "excess error removed"],
            [
                (
                    Markup(esc(named)),
                    result.nrmse_before,
                    result.nrmse_after,
                    result.noise_floor_nrmse,
                    result.excess_removed,
                )
            ],
            left=1,
        )
        + "".join(f"<p>{esc(n)}</p>" for n in result.notes)
        + f"<p>Full report: <a href='{esc(rel)}'>{esc(rel)}</a>.</p>"
    )
    return SectionOutput(html, (path,))
