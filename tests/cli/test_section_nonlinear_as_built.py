"""``softcath section DESIGN --nonlinear`` with a design file of the tip as built."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

from softcath import design
from softcath.cli.main import main
from softcath.design.assembly import Assembly
from softcath.fem.section_model.finite_strain import section_curve


def test_nonlinear_section_takes_an_as_built_design_file(tmp_path, capsys):
    d = replace(design.preset("paper"), assembly=Assembly(tube_coil="sliding", filler="coat"))
    path = tmp_path / "as_built.toml"
    path.write_text(design.dumps(d), encoding="utf-8")
    out = tmp_path / "s"
    argv = ["section", str(path), "--nonlinear", "--pressure", "0:0.4:3", "--no-png", "--out", str(out)]
    assert main(argv) == 0
    doc = json.loads((out / "section.json").read_text())
    assert doc["assembly"]["tube_coil"] == "sliding" and doc["assembly"]["filler"] == "coat"
    slip = doc["interface_slip_per_element"]
    assert len(slip) == 3 and slip[0] == 0.0 and 0.0 < slip[1] < slip[2]
    # what the command wrote is the library's curve of the same design
    c = section_curve(d, [0.0, 0.2, 0.4])
    assert doc["curvature_per_mm"] == pytest.approx(c.curvature_per_mm.tolist(), rel=1e-9)
    assert "largest interface slip" in capsys.readouterr().out


def test_nonlinear_section_takes_assembly_overrides(tmp_path):
    out = tmp_path / "s"
    argv = ["section", "paper", "--nonlinear", "--pressure", "0.2", "--no-png", "--assembly", "filler=none"]
    assert main([*argv, "--out", str(out)]) == 0
    doc = json.loads((out / "section.json").read_text())
    assert doc["assembly"]["filler"] == "none" and doc["interface_slip_per_element"] == [0.0]
