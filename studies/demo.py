"""``softcath demo``: the paper's design end to end, in one ``DIR/index.html`` that tells the story.

The demo is a list of independent sections (:data:`SECTIONS`). Each is a
function ``fn(ctx) -> SectionOutput`` that writes its files under
``ctx.out_dir`` and returns an HTML fragment. A section whose dependency is
not installed returns a clear "not available" note; a section that raises is
reported as failed with the reason, and the others still run. New
capabilities join the demo by adding a section.

Story: 1. the paper's model (geometry as assembled, composite beam, cap vs
lumen load); 2. three tiers: the paper's formula, the 2-D section model and
the 3-D FEM under both loads, and κ/p against the silicone's ν; 3. large
bends: the finite-strain FEM against the linear one, and
the silicone strain; 4. what the measured data add (eq. 8 calibration); 5.
which missing effect the data point to; 6. a small sweep on the section model,
the chosen design checked by the 3-D FEM; 7. the design to build.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from softcath.studies.demo_tiers import section_tiers
from softcath.studies.report.html import Markup, esc, figure, fmt, note, page, table

__all__ = [
    "DemoContext", "SectionOutput", "SECTIONS", "run_demo", "default_data", "DEMO_PRESSURES_MPA", "demo_sweep_spec",
]  # fmt: skip

log = logging.getLogger(__name__)

DEMO_PRESSURES_MPA = (0.5, 1.0, 2.0)  # the bundled bench data span 0–2 MPa
DEMO_MAX_STRAIN = 0.5


@dataclass
class DemoContext:
    """What the sections share: output directory, the design, and results earlier sections leave."""

    out_dir: Path
    design: object
    data_csv: Path
    workers: int = 2
    fem: bool = True
    shared: dict = field(default_factory=dict)


@dataclass(frozen=True)
class SectionOutput:
    """One section's HTML fragment and files; ``status`` is ``ok``, ``unavailable`` or ``failed``."""

    html: str
    files: tuple[Path, ...] = ()
    status: str = "ok"


def _unavailable(what: str, why: str, *, lead: str = "Not available in this build") -> SectionOutput:
    return SectionOutput(note(f"<b>{esc(lead)}:</b> {esc(what)} ({esc(why)})."), status="unavailable")


# ---------------------------------------------------------------- 1. the paper's model
def section_model(ctx: DemoContext) -> SectionOutput:
    from softcath import analytic
    from softcath.studies.plots import analytic_plot, section_plot

    d = ctx.design
    cs = analytic.composite_section(d)
    p = np.linspace(0.0, max(DEMO_PRESSURES_MPA), 41)
    cap, lumen = analytic.response(d, p, "cap"), analytic.response(d, p, "lumen")
    f1 = section_plot(ctx.out_dir / "model_section.png", d)
    f2 = analytic_plot(ctx.out_dir / "model_cap.png", cap, title="paper's model (cap load)")
    kc, ec = analytic.gains(d, "cap")
    kl, el = analytic.gains(d, "lumen")
    parts = [(k, v["EA"], v["EI"], v["y"]) for k, v in cs.parts.items()]
    html = (
        "<p>The paper models the tip as a composite Euler–Bernoulli beam: the pressure p on the sealed "
        "tube's end cap pulls with force p·A_p at the lumen centre y_p, off the composite neutral axis ȳ, "
        "so the tip stretches (ε = p A_p/ΣEA) and bends (κ = p A_p (y_p − ȳ)/ΣEI) into a circular arc.</p>"
        f"<p><b>Geometry as assembled.</b> {esc(d.fit_report()).replace(chr(10), '<br>')}</p>"
        + figure(
            f2.name if False else f1.name, "As-assembled cross-section, neutral axis and pressure centre."
        )
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
        )  # fmt: skip
        + f"<p>A 90° bend needs {fmt(float(analytic.pressure_for_bend_angle(d, np.pi / 2)))} MPa under the "
        f"cap load and {fmt(float(analytic.pressure_for_bend_angle(d, np.pi / 2, load='lumen')))} MPa if the "
        "lumen-wall term acts unconfined.</p>"
        + "<p>The paper's formulas are the response to the end-cap force alone. Pressure also pushes on "
        "the lumen wall; for a bonded section of one Poisson ratio ν that multiplies both by (1 − 2ν) — "
        f"{fmt(1 - 2 * d.tube.material.poisson_ratio)} for ν = {fmt(d.tube.material.poisson_ratio)}: an "
        "unconfined silicone tube would barely bend. The coil confines the tube; the section model and the 3-D FEM "
        "(next section) say how much of the formula survives.</p>"
    )
    ctx.shared["analytic_gains"] = {"cap": (kc, ec), "lumen": (kl, el)}
    return SectionOutput(html, (f1, f2))


