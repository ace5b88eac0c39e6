"""The measurement CSV: bad files give one error naming file, column and first bad line."""

import numpy as np
import pytest

from analytic.io import Measurement, read_measurement_csv, write_measurement_csv
from design.errors import DataError

HEADER = "time_s,pressure_MPa,curvature_per_mm,arc_length_mm,run,comment\n"


def rows(n=12, start=0):
    return "".join(
        f"{0.005 * i},{0.1 * i},{0.01 * i},{5 + 0.001 * i},r{i // 6},x\n" for i in range(start, start + n)
    )


def write(tmp_path, text, name="m.csv"):
    f = tmp_path / name
    f.write_text(text)
    return f


def test_reads_optional_run_and_extra_columns(tmp_path):
    m = read_measurement_csv(write(tmp_path, HEADER + rows()))
    assert len(m) == 12 and m.runs == ["r0", "r1"]
    assert m.arc_length_mm is not None and "comment" in m.extra
    assert np.allclose(m.elongation(5.0), 0.0002 * np.arange(12))
    assert len(m.select_run("r1")) == 6


def test_round_trip(tmp_path):
    m = read_measurement_csv(write(tmp_path, HEADER + rows()))
    again = read_measurement_csv(write_measurement_csv(tmp_path / "o.csv", m))
    assert np.allclose(again.curvature_per_mm, m.curvature_per_mm) and list(again.run) == list(m.run)


@pytest.mark.parametrize(
    "text,message",
    [
        ("time_s,pressure_MPa\n" + "0,1\n" * 12, r"m\.csv: missing required column\(s\) curvature_per_mm"),
        (HEADER + rows(3), r"m\.csv: 3 usable rows, need at least 10"),
        (
            HEADER + rows(5) + "0.1,abc,0.1,5,r,x\n" + rows(6, 5),
            r"column pressure_MPa, line 7: 'abc' is not a number",
        ),
        (
            HEADER + rows(5) + "0.1,nan,0.1,5,r,x\n" + rows(6, 6),
            r"column pressure_MPa: 1 missing/NaN value\(s\), first at line 7",
        ),
        (
            HEADER + rows(5) + "0.1,,0.1,5,r,x\n" + rows(6, 6),
            r"column pressure_MPa: 1 missing/NaN value\(s\), first at line 7",
        ),
        (HEADER + rows(6) + rows(6), r"column time_s is not strictly increasing at line 8"),
        (HEADER + rows(5) + "1,2\n", r"line 7 has 2 fields, header has 6"),
        ("", r"file is empty"),
    ],
)
def test_bad_files(tmp_path, text, message):
    with pytest.raises(DataError, match=message):
        read_measurement_csv(write(tmp_path, text))


def test_missing_rows_can_be_dropped_and_are_reported(tmp_path, caplog):
    text = HEADER + rows(5) + "0.026,,0.1,5,r,x\n" + rows(10, 6)
    m = read_measurement_csv(write(tmp_path, text), missing="drop")
    assert len(m) == 15 and m.dropped == (7,)
    assert "dropped 1 row(s)" in caplog.text


def test_missing_file_and_binary_file(tmp_path):
    with pytest.raises(DataError, match="file not found"):
        read_measurement_csv(tmp_path / "nope.csv")
    (tmp_path / "b.csv").write_bytes(b"\xff\xfe\x00\x01garbage")
    with pytest.raises(DataError, match="b.csv"):
        read_measurement_csv(tmp_path / "b.csv")


def test_from_arrays_validates():
    with pytest.raises(DataError, match="column curvature_per_mm: 1 non-finite"):
        Measurement.from_arrays(
            time_s=np.arange(12.0), pressure_MPa=np.ones(12), curvature_per_mm=[np.nan] + [0.0] * 11
        )
