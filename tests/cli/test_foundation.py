"""The command line of the foundation: design, analytic, calibrate (in-process and as a console script)."""

import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest

from softcath.cli.main import main

ROOT = Path(__file__).parents[2]
DATA = ROOT / "studies" / "data" / "paper_sine.csv"


def test_design_show_and_validate(capsys, tmp_path):
    assert main(["design", "show", "paper", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "the catalogue tube is squeezed to fit" in out and "neutral axis" in out
    assert (tmp_path / "section.png").stat().st_size > 1000
    assert main(["design", "validate", str(ROOT / "design/presets/paper.toml")]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[0].endswith("valid design 'paper'; note: the catalogue tube is squeezed to fit")
    assert "NOT" not in out


def test_bad_design_is_one_line_and_exit_2(tmp_path, capsys):
    f = tmp_path / "bad.toml"
    f.write_text(
        (ROOT / "design/presets/paper.toml")
        .read_text()
        .replace("inner_diameter = 0.6", "inner_diameter = 0.85")
    )
    assert main(["design", "validate", str(f)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0
    assert "coil.inner_diameter = 0.85: must be < outer_diameter = 0.8" in err


def test_analytic_writes_csv_and_png(tmp_path):
    assert main(["analytic", "paper", "--pressure", "0:4:9", "--out", str(tmp_path)]) == 0
    with (tmp_path / "analytic.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == [
        "pressure_MPa",
        "curvature_per_mm",
        "elongation",
        "bend_angle_rad",
        "tip_x_mm",
        "tip_y_mm",
    ]
    assert len(rows) == 9 and float(rows[0]["curvature_per_mm"]) == 0.0
    assert (tmp_path / "analytic.png").stat().st_size > 1000


def test_analytic_bad_range(capsys, tmp_path):
    assert main(["analytic", "paper", "--pressure", "0:x:3", "--out", str(tmp_path)]) == 2
    assert "expected START:STOP:N" in capsys.readouterr().err


def test_calibrate_writes_the_documented_keys(tmp_path):
    assert main(["calibrate", "paper", str(DATA), "--out", str(tmp_path)]) == 0
    doc = json.loads((tmp_path / "calibration.json").read_text())
    for key in (
        "x_opt",
        "nrmse_nominal",
        "nrmse_optimized",
        "ratio",
        "objective",
        "starts",
        "starts_at_optimum",
    ):
        assert key in doc
    assert set(doc["x_opt"]) == {"a", "a_int", "b_int", "h"}
    assert doc["ratio"] == pytest.approx(doc["nrmse_nominal"] / doc["nrmse_optimized"])
    assert (tmp_path / "calibration.png").stat().st_size > 1000
    from softcath import design

    calibrated = design.load(tmp_path / "calibrated_design.toml")
    assert calibrated.tube_shape == pytest.approx(doc["x_opt"])


def test_calibrate_bad_csv_is_one_line(tmp_path):
    f = tmp_path / "bad.csv"
    f.write_text("time_s,pressure_MPa\n0,1\n")
    r = subprocess.run(
        [sys.executable, "-m", "softcath", "calibrate", str(f), "--out", str(tmp_path / "o")],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"},
    )
    assert r.returncode == 2
    assert r.stderr.strip().count("\n") == 0
    assert "bad.csv: missing required column(s) curvature_per_mm" in r.stderr