# ---------------------------------------------------------------- 2. three tiers: formula, section model, FEM
# (studies.demo_tiers.section_tiers)


# ---------------------------------------------------------------- 3. large bends (finite strain)
#: Lumen-load pressures of the finite-strain section [MPa]: far enough to see the bend outgrow the linear
#: prediction and the silicone strain approach the demo's limit (0.47 at 0.5 MPa), in ~15 s on the coarse
#: default mesh.
DEMO_LARGE_BEND_PRESSURES_MPA = (0.1, 0.2, 0.3, 0.4, 0.5)


def section_large_bends(ctx: DemoContext) -> SectionOutput:
    if not ctx.fem:
        return _unavailable("the finite-strain FEM", "switched off with --no-fem", lead="Not run")
    try:
        from softcath.fem.nonlinear import bend_curve
        from softcath.fem.nonlinear.outputs import plot_curve, plot_deformed
    except ImportError as exc:
        return _unavailable("the finite-strain FEM", f"fem.nonlinear is not importable: {exc}")
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
        + figure(f2.name, f"The tip at {fmt(c.pressure[-1])} MPa (side view) over its undeformed outline.")
    )
    ctx.shared["large_bends"] = {
        "pressure": float(c.pressure[-1]), "angle_deg": float(np.degrees(c.bend_angle[-1])), "ratio": ratio,
        "strain_over_at": over[0] if over else None,
    }  # fmt: skip
    return SectionOutput(html, (f1, f2))


# ---------------------------------------------------------------- 4. calibration (eq. 8)
def section_calibration(ctx: DemoContext) -> SectionOutput:
    try:
        from softcath.analytic.calibration import calibrate
        from softcath.design.measurement import read_measurement_csv
    except ImportError as exc:
        return _unavailable("the eq. 8 calibration", str(exc))
    if not ctx.data_csv.is_file():
        return _unavailable("the eq. 8 calibration", f"bundled data {ctx.data_csv} missing")
    from softcath import analytic, design
    from softcath.studies.plots import calibration_plot

    d = ctx.design
    m = read_measurement_csv(ctx.data_csv)
    res = calibrate(m, d, load="cap")
    from softcath.studies.atomic import Outputs, prepare_out_dir

    cal_dir = prepare_out_dir(ctx.out_dir / "calibration", param="demo calibration folder")
    with Outputs(cal_dir) as o:
        o.json("calibration.json", res.to_json())
        o.text("calibrated_design.toml", design.dumps(res.design, header="calibrated by softcath demo"))
    fig = calibration_plot(
        ctx.out_dir / "calibration.png", m,
        nominal=analytic.response(d, m.pressure_MPa, "cap"),
        optimized=analytic.response(res.design, m.pressure_MPa, "cap"),
        title=f"eq. 8 calibration: NRMSE ratio nominal/optimised = {res.ratio:.3g}",
    )  # fmt: skip
    ctx.shared["calibration"] = res
    x0, x1 = res.x_nominal, res.x_opt
    html = (
        f"<p>Bundled bench data: <code>{esc(ctx.data_csv.name)}</code>, {len(m)} samples, "
        f"pressure {fmt(float(np.min(m.pressure_MPa)))}–{fmt(float(np.max(m.pressure_MPa)))} MPa. "
        "The paper fits the squeezed tube's shape x = [a, a_int, b_int, h] so the model's curvature and "
        "elongation match the measurement (eq. 8; CasADi/IPOPT multistart).</p>"
        + table(
            ["", "a [mm]", "a_int [mm]", "b_int [mm]", "h [mm]"],
            [
                ("nominal", x0["a"], x0["a_int"], x0["b_int"], x0["h"]),
                ("calibrated", x1["a"], x1["a_int"], x1["b_int"], x1["h"]),
            ],
            left=1,
        )  # fmt: skip
        + f"<p>Curvature NRMSE {fmt(res.nrmse_nominal)} → {fmt(res.nrmse_optimized)} (ratio {fmt(res.ratio)}; "
        f"the paper reports 20.14). {res.starts_at_optimum}/{res.starts} starts reached the optimum; "
        f"identifiable: {'yes' if res.identifiable else 'no'}; reachable: {'yes' if res.reachable else 'no'}.</p>"
        f"<p>{esc(res.message)}</p>"
        + figure(fig.name, "Measured vs nominal vs calibrated curvature.")
        + "<p>What the data add: a shape the model cannot know from the catalogue (the tube is squeezed), "
        "and — through what the calibrated model still misses — a pointer to the next effect.</p>"
    )
    return SectionOutput(html, (fig, cal_dir / "calibration.json"))


