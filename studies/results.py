"""The sweep results table: column names and units, derived columns, reading and writing.

One row per design × pressure × load. Columns (unit in the name or below):

- ``design_id``, ``task_id``; every swept parameter under its dotted path
  (e.g. ``tube.a`` in mm, ``materials.ecoflex_00_30.youngs_modulus`` in MPa);
- ``outer_diameter_mm``, ``bending_length_mm``, ``catalogue_fits``;
- ``pressure_MPa``, ``at_p_max``, ``load`` (``cap``/``lumen``);
- analytic: ``curvature_analytic_per_mm``, ``elongation_analytic`` [-],
  ``bend_angle_analytic_rad``/``_deg``, ``tip_x_analytic_mm``, ``tip_y_analytic_mm``,
  ``max_strain_analytic`` [-] (Euler–Bernoulli strain at the tube's outer fibres);
- FEM (NaN when not run): ``curvature_fem_per_mm``, ``elongation_fem``,
  ``bend_angle_fem_rad``/``_deg``, ``tip_x_fem_mm``, ``tip_y_fem_mm``,
  ``max_strain_fem``, ``curvature_variation_fem``, ``fem_residual``,
  ``fem_n_elements``, ``fem_dofs``;
- ``rel_diff_curvature``, ``rel_diff_elongation``, ``rel_diff_bend_angle``:
  (FEM − analytic)/|analytic| [-]; ``abs_rel_diff_curvature``;
- best estimate (FEM where it ran, else analytic; ``source`` says which):
  ``curvature_per_mm``, ``elongation``, ``bend_angle_deg``, ``max_strain``,
  ``bend_per_MPa_deg`` [deg/MPa];
- ``feasible_strain`` (max_strain ≤ the spec's limit), ``feasible``;
- ``status`` (``ok``/``failed``), ``reason``;
- ``analytic_seconds``, ``fem_mesh_seconds``, ``fem_solve_seconds``, and
  ``cpu_seconds`` (the evaluating process's CPU time per design) [s].
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from design.errors import DataError
from studies.atomic import write_json

__all__ = ["add_derived_columns", "read_results", "write_results", "COLUMN_UNITS"]

_FEM_RENAME = {
    "fem_curvature_per_mm": "curvature_fem_per_mm",
    "fem_elongation": "elongation_fem",
    "fem_bend_angle_rad": "bend_angle_fem_rad",
    "fem_tip_x_mm": "tip_x_fem_mm",
    "fem_tip_y_mm": "tip_y_fem_mm",
    "fem_max_strain": "max_strain_fem",
    "fem_curvature_variation": "curvature_variation_fem",
}

COLUMN_UNITS = {
    "design_id": "-", "task_id": "-", "outer_diameter_mm": "mm", "bending_length_mm": "mm",
    "catalogue_fits": "bool", "pressure_MPa": "MPa", "at_p_max": "bool", "load": "cap|lumen",
    "curvature_analytic_per_mm": "1/mm", "elongation_analytic": "-", "bend_angle_analytic_rad": "rad",
    "bend_angle_analytic_deg": "deg", "tip_x_analytic_mm": "mm", "tip_y_analytic_mm": "mm",
    "max_strain_analytic": "-", "curvature_fem_per_mm": "1/mm", "elongation_fem": "-",
    "bend_angle_fem_rad": "rad", "bend_angle_fem_deg": "deg", "tip_x_fem_mm": "mm", "tip_y_fem_mm": "mm",
    "max_strain_fem": "-", "curvature_variation_fem": "-", "fem_residual": "-", "fem_n_elements": "-",
    "fem_dofs": "-", "rel_diff_curvature": "-", "rel_diff_elongation": "-", "rel_diff_bend_angle": "-",
    "abs_rel_diff_curvature": "-", "curvature_per_mm": "1/mm", "elongation": "-", "bend_angle_deg": "deg",
    "max_strain": "-", "bend_per_MPa_deg": "deg/MPa", "source": "analytic|fem", "feasible_strain": "bool",
    "feasible": "bool", "status": "ok|failed", "reason": "text", "analytic_seconds": "s",
    "fem_mesh_seconds": "s", "fem_solve_seconds": "s", "cpu_seconds": "s",
    "nonlinear_bend_angle_rad": "rad", "nonlinear_curvature_per_mm": "1/mm", "nonlinear_max_strain": "-",
}  # fmt: skip


def _rel(fem: np.ndarray, ana: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(np.abs(ana) > 0, (fem - ana) / np.abs(ana), np.nan)


def add_derived_columns(df, *, max_strain: float, p_max: float):
    """Add degrees, relative differences, best estimates and feasibility flags; returns the new frame."""
    df = df.rename(columns=_FEM_RENAME)
    df["at_p_max"] = np.isclose(df["pressure_MPa"].to_numpy(float), p_max, rtol=1e-12, atol=0.0)
    df["bend_angle_analytic_deg"] = np.degrees(df["bend_angle_analytic_rad"].to_numpy(float))
    df["bend_angle_fem_deg"] = np.degrees(df["bend_angle_fem_rad"].to_numpy(float))
    for name, ana, fem in (
        ("curvature", "curvature_analytic_per_mm", "curvature_fem_per_mm"),
        ("elongation", "elongation_analytic", "elongation_fem"),
        ("bend_angle", "bend_angle_analytic_rad", "bend_angle_fem_rad"),
    ):
        df[f"rel_diff_{name}"] = _rel(df[fem].to_numpy(float), df[ana].to_numpy(float))
    df["abs_rel_diff_curvature"] = np.abs(df["rel_diff_curvature"].to_numpy(float))
    has_fem = np.isfinite(df["curvature_fem_per_mm"].to_numpy(float))
    df["source"] = np.where(has_fem, "fem", "analytic")
    for best, ana, fem in (
        ("curvature_per_mm", "curvature_analytic_per_mm", "curvature_fem_per_mm"),
        ("elongation", "elongation_analytic", "elongation_fem"),
        ("bend_angle_deg", "bend_angle_analytic_deg", "bend_angle_fem_deg"),
        ("max_strain", "max_strain_analytic", "max_strain_fem"),
    ):
        f = df[fem].to_numpy(float)
        df[best] = np.where(np.isfinite(f), f, df[ana].to_numpy(float))
    p = df["pressure_MPa"].to_numpy(float)
    with np.errstate(divide="ignore", invalid="ignore"):
        df["bend_per_MPa_deg"] = np.where(p > 0, df["bend_angle_deg"].to_numpy(float) / p, np.nan)
    ok = (df["status"] == "ok").to_numpy()
    strain = df["max_strain"].to_numpy(float)
    df["feasible_strain"] = ok & (strain <= max_strain)
    df["feasible"] = df["feasible_strain"]
    return df


def write_results(df, out_dir: str | Path) -> tuple[Path, Path]:
    """Write ``results.parquet`` and ``results.csv`` (each atomically) and ``columns.json`` (units)."""
    from concurrent.futures import ThreadPoolExecutor

    import pyarrow as pa
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    out = Path(out_dir)
    table = pa.Table.from_pandas(_stringify_objects(df), preserve_index=False)
    pq_path, csv_path = out / "results.parquet", out / "results.csv"

    def atomic(writer, path: Path) -> None:
        tmp = out / f".{path.name}.tmp"
        writer(table, tmp)
        os.replace(tmp, path)

    # Both writers release the GIL: write the two files at once.
    with ThreadPoolExecutor(2) as pool:
        jobs = [pool.submit(atomic, pq.write_table, pq_path), pool.submit(atomic, pacsv.write_csv, csv_path)]
        for job in jobs:
            job.result()
    units = {c: COLUMN_UNITS.get(c, "see the design file (mm, MPa)") for c in df.columns}
    write_json(out / "columns.json", units, indent=1)
    return csv_path, pq_path


_TEXT_COLUMNS = ("load", "status", "reason", "source")


def _stringify_objects(df):
    """Object columns (swept values may mix numbers and names) become numbers if they all are, else text."""
    import pandas as pd

    todo = [c for c in df.columns if df[c].dtype == object and c not in _TEXT_COLUMNS]
    if not todo:
        return df
    df = df.copy(deep=False)
    for c in todo:
        num = pd.to_numeric(df[c], errors="coerce")
        if num.notna().sum() == df[c].notna().sum():
            df[c] = num
        else:
            df[c] = df[c].astype(str)
    return df


def read_results(out_dir: str | Path):
    """The results table of a finished sweep directory (``results.parquet``, else ``results.csv``)."""
    import pandas as pd

    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise DataError(f"{out}: is a file; give the sweep directory (from `softcath sweep`)")
    fix = (
        "rerun the same `softcath sweep SPEC --out DIR` command: it keeps every finished task "
        "and rewrites the merged results"
    )
    if (out / "results.parquet").is_file():
        try:
            return pd.read_parquet(out / "results.parquet")
        except Exception as exc:  # pyarrow raises several types for a damaged file
            raise DataError(f"{out / 'results.parquet'}: cannot be read ({_brief(exc)}); {fix}") from None
    if (out / "results.csv").is_file():
        try:
            df = pd.read_csv(out / "results.csv")
        except Exception as exc:
            raise DataError(f"{out / 'results.csv'}: cannot be read ({_brief(exc)}); {fix}") from None
        return df.assign(reason=df["reason"].fillna("")) if "reason" in df else df
    raise DataError(f"{out}: no results.parquet or results.csv (run `softcath sweep SPEC --out {out}` first)")


def _brief(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text[:160]}"
