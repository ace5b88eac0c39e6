"""Property test over CSV content: the reader returns finite, valid data or one clean error."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from softcath.design.errors import DataError
from softcath.design.measurement import LIMITS, REQUIRED, read_measurement_csv

NAMES = ["time_s", "pressure_MPa", "curvature_per_mm", "arc_length_mm", "run", "note", ""]
CELLS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-5, 30).map(str),
    st.sampled_from(["", "nan", "NaN", "inf", "-inf", "1e300", "abc", "r0", "r1", " 3 ", '"1,5"']),
)


@st.composite
def csv_text(draw):
    header = draw(st.lists(st.sampled_from(NAMES), min_size=1, max_size=6))
    n = draw(st.integers(0, 25))
    body = []
    for i in range(n):
        if draw(st.booleans()):
            # a plausible row: increasing time, so that valid files occur often
            cells = [
                str(0.1 * i) if h == "time_s" else draw(st.sampled_from(["0.5", "1", "r0"])) for h in header
            ]
        else:
            cells = draw(st.lists(CELLS, min_size=len(header) - 1, max_size=len(header) + 1))
        body.append(",".join(cells))
    bom = "\ufeff" if draw(st.booleans()) else ""
    return bom + ",".join(header) + "\n" + "\n".join(body) + ("\n" if body else "")


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=csv_text())
def test_reader_returns_valid_data_or_one_line_error(text):
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "fuzz.csv"
        path.write_text(text, encoding="utf-8")
        try:
            m = read_measurement_csv(path)
        except DataError as exc:
            msg = str(exc)
            assert msg.startswith(str(path)) and "\n" not in msg
            return
    for c in REQUIRED:
        v = m[c]
        assert np.all(np.isfinite(v)) and np.all(np.abs(v) <= LIMITS[c])
    labels = m.run_labels()
    for r in m.runs:
        assert np.all(np.diff(m.time_s[labels == r]) > 0)
