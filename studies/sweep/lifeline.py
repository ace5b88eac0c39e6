"""Sweep worker processes die with the sweep that started them.

A sweep killed with SIGKILL runs no clean-up: its pool's workers (children of the
multiprocessing fork server, or of the sweep for a Dask LocalCluster) would finish
their task and then wait forever, holding hundreds of MB each. Two ties, both set
in each worker as it starts:

1. Linux ``prctl(PR_SET_PDEATHSIG, SIGKILL)``: the kernel kills the worker when its
   parent process exits (the fork server exits when the sweep dies).
2. A watchdog thread polling the sweep's pid every ``interval_s``: it covers the
   platforms without ``prctl`` and a parent that is not the sweep itself.
"""

from __future__ import annotations

import logging
import os
import signal
import sys
import threading
import time

from softcath.core.atomic import pid_alive

__all__ = ["tie_to_parent", "pid_alive"]

log = logging.getLogger(__name__)

_PR_SET_PDEATHSIG = 1


def _set_pdeathsig() -> bool:
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def tie_to_parent(sweep_pid: int, *, interval_s: float = 0.5) -> None:
    """Make this worker process exit when process ``sweep_pid`` (the sweep) is gone."""
    parent = os.getppid()
    _set_pdeathsig()
    if not pid_alive(parent) or not pid_alive(sweep_pid):  # died before the tie was made
        os._exit(1)

    def watch() -> None:
        while True:
            time.sleep(interval_s)
            if not pid_alive(sweep_pid) or os.getppid() != parent:
                os._exit(1)  # no clean-up to do: results go back to the (dead) sweep only

    threading.Thread(target=watch, name="softcath-lifeline", daemon=True).start()
