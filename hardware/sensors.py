"""Pressure-sensor and encoder readers over a serial line.

Both speak :mod:`softcath.hardware.protocol` (framed ``$seq,value*CS`` lines or plain
numbers). A reader converts the raw value to physical units with
``value = scale * raw + offset`` (e.g. a sensor reporting kPa read with
``scale=1e-3`` gives MPa; an encoder reporting counts read with
``scale=mm_per_count`` gives mm).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

from softcath.core.errors import DesignError
from softcath.hardware.errors import DeviceError
from softcath.hardware.ports import LineReader, open_port
from softcath.hardware.protocol import LineDecoder, LineStats

__all__ = ["Reading", "SerialSensor"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Reading:
    """One received value in physical units, with its host arrival time (s, monotonic clock)."""

    t_s: float
    value: float
    seq: int | None


class SerialSensor:
    """A line-oriented sensor (pressure sensor, encoder) on a pyserial URL.

    Parameters
    ----------
    url
        pyserial URL or port name.
    name
        Human name used in messages (``"pressure sensor"``).
    framed
        True for ``$seq,value*CS`` lines, False for plain numbers.
    scale, offset
        Conversion ``value = scale * raw + offset`` to physical units.
    baudrate
        Line speed in baud.
    timeout_s
        Longest a :meth:`poll` waits for data, s.
    rate_hz
        The device's sample rate, Hz, for device-clock recording (None: the
        recorder's default).
    """

    def __init__(
        self,
        url: str,
        *,
        name: str = "sensor",
        framed: bool = True,
        scale: float = 1.0,
        offset: float = 0.0,
        baudrate: int = 115200,
        timeout_s: float = 0.02,
        rate_hz: float | None = None,
    ) -> None:
        for param, value in (("scale", scale), ("offset", offset)):
            if not math.isfinite(float(value)):
                raise DesignError(f"{name} {param}", value, "must be a finite number")
        if float(scale) == 0:
            raise DesignError(f"{name} scale", scale, "must be non-zero")
        self.url = url
        self.rate_hz = rate_hz
        self.timeout_s = timeout_s
        self.name = name
        self.scale = float(scale)
        self.offset = float(offset)
        self.baudrate = baudrate
        self.decoder = LineDecoder(framed=framed)
        self._port = None
        self._reader: LineReader | None = None

    @property
    def stats(self) -> LineStats:
        """Received / dropped / gap counters."""
        return self.decoder.stats

    @property
    def is_open(self) -> bool:
        """True while the port is open."""
        return self._port is not None

    def open(self) -> SerialSensor:
        """Open the port (raises :class:`DeviceError` naming the device if it cannot)."""
        self._port = open_port(self.url, baudrate=self.baudrate, timeout_s=self.timeout_s, name=self.name)
        self._reader = LineReader(self._port)
        return self

    def poll(self) -> list[Reading]:
        """Read and decode what has arrived (waits at most the port timeout).

        Raises
        ------
        DeviceError
            If the device vanished; every line completed before that was
            already returned by earlier calls, and a cut-off last line is
            counted as partial.
        """
        import serial

        if self._reader is None:
            raise DeviceError(f"{self.name} on {self.url}: not open")
        try:
            lines = self._reader.read_lines()
        except (serial.SerialException, OSError) as exc:
            self._drop_port()
            raise DeviceError(f"{self.name} on {self.url} disconnected: {exc}") from exc
        out = []
        for t, line in lines:
            s = self.decoder.decode(line)
            if s is not None:
                out.append(Reading(t, self.scale * s.value + self.offset, s.seq))
        return out

    @property
    def pending_bytes(self) -> int:
        """Bytes of an unfinished line received so far (0 when closed): counted partial if the
        device vanishes before its terminator."""
        return 0 if self._reader is None else self._reader.pending_bytes

    def _drop_port(self) -> None:
        if self._reader is not None and self._reader.flush_partial():
            self.decoder.count_partial()
        if self._port is not None:
            try:
                self._port.close()
            except Exception:  # noqa: BLE001 - the port is already broken; closing is best effort
                log.debug("closing %s failed", self.name, exc_info=True)
        self._port = None
        self._reader = None

    def close(self) -> None:
        """Close the port; an incomplete last line is counted as partial."""
        self._drop_port()

    def __enter__(self) -> SerialSensor:
        return self.open()

    def __exit__(self, *exc: object) -> None:
        self.close()
