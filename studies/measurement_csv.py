"""Measurement tables (``ARCHITECTURE.md`` CSV schema) for the missing-effect workflow.

Files are read by ``analytic.io.read_measurement_csv``; this module validates
in-memory tables the same way and writes tables (for the hidden-effect
generator).

Required columns: ``time_s``, ``pressure_MPa``, ``curvature_per_mm``; optional
``arc_length_mm``, ``tip_x_mm``, ``tip_y_mm``, ``bend_angle_rad``, ``run``.
Extra columns are kept. Rows with a missing or non-numeric required value are
reported with their count and first line numbers (the header is line 1),
never silently used; time must increase within each run.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import pandas as pd

from design.errors import DataError

__all__ = [
    "REQUIRED",
    "OPTIONAL",
    "measurement_to_table",
    "read_measurement_csv",
    "validate_table",
    "write_measurement_csv",
]

log = logging.getLogger(__name__)

REQUIRED = ("time_s", "pressure_MPa", "curvature_per_mm")
OPTIONAL = ("arc_length_mm", "tip_x_mm", "tip_y_mm", "bend_angle_rad", "run")


def validate_table(df: pd.DataFrame, *, source: str = "table") -> pd.DataFrame:
    """Check a measurement table; return it with numeric required columns and a ``run``.

    Raises
    ------
    DataError
        A required column is absent, a required value is missing or not a number
        (count and first line numbers given), time does not increase within a run,
        or the table is empty.
    """
    missing_cols = [c for c in REQUIRED if c not in df.columns]
    if missing_cols:
        raise DataError(f"{source}: missing required column(s) {missing_cols}; required are {list(REQUIRED)}")
    if len(df) == 0:
        raise DataError(f"{source}: no data rows")
    out = df.copy()
    bad = np.zeros(len(out), dtype=bool)
    for c in REQUIRED:
        v = pd.to_numeric(out[c], errors="coerce")
        bad |= ~np.isfinite(v.to_numpy(dtype=float))
        out[c] = v
    if bad.any():
        lines = (np.flatnonzero(bad) + 2)[:5]  # +1 for the header, +1 for 1-based lines
        raise DataError(
            f"{source}: {int(bad.sum())} row(s) with a missing or non-numeric required value "
            f"({', '.join(REQUIRED)}), first at line(s) {', '.join(map(str, lines))}"
        )
    if "run" not in out.columns:
        out["run"] = "run1"
    out["run"] = out["run"].fillna("").astype(str)
    for run, g in out.groupby("run", sort=False):
        dt = np.diff(g["time_s"].to_numpy())
        if np.any(dt <= 0):
            first = int(g.index[np.flatnonzero(dt <= 0)[0] + 1]) + 2
            raise DataError(f"{source}: time_s must increase within run {run!r}; it does not at line {first}")
    return out


def measurement_to_table(m) -> pd.DataFrame:
    """An ``analytic.io.Measurement`` as a table (``run`` = "run1" when absent)."""
    cols = {
        "time_s": m.time_s,
        "pressure_MPa": m.pressure_MPa,
        "curvature_per_mm": m.curvature_per_mm,
        **m.optional,
    }
    df = pd.DataFrame(cols)
    run = m.run if m.run is not None else np.full(len(m), "")
    df["run"] = np.where(np.asarray(run, dtype=str) == "", "run1", run)
    return validate_table(df, source=m.source)


def read_measurement_csv(path: str | Path) -> pd.DataFrame:
    """Read and validate a measurement CSV with the project's reader, as a table.

    The file is read by ``analytic.io.read_measurement_csv`` (the one reader of
    the project: missing required values are an error with count and first line;
    time must increase through the file), then checked per run here.
    """
    from analytic.io import read_measurement_csv as _read

    return measurement_to_table(_read(path))


def write_measurement_csv(df: pd.DataFrame, path: str | Path) -> Path:
    """Write a measurement table (validated first) as CSV; returns the path."""
    validate_table(df, source="table to write")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(path, index=False, float_format="%.9g")
    return path
