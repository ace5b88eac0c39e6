"""Measurement CSV access for ``analytic`` users: a re-export of :mod:`softcath.design.measurement`.

The schema, the one reader and the one writer live in ``softcath.design.measurement``
(every layer may import ``design``); this name stays so that
``from softcath.analytic.io import read_measurement_csv`` keeps working.
"""

from __future__ import annotations

from softcath.design.measurement import (
    OPTIONAL,
    REQUIRED,
    Measurement,
    read_measurement_csv,
    write_measurement_csv,
)

__all__ = ["REQUIRED", "OPTIONAL", "Measurement", "read_measurement_csv", "write_measurement_csv"]
