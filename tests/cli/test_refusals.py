"""Inputs the command line once mishandled, each a clean refusal (or a correct answer)."""

from __future__ import annotations

import hashlib
import json
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from softcath import design

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "studies" / "data"


def _digest(folder: Path) -> dict[str, str]:
    return {
        p.name: hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.iterdir())
        if p.is_file() and not p.name.startswith(".")
    }


def _paper_toml(tmp_path: Path, **tube) -> Path:
    text = design.dumps(design.preset("paper"))
    extra = "".join(f"{k} = {v!r}\n" for k, v in tube.items())
    path = tmp_path / "d.toml"
    path.write_text(text.replace("[tube]\n", "[tube]\n" + extra, 1))
    return path


def test_failed_calibration_keeps_the_earlier_good_outputs(tmp_path, cli):
    out = tmp_path / "cal"
    assert cli("calibrate", DATA / "paper_sine.csv", "--out", out, "--grid", "1").status == 0
    good = _digest(out)
    assert set(good) == {"calibration.json", "calibration.png", "calibrated_design.toml"}
    df = pd.read_csv(DATA / "paper_sine.csv")
    df["pressure_MPa"] *= 1e300
    huge = tmp_path / "huge.csv"
    df.to_csv(huge, index=False)
    line = cli("calibrate", huge, "--out", out).error_line()
    # the measurement reader refuses it (plausible bound), or the calibration range check (±100 MPa)
    assert "pressure_MPa" in line and ("must be within ±100 MPa" in line or "plausible bound" in line)
    assert _digest(out) == good  # nothing overwritten, no NaN, no stray PNG or temp file
    json.loads((out / "calibration.json").read_text(), parse_constant=pytest.fail)


def test_design_export_into_a_new_folder_writes_the_file(tmp_path, cli):
    pytest.importorskip("cadquery")
    target = tmp_path / "newdir" / "tip.step"
    r = cli("design", "export", "paper", "--step", target)
    assert r.status == 0, r.err
    assert target.stat().st_size > 10_000
    assert target.read_text(errors="replace").startswith("ISO-10303-21")
    assert f"wrote {target} ({target.stat().st_size} bytes)" in r.out


def test_fem_refuses_an_unmeshable_lumen_before_meshing(tmp_path, cli):
    path = _paper_toml(tmp_path, a=0.2121, a_int=0.001, b_int=0.075, h=0.0)
    assert cli("design", "validate", path).status == 0  # a valid design ...
    line = cli("fem", path, "--pressure", "0.1", "--out", tmp_path / "f").error_line()
    assert (
        "tube.a_int = 0.001: a lumen semi-axis below 0.01 mm cannot be meshed" in line
    )  # ... the FEM cannot mesh


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["--mesh-size", "0.005"], r"--mesh-size = 0\.005: needs about .* DOFs and .* GB of memory"),
        (["--mesh-size", "nan"], r"--mesh-size = nan: must be a finite element size > 0 mm"),
        (["--mesh-size", "-0.1"], r"--mesh-size = -0\.1: must be a finite element size > 0 mm"),
        (["--pressure", "1e300"], r"--pressure = 1e\+300: must be within ±100 MPa"),
        (["--pressure", "inf"], r"--pressure = inf: must be a finite pressure in MPa"),
    ],
)
def test_fem_refuses_bad_sizes_and_pressures_before_the_solve(tmp_path, cli, argv, expected):
    args = {"--pressure": "0.1", **dict(zip(argv[::2], argv[1::2], strict=True))}
    line = cli("fem", "paper", *[x for kv in args.items() for x in kv], "--out", tmp_path / "f").error_line()
    assert re.search(expected, line), line
    assert not (tmp_path / "f" / "fem.json").exists()


