"""The recorder's time base: timestamped series interpolated at the row ticks, and device clocks.

A :class:`Series` holds one source's samples and answers linear interpolation at
forward-moving tick times; a :class:`DeviceStream` gives a serial sensor's readings
their time (host arrival, or the framed protocol's sequence number at the device rate).
"""

from __future__ import annotations

import math
import time
from collections import deque

import numpy as np

from softcath.hardware.protocol import SEQ_MODULUS
from softcath.hardware.record_types import RecorderConfig
from softcath.hardware.sensors import SerialSensor

__all__ = ["Series", "DeviceStream"]


class Series:
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


class DeviceStream:
    """A serial sensor, its series and its clock handling."""

    def __init__(self, sensor: SerialSensor, column: str, cfg: RecorderConfig, t_start: float):
        self.sensor = sensor
        self.column = column
        self.series = Series(column)
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
