"""Before a search: is the chosen tier valid for the bends the objectives and constraints ask about?

The linear tiers hold to about 5 degrees of bend
(:data:`softcath.studies.model_validity.LINEAR_BEND_LIMIT_DEG`). An optimisation on one of them
whose designs bend far past it ranks them on wrong numbers (a "feasible" 107-degree best whose
finite-strain strain breaks the constraint). :func:`tier_validity` estimates, in milliseconds
and before any search, the largest bend in the ``--vary`` box at the problem's pressures with
the paper's formula under the cap load (the base design and the box's corners; a low estimate
of what any tier bends), and says when the tier is out of its range.
"""

from __future__ import annotations

import itertools

import numpy as np

from softcath.analytic import response
from softcath.design.errors import DesignError
from softcath.studies.model_validity import LINEAR_BEND_LIMIT_DEG, LINEAR_TIERS, linear_tier_warning
from softcath.studies.optimise.problem import Problem
from softcath.studies.sweep.variants import VariantBuilder

__all__ = ["tier_validity"]

#: Up to this many variables every corner of the box is tried; beyond, each variable's two ends.
_MAX_CORNER_VARIABLES = 6


def _candidates(problem: Problem) -> list[dict[str, float]]:
    ends = [(v.path, (v.low, v.high)) for v in problem.variables]
    out: list[dict[str, float]] = [{}]
    if len(ends) <= _MAX_CORNER_VARIABLES:
        out += [
            dict(zip([p for p, _ in ends], c, strict=True)) for c in itertools.product(*(e for _, e in ends))
        ]
    else:
        out += [{path: x} for path, pair in ends for x in pair]
    return out


def tier_validity(problem: Problem) -> dict:
    """Where ``problem``'s tier stands against its validity, estimated before the search.

    Returns
    -------
    dict
        ``tier``, ``linear`` (bool), ``limit_deg``; for a linear tier also
        ``estimated_max_bend_deg`` and ``at_MPa`` (the paper's formula under the cap load over
        the base design and the corners of the ``--vary`` box: a low estimate, the section
        model under the lumen load bends about 3x more) and ``warning`` (the message, or
        ``None`` inside the range).
    """
    out: dict = {
        "tier": problem.model,
        "linear": problem.model in LINEAR_TIERS,
        "limit_deg": LINEAR_BEND_LIMIT_DEG,
    }
    if not out["linear"]:
        return out

    p = np.asarray(problem.pressures, float)
    builder = VariantBuilder(problem.base_table)
    best, at = 0.0, float(p.max()) if p.size else 0.0
    for params in _candidates(problem):
        try:
            d = builder.build(params)
        except DesignError:
            continue  # an impossible corner: the search refuses it too
        # the formula under the cap load: under the lumen load it bends almost nothing (it has no
        # lumen-wall bending), while every tier bends at least about as much as it does under the cap
        theta = np.degrees(np.abs(np.atleast_1d(response(d, p, load="cap").bend_angle)))
        if theta.size and np.nanmax(theta) > best:
            best, at = float(np.nanmax(theta)), float(p[int(np.nanargmax(theta))])
    out["estimated_max_bend_deg"], out["at_MPa"] = best, at
    out["warning"] = linear_tier_warning(
        problem.model,
        best,
        at,
        how="designs in the --vary box (estimated before the search by the paper's formula, cap load, "
        "a low estimate)",
        way_out="its objectives and constraints are judged past its validity: give --model section-nonlinear "
        "to search on the finite-strain tier",
    )
    return out
