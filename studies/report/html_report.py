"""The sweep's HTML report: ``DIR/report/index.html``, a static page with its PNGs beside it (opens offline).

Sections: overview, parity (analytic vs FEM curvature, both loads), the three
tiers side by side (the paper's formula, the section model, the 3-D FEM), relative
error against each swept parameter, heat maps for 2-D grids, sensitivity
(standardised regression; RBD-FAST for Latin-hypercube samples), renders of
the best- and worst-agreeing designs, the failed designs with reasons, and
the selection (``DIR/selection.json``) when present.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np

from softcath.core.atomic import staged_dir
from softcath.design.errors import DataError
from softcath.design.reference import with_unit
from softcath.studies.report import figures
from softcath.studies.report.explore import write_explore
from softcath.studies.report.html_blocks import Markup, esc, figure, fmt, note, page, table
from softcath.studies.report.sweep_folder import _manifest, design_of
from softcath.studies.sweep.results import read_results
from softcath.studies.tiers import TIERS

__all__ = ["write_report", "sweep_sections", "design_of"]

log = logging.getLogger(__name__)


def _selection_html(sweep_dir: Path, fig_dir: Path | None = None, prefix: str = "") -> str:
    path = sweep_dir / "selection.json"
    if not path.is_file():
        return note(
            "No selection yet: run <code>softcath select DIR --constraint ... --objective ...</code> "
            "and then this report again."
        )
    try:
        sel = json.loads(path.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise DataError(f"{path}: unreadable ({exc}); run `softcath select` again to rewrite it") from None
    try:
        return _selection_body(sel, fig_dir, prefix)
    except (KeyError, TypeError, AttributeError, IndexError, ValueError) as exc:
        raise DataError(
            f"{path}: not a selection ({type(exc).__name__}: {exc}); run `softcath select` again to rewrite "
            "it"
        ) from None


def _selection_body(sel: dict, fig_dir: Path | None, prefix: str) -> str:
    items = "".join(f"<li><code>{esc(c)}</code></li>" for c in sel["constraints"]) or "<li>none</li>"
    objs = "".join(f"<li><code>{esc(o)}</code></li>" for o in sel["objectives"])
    rej = ", ".join(f"{esc(k)}: {v}" for k, v in sel["rejected"].items() if v) or "none"
    out = (
        "<p>"
        + (
            f"Model <b>{esc(TIERS[sel['model']].label if sel['model'] in TIERS else 'the table as given')}"
            "</b>, l"
            if "model" in sel
            else "L"
        )
        + f"oad case <b>{esc(sel['load'])}</b>."
        + (f" Note: {esc(sel['note'])}." if sel.get("note") else "")
        + f" Constraints:</p><ul>{items}</ul><p>Objectives:</p><ul>{objs}</ul>"
        f"<p><b>{sel['n_feasible']}</b> of {sel['n_designs']} designs meet the constraints (removed: {rej}). "
        + (
            f"Re-checked with {TIERS['section-nonlinear'].label}: {sel['recheck']['n_passing']} of "
            f"{sel['recheck']['n_rechecked']} still pass; Pareto front on its values: "
            f"{len(sel['pareto_front'])} of them.</p>"
            if sel.get("recheck")
            else f"Pareto front: {len(sel['pareto_front'])} designs.</p>"
        )
    )
    rb = sel.get("robust")
    if rb:
        out += (
            f"<p><b>Robust</b> ({esc(rb['model'])} model): {rb['n_passing']} of {rb['n_evaluated']} ranked "
            "designs "
            f"meet every constraint with probability ≥ {fmt(rb['P'])} over {rb['samples']} samples of "
            + ", ".join(f"<code>{esc(r['path'])}</code>" for r in rb["ranges"])
            + "; the ranking below is on the objectives' p50.</p>"
        )
    if fig_dir is not None:
        ppath = figures.pareto_plot(sel, Path(fig_dir) / "pareto.png")
        if ppath:
            caption = (
                f"The {sel['recheck']['n_passing']} re-checked designs that still pass, in the plane of the "
                f"first two objectives, on {TIERS['section-nonlinear'].label}'s values."
                if sel.get("recheck")
                else "Feasible designs in the plane of the first two objectives."
            )
            out += figure(prefix + ppath.name, caption)
    if sel["ranked"]:
        params = list(sel["ranked"][0]["parameters"])
        header = ["rank", "design", "Pareto", *map(with_unit, sel["objectives"]), *map(with_unit, params)]
        rows = [
            [r["rank"], r["design_id"], r["pareto"], *r["objectives"].values(), *r["parameters"].values()]
            for r in sel["ranked"][:15]
        ]
        out += table(header, rows)
        best = sel["ranked"][0]
        out += (
            f"<p><b>Build design {best['design_id']}</b>"
            f" ({', '.join(f'{esc(k)} = {fmt(v)}' for k, v in best['parameters'].items())})"
            + (
                f": its design file is <code>{esc(best['design_file'])}</code> in the selection's folder, "
                "ready for <code>softcath design validate</code>, <code>section</code> and <code>fem</code>"
                if best.get("design_file")
                else ""
            )
            + ".</p>"
        )
        files = [r for r in sel["ranked"][1:] if r.get("design_file")]
        if files:
            out += (
                "<p>Design files of the next ranked designs: "
                + ", ".join(f"#{r['rank']} <code>{esc(r['design_file'])}</code>" for r in files)
                + ".</p>"
            )
    return out


def sweep_sections(sweep_dir: str | Path, fig_dir: str | Path, *, prefix: str = "") -> list[tuple[str, str]]:
    """The report's sections as ``(title, html)``; figures are written into ``fig_dir``.

    Image links are ``prefix + file name`` so the same sections can be placed
    in another page (the demo) whose HTML sits elsewhere.
    """

    sweep_dir, fig_dir = Path(sweep_dir), Path(fig_dir)
    fig_dir.mkdir(parents=True, exist_ok=True)
    manifest = _manifest(sweep_dir)
    spec = manifest["spec"]
    df = read_results(sweep_dir)
    params = [p["path"] for p in spec["parameters"]]
    factorial = [p["path"] for p in spec["parameters"] if p["kind"] != "lhs"]
    lhs = any(p["kind"] == "lhs" for p in spec["parameters"])
    fem = figures.has_fem(df)
    sections: list[tuple[str, str]] = [("Overview", _overview_html(spec, df.drop_duplicates("design_id")))]

    ppath, body = _parity_html(df, fig_dir, prefix)
    if ppath or not figures.has_section(df):  # with the section model alone, the tiers section says it all
        sections.append(("Analytic vs FEM", body))

    sections.append(("Formula, section model and 3-D FEM", _tiers_html(df, fig_dir, prefix)))

    bpath = figures.bend_curves(df, fig_dir / "bend_curves.png")
    if bpath:
        sections.append(
            (
                "Large bends",
                figure(
                    prefix + bpath.name,
                    "Bend angle vs pressure: finite-strain FEM (solid), linear FEM (dashed), analytic "
                    "(dotted). Where they part, the small-rotation models stop being trustworthy.",
                ),
            )
        )

    epath, label = figures.parameter_plots(df, params, fig_dir / "vs_parameters.png")
    sections.append(
        (
            "Against each swept parameter",
            figure(prefix + epath.name, f"{esc(label)} against each swept parameter.")
            if epath
            else note("No valid design with a numeric swept parameter."),
        )
    )

    hpath, caption = figures.heat_maps(df, factorial, fig_dir / "heatmap.png")
    if hpath:
        sections.append(("Heat maps", figure(prefix + hpath.name, esc(caption))))

    sensitivity = _sensitivity_html(df, params, lhs, fig_dir, prefix)
    if sensitivity:
        sections.append(("Sensitivity", sensitivity))

    sections.append(("Renders", _renders(df, sweep_dir, fig_dir, prefix, fem)))
    sections.append(("Failed designs", _failed_html(df)))
    sections.append(("Selection", _selection_html(sweep_dir, fig_dir, prefix)))
    return sections


def _overview_html(spec: dict, per) -> str:
    """The overview paragraph: the sweep, its designs (``per``: one row per design) and the loads."""
    n_ok = int((per.status == "ok").sum())
    kinds = ", ".join(f"<code>{esc(p['path'])}</code> ({p['kind']})" for p in spec["parameters"]) or "none"
    opts = spec.get("options") or {}  # the tiers' options the sweep ran with (none: their defaults)
    options = "".join(
        f" Model options of {esc(tier)}: "
        + ", ".join(f"<code>{esc(k)} = {esc(v)}</code>" for k, v in o.items())
        + "."
        for tier, o in opts.items()
    )
    return (
        f"<p>Sweep <b>{esc(spec['name'])}</b> on base design <code>{esc(spec['base'])}</code>: "
        f"{len(per)} designs ({n_ok} ok, {len(per) - n_ok} failed) × {len(spec['pressures_MPa'])} pressures "
        f"({', '.join(fmt(p) for p in spec['pressures_MPa'])} MPa) × loads {', '.join(spec['loads'])}; "
        f"evaluators: {', '.join(spec['evaluators'])}. Swept: {kinds}.{options}</p>"
        "<p>Loads: <b>cap</b> is the paper's model (end-cap force only); <b>lumen</b> adds the pressure on "
        "the lumen wall, whose Poisson coupling multiplies the analytic response by (1 − 2ν) for an "
        "unconfined tube.</p>"
    )


def _parity_html(df, fig_dir: Path, prefix: str):
    """The FEM-vs-analytic parity plot's path (``None`` without FEM results) and its HTML."""
    ppath = figures.parity_plot(df, fig_dir / "parity.png")
    if ppath:
        ok = df[(df.status == "ok") & np.isfinite(df.rel_diff_curvature)]
        stats = [
            (load, len(g), float(g.rel_diff_curvature.median()), float(g.abs_rel_diff_curvature.max()))
            for load, g in ok.groupby("load")
        ]
        body = figure(
            prefix + ppath.name,
            "FEM vs analytic curvature, every design and pressure, both loads: against the analytic model of "
            "the same load (left) and against the paper's formula, the analytic cap load (right)."
            + _lumen_formula_caption(df),
        )
        body += table(
            ["load", "rows", "median (FEM − analytic)/|analytic|", "max |rel. diff.|"], stats, left=1
        )
    else:
        body = note(
            "No FEM results in this sweep (analytic only, or the FEM evaluator was unavailable): "
            "no parity plot."
        )
    return ppath, body


