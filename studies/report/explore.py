"""The sweep report's interactive page, ``explore.html``: parity with hover, parallel coordinates, Pareto
clicks.

Beside the static ``index.html`` (kept for print) in the same folder, with
``plotly.min.js`` written once there. The parity plot's hover shows each
design's swept parameters; the parallel coordinates cover parameters and
results at p_max (drag along an axis to brush a range); when the sweep has a
``selection.json`` its feasible designs are drawn in the plane of the first
two objectives (p50 for a robust selection), and a click on a Pareto design
shows its section picture and bent tip.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from softcath.design.reference import with_unit
from softcath.studies.report import figures
from softcath.studies.report import interactive as ia
from softcath.studies.report.html_blocks import esc, fmt, note, page
from softcath.studies.report.sweep_folder import design_of
from softcath.studies.sweep.results import MODEL_COLUMNS, model_columns
from softcath.studies.tiers import TIERS

__all__ = ["write_explore"]

#: Pareto designs drawn (section and tip picture, ~0.3 s each).
MAX_PICTURES = 24
_RESULTS = ("bend_angle_deg", "bend_per_MPa_deg", "max_strain", "elongation", "curvature_per_mm")


def _parity(df, params: list[str]) -> str:
    ok = df[df.status == "ok"]
    pairs = [
        (m, c)
        for m, c in (("3-D FEM", "curvature_fem_per_mm"), ("section model", "curvature_section_per_mm"))
        if c in ok and np.isfinite(ok[c].to_numpy(float)).any()
    ]
    out = ""
    for load, g in ok.groupby("load"):
        g = g[g.pressure_MPa > 0]
        if pairs:
            name, col = pairs[0]
            y, ylabel = g[col], f"{name} curvature [1/mm]"
        elif load == "lumen":
            continue
        else:  # the formula alone: cap against lumen load of the same design and pressure
            lumen = ok[(ok.load == "lumen") & (ok.pressure_MPa > 0)]
            if lumen.empty:
                continue
            y, ylabel = (
                lumen["curvature_analytic_per_mm"].to_numpy(float),
                "analytic curvature, lumen load [1/mm]",
            )
        cols = {p: g[p].to_numpy() for p in params if p in g}
        cols["p [MPa]"] = g["pressure_MPa"].to_numpy()
        labels = [f"design {i}" for i in g["design_id"]]
        fig = ia.parity(
            g["curvature_analytic_per_mm"],
            y,
            cols,
            xlabel="paper's formula curvature [1/mm]",
            ylabel=ylabel,
            name=f"{load} load",
            label=labels,
        )
        out += ia.chart(
            fig, f"parity-{load}", f"{esc(load)} load: every design and pressure; hover for its parameters."
        )
    return out or note("No valid design to plot.")


def _selection_tier(df, sel: dict | None) -> str | None:
    """The tier whose values the selection was ranked on, if the sweep has its columns (else None)."""

    if not sel:
        return None
    for tier in (sel.get("model"), (sel.get("recheck") or {}).get("linear_model")):
        cols = MODEL_COLUMNS.get(tier or "", {})
        if cols and any(c in df.columns and np.isfinite(df[c].to_numpy(float)).any() for c in cols.values()):
            return tier
    return None


def _parallel(df, params: list[str], load: str, tier: str | None = None) -> str:
    """Parameters and results at p_max; with ``tier``, the results are that tier's (the selection's)."""

    if tier is not None:
        df = model_columns(df, tier)
    at = df[(df.status == "ok") & df.at_p_max & (df.load == load)]
    if at.empty:
        return note("No valid design to plot.")
    cols = {p: at[p].to_numpy() for p in params if p in at and np.issubdtype(at[p].dtype, np.number)}
    cols.update({c: at[c].to_numpy(float) for c in _RESULTS if c in at})
    cols = {with_unit(k): v for k, v in cols.items()}  # axis titles with units: tube.h [mm]
    fig = ia.parallel(cols, color="bend_angle_deg")
    return ia.chart(
        fig,
        "parallel",
        f"Designs at p_max, {esc(load)} load"
        + (f", {esc(TIERS[tier].label)}'s values (the selection's)" if tier else "")
        + ": drag along an axis to brush a range; "
        "drag the brushed range to move it, click the axis outside it to clear.",
    )


def _pareto(sweep_dir: Path, stage: Path, sel: dict) -> str:

    objs = sel["objectives"]
    robust = sel.get("robust")
    if robust:  # the robust ranking: p50 of the passers
        pts = [[r["design_id"], int(r["pareto"]), *r["objectives"].values()] for r in sel["ranked"]]
    else:
        pts = sel.get("points") or []
    if not pts:
        return note("No feasible design in the selection.")
    pts = np.asarray(pts, float)
    x = pts[:, 2]
    y = pts[:, 3] if len(objs) > 1 else np.zeros(len(pts))
    info = []
    for row in pts:
        did, on_front = int(row[0]), bool(row[1])
        html = f"<b>design {did}</b>" + "".join(
            f"<br>{esc(o)} = {fmt(v)}" for o, v in zip(objs, row[2:], strict=False)
        )
        image = ""
        if on_front and sum(i["image"] != "" for i in info) < MAX_PICTURES:
            d = design_of(sweep_dir, did)
            image = figures.render_design(d, stage / f"explore_design_{did}.png", title=f"design {did}").name
        info.append({"label": f"design {did}", "html": html, "image": image})
    fig = ia.pareto(
        x,
        y,
        info,
        xlabel=with_unit(objs[0]),
        ylabel=with_unit(objs[1]) if len(objs) > 1 else "",
        on_front=pts[:, 1] > 0,
    )
    what = "p50 over the material ranges of the robust passers" if robust else "feasible designs"
    return ia.chart(
        fig, "pareto", f"Selection ({esc(what)}): click a Pareto design to see its section and tip."
    ) + (ia.click_panel("pareto", info))


def write_explore(sweep_dir: str | Path, stage: str | Path, df, params: list[str]) -> Path:
    """Write ``stage/explore.html`` and ``stage/plotly.min.js`` for the sweep in ``sweep_dir``."""
    sweep_dir, stage = Path(sweep_dir), Path(stage)
    ia.write_plotly_js(stage)
    sel = None
    if (sweep_dir / "selection.json").is_file():
        try:
            sel = json.loads((sweep_dir / "selection.json").read_text(encoding="utf-8"))
        except (json.JSONDecodeError, UnicodeDecodeError):
            sel = None  # the static page reports the damaged file
    load = sel["load"] if sel else ("lumen" if (df.load == "lumen").any() else str(df.load.iloc[0]))
    body = "<p><a href='index.html'>Static report</a> (for print).</p>"
    body += "<h2>Parity</h2>" + _parity(df, params)
    body += "<h2>Parameters and results</h2>" + _parallel(df, params, load, _selection_tier(df, sel))
    body += "<h2>Selection</h2>" + (
        _pareto(sweep_dir, stage, sel)
        if sel
        else note("No selection: run <code>softcath select</code> first.")
    )
    path = stage / "explore.html"
    path.write_text(page("softcath sweep: explore", ia.script_tag() + body), encoding="utf-8")
    return path
