"""The optimisation report: ``DIR/index.html`` of a ``softcath optimise`` folder, interactive and offline.

Winners (parameters, objectives, constraint margins, robust percentiles and
probabilities, the 3-D FEM re-check), every evaluation in parallel
coordinates (brush an axis to filter), the objectives of every evaluation
with the winners highlighted (a click shows the design's section and bent tip),
and a static convergence PNG for print.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from softcath import design, models
from softcath.design.errors import DataError
from softcath.design.reference import with_unit
from softcath.studies.report import interactive as ia
from softcath.studies.report.figures import _plt, _save, render_design
from softcath.studies.report.html_blocks import Markup, esc, figure, fmt, note, page, table

__all__ = ["write_optimum_report"]

#: Winners drawn as section-and-tip pictures (each ~0.3 s): the first ones of the Pareto set.
MAX_PICTURES = 12


def _read(out_dir: Path):
    import pandas as pd

    path = out_dir / "optimum.json"
    if not path.is_file():
        raise DataError(f"{out_dir}: no optimum.json (run `softcath optimise ... --out {out_dir}` first)")
    try:
        return json.loads(path.read_text(encoding="utf-8")), pd.read_parquet(out_dir / "history.parquet")
    except Exception as exc:  # json and pyarrow raise several types for damaged files
        raise DataError(
            f"{path.parent}: unreadable optimisation output ({type(exc).__name__}: {exc})"
        ) from None


def _convergence_png(opt: dict, hist, path: Path) -> Path:

    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    first = opt["objectives"][0]
    sign = -1.0 if first.split()[0].lower().startswith("max") else 1.0
    v = hist[first].to_numpy(float)
    feas = hist["feasible"].to_numpy(bool)
    ax.plot(np.flatnonzero(feas), v[feas], ".", ms=3, label="feasible designs")
    best = np.where(feas, sign * v, np.inf)
    run = np.minimum.accumulate(np.where(np.isfinite(best), best, np.inf))
    ok = np.isfinite(run)
    ax.plot(np.flatnonzero(ok), sign * run[ok], "-", color="C3", label="best so far")
    ax.set_xlabel("evaluation")
    ax.set_ylabel(with_unit(first))
    ax.legend(fontsize=8)
    return _save(fig, path)


def _design_info(out_dir: Path, w: dict, draw: bool, opt: dict) -> dict:
    """Label, hover/click HTML and the section-and-tip picture of a winner."""
    image = ""
    src = out_dir / "designs" / f"{w['name']}.toml"
    if draw and src.is_file():
        d = design.load(src)
        p_max = max(opt["pressures_MPa"])
        # the formula through its tier, with the options the search ran it with (none: the formula's own)
        opts = (opt.get("model_options") or {}).get("paper")
        kappa = float(models.response(d, [p_max], tier="paper", load="cap", options=opts).curvature_per_mm[0])
        png = render_design(
            d,
            out_dir / "designs" / f"{w['name']}.png",
            title=w["name"],
            curvatures={f"paper's formula, {fmt(p_max)} MPa": kappa},
        )
        image = f"designs/{png.name}"
    lines = [f"<b>{esc(w['name'])}</b>{'' if w['feasible'] else ' (infeasible)'}"]
    lines += [f"{esc(k)} = {fmt(v)}" for k, v in {**w["parameters"], **w["objectives"]}.items()]
    fem = w.get("fem_check")
    if fem:
        lines.append(
            f"3-D FEM: curvature differs by {fmt(fem.get('curvature_rel_diff'))} "
            f"({'meets' if fem.get('feasible') else 'misses'} the constraints)"
        )
    return {"label": esc(w["name"]), "html": "<br>".join(lines), "image": image}


def _winners_table(opt: dict) -> str:
    best = opt["best"]
    if not best:
        return note("No winner.")
    params = list(best[0]["parameters"])
    header = [
        "design",
        "feasible",
        *map(with_unit, params),
        *opt["objectives"],
        *(f"margin: {c}" for c in opt["constraints"]),
    ]
    rows = [
        [
            Markup(esc(w["name"])),
            w["feasible"],
            *w["parameters"].values(),
            *w["objectives"].values(),
            *_margins(w).values(),
        ]
        for w in best
    ]
    out = table(header, rows, left=1)
    if opt.get("robust"):
        head = [
            "design",
            *(f"{o} p5/p50/p95" for o in opt["objectives"]),
            *(f"P({c})" for c in opt["constraints"]),
        ]
        rows = [
            [
                Markup(esc(w["name"])),
                *(
                    Markup(" / ".join(fmt(w["percentiles"][o][q]) for q in ("p5", "p50", "p95")))
                    for o in opt["objectives"]
                ),
                *(w["probabilities"][c] for c in opt["constraints"]),
            ]
            for w in best
        ]
        out += (
            f"<p>Robust: probability P = {fmt(opt['robust']['P'])} over {opt['robust']['samples']} samples "
            "of "
            + ", ".join(f"<code>{esc(r['path'])}</code>" for r in opt["robust"]["ranges"])
            + ".</p>"
            + table(head, rows, left=1)
        )
    checks = [w for w in best if w.get("fem_check")]
    if checks:
        rows = [
            [
                Markup(esc(w["name"])),
                Markup(esc(w["fem_check"]["status"])),
                w["fem_check"]["feasible"],
                w["fem_check"]["curvature_rel_diff"],
                *w["fem_check"]["objectives"].values(),
            ]
            for w in checks
        ]
        out += "<h3>3-D linear FEM re-check</h3>" + table(
            ["design", "status", "meets constraints", "|FEM − model| / model (κ)", *opt["objectives"]],
            rows,
            left=2,
        )
    else:
        out += note(
            "The winners were not re-checked by the 3-D FEM (run without <code>--no-fem-check</code>)."
        )
    return out


def write_optimum_report(out_dir: str | Path) -> Path:
    """Write ``out_dir/index.html`` (and ``plotly.min.js``, ``convergence.png``) for an optimisation
    folder."""
    out_dir = Path(out_dir)
    opt, hist = _read(out_dir)
    ia.write_plotly_js(out_dir)
    paths = [v["path"] for v in opt["variables"]]
    objs, cons = opt["objectives"], opt["constraints"]
    body = (
        f"<p>{esc(opt['algorithm'])} on the <b>{esc(opt['model'])}</b> model ({esc(opt['load'])} load), "
        f"{opt['evaluations']} designs, {opt['model_runs']} model runs, seed {opt['seed']}, "
        f"{fmt(opt['seconds'])} s on {esc(opt['backend'])}.</p>"
    )
    body += "<h2>Winners</h2>" + _winners_table(opt)
    cols = {p: hist[p] for p in paths}
    cols.update({o: hist[o] for o in objs})
    cols.update({f"margin {c}": hist[f"margin {c}"].clip(lower=-1e3) for c in cons})
    body += "<h2>Every evaluation</h2>" + ia.chart(
        ia.parallel(cols, color=objs[0]),
        "opt-parallel",
        "Parameters and results of every evaluated design; drag along an axis to brush a range.",
    )
    info = [_design_info(out_dir, w, k < MAX_PICTURES, opt) for k, w in enumerate(opt["best"])]
    x = [w["objectives"][objs[0]] for w in opt["best"]]
    if len(objs) > 1:
        y, ylab = [w["objectives"][objs[1]] for w in opt["best"]], objs[1]
    else:
        y, ylab = (
            [_margins(w)[cons[0]] if cons else 0.0 for w in opt["best"]],
            (f"margin {cons[0]}" if cons else ""),
        )
    hy_src = hist[objs[1]] if len(objs) > 1 else (hist[f"margin {cons[0]}"] if cons else hist[objs[0]] * 0)
    hx_all, hy_all = hist[objs[0]].to_numpy(float), hy_src.to_numpy(float)
    winners = set(zip(np.asarray(x, float).tolist(), np.asarray(y, float).tolist(), strict=True))
    # the other feasible evaluations (a winner's own evaluation is drawn once, as a winner)
    feas = hist["feasible"].to_numpy(bool) & np.array(
        [(a, b) not in winners for a, b in zip(hx_all.tolist(), hy_all.tolist(), strict=True)], bool
    )
    all_info = info + [
        {"label": f"evaluation {i}", "html": f"evaluation {i}", "image": ""} for i in np.flatnonzero(feas)
    ]
    hx = np.concatenate([np.asarray(x, float), hx_all[feas]])
    hy = np.concatenate([np.asarray(y, float), hy_all[feas]])
    front = np.r_[np.ones(len(x), bool), np.zeros(int(feas.sum()), bool)]
    fig = ia.pareto(hx, hy, all_info, xlabel=with_unit(objs[0]), ylabel=with_unit(ylab), on_front=front)
    body += (
        "<h2>Objectives</h2>"
        + ia.chart(
            fig,
            "opt-pareto",
            "Feasible evaluations; the winners (Pareto front) large. Click a winner to see it.",
        )
        + ia.click_panel("opt-pareto", all_info)
    )
    png = _convergence_png(opt, hist, out_dir / "convergence.png")
    body += "<h2>Convergence</h2>" + figure(
        png.name, "First objective of every feasible evaluation (static, for print)."
    )
    path = out_dir / "index.html"
    tmp = out_dir / ".index.html.tmp"
    tmp.write_text(page("softcath optimise", ia.script_tag() + body), encoding="utf-8")
    tmp.replace(path)
    return path


def _margins(winner: dict) -> dict:
    """A winner's ``{constraint: margin}`` (``margins``; ``constraints`` in earlier records)."""
    return winner["margins"] if "margins" in winner else winner["constraints"]