def test_analytic_warns_outside_the_linear_range_and_refuses_overflow(tmp_path, cli):
    r = cli("analytic", "paper", "--pressure=-1:5:7", "--out", tmp_path / "a")
    assert r.status == 0
    warnings = [ln for ln in r.err.splitlines() if ln.startswith("WARNING")]
    assert any("negative pressure (-1 MPa)" in w for w in warnings)
    # 5 MPa bends the paper tip 114° in the linear model (κ/p = 0.0756 1/(mm MPa), L = 5 mm: 0.378·5 rad)
    assert any("bend 114 deg is beyond the ~5 deg" in w and "--nonlinear" in w for w in warnings)
    good = _digest(tmp_path / "a")
    line = cli("analytic", "paper", "--pressure", "0:1e300:3", "--out", tmp_path / "a").error_line()
    assert "--pressure" in line and "must be within ±100 MPa" in line
    assert _digest(tmp_path / "a") == good
    r = cli("analytic", "paper", "--pressure", "0:0.01:3", "--out", tmp_path / "small")
    assert r.status == 0 and "WARNING" not in r.err  # 0.4° at 0.01 MPa: inside the linear range


@pytest.mark.parametrize(
    "expr", ["bend_angle_deg >= 1/0", "bend_angle_deg >= 1/(1-1)", "bend_angle_deg >= 1e999", "x >= 1/0"]
)
def test_select_refuses_non_finite_constants(quick_sweep, cli, expr):
    line = cli(
        "select", quick_sweep, "--constraint", expr, "--objective", "maximise bend_per_MPa_deg"
    ).error_line()
    assert expr in line


def test_sweep_spec_with_non_finite_values_is_refused(spec_writer, tmp_path, cli):
    for values, bad in (("[nan, inf]", "values[0] = nan"), ("[0.0, inf]", "values[1] = inf")):
        spec = spec_writer(
            f'[sweep]\nbase = "paper"\npressures_MPa = [0.5]\n[parameters]\n"tube.h" = {{ values = {values} '
            f"}}\n"
        )
        line = cli("sweep", spec, "--out", tmp_path / "s", "--workers", "1").error_line()
        assert f"parameters.tube.h.{bad}: must be a finite number" in line
    assert not (tmp_path / "s" / "sweep.json").exists()


@pytest.fixture
def quick_sweep(spec_writer, tmp_path, cli):
    spec = spec_writer(
        '[sweep]\nbase = "paper"\npressures_MPa = [0.5, 1.0]\nchunk_size = 2\n'
        '[parameters]\n"tube.h" = { values = [-0.02, 0.0, 0.02] }\n"tip.bending_length" = { values = [4.0, '
        "6.0] }\n"
    )
    out = tmp_path / "q"
    assert cli("sweep", spec, "--out", out, "--workers", "1", "--no-progress").status == 0
    return out


def test_damaged_results_name_the_file_and_the_fix(quick_sweep, cli):
    (quick_sweep / "results.parquet").write_bytes(b"PAR1 damaged")
    for argv in (
        ["report", quick_sweep],
        ["select", quick_sweep, "--objective", "maximise bend_per_MPa_deg"],
    ):
        line = cli(*argv).error_line()
        assert f"{quick_sweep / 'results.parquet'}: cannot be read" in line
        assert "rerun the same `softcath sweep SPEC --out DIR` command" in line
    (quick_sweep / "sweep.json").write_text("{ not json")
    line = cli("report", quick_sweep).error_line()
    assert "sweep.json: unreadable sweep manifest" in line


