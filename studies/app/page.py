"""One app session: the design state, its computations and the page that shows them.

An edit is applied to the state (:func:`~softcath.studies.app.state.apply_value`);
when the design changed, the formula and the linear section model are solved
at once (~20-40 ms) and drawn, and the finite-strain curve is submitted to
the session's worker process (:class:`~softcath.studies.app.jobs.LatestJob`:
a newer design supersedes it), its previous curve staying on screen until
the new one arrives. A poll every :data:`POLL_MS` ms moves background results onto the
page. Every callback is guarded: a failure becomes a message on the page and
the session goes on.
"""

from __future__ import annotations

import functools
import logging
import math
import time
from typing import Any

import numpy as np

from softcath import models
from softcath.core.errors import SoftcathError
from softcath.core.limits import check_pressure
from softcath.studies.app.curves import TierCurve, finite_strain_curve, formula_curve, linear_section_curve
from softcath.studies.app.fem_check import FemCheckRunner
from softcath.studies.app.jobs import LatestJob
from softcath.studies.app.measured import MeasuredCurve, read_upload
from softcath.studies.app.state import AppState, apply_value, initial_state

__all__ = ["POLL_MS", "Session"]

log = logging.getLogger(__name__)

#: How often the page looks for background results [ms].
POLL_MS = 150
#: Pressure points of the linear curves and of the finite-strain curve.
LINEAR_POINTS, FINITE_POINTS = 61, 13
#: The finite-strain curve starts this long [s] after the change that asked for it: the fast curves
#: reach the page first (the worker shares the machine's cores with the server and the browser),
#: and a quick run of edits starts one computation, not one per keystroke.
FINITE_DELAY_S = 0.3


def finite_strain_work(progress, design, pressures, version: int, delay: float):
    """The background request (run in the worker process): after ``delay`` [s], the finite-strain
    curve of ``design`` at ``pressures``; returns ``(version, curve)``. ``progress`` raises
    :class:`~softcath.studies.app.jobs.Superseded` once a newer design was submitted."""
    total = len(pressures) - 1
    end = time.monotonic() + delay
    while time.monotonic() < end:  # a quick run of edits starts one computation, not one per edit
        progress(0, total)
        time.sleep(0.05)
    return version, finite_strain_curve(design, pressures, on_pressure=progress)


def guarded(what: str):
    """Decorate a page callback: an exception becomes the page's message, never a dead session."""

    def wrap(fn):
        @functools.wraps(fn)
        def run(self, *args, **kwargs):
            try:
                return fn(self, *args, **kwargs)
            except SoftcathError as exc:
                self.say(f"{what}: {' '.join(str(exc).split())}")
            except Exception as exc:
                log.exception("%s failed", what)
                self.say(
                    f"{what} failed: unexpected {type(exc).__name__}: {' '.join(str(exc).split())[:300]}"
                )
            return None

        return run

    return wrap


