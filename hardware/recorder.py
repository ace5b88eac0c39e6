"""The crash-safe recorder: serial sensors and camera measurements on the paper's 200 Hz base.

Rows of the measurement CSV (shared/ARCHITECTURE.md) are produced on a
uniform time base (``fs_hz``, 200 Hz as in the paper) by linear
interpolation of each source between its samples, so camera data arrive
already resampled. Rows are appended with one ``os.write`` of whole lines
and ``fsync``-ed at least every ``fsync_interval_s`` (1 s): a recorder killed
with SIGKILL leaves a valid CSV holding every row written before the kill.

Clocks: ``"host"`` timestamps lines on arrival (any device); ``"device"``
takes time from the framed protocol's sequence numbers at a known device
rate (no USB jitter, and deterministic: the virtual bench uses it). Camera
frames carry their own times (video: index / fps; live camera: arrival).

A device that vanishes produces a logged message; the recorder retries for
``reconnect_timeout_s`` and otherwise stops cleanly, writing every row it
can still form from what was received.
"""

from __future__ import annotations

import json
import logging
import math
import queue
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from softcath.design.errors import DesignError
from softcath.design.measurement import CsvSink
from softcath.hardware.errors import DeviceError
from softcath.hardware.protocol import SEQ_MODULUS
from softcath.hardware.sensors import SerialSensor

__all__ = [
    "CAMERA_COLUMNS",
    "CsvSink",
    "RecorderConfig",
    "Status",
    "RecordSummary",
    "Recorder",
]

log = logging.getLogger(__name__)

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


class _Series:
    """Timestamped samples of one source, for interpolation at tick times."""

    def __init__(self, name: str, width: int = 1) -> None:
        self.name = name
        self.t: deque[float] = deque()
        self.v: deque[np.ndarray] = deque()
        self.width = width
        self.finished = False
        self.last_arrival = time.monotonic()
        self.first_arrival: float | None = None

    def add(self, t: float, v) -> None:
        if self.t and t <= self.t[-1]:
            return  # out of order or duplicate: keep the series monotonic
        if self.first_arrival is None:
            self.first_arrival = time.monotonic()
        self.t.append(t)
        self.v.append(np.atleast_1d(np.asarray(v, float)))
        self.last_arrival = time.monotonic()

    @property
    def t_last(self) -> float:
        return self.t[-1] if self.t else -math.inf

    def at(self, t: float) -> np.ndarray:
        """Linear interpolation at ``t``; NaN outside the samples."""
        nan = np.full(self.width, np.nan)
        if not self.t or t < self.t[0] or t > self.t[-1]:
            return nan
        # drop samples no longer needed (ticks only move forward)
        while len(self.t) >= 2 and self.t[1] <= t:
            self.t.popleft()
            self.v.popleft()
        if self.t[0] == t or len(self.t) == 1:
            return self.v[0] if self.t[0] == t else nan
        t0, t1 = self.t[0], self.t[1]
        w = (t - t0) / (t1 - t0)
        return self.v[0] * (1 - w) + self.v[1] * w


class _DeviceStream:
    """A serial sensor, its series and its clock handling."""

    def __init__(self, sensor: SerialSensor, column: str, cfg: RecorderConfig, t_start: float):
        self.sensor = sensor
        self.column = column
        self.series = _Series(column)
        self.cfg = cfg
        self.t_start = t_start
        self._seq_last: int | None = None
        self._seq_unwrapped = 0
        self._seq_first: int | None = None
        self.down_since: float | None = None

    def time_of(self, reading) -> float:
        if self.cfg.clock == "host" or reading.seq is None:
            return reading.t_s - self.t_start
        if self._seq_last is None:
            # a device that started with us counts from 0: keep its first samples' times
            self._seq_first = 0 if reading.seq < 16 else reading.seq
            self._seq_unwrapped = reading.seq
        else:
            self._seq_unwrapped += (reading.seq - self._seq_last) % SEQ_MODULUS
        self._seq_last = reading.seq
        rate = self.sensor.rate_hz or self.cfg.device_rate_hz
        return (self._seq_unwrapped - self._seq_first) / rate


