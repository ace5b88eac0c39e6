"""The gallery's scripts run: each ``examples/gallery/plot_*.py`` finishes and draws a figure.

The documentation build (``make docs``, sphinx-gallery) runs the same scripts; this keeps them
working between builds. Each runs in its own interpreter with matplotlib's Agg backend.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
GALLERY = ROOT / "examples" / "gallery"
SCRIPTS = sorted(GALLERY.glob("plot_*.py"))

RUN = """
import runpy, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
runpy.run_path(sys.argv[1], run_name="__main__")
numbers = plt.get_fignums()
assert numbers, "the script drew no figure"
plt.figure(numbers[-1]).savefig(sys.argv[2])
"""


def test_the_gallery_has_scripts():
    assert len(SCRIPTS) >= 3
    for script in SCRIPTS:
        # sphinx-gallery takes the title from the module docstring's first underlined line.
        doc = script.read_text(encoding="utf-8").lstrip()
        assert doc.startswith('"""'), f"{script.name} has no docstring title"
        lines = doc.strip('"').strip().splitlines()
        assert len(lines) >= 2 and set(lines[1]) == {"="}, f"{script.name}: title not underlined with ="


@pytest.mark.parametrize("script", SCRIPTS, ids=[s.stem for s in SCRIPTS])
def test_gallery_script_runs_and_draws(script, tmp_path):
    png = tmp_path / "figure.png"
    env = os.environ | {"MPLBACKEND": "Agg"}
    done = subprocess.run(
        [sys.executable, "-c", RUN, str(script), str(png)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert png.stat().st_size > 5000