class Session:
    """The state and computations of one page (the widgets live in :mod:`~softcath.studies.app.layout`).

    Parameters
    ----------
    spec
        The starting design: a preset name, a TOML path or a :class:`~softcath.design.TipDesign`.
    p_max
        Largest pressure of the curves [MPa].
    pressure
        The chosen pressure for the tip view and the numbers [MPa].
    """

    def __init__(self, spec, *, p_max: float = 1.5, pressure: float = 0.5) -> None:
        self.state: AppState = initial_state(spec)
        self.p_max, self.pressure = float(p_max), float(pressure)
        self.fast: list[TierCurve] = []
        self.finite: TierCurve | None = None
        self.finite_version = -1  # the design version the shown finite-strain curve belongs to
        self.finite_message = ""
        self.pinned: list[TierCurve] = []
        self.pinned_label = ""
        self.measured: MeasuredCurve | None = None
        self.finite_job = LatestJob(finite_strain_work)
        self.messages: list[str] = []
        try:
            self.finite_job.start()  # the worker imports the models while the page loads
        except Exception as exc:  # e.g. a script without a __main__ guard cannot spawn processes
            log.exception("the background worker did not start")
            self.messages.append(f"finite-strain section model unavailable: {type(exc).__name__}: {exc}")
        self.fem = FemCheckRunner()
        self._shown_ticket = 0
        self.listeners: list[Any] = []  # the layout's redraw hooks: called with the name of what changed

    # --- messages and redraws --------------------------------------------------------------------
    def say(self, text: str) -> None:
        """Show ``text`` as the page's latest message."""
        self.messages = [*self.messages[-4:], text]
        self._tell("message")

    def _tell(self, what: str) -> None:
        for listener in self.listeners:
            listener(what)

    @property
    def curves(self) -> list[TierCurve]:
        """The current design's curves: formula, linear section and (when it belongs to this
        design or is the previous one still shown) finite strain."""
        return [*self.fast, *([self.finite] if self.finite is not None else [])]

    @property
    def finite_is_current(self) -> bool:
        return self.finite is not None and self.finite_version == self.state.version

    # --- the design --------------------------------------------------------------------------------
    @guarded("input")
    def edit(self, path: str, value: Any) -> None:
        """Apply a typed value; on a new design, recompute."""
        before = self.state.version
        self.state = apply_value(self.state, path, value)
        self._tell("inputs")
        if self.state.version != before:
            self.recompute()

    @guarded("pressure range")
    def set_pressures(self, *, p_max: float | None = None, pressure: float | None = None) -> None:
        """Change the curves' largest pressure and/or the chosen pressure [MPa]."""
        if p_max is not None:
            p = float(check_pressure(p_max, param="largest pressure")[0])
            if not p > 0:
                raise SoftcathError(f"largest pressure = {p:g}: must be > 0 MPa")
            self.p_max = p
        if pressure is not None:
            self.pressure = float(check_pressure(pressure, param="pressure")[0])
        if p_max is not None:
            self.recompute()
        else:
            self._tell("pressure")

    def recompute(self) -> None:
        """The fast tiers now, the finite-strain tier in the background."""
        self.compute_fast()
        self.submit_finite()

    @guarded("formula and linear section model")
    def compute_fast(self) -> None:
        """Solve the formula and the linear section model for the current design and show them."""
        d = self.state.design
        p = np.linspace(0.0, self.p_max, LINEAR_POINTS)
        curves = [formula_curve(d, p)]
        try:
            curves.append(linear_section_curve(d, p))
        finally:
            self.fast = curves  # the formula is shown even when the section model fails
            self._tell("fast")

    @guarded("finite-strain section model")
    def submit_finite(self) -> None:
        """Submit the finite-strain curve of the current design (supersedes any earlier one)."""
        p = np.linspace(0.0, self.p_max, FINITE_POINTS)
        self.finite_job.submit(self.state.design, p, self.state.version, FINITE_DELAY_S)
        self._tell("finite-progress")

    def poll(self) -> None:
        """Move finished background work onto the page (called every :data:`POLL_MS` ms)."""
        try:
            self._poll_finite()
            self._poll_fem()
        except Exception as exc:  # the poll must keep running whatever a result holds
            log.exception("poll failed")
            self.say(f"background result could not be shown: {type(exc).__name__}: {exc}")

    def _poll_finite(self) -> None:
        ticket = self.finite_job.poll()
        if ticket is None:
            return
        if ticket.state in ("queued", "running"):
            self._tell("finite-progress")
            return
        if ticket.number == self._shown_ticket:
            return
        self._shown_ticket = ticket.number
        if ticket.state == "done":
            version, curve = ticket.result
            self.finite_version, self.finite, self.finite_message = version, curve, curve.message
        elif ticket.state == "failed":
            self.finite, self.finite_version = None, self.state.version
            self.finite_message = ticket.message
        self._tell("finite")

    def _poll_fem(self) -> None:
        before = getattr(self, "_fem_view", None)
        view = self.fem.poll()
        if view != before:
            self._fem_view = view
            self._tell("fem-check")

    # --- compare, upload, 3-D check ------------------------------------------------------------------
    def pin(self) -> None:
        """Pin the current design's curves as A (drawn dashed under the later designs)."""
        self.pinned = [*self.fast, *([self.finite] if self.finite_is_current and self.finite else [])]
        changed = ", ".join(
            f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}" for k, v in self.state.overrides.items()
        )
        self.pinned_label = f"A: design version {self.state.version}" + (f" ({changed})" if changed else "")
        self._tell("pinned")

    def unpin(self) -> None:
        self.pinned, self.pinned_label = [], ""
        self._tell("pinned")

    @guarded("measurement upload")
    def upload(self, data: bytes | None, filename: str | None) -> None:
        """Overlay an uploaded measurement CSV (a bad file: one message, the old overlay kept)."""
        if not data:
            return
        self.measured = read_upload(data, filename or "upload.csv")
        dropped = (
            f", {self.measured.dropped} rows with a missing value dropped" if self.measured.dropped else ""
        )
        self.say(f"overlaid {self.measured.name}: {self.measured.pressure_MPa.size} rows{dropped}")
        self._tell("measured")

    def clear_measured(self) -> None:
        self.measured = None
        self._tell("measured")

    @guarded("3-D FEM check")
    def start_fem(self) -> None:
        """Start the 3-D linear FEM check of the current design at the chosen pressure (lumen load)."""
        if not self.pressure > 0:
            raise SoftcathError(f"pressure = {self.pressure:g}: the 3-D check needs a pressure > 0 MPa")
        self.fem.start(self.state.design, pressure=self.pressure, load="lumen")
        self._poll_fem()

    def cancel_fem(self) -> None:
        self.fem.cancel()
        self._poll_fem()

    def close(self) -> None:
        """End the session's background work (the page was closed)."""
        self.finite_job.close()
        self.fem.cancel()

    def linear_at(self, pressure: float) -> float:
        """The linear section model's curvature at ``pressure`` (NaN without it): the 3-D check's peer."""
        c = next((c for c in self.fast if models.get(c.tier).section_mesh), None)  # not the formula
        return math.nan if c is None else c.at(pressure, "curvature_per_mm")
