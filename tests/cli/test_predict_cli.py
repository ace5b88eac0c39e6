"""``softcath predict``: ranges and --vary checks, seed reproducibility, sensitivity, the CLI end to end."""

from __future__ import annotations

import csv
import json
import tomllib

import numpy as np
import pytest

from softcath.cli.main import main
from softcath.design import presets
from softcath.design.errors import DesignError
from softcath.studies.predict import Range, predict, predict_tier, resolve_ranges
from softcath.studies.predict.ranges import default_ranges, load_ranges

E_PATH = "materials.medical_silicone_tubing.youngs_modulus"
TABLE = tomllib.loads(presets.text("paper"))


def test_shipped_ranges_trace_every_range_to_a_source_and_fit_the_preset():
    ranges = load_ranges(default_ranges("paper"))
    assert all(len(r.source) > 20 for r, _default in ranges.values())
    # every default range is buildable at both ends (resolve_ranges checks each end against the design)
    used = resolve_ranges("paper")
    assert {r.path for r in used} == {p for p, (_r, d) in ranges.items() if d}
    # the Gent end of the tube modulus: Shore 65A
    s = 65
    gent = 0.0981 * (56 + 7.62336 * s) / (0.137505 * (254 - 2.54 * s))
    assert ranges[E_PATH][0].high == pytest.approx(gent, abs=5e-3)


@pytest.mark.parametrize(
    ("vary", "match"),
    [
        (
            ["materials.medical_silicone_tubing.poisson_ratio=0.45:0.6"],
            r"poisson_ratio.* 0\.6: must be <= 0\.4999",
        ),
        ([f"{E_PATH}=-1:2"], rf"vary {E_PATH} low = -1: .*youngs_modulus: must be > 0"),
        (["tube.nonsense=0:1"], r"vary tube\.nonsense.*is not a field of the base design"),
        ([f"{E_PATH}=2:x"], rf"vary {E_PATH} = '2:x': LO and HI must be numbers"),
        ([f"{E_PATH}=3:2"], r"high = 2: must be > low = 3"),
        (["tube.b_int=0.075:0.2"], r"vary tube\.b_int high = 0\.2: tube\."),
        (["model.coil_modulus=tension,steel"], r"coil_modulus levels.* must be a non-empty list"),
        ([f"{E_PATH}=1:2", f"{E_PATH}=2:3"], r"is given twice"),
        (["tip.cap_thickness"], None),  # named alone: the file's (non-default) range is used
    ],
)
def test_bad_vary_is_refused_naming_path_and_bound(vary, match):
    if match is None:
        (r,) = resolve_ranges("paper", vary)
        assert (r.low, r.high) == (0.15, 0.6) and "assumption" in r.source
        return
    with pytest.raises(DesignError, match=match):
        resolve_ranges("paper", vary)


def test_bad_vary_is_one_line_on_the_command_line(tmp_path, capsys):
    argv = [
        "predict",
        "paper",
        "--model",
        "paper",
        "--vary",
        "materials.medical_silicone_tubing.poisson_ratio=0.45:0.6",
        "--out",
        str(tmp_path),
    ]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err
    assert err.startswith("softcath predict: error: --vary materials.medical_silicone_tubing.poisson_ratio")
    assert "0.4999" in err


def test_same_seed_same_prediction_other_seed_other_sample():
    kw = {"model": "paper", "samples": 128, "measured_gain": 0.1}
    a, ta = predict("paper", seed=4, **kw)
    b, tb = predict("paper", seed=4, **kw)
    c, tc = predict("paper", seed=5, **kw)
    for d in (a, b, c):
        d.pop("seconds")
    assert a == b
    np.testing.assert_array_equal(ta[0].gains, tb[0].gains)
    assert not np.array_equal(ta[0].gains, tc[0].gains)
    assert a["gain_percentiles"] != c["gain_percentiles"]


