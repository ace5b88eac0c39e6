"""What a command writes is what the library writes: each writer called directly, byte for byte.

Every command below is run through the command line and its library function is called
directly into another folder with the same inputs; the files must be the same bytes. The
only exceptions are a run's facts that differ between two runs of the same thing: its wall
times (``seconds``) and whether the mesh came from the cache (``mesh_cached``).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from softcath import design
from softcath.studies.outputs.analytic import analytic_run
from softcath.studies.outputs.fem_check import fem_check, paper_formula
from softcath.studies.outputs.overlay import overlay
from softcath.studies.outputs.predict import prediction_run
from softcath.studies.outputs.section import curve_response, section_run
from softcath.studies.outputs.selection import selection_run

CLI_MODULES = (
    "fem",
    "analytic",
    "section",
    "section_overlay",
    "select",
    "optimise",
    "predict",
    "discrepancy",
)
CLI = Path(__file__).resolve().parents[2] / "cli"


def _same_bytes(a: Path, b: Path, names) -> None:
    for name in names:
        assert (a / name).read_bytes() == (b / name).read_bytes(), name


def _without_times(value):
    """A JSON document without its wall times and cache use, which differ run to run."""
    if isinstance(value, dict):
        return {k: _without_times(v) for k, v in value.items() if "seconds" not in k and k != "mesh_cached"}
    if isinstance(value, list):
        return [_without_times(v) for v in value]
    return value


def _json(path: Path) -> dict:
    doc = _without_times(json.loads(path.read_text(encoding="utf-8")))
    assert isinstance(doc, dict), path
    return doc


@pytest.mark.parametrize("module", CLI_MODULES)
def test_the_command_line_composes_no_result_file(module):
    text = (CLI / f"{module}.py").read_text(encoding="utf-8")
    for writer in ("csv.", "json.dump", "savefig", "o.json(", ".write_text(", "matplotlib"):
        assert writer not in text, f"cli/{module}.py writes with {writer}: the library's writer should"


@pytest.mark.parametrize("model", ["paper", "section"])
def test_analytic_files_are_the_librarys(tmp_path, cli, model):
    assert (
        cli("analytic", "paper", "--model", model, "--pressure", "0:0.5:6", "--out", tmp_path / "c").status
        == 0
    )
    run = analytic_run(design.resolve("paper"), np.linspace(0, 0.5, 6), model=model)
    assert run.write(tmp_path / "l") == ("analytic.csv", "analytic.png", "analytic.json")
    _same_bytes(tmp_path / "c", tmp_path / "l", ("analytic.csv", "analytic.json", "analytic.png"))


def test_section_files_are_the_librarys(tmp_path, cli):
    assert cli("section", "paper", "--pressure", "0:0.4:5", "--out", tmp_path / "c").status == 0
    run = section_run(design.resolve("paper"), np.linspace(0, 0.4, 5))
    assert run.write(tmp_path / "l") == ("section.json", "section.csv", "section.png")
    _same_bytes(tmp_path / "c", tmp_path / "l", ("section.csv", "section.png"))
    assert _json(tmp_path / "c" / "section.json") == _json(tmp_path / "l" / "section.json")


def test_coil_bound_section_files_are_the_librarys(tmp_path, cli):
    argv = ("section", "paper", "--pressure", "0:0.4:5", "--coil-bound", "--no-png")
    assert cli(*argv, "--out", tmp_path / "c").status == 0
    run = section_run(
        design.resolve("paper"),
        np.linspace(0, 0.4, 5),
        coil_options={"coil_modulus": "tension", "coil_bending": "resolved"},
        coil_bound="resolved",
        keep_fields=False,
    )
    assert run.write(tmp_path / "l", picture=False) == ("section.json", "section.csv")
    _same_bytes(tmp_path / "c", tmp_path / "l", ("section.csv",))
    doc = _json(tmp_path / "l" / "section.json")
    assert _json(tmp_path / "c" / "section.json") == doc and "coil_bound" in doc


def test_the_coil_bound_tip_pose_is_eq_9():
    """The bilinear curve's pose is the arc's closed form, x = (1 - cos kL)/k, y = sin(kL)/k."""
    run = section_run(
        design.resolve("paper"),
        [0.2, 0.4],
        coil_bound="resolved",
        keep_fields=False,
        coil_options={"coil_modulus": "tension", "coil_bending": "resolved"},
    )
    c = run.curve
    assert c is not None
    r = curve_response(c, run.result.length_mm)
    length = run.result.length_mm * (1 + c.elongation)
    k = c.curvature
    np.testing.assert_allclose(r.tip_x, (1 - np.cos(k * length)) / k, rtol=1e-12)
    np.testing.assert_allclose(r.tip_y, np.sin(k * length) / k, rtol=1e-12)
    np.testing.assert_allclose(r.bend_angle, k * length, rtol=1e-12)


def test_overlay_files_are_the_librarys(tmp_path, cli):
    d = design.preset("paper")
    v = d.with_tube_shape(**{**d.tube_shape, "h": 0.02})
    other = tmp_path / "offset.toml"
    other.write_text(design.dumps(v.__class__(**{**v.__dict__, "name": "offset tube"})))
    argv = ("section", "paper", other, "--pressure", "0:0.3:4")
    assert cli(*argv, "--out", tmp_path / "c").status == 0
    designs = [design.resolve("paper"), design.resolve(str(other))]
    ov = overlay(designs, np.linspace(0, 0.3, 4), sources=["paper", str(other)])
    assert ov.write(tmp_path / "l") == ("overlay.csv", "overlay.json", "overlay.png")
    _same_bytes(tmp_path / "c", tmp_path / "l", ("overlay.csv", "overlay.json", "overlay.png"))
    rows = ov.to_table()
    assert len(rows) == 8 and {r["design"] for r in rows} == {"paper", "offset tube"}


def test_an_overlay_tells_one_name_given_twice_apart_by_its_source(tmp_path):
    d = design.resolve("paper")
    ov = overlay([d, d], [0.1], sources=["paper", "copy.toml"])
    assert [c.label for c in ov.curves] == ["paper (paper)", "paper (copy.toml)"]


#: Absolute tolerances of differences of near-equal numbers: the curvature variation is
#: (max - min) / mean of local curvatures that agree to ~0.2 %, so the solver's ~1e-6 relative
#: rounding reaches it divided by 0.0017 (measured 4e-7 absolute, 2.5e-4 relative). The linear
#: check's discretisation error estimate is (k_h - k_2h) / 3 / k_h of curvatures 1.4 % apart
#: (measured 3.8e-7 absolute, 8e-5 relative between two runs).
_DIFFERENCE_ABS = {"curvature_variation": 5e-6, "discretisation_error_estimate": 5e-6, "relative": 5e-6}


def _same_numbers(a, b, *, rel: float, abs_tol: float = 1e-7) -> None:
    """``a == b`` with floats compared to ``rel`` (nested dicts and lists)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys()
        for k in a:
            _same_numbers(a[k], b[k], rel=rel, abs_tol=_DIFFERENCE_ABS.get(k, abs_tol))
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b)
        for x, y in zip(a, b, strict=True):
            _same_numbers(x, y, rel=rel, abs_tol=abs_tol)
    elif isinstance(a, float) and isinstance(b, float):
        assert a == pytest.approx(b, rel=rel, abs=abs_tol)
    else:
        assert a == b


