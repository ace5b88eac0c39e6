"""The model tiers: one name each, everywhere.

The same five strings name a tier in sweep specs (``evaluators``), on the
command line (``--model``, ``--compare``), in JSON outputs and in reports:

=====================  =========================================================
``paper``              the paper's formula (eq. 7, composite beam)
``section``            the linear section model (2-D generalised plane strain)
``section-nonlinear``  the finite-strain section model
``fem``                the 3-D linear FEM
``fem-nonlinear``      the 3-D finite-strain FEM
=====================  =========================================================

Older spellings (``analytic`` for ``paper``, ``nonlinear`` for
``fem-nonlinear``) are still accepted: :func:`tier` maps them to the new name
and logs a deprecation warning. The results columns keep their stems
(``curvature_analytic_per_mm``, ``nonlinear_curvature_per_mm``): they are a file format,
see :attr:`Tier.column_stem`.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable
from dataclasses import dataclass

from softcath.design.errors import DesignError

__all__ = ["Tier", "TIERS", "ALIASES", "ASSEMBLY_TIERS", "check_assembly", "tier", "tier_name", "tier_names"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Tier:
    """One model tier.

    Attributes
    ----------
    name
        The tier's one name (sweep evaluators, ``--model``, JSON).
    label
        Noun phrase for prose, e.g. ``"the paper's formula"``.
    short_label
        Legend label for plots, e.g. ``"paper's formula (eq. 7)"``.
    description
        One line: what the tier computes and what it costs.
    column_stem
        The word that marks the tier's columns in sweep results
        (``curvature_analytic_per_mm``, ``nonlinear_curvature_per_mm``), kept from
        earlier versions so stored sweeps still read and resume.
    """

    name: str
    label: str
    short_label: str
    description: str
    column_stem: str


#: Name -> tier, from the cheapest to the most expensive.
TIERS: dict[str, Tier] = {
    t.name: t
    for t in (
        Tier(
            "paper",
            "the paper's formula",
            "paper's formula (eq. 7)",
            "composite-beam formula of the paper (eq. 7): microseconds a design",
            "analytic",
        ),
        Tier(
            "section",
            "the section model",
            "section model (2-D GPS)",
            "linear 2-D generalised-plane-strain section model: 3-D-FEM-grade curvature, ~0.2 s a design",
            "section",
        ),
        Tier(
            "section-nonlinear",
            "the finite-strain section model",
            "finite-strain section model",
            "finite-strain section model: valid at large bends, ~1 s a design and load",
            "section_nonlinear",
        ),
        Tier("fem", "the 3-D FEM", "3-D linear FEM", "3-D linear FEM of the tip: minutes a design", "fem"),
        Tier(
            "fem-nonlinear",
            "the 3-D finite-strain FEM",
            "3-D finite-strain FEM",
            "3-D finite-strain FEM, hyperelastic silicone: the slowest tier",
            "nonlinear",
        ),
    )
}

#: Old spellings -> the tier's name (accepted with a deprecation warning in the log).
ALIASES: dict[str, str] = {"analytic": "paper", "nonlinear": "fem-nonlinear"}


def tier(name: str, *, parameter: str = "model", allowed: Iterable[str] | None = None) -> Tier:
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
    names = tuple(TIERS) if allowed is None else tuple(allowed)
    key = name
    if isinstance(name, str) and name in ALIASES:
        key = ALIASES[name]
        log.warning("%s %r is deprecated: use %r (the same model)", parameter, name, key)
    if not isinstance(key, str) or key not in names:
        raise DesignError(parameter, name, f"must be one of {', '.join(names)}")
    return TIERS[key]


def tier_name(name: str, *, parameter: str = "model", allowed: Iterable[str] | None = None) -> str:
    """The tier's one name for ``name`` (see :func:`tier`)."""
    return tier(name, parameter=parameter, allowed=allowed).name


def tier_names(*, exclude: Iterable[str] = ()) -> tuple[str, ...]:
    """The tiers' names in order, without those in ``exclude`` (e.g. for a command's choices)."""
    skip = set(exclude)
    return tuple(n for n in TIERS if n not in skip)


#: The tiers that model an as-built ``[assembly]`` (sliding or tied interfaces, a coat or no filler,
#: a free tube base); every other tier is one bonded body and answers only the default assembly.
ASSEMBLY_TIERS = ("section", "fem")


def check_assembly(name: str, assembly, *, parameter: str = "assembly") -> None:
    """Refuse a tier that would answer an as-built design with its bonded model.

    Parameters
    ----------
    name
        The tier's name.
    assembly
        The design's :class:`~softcath.design.assembly.Assembly` (or its ``[assembly]`` table).
    parameter
        How the caller names the assembly (``assembly``, ``--assembly``).

    Raises
    ------
    DesignError
        Naming ``parameter`` with the options that differ from the bonded tip and the tiers
        that model them.
    """
    from softcath.design.assembly import Assembly

    a = assembly if isinstance(assembly, Assembly) else Assembly.from_dict(assembly or {})
    if a.is_default or name in ASSEMBLY_TIERS:
        return
    if name == "fem-nonlinear":
        from softcath.fem.api import check_assembly as fem_nonlinear_takes

        fem_nonlinear_takes(a)
        return
    base = Assembly()
    changed = {k: v for k, v in a.to_dict().items() if getattr(base, k) != v}
    raise DesignError(
        parameter,
        changed,
        f"is modelled by {' and '.join(TIERS[t].label for t in ASSEMBLY_TIERS)} only "
        f"({TIERS[name].label} is one bonded body and would answer another tip); use --model section",
    )
