"""Running sweeps: results against the analytic model, invalid designs, backends, resume."""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pandas as pd
import pytest

from softcath import analytic, design
from softcath.cli.main import main
from softcath.design.errors import DataError
from softcath.studies.sweep import (
    FEM_UNAVAILABLE,
    SweepStore,
    build_tasks,
    evaluate_task,
    expand,
    fem_check_function,
    load_spec,
    run_sweep,
    variant_table,
)
from softcath.studies.sweep.results import add_derived_columns

# Columns that legitimately differ between two runs of the same sweep.
_RUN_DEPENDENT = ["analytic_seconds", "cpu_seconds", "task_id", "fem_mesh_seconds", "fem_solve_seconds"]


def _values(df: pd.DataFrame) -> pd.DataFrame:
    df = df.assign(reason=df["reason"].fillna(""))  # CSV reads an empty reason as NaN
    return df.drop(columns=_RUN_DEPENDENT).sort_values(
        ["design_id", "load", "pressure_MPa"], ignore_index=True
    )


def test_results_match_analytic_model_and_report_invalid(small_spec, tmp_path):
    spec = load_spec(small_spec)
    s = run_sweep(spec, tmp_path / "out", workers=1, progress=False)
    assert (s.n_designs, s.ok_designs, s.failed_designs) == (12, 10, 2)
    df = pd.read_csv(s.results_csv)
    assert len(df) == 12 * 3 * 2  # design × pressure × load
    failed = df[df.status == "failed"]
    assert set(failed["tube.h"].abs()) == {0.06}
    assert failed.reason.str.contains(r"tube\.h = .*0\.06: \|h\| must be <= b - min_wall - b_int").all()
    assert failed.curvature_analytic_per_mm.isna().all()
    variants = expand(spec)
    for did in (1, 5, 9):
        d = design.from_dict(variant_table(spec.base_table, variants[did]))
        sec = analytic.composite_section(d)
        for load in ("cap", "lumen"):
            r = analytic.response(d, np.array(spec.pressures), load=load)
            rows = df[(df.design_id == did) & (df.load == load)].sort_values("pressure_MPa")
            # Same formulas through a vectorised path: equal up to float rounding (1e-12 relative);
            # the CSV round-trip keeps 17 significant digits.
            np.testing.assert_allclose(rows.curvature_analytic_per_mm, r.curvature, rtol=1e-12, atol=0)
            np.testing.assert_allclose(rows.elongation_analytic, r.elongation, rtol=1e-12, atol=0)
            np.testing.assert_allclose(rows.bend_angle_analytic_deg, np.degrees(r.bend_angle), rtol=1e-12)
            np.testing.assert_allclose(rows.tip_x_analytic_mm, r.tip_x, rtol=1e-12, atol=1e-15)
            # Beam strain ε + κ(y − ȳ) at the tube's outer fibres y_t ± b, from the section peer.
            y = np.array([d.section.tube_center_y + d.section.b, d.section.tube_center_y - d.section.b])
            fibre = r.elongation[:, None] + r.curvature[:, None] * (y[None, :] - sec.neutral_axis_y)
            np.testing.assert_allclose(
                rows.max_strain_analytic, np.abs(fibre).max(axis=1), rtol=1e-12, atol=0
            )
    ok = df[df.status == "ok"]
    assert (ok.at_p_max == np.isclose(ok.pressure_MPa, 1.0)).all()
    pos = ok[ok.pressure_MPa > 0]
    np.testing.assert_allclose(
        pos.bend_per_MPa_deg, pos.bend_angle_analytic_deg / pos.pressure_MPa, rtol=1e-12
    )
    assert (ok.source == "analytic").all() and ok.curvature_fem_per_mm.isna().all()
    pq = pd.read_parquet(s.results_parquet)
    pd.testing.assert_frame_equal(_values(pq), _values(df), check_dtype=False)
    units = json.loads((tmp_path / "out" / "columns.json").read_text())
    assert units["curvature_analytic_per_mm"] == "1/mm"


