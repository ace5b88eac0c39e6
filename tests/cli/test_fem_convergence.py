"""`softcath fem --nonlinear`: every result states its discretisation error; `--convergence`: three meshes.

The stated error is the layers part (a half-layer solve) plus the section part (two small-load
solves on the run's section and a refined one); both are checked here against their own solves.

Coarse section (0.3 mm, 8 segments per circle) and a small pressure keep the three solves short; the
physics of the estimate is checked on the pure functions (tests/fem/nonlinear/test_convergence.py) and
in one slow cross-check below.
"""

import csv
import json

import numpy as np
import pytest

from softcath import design
from softcath.cli.main import main
from softcath.fem.nonlinear.bend import bend_curve
from softcath.fem.nonlinear.convergence import observed_order, richardson_error
from softcath.fem.nonlinear.section_error import (
    AREA_TRUE_SECTION_ORDER,
    SECTION_ANGLE_DEG,
    SECTION_ORDER,
    section_correction,
)

COARSE = ["--mesh-size", "0.3", "--curvature-points", "8"]


def test_convergence_study_writes_table_picture_and_the_error_of_the_middle_mesh(tmp_path, capsys):
    out = tmp_path / "nl"
    args = ["fem", "paper", "--nonlinear", "--pressure", "0.02", "--steps", "1", "--layers", "6"]
    assert main([*args, *COARSE, "--convergence", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "convergence (3/6/12 layers)" in text and "estimated discretisation error" in text
    doc = json.loads((out / "fem.json").read_text())
    study = json.loads((out / "convergence.json").read_text())
    assert study["layers"] == [3, 6, 12] and doc["layers"] == 6 and doc["mixed"] is True
    k = np.array(study["curvature_mid_per_mm"])[:, 0]
    # the run's result is the middle mesh, its error stated from the coarse one with the stated order
    assert doc["curvature_mid_per_mm"] == pytest.approx(k[1])
    err = doc["discretisation_error"]
    assert err["coarse_layers"] == 3 and err["order_source"] in ("observed", "assumed")
    expected = richardson_error(k[1:2], k[0:1], layers=6, coarse_layers=3, order=err["order"])
    layers_part = err["parts"]["layers"]["relative"][0]
    assert layers_part == pytest.approx(float(expected[0]))
    # the study states the section part too: the total is the sum
    section_part = err["parts"]["section"]["relative"]
    assert doc["discretisation_error_estimate"] == pytest.approx(layers_part + section_part)
    q = observed_order(k, [3, 6, 12])
    assert study["observed_order"][0] == (None if np.isnan(q) else pytest.approx(q))
    with (out / "convergence.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [int(r["layers"]) for r in rows] == [3, 6, 12]
    with (out / "pressure_sweep.csv").open() as fh:
        sweep = list(csv.DictReader(fh))
    assert float(sweep[-1]["discretisation_error_estimate"]) == pytest.approx(
        doc["discretisation_error_estimate"], rel=1e-2
    )
    # at 1 deg of bend the layers hardly matter (measured 0.35 % between 3 and 6 layers)
    assert 0 <= layers_part < 0.02
    assert (out / "convergence.png").stat().st_size > 5000


def test_the_stated_section_error_is_richardson_of_two_real_small_load_solves(tmp_path, capsys):
    out = tmp_path / "nl"
    args = ["fem", "paper", "--nonlinear", "--pressure", "0.04", "--steps", "1", "--layers", "6"]
    assert main([*args, *COARSE, "--out", str(out)]) == 0
    assert "+ section" in capsys.readouterr().out
    doc = json.loads((out / "fem.json").read_text())
    err = doc["discretisation_error"]
    sec, lay = err["parts"]["section"], err["parts"]["layers"]
    assert sec["default_section"] == {"size_mm": 0.3, "curvature_points": 8}
    assert sec["refined_section"]["curvature_points"] == 12
    assert sec["refined_section"]["size_mm"] == pytest.approx(0.2)
    # the small load bends the run's linear FEM by the target angle (the run's ~2.2 deg is above it)
    p = sec["pressure_MPa"]
    unit = doc["linear_bend_angle_rad"] / doc["pressure_MPa"]
    assert p == pytest.approx(np.radians(SECTION_ANGLE_DEG) / unit, rel=1e-9) and p < 0.04

    # the two solves, redone here, give the recorded curvatures and the recorded Richardson step
    k = [
        float(bend_curve(design.resolve("paper"), [p], layers=4, size=s, curvature_points=n).curvature_mid[0])
        for s, n in ((0.3, 8), (0.2, 12))
    ]
    assert sec["curvature_mid_per_mm"] == pytest.approx(k, rel=1e-9)
    assert sec["order"] == SECTION_ORDER and doc["true_area"] is False
    corr = section_correction(k[0], k[1], ratio=1.5, order=SECTION_ORDER)
    assert sec["correction"] == pytest.approx(corr, rel=1e-9) and sec["relative"] == pytest.approx(abs(corr))
    # the coarse section under-fills the circles: the refined one bends more (measured +5 % here)
    assert k[1] > k[0]
    total = lay["relative"][0] + sec["relative"]
    assert doc["discretisation_error_estimate"] == pytest.approx(total)
    assert err["relative"] == [pytest.approx(total)]
    assert err["extrapolated"][0] == pytest.approx(lay["extrapolated"][0] * (1 + corr))
    with (out / "pressure_sweep.csv").open() as fh:
        row = next(csv.DictReader(fh))
    assert float(row["discretisation_error_estimate"]) == pytest.approx(total, rel=1e-2)
    assert float(row["discretisation_error_layers"]) == pytest.approx(lay["relative"][0], rel=1e-2)
    assert float(row["discretisation_error_section"]) == pytest.approx(sec["relative"], rel=1e-2)


def test_the_area_true_section_is_meshed_recorded_and_estimated_at_its_own_order(tmp_path):
    out = tmp_path / "area_true"
    args = ["fem", "paper", "--nonlinear", "--pressure", "0.02", "--steps", "1", "--layers", "6"]
    assert main([*args, *COARSE, "--area-true-section", "--out", str(out)]) == 0
    doc = json.loads((out / "fem.json").read_text())
    assert doc["true_area"] is True
    sec = doc["discretisation_error"]["parts"]["section"]
    assert sec["order"] == AREA_TRUE_SECTION_ORDER
    paper = design.resolve("paper")

    def kappa(p, s, n, layers=4):
        c = bend_curve(paper, [p], layers=layers, size=s, curvature_points=n, true_area=True)
        return float(c.curvature_mid[0])

    assert doc["curvature_mid_per_mm"] == pytest.approx(kappa(0.02, 0.3, 8, layers=6), rel=1e-9)
    k = [kappa(sec["pressure_MPa"], s, n) for s, n in ((0.3, 8), (0.2, 12))]
    assert sec["curvature_mid_per_mm"] == pytest.approx(k, rel=1e-9)
    assert sec["correction"] == pytest.approx(section_correction(k[0], k[1], ratio=1.5, order=1.0), rel=1e-9)


def test_too_few_layers_give_no_estimate_and_say_why(tmp_path):
    from softcath.fem.nonlinear import NonlinearSettings, run_check

    s = NonlinearSettings(pressure=0.01, steps=1, load="cap", layers=3, mesh_size=0.3, curvature_points=8)
    run_check(design.resolve("paper"), s, tmp_path)
    doc = json.loads((tmp_path / "fem.json").read_text())
    assert doc["discretisation_error_estimate"] is None
    assert "fewer than 6 layers" in doc["discretisation_error"]["method"]
    with (tmp_path / "pressure_sweep.csv").open() as fh:
        assert next(csv.DictReader(fh))["discretisation_error_estimate"] == "nan"
