"""Which physical ingredients explain a prototype: synthetic prototypes made by the tool itself.

Each synthetic prototype is the finite-strain section model of the paper design with hidden
ingredients, sampled at the real bench's pressures, plus 2 % noise.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from softcath import design
from softcath.design.errors import DataError, DesignError
from softcath.studies.discrepancy.model_bank import ModelBank
from softcath.studies.discrepancy.physical import predict
from softcath.studies.discrepancy.prototype import explain_prototype, load_prototype_csv

P = np.linspace(0.2, 0.5, 13)
FEW = ("filler_none", "pressure_offset", "vision_bias")


@pytest.fixture(scope="module")
def paper():
    return design.preset("paper")


def _synthetic(d, ingredients, values, *, noise=0.02, seed=0):
    bank = ModelBank(d, p_max=float(P.max()))
    k, _ = predict(bank, ingredients, values, P, 1.0)
    rng = np.random.default_rng(seed)
    return {"pressure_MPa": P, "curvature_per_mm": k * (1 + noise * rng.standard_normal(P.size))}


def test_baseline_plus_noise_names_nothing(paper):
    m = _synthetic(paper, (), {})
    r = explain_prototype(paper, m, candidates=FEW, max_size=2)
    assert r["named"] == [] and r["equally_good"] == [[]] and r["explained"]
    base = r["hypotheses"][0]
    assert base["ingredients"] == [] and base["covers_measurement"] and base["nrmse"] < 0.05


def test_hidden_pair_is_named_or_flagged_among_the_equally_good(paper):
    hidden = ["filler_none", "pressure_offset"]
    m = _synthetic(paper, hidden, {"pressure_offset": 0.1})
    r = explain_prototype(paper, m, candidates=FEW, max_size=2)
    assert hidden in r["equally_good"]
    assert all(len(h) == 2 for h in r["equally_good"])  # nothing simpler explains it
    assert set(r["named"]) <= set(hidden)
    if len(r["equally_good"]) > 1:
        assert r["separating_measurement"] and r["ambiguous_with"] == r["equally_good"]
    else:
        assert r["named"] == hidden
    h = next(h for h in r["hypotheses"] if h["ingredients"] == hidden)
    # the chosen offset is the hidden one within the noise's reach
    assert h["parameters"]["pressure_offset"]["value"] == pytest.approx(0.1, abs=0.02)


def test_a_curve_outside_every_range_is_reported_unexplained(paper):
    # twice the baseline's curvature: no ingredient inside its range doubles the gain
    m = _synthetic(paper, (), {})
    m["curvature_per_mm"] = 2.5 * m["curvature_per_mm"]
    r = explain_prototype(paper, m, candidates=FEW, max_size=2)
    assert not r["explained"] and r["named"] == [] and r["equally_good"] == []
    assert any("no hypothesis of up to 2 ingredients" in n for n in r["notes"])
    assert not r["hypotheses"][0]["covers_measurement"]
    # what the data would need: the best refitted with its pinned range ends moved out, never worse
    beyond = r["beyond_ranges"]
    if any(
        v["at_range_end"]
        for h in r["hypotheses"]
        if h["ingredients"] == r["best"]
        for v in h["parameters"].values()
    ):
        assert beyond is not None and beyond["nrmse"] <= r["best_nrmse"] + 1e-3
        assert beyond["text"] in r["notes"]


def test_record_is_strict_json_with_predictions_at_each_pressure(paper):
    m = _synthetic(paper, (), {})
    r = explain_prototype(paper, m, candidates=("pressure_offset",), max_size=1)
    json.dumps(r, allow_nan=False)
    h = r["hypotheses"][1]
    assert h["ingredients"] == ["pressure_offset"]
    assert len(h["predicted"]["curvature_per_mm"]) == P.size == len(h["band"]) == len(h["covered"])
    par = h["parameters"]["pressure_offset"]
    assert par["unit"] == "MPa" and par["range"] == [0.0, 0.21] and par["source"]
    assert 0.0 <= par["value"] <= 0.21
    assert {"named", "ambiguous_with", "notes", "hypotheses", "nrmse_before", "tier"} <= set(r)
    assert r["tier"] == "finite-strain section"


def test_unknown_candidate_is_refused_by_name(paper):
    m = _synthetic(paper, (), {})
    with pytest.raises(DesignError, match=r"--candidates = .coil_resolved.: must be among tube_modulus"):
        explain_prototype(paper, m, candidates=("coil_resolved",))


def test_csv_errors_name_file_line_and_column(tmp_path):
    f = tmp_path / "m.csv"
    f.write_text("pressure_MPa,kappa\n0.1,0.02\n0.2,0.05\n")
    with pytest.raises(DataError, match=r"m\.csv: column curvature_per_mm is required"):
        load_prototype_csv(f)
    f.write_text("pressure_MPa,curvature_per_mm\n0.1,0.02\n0.2\n0.3,0.1\n0.4,0.2\n")
    with pytest.raises(DataError, match=r"m\.csv: line 3: column curvature_per_mm is empty"):
        load_prototype_csv(f)
    f.write_bytes(b"pressure_MPa,curvature_per_mm\n0.1,\xff\xfe\n")
    with pytest.raises(DataError, match=r"m\.csv: not UTF-8"):
        load_prototype_csv(f)
    f.write_text("pressure_MPa,curvature_per_mm\n" + "".join(f"{b},{0.01 * b}\n" for b in (2, 3, 4, 5)))
    with pytest.raises(DataError, match=r"reaches 5: .*in bar"):
        load_prototype_csv(f)
