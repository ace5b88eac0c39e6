"""The effect registry: which module names each candidate effect, and the candidate sets tried.

Each effect is one module of :mod:`softcath.analytic.effects` exposing
``CANDIDATE``; adding an effect is that module plus one line in ``_MODULES``.
"""

from __future__ import annotations

import importlib

from softcath.analytic.effects.base import STAGE_ORDER, Candidate
from softcath.core.errors import DesignError

__all__ = ["get", "names", "register", "MEASURED_CANDIDATES", "FEM_CANDIDATES"]

_MODULES = (
    "hysteresis",
    "lag",
    "delay",
    "dead_zone",
    "viscoelastic",
    "offset",
    "nonlinear_gain",
    "lumen_wall",
)

_REGISTRY: dict[str, Candidate] = {}

#: candidates tried against measured data (time series): all but the FEM-only lumen-wall term
MEASURED_CANDIDATES: tuple[str, ...] = tuple(m for m in _MODULES if m != "lumen_wall")
#: candidates tried against a quasi-static FEM reference (no time, gain not calibrated)
FEM_CANDIDATES: tuple[str, ...] = ("lumen_wall", "nonlinear_gain", "offset", "dead_zone")


def register(candidate: Candidate) -> None:
    """Add a candidate to the registry (its ``name`` must be in ``STAGE_ORDER``)."""
    if candidate.name not in STAGE_ORDER:
        raise DesignError("effect", candidate.name, f"must be one of {STAGE_ORDER}")
    _REGISTRY[candidate.name] = candidate


for _m in _MODULES:
    register(importlib.import_module(f"softcath.analytic.effects.{_m}").CANDIDATE)


def names() -> tuple[str, ...]:
    """Registered candidate names."""
    return tuple(_REGISTRY)


def get(name: str) -> Candidate:
    """The candidate called ``name``.

    Raises
    ------
    DesignError
        If no candidate has that name.
    """
    try:
        return _REGISTRY[name]
    except KeyError:
        raise DesignError("effect", name, f"must be one of {', '.join(_REGISTRY)}") from None
