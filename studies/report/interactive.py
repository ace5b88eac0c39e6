"""Interactive Plotly charts for the offline reports: one ``plotly.min.js`` per report folder.

Every page of a folder loads the library with ``<script src="plotly.min.js">``
(written once by :func:`write_plotly_js`), so a report opens without a
network. Charts: a parity plot whose hover shows the design's parameters, a
parallel-coordinates chart over parameters and results (drag on an axis to
brush a range), and a Pareto front whose click shows the design beside it.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from softcath.studies.report.html_blocks import esc

__all__ = ["PLOTLY_JS", "write_plotly_js", "script_tag", "chart", "parity", "parallel", "pareto"]

PLOTLY_JS = "plotly.min.js"
#: Points drawn as SVG (hover on each); above this, WebGL.
SVG_POINTS = 5000


def write_plotly_js(folder: str | Path) -> Path:
    """Write the Plotly library into ``folder`` once (kept when already there)."""
    from plotly.offline import get_plotlyjs

    path = Path(folder) / PLOTLY_JS
    if not path.is_file():
        tmp = path.with_name(f".{PLOTLY_JS}.tmp")
        tmp.write_text(get_plotlyjs(), encoding="utf-8")
        tmp.replace(path)
    return path


def script_tag() -> str:
    """The ``<script>`` that loads the folder's Plotly (put it once in the page, before the charts)."""
    return f'<script src="{PLOTLY_JS}"></script>'


def chart(fig, div_id: str, caption: str) -> str:
    """A Plotly figure as an HTML fragment (no library inlined), with a caption."""
    body = fig.to_html(full_html=False, include_plotlyjs=False, div_id=div_id, config={"displaylogo": False})
    return f'<figure class="chart">{body}<figcaption>{caption}</figcaption></figure>'


def _hover(params: Mapping[str, Sequence], n: int, label: Sequence[str] | None = None) -> list[str]:
    out = []
    for i in range(n):
        head = [label[i]] if label is not None else []
        lines = head + [f"{esc(k)} = {_num(v[i])}" for k, v in params.items()]
        out.append("<br>".join(lines))
    return out


def _num(v) -> str:
    try:
        x = float(v)
    except (TypeError, ValueError):
        return esc(v)
    return f"{x:.4g}" if np.isfinite(x) else "—"


def parity(x, y, params: Mapping[str, Sequence], *, xlabel: str, ylabel: str, name: str, label=None):
    """Model vs reference scatter with the y = x line; hovering a point shows its design's parameters."""
    import plotly.graph_objects as go

    x, y = np.asarray(x, float), np.asarray(y, float)
    fig = go.Figure()
    kind = go.Scatter if len(x) <= SVG_POINTS else go.Scattergl  # WebGL only where SVG gets slow
    fig.add_trace(
        kind(
            x=x,
            y=y,
            mode="markers",
            name=name,
            marker={"size": 6, "opacity": 0.7},
            text=_hover(params, len(x), label),
            hovertemplate="%{text}<extra></extra>",
        )
    )
    finite = np.concatenate([x[np.isfinite(x)], y[np.isfinite(y)]])
    if finite.size:
        lo, hi = float(finite.min()), float(finite.max())
        fig.add_trace(
            go.Scatter(
                x=[lo, hi],
                y=[lo, hi],
                mode="lines",
                name="y = x",
                line={"color": "#888", "dash": "dash"},
                hoverinfo="skip",
            )
        )
    fig.update_layout(
        xaxis_title=xlabel, yaxis_title=ylabel, height=460, margin={"t": 30}, hovermode="closest"
    )
    return fig


def parallel(columns: Mapping[str, Sequence], *, color: str | None = None):
    """Parallel coordinates over ``columns`` (finite numbers); drag along an axis to brush a range."""
    import plotly.graph_objects as go

    dims = []
    for k, v in columns.items():
        a = np.asarray(v, float)
        if not np.isfinite(a).any():
            continue
        dims.append({"label": k, "values": np.where(np.isfinite(a), a, np.nanmin(a))})
    line = {}
    if color is not None and color in columns:
        c = np.asarray(columns[color], float)
        line = {
            "color": np.where(np.isfinite(c), c, np.nanmin(c)),
            "colorscale": "Viridis",
            "showscale": True,
        }
    fig = go.Figure(go.Parcoords(dimensions=dims, line=line))
    fig.update_layout(height=480, margin={"l": 80, "r": 80, "t": 60})
    return fig


def pareto(x, y, info: Sequence[dict], *, xlabel: str, ylabel: str, on_front=None):
    """Objective scatter (front highlighted); ``info[i]`` (``html``, ``image``) is shown on a click."""
    import plotly.graph_objects as go

    x, y = np.asarray(x, float), np.asarray(y, float)
    front = np.zeros(len(x), bool) if on_front is None else np.asarray(on_front, bool)
    fig = go.Figure()
    for mask, name, size in ((~front, "other designs", 6), (front, "Pareto front", 10)):
        idx = np.flatnonzero(mask)
        if idx.size:
            fig.add_trace(
                go.Scatter(
                    x=x[idx],
                    y=y[idx],
                    mode="markers",
                    name=name,
                    marker={"size": size},
                    customdata=idx.tolist(),
                    text=[info[i].get("label", "") for i in idx],
                    hovertemplate="%{text}<extra></extra>",
                )
            )
    fig.update_layout(
        xaxis_title=xlabel, yaxis_title=ylabel, height=460, margin={"t": 30}, hovermode="closest"
    )
    return fig


def click_panel(div_id: str, info: Sequence[dict]) -> str:
    """A panel beside chart ``div_id`` that shows ``info[customdata]`` (HTML and picture) on a click."""
    data = json.dumps([{"html": i.get("html", ""), "image": i.get("image", "")} for i in info])
    panel = f"{div_id}-panel"
    return (
        f'<div id="{panel}" class="panel">Click a point to see its design.</div>'
        f"<script>(function(){{var info={data};var el=document.getElementById('{div_id}');"
        f"el.on('plotly_click',function(ev){{var i=ev.points[0].customdata;var d=info[i];"
        f"var p=document.getElementById('{panel}');p.innerHTML=d.html+(d.image?"
        f"'<img alt=\"section\" src=\"'+d.image+'\">':'');p.dataset.shown=i;}});}})();</script>"
    )