class Recorder:
    """Record serial sensors (and optionally camera measurements) into the measurement CSV.

    Parameters
    ----------
    out_csv
        CSV path to write.
    pressure
        Pressure sensor reader (values in MPa); its time base drives the rows.
    encoder
        Encoder reader (values in mm), written as ``encoder_mm``; optional.
    camera
        Iterable of ``(time_s, TipMeasurement)`` (e.g.
        :func:`softcath.hardware.measure_video.measured_frames`), consumed in a background
        thread; ``time_s`` None means a live camera, stamped on arrival. With the
        host clock, a file's frame times count from the first row. Optional.
    stage
        An open :class:`softcath.hardware.stage.ZaberStage` polled for its position
        (``stage_position_mm``, host time) about 10 times a second. Optional.
    config
        :class:`RecorderConfig`.
    segments
        ``[(t_start_s, label), ...]``: the ``run`` column is the label of the
        last segment started (one constant label if a single item).
    on_status
        Called with a :class:`Status` every ``status_interval_s``.
    """

    def __init__(
        self,
        out_csv: str | Path,
        *,
        pressure: SerialSensor,
        encoder: SerialSensor | None = None,
        camera: Iterable | None = None,
        stage=None,
        config: RecorderConfig = RecorderConfig(),
        segments: list[tuple[float, str]] | None = None,
        on_status: Callable[[Status], None] | None = None,
    ) -> None:
        self.out_csv = Path(out_csv)
        self.cfg = config
        self.pressure = pressure
        self.encoder = encoder
        self.camera = camera
        self.stage = stage
        self.segments = sorted(segments or [], key=lambda s: s[0])
        self.on_status = on_status
        self.messages: list[str] = []
        self._stop = threading.Event()

    def stop(self) -> None:
        """Ask a running :meth:`run` to finish (thread-safe)."""
        self._stop.set()

    def _columns(self) -> list[str]:
        cols = ["time_s", "pressure_MPa"]
        if self.encoder is not None:
            cols.append("encoder_mm")
        if self.stage is not None:
            cols.append("stage_position_mm")
        if self.camera is not None:
            cols += list(CAMERA_COLUMNS)
        if self.segments:
            cols.append("run")
        return cols

    def _say(self, msg: str) -> None:
        log.warning(msg)
        self.messages.append(msg)

    def _label(self, t: float) -> str:
        label = self.segments[0][1] if self.segments else ""
        for t0, name in self.segments:
            if t >= t0:
                label = name
        return label

    def run(self, *, duration_s: float | None = None) -> RecordSummary:
        """Record until ``duration_s`` of data (recording time), :meth:`stop`, or a lost device."""
        t_start = time.monotonic()
        devs = [_DeviceStream(self.pressure, "pressure_MPa", self.cfg, t_start)]
        if self.encoder is not None:
            devs.append(_DeviceStream(self.encoder, "encoder_mm", self.cfg, t_start))
        for d in devs:
            if not d.sensor.is_open:
                d.sensor.open()
        cam_series = _Series("camera", len(CAMERA_COLUMNS)) if self.camera is not None else None
        cam_q: queue.Queue = queue.Queue()
        cam_counts = {"frames": 0, "misses": 0}
        if self.camera is not None:
            threading.Thread(target=self._camera_thread, args=(cam_q, cam_counts), daemon=True).start()
        stage_series = _Series("stage_position_mm") if self.stage is not None else None
        sink = CsvSink(self.out_csv, self._columns(), fsync_interval_s=self.cfg.fsync_interval_s)
        dt = 1.0 / self.cfg.fs_hz
        k = k0 = None  # row index (time k * dt); starts at the first pressure sample
        stop_reason = "stopped"
        last_status = time.monotonic()
        last_stage = 0.0
        rows_at_status = 0
        latest: dict[str, float] = {}
        # device-time offset estimate for host-timed extras (stage) in device-clock mode
        host_minus_dev = 0.0
        try:
            while True:
                # 1. serial devices
                for d in devs:
                    if d.series.finished:
                        continue
                    try:
                        for r in d.sensor.poll():
                            t = d.time_of(r)
                            d.series.add(t, r.value)
                            latest[d.column] = r.value
                            if d is devs[0]:
                                host_minus_dev = (r.t_s - t_start) - t
                        d.down_since = None
                    except DeviceError as exc:
                        self._reconnect(d, exc)
                # 2. camera results
                # (host clock: a file's frame times start with the first row, so wait for it)
                while cam_series is not None and (self.cfg.clock == "device" or k0 is not None):
                    try:
                        item = cam_q.get_nowait()
                    except queue.Empty:
                        break
                    if item is None:
                        cam_series.finished = True
                        break
                    t, values, live_t = item
                    if t is None:  # a live camera: its arrival time on the host clock
                        t = live_t - t_start
                    elif self.cfg.clock == "host":
                        t += k0 * dt
                    cam_series.add(t, values)
                    if math.isfinite(values[0]):
                        latest["curvature_per_mm"] = values[0]
                # 3. stage position (host time)
                now = time.monotonic()
                if stage_series is not None and now - last_stage > 0.1:
                    last_stage = now
                    try:
                        pos = self.stage.position_mm()
                        ts = (time.monotonic() - t_start) - (
                            host_minus_dev if self.cfg.clock == "device" else 0.0
                        )
                        stage_series.add(ts, pos)
                    except DeviceError as exc:
                        self._say(f"stage: {exc}; stage position no longer recorded")
                        stage_series.finished = True
                # 4. rows that every live source can now provide
                p = devs[0].series
                done = p.finished or self._stop.is_set()
                if k is None and p.t:
                    # the first row is the first tick at or after the first sample of every serial
                    # source (device clock: each device's first sample is t = 0), so no row starts
                    # with a sensor that has not spoken yet; a source silent for max_wait_s after the
                    # pressure sensor is not waited for (its column stays empty until it speaks)
                    others = [d.series for d in devs[1:] if not d.series.finished]
                    started = [sr.t[0] for sr in others if sr.t]
                    if (
                        len(started) == len(others)
                        or time.monotonic() - p.first_arrival > self.cfg.max_wait_s
                    ):
                        k = k0 = int(math.ceil(max([p.t[0], *started]) / dt - 1e-9))
                end_t = math.inf
                if duration_s is not None and k0 is not None:
                    end_t = k0 * dt + duration_s
                while k is not None:
                    t = k * dt
                    if t > end_t + 1e-9 or t > p.t_last:
                        break
                    waiting = [
                        s
                        for s in [d.series for d in devs[1:]] + [cam_series, stage_series]
                        if s is not None and not s.finished and s.t_last < t
                    ]
                    if waiting and not done:
                        # a silent source is given up after max_wait_s; on the device clock the
                        # camera is never given up while it runs (rows stay deterministic)
                        late = all(
                            time.monotonic() - s.last_arrival > self.cfg.max_wait_s
                            and not (s is cam_series and self.cfg.clock == "device")
                            for s in waiting
                        )
                        if not late:
                            break
                    row = {"time_s": t, "pressure_MPa": float(p.at(t)[0])}
                    for d in devs[1:]:
                        row[d.column] = float(d.series.at(t)[0])
                    if stage_series is not None:
                        row["stage_position_mm"] = float(stage_series.at(t)[0])
                    if cam_series is not None:
                        row.update(zip(CAMERA_COLUMNS, cam_series.at(t), strict=True))
                    if self.segments:
                        row["run"] = self._label(t)
                    sink.append(row)
                    k += 1
                sink.flush()
                if duration_s is not None and k is not None and k * dt > end_t + 1e-9:
                    stop_reason = "duration reached"
                    break
                if (
                    duration_s is not None
                    and k0 is None
                    and time.monotonic() - t_start > duration_s + self.cfg.silent_start_s
                ):
                    # the duration counts from the first sample: without one it would never end
                    stop_reason = "no data"
                    break
                if p.finished:
                    stop_reason = "pressure sensor lost"
                    break
                if self._stop.is_set():
                    stop_reason = "stopped"
                    break
                if any(d.series.finished for d in devs[1:]):
                    stop_reason = "encoder lost"
                    break
                if time.monotonic() - last_status >= self.cfg.status_interval_s:
                    el = time.monotonic() - last_status
                    rate = (sink.rows_written - rows_at_status) / el
                    rows_at_status = sink.rows_written
                    last_status = time.monotonic()
                    if self.on_status is not None:
                        self.on_status(self._status(sink.rows_written, rate, devs, latest))
        except KeyboardInterrupt:
            # Ctrl-C is the normal way to end a live recording: stop cleanly, keep every row
            stop_reason = "interrupted"
            self._stop.set()
        finally:
            sink.close()
            for d in devs:
                d.sensor.close()
        summary = RecordSummary(
            csv_path=str(self.out_csv),
            rows=sink.rows_written,
            duration_s=sink.rows_written * dt,
            stop_reason=stop_reason,
            devices={
                d.sensor.name: {
                    "url": d.sensor.url,
                    "received": d.sensor.stats.received,
                    "corrupted": d.sensor.stats.corrupted,
                    "partial": d.sensor.stats.partial,
                    "gaps": d.sensor.stats.gaps,
                    "missing": d.sensor.stats.missing,
                }
                for d in devs
            },
            camera_frames=cam_counts["frames"],
            camera_misses=cam_counts["misses"],
            messages=tuple(self.messages),
        )
        if self.on_status is not None:
            self.on_status(self._status(sink.rows_written, 0.0, devs, latest, stop_reason))
        return summary

    def _status(self, rows, rate, devs, latest, message="") -> Status:
        return Status(
            rows=rows,
            rows_per_s=rate,
            dropped_lines=sum(d.sensor.stats.dropped for d in devs),
            gaps=sum(d.sensor.stats.gaps for d in devs),
            last=dict(latest),
            message=message,
        )

    def _reconnect(self, d: _DeviceStream, exc: DeviceError) -> None:
        if d.down_since is None:
            d.down_since = time.monotonic()
            self._say(f"{exc}; retrying for {self.cfg.reconnect_timeout_s:g} s")
        while time.monotonic() - d.down_since <= self.cfg.reconnect_timeout_s:
            try:
                d.sensor.open()
                self._say(f"{d.sensor.name} on {d.sensor.url}: reconnected")
                d.down_since = None
                return
            except DeviceError:
                time.sleep(0.1)
        d.series.finished = True
        self._say(
            f"{d.sensor.name} on {d.sensor.url}: gone for {self.cfg.reconnect_timeout_s:g} s; "
            "stopping cleanly with every row received so far"
        )

    def _camera_thread(self, q: queue.Queue, counts: dict) -> None:
        try:
            for t, m in self.camera:
                counts["frames"] += 1
                if not m.ok:
                    counts["misses"] += 1
                # live frames are stamped here, after measurement (a few ms late)
                q.put((t, [m.row()[c] for c in CAMERA_COLUMNS], time.monotonic()))
                if self._stop.is_set():
                    break
        except Exception as exc:  # noqa: BLE001 - reported, and the recording goes on without it
            self._say(f"camera stopped: {exc}")
        finally:
            q.put(None)
