"""The eq. 8 shape optimisation: recovery, noise bound, staying inside X, bad data."""

from pathlib import Path

import numpy as np
import pytest

from softcath import analytic, design
from softcath.analytic.calibration import _inside, calibrate
from softcath.design.errors import DesignError
from softcath.design.measurement import Measurement

DATA = Path(__file__).parents[3] / "studies" / "data" / "paper_sine.csv"


def series(truth, *, noise=0.0, seed=0, duration=20.0, fs=200.0):
    t = np.arange(0, duration, 1 / fs)
    p = 2.0 * (1 - np.cos(2 * np.pi * 0.25 * t)) / 2
    r = analytic.response(truth, p)
    rng = np.random.default_rng(seed)
    k = r.curvature + noise * np.ptp(r.curvature) * rng.standard_normal(t.size)
    arc = r.arc_length + noise * np.ptp(r.arc_length) * rng.standard_normal(t.size)
    return Measurement.from_arrays(time_s=t, pressure_MPa=p, curvature_per_mm=k, arc_length_mm=arc)


@pytest.fixture(scope="module")
def paper():
    return design.preset("paper")


@pytest.mark.parametrize(
    "free,true", [(("a_int", "h"), {"a_int": 0.13, "h": 0.02}), (("b_int", "h"), {"b_int": 0.1, "h": -0.01})]
)
def test_recovers_known_shape_from_noise_free_data(paper, free, true):
    """Two gains determine two free shape numbers: recovery to 1e-4 relative (IPOPT tol 1e-12)."""
    shape = dict(paper.tube_shape, **true)
    m = series(paper.with_tube_shape(**shape))
    res = calibrate(m, paper, free=free)
    assert res.identifiable and res.reachable
    for k in free:
        assert res.x_opt[k] == pytest.approx(shape[k], rel=1e-4, abs=1e-8)
    assert res.starts_at_optimum >= 1 and res.starts >= res.starts_at_optimum


def test_all_four_free_fits_the_gains_but_says_x_is_not_identifiable(paper):
    truth = paper.with_tube_shape(a=0.2, a_int=0.12, b_int=0.09, h=0.02)
    res = calibrate(series(truth), paper)
    assert not res.identifiable and "not identifiable" in res.message
    k_true, e_true = analytic.gains(truth)
    assert res.gains_model["curvature_per_mm_per_MPa"] == pytest.approx(k_true, rel=1e-6)
    assert res.gains_model["elongation_per_MPa"] == pytest.approx(e_true, rel=1e-6)
    assert res.nrmse_optimized < 1e-5 < res.nrmse_nominal


def test_noise_stays_within_the_noise_implied_bound(paper):
    """With white noise σ the LS gain has standard error σ/√Σp²; the fit must lie within 5 of those."""
    truth = paper.with_tube_shape(**dict(paper.tube_shape, a_int=0.13, h=0.02))
    noise = 0.02
    m = series(truth, noise=noise, seed=3)
    res = calibrate(m, paper, free=("a_int", "h"))
    k_true, e_true = analytic.gains(truth)
    p = m.pressure_MPa
    sigma_k = noise * np.ptp(analytic.response(truth, p).curvature)
    sigma_e = noise * np.ptp(analytic.response(truth, p).arc_length) / paper.tip.bending_length
    se_k, se_e = sigma_k / np.sqrt(p @ p), sigma_e / np.sqrt(p @ p)
    assert abs(res.gains_model["curvature_per_mm_per_MPa"] - k_true) < 5 * se_k
    assert abs(res.gains_model["elongation_per_MPa"] - e_true) < 5 * se_e
    # the optimised NRMSE sits at the noise floor: σ/range ≈ noise, not above 1.1 × noise
    assert res.nrmse_optimized < 1.1 * noise


@pytest.mark.parametrize("scale", [10.0, 0.01, -1.0])
def test_unreachable_gains_give_best_fit_inside_X(paper, scale):
    m = series(paper)
    m = Measurement.from_arrays(
        time_s=m.time_s,
        pressure_MPa=m.pressure_MPa,
        curvature_per_mm=scale * m.curvature_per_mm,
        arc_length_mm=m.arc_length_mm,
    )
    res = calibrate(m, paper)
    assert not res.reachable and "cannot reach" in res.message
    assert _inside(paper, res.x_opt)
    assert design.loads(design.dumps(res.design)) == res.design  # the calibrated design validates


def test_bundled_example_is_reproducible_and_calibrates():
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "mk", Path(__file__).parents[3] / "examples/make_example_data.py"
    )
    mk = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mk)
    regenerated = mk.make()
    from softcath.design.measurement import read_measurement_csv

    bundled = read_measurement_csv(DATA)
    assert np.allclose(bundled.curvature_per_mm, regenerated.curvature_per_mm, rtol=1e-8, atol=1e-12)
    res = calibrate(bundled, design.preset("paper"))
    assert res.reachable and res.ratio > 5


def test_gain_scale_fits_a_scaled_model_exactly(paper):
    """Data from the formula's gains times (2.5, 0.5) at a known shape: the scaled fit recovers the shape
    (to the same 1e-4 as the unscaled recovery); the unscaled fit cannot."""
    shape = dict(paper.tube_shape, a_int=0.11, h=0.01)
    truth = paper.with_tube_shape(**shape)
    m0 = series(truth)
    k, e = analytic.gains(truth, "cap")
    p = m0.pressure_MPa
    m = Measurement.from_arrays(
        time_s=m0.time_s,
        pressure_MPa=p,
        curvature_per_mm=2.5 * k * p,
        arc_length_mm=truth.tip.bending_length * (1 + 0.5 * e * p),
    )
    res = calibrate(m, paper, free=("a_int", "h"), gain_scale=(2.5, 0.5))
    assert res.reachable
    for key in ("a_int", "h"):
        assert res.x_opt[key] == pytest.approx(shape[key], rel=1e-4, abs=1e-8)
    assert res.gains_model["curvature_per_mm_per_MPa"] == pytest.approx(2.5 * k, rel=1e-6)
    with pytest.raises(DesignError, match="gain_scale"):
        calibrate(m, paper, free=("h",), gain_scale=(0.0, 1.0))
