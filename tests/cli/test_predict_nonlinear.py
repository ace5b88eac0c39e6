"""``softcath predict --nonlinear``: finite-strain curve bands and a measured curve compared point by
point."""

from __future__ import annotations

import json

import numpy as np
import pytest

from softcath.cli.main import main
from softcath.design.measurement import Measurement, write_measurement_csv


def test_predict_nonlinear_places_a_measured_curve_point_by_point(tmp_path, capsys):
    measured = tmp_path / "m.csv"
    p = np.repeat([0.2, 0.5], 10)
    k = np.where(p < 0.3, 0.06, 0.17)  # a convex curve, as the prototype's
    write_measurement_csv(
        measured, Measurement({"time_s": np.arange(p.size) * 0.01, "pressure_MPa": p, "curvature_per_mm": k})
    )
    out = tmp_path / "pred"
    argv = [
        "predict",
        "paper",
        "--model",
        "section",
        "--samples",
        "8",
        "--nonlinear",
        "--curve-samples",
        "3",
        "--pressures",
        "0.2,0.5",
        "--measured",
        str(measured),
        "--no-progress",
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    doc = json.loads((out / "prediction.json").read_text())
    nl = doc["nonlinear"]
    assert [pt["pressure_MPa"] for pt in nl["pressures"]] == [0.2, 0.5]
    m = nl["measured"]
    assert [pt["measured_curvature_per_mm"] for pt in m["points"]] == pytest.approx([0.06, 0.17])
    assert m["gain_line_fit"] == pytest.approx((0.17 - 0.06) / 0.3)
    for pt, band in zip(m["points"], nl["pressures"], strict=True):
        p50 = band["curvature_percentiles"]["p50"]
        assert pt["measured_over_p50"] == pytest.approx(pt["measured_curvature_per_mm"] / p50)
    assert (out / "curve_band.png").stat().st_size > 10_000
    assert "pressures inside the band" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("extra", "flag"),
    [
        (["--measured", "x.csv"], "--measured"),
        (["--nonlinear", "--model", "paper"], "--model"),
        (["--nonlinear", "--curve-samples", "1"], "--curve-samples"),
        (["--nonlinear", "--pressures", "0.3"], "--pressures"),
    ],
)
def test_predict_nonlinear_refuses_before_work(tmp_path, capsys, extra, flag):
    assert main(["predict", "paper", *extra, "--out", str(tmp_path / "x")]) == 2
    assert flag in capsys.readouterr().err
    assert not (tmp_path / "x").exists()
