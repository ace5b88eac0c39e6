"""A response's table and files: unit-bearing columns, strict JSON, a lossless round trip."""

from __future__ import annotations

import json

import numpy as np
import pytest

from softcath import design, models
from softcath.models import TipResponse

PAPER = design.preset("paper")


@pytest.fixture(scope="module")
def response():
    return models.response(PAPER, [0.0, 0.05, 1.0], tier="paper", load="cap")


def test_the_table_has_one_row_per_pressure_and_unit_bearing_columns(response):
    t = response.to_table()
    assert len(t) == 3
    assert list(t.columns[:3]) == ["pressure_MPa", "curvature_per_mm", "tip_curvature_per_mm"]
    np.testing.assert_array_equal(t["bend_angle_deg"], np.degrees(response.bend_angle_rad))
    units = response.units()
    assert units["pressure_MPa"] == "MPa" and units["lumen_volume_change_mm3"] == "mm^3"
    assert set(units) == set(t.columns)


def test_write_then_read_gives_the_same_response(response, tmp_path):
    csv, js = response.write(tmp_path / "out")
    assert (csv.name, js.name) == ("response.csv", "response.json")
    doc = json.loads(js.read_text())
    assert doc["table"] == "response.csv" and doc["tier"] == "paper"
    assert doc["rows"][0]["lumen_volume_change_mm3"] is None  # NaN as null: strict JSON
    assert doc["warnings"] == list(response.warnings) and doc["warnings"]  # 1 MPa: past 5 deg
    back = TipResponse.read(js)
    for name in models.OBSERVABLES:
        np.testing.assert_array_equal(getattr(back, name), getattr(response, name))
    np.testing.assert_array_equal(back.pressures, response.pressures)
    assert (back.tier, back.load, back.warnings) == (response.tier, response.load, response.warnings)
    assert back.parameters == response.parameters
    # the CSV is the same table (17 significant digits: floats round-trip exactly)
    import pandas as pd

    pd.testing.assert_frame_equal(pd.read_csv(csv), response.to_table())


def test_extras_are_columns_with_their_unit(tmp_path):
    r = models.response(PAPER, [0.1], tier="paper")
    r2 = TipResponse(**{**r.__dict__, "extras": {"section_formula_ratio": np.array([3.0])}})
    assert r2.units()["section_formula_ratio"] == "-"
    _, js = r2.write(tmp_path, stem="with_extra")
    assert TipResponse.read(js).extras["section_formula_ratio"][0] == 3.0


def test_a_failed_design_of_a_batch_raises_its_own_error():
    b = models.responses([PAPER], [0.1], tier="paper", loads=("cap",))["cap"]
    broken = type(b)(**{**b.__dict__, "errors": {0: RuntimeError("no solve")}})
    with pytest.raises(RuntimeError, match="no solve"):
        broken[0]
    assert len(b) == 1
