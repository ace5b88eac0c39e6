"""The registry of model tiers: one name each, everywhere, and the one place a tier is chosen by name.

The same five names choose a tier in sweep specs (``evaluators``), on the command line
(``--model``, ``--compare``), in JSON outputs and in reports:

=====================  =========================================================
``paper``              the paper's formula (eq. 7, composite beam)
``section``            the linear section model (2-D generalised plane strain)
``section-nonlinear``  the finite-strain section model
``fem``                the 3-D linear FEM
``fem-nonlinear``      the 3-D finite-strain FEM
=====================  =========================================================

Older spellings (``analytic`` for ``paper``, ``nonlinear`` for ``fem-nonlinear``) are still
accepted: :func:`get` maps them to the new name and logs a deprecation warning.

A new tier is one :class:`~softcath.models.Tier` (its capabilities and its ``_solve``) and
one :func:`register` call; a new option of a tier is one entry of its ``options``. Every
consumer reads the registry, so each offers it without further edits.
"""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Iterable, Iterator, Mapping, Sequence
from typing import Any

import numpy as np

from softcath.core.response import ResponseBatch, TipResponse
from softcath.design.errors import DesignError
from softcath.models.fem3d import FEM
from softcath.models.fem_nonlinear import FEM_NONLINEAR
from softcath.models.paper import PAPER
from softcath.models.section import SECTION
from softcath.models.section_nonlinear import SECTION_NONLINEAR
from softcath.models.tier import REGISTERED, Tier

__all__ = [
    "ALIASES",
    "TIERS",
    "get",
    "linear_names",
    "names",
    "register",
    "registered",
    "response",
    "responses",
    "tier_name",
    "tiers",
    "unregister",
]

log = logging.getLogger(__name__)

#: Name -> tier, from the cheapest to the most expensive (:func:`register` adds to it).
TIERS: dict[str, Tier] = REGISTERED

#: Old spellings -> the tier's name (accepted with a deprecation warning in the log).
ALIASES: dict[str, str] = {"analytic": "paper", "nonlinear": "fem-nonlinear"}


def register(tier: Tier, *, aliases: Iterable[str] = ()) -> Tier:
    """Add ``tier`` (and old spellings of its name) to the registry; return it.

    Raises
    ------
    DesignError
        A tier or alias of that name is registered already.
    """
    if not isinstance(tier, Tier):
        raise DesignError("tier", tier, "must be a softcath.models.Tier")
    for n in (tier.name, *aliases):
        if n in TIERS or n in ALIASES:
            raise DesignError("tier.name", n, f"is registered already (tiers: {', '.join(TIERS)})")
    TIERS[tier.name] = tier
    ALIASES.update({a: tier.name for a in aliases})
    return tier


def unregister(name: str) -> Tier:
    """Remove the tier called ``name`` (and its old spellings) from the registry; return it.

    Raises
    ------
    DesignError
        No tier of that name is registered.
    """
    if name not in TIERS:
        raise DesignError("tier.name", name, f"is not registered (tiers: {', '.join(TIERS)})")
    for alias in [a for a, n in ALIASES.items() if n == name]:
        del ALIASES[alias]
    return TIERS.pop(name)


@contextlib.contextmanager
def registered(tier: Tier, *, replace: bool = False) -> Iterator[Tier]:
    """Register ``tier`` for the ``with`` block, then restore the registry as it was.

    ``replace`` lets ``tier`` stand in for the registered tier of its name (in its place in
    the order), e.g. the same tier with a new option, tried before it is made permanent.

    Raises
    ------
    DesignError
        A tier of that name is registered already and ``replace`` is false.
    """
    before = dict(TIERS)
    if replace and tier.name in TIERS:
        if not isinstance(tier, Tier):
            raise DesignError("tier", tier, "must be a softcath.models.Tier")
        TIERS[tier.name] = tier
    else:
        register(tier)
    try:
        yield tier
    finally:
        TIERS.clear()
        TIERS.update(before)
        for alias in [a for a, n in ALIASES.items() if n not in TIERS]:
            del ALIASES[alias]


def get(name: str, *, parameter: str = "model", allowed: Iterable[str] | None = None) -> Tier:
    """The :class:`Tier` called ``name`` (an old spelling maps to its new name, with a warning logged).

    Parameters
    ----------
    name
        A tier name or an old spelling of one (:data:`ALIASES`).
    parameter
        How the caller names the setting, for the error message.
    allowed
        The tiers the caller supports (default: all of :data:`TIERS`).

    Raises
    ------
    DesignError
        ``name`` is not a tier the caller supports; the message lists the allowed names.
    """
    allowed_names = tuple(TIERS) if allowed is None else tuple(allowed)
    key = name
    if isinstance(name, str) and name in ALIASES:
        key = ALIASES[name]
        log.warning("%s %r is deprecated: use %r (the same model)", parameter, name, key)
    if not isinstance(key, str) or key not in allowed_names or key not in TIERS:
        raise DesignError(parameter, name, f"must be one of {', '.join(allowed_names)}")
    return TIERS[key]


def tier_name(name: str, *, parameter: str = "model", allowed: Iterable[str] | None = None) -> str:
    """The tier's one name for ``name`` (see :func:`get`)."""
    return get(name, parameter=parameter, allowed=allowed).name


def names(*, exclude: Iterable[str] = ()) -> tuple[str, ...]:
    """The tiers' names in order, without those in ``exclude`` (e.g. for a command's choices)."""
    skip = set(exclude)
    return tuple(n for n in TIERS if n not in skip)


def tiers() -> tuple[Tier, ...]:
    """The registered tiers, from the cheapest to the most expensive."""
    return tuple(TIERS.values())


def linear_names() -> tuple[str, ...]:
    """The small-rotation tiers: those valid to a finite bend (:mod:`softcath.models.validity`)."""
    return tuple(t.name for t in TIERS.values() if t.linear)


def response(
    design,
    pressures: Sequence[float] | np.ndarray,
    *,
    tier: str,
    load: str | None = None,
    options: Mapping[str, Any] | None = None,
) -> TipResponse:
    """The response of ``design`` at ``pressures`` [MPa] by the tier called ``tier``.

    Parameters
    ----------
    design
        A :class:`softcath.design.TipDesign`.
    pressures
        Pressures [MPa].
    tier
        A tier name (:func:`names`; old spellings accepted with a warning).
    load
        ``"cap"`` or ``"lumen"``; default: the tier's :attr:`~softcath.models.Tier.default_load`.
    options
        The tier's options (:attr:`~softcath.models.Tier.options`); ``None`` values are left out.

    Raises
    ------
    DesignError
        An unknown tier, a load or an option the tier does not take (the message names
        the parameter, the value and what is accepted).
    """
    return get(tier, parameter="tier").response(design, pressures, load=load, options=options)


def responses(
    designs: Sequence,
    pressures: Sequence[float] | np.ndarray,
    *,
    tier: str,
    loads: Sequence[str] | None = None,
    options: Mapping[str, Any] | None = None,
) -> dict[str, ResponseBatch]:
    """The responses of many ``designs`` by ``tier``: ``{load: ResponseBatch}`` (see :func:`response`)."""
    return get(tier, parameter="tier").responses(designs, pressures, loads=loads, options=options)


for _tier in (PAPER, SECTION, SECTION_NONLINEAR, FEM, FEM_NONLINEAR):
    register(_tier)