def test_process_pool_equals_serial_and_resume_skips_finished(small_spec, tmp_path):
    spec = load_spec(small_spec)
    serial = run_sweep(spec, tmp_path / "serial", workers=1, progress=False)
    pool = run_sweep(spec, tmp_path / "pool", workers=2, progress=False)
    assert pool.backend == "processes(2)" and pool.n_tasks == 3  # 12 designs in chunks of 5
    pd.testing.assert_frame_equal(
        _values(pd.read_parquet(serial.results_parquet)), _values(pd.read_parquet(pool.results_parquet))
    )
    # Resume: remove one finished task; a second run evaluates exactly that one.
    store = SweepStore(tmp_path / "pool")
    store.task_path(1).unlink()
    again = run_sweep(spec, tmp_path / "pool", workers=2, progress=False)
    assert (again.skipped_tasks, again.evaluated_tasks, again.evaluated_designs) == (2, 1, 5)
    runs = {}
    for e in store.events():
        runs.setdefault(e["run"], []).append(e["task"])
    assert sorted(len(v) for v in runs.values()) == [1, 3] and [1] in runs.values()
    pd.testing.assert_frame_equal(
        _values(pd.read_parquet(serial.results_parquet)), _values(pd.read_parquet(again.results_parquet))
    )


def test_other_sweep_in_same_directory_is_refused(small_spec, spec_writer, tmp_path):
    run_sweep(load_spec(small_spec), tmp_path / "out", workers=1, progress=False)
    other = spec_writer("[sweep]\npressures_MPa = [2.0]\n", "other.toml")
    with pytest.raises(DataError, match="holds a different sweep"):
        run_sweep(load_spec(other), tmp_path / "out", workers=1, progress=False)


def test_a_sweep_written_with_other_tasks_resumes_with_its_recorded_task_size(small_spec, tmp_path, caplog):
    import dataclasses
    import logging

    spec = load_spec(small_spec)  # 12 designs in tasks of 5
    first = run_sweep(spec, tmp_path / "out", workers=1, progress=False)
    store = SweepStore(tmp_path / "out")
    store.task_path(2).unlink()
    bigger = dataclasses.replace(spec, chunk_size=500)  # as if the default task size had grown
    assert bigger.fingerprint() != spec.fingerprint()
    with caplog.at_level(logging.INFO, logger="softcath.studies.sweep.runner"):
        again = run_sweep(bigger, tmp_path / "out", workers=1, progress=False)
    assert "resuming with the sweep's recorded tasks of 5 designs" in caplog.text
    counts = (again.n_tasks, again.skipped_tasks, again.evaluated_tasks, again.evaluated_designs)
    assert counts == (3, 2, 1, 2)
    pd.testing.assert_frame_equal(
        _values(pd.read_parquet(first.results_parquet)), _values(pd.read_parquet(again.results_parquet))
    )
    other_seed = dataclasses.replace(bigger, seed=spec.seed + 1)  # another sweep: still refused
    with pytest.raises(DataError, match="holds a different sweep"):
        run_sweep(other_seed, tmp_path / "out", workers=1, progress=False)


def test_cli_sweep_and_bad_options(small_spec, tmp_path, capsys):
    assert (
        main(["sweep", str(small_spec), "--out", str(tmp_path / "o"), "--workers", "1", "--no-progress"]) == 0
    )
    out = capsys.readouterr().out
    assert "12 designs (10 ok, 2 failed)" in out
    assert main(["sweep", str(small_spec), "--out", str(tmp_path / "o2"), "--workers", "0"]) == 2
    assert "--workers = 0: must be an integer in [1, 256]" in capsys.readouterr().err
    assert main(["sweep", str(small_spec), "--out", str(tmp_path / "o3"), "--scheduler", "localhost:1"]) == 2
    assert "scheduler = 'localhost:1'" in capsys.readouterr().err


