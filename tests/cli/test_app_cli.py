"""``softcath app``: serves on 127.0.0.1, prints its address, stops on SIGTERM; a bad design is one line."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "src"), str(ROOT)]))


def test_a_bad_design_is_refused_before_serving(cli):
    line = cli("app", "nonexistent.toml", "--no-browser").error_line()
    assert line.startswith("softcath app: error: file = 'nonexistent.toml': does not exist")
    assert "--port" in cli("app", "paper", "--port", "70000", "--no-browser").error_line()


@pytest.mark.slow
def test_the_app_serves_its_page_on_localhost_and_stops_on_sigterm():
    proc = subprocess.Popen(
        [sys.executable, "-m", "softcath", "app", "paper", "--no-browser"],
        cwd=ROOT,
        env=ENV,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert proc.stdout is not None
        line = proc.stdout.readline()  # printed once the server listens
        assert line.startswith("softcath app: serving paper at http://127.0.0.1:"), line
        url = line.split(" at ")[1].split()[0]
        with urllib.request.urlopen(url, timeout=120) as page:
            assert page.status == 200 and "<title>softcath app</title>" in page.read().decode()
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
        assert proc.returncode == 130 and "softcath app: terminated" in err
        assert "Traceback" not in err
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
