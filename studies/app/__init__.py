"""``softcath app``: a local web app to design the tip interactively (Panel).

Every design field a sweep can vary is an input (same dotted paths, same
validation); the section, κ and θ against pressure (the paper's formula and
the linear section model at once, the finite-strain section model in the
background), the bent tip and the numbers follow each change. Pin a design
and overlay later ones, overlay a measurement CSV, download the design
(TOML), the curves (CSV) and the view (PNG), and run the 3-D FEM check.

Modules: ``fields`` (the inputs), ``state`` (apply a value, keep the last
valid design), ``curves`` and ``numbers`` (what is shown), ``jobs``
(background work, newest wins), ``fem_check`` (the 3-D check in a child
process), ``measured`` (uploads), ``export``, ``shapes`` and ``plots``
(drawing), ``inputs``, ``page`` and ``layout`` (one session's page),
``server`` (serving it; :func:`view` for a notebook).

Panel is imported only when a page is built.
"""

from __future__ import annotations

from softcath.studies.app.fields import Field, design_fields
from softcath.studies.app.server import make_server, start_in_thread, view
from softcath.studies.app.state import AppState, apply_value, initial_state

__all__ = [
    "AppState",
    "Field",
    "apply_value",
    "design_fields",
    "initial_state",
    "make_server",
    "start_in_thread",
    "view",
]
