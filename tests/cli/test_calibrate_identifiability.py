"""A section calibration that reaches the data is a result, its non-identifiability stated; one that
neither converges nor reaches the data still writes nothing."""

from __future__ import annotations

import json
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "studies" / "data" / "paper_sine.csv"


def test_two_free_shape_numbers_against_one_gain_are_a_result_that_says_so(cli, tmp_path):
    out = tmp_path / "cal"
    r = cli("calibrate", "paper", DATA, "--model", "section", "--free", "a_int,h", "--out", out)
    assert r.status == 0, r.err
    doc = json.loads((out / "calibration.json").read_text())
    assert doc["matches_data"] is True and doc["identifiable"] is False
    g, d = doc["gains_model"]["curvature_per_mm_per_MPa"], doc["gains_data"]["curvature_per_mm_per_MPa"]
    assert abs(g - d) / d < 1e-3
    assert "shape not identified" in doc["message"] and "shape not identified" in r.out
    assert (out / "calibrated_design.toml").is_file()


def test_a_fit_that_misses_the_data_still_writes_nothing(cli, tmp_path):
    out = tmp_path / "cal"
    line = cli("calibrate", "paper", DATA, "--model", "section", "--out", out).error_line()
    assert "NOT converged" in line and "nothing written" in line
    assert not out.exists()
