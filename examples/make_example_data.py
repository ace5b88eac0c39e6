"""Regenerate ``studies/data/paper_sine.csv``: the analytic model plus noise (seeded).

The "true" tip is the paper design with a squeezed, offset lumen
(a = nominal, a_int = 0.13, b_int = 0.09, h = 0.02 mm) that the nominal
shape does not know; the pressure is the paper's kind of excitation, a
0.25 Hz sine from 0 to 2 MPa for 5 cycles at 200 Hz. Gaussian noise of 1 %
of full scale is added to curvature and arc length, 0.5 % to pressure.
Run: ``python examples/make_example_data.py [OUT.csv]``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from softcath import analytic, design
from softcath.design.measurement import Measurement, write_measurement_csv

TRUE_SHAPE = {"a_int": 0.13, "b_int": 0.09, "h": 0.02}
SEED = 20240521


def make(seed: int = SEED) -> Measurement:
    base = design.preset("paper")
    truth = base.with_tube_shape(a=base.tube_shape["a"], **TRUE_SHAPE)
    t = np.arange(0, 20.0, 1 / 200)
    p_true = 2.0 * (1 - np.cos(2 * np.pi * 0.25 * t)) / 2
    r = analytic.response(truth, p_true)
    rng = np.random.default_rng(seed)
    noise = lambda x, frac: x + frac * np.ptp(x) * rng.standard_normal(x.shape)  # noqa: E731
    return Measurement.from_arrays(
        time_s=t,
        pressure_MPa=noise(p_true, 0.005),
        curvature_per_mm=noise(r.curvature, 0.01),
        arc_length_mm=noise(r.arc_length, 0.01),
        source="paper_sine",
    )


if __name__ == "__main__":
    out = (
        Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parents[1] / "studies/data/paper_sine.csv"
    )
    write_measurement_csv(out, make())
    print(f"wrote {out}")