def test_sensitivity_names_the_only_parameter_that_moves_the_gain():
    # The paper's formula has no end cap: its thickness cannot move the gain, the tube modulus does.
    # RBD-FAST's S1 of a smooth monotone one-parameter response is 1; of an inert one 0, each within the
    # estimator's bias at 512 samples and 10 harmonics (a few 0.01, Plischke 2010).
    ranges = [Range(E_PATH, low=1.648, high=4.43), Range("tip.cap_thickness", low=0.15, high=0.6)]
    r = predict_tier(TABLE, "paper", ranges, load="cap", samples=512, seed=1)
    s = r.sensitivity["indices"]
    assert r.sensitivity["ranking"][0] == E_PATH
    assert s[E_PATH]["S1"] > 0.95
    assert abs(s["tip.cap_thickness"]["S1"]) < 0.05
    only_cap = predict_tier(TABLE, "paper", ranges[1:], load="cap", samples=128, seed=1)
    assert only_cap.sensitivity["skipped"] == "the gain does not change over the sample"


def test_model_options_the_tier_lacks_are_listed_not_sampled():
    ranges = [Range(E_PATH, low=2.0, high=3.0), Range("model.coil_modulus", levels=("tension", "bending"))]
    r = predict_tier(TABLE, "paper", ranges, load="cap", samples=8, seed=0)
    assert r.not_applicable == ("model.coil_modulus",)
    assert [x.path for x in r.ranges] == [E_PATH]


def test_cli_end_to_end_writes_json_keys_and_png(tmp_path, capsys):
    argv = [
        "predict",
        "paper",
        "--model",
        "section",
        "--compare",
        "paper",
        "--samples",
        "4",
        "--seed",
        "3",
        "--vary",
        "materials.medical_silicone_tubing.poisson_ratio",
        "--vary",
        "model.coil_modulus=tension,bending",
        "--measured-gain",
        "0.388",
        "--no-progress",
        "--out",
        str(tmp_path),
    ]
    assert main(argv) == 0
    doc = json.loads((tmp_path / "prediction.json").read_text())
    for key in (
        "model",
        "load",
        "samples",
        "gain_percentiles",
        "elongation_percentiles",
        "measured_gain",
        "measured_percentile",
        "measured_in_band",
        "sensitivity",
        "ranges",
        "compare",
    ):
        assert key in doc, key
    assert (doc["model"], doc["load"], doc["samples"]) == ("section", "lumen", 4)
    assert set(doc["compare"]) == {"section", "paper"} and doc["compare"]["paper"]["load"] == "cap"
    assert doc["compare"]["paper"]["not_applicable"] == ["model.coil_modulus"]
    p = doc["gain_percentiles"]
    assert p["p5"] <= p["p50"] <= p["p95"]
    assert 0.0 <= doc["measured_percentile"] <= 100.0
    assert all(r["source"] for r in doc["ranges"])
    assert "skipped" in doc["sensitivity"]  # 4 samples are too few for indices, and it says so
    png = (tmp_path / "prediction.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000
    assert "measured 0.388 at percentile" in capsys.readouterr().out
    rows = list(csv.DictReader((tmp_path / "samples.csv").read_text().splitlines()))
    assert [r["tier"] for r in rows] == ["section"] * 4 + ["paper"] * 4
    section = sorted(float(r["curvature_per_mm_per_MPa"]) for r in rows if r["tier"] == "section")
    assert np.median(section) == pytest.approx(p["p50"])  # np.percentile(.., 50) of 4 values: the median
    assert {r["model.coil_modulus"] for r in rows if r["tier"] == "paper"} == {""}


@pytest.mark.parametrize("bad", [float("nan"), float("inf")])
def test_non_finite_measured_gain_is_refused(bad):
    with pytest.raises(DesignError, match=r"measured_gain = .*: must be finite"):
        predict("paper", model="paper", samples=4, measured_gain=bad)


def test_unknown_compare_tier_is_refused():
    with pytest.raises(DesignError, match=r"model = 'ansys': must be one of paper, section, fem"):
        predict("paper", model="paper", compare=("ansys",), samples=4)
