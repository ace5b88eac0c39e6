"""The model tiers behind one interface: every tier answers a design with a ``TipResponse``.

The result type, :class:`~softcath.core.response.TipResponse`, stands on the ground floor;
it is importable from here as ``softcath.models.TipResponse``.

Five tiers, from the cheapest to the most expensive: ``paper`` (the paper's formula),
``section`` (the linear section model), ``section-nonlinear`` (the finite-strain section
model), ``fem`` (the 3-D linear FEM) and ``fem-nonlinear`` (the 3-D finite-strain FEM).
Each is a :class:`Tier` in the registry, with its capabilities (loads, options, the bend it
is valid to, whether it models an as-built assembly) and two methods, ``response`` for one
design and ``responses`` for many (vectorised or batched where the tier can be).

The consumers (sweeps, selection, optimisation, prediction bands, the discrepancy
workflows) ask the registry for a tier and read its capabilities; none compares a tier's
name. A new option of a tier is one entry of its ``options`` (name -> default; its values
checked by ``option_choices`` or ``option_bounds``), which its ``_solve`` passes on; a new
tier is one :class:`Tier` subclass implementing ``_solve`` (one module) and one
:func:`register` call, plus its sweep columns if sweeps are to store it
(:data:`softcath.studies.sweep.results.TIER_COLUMNS`).

>>> from softcath import design, models
>>> r = models.response(design.preset("paper"), [0.1], tier="paper", load="cap")
>>> r.tier, r.load, r.curvature_per_mm.shape
('paper', 'cap', (1,))
>>> models.get("fem").options["mesh_size"]
0.16
"""

from __future__ import annotations

# The deprecated stand-in of the moved module ``softcath.models.response`` loads first: importing a
# submodule sets the package's attribute of its name, and the function ``response`` below must win
# (a later ``import softcath.models.response`` finds it loaded and leaves the attribute alone).
import softcath.models.response  # noqa: F401
from softcath.core.response import OBSERVABLES, ResponseBatch, TipResponse
from softcath.models.options import check_tier_options, coerce_option, options_of, parse_tier_options
from softcath.models.registry import (
    ALIASES,
    TIERS,
    get,
    linear_names,
    names,
    register,
    registered,
    response,
    responses,
    tier_name,
    tiers,
    unregister,
)
from softcath.models.tier import LOADS, OptionBound, Tier
from softcath.models.validity import LINEAR_BEND_LIMIT_DEG, SELF_CONTACT_DEG

__all__ = [
    "ALIASES",
    "LINEAR_BEND_LIMIT_DEG",
    "LOADS",
    "OBSERVABLES",
    "OptionBound",
    "ResponseBatch",
    "SELF_CONTACT_DEG",
    "TIERS",
    "Tier",
    "TipResponse",
    "check_tier_options",
    "coerce_option",
    "get",
    "linear_names",
    "names",
    "options_of",
    "parse_tier_options",
    "register",
    "registered",
    "response",
    "responses",
    "tier_name",
    "tiers",
    "unregister",
]

if __name__ != "softcath.models":  # the bare folder name would load a second copy of every module
    raise ImportError(
        "import softcath.models, not models: the top-level folders are rooms of the softcath package"
    )
