"""Candidate effects against closed forms, and the chain fit against known truths."""

import numpy as np
import pytest

from softcath.analytic import effects
from softcath.analytic.effects import Scales, get
from softcath.analytic.effects.base import first_order
from softcath.analytic.effects.fit import Segment, fit_chain, predict_chain
from softcath.analytic.effects.hysteresis import play
from softcath.design.errors import DesignError

DT = 0.05


def _sine(f=0.1, cycles=3, amp=1.0):
    t = np.arange(0, cycles / f, DT)
    return t, amp / 2 * (1 - np.cos(2 * np.pi * f * t))


def test_registry_lists_every_effect_and_rejects_unknown():
    assert set(effects.names()) == {
        "hysteresis",
        "lag",
        "delay",
        "dead_zone",
        "viscoelastic",
        "offset",
        "nonlinear_gain",
        "lumen_wall",
    }
    for name in effects.names():
        c = get(name)
        assert c.meaning and c.name == name
        for q in c.params:
            assert q.unit and q.doc
    with pytest.raises(DesignError, match=r"effect = 'wobble': must be one of"):
        get("wobble")


def test_param_unit_mapping_round_trips_within_bounds():
    s = Scales(pressure_MPa=2.0, duration_s=60.0)
    for name in effects.names():
        for q in get(name).params:
            lo, hi = q.bounds(s)
            assert lo < hi
            for z in (0.0, 0.3, 1.0):
                v = q.to_value(z, s)
                assert lo - 1e-12 <= v <= hi + 1e-12
                assert q.to_unit(v, s) == pytest.approx(z, abs=1e-9)


def test_play_scan_equals_the_plain_recursion():
    # independent peer: the textbook backlash recursion, one sample at a time
    rng = np.random.default_rng(4)
    x = np.cumsum(rng.normal(size=2500))
    r = np.array([0.0, 0.3, 1.0, 4.0])
    y_ref = np.empty((x.size, r.size))
    y = x[0] - r
    for k, xk in enumerate(x):
        y = np.minimum(np.maximum(y, xk - r), xk + r)
        y_ref[k] = y
    np.testing.assert_array_equal(play(x, r), y_ref)


def test_pi_loop_opening_is_fraction_times_width():
    t, p = _sine(amp=1.0)
    y = get("hysteresis").apply(DT, p, fraction=0.4, loop_width_MPa=0.2)
    second = t >= 10
    up = second & (np.gradient(p) > 0)
    down = second & (np.gradient(p) < 0)
    o = np.argsort(p[down])
    grid = np.array([0.4, 0.5, 0.6])  # interior: every play has reversed fully
    gap = np.interp(grid, p[down][o], y[down][o]) - np.interp(grid, p[up], y[up])
    # each play of radius r opens 2r; the mean of 2 r_i is the width; sampling of the
    # branches by linear interpolation errs by < slope * step ~ 0.016 * 0.4
    np.testing.assert_allclose(gap, 0.4 * 0.2, atol=0.007)


def test_first_order_sine_gain_and_phase():
    tau, f = 0.4, 0.3
    t = np.arange(0, 60, DT)
    u = np.sin(2 * np.pi * f * t)
    z = first_order(DT, u, tau)
    late = t > 20
    w = 2 * np.pi * f
    ref = np.sin(w * t - np.arctan(w * tau)) / np.hypot(1, w * tau)
    # exact for piecewise-linear input; the linear interpolant of a sampled sine has
    # its amplitude off by (w h)^2/12 = 7.4e-4 here
    np.testing.assert_allclose(z[late], ref[late], atol=1e-3)


def test_delay_of_a_smooth_signal_is_a_shift():
    t, p = _sine(f=0.2)
    y = get("delay").apply(DT, p, delay_s=0.123)
    ref = 0.5 * (1 - np.cos(2 * np.pi * 0.2 * (t - 0.123)))
    # cubic spline on (w h) = 0.063: error ~ (w h)^4 / 384 of the amplitude, < 1e-6
    np.testing.assert_allclose(y[t > 1], ref[t > 1], atol=2e-6)


