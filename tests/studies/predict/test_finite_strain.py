"""The finite-strain point of ``softcath predict``: the line fit, and the small-pressure limit (slow)."""

from __future__ import annotations

import pytest

from softcath.design.errors import DesignError
from softcath.studies.predict.finite_strain import finite_strain_point, line_fit


def test_line_fit_recovers_slope_and_intercept_of_points_on_a_line():
    p = [0.1, 0.3, 0.6]
    slope, intercept = line_fit(p, [0.388 * x + 0.012 for x in p])
    assert slope == pytest.approx(0.388, rel=1e-12)
    assert intercept == pytest.approx(0.012, rel=1e-9)


def test_line_fit_needs_two_distinct_pressures():
    with pytest.raises(DesignError, match=r"pressures = \[0\.3\]: need two or more distinct pressures"):
        line_fit([0.3], [0.1])


@pytest.mark.slow
def test_finite_strain_gain_tends_to_the_linear_fem_on_the_same_mesh():
    # At 5-10 kPa the finite-strain tip is linear to ~0.3 % (its kappa/p grows 17 % over 0.6 MPa) and
    # its arc length is L (1 + eps) with eps ~ 5e-4: the line-fit gain must equal the same mesh's
    # small-strain solve, angle / (p L), within 1 %.
    fs = finite_strain_point("paper", [0.005, 0.01], load="lumen", measured_gain=0.388)
    linear = fs["linear_bend_angle_rad"][-1] / (fs["pressures_MPa"][-1] * fs["length_mm"])
    assert fs["gain_line_fit"] == pytest.approx(linear, rel=1e-2)
    assert fs["measured_over_gain"] == pytest.approx(0.388 / fs["gain_line_fit"])


@pytest.mark.slow
def test_cli_adds_the_finite_strain_point_to_json_and_picture(tmp_path):
    import json

    from softcath.cli.main import main

    argv = [
        "predict",
        "paper",
        "--model",
        "paper",
        "--samples",
        "8",
        "--finite-strain",
        "--pressures",
        "0.005,0.01",
        "--measured-gain",
        "0.388",
        "--no-progress",
        "--out",
        str(tmp_path),
    ]
    assert main(argv) == 0
    fs = json.loads((tmp_path / "prediction.json").read_text())["finite_strain"]
    assert fs["pressures_MPa"] == [0.005, 0.01] and fs["load"] == "lumen"
    assert fs["gain_line_fit"] > 0 and (tmp_path / "prediction.png").is_file()


def test_cli_refuses_bad_pressures_in_one_line(tmp_path, capsys):
    from softcath.cli.main import main

    argv = [
        "predict",
        "paper",
        "--model",
        "paper",
        "--samples",
        "8",
        "--finite-strain",
        "--pressures",
        "0.1,x",
        "--out",
        str(tmp_path),
    ]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err == (
        "softcath predict: error: --pressures = '0.1,x': expected START:STOP:N (MPa, MPa, count), one value "
        "or comma-separated numbers in MPa (items may mix both: 0,0.1:0.5:5)"
    )
