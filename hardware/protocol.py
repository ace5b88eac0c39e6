"""The line protocol spoken by softcath's pressure sensor and encoder.

Framed mode (default), one sample per line::

    $<seq>,<value>*<CS>\\r\\n

``seq`` is a decimal sequence number that wraps at :data:`SEQ_MODULUS`,
``value`` a decimal number in the device's raw unit, and ``CS`` two
upper-case hex digits: the XOR of every byte between ``$`` and ``*``
(NMEA-style). The sequence number lets the reader report gaps; the checksum
lets it drop a line corrupted on the wire instead of recording a wrong value.

Plain mode is for simple sensors that print one number per line
(``<value>\\n``): no gap or corruption detection beyond "is it a number".
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

__all__ = [
    "SEQ_MODULUS",
    "checksum",
    "encode_frame",
    "encode_plain",
    "Sample",
    "LineStats",
    "LineDecoder",
]

SEQ_MODULUS = 65536


def checksum(payload: bytes) -> str:
    """XOR of ``payload`` bytes as two upper-case hex digits."""
    cs = 0
    for b in payload:
        cs ^= b
    return f"{cs:02X}"


def encode_frame(seq: int, value: float) -> bytes:
    """One framed line ``$seq,value*CS\\r\\n`` (``seq`` taken modulo :data:`SEQ_MODULUS`)."""
    payload = f"{seq % SEQ_MODULUS},{value:.9g}".encode("ascii")
    return b"$" + payload + b"*" + checksum(payload).encode("ascii") + b"\r\n"


def encode_plain(value: float) -> bytes:
    """One plain line ``value\\n``."""
    return f"{value:.9g}\n".encode("ascii")


@dataclass(frozen=True)
class Sample:
    """One decoded value: raw device value and its sequence number (None in plain mode)."""

    value: float
    seq: int | None


@dataclass
class LineStats:
    """Counters kept by a :class:`LineDecoder` (mutable: updated as lines arrive)."""

    received: int = 0
    corrupted: int = 0
    partial: int = 0
    gaps: int = 0
    missing: int = 0
    gap_log: list[tuple[int, int]] = field(default_factory=list)

    @property
    def dropped(self) -> int:
        """Lines dropped (corrupted or partial)."""
        return self.corrupted + self.partial


class LineDecoder:
    """Decode complete lines and count what had to be dropped.

    Parameters
    ----------
    framed
        True for the ``$seq,value*CS`` protocol, False for plain numbers.
    max_gap_log
        How many ``(expected_seq, got_seq)`` gap records to keep.
    """

    def __init__(self, *, framed: bool = True, max_gap_log: int = 100) -> None:
        self.framed = framed
        self.stats = LineStats()
        self._expected: int | None = None
        self._max_gap_log = max_gap_log

    def decode(self, line: bytes) -> Sample | None:
        """Decode one line (with or without its terminator); None if it is dropped."""
        text = line.strip(b"\r\n \t\x00")
        if not text:
            return None
        sample = self._parse_framed(text) if self.framed else self._parse_plain(text)
        if sample is None:
            self.stats.corrupted += 1
            return None
        self.stats.received += 1
        if sample.seq is not None:
            self._track_seq(sample.seq)
        return sample

    def count_partial(self, n: int = 1) -> None:
        """Record ``n`` lines that were cut off (no terminator before timeout or disconnect)."""
        self.stats.partial += n

    def _track_seq(self, seq: int) -> None:
        if self._expected is not None and seq != self._expected:
            lost = (seq - self._expected) % SEQ_MODULUS
            self.stats.gaps += 1
            self.stats.missing += lost
            if len(self.stats.gap_log) < self._max_gap_log:
                self.stats.gap_log.append((self._expected, seq))
        self._expected = (seq + 1) % SEQ_MODULUS

    @staticmethod
    def _parse_plain(text: bytes) -> Sample | None:
        try:
            value = float(text.decode("ascii"))
        except (UnicodeDecodeError, ValueError):
            return None
        return Sample(value, None) if math.isfinite(value) else None

    @staticmethod
    def _parse_framed(text: bytes) -> Sample | None:
        # a '$' inside the line means a previous line was cut and this one glued on
        if not text.startswith(b"$") or text.count(b"$") != 1 or text.count(b"*") != 1:
            return None
        payload, _, cs = text[1:].partition(b"*")
        if len(cs) != 2 or checksum(payload).encode("ascii") != cs.upper():
            return None
        parts = payload.split(b",")
        if len(parts) != 2:
            return None
        try:
            seq = int(parts[0])
            value = float(parts[1])
        except ValueError:
            return None
        if not (0 <= seq < SEQ_MODULUS and math.isfinite(value)):
            return None
        return Sample(value, seq)