def test_resume_sets_a_damaged_task_file_aside_and_recomputes_exactly(quick_sweep, cli):
    ref = pd.read_parquet(quick_sweep / "results.parquet")
    task = sorted((quick_sweep / "tasks").glob("t*.parquet"))[1]
    task.write_bytes(task.read_bytes()[: len(task.read_bytes()) // 2])  # cut short
    (quick_sweep / "results.parquet").unlink()
    r = cli(
        "sweep", quick_sweep.parent / "spec.toml", "--out", quick_sweep, "--workers", "1", "--no-progress"
    )
    assert r.status == 0, r.err
    assert f"{task}: unreadable" in r.err and f"set aside as {task.name}.corrupt" in r.err
    assert "2 of 3 tasks already done" in r.out  # only the damaged task is evaluated again
    again = pd.read_parquet(quick_sweep / "results.parquet")
    cols = [c for c in ref.columns if not c.endswith("_seconds")]
    pd.testing.assert_frame_equal(again[cols], ref[cols])


def test_demo_with_a_binary_data_file_is_refused_up_front(tmp_path, cli):
    data = tmp_path / "binary.csv"
    data.write_bytes(bytes(range(256)) * 4)
    r = cli("demo", "--data", data, "--out", tmp_path / "demo", "--no-fem", "--only", "calibration")
    line = r.error_line()
    assert "binary.csv" in line
    assert not (tmp_path / "demo" / "index.html").exists()


def test_measure_with_a_base_outside_the_image_is_refused(tmp_path, cli):
    cv2 = pytest.importorskip("cv2")
    from softcath.virtualbench.render import Scene, render_frame

    scene = Scene(px_per_mm=40.0)
    rng = np.random.default_rng(0)
    frames = tmp_path / "frames"
    frames.mkdir()
    for i in range(3):
        img = render_frame(
            scene, curvature_per_mm=math.radians(30 + 20 * i) / 5.0, arc_length_mm=5.0, rng=rng
        )
        cv2.imwrite(str(frames / f"f{i}.png"), img)
    out = tmp_path / "m"
    base = f"{scene.base[0]},{scene.base[1]}"
    assert cli("measure", frames, "--px-per-mm", "40", "--base", base, "--out", out).status == 0
    good = _digest(out)
    line = cli("measure", frames, "--px-per-mm", "40", "--base", "5000,300", "--out", out).error_line()
    assert "no tip found in any of the 3 frames (--base 5000,300" in line
    assert _digest(out) == good
    line = cli("measure", frames, "--px-per-mm", "40", "--base", "5000,-300", "--out", out).error_line()
    assert "--base = '5000,-300': must be finite pixel coordinates >= 0" in line
    line = cli("measure", frames, "--px-per-mm", "nan", "--out", out).error_line()
    assert "--px-per-mm = nan: must be a finite number > 0" in line


def test_record_refuses_non_finite_scales(tmp_path, cli):
    for flag in ("--pressure-scale", "--encoder-scale"):
        for value in ("nan", "inf", "0"):
            argv = ["record", "--pressure-port", "loop://", "--encoder-port", "loop://", flag, value]
            line = cli(*argv, "--duration", "1", "--out", tmp_path / "r").error_line()
            assert f"{flag} = {value if value != '0' else '0.0'}" in line or f"{flag} = {value}" in line
    line = cli(
        "record",
        "--pressure-port",
        "loop://",
        "--encoder-port",
        "loop://",
        "--duration",
        "nan",
        "--out",
        tmp_path / "r",
    ).error_line()
    assert "--duration = nan" in line


def test_paper_preset_and_design_show_agree_on_material_keys(tmp_path, cli):
    r = cli("design", "show", "paper", "--toml")
    preset_text = (ROOT / "design" / "presets" / "paper.toml").read_text()
    for key in re.findall(r"^\[materials\.(\w+)\]", r.out, flags=re.M):
        assert f"[materials.{key}]" in preset_text
    spec = tmp_path / "m.toml"
    spec.write_text(
        '[sweep]\nbase = "paper"\npressures_MPa = [1.0]\nloads = ["cap"]\n'
        '[parameters]\n"materials.medical_silicone_tubing.youngs_modulus" = { values = [2.46, 4.92] }\n'
    )
    assert cli("sweep", spec, "--out", tmp_path / "s", "--workers", "1", "--no-progress").status == 0
    df = pd.read_parquet(tmp_path / "s" / "results.parquet")
    k = df.sort_values("materials.medical_silicone_tubing.youngs_modulus")[
        "curvature_analytic_per_mm"
    ].to_numpy()
    assert k[1] < k[0]  # a stiffer tube bends less: the path reached the tube's material


def test_small_fem_example_states_the_fem_default_mesh_size():
    import inspect

    from softcath import fem

    default = inspect.signature(fem.check).parameters["mesh_size"].default
    text = (ROOT / "examples" / "sweeps" / "small_fem.toml").read_text()
    assert f"FEM default is {default:g}" in text
    assert "0.12 is the FEM default" not in text
