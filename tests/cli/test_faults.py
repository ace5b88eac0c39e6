"""Faults: SIGTERM and SIGKILL of record, sweep, calibrate and fem; a device that never speaks."""

from __future__ import annotations

import hashlib
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from softcath.design.measurement import read_recording
from softcath.virtualbench.devices import VirtualLineDevice

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "studies" / "data"
ENV = dict(os.environ, PYTHONPATH=str(ROOT))


def _softcath(*argv, **kw) -> subprocess.Popen:
    kw = {"stdout": subprocess.PIPE, "stderr": subprocess.PIPE, **kw}
    return subprocess.Popen(
        [sys.executable, "-m", "softcath", *map(str, argv)], cwd=ROOT, env=ENV, text=True, **kw
    )


def _digest(folder: Path) -> dict[str, str]:
    """Content hashes of the visible files (a SIGKILLed writer may leave a hidden temporary file)."""
    files = [p for p in sorted(folder.iterdir()) if p.is_file() and not p.name.startswith(".")]
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in files}


def _wait_for(predicate, timeout_s: float, poll_s: float = 0.002) -> bool:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(poll_s)
    return False


def test_a_device_that_never_speaks_ends_a_timed_recording(tmp_path, cli):
    t0 = time.monotonic()
    r = cli(
        "record",
        "--pressure-port",
        "loop://",
        "--encoder-port",
        "loop://",
        "--duration",
        "0.3",
        "--out",
        tmp_path / "r",
    )
    elapsed = time.monotonic() - t0
    line = r.error_line()
    assert "no rows recorded (no data): no device spoke within 0.3 s" in line
    assert "pressure sensor on loop://: 0 lines" in line
    # the duration, then RecorderConfig.silent_start_s = 2 s of grace for a slow first line
    assert 2.3 <= elapsed < 15
    summary = json.loads((tmp_path / "r" / "record.json").read_text())
    assert summary["rows"] == 0 and summary["stop_reason"] == "no data"


def test_sigterm_stops_a_recording_with_its_summary(tmp_path):
    press, enc = VirtualLineDevice(), VirtualLineDevice()
    press.start_paced(lambda t: 0.3, rate_hz=200.0)
    enc.start_paced(lambda t: 2.0, rate_hz=200.0)
    out = tmp_path / "rec"
    proc = _softcath("record", "--pressure-port", press.url, "--encoder-port", enc.url, "--out", out)
    csv_path = out / "measurements.csv"
    assert _wait_for(lambda: csv_path.exists() and csv_path.read_text().count("\n") > 100, 30, 0.05)
    proc.send_signal(signal.SIGTERM)
    stdout, stderr = proc.communicate(timeout=30)
    press.close()
    enc.close()
    assert proc.returncode == 0, stderr
    assert "Traceback" not in stderr
    summary = json.loads((out / "record.json").read_text())
    data = read_recording(csv_path)
    assert summary["rows"] == len(data.time_s) >= 100 and summary["stop_reason"] == "interrupted"
    np.testing.assert_allclose(data.pressure_MPa, 0.3)
    assert "stop: interrupted" in stdout


def _descendants(pid: int) -> list[int]:
    psutil = pytest.importorskip("psutil")
    return [p.pid for p in psutil.Process(pid).children(recursive=True)]


def _parent(pid: int) -> int | None:
    import psutil

    try:
        return psutil.Process(pid).ppid()
    except psutil.NoSuchProcess:
        return None


def _running(pids) -> list[int]:
    import psutil

    alive = []
    for pid in pids:
        try:
            if psutil.Process(pid).status() != psutil.STATUS_ZOMBIE:
                alive.append(pid)
        except psutil.NoSuchProcess:
            pass
    return alive