def test_static_candidates_and_creep_closed_forms():
    t, p = _sine()
    np.testing.assert_array_equal(get("dead_zone").apply(DT, p, threshold_MPa=0.2), np.maximum(p - 0.2, 0))
    np.testing.assert_allclose(
        get("nonlinear_gain").apply(DT, p, beta_per_MPa=-0.8), p - 0.4 * p**2, rtol=1e-14
    )
    step = (np.arange(0, 30, DT) >= 1.0).astype(float)
    tt = np.arange(0, 30, DT)
    z = get("viscoelastic").apply(DT, step, creep_fraction=0.5, tau_s=2.0)
    s = np.clip(tt - 1.0, 0, None)
    # the FOH treats the step as a one-sample ramp: a time shift of h/2 -> error
    # < c h / (2 tau) = 6e-3 right at the step, decaying with it
    np.testing.assert_allclose(z[tt > 1.1], (1 + 0.5 * (1 - np.exp(-s / 2.0)))[tt > 1.1], atol=7e-3)


def _segments(y_fn, filt, freqs=(0.05, 0.2)):
    segs = []
    for f in freqs:
        t, p = _sine(f=f, cycles=3, amp=2.0)
        y = filt(y_fn(p))
        mask = np.zeros(t.size, bool)
        mask[20:-20] = True
        segs.append(Segment(dt_s=DT, pressure_MPa=p, target=y, mask=mask, label=f"{f}"))
    return segs


def test_fit_recovers_gain_lag_and_offset_of_noise_free_data():
    from scipy import signal

    sos = signal.butter(4, 1.0, fs=1 / DT, output="sos")

    def filt(x):
        return signal.sosfiltfilt(sos, x, axis=0)

    lag = get("lag")
    truth = lambda p: 0.07 * lag.apply(DT, p, tau_s=0.8) + 0.004  # noqa: E731
    segs = _segments(truth, filt)
    fit = fit_chain(
        ["offset", "lag"], segs, output_filter=filt, scales=Scales(pressure_MPa=2.0, duration_s=60.0)
    )
    # noise-free data generated by the candidate itself: recovery is limited only by
    # the optimiser's tolerance (xtol 1e-6 on the unit scale)
    assert fit.params["lag"]["tau_s"] == pytest.approx(0.8, rel=1e-3)
    assert fit.gain == pytest.approx(0.07, rel=1e-4)
    assert fit.coefficients["offset"] == pytest.approx(0.004, rel=1e-3)
    pred = predict_chain(fit, segs[0], output_filter=filt)
    assert np.max(np.abs(pred - segs[0].target)) < 1e-6


def test_fixed_gain_and_lumen_column():
    lum = get("lumen_wall")
    ident = lambda x: np.asarray(x, float)  # noqa: E731
    ctx = {"lumen_minus_cap_gain_per_mm_MPa": -0.05}
    truth = lambda p: 0.07 * p + 0.8 * lum.column(DT, p, **ctx)  # noqa: E731
    segs = _segments(truth, ident)
    fit = fit_chain(
        ["lumen_wall"],
        segs,
        output_filter=ident,
        fixed_gain=0.07,
        context=ctx,
        scales=Scales(pressure_MPa=2.0, duration_s=60.0),
    )
    assert fit.gain == 0.07 and fit.fixed_gain
    # linear least squares on exact data: exact to rounding
    assert fit.coefficients["lumen_wall"] == pytest.approx(0.8, rel=1e-10)


def test_fit_rejects_duplicate_effects():
    with pytest.raises(DesignError, match="each effect at most once"):
        fit_chain(
            ["lag", "lag"], [], output_filter=lambda x: x, scales=Scales(pressure_MPa=1.0, duration_s=1.0)
        )
