"""How the tip is put together: interfaces between parts, the filler as built, the base.

The paper's prototype is not one fused body: the tube is threaded through the
coil and taped at the coil's ends, the channel is dip-coated and threaded
through. :class:`Assembly` names the choices a model of the tip must make:

* each contact pair (tube-coil, tube-channel, channel-coil, filler-coil) is
  ``bonded`` (fused), ``sliding`` (frictionless contact: the normal
  displacement is shared, tangential and axial slip are free) or
  ``tied-at-tip`` (sliding along the tip, tied at the sealed distal end);
* the filler is ``full`` (every void inside the coil filled), ``coat`` (a
  layer of ``filler_coat_thickness`` on the channel, the other voids empty) or
  ``none``;
* the proximal end is ``clamped`` (every part held at the base) or
  ``tube-free`` (the tube slides freely into the catheter body at the base).

The defaults are today's model: bonded, full, clamped.

>>> from softcath.design.assembly import Assembly
>>> Assembly().is_default
True
>>> Assembly(tube_coil="sliding").with_overrides(["filler=coat"]).filler
'coat'
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping
from dataclasses import asdict, dataclass, fields, replace
from typing import Any

from softcath.core.errors import DesignError
from softcath.design.validation import positive

__all__ = ["Assembly", "INTERFACES", "INTERFACE_KINDS", "FILLERS", "PROXIMAL"]

#: The contact pairs, as (key, part, part).
INTERFACES = (
    ("tube_coil", "tube", "coil"),
    ("tube_channel", "tube", "channel"),
    ("channel_coil", "channel", "coil"),
    ("filler_coil", "filler", "coil"),
)
INTERFACE_KINDS = ("bonded", "sliding", "tied-at-tip")
FILLERS = ("full", "coat", "none")
PROXIMAL = ("clamped", "tube-free")
_ALLOWED = {**{k: INTERFACE_KINDS for k, _, _ in INTERFACES}, "filler": FILLERS, "proximal": PROXIMAL}


@dataclass(frozen=True, kw_only=True)
class Assembly:
    """The as-built options of a tip (all keyword-only; defaults = one bonded, clamped body).

    Parameters
    ----------
    tube_coil, tube_channel, channel_coil, filler_coil
        Interface kinds, each one of :data:`INTERFACE_KINDS`.
    filler
        One of :data:`FILLERS`.
    filler_coat_thickness
        Thickness of the filler coat on the channel (mm), used with ``filler = "coat"``.
    proximal
        One of :data:`PROXIMAL`.
    """

    tube_coil: str = "bonded"
    tube_channel: str = "bonded"
    channel_coil: str = "bonded"
    filler_coil: str = "bonded"
    filler: str = "full"
    filler_coat_thickness: float = 0.02  # _COAT_DEFAULT
    proximal: str = "clamped"

    def __post_init__(self) -> None:
        for key, allowed in _ALLOWED.items():
            value = getattr(self, key)
            if value not in allowed:
                raise DesignError(f"assembly.{key}", value, f"must be one of {', '.join(allowed)}")
        object.__setattr__(
            self,
            "filler_coat_thickness",
            positive("assembly.filler_coat_thickness", self.filler_coat_thickness),
        )
        if self.filler != "coat" and self.filler_coat_thickness != _COAT_DEFAULT:
            _coat_unused(self.filler, self.filler_coat_thickness)

    @property
    def is_default(self) -> bool:
        """True for the bonded, fully filled, clamped tip (today's model)."""
        return self == _default()

    def interface(self, a: str, b: str) -> str:
        """The kind of the interface between parts ``a`` and ``b`` (order free; bonded if not a pair)."""
        for key, p, q in INTERFACES:
            if {a, b} == {p, q}:
                return getattr(self, key)
        return "bonded"

    def to_dict(self) -> dict[str, Any]:
        """Plain dict (the TOML ``[assembly]`` table and the output JSON's ``assembly``)."""
        return asdict(self)

    @classmethod
    def from_dict(cls, table: Mapping[str, Any]) -> Assembly:
        """Parse an ``[assembly]`` table (unknown keys are errors naming the allowed ones)."""
        if not isinstance(table, Mapping):
            raise DesignError("assembly", table, "must be a table")
        allowed = [f.name for f in fields(cls)]
        for key, value in table.items():
            if key not in allowed:
                raise DesignError(f"assembly.{key}", value, f"unknown key; allowed: {', '.join(allowed)}")
        return cls(**dict(table))

    def with_overrides(self, items: Iterable[str]) -> Assembly:
        """A copy with ``KEY=VALUE`` strings applied (one key each; later ones win)."""
        allowed = [f.name for f in fields(self)]
        changes: dict[str, Any] = {}
        for item in items:
            key, sep, value = str(item).partition("=")
            key, value = key.strip(), value.strip()
            if not sep or key not in allowed:
                raise DesignError("assembly", item, f"must be KEY=VALUE with KEY one of {', '.join(allowed)}")
            if key == "filler_coat_thickness":
                try:
                    changes[key] = float(value)
                except ValueError:
                    raise DesignError(f"assembly.{key}", value, "must be a number (mm)") from None
            else:
                changes[key] = value
        return replace(self, **changes)


#: The coat thickness an assembly has when none is given, mm.
_COAT_DEFAULT = 0.02


def _coat_unused(filler: str, thickness) -> None:
    """Refuse a coat thickness that would have no effect (the filler is not a coat)."""
    raise DesignError(
        "assembly.filler_coat_thickness",
        thickness,
        f'has no effect with filler = "{filler}" (it sizes filler = "coat" only); '
        'remove it or set filler = "coat"',
    )


@functools.cache
def _default() -> Assembly:
    """The default assembly, made once (``is_default`` is asked for every design of a sweep)."""
    return Assembly()
