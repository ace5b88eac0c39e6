"""`softcath fem` (linear): every run states its discretisation error; `--convergence`: three meshes.

A coarse mesh (0.2 mm, 5 layers; companion 0.4 mm) keeps the runs to seconds; the estimate's
size against a finer mesh is checked in tests/fem/test_fem_discretisation.py (slow).
"""

import csv
import json

import pytest

from softcath.cli.main import main
from softcath.fem.nonlinear.convergence import observed_order, richardson_error

RUN = ["fem", "paper", "--pressure", "0.1", "--load", "cap", "--mesh-size", "0.2", "--no-png"]


def test_a_linear_run_states_its_discretisation_error(tmp_path, capsys):
    out = tmp_path / "lin"
    assert main([*RUN, "--out", str(out)]) == 0
    text = capsys.readouterr().out
    doc = json.loads((out / "fem.json").read_text())
    err = doc["discretisation_error"]
    assert err["mesh_size_mm"] == 0.2 and err["companion_mesh_size_mm"] == 0.4
    assert err["order"] == 2.0 and err["order_source"] == "assumed"
    k, kc = doc["curvature_per_mm"], err["companion_curvature_per_mm"]
    expected = richardson_error([k], [kc], layers=5.0, coarse_layers=2.5, order=2.0)[0]
    assert doc["discretisation_error_estimate"] == pytest.approx(expected, rel=1e-9)
    assert f"{100 * expected:.2g} % (Richardson vs 0.4 mm, order 2 assumed" in text
    assert not (out / "convergence.csv").exists()


def test_convergence_runs_three_meshes_and_states_the_order(tmp_path, capsys):
    out = tmp_path / "study"
    assert main([*RUN, "--convergence", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    study = json.loads((out / "convergence.json").read_text())
    assert study["mesh_size_mm"] == [0.4, 0.2, 0.1] and study["load"] == "cap"
    k = [row[0] for row in study["curvature_per_mm"]]
    q = observed_order(k, [2.5, 5.0, 10.0])
    # measured 2.22 on this coarse sequence (3/5/10 layers; the lumen load's default study: 2.23)
    assert study["observed_order"] == pytest.approx(q) and 1.5 <= q <= 3.5
    assert f"observed order {q:.3g}" in text and "convergence (mesh 0.4/0.2/0.1 mm" in text
    with (out / "convergence.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert [float(r["mesh_size_mm"]) for r in rows] == [0.4, 0.2, 0.1]
    assert [int(r["ndofs"]) for r in rows] == study["ndofs"] and all(float(r["seconds"]) > 0 for r in rows)
    # the run's answer is the middle mesh, its error from the coarse one with the observed order
    doc = json.loads((out / "fem.json").read_text())
    assert doc["curvature_per_mm"] == pytest.approx(k[1], rel=1e-9)
    assert doc["discretisation_error"]["order_source"] == "observed"
    stated = richardson_error([k[1]], [k[0]], layers=5.0, coarse_layers=2.5, order=q)[0]
    assert doc["discretisation_error_estimate"] == pytest.approx(stated, rel=1e-6)
    assert f"{100 * stated:.2g} %" in text
    assert (out / "convergence.png").stat().st_size > 5000
