"""Errors raised by the bench: devices, frame sources and measurements."""

from __future__ import annotations

from softcath.core.errors import SoftcathError

__all__ = ["DeviceError", "FrameSourceError"]


class DeviceError(SoftcathError):
    """A serial device cannot be opened, vanished, or answered something unexpected."""


class FrameSourceError(SoftcathError):
    """A camera, video file or image folder cannot be opened or read."""