def test_fem_evaluator_unavailable_is_reported(spec_writer, tmp_path):
    """Without fem.check every design fails with the stated reason; the analytic values remain."""
    if fem_check_function() is not None:
        pytest.skip("fem.check is installed: this test covers the fem-unavailable path only")
    spec = load_spec(spec_writer('[sweep]\npressures_MPa = [1.0]\nloads = ["cap"]\nevaluators = ["fem"]\n'))
    s = run_sweep(spec, tmp_path / "o", workers=1, progress=False)
    df = pd.read_csv(s.results_csv)
    assert (df.status == "failed").all() and (df.reason == FEM_UNAVAILABLE).all()
    assert np.isfinite(df.curvature_analytic_per_mm).all()
    # A report of a sweep with no valid design still renders, and says why it has no figures.
    assert main(["report", str(tmp_path / "o")]) == 0
    html = (tmp_path / "o" / "report" / "index.html").read_text()
    assert "fem evaluator unavailable" in html and "No valid design to render" in html
    assert not list((tmp_path / "o" / "report").glob("*.png"))


@pytest.mark.slow
def test_dask_local_cluster_equals_local_pool(small_spec, tmp_path):
    """A real 2-worker LocalCluster on loopback gives the same table as the local pool."""
    pytest.importorskip("distributed")
    spec = load_spec(small_spec)
    pool = run_sweep(spec, tmp_path / "pool", workers=2, progress=False)
    dask = run_sweep(spec, tmp_path / "dask", dask_local=2, progress=False)
    assert dask.backend == "dask-local(2)" and dask.evaluated_tasks == 3
    pd.testing.assert_frame_equal(
        _values(pd.read_parquet(pool.results_parquet)), _values(pd.read_parquet(dask.results_parquet))
    )
    assert math.isclose(dask.failed_designs, 2)


@pytest.mark.slow
def test_existing_scheduler_address(small_spec, tmp_path):
    """--scheduler tcp://...: a real scheduler on loopback, started outside the sweep, as on a cluster."""
    from distributed import LocalCluster

    spec = load_spec(small_spec)
    serial = run_sweep(spec, tmp_path / "serial", workers=1, progress=False)
    with LocalCluster(n_workers=2, threads_per_worker=1, host="127.0.0.1", dashboard_address=None) as cluster:
        remote = run_sweep(spec, tmp_path / "remote", scheduler=cluster.scheduler_address, progress=False)
    assert remote.backend.startswith("dask(tcp://127.0.0.1:")
    pd.testing.assert_frame_equal(
        _values(pd.read_parquet(serial.results_parquet)), _values(pd.read_parquet(remote.results_parquet))
    )


@pytest.mark.slow
def test_fem_evaluator_on_a_tiny_case(spec_writer, tmp_path):
    """The FEM adapter end to end: one coarse design, both loads, next to the analytic model."""
    if fem_check_function() is None:
        pytest.skip("fem evaluator unavailable (fem.check not importable in this build)")
    spec = load_spec(
        spec_writer(
            """
            [sweep]
            pressures_MPa = [0.5, 1.0]
            loads = ["cap", "lumen"]
            evaluators = ["analytic", "fem"]
            [sweep.fem]
            mesh_size = 0.12
            """
        )
    )
    s = run_sweep(spec, tmp_path / "o", workers=1, progress=False)
    df = pd.read_parquet(s.results_parquet)
    assert (df.status == "ok").all(), df.reason.unique()
    assert (df.source == "fem").all() and np.isfinite(df.curvature_fem_per_mm).all()
    rel = (df.curvature_fem_per_mm - df.curvature_analytic_per_mm) / df.curvature_analytic_per_mm.abs()
    np.testing.assert_allclose(df.rel_diff_curvature, rel, rtol=1e-12)
    # Linear FEM: curvature doubles with pressure (to solver tolerance, 1e-6 relative).
    for load, g in df.groupby("load"):
        k = g.sort_values("pressure_MPa").curvature_fem_per_mm.to_numpy()
        assert k[1] == pytest.approx(2 * k[0], rel=1e-6), load
    # Under the paper's cap load the FEM bends the same way as the formula (toward the channel).
    cap = df[df.load == "cap"]
    assert (np.sign(cap.curvature_fem_per_mm) == np.sign(cap.curvature_analytic_per_mm)).all()


