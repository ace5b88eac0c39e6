"""The model tiers' names, for the studies: a re-export of :mod:`softcath.models`.

The registry, the tiers' capabilities and their one way of answering live in
:mod:`softcath.models`; this module keeps the names the studies and stored code import
(:data:`TIERS`, :func:`tier`, :func:`tier_name`, :func:`tier_names`, :func:`check_assembly`).
The results columns keep their stems (``curvature_analytic_per_mm``,
``nonlinear_curvature_per_mm``): they are a file format, see :attr:`Tier.column_stem`.
"""

from __future__ import annotations

from softcath.models import ALIASES, TIERS, get, names, tier_name
from softcath.models import Tier as Tier  # importable here, documented once in softcath.models

__all__ = ["TIERS", "ALIASES", "ASSEMBLY_TIERS", "check_assembly", "tier", "tier_name", "tier_names"]

#: The tiers that model an as-built ``[assembly]`` (:attr:`Tier.as_built`); every other tier is one
#: bonded body and answers only the default assembly.
ASSEMBLY_TIERS = tuple(t.name for t in TIERS.values() if t.as_built)

#: The :class:`Tier` called ``name`` (see :func:`softcath.models.get`).
tier = get


def tier_names(*, exclude=()) -> tuple[str, ...]:
    """The tiers' names in order, without those in ``exclude`` (see :func:`softcath.models.names`)."""
    return names(exclude=exclude)


def check_assembly(name: str, assembly, *, parameter: str = "assembly") -> None:
    """Refuse a tier that would answer an as-built design with its bonded model.

    See :meth:`softcath.models.Tier.check_assembly`; ``name`` is the tier's name.
    """
    TIERS[name].check_assembly(assembly, parameter=parameter)
