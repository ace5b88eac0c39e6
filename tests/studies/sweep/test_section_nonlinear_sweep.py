"""The sweep's ``section-nonlinear`` evaluator, and select's re-check of large bends ranked on a linear
model."""

from __future__ import annotations

import json

import numpy as np
import pytest

from softcath.cli.main import main
from softcath.studies.report import design_of
from softcath.studies.sweep import load_spec, run_sweep
from softcath.studies.sweep.results import read_results

SPEC = """
[sweep]
name = "snl"
base = "paper"
pressures_MPa = [0.0, 0.3, 0.6]
loads = ["lumen"]
evaluators = ["analytic", "section", "section-nonlinear"]
[parameters]
"tube.h" = { values = [0.0, 0.03] }
"""


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    root = tmp_path_factory.mktemp("snl")
    (root / "spec.toml").write_text(SPEC, encoding="utf-8")
    summary = run_sweep(load_spec(root / "spec.toml"), root / "out", workers=1, progress=False)
    return summary, root / "out", read_results(root / "out")


def test_section_nonlinear_columns_equal_the_finite_strain_curve(sweep):
    from softcath.fem.section_model.finite_strain import section_curve

    summary, out, df = sweep
    assert summary.failed_designs == 0
    for did in sorted(df.design_id.unique()):
        rows = df[df.design_id == did].sort_values("pressure_MPa")
        c = section_curve(design_of(out, did), rows.pressure_MPa.to_numpy(float))
        # same code path, same mesh: equal to the Newton tolerance (1e-6 relative residual)
        np.testing.assert_allclose(
            rows.curvature_section_nonlinear_per_mm, c.curvature_per_mm, rtol=1e-6, atol=1e-12
        )
        np.testing.assert_allclose(
            rows.bend_angle_section_nonlinear_deg, np.degrees(c.bend_angle_rad), rtol=1e-6
        )
        np.testing.assert_allclose(
            rows.lumen_volume_change_section_nonlinear_mm3, c.lumen_volume_change_mm3, rtol=1e-6, atol=1e-12
        )
    # the best estimates come from the finite-strain section model, which bends more than the linear one
    assert set(df.source) == {"section-nonlinear"}
    np.testing.assert_array_equal(df.curvature_per_mm, df.curvature_section_nonlinear_per_mm)
    top = df[df.pressure_MPa == 0.6]
    assert (top.curvature_section_nonlinear_per_mm > 1.2 * top.curvature_section_per_mm).all()


def test_select_defaults_to_the_finite_strain_model(sweep, tmp_path, capsys):
    _, out, _ = sweep
    argv = [
        "select",
        str(out),
        "--constraint",
        "bend_angle_deg >= 30 at p_max",
        "--objective",
        "maximise bend_per_MPa_deg",
    ]
    assert main([*argv, "--out", str(tmp_path / "a")]) == 0
    doc = json.loads((tmp_path / "a" / "selection.json").read_text())
    assert doc["model"] == "section-nonlinear" and "recheck" not in doc


def test_select_rechecks_a_large_bend_ranked_on_the_linear_model(sweep, tmp_path, capsys):
    """Ranked on the linear section model, a 30 deg constraint asks bends past its validity: the
    ranked designs are re-checked with the finite-strain section model and ranked on its objectives."""
    _, out, df = sweep
    lin = df[df.pressure_MPa == 0.6].bend_angle_section_deg.max()
    fs = df[df.pressure_MPa == 0.6].bend_angle_section_nonlinear_deg.min()
    assert lin < 45 < fs  # the linear model misses what the tip does
    argv = [
        "select",
        str(out),
        "--model",
        "section",
        "--constraint",
        "bend_angle_deg >= 30 at p_max",
        "--objective",
        "maximise bend_per_MPa_deg",
    ]
    assert main([*argv, "--out", str(tmp_path / "b")]) == 0
    doc = json.loads((tmp_path / "b" / "selection.json").read_text())
    assert doc["model"] == "section-nonlinear" and doc["recheck"]["linear_model"] == "section"
    assert doc["recheck"]["n_rechecked"] == 2 and doc["recheck"]["n_passing"] == 2
    for r in doc["ranked"]:
        rows = df[(df.design_id == r["design_id"]) & (df.pressure_MPa == 0.6)]
        k = next(iter(r["objectives"]))
        assert r["objectives"][k] == pytest.approx(
            float(rows.bend_angle_section_nonlinear_deg.iloc[0]) / 0.6, rel=1e-6
        )
        assert r["linear_objectives"][k] == pytest.approx(
            float(rows.bend_angle_section_deg.iloc[0]) / 0.6, rel=1e-9
        )
    assert "validity" in capsys.readouterr().out
    # --no-recheck keeps the linear verdict
    assert main([*argv, "--no-recheck", "--out", str(tmp_path / "c")]) == 0
    doc = json.loads((tmp_path / "c" / "selection.json").read_text())
    assert doc["model"] == "section" and "recheck" not in doc


