"""Work for the app's background worker in tests (module level: the worker process imports it)."""

from __future__ import annotations

import os
import time


def divide(progress, x: float) -> float:
    return 1 / x


def wait_for(progress, seconds: float) -> str:
    """Report progress every 50 ms for ``seconds`` (stops there when superseded)."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        progress(0, 1)
        time.sleep(0.05)
    return "waited"


def die(progress, code: int) -> None:
    os._exit(code)