@pytest.mark.slow
def test_sigkill_of_a_sweep_takes_its_workers_and_resume_is_exact(spec_writer, tmp_path, cli):
    n = 150
    spec = spec_writer(
        f"""
        [sweep]
        name = "killed"
        pressures_MPa = [0.5, 1.0]
        loads = ["cap"]
        chunk_size = 1
        seed = 5
        [sample]
        n = {n}
        [parameters]
        "tube.h" = {{ lhs = [-0.04, 0.04] }}
        """
    )
    out = tmp_path / "s"
    # no pipes: a worker that outlived the sweep would hold them open
    proc = _softcath(
        "sweep",
        spec,
        "--out",
        out,
        "--workers",
        "2",
        "--no-progress",
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    tasks = out / "tasks"
    assert _wait_for(lambda: tasks.is_dir() and len(list(tasks.glob("t*.parquet"))) >= 5, 120, 0.01)
    helpers = _descendants(proc.pid)  # the fork server, the pool's workers, a resource tracker
    pool = [pid for pid in helpers if _parent(pid) != proc.pid]  # the workers: children of the fork server
    assert len(pool) == 2
    os.kill(proc.pid, signal.SIGKILL)
    # not reaped yet (a zombie, as under a parent that is slow to wait): the workers go anyway
    assert _wait_for(lambda: not _running(pool), 10, 0.05), f"left running: {_running(pool)}"
    proc.wait(timeout=30)
    assert _wait_for(lambda: not _running(helpers), 10, 0.05), f"left running: {_running(helpers)}"
    done = len(list(tasks.glob("t*.parquet")))
    assert done < n, "the sweep finished before it was killed"

    r = cli("sweep", spec, "--out", out, "--workers", "1", "--no-progress")
    assert r.status == 0, r.err
    assert f"{done} of {n} tasks already done" in r.out
    fresh = tmp_path / "fresh"
    assert cli("sweep", spec, "--out", fresh, "--workers", "1", "--no-progress").status == 0
    a, b = pd.read_parquet(out / "results.parquet"), pd.read_parquet(fresh / "results.parquet")
    cols = [c for c in a.columns if not c.endswith("_seconds")]
    pd.testing.assert_frame_equal(a[cols], b[cols])


def _first_temp(folder: Path) -> bool:
    return any(p.name.startswith(".") and ".tmp" in p.name for p in folder.iterdir())


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_calibrate_killed_mid_write_keeps_whole_outputs(tmp_path, cli, sig):
    out = tmp_path / "cal"
    assert cli("calibrate", DATA / "paper_sine.csv", "--out", out, "--grid", "1").status == 0
    good = _digest(out)
    # another fit (two free parameters) into the same folder, killed while it writes its outputs
    proc = _softcath("calibrate", DATA / "paper_sine.csv", "--out", out, "--free", "a_int,h", "--grid", "1")
    caught = _wait_for(lambda: proc.poll() is not None or _first_temp(out), 120, 0.0005)
    if proc.returncode is None:  # still running (else it finished first: the check below still holds)
        os.kill(proc.pid, sig)
    _, stderr = proc.communicate(timeout=30)
    assert caught and "Traceback" not in stderr
    now = _digest(out)
    assert set(now) == set(good)  # every output still there, none half-written:
    json.loads((out / "calibration.json").read_text(), parse_constant=pytest.fail)
    from softcath import design

    design.load(out / "calibrated_design.toml")
    if sig == signal.SIGTERM:
        # SIGTERM ends the command like Ctrl-C: unless the outputs were all renamed already, none was
        assert proc.returncode in (0, 130)
        assert now == good or proc.returncode == 0
        assert not _first_temp(out)  # its clean-up removed the temporary files
    # a later run clears the leftovers of a killed one
    assert cli("analytic", "paper", "--out", out).status == 0
    assert not _first_temp(out)


@pytest.mark.slow
def test_fem_terminated_during_the_solve_keeps_the_earlier_outputs(tmp_path, cli):
    out = tmp_path / "fem"
    assert cli("fem", "paper", "--pressure", "0.1", "--out", out, "--no-png").status == 0
    good = _digest(out)
    proc = _softcath("fem", "paper", "--pressure", "0.2", "--out", out, "--no-png")
    assert _wait_for(lambda: "[3/5] solving" in (proc.stderr.readline() or "[3/5] solving"), 120, 0.0)
    proc.send_signal(signal.SIGTERM)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130 and "softcath fem: terminated" in stderr and "Traceback" not in stderr
    assert _digest(out) == good and not _first_temp(out)