def test_fem_json_is_the_librarys(tmp_path, cli):
    assert cli("fem", "paper", "--pressure", "0.1", "--no-png", "--out", tmp_path / "c").status == 0
    fc = fem_check(design.resolve("paper"), 0.1)
    assert fc.write(tmp_path / "l", picture=False) == ("fem.json", "tip.vtu")
    doc = _json(tmp_path / "l" / "fem.json")
    # two 3-D solves of one design: the same keys and values up to the solver's rounding
    # (measured 5e-7 to 1.1e-6 relative between a run that meshes and one that reads the mesh cache)
    _same_numbers(_json(tmp_path / "c" / "fem.json"), doc, rel=1e-5)
    assert doc["paper_formula"] == paper_formula(design.resolve("paper"), 0.1, fc.case.curvature_per_mm)


def test_the_paper_formula_block_is_the_cap_load_formula():
    """kappa = 0.0756 1/(mm MPa) for the paper tip under the cap load (the analytic tier's own gain)."""
    from softcath import analytic

    d = design.resolve("paper")
    block = paper_formula(d, 0.2, 0.03)
    ref = analytic.response(d, 0.2, load="cap")
    assert block["load"] == "cap" and block["curvature_per_mm"] == pytest.approx(
        float(ref.curvature), rel=1e-15
    )
    assert block["curvature_per_mm"] / 0.2 == pytest.approx(0.0756, rel=5e-3)
    assert block["ratio_fem_over_formula"] == pytest.approx(0.03 / block["curvature_per_mm"], rel=1e-15)
    assert paper_formula(d, 0.0, 0.0)["ratio_fem_over_formula"] is None


def test_prediction_files_are_the_librarys(tmp_path, cli):
    argv = ("predict", "paper", "--model", "paper", "--samples", "16", "--seed", "3", "--no-progress")
    assert cli(*argv, "--out", tmp_path / "c").status == 0
    run = prediction_run("paper", model="paper", samples=16, seed=3)
    assert run.write(tmp_path / "l") == ("prediction.json", "samples.csv", "prediction.png")
    _same_bytes(tmp_path / "c", tmp_path / "l", ("samples.csv", "prediction.png"))
    assert _json(tmp_path / "c" / "prediction.json") == _json(tmp_path / "l" / "prediction.json")
    header, rows = run.to_table()
    assert header[:2] == ["tier", "load"] and len(rows) == 16


def test_selection_files_are_the_librarys(spec_writer, tmp_path, cli):
    spec = spec_writer(
        '[sweep]\nbase = "paper"\npressures_MPa = [0.5, 1.0]\nchunk_size = 2\n'
        '[parameters]\n"tube.h" = { values = [-0.02, 0.0, 0.02] }\n'
    )
    sweep = tmp_path / "q"
    assert cli("sweep", spec, "--out", sweep, "--workers", "1", "--no-progress").status == 0
    obj = "maximise bend_per_MPa_deg"
    argv = ("select", sweep, "--objective", obj, "--constraint", "bend_angle_deg >= 1 at p_max")
    assert cli(*argv, "--out", tmp_path / "c").status == 0
    run = selection_run(
        sweep, objectives=[obj], constraints=["bend_angle_deg >= 1 at p_max"], out=tmp_path / "l"
    )
    assert run.path == tmp_path / "l" / "selection.json"
    assert run.path.read_bytes() == (tmp_path / "c" / "selection.json").read_bytes()
    names = sorted(p.relative_to(tmp_path / "c") for p in (tmp_path / "c").rglob("*.toml"))
    assert names and names == sorted(p.relative_to(tmp_path / "l") for p in (tmp_path / "l").rglob("*.toml"))
    _same_bytes(tmp_path / "c", tmp_path / "l", names)
