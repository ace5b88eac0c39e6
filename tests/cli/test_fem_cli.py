"""The ``softcath fem`` command line, in-process and as a subprocess."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from softcath.cli.main import main

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
def test_cli_writes_json_vtu_png(tmp_path, capsys):
    out = tmp_path / "out"
    code = main(
        ["fem", "paper", "--pressure", "0.1", "--load", "cap", "--out", str(out), "--mesh-size", "0.25"]
    )
    assert code == 0
    doc = json.loads((out / "fem.json").read_text())
    assert doc["load"] == "cap" and doc["pressure_MPa"] == 0.1
    assert doc["analytic"]["curvature_per_mm"] > 0
    assert doc["ratio_fem_over_analytic"]["curvature_per_mm"] == pytest.approx(
        doc["curvature_per_mm"] / doc["analytic"]["curvature_per_mm"], rel=1e-12
    )
    import pyvista as pv

    grid = pv.read(str(out / "tip.vtu"))
    assert grid.n_cells == doc["n_elements"]
    assert {"displacement"} <= set(grid.point_data) and "region" in grid.cell_data
    png = (out / "tip.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 5000
    # the rotatable view: self-contained and small (tests/browser opens it in Chromium)
    page = (out / "tip.html").read_text()
    assert "<canvas" in page and "http" not in page and len(page) < 600_000
    text = capsys.readouterr()
    assert "curvature" in text.out and "[1/5] meshing" in text.err


def test_cli_bad_input_exits_2_naming_the_parameter(tmp_path):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "softcath",
            "fem",
            "paper",
            "--pressure",
            "0.1",
            "--out",
            str(tmp_path),
            "--mesh-size",
            "0.001",
            "--no-png",
        ],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines()[-1].startswith("softcath fem: error: --mesh-size = 0.001")


def test_the_default_load_is_lumen_and_the_formula_beside_it_is_softcath_analytics(cli, tmp_path):
    """``fem`` without ``--load`` runs the real (lumen) load and shows the paper's formula under the cap
    load it is defined for: the same curvature and bend ``softcath analytic`` gives at that pressure."""
    import csv

    run = cli("fem", "paper", "--pressure", "0.1", "--mesh-size", "0.3", "--no-png", "--out", tmp_path / "f")
    assert run.status == 0
    assert cli("analytic", "paper", "--pressure", "0.1", "--out", tmp_path / "a").status == 0
    with (tmp_path / "a" / "analytic.csv").open() as fh:
        ref = list(csv.DictReader(fh))[-1]
    doc = json.loads((tmp_path / "f" / "fem.json").read_text())
    assert doc["load"] == "lumen" and doc["analytic"]["load"] == "lumen"
    formula = doc["paper_formula"]
    assert formula["load"] == "cap"
    assert formula["curvature_per_mm"] == pytest.approx(float(ref["curvature_per_mm"]), rel=1e-9)
    assert formula["bend_angle_rad"] == pytest.approx(float(ref["bend_angle_rad"]), rel=1e-9)
    assert formula["ratio_fem_over_formula"] == pytest.approx(
        doc["curvature_per_mm"] / formula["curvature_per_mm"], rel=1e-12
    )
    # the lumen load bends the tip 2-4x the cap force alone (docs/fem.md: 3.1x on this mesh size)
    assert 2 < formula["ratio_fem_over_formula"] < 4
    assert "lumen load at 0.1 MPa" in run.out
    assert f"cap load by definition: {formula['curvature_per_mm']:.4g}" in run.out
