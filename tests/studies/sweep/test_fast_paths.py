"""The sweep's fast paths equal the straightforward computations they replace."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pyarrow as pa
import pytest

from softcath.studies.sweep import build_tasks, evaluate_task, expand, load_spec
from softcath.studies.sweep.results import _stringify_objects
from softcath.studies.sweep.store import arrow_table, design_counts


@pytest.fixture(scope="module")
def task_frame(tmp_path_factory):
    """The rows of one analytic task: 12 designs, 2 of them invalid (a failed status and a reason)."""
    root = tmp_path_factory.mktemp("fast_paths")
    (root / "spec.toml").write_text(
        """
[sweep]
name = "fast"
base = "paper"
pressures_MPa = [0.0, 0.5, 1.0]
loads = ["cap", "lumen"]
evaluators = ["paper"]
[parameters]
"tube.h" = { values = [0.0, 0.03, 0.06] }
"tip.bending_length" = { lhs = [10.0, 20.0] }
[sample]
n = 4
""",
        encoding="utf-8",
    )
    spec = load_spec(root / "spec.toml")
    tasks = build_tasks(spec, expand(spec))
    return pd.concat([evaluate_task(t) for t in tasks], ignore_index=True)


def _variants(frame: pd.DataFrame) -> list[pd.DataFrame]:
    """The task's frame, and copies with swept columns of names, mixed numbers and ints."""
    names = frame.copy()
    names["tube.h"] = np.array(["a", 1.0] * (len(frame) // 2), dtype=object)
    ints = frame.copy()
    ints["tube.h"] = np.array([1, 2.5] * (len(frame) // 2), dtype=object)
    empty = frame.iloc[:0].copy()
    return [frame, names, ints, empty]


def test_arrow_table_equals_from_pandas_of_the_stringified_frame(task_frame):
    assert task_frame["tube.h"].dtype == object and (task_frame.status == "failed").any()
    for frame in _variants(task_frame):
        fast = arrow_table(frame)
        ref = pa.Table.from_pandas(_stringify_objects(frame), preserve_index=False)
        assert fast.equals(ref)  # types, values and nulls (NaN → null); not the pandas metadata
        pd.testing.assert_frame_equal(fast.to_pandas(), ref.to_pandas(), check_exact=True)


def test_design_counts_equal_the_pandas_counts(task_frame):
    for frame in (task_frame, task_frame.iloc[::-1], task_frame.iloc[:0]):
        failed = int((frame.drop_duplicates("design_id")["status"] == "failed").sum())
        assert design_counts(frame) == (frame["design_id"].nunique(), failed)
    assert design_counts(task_frame) == (12, 4)  # h = 0.06 is invalid at each of the 4 samples


def _section_columns_one_by_one(items, pressures, loads):
    """The section evaluator's columns computed per design from ``SectionResult.response``."""
    out = []
    for item in items:
        if isinstance(item, Exception):
            out.append(item)
            continue
        r, cols = item.result, {}
        for load in loads:
            resp = r.response(pressures, load)
            low, high = item.strain_range[load]
            cols[load] = {
                "curvature_section_per_mm": resp.curvature,
                "elongation_section": resp.elongation,
                "bend_angle_section_rad": resp.bend_angle,
                "tip_x_section_mm": resp.tip_x,
                "tip_y_section_mm": resp.tip_y,
                "max_strain_section": np.where(pressures >= 0, pressures * high, pressures * low),
                "section_formula_ratio": np.full(pressures.shape, r.fem_formula_ratio[load]),
                "section_seconds": np.full(pressures.shape, r.seconds),
            }
        out.append(cols)
    return out


def test_section_blocks_equal_the_response_of_each_design(monkeypatch):
    from dataclasses import replace

    from softcath.fem.section_model import batch
    from softcath.models.section_eval import SECTION_KEYS, section_blocks_many
    from softcath.studies.sweep.random_designs import random_designs

    designs = random_designs(3, seed=4)
    # a valid design beyond the section model's Poisson ratio: a failure in the middle of the batch
    tube = designs[1].tube
    designs.insert(
        1, replace(designs[1], tube=replace(tube, material=replace(tube.material, poisson_ratio=0.4999999)))
    )
    pressures, loads = np.array([0.0, 0.5, 1.0, 0.25]), ("cap", "lumen")
    items = batch.section_models(designs, loads=loads)
    monkeypatch.setattr(batch, "section_models", lambda *a, **k: items)  # the same solves for both
    cols, errors = section_blocks_many(designs, pressures, loads)
    ref = _section_columns_one_by_one(items, pressures, loads)
    assert list(errors) == [1] and str(errors[1]) == str(ref[1])
    for load in loads:
        assert list(cols[load]) == list(SECTION_KEYS)
        for k in SECTION_KEYS:
            assert np.isnan(cols[load][k][1]).all()
            for j in (0, 2, 3):
                # the same elementwise operations on arrays: equal to round-off
                np.testing.assert_allclose(cols[load][k][j], ref[j][load][k], rtol=1e-14, atol=1e-300)


def test_task_frame_equals_the_pandas_concat_rename_and_sort(tmp_path, monkeypatch):
    """One frame in np.lexsort order = a frame per load, concatenated, renamed and stably sorted."""
    from softcath.studies.sweep import evaluators
    from softcath.studies.sweep.results import _FEM_RENAME

    spec = tmp_path / "spec.toml"
    spec.write_text(
        """
[sweep]
name = "order"
base = "paper"
pressures_MPa = [0.0, 0.5, 1.0]
loads = ["lumen", "cap"]
evaluators = ["paper"]
[parameters]
"tube.h" = { values = [0.06, 0.0, 0.03] }
""",
        encoding="utf-8",
    )
    seen = []
    real = evaluators._sorted_columns
    monkeypatch.setattr(
        evaluators, "_sorted_columns", lambda per_load: seen.append(per_load) or real(per_load)
    )
    s = load_spec(spec)
    task = build_tasks(s, expand(s))[0]
    # unsorted and repeated pressures (a spec sorts them; a task need not): the stable order matters
    fast = evaluate_task(dict(task, pressures_MPa=[1.0, 0.0, 0.5, 0.5], loads=["lumen", "cap"]))
    frames = [pd.DataFrame(cols) for cols in seen[0]]
    ref = (
        pd.concat(frames, ignore_index=True)
        .rename(columns=_FEM_RENAME)
        .sort_values(["design_id", "load", "pressure_MPa"], kind="stable", ignore_index=True)
    )
    pd.testing.assert_frame_equal(fast, ref, check_exact=True)
    assert (fast.status == "failed").sum() == 8  # h = 0.06: 2 loads x 4 pressures
