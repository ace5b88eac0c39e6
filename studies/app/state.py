"""The app's design state: a base design, the values typed so far, the last valid design.

A value is applied the way a sweep applies one (the base design's TOML tables
with dotted paths replaced, then the full validation of a design file:
:func:`softcath.studies.sweep.variants.build_variant`). A refused value leaves
the last valid design in place and is kept as its one-line message beside
its input.

>>> s = initial_state("paper")
>>> s = apply_value(s, "tube.catalogue_inner_diameter", 0.7)
>>> s.errors["tube.catalogue_inner_diameter"]
'tube.catalogue_inner_diameter = 0.7: must be < catalogue_outer_diameter = 0.6'
>>> s.design.tube.catalogue_inner_diameter, s.version
(0.3, 0)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from softcath import design as design_pkg
from softcath.core.errors import DesignError
from softcath.design.tip import TipDesign
from softcath.studies.app.fields import Field, design_fields
from softcath.studies.sweep.variants import build_variant

__all__ = ["AppState", "apply_value", "initial_state"]


@dataclass(frozen=True)
class AppState:
    """What the app shows as the design (immutable: every change makes a new state).

    Attributes
    ----------
    base_table
        The starting design's TOML tables (``design.to_dict``, with an ``[assembly]`` table).
    overrides
        Dotted path -> value of every accepted change, applied to ``base_table``.
    design
        The last valid design (``base_table`` with ``overrides``).
    errors
        Dotted path -> the validator's one-line message for a value that was refused.
    version
        Counts accepted changes (0: the starting design).
    """

    base_table: Mapping[str, Any]
    overrides: Mapping[str, Any]
    design: TipDesign
    errors: Mapping[str, str] = field(default_factory=dict)
    version: int = 0

    @property
    def fields(self) -> tuple[Field, ...]:
        """The inputs of this design (:func:`~softcath.studies.app.fields.design_fields`)."""
        return design_fields(self.base_table)


def initial_state(spec: str | Path | TipDesign) -> AppState:
    """The state of a design given as a preset name, a TOML path or a :class:`TipDesign`.

    Raises
    ------
    DesignError
        ``spec`` is no preset, no readable design file, or an impossible design.
    """
    d = design_pkg.resolve(spec)
    table = design_pkg.to_dict(d)
    table.setdefault("assembly", d.assembly.to_dict())  # so assembly.* paths have a table to land in
    return AppState(base_table=table, overrides={}, design=d)


def _checked(f: Field, value: Any) -> Any:
    """``value`` as the design wants it: a choice's string, else a finite float."""
    if f.is_choice:
        if value not in f.choices:
            raise DesignError(f.path, value, f"must be one of {', '.join(f.choices)}")
        return value
    if isinstance(value, bool) or value is None:
        raise DesignError(f.path, value, f"must be a number ({f.unit})")
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise DesignError(f.path, value, f"must be a number ({f.unit})") from None
    if not math.isfinite(number):
        raise DesignError(f.path, number, "must be finite")
    return number


def apply_value(state: AppState, path: str, value: Any) -> AppState:
    """``state`` with ``path`` set to ``value``; a refused value keeps the design and records why.

    Parameters
    ----------
    state
        The current state.
    path
        A dotted design path among ``state.fields``.
    value
        The typed value (a number, or one of the field's choices).

    Raises
    ------
    DesignError
        ``path`` is no input of the app (a programming error, not a typed value).
    """
    f = next((f for f in state.fields if f.path == path), None)
    if f is None:
        raise DesignError(
            "path", path, f"is not an input of the app; one of {len(state.fields)} design paths"
        )
    try:
        overrides = {**state.overrides, path: _checked(f, value)}
        d = build_variant(state.base_table, overrides, name=state.design.name)
    except DesignError as exc:
        return replace(state, errors={**state.errors, path: " ".join(str(exc).split())})
    errors = {k: v for k, v in state.errors.items() if k != path}
    return replace(state, overrides=overrides, design=d, errors=errors, version=state.version + 1)
