"""Crash-safe CSV appending and reading of the measurement CSV (numbers as float arrays).

:class:`CsvSink` writes whole lines with one ``os.write`` and ``fsync``-s at
least every ``fsync_interval_s``: a process killed with SIGKILL leaves a file
that ends in a complete line and holds every row written before the kill.
"""

from __future__ import annotations

import csv
import io
import math
import os
import time
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from design.errors import DataError

__all__ = ["CsvSink", "read_measurement_csv"]


class CsvSink:
    """Append-only CSV with explicit durability.

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

    @staticmethod
    def _fmt(v) -> str:
        if v is None:
            return ""
        if isinstance(v, str):
            return v
        v = float(v)
        return "" if not math.isfinite(v) else f"{v:.9g}"

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
        self._pending.append([self._fmt(row.get(c)) for c in self.columns])

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


def read_measurement_csv(path: str | Path) -> dict[str, np.ndarray]:
    """Read a measurement CSV into arrays (numbers as float, NaN if empty; ``run`` as text)."""
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    if not rows:
        raise DataError(f"{path}: empty file (no header)")
    header, body = rows[0], rows[1:]
    out: dict[str, np.ndarray] = {}
    for j, name in enumerate(header):
        col = [r[j] if j < len(r) else "" for r in body]
        if name == "run":
            out[name] = np.array(col, dtype=object)
        else:
            out[name] = np.array([float(x) if x != "" else np.nan for x in col])
    return out