@pytest.mark.slow
def test_sigkill_midway_resumes_without_recomputation(spec_writer, tmp_path):
    """Kill a sweep subprocess with SIGKILL mid-run; the rerun evaluates only the unfinished designs."""
    import dataclasses
    import os
    import signal
    import subprocess
    import sys
    import time
    from pathlib import Path

    n = 60
    spec_path = spec_writer(
        f"""
        [sweep]
        name = "killme"
        pressures_MPa = [0.5, 1.0]
        loads = ["cap", "lumen"]
        chunk_size = 1
        seed = 11
        [sample]
        n = {n}
        [parameters]
        "tube.h" = {{ lhs = [-0.05, 0.05] }}
        "tip.bending_length" = {{ lhs = [3.0, 7.0] }}
        """
    )
    out = tmp_path / "out"
    root = Path(__file__).resolve().parents[3]
    env = {**os.environ, "PYTHONPATH": str(root)}
    cmd = [
        sys.executable,
        "-m",
        "softcath",
        "sweep",
        str(spec_path),
        "--out",
        str(out),
        "--workers",
        "1",
        "--no-progress",
    ]
    proc = subprocess.Popen(cmd, cwd=root, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    store = SweepStore(out)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if store.tasks_dir.is_dir() and len(store.finished()) >= 10:
            break
        time.sleep(0.005)
    assert proc.poll() is None, "the sweep finished before it could be killed"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    finished = store.finished()
    assert 10 <= len(finished) < n
    first_run = {e["task"] for e in store.events()}
    assert first_run <= finished  # a task is logged only after its file is in place

    again = subprocess.run(cmd, cwd=root, env=env, capture_output=True, text=True, timeout=300)
    assert again.returncode == 0, again.stderr
    events = store.events()
    assert len({e["run"] for e in events}) == 2
    last_run = [e for e in events if e["run"] == events[-1]["run"]]
    evaluated = [e["task"] for e in last_run]
    # No recomputation: the rerun evaluated exactly the tasks without a result file, each once.
    assert sorted(evaluated) == sorted(set(range(n)) - finished)
    assert f"{len(finished)} of {n} tasks already done" in again.stdout
    df = pd.read_parquet(out / "results.parquet")
    assert sorted(df.design_id.unique()) == list(range(n)) and len(df) == n * 2 * 2
    # Complete and correct: equal to evaluating every design afresh in one task.
    spec = load_spec(spec_path)
    (task,) = build_tasks(dataclasses.replace(spec, chunk_size=n), expand(spec))
    fresh = add_derived_columns(evaluate_task(task), max_strain=spec.max_strain, p_max=spec.p_max)
    pd.testing.assert_frame_equal(_values(df), _values(fresh), check_dtype=False)


def test_material_paths_scale_exactly(spec_writer, tmp_path):
    """Doubling every modulus halves κ and ε exactly (κ = p A_p e/ΣEI, ε = p A_p/ΣEA; ȳ is unchanged)."""
    spec = load_spec(
        spec_writer(
            """
            [sweep]
            pressures_MPa = [1.0]
            loads = ["cap"]
            [parameters]
            "materials.stainless_steel_sus304.youngs_modulus" = { values = [193000.0, 386000.0] }
            "materials.medical_silicone_tubing.youngs_modulus" = { values = [2.46, 4.92] }
            "materials.ecoflex_00_30.youngs_modulus" = { values = [0.102, 0.204] }
            "filler.material" = { values = ["ecoflex_00_30", "none"] }
            """
        )
    )
    s = run_sweep(spec, tmp_path / "o", workers=1, progress=False)
    df = pd.read_csv(s.results_csv)
    assert s.ok_designs == 16 and set(df["filler.material"]) == {"ecoflex_00_30", "none"}
    for filler in ("ecoflex_00_30", "none"):
        g = df[df["filler.material"] == filler]
        lo = g[g["materials.stainless_steel_sus304.youngs_modulus"] == 193000.0].iloc[0]
        hi = g[g["materials.stainless_steel_sus304.youngs_modulus"] == 386000.0].iloc[-1]
        assert hi["materials.medical_silicone_tubing.youngs_modulus"] == 4.92
        assert hi["materials.ecoflex_00_30.youngs_modulus"] == 0.204
        # rounding only: the same sums with every term doubled
        assert hi.curvature_analytic_per_mm == pytest.approx(lo.curvature_analytic_per_mm / 2, rel=1e-12)
        assert hi.elongation_analytic == pytest.approx(lo.elongation_analytic / 2, rel=1e-12)
    # a void filler makes the section softer: more elongation at the same pressure
    base = df[
        (df["materials.stainless_steel_sus304.youngs_modulus"] == 193000.0)
        & (df["materials.medical_silicone_tubing.youngs_modulus"] == 2.46)
        & (df["materials.ecoflex_00_30.youngs_modulus"] == 0.102)
    ]
    void, filled = (base[base["filler.material"] == f].iloc[0] for f in ("none", "ecoflex_00_30"))
    assert void.elongation_analytic > filled.elongation_analytic


def test_failed_task_rows_keep_analytic_values(small_spec):
    from softcath.studies.sweep.runner import _failed_frame

    spec = load_spec(small_spec)
    task = build_tasks(spec, expand(spec))[0]
    frame = _failed_frame(task, RuntimeError("mesher crashed"))
    assert (frame.status == "failed").all()
    ok_rows = frame[~frame.reason.str.startswith("invalid design")]
    assert (ok_rows.reason == "task failed: RuntimeError: mesher crashed").all()
    assert np.isfinite(ok_rows.curvature_analytic_per_mm).all()
    bare = evaluate_task(dict(task, fail_reason="task failed: X"))
    assert (bare.reason == "task failed: X").all() and bare.curvature_analytic_per_mm.isna().all()


@pytest.mark.slow
def test_killed_worker_loses_only_unsaved_tasks(spec_writer, tmp_path):
    """SIGKILL one pool worker mid-sweep: saved tasks stay, lost ones are not saved, a rerun completes."""
    import multiprocessing
    import os
    import signal
    import threading
    import time

    n = 150
    spec = load_spec(
        spec_writer(
            f"""
            [sweep]
            pressures_MPa = [1.0]
            loads = ["cap"]
            chunk_size = 1
            [sample]
            n = {n}
            [parameters]
            "tube.h" = {{ lhs = [-0.04, 0.04] }}
            """
        )
    )
    out = tmp_path / "o"
    result = {}
    before = {p.pid for p in multiprocessing.active_children()}  # children of earlier tests are not ours
    thread = threading.Thread(target=lambda: result.update(s=run_sweep(spec, out, workers=2, progress=False)))
    thread.start()
    store = SweepStore(out)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not (store.tasks_dir.is_dir() and len(store.finished()) >= 5):
        time.sleep(0.005)
    workers = [p for p in multiprocessing.active_children() if p.pid not in before]
    assert workers and thread.is_alive()
    os.kill(workers[0].pid, signal.SIGKILL)
    thread.join(120)
    first = result["s"]
    saved = store.finished()
    assert first.lost_tasks > 0 and first.evaluated_tasks == len(saved) and len(saved) < n
    second = run_sweep(spec, out, workers=2, progress=False)
    assert second.skipped_tasks == len(saved) and second.evaluated_tasks == n - len(saved)
    assert second.lost_tasks == 0 and second.ok_designs == n


def test_dask_malloc_threshold_is_undone_in_a_worker_process():
    # Dask's nanny sets MALLOC_TRIM_THRESHOLD_, which measured ~30 % more CPU per FEM design; the evaluator
    # restores glibc's thresholds once in such a process and leaves other processes alone.
    import subprocess
    import sys

    code = "from softcath.studies.sweep.evaluators import restore_malloc_thresholds as r; print(r(), r())"
    env = {k: v for k, v in os.environ.items() if k != "MALLOC_TRIM_THRESHOLD_"}
    plain = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert plain.stdout.split() == ["False", "False"]
    nanny = subprocess.run(
        [sys.executable, "-c", code],
        env={**env, "MALLOC_TRIM_THRESHOLD_": "65536"},
        capture_output=True,
        text=True,
        check=True,
    )
    expected = ["True", "False"] if sys.platform.startswith("linux") else ["False", "False"]
    assert nanny.stdout.split() == expected
