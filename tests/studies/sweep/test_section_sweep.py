"""The sweep's ``section`` evaluator: values, failures per design, spec options, derived columns."""

from __future__ import annotations

import json

import numpy as np
import pytest

from softcath.design.errors import DesignError
from softcath.studies.report import design_of
from softcath.studies.sweep import load_spec, run_sweep
from softcath.studies.sweep.results import model_columns, read_results
from softcath.studies.sweep.spec import SECTION_MIN_CHUNK, parse_spec

SPEC = """
[sweep]
name = "sec"
base = "paper"
pressures_MPa = [0.0, 0.5, 1.0]
loads = ["cap", "lumen"]
evaluators = ["analytic", "section"]
[parameters]
"tube.h" = { values = [0.0, 0.03, 0.06] }
"materials.medical_silicone_tubing.poisson_ratio" = { values = [0.49, 0.4999999] }
"""


@pytest.fixture(scope="module")
def section_sweep(tmp_path_factory):
    """6 designs: h = 0.06 is invalid; nu = 0.4999999 is a valid design the section model refuses."""
    root = tmp_path_factory.mktemp("section_sweep")
    (root / "spec.toml").write_text(SPEC, encoding="utf-8")
    summary = run_sweep(load_spec(root / "spec.toml"), root / "out", workers=1, progress=False)
    return summary, root / "out", read_results(root / "out")


def test_section_columns_equal_the_section_model_of_each_design(section_sweep):
    from softcath.fem.section_model import section_model
    from softcath.fem.section_model.strain import silicone_strain_range

    _, out, df = section_sweep
    ok = df[df.status == "ok"]
    assert sorted(ok.design_id.unique()) == [0, 2]  # h = 0, 0.03 at nu = 0.49
    for did in (0, 2):
        d = design_of(out, did)
        r = section_model(d, keep_fields=True)
        for load in ("cap", "lumen"):
            rows = ok[(ok.design_id == did) & (ok.load == load)].sort_values("pressure_MPa")
            p = rows.pressure_MPa.to_numpy(float)
            ref = r.response(p, load)
            # Same code path, same mesh: equal to round-off.
            np.testing.assert_allclose(rows.curvature_section_per_mm, ref.curvature, rtol=1e-10, atol=0)
            np.testing.assert_allclose(rows.elongation_section, ref.elongation, rtol=1e-10, atol=0)
            np.testing.assert_allclose(rows.tip_x_section_mm, ref.tip_x, rtol=1e-10, atol=1e-15)
            np.testing.assert_allclose(rows.bend_angle_section_deg, np.degrees(ref.bend_angle), rtol=1e-10)
            assert rows.max_strain_section.to_numpy() == pytest.approx(p * silicone_strain_range(r, load)[1])
            # The ratio to the paper's formula is the section curvature over the analytic cap load.
            cap = ok[(ok.design_id == did) & (ok.load == "cap")].sort_values("pressure_MPa")
            pos = p > 0
            np.testing.assert_allclose(
                rows.section_formula_ratio.to_numpy()[pos],
                rows.curvature_section_per_mm.to_numpy()[pos] / cap.curvature_analytic_per_mm.to_numpy()[pos],
                rtol=1e-10,
            )
            assert (rows.section_seconds > 0).all()
    # Best estimates come from the section model where it ran (no FEM here).
    assert set(ok.source) == {"section"}
    np.testing.assert_array_equal(ok.curvature_per_mm, ok.curvature_section_per_mm)
    np.testing.assert_array_equal(ok.max_strain, ok.max_strain_section)
    assert ok.fem_formula_ratio.isna().all() and ok.rel_diff_fem_section_curvature.isna().all()


def test_a_design_the_section_model_refuses_is_a_failed_row_with_its_reason(section_sweep):
    summary, out, df = section_sweep
    per = df.drop_duplicates("design_id").set_index("design_id")
    assert summary.n_designs == 6 and summary.failed_designs == 4
    for did in (1, 3):  # nu = 0.4999999: valid design, beyond the section model's nu <= 0.49999
        assert per.at[did, "status"] == "failed"
        assert per.at[did, "reason"].startswith("section failed: DesignError: poisson_ratio")
        rows = df[df.design_id == did]
        assert np.isfinite(rows.curvature_analytic_per_mm).all()  # the analytic values are kept
        assert rows.curvature_section_per_mm.isna().all()
    for did in (4, 5):
        assert per.at[did, "reason"].startswith("invalid design: tube.h")
    units = json.loads((out / "columns.json").read_text())
    assert units["curvature_section_per_mm"] == "1/mm" and units["section_seconds"] == "s"


