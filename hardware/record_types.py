"""The recorder's settings and reports: configuration, live status, and the summary of a recording.

Units: s, Hz; the CSV columns are those of the measurement CSV
(``softcath.design.measurement.schema``).
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field

from softcath.core.errors import DesignError

__all__ = ["PAPER_FS_HZ", "CAMERA_COLUMNS", "RecorderConfig", "Status", "RecordSummary"]

#: The paper's sample rate, Hz (equal to ``softcath.hardware.filtering.PAPER_FS_HZ``, repeated here so
#: that starting a recording does not import scipy.signal, ~2 s).
PAPER_FS_HZ = 200.0

CAMERA_COLUMNS = ("curvature_per_mm", "arc_length_mm", "bend_angle_rad", "tip_x_mm", "tip_y_mm")


@dataclass(frozen=True)
class RecorderConfig:
    """Recorder settings.

    Parameters
    ----------
    fs_hz
        Output time base, Hz (the paper's 200 Hz).
    clock
        ``"host"`` (arrival time) or ``"device"`` (sequence number / ``device_rate_hz``).
    device_rate_hz
        Sample rate of framed devices for the device clock, Hz.
    fsync_interval_s
        Longest time between ``fsync`` calls, s (at most 1).
    reconnect_timeout_s
        How long to retry a vanished device before stopping, s.
    status_interval_s
        How often the status callback runs, s.
    max_wait_s
        How long rows wait for a source that sends nothing before they are
        written with that source's columns empty, s.
    silent_start_s
        With a duration: how long after that duration a recording whose
        pressure sensor has sent nothing gives up (``stop_reason`` "no data"), s.
    """

    fs_hz: float = PAPER_FS_HZ
    clock: str = "host"
    device_rate_hz: float = PAPER_FS_HZ
    fsync_interval_s: float = 1.0
    reconnect_timeout_s: float = 2.0
    status_interval_s: float = 0.5
    max_wait_s: float = 1.0
    silent_start_s: float = 2.0

    def __post_init__(self) -> None:
        if self.clock not in ("host", "device"):
            raise DesignError("clock", self.clock, "must be 'host' or 'device'")
        if not 0 < self.fs_hz <= 10000:
            raise DesignError("fs_hz", self.fs_hz, "must be in (0, 10000] Hz")
        if not 0 < self.device_rate_hz <= 100000:
            raise DesignError("device_rate_hz", self.device_rate_hz, "must be in (0, 1e5] Hz")
        if not 0 < self.fsync_interval_s <= 1.0:
            raise DesignError("fsync_interval_s", self.fsync_interval_s, "must be in (0, 1] s")
        if self.reconnect_timeout_s < 0:
            raise DesignError("reconnect_timeout_s", self.reconnect_timeout_s, "must be >= 0")
        if not self.status_interval_s > 0:
            raise DesignError("status_interval_s", self.status_interval_s, "must be > 0 s")
        if not self.max_wait_s > 0:
            raise DesignError("max_wait_s", self.max_wait_s, "must be > 0 s")
        if not self.silent_start_s > 0:
            raise DesignError("silent_start_s", self.silent_start_s, "must be > 0 s")


@dataclass(frozen=True)
class Status:
    """A live snapshot: rows written, row rate, dropped lines, gaps and the last values."""

    rows: int
    rows_per_s: float
    dropped_lines: int
    gaps: int
    last: dict[str, float]
    message: str = ""

    def line(self) -> str:
        """One human-readable status line."""
        vals = "  ".join(f"{k}={v:.4g}" for k, v in self.last.items() if v is not None and math.isfinite(v))
        return (
            f"rows {self.rows}  {self.rows_per_s:.0f}/s  dropped {self.dropped_lines}  "
            f"gaps {self.gaps}  {vals}"
        )


@dataclass(frozen=True)
class RecordSummary:
    """What a recording produced."""

    csv_path: str
    rows: int
    duration_s: float
    stop_reason: str
    devices: dict[str, dict] = field(default_factory=dict)
    camera_frames: int = 0
    camera_misses: int = 0
    messages: tuple[str, ...] = ()

    def to_json(self) -> str:
        """Summary as JSON text."""
        return json.dumps(asdict(self), indent=2)
