"""Which ingredients explain a prototype: synthetic prototypes made by the tool itself."""

from __future__ import annotations

import json

import numpy as np
import pytest

from softcath import design
from softcath.design.errors import DataError
from softcath.studies.discrepancy.prototype import explain_prototype, hypothesis_gains, load_prototype_csv

CANDS = ("nu_0.4999", "coil_resolved", "filler_none", "vision_bias")
P = np.linspace(0.1, 0.6, 11)


def _synthetic(ingredients, *, noise=0.02, seed=0):
    """The tool's own nominal-material prediction with ``ingredients``, plus 2 % noise."""
    from dataclasses import replace

    from softcath.fem.section_model import section_model
    from softcath.fem.section_model.coil_models import model_options
    from softcath.studies.discrepancy.prototype import _variant

    d = design.preset("paper")
    opts = model_options("resolved") if "coil_resolved" in ingredients else {}
    if "nu_0.4999" in ingredients:
        opts["silicone_poisson"] = 0.4999
    v = _variant(d, ingredients, d.tube.material.youngs_modulus, d.filler.youngs_modulus)
    g = section_model(replace(v), loads=("lumen",), **opts).curvature_per_mm_per_MPa["lumen"]
    rng = np.random.default_rng(seed)
    k = g * P * (1 + noise * rng.standard_normal(P.size))
    return d, {"pressure_MPa": P, "curvature_per_mm": k}


def test_baseline_plus_noise_names_nothing():
    d, m = _synthetic(())
    r = explain_prototype(d, m, candidates=CANDS)
    assert r["named"] == [] and r["equally_good"] == [[]]
    assert r["hypotheses"][0]["ingredients"] == [] and r["hypotheses"][0]["covers_measurement"]


def test_hidden_pair_is_named_or_flagged_among_the_equally_good():
    hidden = ["coil_resolved", "filler_none"]
    d, m = _synthetic(tuple(hidden))
    r = explain_prototype(d, m, candidates=CANDS)
    assert hidden in r["equally_good"]
    # Nothing simpler explains it, and whatever is named is in the hidden combination.
    assert all(len(h) == 2 for h in r["equally_good"])
    assert set(r["named"]) <= set(hidden)
    if len(r["equally_good"]) > 1:
        assert r["separating_measurement"]
    else:
        assert r["named"] == hidden


def test_record_is_strict_json_with_bands_at_each_pressure():
    d, m = _synthetic(())
    r = explain_prototype(d, m, candidates=("filler_none",))
    json.dumps(r, allow_nan=False)
    h = r["hypotheses"][1]
    assert h["ingredients"] == ["filler_none"] and len(h["band"]) == P.size
    assert {"named", "ambiguous_with", "notes", "hypotheses", "nrmse_before"} <= set(r)


def test_bands_trace_the_material_ranges():
    gains, _ = hypothesis_gains(design.preset("paper"), ())
    nominal = 0.23379221417652102  # section model, paper, lumen load (docs/section.md)
    assert gains.min() < nominal < gains.max()


def test_csv_errors_name_file_and_column(tmp_path):
    f = tmp_path / "m.csv"
    f.write_text("pressure_MPa,kappa\n0.1,0.02\n0.2,0.05\n")
    with pytest.raises(DataError, match=r"m\.csv: column curvature_per_mm is required"):
        load_prototype_csv(f)


def test_measured_elongation_separates_what_curvature_cannot():
    from dataclasses import replace

    from softcath.fem.section_model import section_model
    from softcath.studies.discrepancy.prototype import _variant

    hidden = ("coil_resolved", "filler_none")
    d, m = _synthetic(hidden)
    v = _variant(d, hidden, d.tube.material.youngs_modulus, d.filler.youngs_modulus)
    from softcath.fem.section_model.coil_models import model_options

    e = section_model(replace(v), loads=("lumen",), **model_options("resolved")).elongation_per_MPa["lumen"]
    rng = np.random.default_rng(1)
    m["elongation"] = e * P * (1 + 0.02 * rng.standard_normal(P.size))
    r = explain_prototype(d, m, candidates=CANDS)
    assert r["equally_good"] == [list(hidden)] and r["named"] == list(hidden)
