"""Build one design variant: the base design's TOML tables with some dotted fields replaced.

Validation comes from :func:`design.from_dict`, so an impossible combination
raises the same :class:`softcath.design.errors.DesignError` (parameter, value, bound)
a user would get from loading that design file.

Dependent fields follow the swept ones unless they are swept too:

- a coil (outer coil or channel) stays a close-wound single layer: when its
  outer or inner diameter is swept, the wire is (OD − ID)/2 and the pitch the
  wire; when its ``wire_diameter`` is swept, the OD is kept and the ID follows
  (ID = OD − 2·wire), or, if the OD is swept too, the ID follows it, or, if only
  the ID is swept with it, the OD does (OD = ID + 2·wire);
- when some but not all of the tube shape ``a, a_int, b_int, h`` are swept and
  the base leaves the shape to the nominal rule, the others take the base's
  nominal values.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from typing import Any

from softcath import design
from softcath.core.errors import DesignError

__all__ = ["check_path", "set_path", "variant_table", "build_variant", "VariantBuilder"]

_SHAPE = ("a", "a_int", "b_int", "h")
# Fields a design file may set although the base file leaves them out (defaults / nominal rules).
_OPTIONAL = {
    "coil": {"wire_diameter", "pitch", "initial_tension"},
    "channel": {"wire_diameter", "pitch", "initial_tension"},
    "tube": {"a", "a_int", "b_int", "h", "min_wall"},
}


def _known_paths(table: Mapping[str, Any], prefix: str = "") -> list[str]:
    out = []
    for k, v in table.items():
        if isinstance(v, Mapping):
            out += _known_paths(v, f"{prefix}{k}.")
        else:
            out.append(f"{prefix}{k}")
    return out


def check_path(base_table: Mapping[str, Any], path: str) -> None:
    """Raise :class:`DesignError` unless ``path`` names a field of the base design."""
    parts = path.split(".")
    node: Any = base_table
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        if isinstance(node, Mapping) and part in node:
            node = node[part]
            if last and isinstance(node, Mapping):
                raise DesignError(f"parameters.{path}", path, "names a table, not a field")
            continue
        if last and i == 1 and part in _OPTIONAL.get(parts[0], set()):
            return
        known = ", ".join(sorted(_known_paths(base_table)))
        raise DesignError(f"parameters.{path}", path, f"is not a field of the base design; known: {known}")
    if isinstance(node, Mapping):
        raise DesignError(f"parameters.{path}", path, "names a table, not a field")


def set_path(table: dict, path: str, value: Any) -> None:
    """Set ``table[a][b]…`` to ``value`` for the dotted ``path`` (tables must exist)."""
    parts = path.split(".")
    node = table
    for part in parts[:-1]:
        node = node[part]
    node[parts[-1]] = value


def _coil_rule(kw: Mapping[str, Any], base_od: float) -> dict[str, Any]:
    """Updates that keep a coil a close-wound single layer (``None``: use the default)."""
    swept = set(kw)
    out: dict[str, Any] = {}
    if not swept & {"outer_diameter", "inner_diameter", "wire_diameter"}:
        return out
    if "wire_diameter" in swept:
        w = kw["wire_diameter"]
        if isinstance(w, (int, float)) and not isinstance(w, bool):
            if "inner_diameter" not in swept:
                out["inner_diameter"] = kw.get("outer_diameter", base_od) - 2 * w
            elif "outer_diameter" not in swept and isinstance(kw["inner_diameter"], (int, float)):
                out["outer_diameter"] = kw["inner_diameter"] + 2 * w
    else:
        out["wire_diameter"] = None
    if "pitch" not in swept:
        out["pitch"] = None
    return out


def variant_table(base_table: Mapping[str, Any], overrides: Mapping[str, Any]) -> dict:
    """The TOML tables of a variant: ``base_table`` with ``overrides`` (dotted path → value) applied."""
    swept = set(overrides)
    # Copy only the top-level tables a variant changes: a sweep builds many variants.
    touched = {path.split(".")[0] for path in swept} | {"coil", "channel", "tube"}
    table = {k: (copy.deepcopy(v) if k in touched else v) for k, v in base_table.items()}
    for part in ("coil", "channel"):
        kw = {p.split(".", 1)[1]: _plain(v) for p, v in overrides.items() if p.split(".", 1)[0] == part}
        for k, v in _coil_rule(kw, table[part]["outer_diameter"]).items():
            if v is None:
                table[part].pop(k, None)
            else:
                table[part][k] = v
    shape_swept = [k for k in _SHAPE if f"tube.{k}" in swept]
    if shape_swept and len(shape_swept) < len(_SHAPE) and "a" not in table["tube"]:
        nominal = design.from_dict(base_table).tube_shape
        for k in _SHAPE:
            table["tube"].setdefault(k, nominal[k])
    for path, value in overrides.items():
        set_path(table, path, _plain(value))
    return table


def _plain(value: Any) -> Any:
    """numpy scalars → Python scalars (the design checks want real numbers)."""
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):
        return value.item()
    return value


def build_variant(base_table: Mapping[str, Any], overrides: Mapping[str, Any], *, name: str | None = None):
    """A validated :class:`design.TipDesign` for the variant (raises DesignError if impossible)."""
    table = variant_table(base_table, overrides)
    if name is not None:
        table["name"] = name
    return design.from_dict(table)


class VariantBuilder:
    """Build many variants of one base design quickly, with the same validation as :func:`build_variant`.

    Only the components a variant changes are rebuilt (``dataclasses.replace``
    reruns their checks), then the assembled :class:`~design.TipDesign` checks
    the fit. Errors carry the same dotted parameter names as
    :func:`design.from_dict` gives for the equivalent file; a test compares
    the two on valid and invalid variants.
    """

    _PARTS = ("coil", "tube", "channel", "tip")

    def __init__(self, base_table: Mapping[str, Any]) -> None:
        self.base_table = base_table
        self.base = design.from_dict(base_table)
        self._materials: dict[str, Any] = {}
        for part in ("coil", "tube", "channel"):
            self._materials[base_table[part]["material"]] = getattr(self.base, part).material
        filler_key = base_table.get("filler", {}).get("material", "none")
        if self.base.filler is not None:
            self._materials[filler_key] = self.base.filler
        self._nominal_shape = self.base.tube_shape

    def _known_material(self, key: Any, new_materials: dict[str, Any]) -> bool:
        return isinstance(key, str) and (key in new_materials or key in self._materials)

    def build(self, overrides: Mapping[str, Any], *, name: str | None = None):
        """A validated design for ``overrides`` (dotted path → value); raises DesignError if impossible."""
        from dataclasses import replace

        changes: dict[str, dict[str, Any]] = {}
        for path, value in overrides.items():
            head, _, rest = path.partition(".")
            changes.setdefault(head, {})[rest] = _plain(value)
        if set(changes) - {*self._PARTS, "materials", "filler"}:
            return build_variant(self.base_table, overrides, name=name)  # rare paths: the general route
        new_materials: dict[str, Any] = {}
        per_material: dict[str, dict[str, Any]] = {}
        for rest, value in changes.get("materials", {}).items():
            key, _, field = rest.partition(".")
            if key not in self._materials or "." in field:
                return build_variant(self.base_table, overrides, name=name)
            per_material.setdefault(key, {})[field] = tuple(value) if isinstance(value, list) else value
        # from_dict checks the materials in file order, all fields of one at once: same first error
        order = list(self.base_table.get("materials", {}))
        for key in sorted(per_material, key=lambda k: order.index(k) if k in order else len(order)):
            try:
                new_materials[key] = replace(self._materials[key], **per_material[key])
            except DesignError as exc:
                raise DesignError(f"materials.{key}.{exc.parameter}", exc.value, exc.bound) from None
        # Components using a changed material are rebuilt with it.
        parts: dict[str, Any] = {}
        for part in self._PARTS:
            comp = getattr(self.base, part)
            kw = dict(changes.get(part, {}))
            if "material" in kw:
                if not self._known_material(kw["material"], new_materials):
                    return build_variant(self.base_table, overrides, name=name)
                kw["material"] = new_materials.get(kw["material"], self._materials.get(kw["material"]))
            elif part != "tip":
                mkey = self.base_table[part]["material"]
                if mkey in new_materials:
                    kw["material"] = new_materials[mkey]
            if part in ("coil", "channel"):
                kw.update(_coil_rule(kw, comp.outer_diameter))
            if part == "tube" and any(k in kw for k in _SHAPE) and not comp.has_explicit_shape:
                for k in _SHAPE:
                    kw.setdefault(k, self._nominal_shape[k])
            if kw:
                try:
                    comp = replace(comp, **kw)
                except DesignError as exc:
                    raise DesignError(f"{part}.{exc.parameter}", exc.value, exc.bound) from None
                except TypeError as exc:
                    raise DesignError(f"{part}", kw, f"cannot be built: {exc}") from None
            parts[part] = comp
        filler = self.base.filler
        if "filler" in changes:
            ref = changes["filler"].get("material", "none")
            if ref != "none" and not self._known_material(ref, new_materials):
                return build_variant(self.base_table, overrides, name=name)
            filler = None if ref == "none" else new_materials.get(ref, self._materials.get(ref))
        elif filler is not None:
            fkey = self.base_table.get("filler", {}).get("material")
            filler = new_materials.get(fkey, filler)
        return replace(self.base, name=self.base.name if name is None else name, filler=filler, **parts)
