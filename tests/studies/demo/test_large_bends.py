"""The demo's four tiers of the bend and the pressure each needs for 90 degrees."""

from __future__ import annotations

import math

import pytest

from softcath import analytic, design
from softcath.studies.demo.large_bends import _pressure_for, four_tiers


def test_pressure_for_interpolates_the_first_crossing():
    assert _pressure_for(1.0, [1.0, 2.0, 3.0], [0.5, 1.5, 0.2]) == pytest.approx(1.5)
    assert _pressure_for(2.0, [1.0, 2.0], [0.5, 1.5]) is None


def test_four_tiers_without_the_3d_fem(tmp_path):
    d = design.preset("paper")
    rows, extra = four_tiers(d, None, tmp_path / "tiers.png")
    p90 = {name: p for name, p, *_ in rows}
    # the formula's own closed form: kappa p L (1 + eps p) = pi/2, a quadratic in p
    k, e = analytic.gains(d, "cap")
    a, b, c = k * e * d.tip.bending_length, k * d.tip.bending_length, -math.pi / 2
    formula = next(v for k, v in p90.items() if k.startswith("paper"))
    assert formula == pytest.approx((-b + math.sqrt(b * b - 4 * a * c)) / (2 * a), rel=1e-9)
    finite = next(v for k, v in p90.items() if k.startswith("finite-strain"))
    linear = next(v for k, v in p90.items() if k.startswith("linear"))
    assert (
        0.7 < finite < 0.9 < linear < formula
    )  # large bends come at lower pressure than the linear tiers say
    assert (tmp_path / "tiers.png").stat().st_size > 10_000
