"""Small timing helpers shared by the benchmark scripts."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any


def best_of(fn: Callable[[], object], repeat: int = 3) -> tuple[float, Any]:
    """Best wall time of ``repeat`` calls (s) and the last result."""
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def row(label: str, value: str, target: str = "", ok: bool | None = None) -> str:
    flag = "" if ok is None else ("  [meets target]" if ok else "  [MISSES target]")
    return f"  {label:<58} {value:>18}  {target}{flag}"
