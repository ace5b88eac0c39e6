"""The measurement CSV schema: columns, units, bounds and run semantics (one place).

``docs/measurement-csv.md`` is the human version of this table; a test checks
that the two list the same columns and units.

Rules
-----
* Header row first; an Excel UTF-8 byte-order mark is accepted. Every column
  name appears at most once (a second ``curvature_per_mm`` would be ambiguous,
  so it is refused, naming the column).
* ``time_s``, ``pressure_MPa``, ``curvature_per_mm`` are required.
* ``run`` labels one experiment segment (one file, one excitation). Absent: the
  whole file is one run. ``time_s`` increases strictly within a run and may
  restart when ``run`` changes (runs concatenated from several files).
* A ``time_s`` that is a step index (0, 1, 2, ... in every run; quasi-static
  data with no clock) is allowed; the missing-effect workflow recognises it
  and refuses time-dependent candidates.
* Numbers are finite and within :data:`LIMITS` (a pressure of 1e300 MPa is a
  unit or parsing error, not a measurement). An empty cell or ``nan`` in a
  required column is a *missing* value: an error by default, or dropped and
  reported (count, first line numbers). ``inf`` is always an error.
* Other columns are kept (numbers as floats where every cell is a number,
  otherwise as text) and ignored by the schema.
"""

from __future__ import annotations

__all__ = ["COLUMNS", "REQUIRED", "OPTIONAL", "RUN", "LIMITS", "MIN_ROWS", "DEFAULT_RUN"]

#: (name, unit, required, meaning) of every schema column, in file order
COLUMNS: tuple[tuple[str, str, bool, str], ...] = (
    ("time_s", "s", True, "time since the start of the run (strictly increasing within a run)"),
    ("pressure_MPa", "MPa", True, "gauge pressure driving the actuator"),
    ("curvature_per_mm", "1/mm", True, "tip curvature (constant-curvature fit)"),
    ("arc_length_mm", "mm", False, "arc length of the bending segment (elongation = arc / L0 - 1)"),
    ("tip_x_mm", "mm", False, "lateral tip position"),
    ("tip_y_mm", "mm", False, "tip position along the unbent axis"),
    ("bend_angle_rad", "rad", False, "bend angle of the tip"),
    ("run", "-", False, "text label of one experiment segment (one run if absent)"),
)

REQUIRED: tuple[str, ...] = tuple(c for c, _, req, _ in COLUMNS if req)
#: optional numeric columns (``run`` is text and handled apart)
OPTIONAL: tuple[str, ...] = tuple(c for c, _, req, _ in COLUMNS if not req and c != "run")
RUN = "run"
#: label of the one run of a file without a ``run`` column
DEFAULT_RUN = "run1"

#: largest accepted magnitude per numeric schema column, in its unit. Far above any
#: bench (1e6 MPa is 10^4 times the strength of steel; 1e9 s is 30 years): a value
#: beyond is a unit or parsing error, and would overflow squares downstream
LIMITS: dict[str, float] = {
    "time_s": 1e9,
    "pressure_MPa": 1e6,
    "curvature_per_mm": 1e6,
    "arc_length_mm": 1e6,
    "tip_x_mm": 1e6,
    "tip_y_mm": 1e6,
    "bend_angle_rad": 1e6,
}

#: fewest usable rows a measurement file must have
MIN_ROWS = 10
