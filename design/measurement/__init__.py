"""The measurement CSV: schema, the one in-memory type, the one reader and the one writer.

Every layer reads and writes measurements through this package: the recorder
and the virtual bench (``hardware``), calibration (``analytic``), the
missing-effect workflow and the command line (``studies``). It lives in
``design`` because every layer may import ``design``. The schema is
documented in ``docs/measurement-csv.md``.

>>> from softcath.design.measurement import Measurement, REQUIRED
>>> REQUIRED
('time_s', 'pressure_MPa', 'curvature_per_mm')
"""

from __future__ import annotations

from softcath.design.measurement.read import read_measurement_csv, read_recording
from softcath.design.measurement.record import Measurement
from softcath.design.measurement.schema import COLUMNS, DEFAULT_RUN, LIMITS, MIN_ROWS, OPTIONAL, REQUIRED, RUN
from softcath.design.measurement.write import CsvSink, format_cell, write_measurement_csv

__all__ = [
    "COLUMNS",
    "CsvSink",
    "DEFAULT_RUN",
    "LIMITS",
    "MIN_ROWS",
    "Measurement",
    "OPTIONAL",
    "REQUIRED",
    "RUN",
    "format_cell",
    "read_measurement_csv",
    "read_recording",
    "write_measurement_csv",
]
