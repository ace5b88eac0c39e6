"""A measurement CSV uploaded to the app, read by the command line's reader.

The bytes are size-checked, written to a private temporary folder under the
upload's own base name (so the reader's messages name the file the user
chose), read by :func:`softcath.design.measurement.read_measurement_csv` with its
rules, and the folder is removed again. Rows with a missing required value are
dropped and counted, as ``softcath calibrate`` does.
"""

from __future__ import annotations

import re
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softcath.core.errors import DataError
from softcath.design.measurement import Measurement, read_measurement_csv

__all__ = ["MAX_UPLOAD_BYTES", "MeasuredCurve", "read_upload"]

#: Largest upload accepted [bytes]: a 200 Hz recording of an hour is ~40 MB; the app overlays a
#: curve, for which a few MB are plenty.
MAX_UPLOAD_BYTES = 5_000_000


@dataclass(frozen=True)
class MeasuredCurve:
    """The overlaid measurement: per row p [MPa], κ [1/mm] and θ [rad] (NaN where not measured).

    ``bend_angle_rad`` is the file's column, else κ × ``arc_length_mm`` where that is measured.
    """

    name: str
    pressure_MPa: np.ndarray
    curvature_per_mm: np.ndarray
    bend_angle_rad: np.ndarray
    dropped: int


def _safe_name(filename: str) -> str:
    base = Path(str(filename).replace("\\", "/")).name
    base = re.sub(r"[^A-Za-z0-9._-]+", "_", base).strip("._") or "upload"
    return base[:80] if base.lower().endswith(".csv") else base[:76] + ".csv"


def read_upload(data: bytes, filename: str) -> MeasuredCurve:
    """The curve of an uploaded measurement CSV.

    Raises
    ------
    DataError
        The upload is larger than :data:`MAX_UPLOAD_BYTES`, or the reader refuses it (its
        one-line message, naming the uploaded file, column and line).
    """
    name = _safe_name(filename)
    if len(data) > MAX_UPLOAD_BYTES:
        raise DataError(
            f"{name}: {len(data) / 1e6:.1f} MB is larger than the "
            f"{MAX_UPLOAD_BYTES / 1e6:g} MB the app accepts"
        )
    with tempfile.TemporaryDirectory(prefix="softcath-upload-") as tmp:
        path = Path(tmp) / name
        path.write_bytes(data)
        try:
            m = read_measurement_csv(path, missing="drop")
        except DataError as exc:
            raise DataError(" ".join(str(exc).replace(str(path), name).split())) from None
    return _curve(m, name)


def _curve(m: Measurement, name: str) -> MeasuredCurve:
    kappa = m.curvature_per_mm
    if "bend_angle_rad" in m.columns:
        theta = m["bend_angle_rad"]
    elif "arc_length_mm" in m.columns:
        theta = kappa * m["arc_length_mm"]
    else:
        theta = np.full(kappa.shape, np.nan)
    return MeasuredCurve(name, m.pressure_MPa, kappa, theta, len(m.dropped))