def test_a_rechecked_selection_agrees_across_summary_json_plot_and_report(sweep, tmp_path, capsys):
    """After the finite-strain re-check: plot, summary, JSON and report show the same values."""
    _, out, df = sweep
    objectives = ["maximise bend_per_MPa_deg", "minimise elongation at p_max"]
    argv = ["select", str(out), "--model", "section", "--constraint", "bend_angle_deg >= 30 at p_max"]
    for o in objectives:
        argv += ["--objective", o]
    capsys.readouterr()
    assert main(argv) == 0
    stdout = capsys.readouterr().out
    doc = json.loads((out / "selection.json").read_text())
    assert doc["model"] == "section-nonlinear" and doc["recheck"]["n_passing"] == len(doc["ranked"])
    # the Pareto plot's points are the re-checked designs on the finite-strain values they were ranked by
    assert doc["points"] == [
        [r["design_id"], int(r["pareto"]), *r["objectives"].values()] for r in doc["ranked"]
    ]
    assert len(doc["recheck"]["linear_points"]) >= len(doc["points"])
    assert f"still pass; Pareto front on section-nonlinear: {len(doc['pareto_front'])} of them" in stdout
    assert main(["report", str(out)]) == 0
    html = (out / "report" / "index.html").read_text()
    assert "re-checked designs that still pass" in html and "Pareto front on its values" in html
    for r in doc["ranked"]:
        assert r["tier"] == "section-nonlinear" and r["load"] == "lumen"
        line = next(
            ln for ln in stdout.splitlines() if ln.startswith(f"  #{r['rank']} design {r['design_id']}")
        )
        for text, value in r["objectives"].items():
            shown = f"{value:.4g}"
            assert f"{text.split(None, 1)[-1]} = {shown} [section-nonlinear, lumen load]" in line or (
                f"{text.split(None, 1)[-1]} = {shown}," in line
            )
            assert f"<td>{shown}</td>" in html  # the report's table: the same value, same digits


def test_the_explore_page_shows_the_selection_tiers_values(sweep, tmp_path, monkeypatch):
    """Ranked on the linear section model, the explore page's parameters-and-results chart shows that
    tier's values (the sweep's best estimates are the finite-strain model's), as the CLI and JSON do."""
    from softcath.studies.report import explore
    from softcath.studies.sweep.results import model_columns

    _, out, df = sweep
    argv = ["select", str(out), "--model", "section", "--no-recheck", "--objective", "minimise max_strain"]
    assert main([*argv, "--out", str(tmp_path / "sel")]) == 0
    sel = json.loads((tmp_path / "sel" / "selection.json").read_text())
    assert explore._selection_tier(df, sel) == "section"
    seen = {}
    monkeypatch.setattr(explore.ia, "parallel", lambda cols, color: seen.update(cols) or {})
    monkeypatch.setattr(explore.ia, "chart", lambda fig, name, caption: caption)
    caption = explore._parallel(df, ["tube.h"], "lumen", "section")
    assert "the section model's values" in caption
    lin = model_columns(df, "section")
    at = lin[(lin.status == "ok") & lin.at_p_max & (lin.load == "lumen")]
    assert "tube.h [mm]" in seen  # axes carry units
    np.testing.assert_array_equal(seen["max_strain [-]"], at.max_strain.to_numpy(float))
    best = sel["ranked"][0]
    assert best["objectives"]["minimise max_strain"] == pytest.approx(float(np.min(seen["max_strain [-]"])))