# ---------------------------------------------------------------- 5. missing-effect workflow
def section_effects(ctx: DemoContext) -> SectionOutput:
    try:
        from softcath.studies.discrepancy import run_workflow, write_report
    except ImportError as exc:
        return _unavailable("the missing-effect workflow", str(exc))
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
        )  # fmt: skip
        + "".join(f"<p>{esc(n)}</p>" for n in result.notes)
        + f"<p>Full report: <a href='{esc(rel)}'>{esc(rel)}</a>.</p>"
    )
    return SectionOutput(html, (path,))


# ---------------------------------------------------------------- 6. small sweep and selection
#: The selection's check pressure [MPa]: within the bench's range, where the section model's silicone strain of
#: the paper design (0.92 per MPa under the lumen load) stays below the linear models' trust bound.
DEMO_SELECT_PRESSURE_MPA = 0.5


def demo_sweep_spec(*, fem: bool = False) -> str:
    """The demo's sweep around the paper design: lumen offsets h × lumen widths a_int, 20 designs.

    Evaluated by the paper's formula and the section model (3-D-FEM-grade, a
    fraction of a second per design); the 3-D FEM checks only the chosen design
    afterwards (``fem`` is kept for callers and does not change the spec).
    """
    return f"""# The softcath demo sweep: lumen offsets h x lumen widths a_int, paper's formula and section model.
[sweep]
name = "demo"
base = "paper"
pressures_MPa = {sorted({*DEMO_PRESSURES_MPA, DEMO_SELECT_PRESSURE_MPA})}
loads = ["cap", "lumen"]
evaluators = ["analytic", "section"]

[sweep.feasibility]
max_strain = {DEMO_MAX_STRAIN}

[parameters]
"tube.h" = {{ values = [-0.03, -0.015, 0.0, 0.015, 0.03] }}
"tube.a_int" = {{ values = [0.06, 0.08, 0.1, 0.12] }}
"""


def section_sweep(ctx: DemoContext) -> SectionOutput:
    from softcath.studies.report import write_report
    from softcath.studies.results import read_results
    from softcath.studies.selection import select, write_selection
    from softcath.studies.sweep import fem_check_function, load_spec, run_sweep

    check = fem_check_function() if ctx.fem else None
    from softcath.studies.atomic import prepare_out_dir, write_text

    sdir = prepare_out_dir(ctx.out_dir / "sweep", param="demo sweep folder")
    spec_path = write_text(sdir / "spec.toml", demo_sweep_spec())
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
        "<p>The sweep runs on the section model (3-D-FEM-grade curvature in a fraction of a second per design) "
        "next to the paper's formula; the design is chosen on the section model under the lumen load.</p>"
        f"<p>{summary.n_designs} designs ({summary.ok_designs} ok, {summary.failed_designs} failed) × "
        f"{len(spec.pressures_MPa)} pressures × 2 loads in {summary.seconds:.1f} s on {esc(summary.backend)}; "
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
    from softcath.studies.report import design_of
    from softcath.studies.sweep.evaluators import _fem_rows

    did = sel.ranked[0]["design_id"]
    p = DEMO_SELECT_PRESSURE_MPA
    t0 = time.perf_counter()
    rows = _fem_rows(check, design_of(run_dir, did), (p,), ("cap", "lumen"), None)
    seconds = time.perf_counter() - t0
    out = []
    for load in ("cap", "lumen"):
        r = rows.get((load, round(p, 12)))
        s = df[(df.design_id == did) & (df.load == load) & np.isclose(df.pressure_MPa, p)]
        if r is None or s.empty:
            continue
        ks = float(s.curvature_section_per_mm.iloc[0])
        out.append((load, ks, r["curvature_per_mm"], r["curvature_per_mm"] / ks - 1,
                    float(s.max_strain_section.iloc[0]), r["max_strain"]))  # fmt: skip
    ctx.shared["chosen_check"] = {"design_id": did, "rows": out}
    return (
        f"<h3>The chosen design checked by the 3-D FEM</h3><p>Design {did} at {fmt(p)} MPa ({seconds:.0f} s):</p>"
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
        )  # fmt: skip
    )


def section_verdict(ctx: DemoContext) -> SectionOutput:
    sel = ctx.shared.get("selection")
    lines = []
    gains = ctx.shared.get("analytic_gains")
    if gains:
        lines.append(
            f"The paper's model gives {fmt(np.degrees(gains['cap'][0] * ctx.design.tip.bending_length))} deg/MPa "
            "of bend for the nominal squeezed shape."
        )
    tiers = ctx.shared.get("tiers")
    if tiers:
        lines.append(
            "Section model (2-D, FEM-grade): κ/p = "
            + ", ".join(f"{fmt(k, 3)} ({ld} load, {fmt(k / tiers['formula'], 3)}× the formula)"
                        for ld, k in tiers["section"].items())
            + " 1/(mm MPa)."
        )  # fmt: skip
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
            f"Finite strain: {fmt(big['angle_deg'], 3)}° at {fmt(big['pressure'])} MPa, {fmt(big['ratio'], 3)}× the "
            "linear FEM"
            + (f"; silicone strain above {fmt(DEMO_MAX_STRAIN)} from {fmt(big['strain_over_at'])} MPa"
               if big["strain_over_at"] is not None else "")
            + "."
        )  # fmt: skip
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
            f"{', '.join(esc(c) for c in sel.constraints)}, ranked by {', '.join(esc(o) for o in sel.objectives)} "
            f"({'the section model' if sel.model == 'section' else esc(sel.model)}, {esc(sel.load)} load)."
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
        return _unavailable("the verdict", "no earlier section produced results")
    return SectionOutput("<ul>" + "".join(f"<li>{x}</li>" for x in lines) + "</ul>")


