"""The catheter tip as validated, parametrised data (mm, MPa).

>>> from softcath import design
>>> d = design.preset("paper")
>>> round(d.section.b, 3)
0.15
"""

from __future__ import annotations

from pathlib import Path

from softcath.core.errors import DataError, DesignError, SoftcathError
from softcath.design import presets as _presets
from softcath.design.assembly import Assembly
from softcath.design.coil_mechanics import CoilStiffness, coil_stiffness
from softcath.design.components import Coil, Tip, Tube
from softcath.design.io import dumps, from_dict, load, loads, save, to_dict
from softcath.design.materials import Material
from softcath.design.section import AssembledSection
from softcath.design.tip import TipDesign

__all__ = [
    "AssembledSection",
    "Assembly",
    "Coil",
    "CoilStiffness",
    "DataError",
    "DesignError",
    "Material",
    "SoftcathError",
    "Tip",
    "TipDesign",
    "Tube",
    "coil_stiffness",
    "dumps",
    "from_dict",
    "load",
    "loads",
    "preset",
    "resolve",
    "save",
    "to_dict",
]


def preset(name: str = "paper") -> TipDesign:
    """A shipped design by name (``"paper"``: the paper's prototype)."""
    if name not in _presets.names():
        raise DesignError("preset", name, f"unknown; available: {', '.join(_presets.names())}")
    return loads(_presets.text(name), source=f"preset {name}")


def resolve(spec: str | Path | TipDesign) -> TipDesign:
    """A design from a preset name, a TOML path, or a design (returned as is)."""
    if isinstance(spec, TipDesign):
        return spec
    spec_s = str(spec)
    if spec_s in _presets.names():
        return preset(spec_s)
    if spec_s.endswith(".toml") or Path(spec_s).exists():
        return load(spec_s)
    raise DesignError(
        "design", spec_s, f"must be a preset ({', '.join(_presets.names())}) or a path to a .toml file"
    )


if __name__ != "softcath.design":  # the bare folder name would load a second copy of every module
    raise ImportError(
        "import softcath.design, not design: the top-level folders are rooms of the softcath package"
    )
