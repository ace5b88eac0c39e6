"""A driver for a Zaber-style ASCII linear stage pushing a syringe, and the syringe model.

The paper sets the pressure by moving a syringe plunger with a Zaber
X-LRQ150BL-E01 stage driven from the Zaber console (section II.A). This
driver implements the subset of the Zaber ASCII protocol the bench needs:
commands ``/<dev> <axis> <cmd> [data][:CC]\\n``
and replies ``@<dev> <axis> <OK|RJ> <IDLE|BUSY> <warning> <data>[:CC]``. The
optional checksum is Zaber's LRC: the two's complement of the byte sum
(mod 256) of everything after ``/`` or ``@`` up to ``:``.

Positions on the wire are integer microsteps; the driver speaks mm.
``zaber-motion`` exists but bundles a native library and downloads a
device database, hence this small driver.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from softcath.core.errors import DesignError
from softcath.hardware.errors import DeviceError
from softcath.hardware.ports import open_port

__all__ = [
    "lrc",
    "format_command",
    "StageReply",
    "parse_reply",
    "ZaberStage",
    "SyringeModel",
    "sine_trajectory",
    "DEFAULT_MICROSTEP_MM",
    "ZABER_VELOCITY_UNIT",
]

#: Microstep size of the X-LRQ-E series, mm (0.09921875 um per microstep; check your stage's
#: datasheet and pass ``microstep_mm`` if it differs).
DEFAULT_MICROSTEP_MM = 0.09921875e-3

#: Zaber ASCII velocities are in microsteps/s times 1.6384 (the controller's tick unit).
ZABER_VELOCITY_UNIT = 1.6384


def lrc(body: str) -> str:
    """Zaber's longitudinal redundancy check of ``body`` as two upper-case hex digits."""
    return f"{(256 - sum(body.encode('ascii')) % 256) % 256:02X}"


def format_command(command: str, *, device: int = 1, axis: int = 0, checksums: bool = False) -> bytes:
    """One command line, e.g. ``/1 1 move abs 4321\\n`` (with ``:CC`` when ``checksums``)."""
    body = f"{device} {axis} {command}".strip() if command else f"{device} {axis}"
    if checksums:
        return f"/{body}:{lrc(body)}\n".encode("ascii")
    return f"/{body}\n".encode("ascii")


@dataclass(frozen=True)
class StageReply:
    """A parsed reply line: device, axis, flag (OK/RJ), status (IDLE/BUSY), warning, data."""

    device: int
    axis: int
    flag: str
    status: str
    warning: str
    data: str


def parse_reply(line: bytes | str) -> StageReply:
    """Parse a reply line; raises :class:`DeviceError` on malformed text or a bad checksum."""
    text = line.decode("ascii", "replace") if isinstance(line, bytes) else line
    text = text.strip()
    if not text.startswith("@"):
        raise DeviceError(f"stage reply {text!r}: expected a line starting with '@'")
    body = text[1:]
    if ":" in body:
        body, cs = body.rsplit(":", 1)
        if lrc(body) != cs.upper():
            raise DeviceError(f"stage reply {text!r}: checksum {cs} != {lrc(body)}")
    parts = body.split(" ", 5)
    if len(parts) < 5:
        raise DeviceError(f"stage reply {text!r}: expected '@dev axis flag status warning data'")
    try:
        device, axis = int(parts[0]), int(parts[1])
    except ValueError as exc:
        raise DeviceError(f"stage reply {text!r}: device/axis are not integers") from exc
    data = parts[5] if len(parts) > 5 else ""
    return StageReply(device, axis, parts[2], parts[3], parts[4], data)


