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
    assert "curvature" in text.out and "[1/4] meshing" in text.err


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
