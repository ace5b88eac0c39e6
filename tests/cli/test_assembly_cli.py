"""``--assembly KEY=VALUE`` on section, analytic --model section and fem: recorded, validated."""

from __future__ import annotations

import json

import pytest

from softcath.cli.main import main


def test_section_records_the_assembly_it_used(tmp_path):
    out = tmp_path / "s"
    argv = ["section", "paper", "--no-png", "--assembly", "tube_coil=sliding", "--assembly", "filler=none"]
    assert main([*argv, "--out", str(out)]) == 0
    doc = json.loads((out / "section.json").read_text())
    assert doc["assembly"]["tube_coil"] == "sliding" and doc["assembly"]["filler"] == "none"
    assert doc["assembly"]["proximal"] == "clamped"
    default = tmp_path / "d"
    assert main(["section", "paper", "--no-png", "--out", str(default)]) == 0
    base = json.loads((default / "section.json").read_text())
    assert base["assembly"]["tube_coil"] == "bonded" and base["axial_groups"] == 1
    assert doc["curvature_per_mm_per_MPa"] != base["curvature_per_mm_per_MPa"]


def test_bad_override_is_refused_naming_key_and_allowed(tmp_path, capsys):
    assert main(["section", "paper", "--assembly", "filler=foam", "--out", str(tmp_path / "x")]) != 0
    assert "assembly.filler = 'foam': must be one of full, coat, none" in capsys.readouterr().err


def test_analytic_paper_formula_refuses_an_as_built_tip(tmp_path, capsys):
    argv = ["analytic", "paper", "--assembly", "tube_coil=sliding", "--out", str(tmp_path / "a")]
    assert main(argv) != 0
    assert (
        "is modelled by the section model, the finite-strain section model and the 3-D FEM only"
        in capsys.readouterr().err
    )
    argv = ["analytic", "paper", "--model", "section", "--pressure", "0:0.2:3"]
    assert main([*argv, "--assembly", "tube_coil=sliding", "--out", str(tmp_path / "b")]) == 0


def test_fem_nonlinear_refuses_sliding_interfaces_before_meshing(tmp_path, capsys):
    argv = [
        "fem",
        "paper",
        "--nonlinear",
        "--assembly",
        "channel_coil=tied-at-tip",
        "--out",
        str(tmp_path / "f"),
    ]
    assert main(argv) != 0
    assert "assembly.channel_coil = 'tied-at-tip'" in capsys.readouterr().err


@pytest.mark.parametrize("cmd", ["section", "fem", "analytic"])
def test_help_lists_the_option(cmd, capsys):
    try:
        main([cmd, "--help"])
    except SystemExit:
        pass
    assert "--assembly KEY=VALUE" in capsys.readouterr().out


@pytest.mark.slow
def test_fem_linear_takes_sliding_interfaces_and_records_them(tmp_path):
    out = tmp_path / "f"
    argv = [
        "fem",
        "paper",
        "--pressure",
        "0.1",
        "--load",
        "lumen",
        "--no-png",
        "--assembly",
        "tube_coil=sliding",
    ]
    assert main([*argv, "--out", str(out)]) == 0
    doc = json.loads((out / "fem.json").read_text())
    assert doc["assembly"]["tube_coil"] == "sliding"
    # the section model as built, within the 3 % of the as-built cross-check
    from dataclasses import replace

    from softcath import design
    from softcath.design.assembly import Assembly
    from softcath.fem.section_model import section_model

    d = replace(design.preset("paper"), assembly=Assembly(tube_coil="sliding"))
    gain = section_model(d).curvature_per_mm_per_MPa["lumen"]
    assert doc["curvature_per_mm"] / 0.1 == pytest.approx(gain, rel=0.03)
