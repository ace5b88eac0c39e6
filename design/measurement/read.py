"""The one reader of measurement CSV files; every error names file, column and line."""

from __future__ import annotations

import csv
import logging
from pathlib import Path

import numpy as np

from softcath.core.errors import DataError
from softcath.design.measurement.record import Measurement, check_time, check_values
from softcath.design.measurement.schema import MIN_ROWS, OPTIONAL, REQUIRED, RUN

__all__ = ["read_measurement_csv", "read_recording"]

log = logging.getLogger(__name__)

_MISSING = ("error", "drop", "keep")


def _cell(text: str) -> float:
    """A cell as a float: empty and ``nan`` are missing (NaN); anything else must parse."""
    text = text.strip()
    if text == "" or text.lower() == "nan":
        return np.nan
    return float(text)


def _read_rows(path: Path) -> tuple[list[str], list[list[str]]]:
    src = str(path)
    try:
        # utf-8-sig: Excel's "CSV UTF-8" starts with a byte-order mark
        fh = path.open(newline="", encoding="utf-8-sig")
    except FileNotFoundError:
        raise DataError(f"{src}: file not found") from None
    except IsADirectoryError:
        raise DataError(f"{src}: is a directory, not a CSV file") from None
    except PermissionError:
        raise DataError(f"{src}: not readable (permission denied)") from None
    with fh:
        reader = csv.reader(fh)
        try:
            header = next(reader, None)
            if header is None:
                raise DataError(f"{src}: file is empty (no header row)")
            rows = list(reader)
        except UnicodeDecodeError as exc:
            raise DataError(f"{src}: not a UTF-8 text CSV file ({exc.reason})") from None
        except csv.Error as exc:
            raise DataError(f"{src}: malformed CSV at line {reader.line_num}: {exc}") from None
    header = [h.strip() for h in header]
    named = [h for h in header if h]
    for h in dict.fromkeys(named):
        if named.count(h) > 1:
            raise DataError(
                f"{src}: column {h} appears {named.count(h)} times in the header; "
                "which one is meant is ambiguous (rename or delete the copies)"
            )
    return header, rows


def read_measurement_csv(
    path: str | Path,
    *,
    missing: str = "error",
    required: tuple[str, ...] = REQUIRED,
    min_rows: int = MIN_ROWS,
) -> Measurement:
    """Read and validate a measurement CSV (schema: ``softcath.design.measurement.schema``).

    Parameters
    ----------
    path
        The CSV file (header row first; a UTF-8 byte-order mark is accepted).
    missing
        What to do with a missing (empty or ``nan``) value in a required column:
        ``"error"`` (default) names the column and first line; ``"drop"`` drops
        the rows, logs and keeps their line numbers in
        :attr:`Measurement.dropped`; ``"keep"`` keeps them as NaN (raw recordings
        whose camera columns are empty while the camera has no frame).
    required
        Columns that must be present (default: the schema's three).
    min_rows
        Fewest usable rows.

    Raises
    ------
    DataError
        Missing file or columns, a duplicated column, non-numeric cells, infinite
        or implausible values (beyond ``schema.LIMITS``), missing required values
        (with ``missing="error"``), too few rows, or ``time_s`` not strictly
        increasing within a run. The message names file, column and line.
    """
    if missing not in _MISSING:
        raise DataError(f"missing = {missing!r}: must be one of {', '.join(_MISSING)}")
    path = Path(path)
    src = str(path)
    header, rows = _read_rows(path)
    index, lines = _check_columns(src, header, rows, required)
    numbers, text = _parse_columns(src, rows, index, lines)
    bad, dropped = _missing_rows(src, numbers, lines, missing)
    keep = ~bad
    if int(keep.sum()) < min_rows:
        raise DataError(f"{src}: {int(keep.sum())} usable rows, need at least {min_rows}")
    run = None
    if RUN in index:
        run = np.array([row[index[RUN]].strip() for row in rows], dtype=str)[keep]
    m = Measurement(
        {c: v[keep] for c, v in numbers.items()},
        run,
        {c: v[keep] for c, v in text.items()},
        src,
        dropped,
    )
    if "time_s" in numbers:
        check_time(m, lines[keep])
    return m


def _check_columns(src: str, header, rows, required) -> tuple[dict[str, int], np.ndarray]:
    """Check the required columns and the field count of every row; returns column index and line numbers."""
    absent = [c for c in required if c not in header]
    if absent:
        raise DataError(f"{src}: missing required column(s) {', '.join(absent)} (header: {header})")
    index = {name: i for i, name in enumerate(header) if name}
    lines = np.arange(len(rows)) + 2  # the header is line 1
    for r, row in enumerate(rows):
        if len(row) != len(header):
            if len(row) == 0:
                raise DataError(f"{src}: empty line at line {lines[r]}")
            raise DataError(f"{src}: line {lines[r]} has {len(row)} fields, header has {len(header)}")
    return index, lines


def _parse_columns(src: str, rows, index, lines) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Numeric columns (schema columns must parse and pass their limits) and extra text columns."""
    schema = [c for c in (*REQUIRED, *OPTIONAL) if c in index]
    numbers: dict[str, np.ndarray] = {}
    text: dict[str, np.ndarray] = {}
    for c, j in index.items():
        if c == RUN:
            continue
        col = np.empty(len(rows))
        try:
            for r, row in enumerate(rows):
                col[r] = _cell(row[j])
        except ValueError:
            if c in schema:
                raise DataError(f"{src}: column {c}, line {lines[r]}: {row[j]!r} is not a number") from None
            text[c] = np.array([row[j] for row in rows], dtype=str)  # an extra text column
            continue
        numbers[c] = col
    for c in schema:
        check_values(c, numbers[c], src, lines, missing_ok=True)
    return numbers, text


def _missing_rows(src: str, numbers, lines, missing: str) -> tuple[np.ndarray, tuple[int, ...]]:
    """Rows to drop for a missing required value (or raise); returns the mask and their line numbers."""
    bad = np.zeros(lines.size, dtype=bool)
    for c in (c for c in REQUIRED if c in numbers):
        miss = np.isnan(numbers[c])
        if miss.any() and (missing == "error" or c == "time_s"):
            raise DataError(
                f"{src}: column {c}: {int(miss.sum())} missing value(s), first at line "
                f"{int(lines[np.flatnonzero(miss)[0]])}"
            )
        if missing == "drop":
            bad |= miss
    dropped = tuple(int(x) for x in lines[bad])
    if dropped:
        log.warning(
            "%s: dropped %d row(s) with a missing required value (first lines %s)",
            src,
            len(dropped),
            ", ".join(map(str, dropped[:5])),
        )
    return bad, dropped


def read_recording(path: str | Path) -> Measurement:
    """A raw recording or video measurement (recorder, bench, ``softcath measure``).

    The same reader with the rules a raw record needs: only ``time_s`` is
    required (a recorder without camera writes no curvature; a video has no
    pressure), missing cells stay NaN, and a handful of rows is enough.
    """
    return read_measurement_csv(path, missing="keep", required=("time_s",), min_rows=1)
