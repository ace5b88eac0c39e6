"""The sweep report: a static page whose figures exist, with failed designs and the selection."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from softcath.cli.main import main
from softcath.studies.report import design_of
from softcath.studies.sweep import expand, load_spec, variant_table


def _images(html: str) -> list[str]:
    return re.findall(r'<img src="([^"]+)"', html)


def test_report_contains_figures_failures_and_selection(small_spec, tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["sweep", str(small_spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    from softcath.studies.report.html_report import _selection_html

    assert "No selection yet" in _selection_html(out)
    select = [
        "select",
        str(out),
        "--constraint",
        "max_strain <= 0.3",
        "--objective",
        "maximise bend_per_MPa_deg",
    ]
    assert main([*select, "--objective", "minimise elongation at p_max"]) == 0
    assert main(["report", str(out)]) == 0
    html = (out / "report" / "index.html").read_text()
    images = _images(html)
    # error/response vs parameters, heat map (2 factorial parameters), sensitivity, two renders, Pareto plot
    assert {"vs_parameters.png", "heatmap.png", "sensitivity.png", "pareto.png"} <= set(images)
    assert len(images) == 6
    for name in images:
        data = (out / "report" / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000  # a real, non-empty PNG
    assert "http://" not in html and "https://" not in html and "<script" not in html  # opens offline
    assert "|h| must be &lt;= b - min_wall - b_int" in html  # failed designs with their reason
    assert "Build design" in html and "maximise bend_per_MPa_deg" in html
    best = json.loads((out / "selection.json").read_text())["ranked"][0]
    assert f"its design file is <code>{best['design_file']}</code>" in html
    assert (out / best["design_file"]).is_file()  # the report names the file select wrote
    assert "No FEM results" in html  # analytic-only sweep: the parity section says why it is empty


def test_design_of_rebuilds_the_swept_design(small_spec, tmp_path):
    from softcath import design

    out = tmp_path / "o"
    assert main(["sweep", str(small_spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    spec = load_spec(small_spec)
    expected = design.from_dict(variant_table(spec.base_table, expand(spec)[7]))
    got = design_of(out, 7)
    assert got.tube == expected.tube and got.tip == expected.tip


def test_report_of_non_sweep_directory_is_an_error(tmp_path, capsys):
    assert main(["report", str(tmp_path)]) == 2
    assert "no sweep.json" in capsys.readouterr().err


@pytest.mark.parametrize("n", [40])
def test_lhs_sweep_report_has_rbd_fast(spec_writer, tmp_path, n):
    spec = spec_writer(
        f"""
        [sweep]
        pressures_MPa = [1.0]
        loads = ["cap"]
        seed = 2
        [sample]
        n = {n}
        [parameters]
        "tube.h" = {{ lhs = [-0.04, 0.04] }}
        "tip.bending_length" = {{ lhs = [3.0, 7.0] }}
        """
    )
    out = tmp_path / "o"
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    assert main(["report", str(out)]) == 0
    html = (out / "report" / "index.html").read_text()
    assert "RBD-FAST" in html and "heatmap.png" not in html  # a sample: no grid to map
    # Closed form: κ = p A_p (y_p − ȳ)/ΣEI does not depend on the bending length, and rises with h.
    import pandas as pd

    from softcath.studies.report import figures

    df = pd.read_parquet(out / "results.parquet")
    _, rows = figures.sensitivity(df, ["tube.h", "tip.bending_length"], True, tmp_path / "s.png")
    src = {p: (s, s1) for p, s, s1 in rows}
    assert src["tube.h"][0] > 0.95  # κ is nearly linear in h: SRC ≈ 1 (R² ≈ 1)
    # LHS columns are nearly uncorrelated (|r| ~ 1/sqrt(n)), so a parameter with no effect gets |SRC| ≲ 0.05
    assert abs(src["tip.bending_length"][0]) < 0.05
    assert src["tube.h"][1] > 0.8 and src["tip.bending_length"][1] < 0.2


def test_tiers_section_promises_only_what_ran(spec_writer, tmp_path):
    """A lumen-only section sweep: the section model ran, the formula has nothing to compare (cap load)."""
    from softcath.studies.report import write_report

    spec = spec_writer(
        """
        [sweep]
        name = "lumen-only"
        base = "paper"
        pressures_MPa = [0.0, 0.5]
        loads = ["lumen"]
        evaluators = ["analytic", "section"]
        [parameters]
        "tube.h" = { values = [0.0, 0.01] }
        """
    )
    out = tmp_path / "s"
    assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    html = write_report(out)[0].read_text()
    assert "Only the paper's formula ran" not in html
    assert "The section model ran, but the paper's formula is a cap-load model" in html
    spec2 = spec_writer(
        """
        [sweep]
        name = "both-loads"
        base = "paper"
        pressures_MPa = [0.0, 0.5]
        loads = ["cap", "lumen"]
        evaluators = ["analytic", "section"]
        [parameters]
        "tube.h" = { values = [0.0, 0.01] }
        """,
        name="spec2.toml",
    )
    out2 = tmp_path / "s2"
    assert main(["sweep", str(spec2), "--out", str(out2), "--workers", "1", "--no-progress"]) == 0
    html = write_report(out2)[0].read_text()
    tiers = html[html.index("Formula, section model and 3-D FEM") :]
    tiers = tiers[: tiers.index("</table>")]
    assert "median section / formula" in tiers and "FEM" not in tiers.split("</h2>", 1)[-1]


def test_the_lumen_formula_points_near_zero_are_explained(small_spec, tmp_path):
    """The analytic lumen-load bend is a few % of the cap-load one: the caption says it is its answer."""
    from softcath.studies.report.html_report import _lumen_formula_caption
    from softcath.studies.sweep.results import read_results

    out = tmp_path / "o"
    assert main(["sweep", str(small_spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    df = read_results(out)
    text = _lumen_formula_caption(df)
    ok = df[(df.status == "ok") & (df.pressure_MPa > 0)]
    cap = ok[ok.load == "cap"].curvature_analytic_per_mm.to_numpy(float)
    lumen = ok[ok.load == "lumen"].curvature_analytic_per_mm.to_numpy(float)
    assert f"bends {np.median(np.abs(lumen / cap)):.1%} of its cap-load bend" in text
    assert "not missing data" in text
    assert _lumen_formula_caption(df[df.load == "cap"]) == ""  # one load: nothing to explain
