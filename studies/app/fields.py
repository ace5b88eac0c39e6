"""The app's inputs: every design field a sweep can vary, by its dotted path, grouped as the design file.

The paths are those of sweep specs (``tube.h``,
``materials.medical_silicone_tubing.youngs_modulus``, ``assembly.filler``), so a
value typed in the app and a value swept by ``softcath sweep`` reach the design
through the same code (:func:`softcath.studies.sweep.variants.build_variant`).

>>> from softcath import design
>>> fields = design_fields(design.to_dict(design.preset("paper")))
>>> [f.path for f in fields if f.group == "tip"]
['tip.bending_length', 'tip.cap_thickness']
>>> next(f for f in fields if f.path == "tube.h").unit
'mm'
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from softcath.design.assembly import FILLERS, INTERFACE_KINDS, INTERFACES, PROXIMAL
from softcath.design.io import to_dict

__all__ = ["Field", "design_fields", "field_value"]

_COIL = (
    ("outer_diameter", "outer diameter", "mm"),
    ("inner_diameter", "inner diameter", "mm"),
    ("wire_diameter", "wire diameter", "mm"),
    ("pitch", "pitch", "mm"),
    ("initial_tension", "initial tension", "N"),
)
_TUBE = (
    ("catalogue_outer_diameter", "catalogue outer diameter", "mm"),
    ("catalogue_inner_diameter", "catalogue inner diameter", "mm"),
    ("min_wall", "smallest wall", "mm"),
    ("a", "as assembled: outer semi-axis a", "mm"),
    ("a_int", "as assembled: lumen semi-axis a_int", "mm"),
    ("b_int", "as assembled: lumen semi-axis b_int", "mm"),
    ("h", "as assembled: lumen offset h", "mm"),
)
_TIP = (("bending_length", "bending length L0", "mm"), ("cap_thickness", "cap thickness", "mm"))
_MATERIAL = (("youngs_modulus", "Young's modulus E", "MPa"), ("poisson_ratio", "Poisson ratio ν", "-"))


@dataclass(frozen=True)
class Field:
    """One input of the app.

    Attributes
    ----------
    path
        Dotted design path (as in a sweep spec).
    group
        The design file's table it belongs to (``coil``, ``materials.ecoflex_00_30``, ``assembly``).
    label
        What the input is called beside its box.
    unit
        Its unit (``mm``, ``MPa``, ``N``, ``-``), empty for a choice.
    choices
        The allowed values of a choice (empty for a number).
    """

    path: str
    group: str
    label: str
    unit: str
    choices: tuple[str, ...] = ()

    @property
    def is_choice(self) -> bool:
        return bool(self.choices)


def design_fields(table: Mapping[str, Any]) -> tuple[Field, ...]:
    """The inputs of a design given as its TOML tables (``design.to_dict``), in the file's order."""
    out: list[Field] = []
    for part, label in (("coil", "coil"), ("tube", "tube"), ("channel", "channel")):
        rows = _TUBE if part == "tube" else _COIL
        out += [Field(f"{part}.{k}", label, name, unit) for k, name, unit in rows]
    out += [Field(f"tip.{k}", "tip", name, unit) for k, name, unit in _TIP]
    materials = tuple(table.get("materials", {}))
    out.append(Field("filler.material", "filler", "filler material", "", ("none", *materials)))
    for key in materials:
        out += [Field(f"materials.{key}.{k}", f"materials.{key}", name, unit) for k, name, unit in _MATERIAL]
    for key, a, b in INTERFACES:
        out.append(Field(f"assembly.{key}", "assembly", f"{a}-{b} interface", "", INTERFACE_KINDS))
    out.append(Field("assembly.filler", "assembly", "filler as built", "", FILLERS))
    out.append(Field("assembly.filler_coat_thickness", "assembly", "filler coat thickness", "mm"))
    out.append(Field("assembly.proximal", "assembly", "proximal end", "", PROXIMAL))
    return tuple(out)


def field_value(design, path: str, table: Mapping[str, Any] | None = None) -> Any:
    """The value ``design`` has at ``path``: from its TOML tables (``table``, else
    ``design.to_dict(design)``), the nominal shape's numbers for a tube shape the file leaves
    out, the default assembly's for an ``[assembly]`` it leaves out; ``None`` if it has none."""
    head, _, rest = path.partition(".")
    if head == "tube" and rest in ("a", "a_int", "b_int", "h"):
        return float(design.tube_shape[rest])
    if head == "assembly":
        return getattr(design.assembly, rest)
    node: Any = to_dict(design) if table is None else table
    for part in path.split("."):
        if not isinstance(node, Mapping) or part not in node:
            return None
        node = node[part]
    return node
