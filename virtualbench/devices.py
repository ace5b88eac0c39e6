"""Virtual serial devices on pseudo-terminals: a line sensor and a Zaber-style stage.

They speak exactly what the real readers and driver expect, so tests and the
virtual bench exercise the real code paths (pyserial, framing, checksums,
partial lines, disconnects) with no hardware.
"""

from __future__ import annotations

import logging
import os
import select
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from softcath.hardware.ports import PtyPair
from softcath.hardware.protocol import encode_frame, encode_plain
from softcath.hardware.stage import ZABER_VELOCITY_UNIT, lrc

__all__ = ["VirtualClock", "VirtualLineDevice", "VirtualStage", "ZABER_VELOCITY_UNIT"]

log = logging.getLogger(__name__)


class VirtualClock:
    """A clock that virtual devices share: host time scaled by ``speed``, or set by hand.

    With ``manual=True`` the owner advances it with :meth:`set` (lock-step
    simulation, fully deterministic); otherwise it follows the host clock.
    """

    def __init__(self, *, speed: float = 1.0, manual: bool = False) -> None:
        self.speed = speed
        self.manual = manual
        self._t0 = time.monotonic()
        self._t = 0.0

    def now(self) -> float:
        """Current virtual time, s."""
        if self.manual:
            return self._t
        return (time.monotonic() - self._t0) * self.speed

    def set(self, t_s: float) -> None:
        """Set the virtual time (manual clocks only)."""
        self._t = float(t_s)


