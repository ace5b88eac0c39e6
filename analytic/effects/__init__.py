"""Candidate missing effects: named, physically meaningful augmentations of the model.

Each effect is one small module exposing ``CANDIDATE`` (a
:class:`~analytic.effects.base.Candidate`): bounded parameters with units and
an operator. :mod:`~softcath.analytic.effects.registry` names them (adding an
effect is one module plus one line there); :func:`fit_chain` fits the model
plus any chain of them to data.

>>> from softcath.analytic import effects
>>> effects.names()[:3]
('hysteresis', 'lag', 'delay')
"""

from __future__ import annotations

import importlib

from softcath.analytic.effects.base import STAGE_ORDER, Candidate, Param, Scales
from softcath.analytic.effects.registry import FEM_CANDIDATES, MEASURED_CANDIDATES, get, names, register

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


def __getattr__(attr: str):  # lazy: the fitting module pulls in scipy.optimize
    if attr in ("fit_chain", "predict_chain", "ChainFit", "Segment"):
        return getattr(importlib.import_module("softcath.analytic.effects.fit"), attr)
    raise AttributeError(attr)
