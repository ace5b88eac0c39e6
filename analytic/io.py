"""Measurement CSV access for ``analytic`` users: a re-export of :mod:`design.measurement`.

The schema, the one reader and the one writer live in ``design.measurement``
(every layer may import ``design``); this name stays so that
``from analytic.io import read_measurement_csv`` keeps working.
"""

from __future__ import annotations

from design.measurement import (
    OPTIONAL,
    REQUIRED,
    Measurement,
    read_measurement_csv,
    write_measurement_csv,
)

__all__ = ["REQUIRED", "OPTIONAL", "Measurement", "read_measurement_csv", "write_measurement_csv"]