class VirtualLineDevice:
    """A sensor or encoder writing :mod:`softcath.hardware.protocol` lines into a pty.

    Parameters
    ----------
    framed
        Framed ``$seq,value*CS`` lines (True) or plain numbers.
    """

    def __init__(self, *, framed: bool = True) -> None:
        self.pty = PtyPair()
        self.framed = framed
        self.seq = 0
        self._thread: threading.Thread | None = None
        self._stop = threading.Event()

    @property
    def url(self) -> str:
        """The port a reader opens."""
        return self.pty.path

    def line(self, value: float) -> bytes:
        """The bytes of the next line (advances the sequence number)."""
        data = encode_frame(self.seq, value) if self.framed else encode_plain(value)
        self.seq += 1
        return data

    def emit(self, value: float) -> None:
        """Send one sample."""
        self.pty.write(self.line(value))

    def emit_corrupted(self, value: float) -> None:
        """Send one sample with a flipped character (its checksum no longer matches)."""
        data = bytearray(self.line(value))
        i = data.index(b",") + 1  # first digit of the value
        data[i] = ord("7") if data[i] != ord("7") else ord("3")
        if not self.framed:
            data[i:i] = b"x"  # plain mode has no checksum: make it unparseable instead
        self.pty.write(bytes(data))

    def emit_partial(self, value: float) -> None:
        """Send the first half of a line and no terminator (a cut-off transmission)."""
        data = self.line(value)
        self.pty.write(data[: len(data) // 2])

    def skip(self, n: int = 1) -> None:
        """Lose ``n`` samples (advance the sequence number without sending)."""
        self.seq += n

    def start_paced(
        self, value_at: Callable[[float], float], *, rate_hz: float, duration_s: float | None = None
    ) -> None:
        """Emit ``value_at(t)`` at ``rate_hz`` in real time from a background thread."""

        def loop() -> None:
            t0 = time.monotonic()
            k = 0
            while not self._stop.is_set():
                t = k / rate_hz
                if duration_s is not None and t > duration_s:
                    break
                delay = t0 + t - time.monotonic()
                if delay > 0:
                    time.sleep(delay)
                try:
                    self.emit(value_at(t))
                except OSError:
                    break
                k += 1

        self._thread = threading.Thread(target=loop, daemon=True, name="virtual-line-device")
        self._thread.start()

    def unplug(self) -> None:
        """Stop sending and close the device side (the reader sees an I/O error)."""
        self.stop()
        self.pty.close_master()

    def stop(self) -> None:
        """Stop the paced thread."""
        self._stop.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=2)

    def close(self) -> None:
        """Stop and close both pty sides."""
        self.stop()
        self.pty.close()


@dataclass(frozen=True)
class _Motion:
    t0: float
    x0: float  # microsteps
    kind: str  # hold, line, vel, sin
    a: float = 0.0  # target (line) | velocity (vel) | amplitude (sin)
    b: float = 0.0  # speed (line) | period s (sin)
    cycles: float = float("inf")

    def position(self, t: float) -> float:
        dt = max(0.0, t - self.t0)
        if self.kind == "hold":
            return self.x0
        if self.kind == "vel":
            return self.x0 + self.a * dt
        if self.kind == "line":
            dist = self.a - self.x0
            if self.b <= 0 or abs(dist) <= self.b * dt:
                return self.a
            return self.x0 + np.sign(dist) * self.b * dt
        dt = min(dt, self.cycles * self.b)  # sin
        return self.x0 + self.a * (1.0 - np.cos(2 * np.pi * dt / self.b))

    def busy(self, t: float) -> bool:
        dt = t - self.t0
        if self.kind == "hold":
            return False
        if self.kind == "vel":
            return self.a != 0
        if self.kind == "line":
            return self.b > 0 and abs(self.a - self.x0) > self.b * max(dt, 0.0)
        return dt < self.cycles * self.b


class VirtualStage:
    """A Zaber-style ASCII stage answering on a pty, its motion following a :class:`VirtualClock`.

    Moves run at constant speed (no acceleration ramp); ``move sin`` follows
    :func:`softcath.hardware.stage.sine_trajectory`. Positions are microsteps,
    velocities Zaber units (microsteps/s x 1.6384).
    """

    def __init__(
        self,
        clock: VirtualClock | None = None,
        *,
        device: int = 1,
        max_position: int = 10**9,
        maxspeed: float = 153600.0,
    ) -> None:
        self.pty = PtyPair()
        self.clock = clock or VirtualClock()
        self.device = device
        self.max_position = max_position
        self.maxspeed = maxspeed  # Zaber units
        self.motion = _Motion(0.0, 0.0, "hold")
        self.history: list[_Motion] = [self.motion]
        self.commands: list[tuple[float, str]] = []
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._serve, daemon=True, name="virtual-stage")
        self._thread.start()

    @property
    def url(self) -> str:
        """The port a driver opens."""
        return self.pty.path

    def trajectory_steps(self, t_s) -> np.ndarray:
        """Position in microsteps at the times ``t_s`` from the recorded motion history.

        Valid for times at or after the command that started each motion (the
        virtual bench sends its commands on a manual clock before it samples).
        """
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        with self._lock:
            hist = list(self.history)
        starts = np.array([m.t0 for m in hist])
        idx = np.searchsorted(starts, t, side="right") - 1
        out = np.empty_like(t)
        for j in np.unique(idx):
            sel = idx == j
            m = hist[max(j, 0)]
            out[sel] = [m.position(ti) for ti in t[sel]]
        return out

    def _serve(self) -> None:
        buf = b""
        fd = self.pty.master_fd
        while not self._stop.is_set():
            try:
                ready, _, _ = select.select([fd], [], [], 0.05)
                if not ready:
                    continue
                chunk = os.read(fd, 1024)
            except OSError:
                return
            if not chunk:
                return
            buf += chunk
            while b"\n" in buf:
                line, buf = buf.split(b"\n", 1)
                reply = self.handle(line.decode("ascii", "replace").strip())
                if reply is not None:
                    try:
                        self.pty.write(reply)
                    except OSError:
                        return

    def handle(self, text: str) -> bytes | None:
        """Answer one command line (without terminator); None if it is not for us."""
        if not text.startswith("/"):
            return None
        body = text[1:]
        with_cs = False
        if ":" in body:
            body, cs = body.rsplit(":", 1)
            with_cs = True
            if lrc(body) != cs.upper():
                return self._reply(0, "RJ", "BADDATA", with_cs)
        parts = body.split()
        try:
            device = int(parts[0]) if parts else 0
            axis = int(parts[1]) if len(parts) > 1 else 0
        except ValueError:
            return self._reply(0, "RJ", "BADCOMMAND", with_cs)
        if device not in (0, self.device):
            return None
        words = parts[2:]
        t = self.clock.now()
        with self._lock:
            self.commands.append((t, " ".join(words)))
            before = self.motion
            try:
                data = self._execute(words, t)
            except (ValueError, IndexError):
                return self._reply(axis, "RJ", "BADDATA", with_cs, t)
            if self.motion is not before:
                self.history.append(self.motion)
            if data is None:
                return self._reply(axis, "RJ", "BADCOMMAND", with_cs, t)
            return self._reply(axis, "OK", data, with_cs, t)

    def _execute(self, w: list[str], t: float) -> str | None:
        x = self.motion.position(t)
        speed = self.maxspeed / ZABER_VELOCITY_UNIT  # microsteps/s
        if not w:
            return "0"
        if w == ["home"]:
            self.motion = _Motion(t, x, "line", 0.0, speed)
        elif w[:2] == ["move", "abs"]:
            target = int(w[2])
            if not 0 <= target <= self.max_position:
                raise ValueError(target)
            self.motion = _Motion(t, x, "line", float(target), speed)
        elif w[:2] == ["move", "rel"]:
            self.motion = _Motion(t, x, "line", x + int(w[2]), speed)
        elif w[:2] == ["move", "vel"]:
            self.motion = _Motion(t, x, "vel", int(w[2]) / ZABER_VELOCITY_UNIT)
        elif w[:2] == ["move", "sin"] and w[2:3] == ["stop"]:
            self.motion = _Motion(t, x, "hold")
        elif w[:2] == ["move", "sin"]:
            amp, period_ms = int(w[2]), int(w[3])
            cycles = float(w[4]) if len(w) > 4 else float("inf")
            if amp <= 0 or period_ms <= 0:
                raise ValueError(w)
            self.motion = _Motion(t, x, "sin", float(amp), period_ms / 1000.0, cycles)
        elif w == ["stop"]:
            self.motion = _Motion(t, x, "hold")
        elif w[:2] == ["set", "maxspeed"]:
            value = int(w[2])
            if value <= 0:
                raise ValueError(value)
            self.maxspeed = float(value)
        elif w == ["get", "pos"]:
            return str(int(round(x)))
        elif w == ["get", "maxspeed"]:
            return str(int(self.maxspeed))
        else:
            return None
        return "0"

    def _reply(self, axis: int, flag: str, data: str, with_cs: bool, t: float | None = None) -> bytes:
        busy = t is not None and self.motion.busy(t)
        body = f"{self.device:02d} {axis} {flag} {'BUSY' if busy else 'IDLE'} -- {data}"
        if with_cs:
            return f"@{body}:{lrc(body)}\r\n".encode("ascii")
        return f"@{body}\r\n".encode("ascii")

    def close(self) -> None:
        """Stop answering and close the pty."""
        self._stop.set()
        self._thread.join(timeout=2)
        self.pty.close()