def _lumen_formula_caption(df) -> str:
    """Why the lumen-load analytic points sit near zero, when they do (they are the formula's answer)."""
    ok = df[(df.status == "ok") & (df.pressure_MPa > 0)]
    cap = ok[ok.load == "cap"].set_index(["design_id", "pressure_MPa"]).curvature_analytic_per_mm
    lumen = ok[ok.load == "lumen"].set_index(["design_id", "pressure_MPa"]).curvature_analytic_per_mm
    both = cap.index.intersection(lumen.index)
    if not len(both):
        return ""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.abs(lumen.loc[both].to_numpy(float) / cap.loc[both].to_numpy(float))
    ratio = ratio[np.isfinite(ratio)]
    if not ratio.size or np.median(ratio) >= 0.1:
        return ""
    return (
        f" Under the lumen load the analytic model bends {np.median(ratio):.1%} of its cap-load bend "
        "(median), so its lumen points sit near zero on the left: that is the model's answer under that "
        "load, not missing data."
    )


def _sensitivity_html(df, params: list[str], lhs: bool, fig_dir: Path, prefix: str) -> str | None:
    """The sensitivity figure and table (HTML), or ``None`` when there is nothing to show."""
    spath, rows = figures.sensitivity(df, params, lhs, fig_dir / "sensitivity.png")
    if not spath:
        return None
    body = figure(
        prefix + spath.name,
        "Sensitivity of the "
        f"{'section-model curvature (lumen load)' if figures.has_section(df) else 'analytic curvature'} "
        "at p_max to each parameter: "
        "standardised regression coefficients" + (" and RBD-FAST first-order indices (SALib)" if lhs else ""),
    )
    body += table(["parameter", "SRC", "RBD-FAST S1"], rows, left=1)
    return body


