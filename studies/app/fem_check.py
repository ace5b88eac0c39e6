"""The 3-D FEM check of the app's current design, in a child process that a cancel ends at once.

The check is :func:`softcath.fem.check` (what ``softcath fem DESIGN --pressure P`` runs):
tens of seconds to minutes of meshing and solving, in compiled code that no
flag can interrupt, so it runs in its own process (``spawn``: a fresh
interpreter, no state shared with the server's threads) and a cancel
terminates that process. The mesh cache is not used: the app writes no files.
Stages and the result come back on a queue that the page polls.
"""

from __future__ import annotations

import logging
import multiprocessing as mp
import queue
from dataclasses import dataclass, field
from typing import Any

from softcath import design as design_pkg
from softcath import fem

__all__ = ["FemCheckRunner", "FemCheckView"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class FemCheckView:
    """What the page shows of a 3-D check.

    Attributes
    ----------
    state
        ``"idle"``, ``"running"``, ``"done"``, ``"failed"`` or ``"cancelled"``.
    stage
        The check's current stage (``"meshing"``, ``"solving"``, …) while running.
    message
        The one-line reason of a failure.
    numbers
        The result at the requested pressure and load: ``curvature_per_mm``,
        ``bend_angle_rad``, ``elongation``, ``max_strain``, ``curvature_formula_per_mm``
        (the paper's formula at the same load), ``pressure_MPa``, ``load``, ``dofs``.
    """

    state: str = "idle"
    stage: str = ""
    message: str = ""
    numbers: dict[str, Any] = field(default_factory=dict)


def _child(toml_text: str, pressure: float, load: str, mesh_size: float, out: Any) -> None:
    """The child process: run the check and put ``("stage", text)`` … ``("done", numbers)``."""
    try:
        d = design_pkg.loads(toml_text, source="the app's design")
        r = fem.check(
            d,
            pressures=[pressure],
            loads=(load,),
            mesh_size=mesh_size,
            use_cache=False,
            progress=lambda stage: out.put(("stage", str(stage))),
        )
        c = r.case(load, pressure)
        out.put(
            (
                "done",
                {
                    "pressure_MPa": pressure,
                    "load": load,
                    "curvature_per_mm": c.curvature_per_mm,
                    "bend_angle_rad": c.bend_angle_rad,
                    "elongation": c.elongation,
                    "max_strain": c.max_strain,
                    "curvature_formula_per_mm": c.analytic["curvature_per_mm"],
                    "dofs": r.dofs,
                },
            )
        )
    except Exception as exc:  # reported to the page as one line; the server never sees a traceback
        out.put(("failed", f"{type(exc).__name__}: {' '.join(str(exc).split())[:300]}"))


class FemCheckRunner:
    """At most one 3-D FEM check at a time, started, polled and cancelled by the page."""

    def __init__(self) -> None:
        self._ctx = mp.get_context("spawn")
        self._proc: Any = None
        self._queue: Any = None
        self._view = FemCheckView()

    def start(self, design, *, pressure: float, load: str = "lumen", mesh_size: float = 0.16) -> None:
        """Start the check of ``design`` at ``pressure`` [MPa] (a running one is cancelled first)."""
        self.cancel()
        self._queue = self._ctx.Queue()
        text = design_pkg.dumps(design)
        self._proc = self._ctx.Process(
            target=_child, args=(text, float(pressure), load, float(mesh_size), self._queue), daemon=True
        )
        self._proc.start()
        self._view = FemCheckView(state="running", stage="starting")

    def poll(self) -> FemCheckView:
        """Read what the child reported since the last poll; the current view."""
        if self._view.state != "running" or self._queue is None:
            return self._view
        alive = self._proc is not None and self._proc.is_alive()  # before reading: no message missed
        while True:
            try:
                kind, payload = self._queue.get_nowait()
            except queue.Empty:
                break
            if kind == "stage":
                self._view = FemCheckView(state="running", stage=payload)
            elif kind == "done":
                self._view = FemCheckView(state="done", numbers=payload)
            else:
                self._view = FemCheckView(state="failed", message=payload)
        if self._view.state == "running" and not alive:
            exitcode = None if self._proc is None else self._proc.exitcode
            self._view = FemCheckView(
                state="failed", message=f"the check's process ended (exit code {exitcode})"
            )
        if self._view.state != "running":
            self._reap()
        return self._view

    def cancel(self) -> None:
        """End a running check now (its process is terminated)."""
        if self._proc is not None and self._proc.is_alive():
            self._proc.terminate()
            self._view = FemCheckView(state="cancelled")
        self._reap()

    def _reap(self) -> None:
        if self._proc is not None:
            self._proc.join(timeout=5)
            self._proc = None
        if self._queue is not None:
            self._queue.close()
            self._queue = None
