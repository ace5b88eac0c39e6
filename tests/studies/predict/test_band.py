"""Prediction bands against closed forms: the paper tier with one monotone parameter, the nu-log scale."""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest

from softcath import analytic, design
from softcath.design import presets
from softcath.studies.predict import Range, predict_tier
from softcath.studies.predict.band import measured_position, percentiles

E_PATH = "materials.medical_silicone_tubing.youngs_modulus"
E_LOW, E_HIGH = 1.648, 4.43
TABLE = tomllib.loads(presets.text("paper"))


def formula_gain(e_tube: float) -> float:
    """The paper's formula on a design built the scalar way (independent of the vectorised tier)."""
    t = tomllib.loads(presets.text("paper"))
    t["materials"]["medical_silicone_tubing"]["youngs_modulus"] = e_tube
    return analytic.gains(design.from_dict(t), "cap")[0]


def e_at(u: float) -> float:
    return E_LOW + min(max(u, 0.0), 1.0) * (E_HIGH - E_LOW)


def test_formula_gain_falls_with_tube_modulus():
    # the premise of the closed form below: kappa/p = P e / EI is monotone in the tube's E
    k = [formula_gain(e) for e in np.linspace(E_LOW, E_HIGH, 9)]
    assert all(b < a for a, b in zip(k, k[1:], strict=False))


@pytest.mark.parametrize("n", [50, 400])
def test_paper_percentiles_are_the_formula_at_the_transformed_quantiles(n):
    # Uniform E on [E_LOW, E_HIGH], kappa falling in E: the q-th percentile of kappa is the formula at
    # the (1 - q)-quantile of E. A 1-D Latin hypercube puts one point in each of n strata, and
    # np.percentile interpolates between neighbouring order statistics, so the sample's u-quantile lies
    # within 2/n of the exact one: the percentile must sit between the formula at u -/+ 2/n.
    r = predict_tier(TABLE, "paper", [Range(E_PATH, low=E_LOW, high=E_HIGH)], load="cap", samples=n, seed=11)
    for q in (5, 50, 95):
        u = 1 - q / 100
        got = r.gain_percentiles[f"p{q}"]
        assert formula_gain(e_at(u + 2 / n)) <= got <= formula_gain(e_at(u - 2 / n))
    # the stratum bound shrinks with n: at n = 400 the band is the formula's to 0.3 %
    if n == 400:
        assert r.gain_percentiles["p50"] == pytest.approx(formula_gain(e_at(0.5)), rel=3e-3)


def test_measured_percentile_is_the_share_of_e_above_the_matching_modulus():
    # kappa(E*) with E* at u* = 0.3: the samples at or below it are those with u >= 0.3, i.e. exactly
    # 70 % of the strata (0.3 is a stratum edge for n = 400); one stratum (0.25 %) of slack.
    n = 400
    k_star = formula_gain(e_at(0.3))
    r = predict_tier(
        TABLE,
        "paper",
        [Range(E_PATH, low=E_LOW, high=E_HIGH)],
        load="cap",
        samples=n,
        seed=5,
        measured_gain=k_star,
    )
    assert r.measured["measured_percentile"] == pytest.approx(70.0, abs=100 / n)
    assert r.measured["measured_in_band"] is True and r.measured["measured_outside"] is None


def test_measurement_outside_the_band_is_flagged():
    g = np.linspace(1.0, 2.0, 101)
    below, above = measured_position(g, 0.5), measured_position(g, 1.99)
    assert below["measured_percentile"] == 0.0 and below["measured_outside"] == "below p5"
    assert above["measured_outside"] == "above p95" and not above["measured_in_band"]
    assert above["measured_percentile"] == pytest.approx(100 * 100 / 101)  # 1.00 .. 1.99: 100 of 101 values
    assert percentiles(g) == pytest.approx({"p5": 1.05, "p50": 1.5, "p95": 1.95})


def test_nu_log_scale_is_log_uniform_in_the_gap_to_one_half():
    r = Range("materials.medical_silicone_tubing.poisson_ratio", low=0.49, high=0.4999, scale="nu-log")
    assert r.value(0.0) == pytest.approx(0.49)
    assert r.value(1.0) == pytest.approx(0.4999)
    assert 0.5 - r.value(0.5) == pytest.approx(math.sqrt(0.01 * 0.0001))  # geometric mean of the gaps


def test_categorical_levels_split_the_unit_interval_evenly():
    r = Range("model.coil_modulus", levels=("tension", "bending"))
    assert [r.value(u) for u in (0.0, 0.49, 0.5, 0.999)] == ["tension", "tension", "bending", "bending"]


def test_section_tier_percentiles_bracket_the_section_model_at_the_quantiles():
    # The section tier with only the tube's nu on the nu-log scale: kappa/p rises with nu (checked),
    # so its median lies between the section model at the u = 0.5 -/+ 2/n quantiles (as above).
    from softcath.fem.section_model import section_model

    nu = Range("materials.medical_silicone_tubing.poisson_ratio", low=0.49, high=0.4999, scale="nu-log")

    def direct(u):
        t = tomllib.loads(presets.text("paper"))
        t["materials"]["medical_silicone_tubing"]["poisson_ratio"] = nu.value(min(max(u, 0.0), 1.0))
        return section_model(design.from_dict(t), loads=("lumen",)).curvature_per_mm_per_MPa["lumen"]

    n = 8
    lo, mid, hi = direct(0.5 - 2 / n), direct(0.5), direct(0.5 + 2 / n)
    assert lo < mid < hi
    r = predict_tier(TABLE, "section", [nu], load="lumen", samples=n, seed=2)
    assert lo <= r.gain_percentiles["p50"] <= hi
    assert r.nominal_gain == pytest.approx(direct(0.0), rel=1e-9)  # the preset's nu = 0.49 is u = 0
