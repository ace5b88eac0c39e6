"""``softcath section`` end to end."""

from __future__ import annotations

import csv
import json

from softcath.cli.main import main

KEYS = (
    "curvature_per_mm_per_MPa",
    "elongation_per_MPa",
    "EA_N",
    "EI_N_mm2",
    "neutral_axis_mm",
    "lumen_area_change_mm2_per_MPa",
    "dofs",
    "seconds",
    "load",
    "poisson_ratio_silicone",
    "fem_formula_ratio",
)


def test_section_command_writes_json_csv_png(tmp_path, capsys):
    out = tmp_path / "s"
    assert main(["section", "paper", "--pressure", "0:0.5:6", "--poisson", "0.4999", "--out", str(out)]) == 0
    doc = json.loads((out / "section.json").read_text())
    assert set(KEYS) <= set(doc)
    assert doc["load"] == "lumen" and doc["poisson_ratio_silicone"] == 0.4999
    assert doc["loads"]["curvature_per_mm_per_MPa"]["cap"] < doc["curvature_per_mm_per_MPa"]
    with (out / "section.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == [
        "pressure_MPa",
        "curvature_per_mm",
        "elongation",
        "bend_angle_rad",
        "tip_x_mm",
        "tip_y_mm",
    ]
    assert float(rows[-1]["curvature_per_mm"]) == pytest_approx(0.5 * doc["curvature_per_mm_per_MPa"])
    assert (out / "section.png").stat().st_size > 10_000
    assert "section.json" in capsys.readouterr().out


def pytest_approx(x):
    import pytest

    return pytest.approx(x, rel=1e-6)


def test_bad_poisson_is_one_line(tmp_path, capsys):
    assert main(["section", "paper", "--poisson", "0.6", "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--poisson = 0.6" in err[0]


def test_coil_models_and_coil_bound(tmp_path, capsys):
    import pytest

    from softcath.fem.section_model import bend_curve, section_model

    out = tmp_path / "r"
    assert main(["section", "paper", "--coil-model", "resolved", "--no-png", "--out", str(out)]) == 0
    doc = json.loads((out / "section.json").read_text())
    assert doc["coil_bending"] == "resolved" and "coil_bound" not in doc
    lin = section_model("paper", coil_bending="resolved").curvature_per_mm_per_MPa["lumen"]
    assert doc["curvature_per_mm_per_MPa"] == pytest.approx(lin, rel=1e-9)

    out = tmp_path / "b"
    args = ["section", "paper", "--pressure", "0:0.6:7", "--initial-tension", "0.005", "--out", str(out)]
    assert main(args) == 0
    doc = json.loads((out / "section.json").read_text())
    curve = bend_curve("paper", [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6], initial_tension=(0.005, 0.0))
    assert doc["coil_bound"]["threshold_pressure"] == pytest.approx(curve.threshold_pressure, rel=1e-9)
    with (out / "section.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    got = [float(r["curvature_per_mm"]) for r in rows]
    assert got == pytest.approx(curve.curvature.tolist(), rel=1e-6, abs=1e-15)
    assert (out / "section_curve.png").stat().st_size > 10_000
    assert "threshold" in capsys.readouterr().out


def test_coil_options_conflict_is_one_line(tmp_path, capsys):
    argv = [
        "section",
        "paper",
        "--coil-model",
        "wahl",
        "--coil-bending",
        "wahl",
        "--out",
        str(tmp_path / "x"),
    ]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--coil-model" in err[0]
    assert (
        main(["section", "paper", "--coil-model", "wahl", "--coil-bound", "--out", str(tmp_path / "y")]) == 2
    )
    assert "--coil-bound" in capsys.readouterr().err
    assert main(["section", "paper", "--initial-tension", "a,b,c", "--out", str(tmp_path / "z")]) == 2
    assert "--initial-tension" in capsys.readouterr().err


def test_mesher_option_template_and_gmsh_agree_on_a_random_design(tmp_path, capsys):
    """The template mesher (default) and a fresh gmsh mesh, within the template's 0.2 % bound."""
    import pytest

    from softcath.design.io import save
    from softcath.studies.sweep.random_designs import random_designs

    path = save(random_designs(1, seed=47)[0], tmp_path / "d.toml")
    k = {}
    for mesher in ("template", "gmsh"):
        out = tmp_path / mesher
        assert main(["section", str(path), "--mesher", mesher, "--no-png", "--out", str(out)]) == 0
        k[mesher] = json.loads((out / "section.json").read_text())["curvature_per_mm_per_MPa"]
    assert k["template"] == pytest.approx(k["gmsh"], rel=2e-3)
    assert main(["section", "paper", "--mesher", "delaunay", "--out", str(tmp_path / "x")]) != 0
    assert "--mesher = 'delaunay': invalid choice" in capsys.readouterr().err