def _failed_html(df) -> str:
    """The failed designs grouped by reason (HTML table), or a line saying there are none."""
    fails = figures.failed_summary(df)
    if fails:
        return table(["reason", "designs", "design ids"], fails, left=1)
    return "<p class='ok'>No failed designs.</p>"


def _tiers_html(df, fig_dir: Path, prefix: str) -> str:
    """The three tiers side by side: parity panels and the agreement table (section model, FEM, formula).

    The caption and the table name only the tiers that ran; a tier that ran but has nothing to be
    compared with (the formula is a cap-load model: a lumen-only sweep has no formula value to
    set the section model against) is said so, with what to add.
    """
    section, fem = figures.has_section(df), figures.has_fem(df)
    if not (section or fem):
        return note(
            'Only the paper\'s formula ran in this sweep: add <code>"section"</code> (2-D section model, '
            '3-D-FEM-grade curvature in a fraction of a second per design) or <code>"fem"</code> to the '
            "sweep's evaluators to compare."
        )
    tpath = figures.tiers_parity_plot(df, fig_dir / "parity_tiers.png")
    ran = " and ".join(n for n, has in (("the section model", section), ("the 3-D FEM", fem)) if has)
    if tpath is None:
        return note(
            f"{ran[0].upper() + ran[1:]} ran, but the paper's formula is a cap-load model (eq. 7) and this "
            'sweep has no cap-load rows to compare with: add <code>"cap"</code> to the sweep\'s loads.'
        )
    what = [
        f"{n} against the paper's formula"
        for n, has in (("the section model", section), ("the 3-D FEM", fem))
        if has
    ]
    if section and fem:
        what.append("the 3-D FEM against the section model (their agreement)")
    body = figure(
        prefix + tpath.name,
        f"Curvature of every design and pressure, each load of the sweep: {', '.join(what)}; the formula is "
        "eq. 7 under the cap load, what the paper predicts.",
    )
    header = ["load", "rows", "median section / formula", "median FEM / formula"]
    header += ["median |FEM / section − 1|", "max |FEM / section − 1|"]
    keep = [0, 1] + ([2] if section else []) + ([3] if fem else []) + ([4, 5] if section and fem else [])
    rows = [[row[i] for i in keep] for row in figures.tier_agreement(df)]
    body += table([header[i] for i in keep], rows, left=1)
    return body


