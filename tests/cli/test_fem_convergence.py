"""`softcath fem --nonlinear`: every result states its discretisation error; `--convergence`: three meshes.

Coarse section (0.3 mm, 8 segments per circle) and a small pressure keep the three solves short; the
physics of the estimate is checked on the pure functions (tests/fem/nonlinear/test_convergence.py) and
in one slow cross-check below.
"""

import csv
import json

import numpy as np
import pytest

from softcath.cli.main import main
from softcath.fem.nonlinear.convergence import observed_order, richardson_error

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
    assert doc["discretisation_error_estimate"] == pytest.approx(float(expected[0]))
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
    assert 0 <= doc["discretisation_error_estimate"] < 0.02
    assert (out / "convergence.png").stat().st_size > 5000


def test_too_few_layers_give_no_estimate_and_say_why(tmp_path):
    from softcath import design
    from softcath.fem.nonlinear import NonlinearSettings, run_check

    s = NonlinearSettings(pressure=0.01, steps=1, load="cap", layers=3, mesh_size=0.3, curvature_points=8)
    run_check(design.resolve("paper"), s, tmp_path)
    doc = json.loads((tmp_path / "fem.json").read_text())
    assert doc["discretisation_error_estimate"] is None
    assert "fewer than 6 layers" in doc["discretisation_error"]["method"]
    with (tmp_path / "pressure_sweep.csv").open() as fh:
        assert next(csv.DictReader(fh))["discretisation_error_estimate"] == "nan"
