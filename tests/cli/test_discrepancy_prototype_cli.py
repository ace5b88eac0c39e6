"""``softcath discrepancy DESIGN MEASURED.csv --reference prototype``."""

from __future__ import annotations

import json

import numpy as np
import pytest

from softcath.cli.main import main
from softcath.fem.section_model.finite_strain import section_curve


def test_prototype_reference_writes_hypotheses(tmp_path, capsys):
    p = np.linspace(0.2, 0.5, 8)
    k = section_curve("paper", p, linear_gain=False).curvature_per_mm  # the baseline's own curve
    k = k * (1 + 0.01 * np.random.default_rng(0).standard_normal(p.size))
    csv = tmp_path / "m.csv"
    csv.write_text(
        "pressure_MPa,curvature_per_mm\n" + "".join(f"{a:g},{b:.6f}\n" for a, b in zip(p, k, strict=True))
    )
    argv = ["discrepancy", "paper", str(csv), "--reference", "prototype", "--tip-factor", "1"]
    assert main([*argv, "--candidates", "pressure_offset", "--out", str(tmp_path / "d")]) == 0
    doc = json.loads((tmp_path / "d" / "discrepancy.json").read_text())
    assert doc["reference"] == "prototype" and doc["named"] == [] and doc["explained"]
    assert [h["ingredients"] for h in doc["hypotheses"]] == [[], ["pressure_offset"]]
    assert len(doc["hypotheses"][0]["predicted"]["curvature_per_mm"]) == p.size
    out = capsys.readouterr().out
    assert "named: nothing" in out and "baseline (nominal design)" in out and "finite-strain section" in out


def test_prototype_reference_refuses_a_bad_tip_factor(tmp_path, capsys):
    csv = tmp_path / "m.csv"
    csv.write_text("pressure_MPa,curvature_per_mm\n0.1,0.02\n0.2,0.04\n0.3,0.07\n0.4,0.1\n")
    # the file may come after the options
    argv = ["discrepancy", "paper", "--reference", "prototype", "--tip-factor", "9", str(csv)]
    assert main([*argv, "--out", str(tmp_path / "d")]) != 0
    assert "--tip-factor = 9: must be in [0.2, 5]" in capsys.readouterr().err


def test_prototype_reference_refuses_an_unknown_ingredient(tmp_path, capsys):
    csv = tmp_path / "m.csv"
    csv.write_text("pressure_MPa,curvature_per_mm\n0.1,0.02\n0.2,0.04\n0.3,0.07\n0.4,0.1\n")
    argv = ["discrepancy", "paper", str(csv), "--reference", "prototype", "--tip-factor", "1"]
    assert main([*argv, "--candidates", "bogus", "--out", str(tmp_path / "d")]) == 2
    assert "--candidates = 'bogus': must be among tube_modulus" in capsys.readouterr().err
    assert not (tmp_path / "d" / "discrepancy.json").exists()


@pytest.mark.slow
def test_physical_step_on_a_time_series_writes_its_record(tmp_path, capsys):
    t = np.arange(0, 30, 0.05)
    p = 0.35 - 0.15 * np.cos(2 * np.pi * 0.2 * t)
    k = section_curve("paper", np.linspace(0, 0.5, 11), linear_gain=False)
    kappa = np.interp(p, np.linspace(0, 0.5, 11), k.curvature_per_mm)
    kappa = kappa + 0.0005 * np.random.default_rng(2).standard_normal(t.size)
    csv = tmp_path / "sine.csv"
    csv.write_text(
        "time_s,pressure_MPa,curvature_per_mm\n"
        + "".join(f"{a:.3f},{b:.6f},{c:.6f}\n" for a, b, c in zip(t, p, kappa, strict=True))
    )
    argv = ["discrepancy", "paper", str(csv), "--physical", "--candidates", "offset,delay"]
    assert main([*argv, "--out", str(tmp_path / "d")]) == 0
    doc = json.loads((tmp_path / "d" / "discrepancy.json").read_text())
    phys = doc["physical"]
    # the recording is the baseline's own curve: the physical step needs nothing
    assert phys["chosen"] == [] and phys["explained"] and phys["nrmse_before"] < 0.1
    assert "held-out NRMSE (second half of each run)" in capsys.readouterr().out
