"""The measurement CSV (design.measurement): one reader, one type, one writer; bad files give
one error naming file, column and first bad line."""

import numpy as np
import pytest

from softcath.design.errors import DataError
from softcath.design.measurement import (
    COLUMNS,
    Measurement,
    read_measurement_csv,
    read_recording,
    write_measurement_csv,
)

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
            r"column pressure_MPa: 1 missing value\(s\), first at line 7",
        ),
        (
            HEADER + rows(5) + "0.1,,0.1,5,r,x\n" + rows(6, 6),
            r"column pressure_MPa: 1 missing value\(s\), first at line 7",
        ),
        (HEADER + rows(6) + rows(6), r"column time_s is not strictly increasing in run 'r0' at line 8"),
        (
            HEADER + rows(5) + "0.1,inf,0.1,5,r,x\n" + rows(6, 6),
            r"column pressure_MPa, line 7: inf is not a finite",
        ),
        (
            HEADER + rows(5) + "0.1,1e300,0.1,5,r,x\n" + rows(6, 6),
            r"column pressure_MPa, line 7: 1e\+300 is beyond the plausible bound",
        ),
        (
            "time_s,pressure_MPa,curvature_per_mm,curvature_per_mm\n" + "0,1,2,3\n" * 12,
            r"m\.csv: column curvature_per_mm appears 2 times in the header",
        ),
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
    with pytest.raises(DataError, match=r"column curvature_per_mm, row 0: nan is not a finite number"):
        Measurement.from_arrays(
            time_s=np.arange(12.0), pressure_MPa=np.ones(12), curvature_per_mm=[np.nan] + [0.0] * 11
        )


def test_time_restarts_when_the_run_changes(tmp_path):
    # runs concatenated from several files: each run's clock starts at 0 again
    text = HEADER + rows(6) + rows(6).replace(",r0,", ",r1,")
    m = read_measurement_csv(write(tmp_path, text))
    assert m.runs == ["r0", "r1"] and len(m) == 12
    np.testing.assert_allclose(m.select_run("r1").time_s, 0.005 * np.arange(6))


def test_excel_bom_is_accepted(tmp_path):
    f = tmp_path / "excel.csv"
    f.write_bytes("\ufeff".encode() + (HEADER + rows()).encode())
    m = read_measurement_csv(f)
    assert len(m) == 12 and m.time_s[1] == pytest.approx(0.005)


def test_recording_keeps_missing_cells_and_extra_numeric_columns(tmp_path):
    text = "time_s,pressure_MPa,encoder_mm,curvature_per_mm\n0,0.1,1,\n0.005,0.2,2,0.01\n"
    m = read_recording(write(tmp_path, text))
    assert np.isnan(m["curvature_per_mm"][0]) and m["encoder_mm"].tolist() == [1.0, 2.0]
    assert "encoder_mm" in m.extra and "encoder_mm" in m


def test_table_round_trip_and_same_rules():
    import pandas as pd

    t = np.arange(12) * 0.1
    df = pd.DataFrame({"time_s": t, "pressure_MPa": t, "curvature_per_mm": 0.1 * t})
    m = Measurement.from_table(df)
    assert m.runs == ["run1"] and list(m.to_table()["run"]) == ["run1"] * 12
    df.loc[3, "pressure_MPa"] = np.inf
    with pytest.raises(DataError, match=r"table: column pressure_MPa, line 5: inf is not a finite"):
        Measurement.from_table(df)


def test_schema_document_lists_every_column_with_its_unit():
    from pathlib import Path

    doc = (Path(__file__).resolve().parents[2] / "docs" / "measurement-csv.md").read_text()
    for name, unit, _, _ in COLUMNS:
        assert f"| `{name}` | {unit} |" in doc
