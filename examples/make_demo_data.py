"""Regenerate ``studies/data/bench_hysteresis.csv``, the demo's bundled bench data.

The paper's data shape: sinusoidal pressure (0.1 and 0.25 Hz, 3 cycles each, 0–2 MPa)
on the paper design with a squeezed, offset lumen (``examples/bench_tip.toml``: what the
calibration should find), recorded through the **virtual bench** (pseudo-terminal devices,
rendered camera frames, the real recorder and tip-measurement pipeline), with a hidden
rate-independent hysteresis (a Preisach plant, which the workflow's candidates do not
share in form) of about the size the paper's Fig. 4 shows. Two frequencies, so the
missing-effect workflow can tell hysteresis from lag. Seeded: the file is reproducible.
Run: ``python examples/make_demo_data.py``.
"""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

from softcath.cli.main import main

ARGS = [
    "bench",
    str(Path(__file__).with_name("bench_tip.toml")),
    "--effect",
    "hysteresis:loop_width_MPa=0.4,fraction=0.3,range_MPa=2.0",
    "--waveform",
    "sine",
    "--freq",
    "0.1,0.25",
    "--cycles",
    "3",
    "--pressure-max",
    "2",
    "--seed",
    "1",
]

if __name__ == "__main__":
    target = Path(__file__).parents[1] / "studies" / "data" / "bench_hysteresis.csv"
    with tempfile.TemporaryDirectory() as tmp:
        code = main([*ARGS, "--out", tmp])
        if code:
            sys.exit(code)
        shutil.copy(Path(tmp) / "run.csv", target)
        shutil.copy(Path(tmp) / "truth.json", target.with_suffix(".truth.json"))
    print(f"wrote {target}")