def test_model_columns_pick_one_model(section_sweep):
    _, _, df = section_sweep
    paper = model_columns(df, "paper")
    np.testing.assert_array_equal(paper.bend_angle_deg, paper.bend_angle_analytic_deg)
    sec = model_columns(df, "section")
    p = sec.pressure_MPa.to_numpy(float)
    np.testing.assert_allclose(
        sec.bend_per_MPa_deg[p > 0], np.degrees(sec.bend_angle_section_rad[p > 0]) / p[p > 0], rtol=1e-12
    )
    assert model_columns(df, "fem").curvature_per_mm.isna().all()
    with pytest.raises(DesignError, match="model = 'beam'"):
        model_columns(df, "beam")


def _spec(extra: str, evaluators: str = '["paper", "section"]') -> dict:
    import tomllib

    return tomllib.loads(
        f"""
[sweep]
base = "paper"
pressures_MPa = [1.0]
evaluators = {evaluators}
chunk_size = 500
{extra}
[parameters]
"tube.h" = {{ values = [0.0] }}
"""
    )


@pytest.mark.parametrize(
    ("n", "chunk_size", "expected"),
    [(200, 500, 25), (300, 500, 38), (2000, 500, 250), (10**5, 500, 500), (10**5, 80, 80)],
)
def test_section_tasks_keep_every_worker_busy_and_share_templates(n, chunk_size, expected):
    import tomllib

    spec = parse_spec(
        tomllib.loads(
            f'[sweep]\nbase = "paper"\npressures_MPa = [1.0]\nevaluators = ["paper", "section"]\n'
            f"chunk_size = {chunk_size}\n[sample]\nn = {n}\n"
            '[parameters]\n"tube.h" = { lhs = [-0.02, 0.02] }\n'
            '"tip.bending_length" = { values = [4.0, 5.0] }\n'
        )
    )
    assert spec.n_designs == 2 * n
    assert spec.effective_chunk_size == expected  # 2n designs: 16 tasks at least, 25 to 500 designs each


@pytest.mark.parametrize(
    ("n", "chunk_size", "expected"),
    [(50, 500, 8), (400, 500, 25), (10**5, 500, 125), (10**5, 40, 40)],
)
def test_finite_strain_tasks_balance_small_sweeps_and_stay_short(n, chunk_size, expected):
    import tomllib

    spec = parse_spec(
        tomllib.loads(
            f'[sweep]\nbase = "paper"\npressures_MPa = [0.3]\nevaluators = ["paper", "section-nonlinear"]\n'
            f"chunk_size = {chunk_size}\n[sample]\nn = {n}\n"
            '[parameters]\n"tube.h" = { lhs = [-0.02, 0.02] }\n'
        )
    )
    assert spec.n_designs == n
    assert spec.effective_chunk_size == expected  # 16 tasks at least, 8 to 125 designs each


def test_spec_section_options_and_chunks():
    spec = parse_spec(_spec('[sweep.section]\nmesh_size = 0.08\ncoil_bending = "wahl"'))
    assert spec.evaluators == ("paper", "section")
    assert spec.section_options == {"mesh_size": 0.08, "coil_bending": "wahl"}
    assert spec.n_designs == 1 and spec.effective_chunk_size == SECTION_MIN_CHUNK
    assert parse_spec(_spec("")).fingerprint() != spec.fingerprint()
    plain = parse_spec(_spec("", '["paper"]'))
    assert plain.effective_chunk_size == 500 and "section" not in plain.evaluators
    with pytest.raises(DesignError, match=r"sweep.section.mesh_size = 0.9: must be in \[0.005, 0.5\] mm"):
        parse_spec(_spec("[sweep.section]\nmesh_size = 0.9"))
    with pytest.raises(DesignError, match="sweep.section.coil_bending = 'spring'"):
        parse_spec(_spec('[sweep.section]\ncoil_bending = "spring"'))
    assert parse_spec(_spec('[sweep.section]\nmesher = "gmsh"')).section_options == {"mesher": "gmsh"}
    with pytest.raises(DesignError, match="sweep.section.mesher = 'tetgen': must be one of"):
        parse_spec(_spec('[sweep.section]\nmesher = "tetgen"'))
    with pytest.raises(
        DesignError, match="sweep.section = .*must be a table with only coil_bending, mesh_size"
    ):
        parse_spec(_spec("[sweep.section]\nsegments = 24"))
    with pytest.raises(DesignError, match="sweep.evaluators"):
        parse_spec(_spec("", '["sectoin"]'))


def test_shipped_section_example_parses():
    from pathlib import Path

    spec = load_spec(Path(__file__).parents[3] / "examples" / "sweeps" / "section.toml")
    assert "section" in spec.evaluators and spec.n_samples >= 200


