"""``softcath discrepancy DESIGN MEASURED.csv --reference prototype``."""

from __future__ import annotations

import json

import numpy as np

from softcath.cli.main import main


def test_prototype_reference_writes_hypotheses(tmp_path, capsys):
    p = np.linspace(0.1, 0.6, 6)
    csv = tmp_path / "m.csv"
    csv.write_text("pressure_MPa,curvature_per_mm\n" + "".join(f"{a:g},{0.2 * a:.5f}\n" for a in p))
    argv = ["discrepancy", "paper", str(csv), "--reference", "prototype", "--tip-factor", "1"]
    assert main([*argv, "--candidates", "filler_none", "--out", str(tmp_path / "d")]) == 0
    doc = json.loads((tmp_path / "d" / "discrepancy.json").read_text())
    assert doc["reference"] == "prototype" and doc["named"] == []  # 0.2 lies in the baseline band
    assert [h["ingredients"] for h in doc["hypotheses"]] == [[], ["filler_none"]]
    assert len(doc["hypotheses"][0]["band"]) == p.size
    out = capsys.readouterr().out
    assert "named: nothing" in out and "baseline (bonded, nominal ranges)" in out


def test_prototype_reference_refuses_a_bad_tip_factor(tmp_path, capsys):
    csv = tmp_path / "m.csv"
    csv.write_text("pressure_MPa,curvature_per_mm\n0.1,0.02\n0.2,0.04\n")
    argv = ["discrepancy", "paper", str(csv), "--reference", "prototype", "--tip-factor", "9"]
    assert main([*argv, "--out", str(tmp_path / "d")]) != 0
    assert "--tip-factor = 9: must be in [0.2, 5]" in capsys.readouterr().err
