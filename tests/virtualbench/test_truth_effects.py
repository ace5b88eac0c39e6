"""The truth effects against closed forms, one effect at a time (through a plant with no other effect)."""

import numpy as np
import pytest

from softcath.design.errors import DesignError
from softcath.virtualbench.truth_effects import EFFECT_NAMES, make_effect
from tests.virtualbench._plants import FS, plant_with, sine


def test_first_order_lag_matches_sine_steady_state_amplitude():
    # one RC section is a first-order lag: steady amplitude 1/sqrt(1+(w tau)^2)
    tau, f = 0.5, 0.4
    t = np.arange(0, 40, 1 / FS)
    p = np.sin(2 * np.pi * f * t)
    y = plant_with(make_effect("lag", tau_s=tau, sections=1), g=1.0).simulate(t, p).curvature_per_mm
    late = t > 20  # transients decayed (20 s = 40 tau)
    amp = np.sqrt(2 * np.mean(y[late] ** 2))
    # tolerance: the discretisation is exact for piecewise-linear input; the residual
    # error is the sampled-sine vs piecewise-linear difference, O((w h)^2) ~ 1e-4
    assert amp == pytest.approx(1 / np.hypot(1, 2 * np.pi * f * tau), rel=2e-4)


def test_ladder_step_has_unit_gain_and_elmore_mean_delay():
    tau = 0.3
    t = np.arange(0, 30, 1 / FS)
    p = (t >= 1.0).astype(float)
    y = plant_with(make_effect("lag", tau_s=tau), g=1.0).simulate(t, p).curvature_per_mm
    assert y[-1] == pytest.approx(1.0, abs=1e-9)
    # Elmore: the area between the step and the response is the mean delay tau.
    # Tolerance: rectangle rule on a 5 ms grid, error < h = 0.005 s.
    area = np.sum((p - y)[t >= 1.0]) / FS
    assert area == pytest.approx(tau, abs=0.006)


def test_nonuniform_time_base_agrees_with_uniform():
    t, p = sine(f=0.2, cycles=2)
    rng = np.random.default_rng(1)
    # every third sample, jittered by one: irregular gaps of 1..5 samples
    keep = np.arange(3, t.size - 3, 3) + rng.integers(-1, 2, size=(t.size - 4) // 3)
    keep = np.concatenate([[0], keep])
    plant = plant_with(make_effect("lag", tau_s=0.4), make_effect("viscoelastic", tau_s=1.0))
    full = plant.simulate(t, p).curvature_per_mm
    part = plant.simulate(t[keep], p[keep]).curvature_per_mm
    # both integrate their piecewise-linear input exactly; the only difference is the
    # input interpolation over gaps <= 25 ms: h^2/8 max|p''| ~ 1.2e-5 MPa, times the
    # creep-amplified gain ~2.5 -> ~3e-5, below 2e-4 of the 0.5 range
    np.testing.assert_allclose(part, full[keep], atol=2e-4 * np.ptp(full))


def test_delay_shifts_the_output():
    t, p = sine()
    r = plant_with(make_effect("delay", delay_s=0.25), g=1.0).simulate(t, p)
    late = t > 0.25
    expect = np.interp(t[late] - 0.25, t, p)
    np.testing.assert_allclose(r.curvature_per_mm[late], expect, atol=1e-15)


def test_dead_zone_is_a_rounded_threshold():
    t, p = sine()
    y = plant_with(make_effect("dead_zone", threshold_MPa=0.02), g=1.0).simulate(t, p).curvature_per_mm
    far = p > 0.05  # 15 corner widths above the threshold: softplus error < s e^-15
    np.testing.assert_allclose(y[far], p[far] - 0.02, atol=1e-8)
    assert np.all(y[p < 0.004] < 1e-6)  # s e^-8 = 6.7e-7 below
    hard = plant_with(make_effect("dead_zone", threshold_MPa=0.02, smoothness_MPa=0.0), g=1.0)
    np.testing.assert_array_equal(hard.simulate(t, p).curvature_per_mm, np.maximum(p - 0.02, 0))


def test_viscoelastic_creep_matches_two_kelvin_units():
    c, tau = 0.4, 1.5
    t = np.arange(0, 40, 1 / FS)
    p = (t >= 1.0).astype(float)
    y = plant_with(make_effect("viscoelastic", creep_fraction=c, tau_s=tau), g=1.0).simulate(t, p)
    s = np.clip(t - 1.0, 0, None)
    expect = p * (1 + c * (1 - 0.5 * np.exp(-s / (tau / 2)) - 0.5 * np.exp(-s / (2 * tau))))
    # tolerance: the step falls between samples; the piecewise-linear input ramps over
    # one 5 ms sample, a shift of h/2 in time, i.e. < c h / tau ~ 1.3e-3 at the jump
    np.testing.assert_allclose(y.curvature_per_mm[t > 1.05], expect[t > 1.05], atol=2e-3)


def test_offset_and_exponential_gain():
    t, p = sine()
    y = plant_with(make_effect("offset", curvature_per_mm=0.01), g=2.0).simulate(t, p)
    np.testing.assert_allclose(y.curvature_per_mm, 2.0 * p + 0.01, atol=1e-15)
    z = plant_with(make_effect("nonlinear_gain", beta_per_MPa=-2.0), g=1.0).simulate(t, p)
    # exp(x) - 1 written out loses ~1e-17 absolute to cancellation near p = 0
    np.testing.assert_allclose(z.curvature_per_mm, (np.exp(-2.0 * p) - 1) / -2.0, atol=1e-15)


def test_preisach_loop_is_rate_independent_with_predicted_opening():
    eff = make_effect("hysteresis", loop_width_MPa=0.03, fraction=0.5, range_MPa=0.2)
    plant = plant_with(eff, g=1.0)
    gaps = []
    for f in (0.05, 0.5):
        t, p = sine(f=f, cycles=2)
        y = plant.simulate(t, p).curvature_per_mm
        second = t >= 1 / f
        rising = second & (np.gradient(p) > 0)
        falling = second & (np.gradient(p) < 0)
        grid = np.array([0.08, 0.1, 0.12])
        up = np.interp(grid, p[rising], y[rising])
        order = np.argsort(p[falling])
        down = np.interp(grid, p[falling][order], y[falling][order])
        gaps.append(down - up)
    # rate independence: same loop at 10x the frequency (sampling differences only,
    # bounded by the relay staircase step 0.23/80 * fraction)
    np.testing.assert_allclose(gaps[0], gaps[1], atol=0.0015)
    # interior of the range: uniformly spread relays act as play operators, the
    # descending minus ascending branch equals fraction * mean relay width
    a, b, w, _ = eff.relays()
    mean_width = np.mean(a - b)
    np.testing.assert_allclose(gaps[0], 0.5 * mean_width, atol=0.0015)


@pytest.mark.parametrize("name", EFFECT_NAMES)
def test_every_effect_has_defaults_and_records_its_params(name):
    eff = make_effect(name)
    assert eff.name == name
    assert all(np.isfinite(v) for v in eff.params().values())


def test_bad_effect_input_names_parameter_value_and_bound():
    with pytest.raises(DesignError, match=r"effect = 'wobble': must be one of"):
        make_effect("wobble")
    with pytest.raises(DesignError, match=r"lag.tau_s = -1: must be in \[0, 1000\]"):
        make_effect("lag", tau_s=-1.0)
    with pytest.raises(DesignError, match=r"delay.latency = 1: unknown"):
        make_effect("delay", latency=1.0)
