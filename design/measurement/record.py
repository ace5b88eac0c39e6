"""``Measurement``: the one in-memory type of a measurement (arrays by column, run labels)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from softcath.core.errors import DataError
from softcath.design.measurement.schema import DEFAULT_RUN, LIMITS, MIN_ROWS, OPTIONAL, REQUIRED, RUN

__all__ = ["Measurement", "check_values", "check_time"]


@dataclass(frozen=True)
class Measurement:
    """A validated measurement series.

    Attributes
    ----------
    columns
        Numeric columns by name (float arrays of equal length): the schema's
        columns present in the source plus numeric extra columns. NaN only where
        the reader was told to keep missing cells (raw recordings).
    run
        Run label per row, or None when the source has no ``run`` column (one run).
    text
        Non-numeric extra columns, as text.
    source
        Where it came from (file name), used in every error message.
    dropped
        Line numbers (1-based, header = line 1) of rows dropped for a missing
        required value.

    Examples
    --------
    >>> m = Measurement.from_arrays(time_s=range(10), pressure_MPa=[0.1] * 10,
    ...                             curvature_per_mm=[0.01] * 10)
    >>> len(m), m.runs
    (10, ['run1'])
    """

    columns: Mapping[str, np.ndarray]
    run: np.ndarray | None = None
    text: Mapping[str, np.ndarray] = field(default_factory=dict)
    source: str = "<memory>"
    dropped: tuple[int, ...] = ()

    # --- access ------------------------------------------------------------------
    def __len__(self) -> int:
        return int(next(iter(self.columns.values())).size) if self.columns else 0

    def __contains__(self, name: object) -> bool:
        return name in self.columns or name in self.text or (name == RUN and self.run is not None)

    def __getitem__(self, name: str) -> np.ndarray:
        """A column by name: numbers as floats, ``run`` and text columns as strings."""
        if name in self.columns:
            return self.columns[name]
        if name == RUN and self.run is not None:
            return self.run
        if name in self.text:
            return self.text[name]
        raise DataError(f"{self.source}: no column {name!r} (columns: {', '.join(self.keys())})")

    def keys(self) -> list[str]:
        return [*self.columns, *([RUN] if self.run is not None else []), *self.text]

    @property
    def time_s(self) -> np.ndarray:
        return self["time_s"]

    @property
    def pressure_MPa(self) -> np.ndarray:
        return self["pressure_MPa"]

    @property
    def curvature_per_mm(self) -> np.ndarray:
        return self["curvature_per_mm"]

    @property
    def arc_length_mm(self) -> np.ndarray | None:
        return self.columns.get("arc_length_mm")

    @property
    def optional(self) -> dict[str, np.ndarray]:
        """The optional schema columns present."""
        return {c: self.columns[c] for c in OPTIONAL if c in self.columns}

    @property
    def extra(self) -> dict[str, np.ndarray]:
        """Columns outside the schema (numeric and text)."""
        known = {*REQUIRED, *OPTIONAL}
        return {**{c: v for c, v in self.columns.items() if c not in known}, **self.text}

    def elongation(self, rest_length_mm: float) -> np.ndarray | None:
        """ε = arc_length / L0 − 1, or None when there is no arc length."""
        arc = self.arc_length_mm
        return None if arc is None else arc / rest_length_mm - 1.0

    def run_labels(self) -> np.ndarray:
        """Run label per row (:data:`DEFAULT_RUN` for a file without runs)."""
        if self.run is None:
            return np.full(len(self), DEFAULT_RUN)
        return self.run

    @property
    def runs(self) -> list[str]:
        """Distinct run labels in order of appearance."""
        return list(dict.fromkeys(str(r) for r in self.run_labels()))

    def select(self, mask: np.ndarray) -> Measurement:
        """The rows where ``mask`` is true."""
        return Measurement(
            {k: v[mask] for k, v in self.columns.items()},
            None if self.run is None else self.run[mask],
            {k: v[mask] for k, v in self.text.items()},
            self.source,
        )

    def select_run(self, label: str) -> Measurement:
        return self.select(self.run_labels() == label)

    def is_step_index(self) -> bool:
        """True when ``time_s`` counts steps (0, 1, 2, ... in every run): quasi-static data."""
        t, labels = self.time_s, self.run_labels()
        for r in self.runs:
            tr = t[labels == r]
            if tr.size < 2 or tr[0] not in (0.0, 1.0) or np.any(np.diff(tr) != 1.0):
                return False
        return True

    # --- conversion --------------------------------------------------------------
    @classmethod
    def from_arrays(
        cls, *, time_s, pressure_MPa, curvature_per_mm, run=None, source: str = "<memory>", **optional
    ) -> Measurement:
        """A measurement from arrays, validated like a file (row numbers instead of lines)."""
        unknown = set(optional) - set(OPTIONAL)
        if unknown:
            raise DataError(f"{source}: unknown optional column(s) {sorted(unknown)}; allowed {OPTIONAL}")
        given = {"time_s": time_s, "pressure_MPa": pressure_MPa, "curvature_per_mm": curvature_per_mm}
        given |= {k: v for k, v in optional.items() if v is not None}
        return cls._validated(given, run, source, where="row", min_rows=MIN_ROWS)

    @classmethod
    def from_table(cls, table, *, source: str = "table") -> Measurement:
        """A measurement from a pandas DataFrame with the schema's column names."""
        names = [str(c) for c in table.columns]
        dup = sorted({c for c in names if names.count(c) > 1})
        if dup:
            raise DataError(f"{source}: column {dup[0]} appears {names.count(dup[0])} times")
        absent = [c for c in REQUIRED if c not in names]
        if absent:
            raise DataError(f"{source}: missing required column(s) {', '.join(absent)}")
        given = {}
        for c in (*REQUIRED, *OPTIONAL):
            if c in names:
                try:
                    given[c] = np.asarray(table[c], dtype=float)
                except (TypeError, ValueError):
                    raise DataError(f"{source}: column {c} holds values that are not numbers") from None
        run = None if RUN not in names else np.asarray(table[RUN].fillna("").astype(str), dtype=str)
        m = cls._validated(given, run, source, where="line", min_rows=1)
        numbers, text = dict(m.columns), {}
        for c in names:  # extra columns are kept, numbers as floats, the rest as text
            if c in numbers or c == RUN:
                continue
            try:
                numbers[c] = np.asarray(table[c], dtype=float)
            except (TypeError, ValueError):
                text[c] = np.asarray(table[c].astype(str), dtype=str)
        return cls(numbers, m.run, text, source)

    @classmethod
    def _validated(cls, given: dict, run, source: str, *, where: str, min_rows: int) -> Measurement:
        arrays = {k: np.asarray(v, dtype=float).ravel() for k, v in given.items()}
        n = arrays["time_s"].size
        if n < min_rows:
            raise DataError(f"{source}: {n} usable rows, need at least {min_rows}")
        for k, v in arrays.items():
            if v.size != n:
                raise DataError(f"{source}: column {k} has {v.size} values, time_s has {n}")
        # "line": a table as a file would have it (header = line 1); "row": 0-based index
        lines = np.arange(n) + (2 if where == "line" else 0)
        for k, v in arrays.items():
            check_values(k, v, source, lines, missing_ok=False, where=where)
        run_arr = None if run is None else np.asarray(run, dtype=str).ravel()
        if run_arr is not None and run_arr.size != n:
            raise DataError(f"{source}: column run has {run_arr.size} values, time_s has {n}")
        m = cls(arrays, run_arr, {}, source)
        check_time(m, lines, where=where)
        return m

    def to_table(self):
        """A pandas DataFrame (``run`` filled with :data:`DEFAULT_RUN` when absent)."""
        import pandas as pd

        df = pd.DataFrame({**self.columns, **self.text})
        df[RUN] = self.run_labels()
        return df


