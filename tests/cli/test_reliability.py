"""The classes of failure of a second reliability pass, each checked at its shared mechanism.

Costs estimated before work, no silent wrong answers, input errors never reported as bugs,
outputs that cannot collide, non-zero exits after failures, checks before work, messages that
name the value given. Property-based where a rule has a domain (hypothesis, derandomised).
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from softcath import design
from softcath.cli.options import parse_pressure_list, parse_pressure_range
from softcath.design.errors import DesignError
from softcath.fem.limits import MAX_SECTION_DOFS, check_section_budget, estimate_section_dofs
from softcath.studies.atomic import check_outputs

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "studies" / "data"
PROPS = settings(
    max_examples=60,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
FLOATS = st.floats(allow_nan=True, allow_infinity=True, width=64)


# --- 1. cost known before work ------------------------------------------------------------


@PROPS
@given(radius=st.floats(0.05, 6.0), mesh=st.floats(0.005, 0.5))
def test_section_budget_refuses_exactly_what_its_estimate_cannot_afford(radius, mesh):
    dofs = estimate_section_dofs(section_area=math.pi * radius**2, mesh_size=mesh)
    if dofs > MAX_SECTION_DOFS:
        with pytest.raises(DesignError, match=r"mesh_size = .* DOFs"):
            check_section_budget(coil_outer_radius=radius, mesh_size=mesh)
    else:
        try:
            assert check_section_budget(coil_outer_radius=radius, mesh_size=mesh) == dofs
        except DesignError as exc:  # only memory can refuse a design under the DOF cap
            assert "GB" in str(exc)


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (["predict", "paper", "--samples", "10000000"], "--samples = 10000000: must be <= 10000"),
        (["predict", "paper", "--model", "fem", "--fem-samples", "100000000"], "--fem-samples = 100000000"),
        (["predict", "paper", "--finite-strain", "--pressures", "0.1,1e300"], "--pressures = 1e+300"),
        (["predict", "paper", "--finite-strain", "--pressures", "0.3,0.1"], "strictly increasing"),
        (["predict", "paper", "--measured-gain", "1e308"], "--measured-gain = 1e+308"),
        (["coil", "paper", "--elements-per-turn", "100000000"], "--elements-per-turn = 100000000"),
        (["section", "paper", "--mesh-size", "0.005", "--pressure", "0:1:3:4"], "--pressure = '0:1:3:4'"),
    ],
)
def test_costly_or_malformed_options_are_refused_before_any_work(tmp_path, cli, argv, expected):
    out = tmp_path / "out"
    t0 = time.monotonic()
    line = cli(*argv, "--out", out).error_line()
    assert expected in line and time.monotonic() - t0 < 5
    assert not out.exists()  # a refused command leaves no empty --out


def test_predict_refuses_a_section_tier_that_would_take_hours(tmp_path, cli):
    d = design.resolve("paper")
    big = replace(d, coil=replace(d.coil, outer_diameter=12.0, wire_diameter=5.7, pitch=5.7))
    toml = tmp_path / "big.toml"
    toml.write_text(design.dumps(big), encoding="utf-8")
    t0 = time.monotonic()
    line = cli("predict", toml, "--vary", "tube.h=-0.01:0.01", "--out", tmp_path / "p").error_line()
    assert "--samples = 512: would take about" in line and "h with the section model" in line
    assert time.monotonic() - t0 < 5 and not (tmp_path / "p").exists()


@pytest.mark.parametrize(
    ("parameters", "reason"),
    [
        # a 12 mm coil at a 20 µm section mesh: ~3e6 DOFs, refused before meshing
        (
            '"coil.outer_diameter" = { values = [12.0] }\n"coil.wire_diameter" = { values = [5.7] }\n'
            '"coil.pitch" = { values = [5.7] }',
            "mesh_size = 0.02: the 12 mm section needs about",
        ),
        # a 10⁶ mm tip is no catheter: failed by the validator, never ranked feasible
        ('"tip.bending_length" = { values = [1e6] }', "bending_length = 1e+06: must be <= 200"),
    ],
)
def test_a_section_sweep_marks_an_impossible_design_failed_with_the_reason(
    spec_writer, tmp_path, cli, parameters, reason
):
    import pandas as pd

    spec = spec_writer(
        f"""
