"""``softcath select`` on a linear tier warns when its ranked designs bend past the tier's validity."""

from __future__ import annotations

import json

from softcath.cli.main import main


def test_select_warns_when_a_linear_tier_ranks_large_bends(small_spec, tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["sweep", str(small_spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    capsys.readouterr()
    # a strain constraint: no bend constraint, so no finite-strain re-check; the bends reach ~20 deg
    argv = ["select", str(out), "--constraint", "max_strain <= 0.3", "--objective", "maximise bend_angle_deg"]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "the paper's formula (paper) is a linear tier, valid to ~5 deg of bend" in err
    assert "--model section-nonlinear" in err
    data = json.loads((out / "selection.json").read_text())
    assert len(data["warnings"]) == 1 and "linear tier" in data["warnings"][0]


def test_no_warning_inside_the_linear_range(spec_writer, tmp_path, capsys):
    spec = spec_writer(
        """
        [sweep]
        name = "small-bends"
        base = "paper"
        pressures_MPa = [0.0, 0.05]
        loads = ["cap"]
        [parameters]
        "tube.h" = { values = [0.0, 0.01] }
        """
    )
    out = tmp_path / "o"
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    capsys.readouterr()
    assert main(["select", str(out), "--objective", "maximise bend_angle_deg"]) == 0
    assert "linear tier" not in capsys.readouterr().err
    assert "warnings" not in json.loads((out / "selection.json").read_text())
