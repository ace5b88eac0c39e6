"""The virtual bench end to end, through the command line and the real recorder."""

from __future__ import annotations

import json

import numpy as np
import pytest

from softcath import design
from softcath.cli.main import main
from softcath.design.measurement import read_measurement_csv as read_peer
from softcath.design.measurement import read_recording
from softcath.hardware.stage import SyringeModel
from softcath.virtualbench.bench import BenchConfig, make_plant, run_bench

SHORT = ["--freq", "2", "--cycles", "1", "--fps", "25"]


def test_cli_bench_outputs_match_the_plant(tmp_path, capsys):
    out = tmp_path / "b"
    assert main(["bench", "--out", str(out), *SHORT]) == 0
    for name in ("run.csv", "frames.avi", "truth.json", "truth.csv", "bench.png"):
        assert (out / name).stat().st_size > 0
    assert "curvature RMS error" in capsys.readouterr().out
    # the strict measurement-CSV reader accepts the file
    m = read_peer(out / "run.csv")
    assert m.runs == ["sine_2Hz"]
    truth = json.loads((out / "truth.json").read_text())
    assert truth["seed"] == 0 and truth["excitation"]["waveform"] == "sine"
    assert truth["record"]["devices"]["pressure sensor"]["corrupted"] == 0
    # measured curvature vs the analytic model of the measured pressure: the gain is the
    # analytic response of the paper design at 1 MPa (closed form of the linear model)
    k_gain = make_plant(design.preset("paper")).curvature_per_mpa
    tr = read_recording(out / "truth.csv")
    run = read_recording(out / "run.csv")
    # (both columns are printed with 9 significant digits: rtol 1e-8)
    np.testing.assert_allclose(tr["curvature_per_mm"], k_gain * tr["pressure_MPa"], rtol=1e-8, atol=1e-15)
    # camera noise 2 grey levels, 40 px/mm: the default method is within 2 % of the peak
    # curvature at every row (frames are 25 Hz, rows 200 Hz: interpolation between frames
    # of a 2 Hz sine adds <= (2 pi 2)^2 A / (8 * 25^2) = 0.3 % of the amplitude A)
    err = run["curvature_per_mm"] - np.interp(run["time_s"], tr["time_s"], tr["curvature_per_mm"])
    peak = tr["curvature_per_mm"].max()
    assert np.nanmax(np.abs(err)) < 0.02 * peak
    # the pressure sensor: truth plus 2 kPa white noise (5 sigma bound on every sample)
    assert np.max(np.abs(run["pressure_MPa"] - tr["pressure_MPa"])) < 5 * 0.002
    # the peak pressure reaches the requested 2 MPa within the stage's microstep quantisation
    assert tr["pressure_MPa"].max() == pytest.approx(2.0, abs=1e-3)


def test_bench_is_deterministic_for_a_seed(tmp_path):
    cfg = BenchConfig(freqs_hz=(2.0,), cycles=1, fps=25.0, rest_s=0.25)
    d = design.preset("paper")
    a = run_bench(d, tmp_path / "a", cfg)
    b = run_bench(d, tmp_path / "b", cfg)
    assert (tmp_path / "a" / "run.csv").read_bytes() == (tmp_path / "b" / "run.csv").read_bytes()
    assert a.rows == b.rows == int(round(cfg.duration_s * 200)) + 1


@pytest.mark.parametrize("waveform", ["triangle", "steps"])
def test_stage_waveforms_follow_their_closed_forms(tmp_path, waveform):
    cfg = BenchConfig(waveform=waveform, freqs_hz=(2.0,), cycles=1, fps=10.0, noise=0.0)
    run_bench(design.preset("paper"), tmp_path, cfg)
    tr = read_recording(tmp_path / "truth.csv")
    run = read_recording(tmp_path / "run.csv")
    syr = SyringeModel()
    x_max = syr.displacement_mm(2.0)
    t = tr["time_s"] - cfg.rest_s
    phase = np.mod(t, 0.5) / 0.5
    inside = (t >= 0) & (t < 0.5)
    if waveform == "triangle":
        expect = x_max * np.where(phase < 0.5, 2 * phase, 2 - 2 * phase)
        tol = 2e-3 * x_max  # speed is rounded to whole Zaber velocity units
    else:
        levels = np.array([0.25, 0.5, 0.75, 1.0, 0.75, 0.5, 0.25, 0.0])
        j = np.minimum((phase * 8).astype(int), 7)
        expect = x_max * levels[j]
        # moves take 1/20 of a hold: compare only the settled second half of each hold
        inside &= np.mod(phase * 8, 1) > 0.5
        tol = 1e-3 * x_max
    np.testing.assert_allclose(tr["stage_mm"][inside], expect[inside], atol=tol)
    # the encoder reports the stage through the serial protocol, exactly (microsteps)
    np.testing.assert_allclose(run["encoder_mm"], tr["stage_mm"][: len(run["encoder_mm"])], atol=1e-4)


def test_effects_reach_the_plant(tmp_path):
    out = tmp_path / "e"
    assert main(["bench", "--out", str(out), *SHORT, "--effect", "offset:curvature_per_mm=0.02"]) == 0
    truth = json.loads((out / "truth.json").read_text())
    assert [e["name"] for e in truth["plant"]["effects"]] == ["offset"]
    run = read_recording(out / "run.csv")
    rest = run["time_s"] < 0.4  # zero pressure: the pre-curvature alone
    assert np.nanmedian(run["curvature_per_mm"][rest]) == pytest.approx(0.02, rel=0.03)


def test_bad_bench_input_is_one_line_and_exit_2(tmp_path, capsys):
    assert main(["bench", "--out", str(tmp_path), "--freq", "abc"]) == 2
    assert "--freq = 'abc': must be numbers" in capsys.readouterr().err
    assert main(["bench", "--out", str(tmp_path), "--pressure-max", "-1"]) == 2
    assert "pressure_max_MPa = -1: must be in (0, 10] MPa" in capsys.readouterr().err
    assert main(["bench", "--out", str(tmp_path), "--effect", "lag:tau_s"]) == 2


@pytest.mark.slow
def test_default_bench_run(tmp_path):
    # the default end-to-end run (speed is measured in benchmarks/, not here)
    assert main(["bench", "--out", str(tmp_path)]) == 0
    run = read_peer(tmp_path / "run.csv")
    assert run.runs == ["sine_0.5Hz", "sine_1Hz"]
    assert len(run) == int(round(BenchConfig().duration_s * 200)) + 1


def test_parse_effect():
    from softcath.cli.bench import parse_effect

    assert parse_effect("lag") == ("lag", {})
    assert parse_effect("hysteresis:n_centres=40, fraction=0.5") == (
        "hysteresis",
        {"n_centres": 40, "fraction": 0.5},
    )
    assert isinstance(parse_effect("x:n=3")[1]["n"], int)
