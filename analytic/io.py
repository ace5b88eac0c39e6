"""Reading the measurement CSV (schema in ARCHITECTURE.md), with errors that name file, column and line.

Columns (units in the names): ``time_s``, ``pressure_MPa``, ``curvature_per_mm``
(required); ``arc_length_mm``, ``tip_x_mm``, ``tip_y_mm``, ``bend_angle_rad``,
``run`` (optional). Extra columns are kept as text and otherwise ignored.
Rows with a missing required value are never silently used: by default they
are an error; with ``missing="drop"`` they are dropped and reported (count and
first line numbers) in :attr:`Measurement.dropped`.
"""

from __future__ import annotations

import csv
import logging
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from design.errors import DataError

__all__ = ["REQUIRED", "OPTIONAL", "Measurement", "read_measurement_csv", "write_measurement_csv"]

log = logging.getLogger(__name__)

REQUIRED = ("time_s", "pressure_MPa", "curvature_per_mm")
OPTIONAL = ("arc_length_mm", "tip_x_mm", "tip_y_mm", "bend_angle_rad")
MIN_ROWS = 10


@dataclass(frozen=True)
class Measurement:
    """A validated measurement series (arrays of equal length, time strictly increasing).

    Attributes
    ----------
    time_s, pressure_MPa, curvature_per_mm
        Required series.
    optional
        Optional numeric series present in the file, by column name (NaN where a cell was empty).
    run
        Segment label per row ("" when the file has no ``run`` column).
    extra
        Other columns, as text.
    source
        The file it came from.
    dropped
        Line numbers (1-based, header = line 1) of rows dropped for a missing required value.
    """

    time_s: np.ndarray
    pressure_MPa: np.ndarray
    curvature_per_mm: np.ndarray
    optional: dict[str, np.ndarray] = field(default_factory=dict)
    run: np.ndarray | None = None
    extra: dict[str, np.ndarray] = field(default_factory=dict)
    source: str = "<memory>"
    dropped: tuple[int, ...] = ()

    def __len__(self) -> int:
        return int(self.time_s.size)

    @property
    def arc_length_mm(self) -> np.ndarray | None:
        return self.optional.get("arc_length_mm")

    def elongation(self, rest_length_mm: float) -> np.ndarray | None:
        """ε = arc_length / L0 − 1, or None when the file has no arc length."""
        arc = self.arc_length_mm
        return None if arc is None else arc / rest_length_mm - 1.0

    @property
    def runs(self) -> list[str]:
        """Distinct run labels in order of appearance."""
        if self.run is None:
            return [""]
        seen: dict[str, None] = {}
        for r in self.run:
            seen.setdefault(str(r), None)
        return list(seen)

    def select(self, mask: np.ndarray) -> Measurement:
        """The rows where ``mask`` is true (no re-validation of the minimum length)."""
        return Measurement(
            self.time_s[mask],
            self.pressure_MPa[mask],
            self.curvature_per_mm[mask],
            {k: v[mask] for k, v in self.optional.items()},
            None if self.run is None else self.run[mask],
            {k: v[mask] for k, v in self.extra.items()},
            self.source,
        )

    def select_run(self, label: str) -> Measurement:
        if self.run is None:
            return self
        return self.select(self.run == label)

    @classmethod
    def from_arrays(
        cls,
        *,
        time_s,
        pressure_MPa,
        curvature_per_mm,
        run=None,
        source: str = "<memory>",
        **optional,
    ) -> Measurement:
        """A measurement from arrays, validated like a file."""
        cols = {"time_s": time_s, "pressure_MPa": pressure_MPa, "curvature_per_mm": curvature_per_mm}
        unknown = set(optional) - set(OPTIONAL)
        if unknown:
            raise DataError(f"{source}: unknown optional column(s) {sorted(unknown)}; allowed {OPTIONAL}")
        arrays = {
            k: np.asarray(v, dtype=float).ravel() for k, v in {**cols, **optional}.items() if v is not None
        }
        n = arrays["time_s"].size
        for k, v in arrays.items():
            if v.size != n:
                raise DataError(f"{source}: column {k} has {v.size} values, time_s has {n}")
        for k in REQUIRED:
            bad = np.flatnonzero(~np.isfinite(arrays[k]))
            if bad.size:
                raise DataError(
                    f"{source}: column {k}: {bad.size} non-finite value(s), first at row {bad[0]}"
                )
        _check_length_and_time(arrays["time_s"], source, lines=np.arange(n) + 2)
        run_arr = None if run is None else np.asarray(run, dtype=str)
        return cls(
            arrays["time_s"],
            arrays["pressure_MPa"],
            arrays["curvature_per_mm"],
            {k: arrays[k] for k in OPTIONAL if k in arrays},
            run_arr,
            {},
            source,
        )


