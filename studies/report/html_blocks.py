"""Small helpers for static, offline HTML pages (no scripts, no external assets)."""

from __future__ import annotations

import html
import math
from collections.abc import Iterable, Sequence

__all__ = ["esc", "table", "figure", "page", "note", "fmt"]

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;max-width:1100px;margin:2em auto;
padding:0 1em;color:#222;line-height:1.45}
h1{font-size:1.7em;margin-bottom:.2em} h2{margin-top:2em;border-bottom:1px solid #ddd;padding-bottom:.2em}
table{border-collapse:collapse;margin:.8em 0;font-size:.9em}
td,th{border:1px solid #ccc;padding:.25em .6em;text-align:right}
th{background:#f3f3f3} td.l,th.l{text-align:left} figure{margin:1em 0}
img{max-width:100%;border:1px solid #eee}
figcaption{font-size:.9em;color:#555} .note{background:#fff8e1;border-left:4px solid #f0b400;padding:.5em 1em}
.ok{color:#1a7f37} .bad{color:#b42318} code{background:#f5f5f5;padding:0 .2em}
"""


def esc(text: object) -> str:
    return html.escape(str(text))


def fmt(v: object, digits: int = 4) -> str:
    """A number for a table: 4 significant digits, '—' for missing."""
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, (int,)) and not isinstance(v, bool):
        return str(v)
    try:
        x = float(v)
    except (TypeError, ValueError):
        return esc(v)
    if not math.isfinite(x):
        return "—"
    return f"{x:.{digits}g}"


def table(header: Sequence[str], rows: Iterable[Sequence[object]], *, left: int = 0) -> str:
    """An HTML table; the first ``left`` columns are left-aligned text."""
    cls = lambda i: ' class="l"' if i < left else ""  # noqa: E731
    head = "".join(f"<th{cls(i)}>{esc(h)}</th>" for i, h in enumerate(header))
    body = "".join(
        "<tr>"
        + "".join(f"<td{cls(i)}>{c if isinstance(c, Markup) else fmt(c)}</td>" for i, c in enumerate(r))
        + "</tr>"
        for r in rows
    )
    return f"<table><tr>{head}</tr>{body}</table>"


class Markup(str):
    """Text already in HTML (not escaped again by :func:`table`)."""


def figure(src: str, caption: str, *, alt: str = "") -> str:
    return (
        f'<figure><img src="{esc(src)}" alt="{esc(alt or caption)}">'
        f"<figcaption>{caption}</figcaption></figure>"
    )


def note(text: str) -> str:
    return f'<p class="note">{text}</p>'


def page(title: str, body: str, *, subtitle: str = "") -> str:
    sub = f"<p>{subtitle}</p>" if subtitle else ""
    return (
        "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
        f"<meta name='viewport' content='width=device-width,initial-scale=1'><title>{esc(title)}</title>"
        f"<style>{_CSS}</style></head><body><h1>{esc(title)}</h1>{sub}{body}</body></html>\n"
    )
