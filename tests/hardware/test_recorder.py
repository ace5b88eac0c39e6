"""The recorder over real pseudo-terminals: time base, faults, unplugging and SIGKILL."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from softcath.design.errors import DesignError
from softcath.design.measurement import read_recording
from softcath.hardware.recorder import CsvSink, Recorder, RecorderConfig
from softcath.hardware.sensors import SerialSensor
from softcath.virtualbench.devices import VirtualLineDevice

ROOT = Path(__file__).resolve().parents[2]


def _p(k):  # pressure of sample k, MPa (a smooth, exactly known signal)
    return 0.05 + 0.04 * np.sin(2 * np.pi * 0.7 * k / 200.0)


def test_device_clock_rows_are_exact_and_deterministic(tmp_path):
    press, enc = VirtualLineDevice(), VirtualLineDevice()
    n = 600

    def feed():
        for k in range(n):
            if k == 300:
                press.emit_corrupted(_p(k) * 1e3)  # sample 300 is lost on the wire
            else:
                press.emit(_p(k) * 1e3)  # the sensor reports kPa
            if k % 2 == 0:  # a 100 Hz encoder: rows interpolate between its samples
                enc.emit(2.0 * k)

    # open before the devices talk: pyserial flushes the input buffer on open
    rec = Recorder(
        tmp_path / "r.csv",
        pressure=SerialSensor(press.url, name="pressure sensor", scale=1e-3).open(),
        encoder=SerialSensor(enc.url, name="encoder", scale=1e-3, rate_hz=100.0).open(),
        config=RecorderConfig(clock="device", device_rate_hz=200.0),
        segments=[(0.0, "a"), (1.0, "b")],
    )
    th = threading.Thread(target=feed)
    th.start()
    summary = rec.run(duration_s=(n - 2) / 200.0)
    th.join()
    data = read_recording(tmp_path / "r.csv")
    k = np.arange(len(data["time_s"]))
    np.testing.assert_allclose(data["time_s"], k / 200.0, atol=1e-12)
    p = data["pressure_MPa"]
    # every received sample lands exactly on its row (values printed with 9 digits)
    np.testing.assert_allclose(np.delete(p, 300), np.delete(_p(k), 300), rtol=1e-8)
    # the lost sample is interpolated: error <= max|p''| dt^2 / 8 = 0.04 (2 pi 0.7)^2 / 8e4 = 1e-5
    assert p[300] == pytest.approx(_p(300), abs=1e-5)
    # encoder sample j at t = j / 100 Hz holds 2 (2 j) counts = 4 j / 1000 mm = 0.4 mm/s * t:
    # linear in t, so the rows interpolated between 100 Hz samples are exact
    np.testing.assert_allclose(data["encoder_mm"], 0.4 * data["time_s"], atol=1e-9)
    assert list(data["run"][:2]) == ["a", "a"] and data["run"][-1] == "b"
    assert (data["run"] == "a").sum() == 200
    assert summary.devices["pressure sensor"]["corrupted"] == 1
    press.close()
    enc.close()


def test_unplugged_sensor_keeps_every_received_row(tmp_path):
    press = VirtualLineDevice()
    n = 250

    def feed():
        for k in range(n):
            press.emit(_p(k))
        time.sleep(0.3)
        press.unplug()

    # open before the device talks: pyserial flushes the input buffer on open
    sensor = SerialSensor(press.url, name="pressure sensor").open()
    rec = Recorder(
        tmp_path / "u.csv",
        pressure=sensor,
        config=RecorderConfig(clock="device", reconnect_timeout_s=0.3),
    )
    th = threading.Thread(target=feed)
    th.start()
    summary = rec.run()
    th.join()
    data = read_recording(tmp_path / "u.csv")
    assert len(data["time_s"]) == n
    np.testing.assert_allclose(data["pressure_MPa"], _p(np.arange(n)), rtol=1e-8)
    assert summary.stop_reason == "pressure sensor lost"
    assert any("disconnected" in m for m in summary.messages)
    assert any("stopping cleanly" in m for m in summary.messages)
    press.close()


def test_csv_sink_syncs_at_least_every_second(tmp_path):
    sink = CsvSink(tmp_path / "s.csv", ["time_s", "pressure_MPa"], fsync_interval_s=0.05)
    sink.append({"time_s": 0.0, "pressure_MPa": float("nan")})
    sink.flush()
    time.sleep(0.06)
    sink.append({"time_s": 0.005, "pressure_MPa": 0.1})
    sink.flush()
    assert sink.rows_synced == 2
    sink.close()
    assert (tmp_path / "s.csv").read_text() == "time_s,pressure_MPa\n0,\n0.005,0.1\n"
    with pytest.raises(DesignError, match=r"fsync_interval_s = 5: must be in \(0, 1\] s"):
        RecorderConfig(fsync_interval_s=5.0)


def _record_subprocess(press, enc, out, *extra: str, stdout) -> subprocess.Popen:
    """``softcath record`` on the two virtual devices in a child process, as a user runs it."""
    cmd = [
        sys.executable,
        "-m",
        "softcath",
        "record",
        "--pressure-port",
        press.url,
        "--encoder-port",
        enc.url,
    ]
    return subprocess.Popen(
        [*cmd, *extra, "--out", str(out)],
        cwd=ROOT,
        env=dict(os.environ, PYTHONPATH=str(ROOT)),
        stdout=stdout,
        stderr=subprocess.PIPE,
    )


def _wait_for_rows(csv_path, rows: int, timeout_s: float = 20.0) -> int:
    """Data rows in ``csv_path`` once at least ``rows`` are there (or the count at the timeout)."""
    deadline = time.monotonic() + timeout_s
    seen = 0
    while time.monotonic() < deadline:
        if csv_path.exists():
            seen = csv_path.read_text().count("\n") - 1
            if seen >= rows:
                break
        time.sleep(0.05)
    return seen


def test_sigkill_leaves_a_valid_csv_with_every_flushed_row(tmp_path):
    press, enc = VirtualLineDevice(), VirtualLineDevice()
    press.start_paced(lambda t: 0.05 + 0.01 * t, rate_hz=200.0)
    enc.start_paced(lambda t: 3.0 * t, rate_hz=200.0)
    out = tmp_path / "rec"
    proc = _record_subprocess(press, enc, out, "--clock", "device", stdout=subprocess.DEVNULL)
    csv_path = out / "measurements.csv"
    before = _wait_for_rows(csv_path, 300)
    os.kill(proc.pid, signal.SIGKILL)
    _, err = proc.communicate(timeout=10)
    press.close()
    enc.close()
    assert proc.returncode == -signal.SIGKILL
    assert before >= 300, err.decode()
    text = csv_path.read_text()
    assert text.endswith("\n")  # no torn last line
    data = read_recording(csv_path)
    assert len(data["time_s"]) >= before
    np.testing.assert_allclose(np.diff(data["time_s"]), 0.005, atol=1e-9)
    assert not np.isnan(data["pressure_MPa"]).any()
    # pressure is 0.05 + 0.01 t on the device's clock, which started before the recorder:
    # consecutive rows differ by exactly 0.01 MPa/s * 5 ms (no row lost or duplicated)
    np.testing.assert_allclose(np.diff(data["pressure_MPa"]), 0.01 * 0.005, atol=1e-9)


def test_sigint_stops_a_recording_cleanly(tmp_path):
    press, enc = VirtualLineDevice(), VirtualLineDevice()
    press.start_paced(lambda t: 0.2, rate_hz=200.0)
    enc.start_paced(lambda t: 1.0, rate_hz=200.0)
    out = tmp_path / "rec"
    proc = _record_subprocess(press, enc, out, stdout=subprocess.PIPE)
    csv_path = out / "measurements.csv"
    _wait_for_rows(csv_path, 100)
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=20)
    press.close()
    enc.close()
    assert proc.returncode == 0, stderr.decode()
    assert "stop: interrupted" in stdout.decode()
    summary = json.loads((out / "record.json").read_text())
    data = read_recording(csv_path)
    assert summary["rows"] == len(data["time_s"]) >= 100
    np.testing.assert_allclose(data["pressure_MPa"], 0.2)


def _pressure_and_encoder(tmp_path, name: str, **config):
    """A paced 200 Hz pressure sensor (100 kPa), a quiet encoder device, and a host-clock recorder on both."""
    press, enc = VirtualLineDevice(), VirtualLineDevice()
    p_sensor = SerialSensor(press.url, name="pressure sensor", scale=1e-3).open()
    e_sensor = SerialSensor(enc.url, name="encoder").open()
    press.start_paced(lambda t: 100.0, rate_hz=200.0)
    rec = Recorder(
        tmp_path / name, pressure=p_sensor, encoder=e_sensor, config=RecorderConfig(clock="host", **config)
    )
    return press, enc, rec


def test_host_clock_rows_start_when_every_sensor_has_spoken(tmp_path):
    # The encoder starts 0.2 s after the pressure sensor: no row may carry an encoder gap at the start
    # (this raced under load before: the first row came before the encoder's first line).
    press, enc, rec = _pressure_and_encoder(tmp_path, "late.csv")
    threading.Timer(0.2, lambda: enc.start_paced(lambda t: 7.0, rate_hz=200.0)).start()
    rec.run(duration_s=0.5)
    press.close()
    enc.close()
    data = read_recording(tmp_path / "late.csv")
    assert len(data["time_s"]) == 101  # 0.5 s at 200 Hz, both ends
    assert np.all(np.isfinite(data["encoder_mm"])) and np.all(np.isfinite(data["pressure_MPa"]))
    assert data["time_s"][0] >= 0.2  # the clock starts at the encoder's first line, not the pressure's


def test_host_clock_does_not_wait_for_a_silent_sensor(tmp_path):
    press, enc, rec = _pressure_and_encoder(tmp_path, "silent.csv", max_wait_s=0.2)
    rec.run(duration_s=0.3)
    press.close()
    enc.close()
    data = read_recording(tmp_path / "silent.csv")
    assert len(data["time_s"]) == 61
    assert np.all(np.isnan(data["encoder_mm"])) and np.all(np.isfinite(data["pressure_MPa"]))
