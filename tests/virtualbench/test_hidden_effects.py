"""The hidden-effect generator: it hits the requested effect-to-noise ratio and noise level."""

import numpy as np
import pytest

from softcath.design.errors import DesignError
from softcath.design.measurement import Measurement, read_measurement_csv, write_measurement_csv
from softcath.studies.discrepancy import run_workflow
from softcath.virtualbench.hidden_effects import Protocol, make_case, paper_demo_case, signature_rms

SHORT = Protocol(frequencies_hz=(0.1, 0.2), cycles=2, step_hold=True, hold_s=5.0)


@pytest.mark.parametrize("effect", ["lag", "offset", "viscoelastic", "nonlinear_gain"])
def test_effect_to_noise_ratio_is_as_requested(effect):
    case = make_case(
        (effect,), seed=3, noise_fraction=0.02, effect_to_noise=2.5, protocol=SHORT, sensor_bandwidth_hz=None
    )
    # recompute the ratio independently from the noise-free plant output
    k_all, p_all = [], []
    for _, t, p in SHORT.runs():
        k_all.append(case.plant.simulate(t, p).curvature_per_mm)
        p_all.append(p)
    k, p = np.concatenate(k_all), np.concatenate(p_all)
    clean = case.gain_per_mm_MPa * p
    sigma = 0.02 * np.ptp(clean)
    # bisection/linear scaling to 1e-3 relative
    assert signature_rms(k, p) / sigma == pytest.approx(2.5, rel=1e-3)
    # the written noise has the requested s.d. (8000 samples: s.e. of an s.d. ~0.8 %)
    resid = case.table["curvature_per_mm"].to_numpy() - k
    assert np.std(resid) == pytest.approx(sigma, rel=0.04)


def test_no_effect_case_is_the_linear_model_plus_noise():
    # the same sensor response on both channels keeps measured curvature = g * measured
    # pressure + noise, so a correct model has nothing to explain
    case = make_case((), seed=5, noise_fraction=0.01, pressure_noise_fraction=1e-12, protocol=SHORT)
    assert case.effects == () and case.truth_params == {}
    resid = case.table["curvature_per_mm"] - case.gain_per_mm_MPa * case.table["pressure_MPa"]
    sigma = 0.01 * case.gain_per_mm_MPa * 2.0  # 1 % of the clean full scale (0..2 MPa)
    # 8000 samples: the s.d. estimate is within 4 % (5 s.e.), the mean within 5 s.e.
    assert float(np.std(resid)) == pytest.approx(sigma, rel=0.04)
    assert abs(float(np.mean(resid))) < 5 * sigma / np.sqrt(len(resid))
    # and the sensor is really there: the measured pressure lags the commanded one
    p_cmd = np.concatenate([p for _, _, p in SHORT.runs()])
    assert np.max(np.abs(case.table["pressure_MPa"].to_numpy() - p_cmd)) > 1e-4


def test_generated_csv_reads_with_the_project_reader(tmp_path):
    case = make_case(("delay",), seed=6, protocol=SHORT)
    path = write_measurement_csv(tmp_path / "hidden.csv", Measurement.from_table(case.table))
    m = read_measurement_csv(path)  # time increases through the file, runs labelled
    assert len(m) == len(case.table) and set(m.runs) == {"sine_0.1Hz", "sine_0.2Hz", "step_hold"}


def test_generator_rejects_impossible_requests():
    with pytest.raises(DesignError, match="effect = 'gravity'"):
        make_case(("gravity",))
    with pytest.raises(DesignError, match=r"noise_fraction = 2: must be in \(0, 1\)"):
        make_case((), noise_fraction=2.0)
    with pytest.raises(DesignError, match="the most dead_zone can produce"):
        make_case(("dead_zone",), noise_fraction=0.2, effect_to_noise=5.0, protocol=SHORT)


@pytest.mark.slow
def test_paper_demo_story_names_hysteresis_and_shrinks_the_gap():
    r = run_workflow(paper_demo_case().table, "paper")
    assert r.named[:1] == ("hysteresis",)
    assert r.ambiguous_with[0] == []  # two frequencies: hysteresis, not lag
    assert r.nrmse_before / r.nrmse_after >= 2.0
    one = run_workflow(paper_demo_case(two_frequencies=False).table, "paper", max_effects=1)
    assert one.named == ("hysteresis",) and one.ambiguous_with[0]  # the paper's single sine


def test_quasi_static_protocol_records_one_point_per_hold():
    from softcath.virtualbench.hidden_effects import quasi_static_protocol

    proto = quasi_static_protocol()
    case = make_case(("dead_zone",), seed=2, noise_fraction=0.01, effect_to_noise=1.0, protocol=proto)
    tab = case.table
    assert set(tab["run"]) == {"quasi_static_1", "quasi_static_2"}
    levels = np.r_[0.0, np.arange(1, 11) / 10, np.arange(9, 0, -1) / 10, 0.0] * proto.p_max_MPa
    for _, g in tab.groupby("run"):
        np.testing.assert_array_equal(g["time_s"], np.arange(21.0))  # the step index
        # the end of each 15 s hold: the sensor has settled on the level (noise 0.2 % of p_max)
        np.testing.assert_allclose(g["pressure_MPa"], levels, atol=5 * 0.002 * proto.p_max_MPa)
    # the effect-to-noise ratio holds on the recorded points, recomputed from the plant
    k, p = [], []
    for label, t, pr in proto.runs():
        i = proto.recorded(label, t)
        k.append(case.plant.simulate(t, pr).curvature_per_mm[i])
        p.append(pr[i])
    k, p = np.concatenate(k), np.concatenate(p)
    sigma = 0.01 * case.gain_per_mm_MPa * proto.p_max_MPa
    assert signature_rms(k, p) / sigma == pytest.approx(1.0, rel=1e-3)


def test_step_protocol_holds_only_steps():
    from softcath.studies.discrepancy.prepare import prepare
    from softcath.virtualbench.hidden_effects import step_protocol

    case = make_case((), seed=3, protocol=step_protocol())
    assert set(case.table["run"]) == {"step_hold", "staircase"}
    assert prepare(case.table).kinds() == {"step"}
