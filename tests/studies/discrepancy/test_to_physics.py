"""From a raw time series to the physical cause: delay and threshold, then the ingredient."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from softcath import design
from softcath.studies.discrepancy import run_workflow
from softcath.studies.discrepancy.model_bank import ModelBank
from softcath.studies.discrepancy.physical import predict
from softcath.studies.discrepancy.to_physics import physical_step, quasi_static_curve


def test_quasi_static_curve_takes_bin_medians():
    p = np.repeat(np.linspace(0.1, 0.5, 5), 4)
    k = 2 * p + np.tile([0.0, 0.01, -0.01, 0.0], 5)
    c = quasi_static_curve(p, k, bins=5)
    np.testing.assert_allclose(c["pressure_MPa"], np.linspace(0.1, 0.5, 5))
    np.testing.assert_allclose(c["curvature_per_mm"], 2 * np.linspace(0.1, 0.5, 5))


@pytest.mark.slow
def test_a_delayed_threshold_recording_is_taken_to_its_physical_cause():
    d = design.preset("paper")
    fs, delay, offset = 20.0, 0.5, 0.12
    t = np.arange(0, 50, 1 / fs)
    p = 0.35 - 0.15 * np.cos(2 * np.pi * 0.2 * t)  # 0.2-0.5 MPa, as the bench's sine
    bank = ModelBank(d, p_max=0.5)
    k, _ = predict(bank, ("pressure_offset",), {"pressure_offset": offset}, p, 1.0)
    k = np.interp(t - delay, t, k, left=k[0])  # the camera sees it late
    rng = np.random.default_rng(0)
    k = k + 0.001 * rng.standard_normal(t.size)
    table = pd.DataFrame({"time_s": t, "pressure_MPa": p, "curvature_per_mm": k})
    result = run_workflow(table, d)
    assert "delay" in result.named  # the time-series step finds the latency
    phys = physical_step(result, d, candidates=("pressure_offset", "filler_none", "vision_bias"))
    assert phys["delay_removed_s"] == pytest.approx(delay, abs=0.1)
    assert "pressure_offset" in phys["chosen"]
    h = next(h for h in phys["hypotheses"] if h["ingredients"] == phys["chosen"])
    assert h["parameters"]["pressure_offset"]["value"] == pytest.approx(offset, abs=0.02)
    # the physical model, fitted on the first half, shrinks the gap on the second half
    assert phys["nrmse_after"] < 0.5 * phys["nrmse_before"]