SECTIONS: list[tuple[str, str, Callable[[DemoContext], SectionOutput]]] = [
    ("model", "1. The paper's model", section_model),
    ("fem", "2. Three tiers: the paper's formula, the section model, the 3-D FEM", section_tiers),
    ("large_bends", "3. Large bends: finite-strain FEM", section_large_bends),
    ("calibration", "4. What the measured data add: calibration (eq. 8)", section_calibration),
    ("effects", "5. The missing effect", section_effects),
    ("sweep", "6. A small sweep", section_sweep),
    ("verdict", "7. Which design to build", section_verdict),
]


@dataclass(frozen=True)
class DemoResult:
    index_html: Path
    sections: list[dict]
    seconds: float


def default_data() -> Path:
    """The bundled bench data: ``bench_hysteresis.csv`` (virtual bench: squeezed lumen and a hidden
    hysteresis, two frequencies), else ``paper_sine.csv``."""
    data = Path(__file__).parent / "data"
    for name in ("bench_hysteresis.csv", "paper_sine.csv"):
        if (data / name).is_file():
            return data / name
    return data / "bench_hysteresis.csv"


def run_demo(out_dir: str | Path, *, design_ref: str = "paper", data_csv: str | Path | None = None,
             workers: int = 2, only: tuple[str, ...] | None = None, progress: bool = True,
             fem: bool = True) -> DemoResult:  # fmt: skip
    """Run the demo sections into ``out_dir`` and write ``out_dir/index.html``.

    Parameters
    ----------
    out_dir
        Output directory (created).
    design_ref
        Preset name or design TOML path (default: the paper's prototype).
    data_csv
        Measurement CSV (default: :func:`default_data`).
    workers
        Processes for the sweep.
    only
        Run only these section keys (default: all).
    progress
        Show a progress bar over the sections.
    fem
        Run the FEM (section 2 and the sweep's FEM evaluator) when ``fem.check`` is installed.
    """
    from tqdm import tqdm

    from softcath import design

    t0 = time.perf_counter()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    data = Path(data_csv) if data_csv else default_data()
    ctx = DemoContext(out_dir=out, design=design.resolve(design_ref), data_csv=data, workers=workers, fem=fem)
    chosen = [s for s in SECTIONS if only is None or s[0] in only]
    records, body, toc = [], "", ""
    for key, title, fn in tqdm(chosen, desc="demo", unit="section", disable=not progress):
        t = time.perf_counter()
        try:
            res = fn(ctx)
        except Exception as exc:  # one section's failure must not lose the others
            log.error("demo section %s failed: %s: %s", key, type(exc).__name__, exc, exc_info=True)
            res = SectionOutput(note(f"<b>This section failed:</b> {esc(type(exc).__name__)}: {esc(exc)}"),
                                status="failed")  # fmt: skip
        secs = time.perf_counter() - t
        records.append({"key": key, "title": title, "status": res.status, "seconds": round(secs, 2)})
        badge = {
            "ok": "",
            "unavailable": " <small>(not available)</small>",
            "failed": " <small class='bad'>(failed)</small>",
        }[res.status]
        body += f"<h2 id='{key}'>{esc(title)}{badge}</h2>{res.html}"
        toc += f"<li><a href='#{key}'>{esc(title)}</a>{badge}</li>"
    intro = (
        f"<p>The hydraulically actuated soft micro-catheter tip of the paper, design "
        f"<code>{esc(ctx.design.name)}</code>, from the paper's model to the design to build. "
        f"Generated by <code>softcath demo</code> in {time.perf_counter() - t0:.0f} s. Units: mm, N, MPa, s.</p>"
        f"<ol style='list-style:none;padding-left:0'>{toc}</ol>"
    )
    from softcath.studies.atomic import Outputs

    index = out / "index.html"
    with Outputs(out) as o:
        o.text("index.html", page("softcath demo", intro + body))
        o.json("demo.json", {"sections": records}, indent=1)
    return DemoResult(index, records, time.perf_counter() - t0)
