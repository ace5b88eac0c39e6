"""Bands of the finite-strain bend curve and a measured curve placed in them point by point."""

from __future__ import annotations

import numpy as np
import pytest

from softcath.design.errors import DesignError
from softcath.design.measurement import Measurement
from softcath.studies.predict.curve_band import curve_bands, measured_points


def test_measured_points_take_the_median_within_half_a_step():
    p = np.array([0.09, 0.1, 0.11, 0.29, 0.31, 0.65, np.nan])
    k = np.array([1.0, 2.0, 30.0, 4.0, 6.0, 9.0, 1.0])
    pts = measured_points(p, k, [0.1, 0.3, 0.5])
    assert [pt["measured_curvature_per_mm"] for pt in pts] == [2.0, 5.0, None]
    assert [pt["points"] for pt in pts] == [3, 2, 0]


def test_curve_bands_place_a_measured_curve_pressure_by_pressure():
    pressures = [0.2, 0.5]
    doc = curve_bands("paper", pressures, samples=4, seed=3)
    assert doc["feasible_samples"] == 4 and len(doc["pressures"]) == 2
    for pt in doc["pressures"]:
        band = pt["curvature_percentiles"]
        assert band["p5"] <= band["p50"] <= band["p95"]
    # the finite-strain curve is convex: its band at 0.5 MPa lies above 2.5x the band at 0.2
    assert (
        doc["pressures"][1]["curvature_percentiles"]["p50"]
        > 2.5 * doc["pressures"][0]["curvature_percentiles"]["p50"]
    )
    # a measured curve equal to the p50 at each pressure sits at the band's middle, point by point
    p50 = [pt["curvature_percentiles"]["p50"] for pt in doc["pressures"]]
    p = np.repeat(pressures, 5)
    m = Measurement(
        {"time_s": np.arange(p.size) * 0.01, "pressure_MPa": p, "curvature_per_mm": np.repeat(p50, 5)}
    )
    placed = curve_bands("paper", pressures, samples=4, seed=3, measured=m)["measured"]
    assert placed["pressures_compared"] == 2 and placed["pressures_in_band"] == 2
    for pt in placed["points"]:
        assert pt["measured_over_p50"] == pytest.approx(1.0, rel=1e-12)
        assert 25 <= pt["measured_percentile"] <= 75
    assert placed["gain_line_fit"] == pytest.approx((p50[1] - p50[0]) / 0.3, rel=1e-9)


@pytest.mark.parametrize(("kw", "name"), [({"samples": 1}, "samples"), ({"pressures": [0.3]}, "pressures")])
def test_curve_bands_refuse_before_work(kw, name):
    args = {"pressures": [0.1, 0.3], **kw}
    with pytest.raises(DesignError, match=name):
        curve_bands("paper", args.pop("pressures"), **args)
