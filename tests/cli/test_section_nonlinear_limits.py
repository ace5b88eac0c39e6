"""``softcath section --nonlinear``: the rest state alone is an answer, work beyond the limit is
refused before it starts, bends past a full turn are said, a measurement far beyond the model's
pressures (bar read as MPa) is refused, and an input inside ``--out`` is never overwritten."""

from __future__ import annotations

import csv
import json
import logging
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from softcath.design.errors import DesignError
from softcath.studies.model_validity import check_measured_pressures, self_contact_warning


def test_the_rest_state_alone_is_an_answer(cli, tmp_path):
    r = cli("section", "paper", "--nonlinear", "--pressure=0", "--no-png", "--out", tmp_path / "o")
    assert r.status == 0, r.err
    with (tmp_path / "o" / "section.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 1 and float(rows[0]["pressure_MPa"]) == 0.0
    assert float(rows[0]["curvature_per_mm"]) == 0.0 and float(rows[0]["lumen_area_mm2"]) > 0


def test_a_million_pressures_are_refused_with_the_estimate_before_any_work(cli, tmp_path):
    t0 = time.perf_counter()
    line = cli(
        "section", "paper", "--nonlinear", "--pressure=0:1:1000000", "--out", tmp_path / "o"
    ).error_line()
    assert time.perf_counter() - t0 < 10
    assert (
        "--pressure = '0:1:1000000': the finite-strain curve through 1000000 pressures is estimated" in line
    )
    assert "above the 2 h a command starts" in line
    assert not (tmp_path / "o").exists()


def test_suction_is_refused_naming_the_option(cli, tmp_path):
    line = cli(
        "section", "paper", "--nonlinear", "--pressure=-0.5:0.5:3", "--out", tmp_path / "o"
    ).error_line()
    assert "--pressure = '-0.5:0.5:3': must be >= 0 MPa with --nonlinear" in line


def _measurement(path, top):
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["time_s", "pressure_MPa", "curvature_per_mm"])
        for i, p in enumerate(np.linspace(0, top, 40)):
            w.writerow([i * 0.1, p, 0.2 * p])


def test_a_measurement_in_bar_is_refused_and_an_input_inside_out_is_kept(cli, tmp_path):
    bar = tmp_path / "bar.csv"
    _measurement(bar, 6.0)
    line = cli(
        "section", "paper", "--nonlinear", "--pressure=0:0.6:3", "--measured", bar, "--out", tmp_path / "o"
    ).error_line()
    assert "--measured = " in line and "reaches 6, 10x the model's highest 0.6 MPa" in line and "bar" in line
    out = tmp_path / "o2"
    assert cli("section", "paper", "--nonlinear", "--pressure=0:0.6:3", "--no-png", "--out", out).status == 0
    _measurement(out / "section.csv", 0.6)  # the user turns the output into their measurement
    before = (out / "section.csv").read_bytes()
    line = cli(
        "section",
        "paper",
        "--nonlinear",
        "--pressure=0:0.6:3",
        "--measured",
        out / "section.csv",
        "--out",
        out,
    ).error_line()
    assert "--out = " in line and "section.csv" in line
    assert (out / "section.csv").read_bytes() == before


@settings(max_examples=60, deadline=None, derandomize=True, database=None)
@given(top=st.floats(0.01, 100), ratio=st.floats(0.0, 50.0))
def test_measured_pressures_one_rule(top, ratio):
    """Refused above 5x the model's highest pressure, accepted (with a warning above 1.5x) below."""
    measured = np.array([0.0, top * ratio])
    if ratio > 5.0:
        with pytest.raises(DesignError, match="is the file in bar"):
            check_measured_pressures(measured, top, param="--measured", value="m.csv")
    else:
        check_measured_pressures(measured, top, param="--measured", value="m.csv")


@settings(max_examples=80, deadline=None, derandomize=True, database=None)
@given(angles=st.lists(st.floats(-20.0, 20.0), min_size=1, max_size=8))
def test_a_bend_past_a_full_turn_is_always_said(angles):
    p = np.arange(len(angles), dtype=float)
    msg = self_contact_warning(p, np.array(angles), model="m")
    assert (msg is not None) == bool(np.any(np.abs(np.degrees(angles)) > 360.0))
    if msg:
        assert "pass through itself" in msg


def test_section_nonlinear_says_the_tip_passes_through_itself(cli, tmp_path, caplog):
    caplog.set_level(logging.WARNING)
    r = cli("section", "paper", "--nonlinear", "--pressure=0:4:3", "--no-png", "--out", tmp_path / "o")
    assert r.status == 0, r.err
    assert "pass through itself" in r.err + caplog.text
    doc = json.loads((tmp_path / "o" / "section.json").read_text())
    assert doc["self_contact_from_MPa"] == 4.0