def _renders(df, sweep_dir: Path, fig_dir: Path, prefix: str, fem: bool) -> str:
    ok = df[(df.status == "ok") & df.at_p_max]
    if ok.empty:
        return note("No valid design to render.")
    if fem:
        # Agreement under the cap load, where the analytic model claims validity (the lumen-load
        # ratios are orders of magnitude larger and would decide alone).
        base = ok[ok.load == "cap"] if (ok.load == "cap").any() else ok
        score = base.groupby("design_id").abs_rel_diff_curvature.mean().dropna()
        picks = [
            ("best-agreeing", int(score.idxmin()), score.min()),
            ("worst-agreeing", int(score.idxmax()), score.max()),
        ]
        what = (
            "|FEM − analytic|/|analytic| of curvature, cap load"
            if (ok.load == "cap").any()
            else "mean |rel. diff.| of curvature"
        )
    else:
        score = ok[ok.load == ok.load.iloc[0]].groupby("design_id").bend_per_MPa_deg.mean()
        picks = [
            ("most bending", int(score.idxmax()), score.max()),
            ("least bending", int(score.idxmin()), score.min()),
        ]
        what = "bend per MPa [deg/MPa] (best estimate: " + ", ".join(sorted(set(ok.source))) + ")"
    out = ""
    for label, did, value in picks:
        d = design_of(sweep_dir, did)
        rows = ok[ok.design_id == did]
        curv = {}
        for _, r in rows.iterrows():
            curv[f"analytic, {r.load}"] = float(r.curvature_analytic_per_mm)
            if np.isfinite(r.get("curvature_section_per_mm", np.nan)):
                curv[f"section, {r.load}"] = float(r.curvature_section_per_mm)
            if np.isfinite(r.curvature_fem_per_mm):
                curv[f"FEM, {r.load}"] = float(r.curvature_fem_per_mm)
        path = figures.render_design(
            d, fig_dir / f"render_{did}.png", title=f"{label}: design {did}", curvatures=curv
        )
        out += figure(prefix + path.name, f"{esc(label)} design {did} ({what} = {fmt(value)}) at p_max.")
    return out


def write_report(
    sweep_dir: str | Path, *, prefix: str = "", out: str | Path | None = None
) -> tuple[Path, list[tuple[str, str]]]:
    """Write ``DIR/report/index.html`` (and its PNGs) for the sweep in ``DIR``; ``out`` moves the folder.

    Returns the page's path and its sections ``(title, html)`` with image links
    prefixed by ``prefix``, for embedding the report in another page.
    """

    sweep_dir = Path(sweep_dir)
    out = sweep_dir / "report" if out is None else Path(out)
    # The page and its figures replace the old ones only as a whole; an earlier report's figures
    # that this one did not redraw go (they are the report's), anything else in the folder stays.
    with staged_dir(out, owner="report") as stage:
        sections = sweep_sections(sweep_dir, stage, prefix=prefix)
        mark = '<img src="' + prefix
        body = "".join(f"<h2>{esc(t)}</h2>{h}" for t, h in sections)
        if prefix:
            body = body.replace(mark, '<img src="')  # the page itself sits beside its figures
        body = _explore_link(sweep_dir, stage) + body
        (stage / "index.html").write_text(
            page("softcath sweep report", body, subtitle=f"Directory: <code>{esc(sweep_dir)}</code>"),
            encoding="utf-8",
        )
    path = out / "index.html"
    return path, sections


def _explore_link(sweep_dir: Path, stage: Path) -> str:
    """Write the interactive ``explore.html`` beside the page; the link to it."""

    params = [p["path"] for p in _manifest(sweep_dir)["spec"]["parameters"]]
    write_explore(sweep_dir, stage, read_results(sweep_dir), params)
    return (
        "<p><b><a href='explore.html'>Explore interactively</a></b>: hover for a design's parameters, "
        "brush ranges in parallel coordinates, click a Pareto design for its section and tip.</p>"
    )


_ = Markup  # re-exported for callers building tables with HTML cells
