"""The one writer of measurement CSV files: whole files atomically, or rows crash-safely.

:func:`write_measurement_csv` writes a :class:`Measurement` through a
temporary name and renames it on success. :class:`CsvSink` is the recorder's
append-only form of the same format: whole lines with one ``os.write`` and an
``fsync`` at least every ``fsync_interval_s``, so a process killed with
SIGKILL leaves a file that ends in a complete line and holds every row
written before the kill. Both format numbers the same way (:func:`format_cell`).
"""

from __future__ import annotations

import csv
import io
import math
import os
import time
from collections.abc import Iterable
from pathlib import Path

from softcath.design.measurement.record import Measurement
from softcath.design.measurement.schema import OPTIONAL, REQUIRED, RUN

__all__ = ["CsvSink", "format_cell", "write_measurement_csv"]


def format_cell(v) -> str:
    """A value as a CSV cell: text as is, numbers with 9 significant digits, NaN/None empty."""
    if v is None:
        return ""
    if isinstance(v, str):
        return v
    v = float(v)
    return "" if not math.isfinite(v) else f"{v:.9g}"


def write_measurement_csv(path: str | Path, m: Measurement) -> Path:
    """Write ``m`` (schema columns first, then its extra columns) atomically; returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    names = [c for c in (*REQUIRED, *OPTIONAL) if c in m.columns]
    names += [c for c in m.columns if c not in names]
    text = list(m.text)
    cols = [m.columns[c] for c in names] + [m.text[c] for c in text]
    header = names + text + ([RUN] if m.run is not None else [])
    if m.run is not None:
        cols.append(m.run)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with tmp.open("w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(header)
            w.writerows([format_cell(c[i].item()) for c in cols] for i in range(len(m)))
        tmp.replace(path)
    finally:
        tmp.unlink(missing_ok=True)
    return path


class CsvSink:
    """Append-only measurement CSV with explicit durability (the recorder's writer).

    Parameters
    ----------
    path
        File to create (an existing file is replaced).
    columns
        Header.
    fsync_interval_s
        Longest time a written row may stay without ``fsync``, s.
    """

    def __init__(self, path: str | Path, columns: Iterable[str], *, fsync_interval_s: float = 1.0):
        self.path = Path(path)
        self.columns = tuple(columns)
        self.fsync_interval_s = fsync_interval_s
        self.rows_written = 0
        self.rows_synced = 0
        self._pending: list[list[str]] = []
        self._fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        self._write_lines([list(self.columns)])
        os.fsync(self._fd)
        self._last_sync = time.monotonic()

    _fmt = staticmethod(format_cell)

    def _write_lines(self, rows: list[list[str]]) -> None:
        buf = io.StringIO()
        csv.writer(buf, lineterminator="\n").writerows(rows)
        data = buf.getvalue().encode("utf-8")
        view = memoryview(data)
        while view:  # whole lines in as few write calls as the kernel allows
            n = os.write(self._fd, view)
            view = view[n:]

    def append(self, row: dict) -> None:
        """Queue one row (a dict by column name; missing or NaN values are left empty)."""
        self._pending.append([format_cell(row.get(c)) for c in self.columns])

    def flush(self, *, sync: bool | None = None) -> None:
        """Write queued rows; ``fsync`` if asked or if the interval has passed."""
        if self._pending:
            self._write_lines(self._pending)
            self.rows_written += len(self._pending)
            self._pending.clear()
        now = time.monotonic()
        if sync or (sync is None and now - self._last_sync >= self.fsync_interval_s):
            os.fsync(self._fd)
            self.rows_synced = self.rows_written
            self._last_sync = now

    def close(self) -> None:
        """Write, sync and close."""
        if self._fd >= 0:
            self.flush(sync=True)
            os.close(self._fd)
            self._fd = -1