def check_values(
    name: str, v: np.ndarray, source: str, lines: np.ndarray, *, missing_ok: bool, where: str = "line"
) -> None:
    """Refuse infinite values, values beyond :data:`LIMITS` and (unless ``missing_ok``) NaN."""
    bad = np.isinf(v) if missing_ok else ~np.isfinite(v)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise DataError(
            f"{source}: column {name}, {where} {int(lines[i])}: {float(v[i])} is not a finite number "
            f"({int(bad.sum())} such value(s))"
        )
    limit = LIMITS.get(name)
    if limit is not None:
        with np.errstate(invalid="ignore"):
            big = np.abs(v) > limit
        if big.any():
            i = int(np.flatnonzero(big)[0])
            raise DataError(
                f"{source}: column {name}, {where} {int(lines[i])}: {v[i]:g} is beyond the "
                f"plausible bound |{name}| <= {limit:g} (a unit or parsing error?)"
            )


def check_time(m: Measurement, lines: np.ndarray, *, where: str = "line") -> None:
    """``time_s`` strictly increasing within each run (it may restart when the run changes)."""
    t, labels = m.time_s, m.run_labels()
    for r in m.runs:
        idx = np.flatnonzero(labels == r)
        bad = np.flatnonzero(np.diff(t[idx]) <= 0)
        if bad.size:
            a, b = idx[bad[0]], idx[bad[0] + 1]
            run = f" in run {r!r}" if m.run is not None else ""
            raise DataError(
                f"{m.source}: column time_s is not strictly increasing{run} at {where} "
                f"{int(lines[b])} ({t[a]:g} then {t[b]:g})"
            )
