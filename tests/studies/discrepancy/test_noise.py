"""The noise of a measured curve, from the data alone."""

from __future__ import annotations

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from softcath.studies.discrepancy.noise import data_noise


def test_repeat_points_give_the_pooled_within_pressure_sd():
    p = np.repeat([0.1, 0.2, 0.3], 2)
    y = np.array([1.0, 3.0, 5.0, 7.0, 2.0, 2.0])
    n = data_noise(p, y)
    # within-pair deviations: +-1, +-1, 0; pooled variance (1+1+1+1)/3
    assert n.dof == 3 and np.isclose(n.sigma, np.sqrt(4 / 3)) and "repeat" in n.method


def test_scatter_about_a_smooth_curve_recovers_the_noise_on_average():
    p = np.linspace(0.2, 0.5, 13)
    w = 0.04  # a threshold with a knee as wide as a bench curve's
    truth = 0.02 + 0.9 * w * np.log1p(np.exp((p - 0.29) / w))
    rng = np.random.default_rng(3)
    ratios = [data_noise(p, truth + 0.003 * rng.standard_normal(p.size)).sigma / 0.003 for _ in range(200)]
    # the knee is not a polynomial: its misfit may inflate the estimate a little (the safe side:
    # a model is then judged more leniently), never halve it
    assert 0.9 < float(np.median(ratios)) < 1.3


@settings(max_examples=30, deadline=None)
@given(a=st.floats(-1, 1), b=st.floats(-5, 5), c=st.floats(-5, 5))
@example(a=-1.0, b=0.0, c=0.0)  # a curve of zeros: the floor is then 1e-3 in the curve's units
def test_an_exact_polynomial_has_only_the_round_off_floor(a, b, c):
    p = np.linspace(0.1, 0.6, 9)
    y = a + b * p + c * p**2 + 1.0
    n = data_noise(p, y)
    # the floor is 1e-3 of the largest |value|, or of 1 where every value is 0 (a sigma must be > 0)
    assert n.sigma <= 1e-3 * (np.max(np.abs(y)) or 1.0) * (1 + 1e-9)
