"""The numbers a designer asks for, each labelled with its tier, load and unit.

Per tier: the pressure for a 90° bend; at the chosen pressure, the bend angle,
curvature, elongation and largest silicone strain; and the validity warnings
of the linear tiers (:func:`softcath.studies.model_validity.linear_range_warnings`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from softcath.studies.app.curves import LOAD_NOTE, TierCurve, pressure_for_angle
from softcath.studies.model_validity import linear_range_warnings
from softcath.studies.tiers import TIERS

__all__ = ["NumberRow", "design_numbers", "validity_warnings"]


@dataclass(frozen=True)
class NumberRow:
    """One number on the page: ``quantity`` by ``tier`` under ``load`` is ``value`` ``unit``.

    ``value`` is NaN where the tier has no answer (``note`` says why).
    """

    quantity: str
    tier: str
    load: str
    value: float
    unit: str
    note: str = ""

    def text(self) -> str:
        """The value as the page prints it (4 significant digits, or the note)."""
        return self.note if not math.isfinite(self.value) else f"{self.value:.4g}"


def design_numbers(curves: Sequence[TierCurve], pressure: float) -> list[NumberRow]:
    """The rows for ``curves`` at ``pressure`` [MPa], grouped by quantity."""
    rows: list[NumberRow] = []
    for c in curves:
        tier, load = TIERS[c.tier].label, LOAD_NOTE[c.tier]
        p90 = pressure_for_angle(c, math.pi / 2)
        beyond = c.gains is None and not math.isfinite(p90)
        note = f"beyond {c.pressure_MPa[-1]:.3g} MPa" if beyond and c.pressure_MPa.size else "never"
        rows.append(NumberRow("pressure for a 90° bend", tier, load, p90, "MPa", note))
    for quantity, column, unit, scale in (
        ("bend angle", "bend_angle_rad", "°", 180 / math.pi),
        ("curvature κ", "curvature_per_mm", "1/mm", 1.0),
        ("elongation ε", "elongation", "-", 1.0),
        ("max silicone strain", "max_strain", "-", 1.0),
    ):
        for c in curves:
            tier, load = TIERS[c.tier].label, LOAD_NOTE[c.tier]
            value = c.at(pressure, column) * scale
            if getattr(c, column) is None:
                note = "not given by this tier"
            else:
                note = "not computed at this pressure"
            rows.append(NumberRow(f"{quantity} at {pressure:g} MPa", tier, load, value, unit, note))
    return rows


def validity_warnings(curves: Sequence[TierCurve], pressure: float) -> list[str]:
    """Where a linear tier leaves its validity at ``pressure`` [MPa] (one line each, tier named)."""
    out: list[str] = []
    for c in curves:
        if c.gains is None:  # the finite-strain tier holds at large bends
            if c.message:
                out.append(f"{TIERS[c.tier].label}: {c.message}")
            continue
        strain = None if c.max_strain is None else c.at(pressure, "max_strain")
        out += [
            f"{TIERS[c.tier].label} ({c.load} load): {msg}"
            for msg in linear_range_warnings(
                [pressure],
                [c.at(pressure, "bend_angle_rad")],
                max_strain=strain,
                elongation=[c.at(pressure, "elongation")],
                model=TIERS[c.tier].label,
            )
        ]
    return out
