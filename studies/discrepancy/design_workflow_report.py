"""``discrepancy.json`` and ``report.html`` of the design-space workflow."""

from __future__ import annotations

import base64
import html
import io
import textwrap
from pathlib import Path

from softcath.core.atomic import Outputs, prepare_out_dir
from softcath.core.plotting import pyplot

__all__ = ["write_design_report"]


def _png(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    return base64.b64encode(buf.getvalue()).decode()


def _parity(result) -> str:
    plt = pyplot()
    import numpy as np

    t = result.table
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6), sharex=True, sharey=True)
    ref = np.array([r["reference_gain"] for r in t])
    lo, hi = 0.0, 1.1 * float(ref.max())
    for ax, key, title in (
        (axes[0], "formula_gain", "before: the paper's formula"),
        (axes[1], "model_gain", textwrap.fill("after: " + (" + ".join(result.named) or "nothing named"), 60)),
    ):
        for load, marker in (("cap", "o"), ("lumen", "s")):
            for held, colour in ((False, "tab:blue"), (True, "tab:orange")):
                sel = [r for r in t if r["load"] == load and r["heldout"] == held]
                if sel:
                    ax.scatter(
                        [r[key] for r in sel],
                        [r["reference_gain"] for r in sel],
                        marker=marker,
                        c=colour,
                        s=22,
                        label=f"{load}, {'held-out' if held else 'training'}",
                    )
        ax.plot([lo, hi], [lo, hi], "k--", lw=0.8)
        ax.set_xlabel("model κ/p [1/(mm MPa)]")
        ax.set_title(title, fontsize=10)
    axes[0].set_ylabel("3-D FEM κ/p [1/(mm MPa)]")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    out = _png(fig)
    plt.close(fig)
    return out


def write_design_report(result, out_dir: str | Path) -> Path:
    """Write ``discrepancy.json`` and ``report.html`` into ``out_dir``; return the HTML path."""

    out = prepare_out_dir(out_dir)
    doc = result.to_json()
    rows = []
    for s in result.steps:
        for cand, v in s["candidates"].items():
            mark = " (named)" if s["named"] == cand else ""
            rows.append(
                f"<tr><td>{s['step']}</td><td>{html.escape(cand)}{mark}</td><td>{s['gap_heldout_before']:.4g}</td>"
                f"<td>{v['gap_train']:.4g}</td><td>{v['gap_heldout']:.4g}</td></tr>"
            )
    named = " + ".join(result.named) or "nothing"
    notes = "".join(f"<li>{html.escape(n)}</li>" for n in result.notes)
    amb = "".join(f"<li>{html.escape(k)} ~ {', '.join(v)}</li>" for k, v in result.ambiguous_with.items())
    page = f"""<!doctype html><html><head><meta charset="utf-8">
<title>softcath: what the formula misses</title>
<style>body{{font-family:sans-serif;max-width:1000px;margin:2em auto}}table{{border-collapse:collapse}}
td,th{{border:1px solid #ccc;padding:3px 8px;text-align:right}}</style></head><body>
<h1>What the paper's formula misses, over {result.n_designs} designs</h1>
<p>Named: <b>{html.escape(named)}</b>. Held-out gap (median |FEM/model − 1|)
{result.gap_before:.4g} → {result.gap_after:.4g}
({result.gap_before / max(result.gap_after, 1e-300):.3g}× smaller);
held-out NRMSE {result.nrmse_before:.4g} → {result.nrmse_after:.4g}.
{result.n_train} training and {result.n_heldout} held-out designs (seed {result.seed}),
margin {result.margin:.0%}.</p>
<h2>Parity before and after</h2><img alt="parity" src="data:image/png;base64,{_parity(result)}">
<h2>Steps</h2><table><tr><th>step</th><th>candidate</th><th>gap before</th><th>gap train</th>
<th>gap held-out</th></tr>{"".join(rows)}</table>
{"<h2>Ambiguous</h2><ul>" + amb + "</ul>" if amb else ""}
{"<h2>Notes</h2><ul>" + notes + "</ul>" if notes else ""}
</body></html>"""
    with Outputs(out) as o:  # both files or neither
        o.json("discrepancy.json", doc)
        o.text("report.html", page)
    return out / "report.html"
