"""``softcath demo``: independent sections, one index.html, clear notes for what is missing."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from softcath import analytic, design
from softcath.cli.main import main
from softcath.studies import demo
from softcath.studies.sweep import fem_check_function

ROOT = Path(__file__).resolve().parents[3]


def test_demo_model_sweep_verdict(tmp_path, capsys):
    out = tmp_path / "demo"
    assert (
        main(["demo", "--out", str(out), "--only", "model,sweep,verdict", "--workers", "1", "--no-fem"]) == 0
    )
    html = (out / "index.html").read_text()
    status = {s["key"]: s["status"] for s in json.loads((out / "demo.json").read_text())["sections"]}
    assert status == {"model": "ok", "sweep": "ok", "verdict": "ok"}
    for src in re.findall(r'<img src="([^"]+)"', html):
        assert (out / src).read_bytes()[:4] == b"\x89PNG", src  # every figure link resolves offline
    sweep_report = out / "sweep" / "run" / "report" / "index.html"  # the sweep's own page, linked
    assert "sweep/run/report/index.html" in html
    for src in re.findall(r'<img src="([^"]+)"', sweep_report.read_text()):
        assert (sweep_report.parent / src).is_file(), src
    # The model table states the paper's cap-load bend at 2 MPa: θ = κ L0 (1 + ε), from the analytic model.
    r = analytic.response(design.preset("paper"), 2.0, "cap")
    assert f"{np.degrees(float(r.bend_angle)):.4g}" in html
    # The sweep has at most 20 designs, chosen on the section model under the lumen load, and the verdict
    # names the selection's best design.
    sel = json.loads((out / "sweep" / "run" / "selection.json").read_text())
    assert sel["n_designs"] <= 20 and (sel["model"], sel["load"]) == ("section", "lumen")
    assert f"Build design {sel['ranked'][0]['design_id']}</b>" in html
    assert "Not run:</b> the 3-D FEM check of the chosen design (switched off with --no-fem)" in html
    assert "softcath demo" in html and "<script" not in html


def test_failing_or_missing_section_does_not_stop_the_demo(tmp_path, monkeypatch):
    def boom(ctx):
        raise RuntimeError("solver exploded")

    monkeypatch.setattr(
        demo,
        "SECTIONS",
        [
            ("boom", "Boom", boom),
            ("fem", "FEM", demo.section_tiers),
            ("verdict", "Verdict", demo.section_verdict),
        ],
    )
    res = demo.run_demo(tmp_path / "d", progress=False, fem=False)
    status = {s["key"]: s["status"] for s in res.sections}
    # Without the FEM the tiers section still shows the formula and the section model, and says so.
    assert status == {"boom": "failed", "fem": "ok", "verdict": "ok"}
    html = res.index_html.read_text()
    assert "This section failed:</b> RuntimeError: solver exploded" in html
    assert "Not run:</b> the 3-D FEM (switched off with --no-fem); the section model stands in for it" in html


def test_fem_section_says_why_it_is_missing(tmp_path):
    if fem_check_function() is not None:
        pytest.skip("fem.check is installed: this test covers the fem-unavailable note only")
    ctx = demo.DemoContext(out_dir=tmp_path, design=design.preset("paper"), data_csv=tmp_path / "x.csv")
    res = demo.section_tiers(ctx)
    assert res.status == "ok" and "fem.check is not importable" in res.html


@pytest.mark.parametrize("fem", [False, pytest.param(True, marks=pytest.mark.slow)])
def test_tiers_section_shows_the_three_tiers_and_the_nu_plot(tmp_path, fem):
    """The table's values are the formula's and the section model's gains; the nu plot runs to 0.4999.

    With the FEM (one 3-D design, ~10-20 s: slow) its mid-span curvature agrees with the section model's
    within 1 % under both loads (0.3 % measured on the paper design; the FEM's default mesh adds < 0.5 %).
    """
    from softcath.fem.section_model import section_model
    from softcath.studies.demo.tiers import NU_SWEEP

    if fem and fem_check_function() is None:
        pytest.skip("fem.check is not installed")
    d = design.preset("paper")
    ctx = demo.DemoContext(out_dir=tmp_path, design=d, data_csv=tmp_path / "x.csv", fem=fem)
    res = demo.section_tiers(ctx)
    tiers = ctx.shared["tiers"]
    sm = section_model(d)
    assert tiers["formula"] == analytic.gains(d, "cap")[0]
    assert tiers["section"] == sm.curvature_per_mm_per_MPa
    assert tiers["nu"][0.49] == pytest.approx(sm.curvature_per_mm_per_MPa["lumen"], rel=1e-12)  # design nu
    assert max(NU_SWEEP) == 0.4999 and (tmp_path / "tiers_nu.png").read_bytes()[:4] == b"\x89PNG"
    assert f"{sm.fem_formula_ratio['lumen']:.4g}" in res.html
    if fem:
        assert set(tiers["fem"]) == {"cap", "lumen"}
        for load, k in tiers["fem"].items():
            assert k == pytest.approx(tiers["section"][load], rel=0.01)


def test_demo_bad_arguments(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path), "--only", "model,nope"]) == 2
    assert "only = 'nope': unknown section" in capsys.readouterr().err


@pytest.mark.slow
def test_full_demo_subprocess(tmp_path):
    """`softcath demo --out DIR` end to end as a user runs it; no section may fail."""
    out = tmp_path / "demo"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.run(
        [sys.executable, "-m", "softcath", "demo", "--out", str(out)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    sections = json.loads((out / "demo.json").read_text())["sections"]
    assert [s["key"] for s in sections] == [k for k, _, _ in demo.SECTIONS]
    assert all(s["status"] in ("ok", "unavailable") for s in sections), sections
    ok = {s["key"] for s in sections if s["status"] == "ok"}
    assert ok >= {"model", "calibration", "effects", "sweep", "verdict"}
    if fem_check_function() is not None:
        assert ok >= {"fem", "large_bends"}
        assert "large_bends_curve.png" in (out / "index.html").read_text()
    assert (out / "effects" / "report.html").is_file() and "effects/report.html" in (
        out / "index.html"
    ).read_text()
    assert (out / "index.html").is_file() and "demo:" in proc.stdout


def test_demo_prototype_section_finds_the_hidden_offset(tmp_path):
    out = tmp_path / "demo"
    assert main(["demo", "--out", str(out), "--only", "prototype", "--workers", "1", "--no-fem"]) == 0
    html = (out / "index.html").read_text()
    assert "6. A built prototype, point by point" in html and (out / "prototype_curve.png").is_file()
    # the hidden pressure offset is in every equally good hypothesis, so it is named
    assert "Named: <b>pressure_offset" in html
