"""Every number of a selection says where it comes from: tier and load by its values, units by parameters."""

from __future__ import annotations

import json

from softcath.cli.main import main
from softcath.design.reference import unit_of, with_unit


def test_units_come_from_the_design_file_reference():
    assert unit_of("tube.h") == "mm" and unit_of("tip.bending_length") == "mm"
    assert unit_of("materials.medical_silicone_tubing.youngs_modulus") == "MPa"
    assert unit_of("coil.initial_tension") == "N" and unit_of("nope.x") == ""
    assert with_unit("tube.h") == "tube.h [mm]" and with_unit("elongation") == "elongation [-]"
    assert with_unit("bend_angle_deg") == "bend_angle_deg"  # the name carries its unit


def test_select_summary_json_and_report_name_tier_load_and_units(small_spec, tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["sweep", str(small_spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    argv = ["select", str(out), "--constraint", "max_strain <= 0.3"]
    assert main([*argv, "--objective", "maximise bend_angle_deg", "--objective", "minimise elongation"]) == 0
    stdout = capsys.readouterr().out
    data = json.loads((out / "selection.json").read_text())
    first = data["ranked"][0]
    assert first["tier"] == "paper" and first["load"] == "cap"
    line = next(ln for ln in stdout.splitlines() if ln.startswith(f"  #1 design {first['design_id']}"))
    assert "[paper, cap load]" in line and f"tube.h={first['parameters']['tube.h']:.4g} mm" in line
    assert "designs meet the constraints (paper, cap load)" in stdout
    assert main(["report", str(out)]) == 0
    html = (out / "report" / "index.html").read_text()
    assert "<th>tube.h [mm]</th>" in html and "<th>minimise elongation [-]</th>" in html
