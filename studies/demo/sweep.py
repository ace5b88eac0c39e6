"""Demo section 6: a small sweep on the section model, the selection, the chosen design checked by the 3-D
FEM."""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

from softcath import models
from softcath.core.atomic import prepare_out_dir, write_text
from softcath.studies.demo.context import DEMO_MAX_STRAIN, DEMO_PRESSURES_MPA, DemoContext, SectionOutput
from softcath.studies.report import design_of, write_report
from softcath.studies.report.html_blocks import esc, fmt, note, table
from softcath.studies.selection import select, write_selection
from softcath.studies.sweep import fem_check_function, load_spec, run_sweep
from softcath.studies.sweep.results import read_results

__all__ = ["DEMO_SELECT_PRESSURE_MPA", "DEMO_SWEEP_TIERS", "demo_sweep_spec", "section_sweep"]

#: The selection's check pressure [MPa]: within the bench's range, where the section model's silicone
#: strain of the paper design (0.92 per MPa under the lumen load) stays below the linear models' trust bound.
DEMO_SELECT_PRESSURE_MPA = 0.5
#: The tiers the demo's sweep evaluates (the 3-D FEM checks only the chosen design afterwards).
DEMO_SWEEP_TIERS = ("paper", "section")


def demo_sweep_spec(options: dict | None = None) -> str:
    """The demo's sweep around the paper design: lumen offsets h × lumen widths a_int, 20 designs.

    Evaluated by the paper's formula and the section model (3-D-FEM-grade, a
    fraction of a second per design); the 3-D FEM checks only the chosen design
    afterwards. ``options`` (tier name -> options) become its ``[sweep.options.<tier>]`` tables.
    """
    tables = "".join(
        f"\n[sweep.options.{tier}]\n" + "".join(f"{k} = {json.dumps(v)}\n" for k, v in opts.items())
        for tier, opts in (options or {}).items()
        if tier in DEMO_SWEEP_TIERS  # the other tiers' options are the demo's other sections'
    )
    return f"""# The softcath demo sweep: lumen offsets h x lumen widths a_int,
# paper's formula and section model.
[sweep]
name = "demo"
base = "paper"
pressures_MPa = {sorted({*DEMO_PRESSURES_MPA, DEMO_SELECT_PRESSURE_MPA})}
loads = ["cap", "lumen"]
evaluators = {json.dumps(list(DEMO_SWEEP_TIERS))}

{tables}
[sweep.feasibility]
max_strain = {DEMO_MAX_STRAIN}

[parameters]
"tube.h" = {{ values = [-0.03, -0.015, 0.0, 0.015, 0.03] }}
"tube.a_int" = {{ values = [0.06, 0.08, 0.1, 0.12] }}
"""


def section_sweep(ctx: DemoContext) -> SectionOutput:

    check = fem_check_function() if ctx.fem else None

    sdir = prepare_out_dir(ctx.out_dir / "sweep", param="demo sweep folder")
    spec_path = write_text(sdir / "spec.toml", demo_sweep_spec(ctx.options))
    spec = load_spec(spec_path)
    summary = run_sweep(spec, sdir / "run", workers=ctx.workers, progress=True)
    df = read_results(sdir / "run")
    # On the section model under the real (lumen) load: a 30° bend at 0.5 MPa with the silicone's largest
    # principal strain below 0.5, beyond which no linear model is to be trusted (finite-strain section).
    at = f"at p={DEMO_SELECT_PRESSURE_MPA:g}"
    constraints = [f"max_strain <= {DEMO_MAX_STRAIN} {at}", f"bend_angle_deg >= 30 {at}"]
    objectives = ["maximise bend_per_MPa_deg", f"minimise elongation {at}"]
    sel = select(df, constraints=constraints, objectives=objectives, model="section", load="lumen")
    write_selection(sel, sdir / "run")
    ctx.shared["selection"] = sel
    check_html = _check_chosen(ctx, check, sdir / "run", sel, df)
    _, parts = write_report(sdir / "run", prefix="sweep/run/report/")
    body = (
        "<p>The sweep runs on the section model (3-D-FEM-grade curvature in a fraction of a second per "
        "design) "
        "next to the paper's formula; the design is chosen on the section model under the lumen load.</p>"
        f"<p>{summary.n_designs} designs ({summary.ok_designs} ok, {summary.failed_designs} failed) × "
        f"{len(spec.pressures)} pressures × 2 loads in {summary.seconds:.1f} s on "
        f"{esc(summary.backend)}; "
        f"spec <code>sweep/spec.toml</code>, results <code>sweep/run/results.csv</code>. Re-run it with "
        "<code>softcath sweep sweep/spec.toml --out sweep/run</code>; the sweep's own report: "
        "<a href='sweep/run/report/index.html'>sweep/run/report/index.html</a>.</p>"
    )
    for title, frag in parts:
        if title in ("Overview",):
            continue
        body += f"<h3>{esc(title)}</h3>{frag}"
    body += check_html
    return SectionOutput(body, (summary.results_csv,))


def _check_chosen(ctx: DemoContext, check, run_dir: Path, sel, df) -> str:
    """The 3-D FEM on the selection's best design at the check pressure, against the section model."""
    if not sel.ranked:
        return ""
    if check is None:
        why = "switched off with --no-fem" if not ctx.fem else "fem.check is not importable"
        return note(f"<b>Not run:</b> the 3-D FEM check of the chosen design ({esc(why)}).")

    did = sel.ranked[0]["design_id"]
    p = DEMO_SELECT_PRESSURE_MPA
    t0 = time.perf_counter()
    batches = models.responses(
        [design_of(run_dir, did)], [p], tier="fem", loads=models.LOADS, options=ctx.options.get("fem")
    )
    seconds = time.perf_counter() - t0
    out = []
    for load, b in batches.items():
        resp = b[0]  # a failed FEM raises its error here, as the check always did
        r = {"curvature_per_mm": float(resp.curvature_per_mm[0]), "max_strain": float(resp.max_strain[0])}
        s = df[(df.design_id == did) & (df.load == load) & np.isclose(df.pressure_MPa, p)]
        if s.empty:
            continue
        ks = float(s.curvature_section_per_mm.iloc[0])
        out.append(
            (
                load,
                ks,
                r["curvature_per_mm"],
                r["curvature_per_mm"] / ks - 1,
                float(s.max_strain_section.iloc[0]),
                r["max_strain"],
            )
        )
    ctx.shared["chosen_check"] = {"design_id": did, "rows": out}
    return (
        f"<h3>The chosen design checked by the 3-D FEM</h3><p>Design {did} at {fmt(p)} MPa ({seconds:.0f} "
        "s):</p>"
        + table(
            [
                "load",
                "κ section [1/mm]",
                "κ 3-D FEM [1/mm]",
                "FEM / section − 1",
                "max strain section (mid-span)",
                "max strain 3-D FEM (whole tip)",
            ],
            out,
            left=1,
        )
    )
