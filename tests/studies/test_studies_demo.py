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

import analytic
import design
from studies import demo
from studies.cli import main
from studies.sweep import fem_check_function

ROOT = Path(__file__).resolve().parents[2]


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
    # The sweep has at most 12 designs, and the verdict names the selection's best design.
    sel = json.loads((out / "sweep" / "run" / "selection.json").read_text())
    assert sel["n_designs"] <= 12
    assert f"Build design {sel['ranked'][0]['design_id']}</b>" in html
    assert "softcath demo" in html and "<script" not in html


def test_failing_or_missing_section_does_not_stop_the_demo(tmp_path, monkeypatch):
    def boom(ctx):
        raise RuntimeError("solver exploded")

    monkeypatch.setattr(
        demo,
        "SECTIONS",
        [
            ("boom", "Boom", boom),
            ("fem", "FEM", demo.section_fem),
            ("verdict", "Verdict", demo.section_verdict),
        ],
    )
    res = demo.run_demo(tmp_path / "d", progress=False, fem=False)
    status = {s["key"]: s["status"] for s in res.sections}
    assert status == {"boom": "failed", "fem": "unavailable", "verdict": "unavailable"}
    html = res.index_html.read_text()
    assert "This section failed:</b> RuntimeError: solver exploded" in html
    assert "Not run:</b> the FEM check under both loads (switched off with --no-fem)" in html


def test_fem_section_says_why_it_is_missing(tmp_path):
    if fem_check_function() is not None:
        pytest.skip("fem.check is installed: this test covers the fem-unavailable note only")
    ctx = demo.DemoContext(out_dir=tmp_path, design=design.preset("paper"), data_csv=tmp_path / "x.csv")
    res = demo.section_fem(ctx)
    assert res.status == "unavailable" and "fem.check is not importable" in res.html


def test_demo_bad_arguments(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path), "--only", "model,nope"]) == 2
    assert "only = 'nope': unknown section" in capsys.readouterr().err


@pytest.mark.slow
def test_full_demo_subprocess(tmp_path):
    """`softcath demo --out DIR` end to end as a user runs it; no section may fail."""
    out = tmp_path / "demo"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.run([sys.executable, "-m", "studies", "demo", "--out", str(out)], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=900)  # fmt: skip
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