def test_select_ranks_on_the_section_model_under_the_lumen_load_by_default(section_sweep, capsys):
    from softcath.cli.main import main
    from softcath.studies.selection import SelectionError, select

    _, out, df = section_sweep
    sel = select(df, objectives=["maximise bend_per_MPa_deg"])
    assert (sel.model, sel.load, sel.note) == ("section", "lumen", "")
    at = df[(df.load == "lumen") & (df.pressure_MPa == 1.0) & (df.status == "ok")].set_index("design_id")
    for r in sel.ranked:
        assert r["objectives"]["maximise bend_per_MPa_deg"] == pytest.approx(
            at.at[r["design_id"], "bend_angle_section_deg"] / 1.0, rel=1e-12
        )
    paper = select(df, objectives=["maximise bend_per_MPa_deg"], model="paper")
    assert (paper.model, paper.load) == ("paper", "cap")
    assert paper.ranked[0]["objectives"]["maximise bend_per_MPa_deg"] == pytest.approx(
        df[
            (df.load == "cap") & (df.pressure_MPa == 1.0) & (df.design_id == paper.ranked[0]["design_id"])
        ].bend_angle_analytic_deg.iloc[0]
    )
    with pytest.raises(SelectionError, match="model 'fem': this sweep has no results of the 3-D FEM"):
        select(df, objectives=["maximise bend_per_MPa_deg"], model="fem")
    assert main(["select", str(out), "--objective", "maximise bend_per_MPa_deg"]) == 0
    text = capsys.readouterr().out
    assert "model: the section model (section), lumen load" in text
    doc = json.loads((out / "selection.json").read_text())
    assert (doc["model"], doc["load"]) == ("section", "lumen")


def test_select_on_an_analytic_sweep_says_the_papers_formula_was_used(small_spec, tmp_path, capsys):
    from softcath.cli.main import main
    from softcath.studies.selection import SelectionError, select

    run_sweep(load_spec(small_spec), tmp_path / "old", workers=1, progress=False)
    df = read_results(tmp_path / "old")
    sel = select(df, objectives=["maximise bend_per_MPa_deg"])
    assert (sel.model, sel.load) == ("paper", "cap")
    assert "no section-model results: ranked on the paper's formula" in sel.note
    with pytest.raises(
        SelectionError, match="model 'section': this sweep has no results of the section model"
    ):
        select(df, objectives=["maximise bend_per_MPa_deg"], model="section")
    assert main(["select", str(tmp_path / "old"), "--objective", "maximise bend_per_MPa_deg"]) == 0
    assert "note: this sweep has no section-model results" in capsys.readouterr().out


def test_report_shows_the_tiers_side_by_side(section_sweep, small_spec, tmp_path):
    from softcath.studies.report import write_report
    from softcath.studies.report.figures import tier_agreement

    _, out, df = section_sweep
    path, _ = write_report(out)
    html = path.read_text()
    assert "Formula, section model and 3-D FEM" in html and (out / "report" / "parity_tiers.png").is_file()
    rows = {r[0]: r for r in tier_agreement(df)}
    ok = df[(df.status == "ok") & (df.pressure_MPa > 0) & (df.load == "lumen")]
    assert rows["lumen"][2] == pytest.approx(float(np.median(ok.section_formula_ratio)), rel=1e-12)
    assert np.isnan(rows["lumen"][3])  # no FEM in this sweep
    run_sweep(load_spec(small_spec), tmp_path / "old", workers=1, progress=False)
    assert "Only the paper's formula ran" in write_report(tmp_path / "old")[0].read_text()


@pytest.mark.slow
def test_fem_and_section_agree_in_a_sweep(spec_writer, tmp_path):
    """One design through all three tiers: the section model is the 3-D FEM's mid-span section.

    The section model reproduces the 3-D FEM to 0.3 % on the paper design and
    within 2 % on random designs (fem/section_model tests); the FEM's coarse
    0.16 mm mesh adds < 1 %: 2 % here.
    """
    from softcath.studies.report import write_report

    spec = spec_writer(
        """
        [sweep]
        base = "paper"
        pressures_MPa = [1.0]
        loads = ["cap", "lumen"]
        evaluators = ["analytic", "section", "fem"]
        [sweep.fem]
        mesh_size = 0.16
        [parameters]
        "tube.h" = { values = [0.02] }
        """
    )
    run_sweep(load_spec(spec), tmp_path / "o", workers=1, progress=False)
    df = read_results(tmp_path / "o")
    assert (df.status == "ok").all() and set(df.source) == {"fem"}
    assert np.abs(df.rel_diff_fem_section_curvature).max() < 0.02
    np.testing.assert_allclose(
        df.fem_formula_ratio, df.curvature_fem_per_mm / df[df.load == "cap"].curvature_analytic_per_mm.iloc[0]
    )
    html = write_report(tmp_path / "o")[0].read_text()
    assert "median |FEM / section − 1|" in html
