"""Candidate missing effects: named, physically meaningful augmentations of the model.

Each effect is one small module exposing ``CANDIDATE`` (a
:class:`~analytic.effects.base.Candidate`): bounded parameters with units and
an operator. :func:`fit_chain` fits the model plus any chain of them to data.
Adding an effect is one module plus one line in ``_MODULES``.

>>> from softcath.analytic import effects
>>> effects.names()[:3]
('hysteresis', 'lag', 'delay')
"""

from __future__ import annotations

import importlib

from softcath.analytic.effects.base import STAGE_ORDER, Candidate, Param, Scales

__all__ = [
    "Candidate",
    "Param",
    "Scales",
    "STAGE_ORDER",
    "get",
    "names",
    "register",
    "MEASURED_CANDIDATES",
    "FEM_CANDIDATES",
]

_MODULES = (
    "hysteresis",
    "lag",
    "delay",
    "dead_zone",
    "viscoelastic",
    "offset",
    "nonlinear_gain",
    "lumen_poisson",
)

_REGISTRY: dict[str, Candidate] = {}

#: candidates tried against measured data (time series): all but the FEM-only lumen-wall term
MEASURED_CANDIDATES: tuple[str, ...] = tuple(m for m in _MODULES if m != "lumen_poisson")
#: candidates tried against a quasi-static FEM reference (no time, gain not calibrated)
FEM_CANDIDATES: tuple[str, ...] = ("lumen_poisson", "nonlinear_gain", "offset", "dead_zone")


def register(candidate: Candidate) -> None:
    """Add a candidate to the registry (its ``name`` must be in ``STAGE_ORDER``)."""
    from softcath.design.errors import DesignError

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
    from softcath.design.errors import DesignError

    try:
        return _REGISTRY[name]
    except KeyError:
        raise DesignError("effect", name, f"must be one of {', '.join(_REGISTRY)}") from None


def __getattr__(attr: str):  # lazy: the fitting module pulls in scipy.optimize
    if attr in ("fit_chain", "predict_chain", "ChainFit", "Segment"):
        return getattr(importlib.import_module("softcath.analytic.effects.fit"), attr)
    raise AttributeError(attr)