class ZaberStage:
    """A Zaber-style ASCII stage on a pyserial URL, positions and speeds in mm and mm/s.

    Parameters
    ----------
    url
        pyserial URL or port name (Zaber default 115200 baud).
    device, axis
        Device address and axis number.
    microstep_mm
        Length of one microstep, mm.
    checksums
        Send and demand LRC checksums.
    reply_timeout_s
        How long to wait for a reply, s.
    """

    def __init__(
        self,
        url: str,
        *,
        device: int = 1,
        axis: int = 1,
        microstep_mm: float = DEFAULT_MICROSTEP_MM,
        checksums: bool = False,
        reply_timeout_s: float = 1.0,
    ) -> None:
        if not microstep_mm > 0:
            raise DesignError("microstep_mm", microstep_mm, "must be > 0")
        self.url = url
        self.device = device
        self.axis = axis
        self.microstep_mm = float(microstep_mm)
        self.checksums = checksums
        self.reply_timeout_s = reply_timeout_s
        self._port = None

    # -- connection -------------------------------------------------------------------------
    def open(self) -> ZaberStage:
        """Open the port."""
        self._port = open_port(self.url, name="stage", timeout_s=0.05)
        return self

    def close(self) -> None:
        """Close the port."""
        if self._port is not None:
            self._port.close()
            self._port = None

    def __enter__(self) -> ZaberStage:
        return self.open()

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- protocol ---------------------------------------------------------------------------
    def command(self, text: str) -> StageReply:
        """Send one command and return its reply; raises :class:`DeviceError` if rejected."""
        import serial

        if self._port is None:
            raise DeviceError(f"stage on {self.url}: not open")
        line = format_command(text, device=self.device, axis=self.axis, checksums=self.checksums)
        try:
            self._port.write(line)
            reply = self._read_reply()
        except (serial.SerialException, OSError) as exc:
            raise DeviceError(f"stage on {self.url} disconnected: {exc}") from exc
        if reply.flag != "OK":
            raise DeviceError(f"stage rejected {text!r}: {reply.flag} {reply.data}")
        return reply

    def _read_reply(self) -> StageReply:
        deadline = time.monotonic() + self.reply_timeout_s
        buf = b""
        while time.monotonic() < deadline:
            buf += self._port.readline()
            if buf.endswith(b"\n"):
                if buf.startswith(b"@"):
                    return parse_reply(buf)
                buf = b""  # an alert ('!') or info ('#') line: not our reply
        raise DeviceError(f"stage on {self.url}: no reply within {self.reply_timeout_s} s")

    def _steps(self, mm: float) -> int:
        return int(round(mm / self.microstep_mm))

    def _speed(self, mm_s: float) -> int:
        return int(round(mm_s / self.microstep_mm * ZABER_VELOCITY_UNIT))

    # -- motion -----------------------------------------------------------------------------
    def home(self) -> None:
        """Home the axis."""
        self.command("home")

    def move_abs(self, position_mm: float) -> None:
        """Move to ``position_mm``."""
        self.command(f"move abs {self._steps(position_mm)}")

    def move_rel(self, distance_mm: float) -> None:
        """Move by ``distance_mm``."""
        self.command(f"move rel {self._steps(distance_mm)}")

    def move_velocity(self, speed_mm_s: float) -> None:
        """Move at constant ``speed_mm_s`` (sign gives direction) until stopped."""
        self.command(f"move vel {self._speed(speed_mm_s)}")

    def set_max_speed(self, speed_mm_s: float) -> None:
        """Set the speed used by absolute and relative moves, mm/s."""
        if not speed_mm_s > 0:
            raise DesignError("stage.max_speed_mm_s", speed_mm_s, "must be > 0")
        self.command(f"set maxspeed {self._speed(speed_mm_s)}")

    def move_sine(self, amplitude_mm: float, period_s: float, cycles: int | None = None) -> None:
        """The firmware sine move the paper drove from the Zaber console (``move sin``).

        Sends ``amplitude_mm`` (microsteps) and ``period_s`` (ms) and
        ``cycles`` (forever if None). softcath's virtual stage starts at rest
        at the current position ``x0`` and follows
        :func:`sine_trajectory`, ``x0 + A (1 - cos(2 pi t / T))``; check the
        manual of your firmware for its exact phase convention.
        """
        if not amplitude_mm > 0:
            raise DesignError("stage.sine_amplitude_mm", amplitude_mm, "must be > 0")
        if not period_s > 0:
            raise DesignError("stage.sine_period_s", period_s, "must be > 0")
        cmd = f"move sin {self._steps(amplitude_mm)} {int(round(period_s * 1000))}"
        if cycles is not None:
            cmd += f" {int(cycles)}"
        self.command(cmd)

    def stop(self) -> None:
        """Decelerate to a stop."""
        self.command("stop")

    def position_mm(self) -> float:
        """Current position, mm."""
        return int(self.command("get pos").data.split()[0]) * self.microstep_mm

    def status(self) -> StageReply:
        """The status reply of an empty command (BUSY or IDLE)."""
        return self.command("")

    def wait_idle(self, timeout_s: float = 30.0, poll_s: float = 0.02) -> None:
        """Poll until the axis reports IDLE."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if self.status().status == "IDLE":
                return
            time.sleep(poll_s)
        raise DeviceError(f"stage on {self.url}: still BUSY after {timeout_s} s")


@dataclass(frozen=True)
class SyringeModel:
    """Plunger displacement to expected pressure for a syringe feeding a compliant line.

    ``p = p0 + (pi/4 d^2 x) / C``: the displaced volume (mm^3) divided by the
    hydraulic compliance ``C`` of line, tube and trapped air (mm^3/MPa).
    Measure ``C`` once by recording pressure against displacement.

    Parameters
    ----------
    plunger_diameter_mm
        Syringe bore, mm.
    compliance_mm3_per_MPa
        Volume needed per MPa of pressure rise, mm^3/MPa.
    p0_MPa
        Pressure at zero displacement, MPa.
    """

    plunger_diameter_mm: float = 4.7
    compliance_mm3_per_MPa: float = 120.0
    p0_MPa: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.plunger_diameter_mm) and self.plunger_diameter_mm > 0):
            raise DesignError("syringe.plunger_diameter_mm", self.plunger_diameter_mm, "must be > 0")
        if not (math.isfinite(self.compliance_mm3_per_MPa) and self.compliance_mm3_per_MPa > 0):
            raise DesignError("syringe.compliance_mm3_per_MPa", self.compliance_mm3_per_MPa, "must be > 0")

    @property
    def gain_MPa_per_mm(self) -> float:
        """Pressure rise per mm of plunger travel, MPa/mm."""
        return math.pi / 4 * self.plunger_diameter_mm**2 / self.compliance_mm3_per_MPa

    def pressure_MPa(self, displacement_mm):
        """Expected pressure for a plunger displacement, MPa."""
        return self.p0_MPa + self.gain_MPa_per_mm * np.asarray(displacement_mm, dtype=float)

    def displacement_mm(self, pressure_MPa):
        """Plunger displacement giving ``pressure_MPa``, mm."""
        return (np.asarray(pressure_MPa, dtype=float) - self.p0_MPa) / self.gain_MPa_per_mm


def sine_trajectory(t_s, *, amplitude_mm: float, period_s: float, start_mm: float = 0.0) -> np.ndarray:
    """Sine move started at rest at ``start_mm`` at ``t = 0``: ``x0 + A (1 - cos(2 pi t/T))``, mm.

    Starting at an extreme with zero velocity avoids a velocity step, and a
    syringe pressure then rises from its rest value to ``2 A`` worth of
    displacement and back, like the paper's Fig. 4 excitation.
    """
    t = np.asarray(t_s, dtype=float)
    return start_mm + amplitude_mm * (1.0 - np.cos(2 * np.pi * t / period_s))
