"""TOML load/save of designs, with errors that name the parameter.

File layout: one table per component (``[coil]``, ``[tube]``, ``[channel]``,
``[tip]``, ``[filler]``) whose ``material`` names a table under
``[materials.*]``. ``[filler] material = "none"`` leaves the coil interior void.
An optional ``[assembly]`` table holds the as-built options
(:class:`softcath.design.assembly.Assembly`); it is written only when it
differs from the default.
"""

from __future__ import annotations

import math
import re
import tomllib
from collections.abc import Mapping
from dataclasses import MISSING as _MISSING
from dataclasses import fields
from pathlib import Path
from typing import Any

from softcath.core.errors import DesignError
from softcath.design.assembly import Assembly
from softcath.design.components import Coil, Tip, Tube
from softcath.design.materials import Material
from softcath.design.tip import TipDesign

__all__ = ["from_dict", "to_dict", "load", "save", "dumps", "loads"]

_COMPONENTS = {"coil": Coil, "tube": Tube, "channel": Coil, "tip": Tip}
_TOP_KEYS = {"name", "coil", "tube", "channel", "tip", "filler", "materials", "assembly"}


def _table(path: str, value: Any) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise DesignError(path, value, "must be a table")
    return value


def _reject_unknown(path: str, table: Mapping[str, Any], allowed: set[str]) -> None:
    for key in table:
        if key not in allowed:
            prefix = f"{path}." if path else ""
            raise DesignError(
                f"{prefix}{key}", table[key], f"unknown key; allowed: {', '.join(sorted(allowed))}"
            )


def _build(path: str, cls: type, kwargs: dict[str, Any]) -> Any:
    try:
        return cls(**kwargs)
    except DesignError as exc:
        raise DesignError(f"{path}.{exc.parameter}", exc.value, exc.bound) from None


def _material(name: str, table: Mapping[str, Any]) -> Material:
    path = f"materials.{name}"
    table = _table(path, table)
    allowed = {f.name for f in fields(Material)}
    _reject_unknown(path, table, allowed)
    kwargs = dict(table)
    kwargs.setdefault("name", name)
    for req in ("youngs_modulus", "poisson_ratio"):
        if req not in kwargs:
            raise DesignError(f"{path}.{req}", None, "is required")
    if "yeoh" in kwargs and isinstance(kwargs["yeoh"], list):
        kwargs["yeoh"] = tuple(kwargs["yeoh"])
    return _build(path, Material, kwargs)


def from_dict(data: Mapping[str, Any]) -> TipDesign:
    """Build a validated :class:`TipDesign` from the TOML table structure."""
    data = _table("design", data)
    _reject_unknown("", data, _TOP_KEYS)
    raw_materials = _table("materials", data.get("materials", {}))
    materials = {str(k): _material(str(k), v) for k, v in raw_materials.items()}

    def material_ref(path: str, table: Mapping[str, Any]) -> Material:
        ref = table.get("material")
        if ref is None:
            raise DesignError(f"{path}.material", None, "is required (name of a [materials.*] table)")
        if not isinstance(ref, str) or ref not in materials:
            raise DesignError(f"{path}.material", ref, f"must name one of [materials.*]: {sorted(materials)}")
        return materials[ref]

    parts: dict[str, Any] = {}
    for key, cls in _COMPONENTS.items():
        if key not in data:
            raise DesignError(key, None, "table is required")
        table = _table(key, data[key])
        allowed = {f.name for f in fields(cls)}
        _reject_unknown(key, table, allowed)
        kwargs = dict(table)
        if "material" in allowed:
            kwargs["material"] = material_ref(key, table)
        required = [
            f.name
            for f in fields(cls)
            if f.name not in kwargs and f.default is _MISSING and f.default_factory is _MISSING
        ]
        if required:
            raise DesignError(f"{key}.{required[0]}", None, "is required")
        parts[key] = _build(key, cls, kwargs)

    filler = None
    if "filler" in data:
        table = _table("filler", data["filler"])
        _reject_unknown("filler", table, {"material"})
        if table.get("material", "none") != "none":
            filler = material_ref("filler", table)
    name = data.get("name", "design")
    if not isinstance(name, str):
        raise DesignError("name", name, "must be a string")
    assembly = Assembly.from_dict(data["assembly"]) if "assembly" in data else Assembly()
    return TipDesign(name=name, filler=filler, assembly=assembly, **parts)


def _material_key(m: Material) -> str:
    return re.sub(r"[^a-z0-9]+", "_", m.name.lower()).strip("_") or "material"


def to_dict(design: TipDesign) -> dict[str, Any]:
    """The TOML table structure of ``design`` (inverse of :func:`from_dict`)."""
    materials: dict[str, Material] = {}

    def ref(m: Material) -> str:
        key = _material_key(m)
        base, i = key, 2
        while key in materials and materials[key] != m:
            key, i = f"{base}_{i}", i + 1
        materials[key] = m
        return key

    out: dict[str, Any] = {"name": design.name}
    for key in _COMPONENTS:
        part = getattr(design, key)
        table: dict[str, Any] = {}
        for f in fields(part):
            v = getattr(part, f.name)
            if v is None:
                continue
            table[f.name] = ref(v) if isinstance(v, Material) else v
        out[key] = table
    out["filler"] = {"material": ref(design.filler) if design.filler is not None else "none"}
    out["materials"] = {
        k: {f.name: getattr(m, f.name) for f in fields(m) if getattr(m, f.name) not in (None, "")}
        for k, m in materials.items()
    }
    if not design.assembly.is_default:
        out["assembly"] = design.assembly.to_dict()
    return out


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        if not math.isfinite(v):
            raise DesignError("value", v, "must be finite to be written")
        return repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def dumps(design: TipDesign, *, header: str = "") -> str:
    """TOML text of ``design``."""
    data = to_dict(design)
    lines = [f"# {line}" for line in header.splitlines()] if header else []
    lines.append(f"name = {_toml_value(data['name'])}")
    for key in (*_COMPONENTS, "filler"):
        lines += ["", f"[{key}]"] + [f"{k} = {_toml_value(v)}" for k, v in data[key].items()]
    for mkey, table in data["materials"].items():
        lines += ["", f"[materials.{mkey}]"] + [f"{k} = {_toml_value(v)}" for k, v in table.items()]
    if "assembly" in data:
        lines += ["", "[assembly]"] + [f"{k} = {_toml_value(v)}" for k, v in data["assembly"].items()]
    return "\n".join(lines) + "\n"


def loads(text: str, *, source: str = "<string>") -> TipDesign:
    """Parse TOML text into a validated design."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise DesignError("file", source, f"is not valid TOML: {exc}") from None
    return from_dict(data)


def load(path: str | Path) -> TipDesign:
    """Load and validate a design TOML file."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise DesignError("file", str(path), "does not exist") from None
    except (IsADirectoryError, UnicodeDecodeError) as exc:
        raise DesignError("file", str(path), f"cannot be read as text: {exc}") from None
    return loads(text, source=str(path))


def save(design: TipDesign, path: str | Path, *, header: str = "") -> Path:
    """Write ``design`` as TOML (atomically: temp file, then rename)."""
    path = Path(path)
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(dumps(design, header=header), encoding="utf-8")
    tmp.replace(path)
    return path
