"""``discrepancy.json`` and ``report.html``: residual maps, before/after loops, decisions."""

from __future__ import annotations

import html
import json
import logging
from pathlib import Path

import numpy as np

from softcath.analytic.effects import get
from softcath.core.atomic import check_finite_json, prepare_out_dir
from softcath.core.plotting import pyplot
from softcath.studies.discrepancy.maps import Residuals, binned, residuals
from softcath.studies.discrepancy.workflow import DiscrepancyResult

__all__ = ["write_report"]

log = logging.getLogger(__name__)


def _plot_maps(res: Residuals, title: str, path: Path, static: bool) -> None:
    plt = pyplot()

    fig, ax = plt.subplots(2, 2, figsize=(11, 7.5))
    step = max(1, res.residual.size // 4000)
    r = res.residual * 1e3
    a = ax[0, 0]
    if static:
        a.plot(res.pressure_MPa, r, "o-", color="k")
    else:
        a.scatter(
            res.pressure_MPa[res.loading][::step],
            r[res.loading][::step],
            s=3,
            color="tab:red",
            label="loading",
        )
        a.scatter(
            res.pressure_MPa[~res.loading][::step],
            r[~res.loading][::step],
            s=3,
            color="tab:blue",
            label="unloading",
        )
        a.legend(loc="best", fontsize=8)
    a.axhline(0, color="grey", lw=0.8)
    a.set(
        xlabel="pressure [MPa]",
        ylabel="residual data - model [1e-3/mm]",
        title="over pressure (loading vs unloading)",
    )
    a = ax[0, 1]
    if not static:
        c, m = binned(res.rate_MPa_per_s, r)
        a.plot(c, m, "o-", color="k")
        a.set(xlabel="pressure rate [MPa/s]", ylabel="mean residual [1e-3/mm]", title="over pressure rate")
    else:
        a.text(0.5, 0.5, "quasi-static reference: no rate", ha="center", transform=a.transAxes)
    a.axhline(0, color="grey", lw=0.8)
    a = ax[1, 0]
    rms = res.rms_by_run()
    labels = [
        f"{lab}\n{f:.3g} Hz" if f > 0 else lab for lab, f in zip(res.labels, res.frequency_hz, strict=True)
    ]
    a.bar(range(len(rms)), [v * 1e3 for v in rms.values()], color="tab:gray")
    a.set_xticks(range(len(rms)), labels, fontsize=8)
    a.set(ylabel="RMS residual [1e-3/mm]", title="by run / excitation frequency")
    a = ax[1, 1]
    offset = 0.0
    for i, lab in enumerate(res.labels):
        sel = res.run == i
        t = res.time_s[sel]
        if t.size == 0:
            continue
        a.plot(t - t[0] + offset, r[sel], lw=0.8, label=lab)
        offset += t[-1] - t[0] + 2
    a.axhline(0, color="grey", lw=0.8)
    a.set(xlabel="time, runs end to end [s]", ylabel="residual [1e-3/mm]", title="over time")
    a.legend(loc="best", fontsize=7)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _plot_loops(before: Residuals, after: Residuals, named: str, path: Path) -> None:
    plt = pyplot()

    n = len(before.labels)
    cols = min(n, 4)
    rows = int(np.ceil(n / cols))
    fig, ax = plt.subplots(rows, cols, figsize=(3.6 * cols, 3.3 * rows), squeeze=False)
    for i, lab in enumerate(before.labels):
        a = ax.flat[i]
        sel = before.run == i
        a.plot(before.pressure_MPa[sel], before.data[sel], color="k", lw=1.6, label="data")
        a.plot(
            before.pressure_MPa[sel],
            before.model[sel],
            color="tab:blue",
            lw=1,
            ls="--",
            label="model (calibrated)",
        )
        a.plot(
            after.pressure_MPa[sel],
            after.model[sel],
            color="tab:red",
            lw=1,
            label=f"model + {named}" if named else "model (final)",
        )
        f = before.frequency_hz[i]
        a.set(
            title=f"{lab}" + (f" ({f:.3g} Hz)" if f > 0 else ""),
            xlabel="pressure [MPa]",
            ylabel="curvature [1/mm]",
        )
        if i == 0:
            a.legend(fontsize=7, loc="upper left")
    for j in range(n, rows * cols):
        ax.flat[j].axis("off")
    fig.suptitle("pressure-curvature loops, filtered: before and after the named effects")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _plot_candidates(result: DiscrepancyResult, path: Path) -> None:
    plt = pyplot()
    from matplotlib.ticker import MaxNLocator

    k = len(result.candidates)
    fig, ax = plt.subplots(1, k, figsize=(4.4 * k, 3.4), squeeze=False)
    for i, table in enumerate(result.candidates):
        a = ax[0, i]
        cur = table["(current)"]
        names = [c for c in table if c != "(current)"]
        vals = [table[c] for c in names]
        chosen = result.named[i] if i < len(result.named) else None
        colors = ["tab:red" if c == chosen else "tab:gray" for c in names]
        a.barh(names, [0.0 if not np.isfinite(v) else v for v in vals], color=colors)
        for j, v in enumerate(vals):
            if not np.isfinite(v):  # pruned: could not beat the model even in-sample
                a.text(0, j, " pruned (in-sample)", va="center", fontsize=7, color="grey")
        a.axvline(cur, color="k", lw=1, label="current model")
        a.axvline(cur * (1 - result.margin), color="k", ls="--", lw=1, label="margin")
        a.xaxis.set_major_locator(MaxNLocator(4))
        verdict = f"named {chosen}" if chosen else "nothing named (see notes)"
        a.set(xlabel="held-out NRMSE", title=f"step {i + 1}: {verdict}")
        a.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _cell(v) -> str:
    """A table cell; nested records become nested tables."""
    if isinstance(v, dict):
        rows = "".join(f"<tr><td>{html.escape(str(k))}</td><td>{_cell(x)}</td></tr>" for k, x in v.items())
        return f"<table>{rows}</table>"
    return _fmt(v)


def _fmt(v) -> str:
    if v is None:
        return "-"
    if isinstance(v, float):
        return f"{v:.4g}"
    return html.escape(str(v))


def write_report(result: DiscrepancyResult, out_dir) -> Path:
    """Write ``discrepancy.json``, ``report.html`` and PNG figures; returns the HTML path."""

    out = prepare_out_dir(out_dir)
    record = result.as_dict()
    check_finite_json(record)  # strict JSON: a NaN in the record is refused, not written
    (out / "discrepancy.json").write_text(json.dumps(record, indent=2, allow_nan=False))
    _write_figures(result, out)
    shrink = record["gap_shrink"]
    rows = _step_rows(result)
    notes = "".join(f"<li>{html.escape(n)}</li>" for n in result.notes)
    runs = "".join(
        f"<tr><td>{html.escape(r['run'])}</td><td>{r['kind']}</td>"
        f"<td>{_fmt(r['frequency_hz'])}</td><td>{_fmt(r['duration_s'])}</td></tr>"
        for r in record["runs"]
    )
    cal = "".join(
        f"<tr><td>{html.escape(k)}</td><td>{_cell(v)}</td></tr>" for k, v in result.calibration.items()
    )
    filt = "".join(f"<tr><td>{html.escape(k)}</td><td>{_fmt(v)}</td></tr>" for k, v in result.filter.items())
    library = _library_rows(result)
    verdict = (
        f"named: <b>{html.escape(' + '.join(result.named))}</b>"
        if result.named
        else "<b>nothing named</b>: the calibrated model explains the data to within the margin"
    )
    page = f"""<!doctype html><html><head><meta charset="utf-8">
<title>softcath discrepancy report</title>
<style>body{{font-family:sans-serif;max-width:1150px;margin:2em auto;color:#222}}
table{{border-collapse:collapse;margin:0.5em 0}}td,th{{border:1px solid #ccc;padding:4px 8px;
vertical-align:top}}img{{max-width:100%}}</style></head><body>
<h1>Missing-effect workflow ({html.escape(result.reference)} reference)</h1>
<p>{verdict}. Held-out NRMSE {result.nrmse_before:.4g} &rarr; {result.nrmse_after:.4g}
(gap shrink {_fmt(shrink)}&times;; noise floor {result.noise_floor_nrmse:.3g};
{result.excess_removed:.1%} of the excess error power above the floor removed).</p>
<p><small>Rule: {html.escape(record["decision_rule"]["text"])}. Scores are held-out
(leave-one-run-out, or blocks of cycles for a single run); model output is filtered exactly
as the data.</small></p>
<h2>Steps</h2><table><tr><th>#</th><th>effect</th><th>estimate &plusmn; 1&sigma;</th>
<th>NRMSE before</th><th>after</th><th>excess removed</th><th>cannot rule out</th></tr>{rows}
</table><ul>{notes}</ul>
<h2>Where the model is wrong</h2><img src="residual_maps_before.png" alt="residual maps before">
<h2>Before and after</h2><img src="loops.png" alt="loops"><img src="residual_maps_after.png"
alt="residual maps after">
<h2>Candidates (held-out)</h2><img src="candidates.png" alt="candidate scores">
<table><tr><th>candidate</th><th>meaning</th><th>parameters (bounds relative to the data)</th></tr>
{library}</table>
<h2>Calibration</h2><table>{cal}</table>
<h2>Filter</h2><table>{filt}</table>
<h2>Runs</h2><table><tr><th>run</th><th>kind</th><th>frequency [Hz]</th><th>duration [s]</th>
</tr>{runs}</table>
</body></html>"""
    path = out / "report.html"
    path.write_text(page)
    log.info("wrote %s", path)
    return path


def _write_figures(result: DiscrepancyResult, out: Path) -> None:
    """Residual maps before and after, the loops and the candidate scores as PNGs."""
    prep = result.prepared
    before = residuals(prep, result.baseline_fit)
    after = residuals(prep, result.final_fit)
    _plot_maps(
        before,
        "where the calibrated model is wrong (residual maps, before)",
        out / "residual_maps_before.png",
        prep.static,
    )
    _plot_maps(
        after,
        "residual maps after adding " + (", ".join(result.named) or "nothing"),
        out / "residual_maps_after.png",
        prep.static,
    )
    _plot_loops(before, after, " + ".join(result.named), out / "loops.png")
    _plot_candidates(result, out / "candidates.png")


def _step_rows(result: DiscrepancyResult) -> str:
    """HTML rows of the named steps."""
    return "".join(
        f"<tr><td>{i + 1}</td><td><b>{html.escape(s['effect'])}</b><br><small>"
        f"{html.escape(s['meaning'])}</small></td><td>"
        + "<br>".join(
            f"{k} = {_fmt(v)} &plusmn; {_fmt(s['params_stderr'].get(k))}" for k, v in s["params"].items()
        )
        + (
            f"coefficient = {_fmt(s['coefficient'])} &plusmn; {_fmt(s['coefficient_stderr'])}"
            if s["coefficient"] is not None
            else ""
        )
        + f"</td><td>{_fmt(s['nrmse_before'])}</td><td>{_fmt(s['nrmse_after'])}</td>"
        f"<td>{s['excess_removed']:.1%}</td><td>{_fmt(', '.join(s['ambiguous_with']) or 'none')}"
        f"</td></tr>"
        for i, s in enumerate(result.steps)
    )


def _library_rows(result: DiscrepancyResult) -> str:
    """HTML rows describing the candidates of the first step."""

    return "".join(
        f"<tr><td>{html.escape(d['name'])}</td><td>{html.escape(d['meaning'])}</td><td>"
        + "<br>".join(
            f"{html.escape(q['name'])} [{html.escape(q['unit'])}]: {html.escape(q['doc'])}"
            for q in d["params"]
        )
        + "</td></tr>"
        for d in (get(c).describe() for c in result.candidates[0] if c != "(current)")
    )
