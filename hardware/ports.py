"""Opening serial devices from pyserial URLs, and pseudo-terminal pairs for virtual devices.

Every device in softcath opens from a URL that :func:`serial.serial_for_url`
understands: a real port (``/dev/ttyUSB0``, ``COM3``), ``loop://``,
``socket://host:port`` or the slave side of a pseudo-terminal (``/dev/pts/N``).
"""

from __future__ import annotations

import logging
import os
import time

from softcath.hardware.errors import DeviceError

__all__ = ["open_port", "PtyPair", "LineReader"]

log = logging.getLogger(__name__)


def open_port(url: str, *, baudrate: int = 115200, timeout_s: float = 0.05, name: str = "device"):
    """Open a serial port from a pyserial URL.

    Parameters
    ----------
    url
        Port name or pyserial URL.
    baudrate
        Line speed in baud (ignored by ``loop://`` and sockets).
    timeout_s
        Read timeout in s.
    name
        What the device is, used in error messages (``"pressure sensor"``).

    Raises
    ------
    DeviceError
        If the port cannot be opened; the message names the device and the URL.
    """
    import serial

    if not isinstance(url, str) or not url:
        raise DeviceError(f"{name} port = {url!r}: must be a port name or pyserial URL")
    try:
        return serial.serial_for_url(url, baudrate=baudrate, timeout=timeout_s, write_timeout=1.0)
    except (serial.SerialException, ValueError, OSError) as exc:
        raise DeviceError(f"{name} port = {url!r}: cannot open ({exc})") from exc


class PtyPair:
    """A raw pseudo-terminal pair: a virtual device writes ``master_fd``, clients open ``path``.

    Closing the master (``close_master``) is what unplugging a USB-serial
    adapter looks like to the client: reads fail with an I/O error.
    """

    def __init__(self) -> None:
        import tty

        self.master_fd, self._slave_fd = os.openpty()
        tty.setraw(self._slave_fd)  # no echo, no CR/LF translation
        tty.setraw(self.master_fd)
        self.path = os.ttyname(self._slave_fd)
        os.set_blocking(self.master_fd, True)

    def write(self, data: bytes, *, timeout_s: float = 10.0) -> None:
        """Write all of ``data`` to the master side.

        Raises ``TimeoutError`` (an ``OSError``) if the pty stays full for
        ``timeout_s``: nobody is reading the other side.
        """
        import select

        view = memoryview(data)
        while view:
            _, ready, _ = select.select([], [self.master_fd], [], timeout_s)
            if not ready:
                raise TimeoutError(f"pty {self.path}: full for {timeout_s} s (no reader)")
            n = os.write(self.master_fd, view)
            view = view[n:]

    def close_master(self) -> None:
        """Close the device side (simulated unplug)."""
        if self.master_fd >= 0:
            os.close(self.master_fd)
            self.master_fd = -1

    def close(self) -> None:
        """Close both sides."""
        self.close_master()
        if self._slave_fd >= 0:
            os.close(self._slave_fd)
            self._slave_fd = -1

    def __enter__(self) -> PtyPair:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class LineReader:
    """Split a serial byte stream into complete lines, keeping partial lines for later.

    ``readline`` in pyserial returns a partial line without its ``\\n`` on
    timeout; this reader instead buffers bytes until the terminator arrives,
    so a slow line is never cut. A line still incomplete when the device
    vanishes is reported by :meth:`flush_partial`.
    """

    def __init__(self, port, *, max_line: int = 256) -> None:
        self.port = port
        self._buf = bytearray()
        self._max_line = max_line
        self.overlong = 0

    def read_lines(self) -> list[tuple[float, bytes]]:
        """Read what is available (waiting up to the port timeout); return ``(t_s, line)`` pairs.

        ``t_s`` is :func:`time.monotonic` when the chunk holding the line arrived.
        Raises :class:`serial.SerialException` if the device vanished.
        """
        chunk = self.port.read(max(1, self.port.in_waiting))
        now = time.monotonic()
        if not chunk:
            return []
        self._buf.extend(chunk)
        out: list[tuple[float, bytes]] = []
        while True:
            i = self._buf.find(b"\n")
            if i < 0:
                break
            out.append((now, bytes(self._buf[: i + 1])))
            del self._buf[: i + 1]
        if len(self._buf) > self._max_line:  # garbage without terminators: drop it
            self.overlong += 1
            self._buf.clear()
        return out

    @property
    def pending_bytes(self) -> int:
        """Bytes of a line received so far whose terminator has not arrived yet."""
        return len(self._buf)

    def flush_partial(self) -> bytes:
        """Return and forget the incomplete line in the buffer (empty if none)."""
        rest = bytes(self._buf)
        self._buf.clear()
        return rest
