"""The sweep results table: column names and units, derived columns, reading and writing.

One row per design × pressure × load. Columns (unit in the name or below):

- ``design_id``, ``task_id``; every swept parameter under its dotted path
  (e.g. ``tube.a`` in mm, ``materials.ecoflex_00_30.youngs_modulus`` in MPa);
- ``outer_diameter_mm``, ``bending_length_mm``, ``catalogue_fits``;
- ``pressure_MPa``, ``at_p_max``, ``load`` (``cap``/``lumen``);
- analytic: ``curvature_analytic_per_mm``, ``elongation_analytic`` [-],
  ``bend_angle_analytic_rad``/``_deg``, ``tip_x_analytic_mm``, ``tip_y_analytic_mm``,
  ``max_strain_analytic`` [-] (Euler–Bernoulli strain at the tube's outer fibres);
- section model (NaN when not run; evaluator ``section``): ``curvature_section_per_mm``,
  ``elongation_section``, ``bend_angle_section_rad``/``_deg``, ``tip_x_section_mm``,
  ``tip_y_section_mm``, ``max_strain_section`` (largest principal silicone strain at
  mid-span), ``section_formula_ratio`` (section κ over the paper's formula, eq. 7 cap
  load), ``section_seconds``;
- FEM (NaN when not run): ``curvature_fem_per_mm``, ``elongation_fem``,
  ``bend_angle_fem_rad``/``_deg``, ``tip_x_fem_mm``, ``tip_y_fem_mm``,
  ``max_strain_fem``, ``curvature_variation_fem``, ``fem_residual``,
  ``fem_n_elements``, ``fem_dofs``;
- ``rel_diff_curvature``, ``rel_diff_elongation``, ``rel_diff_bend_angle``:
  ``(FEM − analytic)/|analytic|`` [-]; ``abs_rel_diff_curvature``;
  ``rel_diff_fem_section_curvature``: ``(FEM − section)/|section|`` [-] (the section
  model's agreement with the 3-D FEM); ``fem_formula_ratio``: FEM κ over the
  paper's formula;
- best estimate (FEM where it ran, else the section model, else analytic; ``source``
  says which):
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

from softcath.core.atomic import write_json
from softcath.design.errors import DataError, DesignError
from softcath.models.section_eval import SECTION_KEYS
from softcath.models.section_nonlinear_eval import SECTION_NONLINEAR_KEYS
from softcath.studies.model_validity import SELF_CONTACT_DEG

__all__ = [
    "add_derived_columns",
    "has_model",
    "model_columns",
    "read_results",
    "write_results",
    "COLUMN_UNITS",
    "MODEL_COLUMNS",
    "SECTION_COLUMNS",
]

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
    "design_id": "-",
    "task_id": "-",
    "outer_diameter_mm": "mm",
    "bending_length_mm": "mm",
    "catalogue_fits": "bool",
    "pressure_MPa": "MPa",
    "at_p_max": "bool",
    "load": "cap|lumen",
    "curvature_analytic_per_mm": "1/mm",
    "elongation_analytic": "-",
    "bend_angle_analytic_rad": "rad",
    "bend_angle_analytic_deg": "deg",
    "tip_x_analytic_mm": "mm",
    "tip_y_analytic_mm": "mm",
    "max_strain_analytic": "-",
    "curvature_fem_per_mm": "1/mm",
    "elongation_fem": "-",
    "bend_angle_fem_rad": "rad",
    "bend_angle_fem_deg": "deg",
    "tip_x_fem_mm": "mm",
    "tip_y_fem_mm": "mm",
    "max_strain_fem": "-",
    "curvature_variation_fem": "-",
    "fem_residual": "-",
    "fem_n_elements": "-",
    "fem_dofs": "-",
    "rel_diff_curvature": "-",
    "rel_diff_elongation": "-",
    "rel_diff_bend_angle": "-",
    "abs_rel_diff_curvature": "-",
    "curvature_per_mm": "1/mm",
    "elongation": "-",
    "bend_angle_deg": "deg",
    "max_strain": "-",
    "bend_per_MPa_deg": "deg/MPa",
    "source": "analytic|section|fem|section-nonlinear",
    "feasible_strain": "bool",
    "feasible": "bool",
    "self_contact": "bool",
    "status": "ok|failed",
    "reason": "text",
    "analytic_seconds": "s",
    "fem_mesh_seconds": "s",
    "fem_solve_seconds": "s",
    "cpu_seconds": "s",
    "nonlinear_bend_angle_rad": "rad",
    "nonlinear_curvature_per_mm": "1/mm",
    "nonlinear_max_strain": "-",
    "curvature_section_per_mm": "1/mm",
    "elongation_section": "-",
    "bend_angle_section_rad": "rad",
    "bend_angle_section_deg": "deg",
    "tip_x_section_mm": "mm",
    "tip_y_section_mm": "mm",
    "max_strain_section": "-",
    "section_formula_ratio": "-",
    "section_seconds": "s",
    "rel_diff_fem_section_curvature": "-",
    "fem_formula_ratio": "-",
    "curvature_section_nonlinear_per_mm": "1/mm",
    "elongation_section_nonlinear": "-",
    "bend_angle_section_nonlinear_rad": "rad",
    "bend_angle_section_nonlinear_deg": "deg",
    "tip_x_section_nonlinear_mm": "mm",
    "tip_y_section_nonlinear_mm": "mm",
    "max_strain_section_nonlinear": "-",
    "lumen_volume_change_section_nonlinear_mm3": "mm^3",
    "section_nonlinear_seconds": "s",
}

#: Section-model columns; sweeps (or resumed task files) from before the section evaluator lack them.
SECTION_COLUMNS = SECTION_KEYS

#: Columns of the ``section-nonlinear`` evaluator (the finite-strain section model).
SECTION_NONLINEAR_COLUMNS = (
    "curvature_section_nonlinear_per_mm",
    "elongation_section_nonlinear",
    "bend_angle_section_nonlinear_rad",
    "tip_x_section_nonlinear_mm",
    "tip_y_section_nonlinear_mm",
    "max_strain_section_nonlinear",
    "lumen_volume_change_section_nonlinear_mm3",
    "section_nonlinear_seconds",
)

#: Tier -> its sweep columns (before the FEM renaming, :data:`_FEM_RENAME`) and where each comes
#: from in the tier's :class:`~softcath.models.ResponseBatch`: a response field, ``extras.<name>``
#: or ``seconds``. The tiers' order is the columns' order in the results (a file format).
TIER_COLUMNS: dict[str, dict[str, str]] = {
    "paper": {
        "curvature_analytic_per_mm": "curvature_per_mm",
        "elongation_analytic": "elongation",
        "bend_angle_analytic_rad": "bend_angle_rad",
        "tip_x_analytic_mm": "tip_x_mm",
        "tip_y_analytic_mm": "tip_y_mm",
        "max_strain_analytic": "max_strain",
    },
    "fem": {
        "fem_curvature_per_mm": "curvature_per_mm",
        "fem_elongation": "elongation",
        "fem_bend_angle_rad": "bend_angle_rad",
        "fem_tip_x_mm": "tip_x_mm",
        "fem_tip_y_mm": "tip_y_mm",
        "fem_curvature_variation": "extras.curvature_variation",
        "fem_max_strain": "max_strain",
        "fem_residual": "extras.residual",
        "fem_n_elements": "extras.n_elements",
        "fem_dofs": "extras.dofs",
        "fem_mesh_seconds": "extras.mesh_seconds",
        "fem_solve_seconds": "extras.solve_seconds",
    },
    "fem-nonlinear": {
        "nonlinear_bend_angle_rad": "bend_angle_rad",
        "nonlinear_curvature_per_mm": "tip_curvature_per_mm",
        "nonlinear_max_strain": "max_strain",
    },
    "section": {
        "curvature_section_per_mm": "curvature_per_mm",
        "elongation_section": "elongation",
        "bend_angle_section_rad": "bend_angle_rad",
        "tip_x_section_mm": "tip_x_mm",
        "tip_y_section_mm": "tip_y_mm",
        "max_strain_section": "max_strain",
        "section_formula_ratio": "extras.section_formula_ratio",
        "section_seconds": "seconds",
    },
    "section-nonlinear": {**SECTION_NONLINEAR_KEYS, "section_nonlinear_seconds": "seconds"},
}

#: Model -> its columns for the best-estimate quantities (see :func:`model_columns`).
MODEL_COLUMNS = {
    "paper": {
        "curvature_per_mm": "curvature_analytic_per_mm",
        "elongation": "elongation_analytic",
        "bend_angle_deg": "bend_angle_analytic_deg",
        "max_strain": "max_strain_analytic",
    },
    "section": {
        "curvature_per_mm": "curvature_section_per_mm",
        "elongation": "elongation_section",
        "bend_angle_deg": "bend_angle_section_deg",
        "max_strain": "max_strain_section",
    },
    "fem": {
        "curvature_per_mm": "curvature_fem_per_mm",
        "elongation": "elongation_fem",
        "bend_angle_deg": "bend_angle_fem_deg",
        "max_strain": "max_strain_fem",
    },
    "section-nonlinear": {
        "curvature_per_mm": "curvature_section_nonlinear_per_mm",
        "elongation": "elongation_section_nonlinear",
        "bend_angle_deg": "bend_angle_section_nonlinear_deg",
        "max_strain": "max_strain_section_nonlinear",
    },
}


def _rel(fem: np.ndarray, ana: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(np.abs(ana) > 0, (fem - ana) / np.abs(ana), np.nan)


def add_derived_columns(df, *, max_strain: float, p_max: float):
    """Add degrees, relative differences, best estimates and feasibility flags; returns the new frame."""
    df = df.rename(columns=_FEM_RENAME)
    for c in (*SECTION_COLUMNS, *SECTION_NONLINEAR_COLUMNS):
        if c not in df.columns:
            df[c] = np.nan
    df["at_p_max"] = np.isclose(df["pressure_MPa"].to_numpy(float), p_max, rtol=1e-12, atol=0.0)
    df["bend_angle_analytic_deg"] = np.degrees(df["bend_angle_analytic_rad"].to_numpy(float))
    df["bend_angle_fem_deg"] = np.degrees(df["bend_angle_fem_rad"].to_numpy(float))
    df["bend_angle_section_deg"] = np.degrees(df["bend_angle_section_rad"].to_numpy(float))
    df["bend_angle_section_nonlinear_deg"] = np.degrees(
        df["bend_angle_section_nonlinear_rad"].to_numpy(float)
    )
    for name, ana, fem in (
        ("curvature", "curvature_analytic_per_mm", "curvature_fem_per_mm"),
        ("elongation", "elongation_analytic", "elongation_fem"),
        ("bend_angle", "bend_angle_analytic_rad", "bend_angle_fem_rad"),
    ):
        df[f"rel_diff_{name}"] = _rel(df[fem].to_numpy(float), df[ana].to_numpy(float))
    df["abs_rel_diff_curvature"] = np.abs(df["rel_diff_curvature"].to_numpy(float))
    fem_k = df["curvature_fem_per_mm"].to_numpy(float)
    df["rel_diff_fem_section_curvature"] = _rel(fem_k, df["curvature_section_per_mm"].to_numpy(float))
    df["fem_formula_ratio"] = _over_formula(df, fem_k)
    has_fem, has_sec = np.isfinite(fem_k), np.isfinite(df["curvature_section_per_mm"].to_numpy(float))
    has_sn = np.isfinite(df["curvature_section_nonlinear_per_mm"].to_numpy(float))
    df["source"] = np.where(
        has_sn, "section-nonlinear", np.where(has_fem, "fem", np.where(has_sec, "section", "analytic"))
    )
    for best in MODEL_COLUMNS["paper"]:
        value = df[MODEL_COLUMNS["paper"][best]].to_numpy(float)
        # later models win where they ran: the finite-strain section model is the one valid at large bends
        for model in ("section", "fem", "section-nonlinear"):
            v = df[MODEL_COLUMNS[model][best]].to_numpy(float)
            value = np.where(np.isfinite(v), v, value)
        df[best] = value
    _bend_per_mpa(df)
    ok = (df["status"] == "ok").to_numpy()
    strain = df["max_strain"].to_numpy(float)
    df["feasible_strain"] = ok & (strain <= max_strain)
    # past a full turn the tip passes through itself: no tier models that, so the row is flagged
    with np.errstate(invalid="ignore"):
        df["self_contact"] = np.abs(df["bend_angle_deg"].to_numpy(float)) > SELF_CONTACT_DEG
    df["feasible"] = df["feasible_strain"] & ~df["self_contact"]
    return df


def _bend_per_mpa(df) -> None:
    p = df["pressure_MPa"].to_numpy(float)
    with np.errstate(divide="ignore", invalid="ignore"):
        df["bend_per_MPa_deg"] = np.where(p > 0, df["bend_angle_deg"].to_numpy(float) / p, np.nan)


def _over_formula(df, kappa: np.ndarray) -> np.ndarray:
    """``kappa`` over the paper's formula (the analytic cap-load curvature of the same design and
    pressure)."""
    import pandas as pd

    cap = df[df["load"] == "cap"]
    if cap.empty:
        return np.full(len(df), np.nan)
    formula = pd.Series(
        cap["curvature_analytic_per_mm"].to_numpy(float),
        index=pd.MultiIndex.from_arrays([cap["design_id"].to_numpy(), cap["pressure_MPa"].to_numpy(float)]),
    )
    idx = pd.MultiIndex.from_arrays([df["design_id"].to_numpy(), df["pressure_MPa"].to_numpy(float)])
    ref = formula.reindex(idx).to_numpy(float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(np.abs(ref) > 0, kappa / ref, np.nan)


def has_model(df, model: str) -> bool:
    """Whether the results hold any value of ``model`` (``paper``, ``section`` or ``fem``)."""
    col = MODEL_COLUMNS[model]["curvature_per_mm"]
    return col in df.columns and bool(np.isfinite(df[col].to_numpy(float)).any())


#: The ``source`` of a tier's rows where it is not the tier's name (a file format kept from before).
_SOURCE = {"paper": "analytic"}


def model_columns(df, model: str):
    """A copy of ``df`` whose best-estimate columns come from one model.

    ``curvature_per_mm``, ``elongation``, ``bend_angle_deg``, ``max_strain`` and
    ``bend_per_MPa_deg`` are set from ``model``'s own columns (``paper``: the
    analytic model, ``section``: the section model, ``fem``: the 3-D FEM); rows
    without that model's value become NaN (so a selection skips them), and
    ``source`` names the model.
    """

    if model not in MODEL_COLUMNS:
        raise DesignError("model", model, f"must be one of {', '.join(MODEL_COLUMNS)}")
    df = df.copy()
    for best, col in MODEL_COLUMNS[model].items():
        if (
            col == "bend_angle_section_deg"
            and col not in df.columns
            and "bend_angle_section_rad" in df.columns
        ):
            df[col] = np.degrees(df["bend_angle_section_rad"].to_numpy(float))
        df[best] = df[col].to_numpy(float) if col in df.columns else np.nan
    _bend_per_mpa(df)
    df["source"] = _SOURCE.get(model, model)
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