def _check_length_and_time(t: np.ndarray, source: str, lines: np.ndarray) -> None:
    if t.size < MIN_ROWS:
        raise DataError(f"{source}: {t.size} usable rows, need at least {MIN_ROWS}")
    bad = np.flatnonzero(np.diff(t) <= 0)
    if bad.size:
        raise DataError(
            f"{source}: column time_s is not strictly increasing at line {int(lines[bad[0] + 1])} "
            f"({t[bad[0]]:g} then {t[bad[0] + 1]:g})"
        )


def _parse_float(text: str) -> float:
    text = text.strip()
    if text == "":
        return math.nan
    return float(text)


def read_measurement_csv(path: str | Path, *, missing: str = "error") -> Measurement:
    """Read and validate a measurement CSV.

    Parameters
    ----------
    path
        The CSV file (header row first).
    missing
        ``"error"`` (default): any empty or NaN required value is an error naming the
        column and first line. ``"drop"``: such rows are dropped, counted and
        logged, and their line numbers kept in :attr:`Measurement.dropped`.

    Raises
    ------
    DataError
        Missing file or columns, non-numeric cells, NaN/empty required values (with
        ``missing="error"``), fewer than 10 rows, or time not strictly increasing.
    """
    if missing not in ("error", "drop"):
        raise DataError(f"missing = {missing!r}: must be 'error' or 'drop'")
    path = Path(path)
    src = str(path)
    try:
        fh = path.open(newline="", encoding="utf-8")
    except FileNotFoundError:
        raise DataError(f"{src}: file not found") from None
    except IsADirectoryError:
        raise DataError(f"{src}: is a directory, not a CSV file") from None
    with fh:
        try:
            reader = csv.reader(fh)
            header = next(reader, None)
            if header is None:
                raise DataError(f"{src}: file is empty (no header row)")
            header = [h.strip() for h in header]
            absent = [c for c in REQUIRED if c not in header]
            if absent:
                raise DataError(f"{src}: missing required column(s) {', '.join(absent)} (header: {header})")
            rows = list(reader)
        except UnicodeDecodeError as exc:
            raise DataError(f"{src}: not a text CSV file ({exc.reason})") from None
        except csv.Error as exc:
            raise DataError(f"{src}: malformed CSV at line {reader.line_num}: {exc}") from None
    index = {name: i for i, name in enumerate(header)}
    numeric = [c for c in (*REQUIRED, *OPTIONAL) if c in index]
    values = {c: np.empty(len(rows)) for c in numeric}
    lines = np.arange(len(rows)) + 2
    for r, row in enumerate(rows):
        if len(row) != len(header):
            if len(row) == 0:
                raise DataError(f"{src}: empty line at line {lines[r]}")
            raise DataError(f"{src}: line {lines[r]} has {len(row)} fields, header has {len(header)}")
        for c in numeric:
            cell = row[index[c]]
            try:
                values[c][r] = _parse_float(cell)
            except ValueError:
                raise DataError(f"{src}: column {c}, line {lines[r]}: {cell!r} is not a number") from None
    bad_rows = np.zeros(len(rows), dtype=bool)
    for c in REQUIRED:
        bad = ~np.isfinite(values[c])
        if bad.any() and missing == "error":
            first = int(lines[np.flatnonzero(bad)[0]])
            raise DataError(
                f"{src}: column {c}: {int(bad.sum())} missing/NaN value(s), first at line {first}"
            )
        bad_rows |= bad
    dropped = tuple(int(x) for x in lines[bad_rows])
    if dropped:
        log.warning(
            "%s: dropped %d row(s) with a missing required value (first lines %s)",
            src,
            len(dropped),
            ", ".join(map(str, dropped[:5])),
        )
    keep = ~bad_rows
    t = values["time_s"][keep]
    _check_length_and_time(t, src, lines[keep])
    text_cols = [c for c in header if c not in numeric]
    text = {c: np.array([row[index[c]] for row in rows], dtype=str)[keep] for c in text_cols}
    run = text.pop("run", None)
    return Measurement(
        t,
        values["pressure_MPa"][keep],
        values["curvature_per_mm"][keep],
        {c: values[c][keep] for c in OPTIONAL if c in values},
        run,
        text,
        src,
        dropped,
    )


def write_measurement_csv(path: str | Path, m: Measurement) -> Path:
    """Write ``m`` in the ARCHITECTURE.md schema (atomically)."""
    path = Path(path)
    cols = list(REQUIRED) + [c for c in OPTIONAL if c in m.optional]
    data = [m.time_s, m.pressure_MPa, m.curvature_per_mm] + [m.optional[c] for c in cols[3:]]
    tmp = path.with_suffix(path.suffix + ".tmp")
    with tmp.open("w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(cols + (["run"] if m.run is not None else []))
        for i in range(len(m)):
            row = ["" if not np.isfinite(col[i]) else f"{col[i]:.10g}" for col in data]
            if m.run is not None:
                row.append(str(m.run[i]))
            w.writerow(row)
    tmp.replace(path)
    return path
