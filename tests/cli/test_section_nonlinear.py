"""``softcath section --nonlinear`` end to end."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from softcath.cli.main import main
from softcath.design.measurement import Measurement, write_measurement_csv
from softcath.fem.section_model.end_zones import end_zones, tip_pose


def test_nonlinear_section_writes_curve_json_csv_png(tmp_path, capsys):
    out = tmp_path / "s"
    measured = tmp_path / "m.csv"
    p = np.linspace(0.1, 0.6, 30)
    write_measurement_csv(
        measured,
        Measurement({"time_s": np.arange(30) * 0.005, "pressure_MPa": p, "curvature_per_mm": 0.3 * p}),
    )
    argv = ["section", "paper", "--nonlinear", "--pressure", "0:0.6:4", "--measured", str(measured)]
    assert main([*argv, "--out", str(out)]) == 0
    doc = json.loads((out / "section.json").read_text())
    assert doc["nonlinear"] is True and doc["design"] == "paper" and doc["load"] == "lumen"
    assert doc["dofs"] > 1000 and doc["seconds"] > 0
    assert (
        len(doc["newton_iterations"]) == 4
        and doc["newton_iterations"][0] == 0
        and min(doc["newton_iterations"][1:]) >= 1
    )
    with (out / "section.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0])[:6] == [
        "pressure_MPa",
        "curvature_per_mm",
        "elongation",
        "bend_angle_rad",
        "tip_x_mm",
        "tip_y_mm",
    ]
    assert {"lumen_volume_change_mm3", "max_strain"} <= set(rows[0])
    last = {k: float(v) for k, v in rows[-1].items()}
    # large-bend softening: the finite-strain curvature exceeds the linear gain's at 0.6 MPa
    assert last["curvature_per_mm"] > 1.2 * doc["linear_curvature_per_mm_per_MPa"] * 0.6
    # eq. 9 with the end zones: the arc of the reported curvature over the stretched L - deficit,
    # then the deficit straight along its end tangent and the plug turned on by its tilt at this pressure
    zones = end_zones("paper")
    x, y, _ = tip_pose(last["curvature_per_mm"], last["elongation"], zones, pressure=last["pressure_MPa"])
    assert (last["tip_x_mm"], last["tip_y_mm"]) == pytest.approx((float(x), float(y)), rel=1e-9)
    assert last["lumen_volume_change_mm3"] > 0 and 0 < last["max_strain"] < 2
    assert (out / "section_curve.png").stat().st_size > 10_000
    assert "finite-strain section" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("extra", "flag"),
    [
        (["--nonlinear", "--coil-bound"], "--coil-bound"),
        (["--nonlinear", "--coil-model", "wahl"], "--coil-model"),
        (["--measured", "x.csv"], "--measured"),
        (["--hoop-cap", "1000"], "--hoop-cap"),
        (["--nonlinear", "--pressure", "0:1e300:3"], "pressure"),
    ],
)
def test_nonlinear_section_refuses_what_it_cannot_do(tmp_path, capsys, extra, flag):
    assert main(["section", "paper", *extra, "--out", str(tmp_path / "x")]) == 2
    assert flag in capsys.readouterr().err
    assert not (tmp_path / "x" / "section.json").exists()


def test_nonlinear_section_90_degrees(tmp_path, capsys):
    """The paper design's tip passes 90 degrees below 1 MPa and says where."""
    out = tmp_path / "s90"
    assert (
        main(["section", "paper", "--nonlinear", "--pressure", "0.1:0.9:5", "--no-png", "--out", str(out)])
        == 0
    )
    doc = json.loads((out / "section.json").read_text())
    p90 = doc["pressure_for_90_deg_MPa"]
    assert 0.7 < p90 < 0.9
    angles = np.degrees(doc["bend_angle_rad"])
    assert angles[-1] > 90 and math.isclose(np.interp(p90, doc["pressure"], angles), 90, rel_tol=1e-9)
    assert "90 deg" in capsys.readouterr().out
