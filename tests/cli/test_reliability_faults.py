"""Faults through real ``softcath`` subprocesses: SIGTERM after gmsh ran, two sweeps into one folder."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _softcath(*argv, cache: Path, **kw) -> subprocess.Popen:
    # A fresh mesh cache makes the command run gmsh itself (a cached mesh would skip it).
    env = dict(os.environ, PYTHONPATH=str(ROOT), SOFTCATH_CACHE=str(cache))
    kw = {"stdout": subprocess.PIPE, "stderr": subprocess.PIPE, **kw}
    return subprocess.Popen(
        [sys.executable, "-m", "softcath", *map(str, argv)], cwd=ROOT, env=env, text=True, **kw
    )


def _temps(folder: Path) -> list[str]:
    return [p.name for p in folder.rglob("*") if ".tmp" in p.name or "staging" in p.name]


def _sweep_spec(path: Path, n: int) -> Path:
    path.write_text(
        f"""
[sweep]
name = "sig"
base = "paper"
pressures_MPa = [0.1, 0.3]
loads = ["lumen"]
evaluators = ["section"]
chunk_size = 1
[sample]
n = {n}
[parameters]
"tube.h" = {{ lhs = [-0.03, 0.03] }}
""",
        encoding="utf-8",
    )
    return path


def test_sigterm_after_gmsh_ran_in_a_sweep_ends_cleanly(tmp_path):
    """gmsh resets SIGTERM to terminate at C level; the sweep must still stop with its clean-up."""
    spec = _sweep_spec(tmp_path / "spec.toml", 200)
    out = tmp_path / "sweep"
    proc = _softcath("sweep", spec, "--out", out, "--workers", "1", cache=tmp_path / "cache")
    tasks = out / "tasks"
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not (tasks.exists() and len(list(tasks.glob("t*.parquet"))) >= 2):
        time.sleep(0.05)
    assert proc.poll() is None, proc.communicate()
    proc.send_signal(signal.SIGTERM)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, stderr
    assert "terminated" in stderr and "Traceback" not in stderr
    assert not _temps(out)


@pytest.mark.slow
def test_sigterm_after_gmsh_ran_in_fem_ends_cleanly(tmp_path):
    out = tmp_path / "fem"
    proc = _softcath("fem", "paper", "--pressure", "0.1", "--out", out, cache=tmp_path / "cache")
    deadline = time.monotonic() + 120
    seen = ""
    while time.monotonic() < deadline and "[3/5] solving" not in seen:
        line = proc.stderr.readline()
        if not line:
            break
        seen += line
    assert "[3/5] solving" in seen, seen
    proc.send_signal(signal.SIGTERM)
    _, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, seen + stderr
    assert "softcath fem: terminated" in stderr and "Traceback" not in stderr
    assert not _temps(out)


def test_a_second_sweep_into_the_same_folder_is_refused(tmp_path):
    spec = _sweep_spec(tmp_path / "spec.toml", 200)
    out = tmp_path / "sweep"
    first = _softcath("sweep", spec, "--out", out, "--workers", "1", cache=tmp_path / "cache")
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not (out / "tasks").exists():
            time.sleep(0.05)
        second = _softcath("sweep", spec, "--out", out, "--workers", "1", cache=tmp_path / "cache")
        _, stderr = second.communicate(timeout=60)
        assert second.returncode == 2, stderr
        assert "--out" in stderr and "another sweep" in stderr and "Traceback" not in stderr
    finally:
        first.send_signal(signal.SIGTERM)
        first.communicate(timeout=60)
    assert first.returncode == 130
