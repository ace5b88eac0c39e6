"""``softcath analytic --model`` and ``softcath calibrate --model``: the section model behind the same
outputs."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from softcath import design
from softcath.cli.main import main
from softcath.fem.section_model import section_model
from softcath.fem.section_model.end_zones import end_zones

COLUMNS = ["pressure_MPa", "curvature_per_mm", "elongation", "bend_angle_rad", "tip_x_mm", "tip_y_mm"]


def _read(path):
    with path.open() as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array(rows[1:], dtype=float)


@pytest.mark.parametrize("load", ["cap", "lumen"])
def test_analytic_model_section_writes_the_same_columns_from_the_section_model(tmp_path, capsys, load):
    out = tmp_path / load
    assert (
        main(
            [
                "analytic",
                "paper",
                "--model",
                "section",
                "--load",
                load,
                "--pressure",
                "0:1:5",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    header, a = _read(out / "analytic.csv")
    assert header == COLUMNS and (out / "analytic.png").is_file()
    k, e = section_model("paper", loads=(load,)).gains(load)
    p = a[:, 0]
    np.testing.assert_allclose(a[:, 1], k * p, rtol=1e-9)
    np.testing.assert_allclose(a[:, 2], e * p, rtol=1e-9)
    # Tip pose (eq. 9 with the end zones), written out here: an arc of length (L - d) (1 + eps),
    # d = cap plug + Saint-Venant deficit, then straight along its end tangent the deficit
    # (stretched) and the plug (not).
    zones = end_zones("paper")
    stretch = 1 + a[:, 2]
    theta = a[:, 1] * (5.0 - zones.deficit_mm) * stretch
    tail = zones.saint_venant_mm * stretch + zones.plug_mm
    pos = p > 0
    theta, tail, k = theta[pos], tail[pos], a[pos, 1]
    x = (1 - np.cos(theta)) / k + tail * np.sin(theta)
    y = np.sin(theta) / k + tail * np.cos(theta)
    np.testing.assert_allclose(a[pos, 3], theta, rtol=1e-9)
    np.testing.assert_allclose(a[pos, 4], x, rtol=1e-8)
    np.testing.assert_allclose(a[pos, 5], y, rtol=1e-8)
    assert "section model" in capsys.readouterr().out
    assert main(["analytic", "paper", "--pressure", "0:1:5", "--out", str(tmp_path / "paper")]) == 0
    _, b = _read(tmp_path / "paper" / "analytic.csv")
    assert b[-1, 1] == pytest.approx(0.0756475, rel=1e-5)  # the paper's formula stays the default


def test_calibrate_model_section_from_the_cli(tmp_path, capsys):
    """Section-model data of a known shape through the CLI: the shape comes back (see the API test's
    tolerance)."""
    paper = design.preset("paper")
    shape = dict(paper.tube_shape, a_int=0.12, h=0.015)
    t = np.arange(0, 8.0, 1 / 100)
    p = 1.0 - np.cos(2 * np.pi * 0.25 * t)
    r = section_model(paper.with_tube_shape(**shape), loads=("lumen",)).response(p, "lumen")
    path = tmp_path / "m.csv"
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["time_s", "pressure_MPa", "curvature_per_mm", "arc_length_mm"])
        w.writerows(zip(t, p, r.curvature, r.arc_length, strict=True))
    out = tmp_path / "cal"
    assert main(["calibrate", str(path), "--model", "section", "--free", "a_int,h", "--out", str(out)]) == 0
    doc = json.loads((out / "calibration.json").read_text())
    assert (doc["model"], doc["load"], doc["converged"]) == ("section", "lumen", True)
    assert doc["x_opt"]["a_int"] == pytest.approx(0.12, rel=1e-3)
    assert doc["x_opt"]["h"] == pytest.approx(0.015, rel=1e-3)
    assert (out / "calibration.png").is_file() and (out / "calibrated_design.toml").is_file()
    assert "space-mapping iteration" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("model", "load", "reason"),
    [("paper", "cap", "defined for the cap load"), ("section", "lumen", "the real load")],
)
def test_analytic_says_its_load_and_why(tmp_path, cli, model, load, reason):
    """The paper's formula is the cap-load formula by definition; the section model takes the real load,
    as every other command; the summary and analytic.json say which and why, and the curve is that
    load's (the same values as asking for the load explicitly)."""
    r = cli("analytic", "paper", "--model", model, "--pressure", "0.1,0.3", "--out", tmp_path / "d")
    assert r.status == 0
    assert f"({load} load" in r.out and f"load: {load}: " in r.out and reason in r.out
    doc = json.loads((tmp_path / "d" / "analytic.json").read_text())
    assert (doc["model"], doc["load"]) == (model, load) and reason in doc["load_reason"]
    argv = ("analytic", "paper", "--model", model, "--pressure", "0.1,0.3", "--load", load)
    assert cli(*argv, "--out", tmp_path / "e").status == 0
    _, a = _read(tmp_path / "d" / "analytic.csv")
    _, b = _read(tmp_path / "e" / "analytic.csv")
    np.testing.assert_array_equal(a, b)