[sweep]
name = "cost"
base = "paper"
pressures_MPa = [0.1]
loads = ["lumen"]
evaluators = ["section"]
[sweep.section]
mesh_size = 0.02
[parameters]
{parameters}
"""
    )
    t0 = time.monotonic()
    r = cli("sweep", spec, "--out", tmp_path / "s", "--workers", "1", "--no-progress")
    assert r.status == 0, r.err
    assert time.monotonic() - t0 < 20
    df = pd.read_parquet(tmp_path / "s" / "results.parquet")
    assert (df["status"] == "failed").all()
    assert df["reason"].astype(str).str.contains(reason, regex=False).all(), df["reason"].tolist()


# --- 2. no silent wrong answers -----------------------------------------------------------


@PROPS
@given(text=st.text(alphabet="0123456789.:-e+", max_size=16))
def test_a_pressure_range_is_exact_or_refused(text):
    try:
        p = parse_pressure_range(text)
    except DesignError as exc:
        assert exc.parameter == "--pressure"
        return
    fields = text.split(":")
    assert len(fields) in (1, 3)
    assert p.size == (1 if len(fields) == 1 else int(fields[2]))
    assert np.all(np.isfinite(p)) and np.all(np.abs(p) <= 100)


@PROPS
@given(values=st.lists(FLOATS, min_size=1, max_size=5))
def test_a_pressure_list_is_bounded_like_a_pressure(values):
    text = ",".join(repr(v) for v in values)
    if all(math.isfinite(v) and abs(v) <= 100 for v in values):
        assert parse_pressure_list(text) == pytest.approx(values)
    else:
        with pytest.raises(DesignError, match=r"--pressures = .*(finite|±100 MPa)"):
            parse_pressure_list(text)


@PROPS
@given(tension=st.floats(0, 1e9), wire=st.sampled_from([0.05, 0.1, 0.15]))
def test_initial_tension_is_bounded_by_the_wire_and_the_threshold_stays_physical(tension, wire):
    base = design.resolve("paper").coil
    od = base.inner_diameter + 2 * wire
    try:
        c = replace(base, outer_diameter=od, wire_diameter=wire, pitch=wire, initial_tension=tension)
    except DesignError as exc:
        assert exc.parameter == "initial_tension" and "torsional stress" in exc.bound
        assert tension > 0.1  # the paper-sized wires take at least 0.1 N
        return
    assert c.initial_tension == tension
    assert tension <= 0.006 * c.material.youngs_modulus * math.pi * wire**3 / (8 * c.mean_radius * 2) + 1e-12


@pytest.mark.parametrize(
    ("path", "value", "bound"),
    [
        ("tip.bending_length", 1e6, "must be <= 200"),
        ("coil.outer_diameter", 100.0, "must be <= 12"),
        ("coil.initial_tension", 100.0, "must be <= 0.6496 N"),
    ],
)
def test_the_validator_refuses_what_no_catheter_can_have(tmp_path, cli, path, value, bound):
    text = design.dumps(design.resolve("paper"))
    section, key = path.split(".")
    lines, current = [], None
    for line in text.splitlines():
        if line.startswith("["):
            current = line.strip("[]")
        if current == section and line.split("=")[0].strip() == key:
            line = f"{key} = {value!r}"
        lines.append(line)
    toml = tmp_path / "absurd.toml"
    toml.write_text("\n".join(lines) + "\n", encoding="utf-8")
    line = cli("design", "validate", toml).error_line()
    assert f"{key} = " in line and bound in line


def test_section_warns_outside_the_linear_range_as_analytic_does(tmp_path, cli):
    r = cli("section", "paper", "--pressure=-1:5:3", "--no-png", "--out", tmp_path / "s")
    assert r.status == 0, r.err
    assert (
        "negative pressure (-1 MPa)" in r.err and "bend 349 deg" in r.err
    )  # the tip's angle (end zones taken off)


def test_fem_states_the_silicone_poisson_ratio_it_used():
    from softcath.fem.adapter import NU_CAP, silicone_parameters

    d = design.resolve("paper")
    soft = replace(d.tube.material, poisson_ratio=0.4999)
    used = silicone_parameters(replace(d, tube=replace(d.tube, material=soft)))["tube"]
    assert used == {**used, "poisson_ratio_design": 0.4999, "poisson_ratio_used": NU_CAP, "capped": True}


# --- 3. input errors are not bug reports --------------------------------------------------


@pytest.mark.parametrize(
    ("rows", "expected"),
    [
        ([(0.5, 0.01 * i) for i in range(8)], "all 8 pressures are 0.5 MPa"),
        ([(0.1 * i, 0.0) for i in range(8)], "all 8 curvatures are 0 1/mm"),
        ([(0.1 * i, 1e300 * i) for i in range(8)], "exceeds 1000 1/mm"),
    ],
)
def test_discrepancy_refuses_degenerate_reference_curves(tmp_path, cli, rows, expected):
    csv = tmp_path / "ref.csv"
    csv.write_text(
        "pressure_MPa,curvature_per_mm\n" + "".join(f"{p},{k}\n" for p, k in rows), encoding="utf-8"
    )
    line = cli("discrepancy", "paper", csv, "--reference", "fem", "--out", tmp_path / "d").error_line()
    assert expected in line


def test_seed_and_ranges_encoding_are_input_errors(tmp_path, cli):
    assert "invalid seed -1" in cli("predict", "paper", "--seed", "-1", "--out", tmp_path / "p").error_line()
    bad = tmp_path / "ranges.toml"
    bad.write_bytes(b'x = "\xff\xfe"\n')
    line = cli("predict", "paper", "--ranges", bad, "--out", tmp_path / "p").error_line()
    assert "--ranges" in line and "not UTF-8" in line


def test_a_path_the_terminal_cannot_print_does_not_fail_after_the_outputs(tmp_path):
    out = tmp_path / "résultat-✓"
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONIOENCODING="ascii", LC_ALL="C")
    r = subprocess.run(
        [sys.executable, "-m", "softcath", "analytic", "paper", "--pressure", "0:0.1:3", "--out", str(out)],
        capture_output=True,
        text=True,
        env=env,
        cwd=ROOT,
        timeout=120,
        encoding="utf-8",
        errors="replace",
    )
    assert r.returncode == 0, r.stderr
    assert "r\\xe9sultat" in r.stdout and (out / "analytic.csv").exists()


# --- 5. outputs never collide -------------------------------------------------------------


@PROPS
@given(parts=st.lists(st.sampled_from(["a", "b", "..", "."]), min_size=1, max_size=4))
def test_a_relative_output_stays_inside_its_folder_or_is_refused(tmp_path, parts):
    out = tmp_path / "out"
    given_path = Path(*parts) / "x.step"
    try:
        p = check_outputs({"--step": given_path}, inside=out)["--step"]
    except DesignError as exc:
        assert exc.parameter == "--step" and "leaves the output folder" in exc.bound
        assert ".." in parts
        return
    assert out.resolve() in p.resolve().parents


@pytest.mark.parametrize(
    ("extra", "expected"),
    [
        (["--step", "X", "--stl", "X"], "--stl = 'X': names the same file as --step"),
        (["--out", "e", "--step", "../x.step"], "--step = '../x.step': leaves the output folder"),
        (["--step", "DESIGN"], "is the input"),
    ],
)
def test_design_export_refuses_colliding_or_escaping_outputs(tmp_path, cli, extra, expected):
    toml = tmp_path / "d.toml"
    toml.write_text(design.dumps(design.resolve("paper")), encoding="utf-8")
    before = toml.read_bytes()
    extra = [str(toml) if e == "DESIGN" else str(tmp_path / e) if e in ("X", "e") else e for e in extra]
    line = cli("design", "export", toml, *extra).error_line()
    assert expected.replace("'X'", repr(str(tmp_path / "X"))) in line
    assert toml.read_bytes() == before and not (tmp_path / "X").exists()


# --- 6. non-zero exit after a failure -----------------------------------------------------


def test_an_unconverged_section_calibration_exits_2_and_writes_nothing(tmp_path, cli):
    out = tmp_path / "cal"
    line = cli("calibrate", "paper", DATA / "paper_sine.csv", "--model", "section", "--out", out).error_line()
    assert "NOT converged" in line and "nothing written" in line
    assert not out.exists()


# --- 7. what can be checked is checked first ----------------------------------------------


def test_an_unwritable_out_is_refused_before_the_work_naming_out(tmp_path, cli):
    t0 = time.monotonic()
    line = cli("section", "paper", "--out", "/proc/self").error_line()
    assert line.startswith("softcath section: error: --out = '/proc/self': is not writable")
    assert time.monotonic() - t0 < 5


# --- 8. messages name what was given ------------------------------------------------------


def test_messages_name_the_value_and_option_given(tmp_path, cli):
    line = cli("section", "paper", "--poisson", "0.49999999", "--out", tmp_path / "s").error_line()
    assert "--poisson = 0.49999999:" in line
    line = cli(
        "section", "paper", "--coil-model", "annulus-bending", "--coil-bound", "--out", tmp_path / "s"
    ).error_line()
    assert "--coil-model = 'annulus-bending': cannot be used with --coil-bound" in line
    line = cli("calibrate", DATA / "paper_sine.csv", "--grid", "11", "--out", tmp_path / "c").error_line()
    assert "--grid = 11: must be an integer in [1, 10] with 4 free parameter(s)" in line


@PROPS
@given(value=st.floats(allow_nan=False, allow_infinity=False))
def test_an_error_shows_the_value_exactly(value):
    text = str(DesignError("x", value, "bound"))
    assert float(text.split(" = ")[1].split(":")[0]) == value


@pytest.mark.slow
def test_fem_json_states_and_warns_the_capped_poisson_ratio(tmp_path, cli):
    import json

    d = design.resolve("paper")
    soft = replace(d.tube.material, poisson_ratio=0.4999)
    toml = tmp_path / "nu.toml"
    toml.write_text(design.dumps(replace(d, tube=replace(d.tube, material=soft))), encoding="utf-8")
    r = cli("fem", toml, "--pressure", "0.1", "--no-png", "--out", tmp_path / "f")
    assert r.status == 0, r.err
    assert "tube silicone Poisson ratio 0.4999 is solved as 0.49" in r.err
    tube = json.loads((tmp_path / "f" / "fem.json").read_text())["silicones"]["tube"]
    assert (tube["poisson_ratio_design"], tube["poisson_ratio_used"], tube["capped"]) == (0.4999, 0.49, True)
