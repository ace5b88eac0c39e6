"""The CSV number format every result table shares (ten significant digits, text as given)."""

from __future__ import annotations

import csv
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np

__all__ = ["cell", "range_text", "write_rows"]


def cell(value) -> str:
    """One table cell: a number to ten significant digits, text unchanged."""
    return value if isinstance(value, str) else f"{value:.10g}"


def write_rows(path: str | Path, header: Sequence[str], rows: Iterable[Sequence]) -> None:
    """Write ``header`` and ``rows`` (each cell through :func:`cell`) to the CSV file ``path``."""
    with Path(path).open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(list(header))
        for row in rows:
            w.writerow([cell(v) for v in row])


def range_text(pressures) -> str:
    """A table's pressures as a refusal names them: their range and count."""
    p = np.asarray(pressures, dtype=float)
    return f"{p.min():g}:{p.max():g} ({p.size} pressures)" if p.size else "(none)"
