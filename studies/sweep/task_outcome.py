"""What a sweep task that raised leaves behind: failed rows, or nothing for a retry."""

from __future__ import annotations

import logging

from softcath.core.interrupts import raise_pending_stop
from softcath.studies.sweep.evaluators import evaluate_task

__all__ = ["failed_frame", "outcome"]

# The sweep's messages keep the runner's logger name (one logger per sweep run for the user).
log = logging.getLogger("softcath.studies.sweep.runner")

# Failures of the machinery, not of the design: the task is not saved, so a rerun retries it.
# (ModuleNotFoundError: a cluster worker without softcath installed.)
_INFRASTRUCTURE = {
    "BrokenProcessPool",
    "KilledWorker",
    "CancelledError",
    "CommClosedError",
    "TimeoutError",
    "ModuleNotFoundError",
}


def outcome(task: dict, exc: BaseException):
    """``(task, rows)`` of a task that raised ``exc``: no rows (retried) when the machinery failed."""
    if type(exc).__name__ in _INFRASTRUCTURE:
        log.warning(
            "sweep task %s lost (%s: %s); it will be retried on the next run",
            task["task_id"],
            type(exc).__name__,
            exc,
        )
        return task, None
    return task, failed_frame(task, exc)


def failed_frame(task: dict, exc: BaseException):
    """Rows of a task whose evaluation raised: analytic values kept, status failed with the reason."""
    reason = f"task failed: {type(exc).__name__}: {exc}"
    log.warning("sweep task %s failed: %s", task["task_id"], reason)
    try:
        frame = evaluate_task(dict(task, evaluators=["paper"]))
    except Exception:  # even the analytic path fails: rows with the reason and no values
        raise_pending_stop()
        return evaluate_task(dict(task, fail_reason=reason))
    frame["status"] = "failed"
    frame["reason"] = [r or reason for r in frame["reason"]]
    return frame
