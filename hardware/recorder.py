"""The crash-safe recorder: serial sensors and camera measurements on the paper's 200 Hz base.

Rows of the measurement CSV (``softcath.design.measurement.schema``) are produced on a
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

The settings and reports are in :mod:`softcath.hardware.record_types`, the time base
(interpolation, device clocks) in :mod:`softcath.hardware.timebase`, the CSV sink in
:class:`softcath.design.measurement.CsvSink`; this module is the recording loop.
"""

from __future__ import annotations

import logging
import math
import queue
import threading
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path

from softcath.design.measurement import CsvSink
from softcath.hardware.errors import DeviceError
from softcath.hardware.record_types import (
    CAMERA_COLUMNS,
    PAPER_FS_HZ,
    RecorderConfig,
    RecordSummary,
    Status,
)
from softcath.hardware.sensors import SerialSensor
from softcath.hardware.timebase import DeviceStream, Series

__all__ = [
    "CAMERA_COLUMNS",
    "PAPER_FS_HZ",
    "RecorderConfig",
    "Status",
    "RecordSummary",
    "Recorder",
]

log = logging.getLogger(__name__)


@dataclass
class _Run:
    """The mutable state of one recording, threaded through the steps of :meth:`Recorder.run`."""

    t_start: float
    dt: float
    devs: list[DeviceStream]
    sink: CsvSink
    cam_series: Series | None
    cam_q: queue.Queue
    cam_counts: dict[str, int]
    stage_series: Series | None
    last_status: float
    k: int | None = None  # row index (time k * dt); starts at the first pressure sample
    k0: int | None = None
    last_stage: float = 0.0
    rows_at_status: int = 0
    latest: dict[str, float] = field(default_factory=dict)
    # device-time offset estimate for host-timed extras (stage) in device-clock mode
    host_minus_dev: float = 0.0


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
        config: RecorderConfig = RecorderConfig(),  # noqa: B008 - frozen, so one shared default is safe
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
        st = self._start()
        stop_reason = "stopped"
        try:
            while True:
                self._poll_devices(st)
                self._drain_camera(st)
                self._poll_stage(st)
                # rows that every live source can now provide
                p = st.devs[0].series
                done = p.finished or self._stop.is_set()
                if st.k is None and p.t:
                    self._first_row(st)
                end_t = math.inf
                if duration_s is not None and st.k0 is not None:
                    end_t = st.k0 * st.dt + duration_s
                self._write_rows(st, end_t, done)
                st.sink.flush()
                reason = self._stop_reason(st, duration_s, end_t)
                if reason is not None:
                    stop_reason = reason
                    break
                self._report(st)
        except KeyboardInterrupt:
            # Ctrl-C is the normal way to end a live recording: stop cleanly, keep every row
            stop_reason = "interrupted"
            self._stop.set()
        finally:
            st.sink.close()
            for d in st.devs:
                d.sensor.close()
        summary = self._summary(st, stop_reason)
        if self.on_status is not None:
            self.on_status(self._status(st.sink.rows_written, 0.0, st.devs, st.latest, stop_reason))
        return summary

    def _start(self) -> _Run:
        """Open the devices, start the camera thread, open the CSV: the state of a new recording."""
        t_start = time.monotonic()
        devs = [DeviceStream(self.pressure, "pressure_MPa", self.cfg, t_start)]
        if self.encoder is not None:
            devs.append(DeviceStream(self.encoder, "encoder_mm", self.cfg, t_start))
        for d in devs:
            if not d.sensor.is_open:
                d.sensor.open()
        cam_series = Series("camera", len(CAMERA_COLUMNS)) if self.camera is not None else None
        cam_q: queue.Queue = queue.Queue()
        cam_counts = {"frames": 0, "misses": 0}
        if self.camera is not None:
            threading.Thread(target=self._camera_thread, args=(cam_q, cam_counts), daemon=True).start()
        stage_series = Series("stage_position_mm") if self.stage is not None else None
        sink = CsvSink(self.out_csv, self._columns(), fsync_interval_s=self.cfg.fsync_interval_s)
        return _Run(
            t_start=t_start,
            dt=1.0 / self.cfg.fs_hz,
            devs=devs,
            sink=sink,
            cam_series=cam_series,
            cam_q=cam_q,
            cam_counts=cam_counts,
            stage_series=stage_series,
            last_status=time.monotonic(),
        )

    def _poll_devices(self, st: _Run) -> None:
        """Read what the serial devices sent; reconnect a device that vanished."""
        for d in st.devs:
            if d.series.finished:
                continue
            try:
                for r in d.sensor.poll():
                    t = d.time_of(r)
                    d.series.add(t, r.value)
                    st.latest[d.column] = r.value
                    if d is st.devs[0]:
                        st.host_minus_dev = (r.t_s - st.t_start) - t
                d.down_since = None
            except DeviceError as exc:
                self._reconnect(d, exc)

    def _drain_camera(self, st: _Run) -> None:
        """Take the camera results queued by the camera thread into the camera series."""
        # (host clock: a file's frame times start with the first row, so wait for it)
        while st.cam_series is not None and (self.cfg.clock == "device" or st.k0 is not None):
            try:
                item = st.cam_q.get_nowait()
            except queue.Empty:
                break
            if item is None:
                st.cam_series.finished = True
                break
            t, values, live_t = item
            if t is None:  # a live camera: its arrival time on the host clock
                t = live_t - st.t_start
            elif self.cfg.clock == "host":
                t += st.k0 * st.dt
            st.cam_series.add(t, values)
            if math.isfinite(values[0]):
                st.latest["curvature_per_mm"] = values[0]

    def _poll_stage(self, st: _Run) -> None:
        """Read the stage position (host time) about 10 times a second."""
        now = time.monotonic()
        if st.stage_series is None or now - st.last_stage <= 0.1:
            return
        st.last_stage = now
        try:
            pos = self.stage.position_mm()
            ts = (time.monotonic() - st.t_start) - (st.host_minus_dev if self.cfg.clock == "device" else 0.0)
            st.stage_series.add(ts, pos)
        except DeviceError as exc:
            self._say(f"stage: {exc}; stage position no longer recorded")
            st.stage_series.finished = True

    def _first_row(self, st: _Run) -> None:
        """Fix the first row's index once the serial sources have spoken (or been waited for)."""
        # the first row is the first tick at or after the first sample of every serial
        # source (device clock: each device's first sample is t = 0), so no row starts
        # with a sensor that has not spoken yet; a source silent for max_wait_s after the
        # pressure sensor is not waited for (its column stays empty until it speaks)
        p = st.devs[0].series
        others = [d.series for d in st.devs[1:] if not d.series.finished]
        started = [sr.t[0] for sr in others if sr.t]
        if len(started) == len(others) or time.monotonic() - p.first_arrival > self.cfg.max_wait_s:
            st.k = st.k0 = int(math.ceil(max([p.t[0], *started]) / st.dt - 1e-9))

    def _write_rows(self, st: _Run, end_t: float, done: bool) -> None:
        """Append every row up to ``end_t`` that the live sources can provide."""
        p = st.devs[0].series
        while st.k is not None:
            t = st.k * st.dt
            if t > end_t + 1e-9 or t > p.t_last:
                break
            waiting = [
                s
                for s in [d.series for d in st.devs[1:]] + [st.cam_series, st.stage_series]
                if s is not None and not s.finished and s.t_last < t
            ]
            if waiting and not done:
                # a silent source is given up after max_wait_s; on the device clock the
                # camera is never given up while it runs (rows stay deterministic)
                late = all(
                    time.monotonic() - s.last_arrival > self.cfg.max_wait_s
                    and not (s is st.cam_series and self.cfg.clock == "device")
                    for s in waiting
                )
                if not late:
                    break
            st.sink.append(self._row(st, t))
            st.k += 1

    def _row(self, st: _Run, t: float) -> dict:
        """The CSV row at tick time ``t``: every source interpolated."""
        row = {"time_s": t, "pressure_MPa": float(st.devs[0].series.at(t)[0])}
        for d in st.devs[1:]:
            row[d.column] = float(d.series.at(t)[0])
        if st.stage_series is not None:
            row["stage_position_mm"] = float(st.stage_series.at(t)[0])
        if st.cam_series is not None:
            row.update(zip(CAMERA_COLUMNS, st.cam_series.at(t), strict=True))
        if self.segments:
            row["run"] = self._label(t)
        return row

    def _stop_reason(self, st: _Run, duration_s: float | None, end_t: float) -> str | None:
        """Why the recording ends now, or None to go on."""
        if duration_s is not None and st.k is not None and st.k * st.dt > end_t + 1e-9:
            return "duration reached"
        if (
            duration_s is not None
            and st.k0 is None
            and time.monotonic() - st.t_start > duration_s + self.cfg.silent_start_s
        ):
            # the duration counts from the first sample: without one it would never end
            return "no data"
        if st.devs[0].series.finished:
            return "pressure sensor lost"
        if self._stop.is_set():
            return "stopped"
        if any(d.series.finished for d in st.devs[1:]):
            return "encoder lost"
        return None

    def _report(self, st: _Run) -> None:
        """Call the status callback every ``status_interval_s``."""
        if time.monotonic() - st.last_status < self.cfg.status_interval_s:
            return
        el = time.monotonic() - st.last_status
        rate = (st.sink.rows_written - st.rows_at_status) / el
        st.rows_at_status = st.sink.rows_written
        st.last_status = time.monotonic()
        if self.on_status is not None:
            self.on_status(self._status(st.sink.rows_written, rate, st.devs, st.latest))

    def _summary(self, st: _Run, stop_reason: str) -> RecordSummary:
        return RecordSummary(
            csv_path=str(self.out_csv),
            rows=st.sink.rows_written,
            duration_s=st.sink.rows_written * st.dt,
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
                for d in st.devs
            },
            camera_frames=st.cam_counts["frames"],
            camera_misses=st.cam_counts["misses"],
            messages=tuple(self.messages),
        )

    def _status(self, rows, rate, devs, latest, message="") -> Status:
        return Status(
            rows=rows,
            rows_per_s=rate,
            dropped_lines=sum(d.sensor.stats.dropped for d in devs),
            gaps=sum(d.sensor.stats.gaps for d in devs),
            last=dict(latest),
            message=message,
        )

    def _reconnect(self, d: DeviceStream, exc: DeviceError) -> None:
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
