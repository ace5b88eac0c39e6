"""Robust selection: probabilities over material ranges, checked against the formula evaluated directly."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from softcath import analytic
from softcath.cli.main import main
from softcath.studies.predict.ranges import Range
from softcath.studies.predict.sampling import sample_values, unit_sample
from softcath.studies.selection import robust_select, select
from softcath.studies.sweep import load_spec, run_sweep
from softcath.studies.sweep.results import read_results
from softcath.studies.sweep.variants import build_variant

ROOT = Path(__file__).resolve().parents[3]
RANGES = [
    Range("materials.medical_silicone_tubing.youngs_modulus", low=1.648, high=4.43),
    Range("materials.ecoflex_00_30.youngs_modulus", low=0.069, high=0.118),
]
CONS = "bend_angle_deg >= 30 at p_max"
OBJ = "maximise bend_per_MPa_deg"


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    out = tmp_path_factory.mktemp("sweep")
    spec = load_spec(ROOT / "examples/sweeps/quick_analytic.toml")
    run_sweep(spec, out, workers=1, progress=False)
    return out, spec


def _robust(sweep, seed=0):
    out, spec = sweep
    sel = select(read_results(out), constraints=[CONS], objectives=[OBJ], top=20)
    return sel, robust_select(
        sel,
        base_table=spec.base_table,
        pressures=spec.pressures,
        probability=0.9,
        ranges=RANGES,
        samples=24,
        seed=seed,
    )


def test_probabilities_match_the_formula_evaluated_directly(sweep):
    out, spec = sweep
    sel, rob = _robust(sweep)
    assert rob.robust["P"] == 0.9 and rob.robust["samples"] == 24 and rob.robust["model"] == "paper"
    values = sample_values(unit_sample(24, 2, 0), RANGES)
    some_fail = False
    for r in sel.ranked:
        info = rob.robust["designs"][str(r["design_id"])]
        params = {k: v for k, v in r["parameters"].items() if k != "outer_diameter_mm"}
        bends = []
        for v in values:
            d = build_variant(spec.base_table, {**v, **params})
            resp = analytic.response(d, np.array([max(spec.pressures)]), load="cap")
            bends.append(math.degrees(float(np.asarray(resp.bend_angle)[0])))
        expected = float(np.mean(np.array(bends) >= 30))
        assert info["probabilities"][CONS] == pytest.approx(expected)
        assert info["percentiles"][OBJ]["p50"] == pytest.approx(
            np.percentile(bends, 50) / max(spec.pressures)
        )
        assert info["passes"] == (expected >= 0.9)
        some_fail |= not info["passes"]
    assert some_fail, "the threshold should reject some nominal passers"
    assert rob.ranked and all(r["probabilities"][CONS] >= 0.9 for r in rob.ranked)
    p50 = [r["objectives"][OBJ] for r in rob.ranked]
    assert p50 == sorted(p50, reverse=True)
    assert rob == _robust(sweep)[1]  # seeded


def test_select_cli_robust_writes_the_robust_block(sweep, tmp_path, capsys):
    out, _ = sweep
    rc = main(
        [
            "select",
            str(out),
            "--constraint",
            CONS,
            "--objective",
            OBJ,
            "--robust",
            "0.9",
            "--vary",
            "materials.ecoflex_00_30.youngs_modulus=0.069:0.118",
            "--samples",
            "8",
            "--no-progress",
            "--out",
            str(tmp_path / "sel"),
        ]
    )
    assert rc == 0
    doc = json.loads((tmp_path / "sel" / "selection.json").read_text())
    assert set(doc["robust"]) >= {"P", "samples", "ranges", "designs"}
    assert doc["robust"]["ranges"][0]["path"] == "materials.ecoflex_00_30.youngs_modulus"
    stdout = capsys.readouterr().out
    assert "pass" in stdout
    for r in doc["ranked"]:  # the ranked values are the robust model's p50, and say so
        assert (r["tier"], r["statistic"]) == (doc["robust"]["model"], "p50")
    if doc["ranked"]:
        assert f"[{doc['robust']['model']} p50, {doc['load']} load]" in stdout
    rc = main(["select", str(out), "--objective", OBJ, "--robust", "2", "--out", str(tmp_path / "s2")])
    assert rc == 2 and "--robust = 2" in capsys.readouterr().err


def test_select_cli_robust_needs_a_manifest(sweep, tmp_path, capsys):
    out, _ = sweep
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    (copy / "sweep.json").unlink()
    rc = main(["select", str(copy), "--objective", OBJ, "--robust", "0.9"])
    assert rc == 2 and "sweep.json" in capsys.readouterr().err


def test_work_beyond_two_hours_or_absurd_samples_is_refused_before_any_run(sweep, monkeypatch):
    from softcath.design.errors import DesignError

    out, spec = sweep
    sel = select(read_results(out), constraints=[CONS], objectives=[OBJ], top=20)
    kw = {
        "base_table": spec.base_table,
        "pressures": spec.pressures,
        "probability": 0.9,
        "ranges": RANGES,
    }
    with pytest.raises(DesignError, match=r"samples = 20000: must be an integer in \[2, 10000\]"):
        robust_select(sel, samples=20_000, **kw)
    monkeypatch.setattr("softcath.studies.optimise.evaluate.MAX_WORK_SECONDS", 1.0)
    runs = len(sel.ranked) * 1000
    with pytest.raises(DesignError, match=rf"samples = 1000: {runs} section-model runs would take about"):
        robust_select(sel, samples=1000, model="section", **kw)
