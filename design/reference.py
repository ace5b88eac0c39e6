"""The design file's reference page (``docs/design-file.md``), generated from the dataclasses.

Every field of every table is listed with its unit, its bound and its default. The
fields and defaults come from the dataclasses themselves, the numeric limits from
:mod:`softcath.design.validation`, the allowed words from :mod:`softcath.design.assembly`;
only the unit, bound wording and meaning are written here, one entry per field. A test
checks that every dataclass field has an entry (and no entry lacks a field), that the
bounds listed here are the ones the validator enforces, and that the committed page is
this module's output, so the page cannot drift from the code.

Regenerate the page with ``python -m softcath.design.reference docs/design-file.md``.
"""

from __future__ import annotations

import sys
from dataclasses import MISSING, dataclass, fields
from pathlib import Path

from softcath.design import validation as v
from softcath.design.assembly import FILLERS, INTERFACE_KINDS, PROXIMAL, Assembly
from softcath.design.components import Coil, Tip, Tube
from softcath.design.materials import Material

__all__ = ["FieldDoc", "TABLES", "FIELD_DOCS", "design_file_reference", "unit_of", "with_unit"]


@dataclass(frozen=True)
class FieldDoc:
    """One field of the design file.

    Attributes
    ----------
    unit
        Its unit (``mm``, ``MPa``, ``N``) or ``-`` for a word or a number without unit.
    bound
        What the validator requires of it.
    meaning
        What it is, in a few words.
    """

    unit: str
    bound: str
    meaning: str


def _words(values: tuple[str, ...]) -> str:
    return "one of " + ", ".join(f"`{x}`" for x in values)


_COIL = {
    "outer_diameter": FieldDoc("mm", f"> 0, <= {v.MAX_COIL_DIAMETER_MM:g} (36 Fr)", "coil OD"),
    "inner_diameter": FieldDoc("mm", "> 0, < `outer_diameter`", "coil ID"),
    "material": FieldDoc("-", "names a `[materials.*]` table", "the wire material"),
    "wire_diameter": FieldDoc(
        "mm",
        "= (`outer_diameter` - `inner_diameter`)/2 (one layer of round wire); spring index "
        f"(OD + ID)/2 / wire <= {v.MAX_SPRING_INDEX:g}",
        "wire diameter d",
    ),
    "pitch": FieldDoc(
        "mm",
        ">= `wire_diameter`, <= pi x mean diameter (helix angle <= 45 deg)",
        "axial distance between turns",
    ),
    "initial_tension": FieldDoc(
        "N",
        "finite, >= 0; 0 unless close-wound (`pitch` = `wire_diameter`); wound-in stress "
        f"8 F0 D/(pi d^3) <= {v.MAX_INITIAL_STRESS_OVER_E:g} E of the wire",
        "force before the turns separate",
    ),
}

#: Every table of the design file: (TOML header, dataclass or None, what it is).
TABLES: tuple[tuple[str, type | None, str], ...] = (
    ("[coil]", Coil, "the outer helical coil (homogenised as an annulus on the axis)"),
    ("[tube]", Tube, "the silicone actuation tube, as catalogued and as squeezed into the coil"),
    ("[channel]", Coil, "the hollow-channel coil (delivery lumen), tangent to the coil ID at the bottom"),
    ("[tip]", Tip, "the bending segment"),
    ("[filler]", None, "the silicone filling the space inside the coil (optional)"),
    ("[materials.NAME]", Material, "one isotropic material, referred to by NAME"),
    ("[assembly]", Assembly, "how the parts are put together (optional; written only when not the default)"),
)

#: Per dataclass: field name -> its documentation.
FIELD_DOCS: dict[type, dict[str, FieldDoc]] = {
    Coil: _COIL,
    Tube: {
        "catalogue_outer_diameter": FieldDoc("mm", "> 0", "free-tube OD"),
        "catalogue_inner_diameter": FieldDoc("mm", "> 0, < `catalogue_outer_diameter`", "free-tube ID"),
        "material": FieldDoc("-", "names a `[materials.*]` table", "the tube silicone"),
        "a": FieldDoc(
            "mm",
            "> 0, <= sqrt(coil ID/2 x b); all of `a`, `a_int`, `b_int`, `h` or none",
            "as-assembled outer horizontal semi-axis (none: the nominal rule)",
        ),
        "a_int": FieldDoc("mm", "> 0, <= `a` - `min_wall`", "lumen horizontal semi-axis"),
        "b_int": FieldDoc("mm", "> 0, <= b - `min_wall`", "lumen vertical semi-axis"),
        "h": FieldDoc(
            "mm",
            "finite, abs(`h`) <= b - `min_wall` - `b_int`",
            "lumen-centre offset from the outer-ellipse centre (+y toward the coil wall)",
        ),
        "min_wall": FieldDoc(
            "mm", "> 0; b = (coil ID - channel OD)/2 must exceed it", "thinnest wall allowed"
        ),
    },
    Tip: {
        "bending_length": FieldDoc(
            "mm", f"> 0, <= {v.MAX_BENDING_LENGTH_MM:g}", "free length L0 from the clamp to the tip end"
        ),
        "cap_thickness": FieldDoc("mm", "> 0, < `bending_length`/2", "axial length of the sealed tube end"),
    },
    Material: {
        "name": FieldDoc("-", "non-empty text", "label in reports"),
        "youngs_modulus": FieldDoc("MPa", "> 0", "small-strain Young's modulus E"),
        "poisson_ratio": FieldDoc("-", "in (-1, 0.5)", "Poisson's ratio"),
        "yeoh": FieldDoc("MPa", "three numbers [C1, C2, C3], C1 > 0", "Yeoh coefficients for finite strain"),
        "source": FieldDoc("-", "text", "where the numbers come from"),
    },
    Assembly: {
        "tube_coil": FieldDoc("-", _words(INTERFACE_KINDS), "tube-coil interface"),
        "tube_channel": FieldDoc("-", _words(INTERFACE_KINDS), "tube-channel interface"),
        "channel_coil": FieldDoc("-", _words(INTERFACE_KINDS), "channel-coil interface"),
        "filler_coil": FieldDoc("-", _words(INTERFACE_KINDS), "filler-coil interface"),
        "filler": FieldDoc("-", _words(FILLERS), "the filler as built"),
        "filler_coat_thickness": FieldDoc(
            "mm",
            '> 0, < coil ID - channel OD; only with `filler = "coat"`',
            "thickness of the filler coat on the channel",
        ),
        "proximal": FieldDoc("-", _words(PROXIMAL), "how the base is held"),
    },
}


_PART_CLASSES = {"coil": Coil, "channel": Coil, "tube": Tube, "tip": Tip, "assembly": Assembly}


def unit_of(path: str) -> str:
    """The unit of a dotted design path (``tube.h`` -> ``mm``), ``-`` for none, ``""`` if unknown.

    >>> unit_of("tube.h"), unit_of("materials.ecoflex_00_30.youngs_modulus"), unit_of("assembly.filler")
    ('mm', 'MPa', '-')
    """
    head, _, rest = str(path).partition(".")
    if head == "materials":
        cls, name = Material, rest.partition(".")[2]
    else:
        cls, name = _PART_CLASSES.get(head), rest
    doc = FIELD_DOCS.get(cls, {}).get(name) if cls is not None else None
    return doc.unit if doc is not None else ""


#: Units of result columns whose name does not say it (dimensionless ones as such).
_COLUMN_UNITS = {"elongation": "-", "max_strain": "-"}


def with_unit(name: str) -> str:
    """``name`` with its unit for an axis or a column head: ``tube.h [mm]``, ``elongation [-]``.

    A name that carries its unit (``bend_angle_deg``, ``curvature_per_mm``) or has none known is
    returned as it is.
    """
    unit = unit_of(name) or _COLUMN_UNITS.get(name.split(" at ")[0].split()[-1] if name.split() else name, "")
    return f"{name} [{unit}]" if unit else name


def _power(x: float) -> str:
    """``1e9``, ``1e-9``: a limit as the power of ten it is."""
    mantissa, _, exponent = f"{x:.0e}".partition("e")
    return f"{mantissa}e{int(exponent)}"


#: Defaults the file loader supplies where the dataclass has none.
_LOADER_DEFAULTS = {(Material, "name"): "the table's NAME"}


def _default(cls: type, name: str) -> str:
    if (cls, name) in _LOADER_DEFAULTS:
        return _LOADER_DEFAULTS[cls, name]
    f = next(f for f in fields(cls) if f.name == name)
    if f.default is not MISSING:
        value = f.default
    elif f.default_factory is not MISSING:
        value = f.default_factory()
    else:
        return "required"
    if value is None:
        return {"wire_diameter": "(OD - ID)/2", "pitch": "`wire_diameter`"}.get(name, "none")
    if value == "":
        return '""'
    return f"`{value}`" if isinstance(value, str) else f"{value:g}"


def _rows(cls: type) -> list[str]:
    docs = FIELD_DOCS[cls]
    out = ["| field | unit | bound | default | meaning |", "|---|---|---|---|---|"]
    for f in fields(cls):
        d = docs[f.name]
        out.append(f"| `{f.name}` | {d.unit} | {d.bound} | {_default(cls, f.name)} | {d.meaning} |")
    return out


def design_file_reference() -> str:
    """The Markdown text of ``docs/design-file.md``."""
    lines = [
        "# The design file",
        "",
        "<!-- Generated by softcath.design.reference; do not edit: run",
        "     python -m softcath.design.reference docs/design-file.md -->",
        "",
        "A design is a TOML file with one table per part; `softcath design show paper --toml` prints the",
        "paper's prototype as one. Every command that takes DESIGN takes such a file, and `softcath select`",
        "writes its chosen designs as such files. Loading a file checks every field below and refuses",
        "the first that breaks its bound in one line, `softcath CMD: error: TABLE.FIELD = VALUE: bound`;",
        "an unknown key is refused with the allowed ones.",
        "",
        "Lengths are mm, forces N, moduli MPa. Every number must be finite and at most "
        f"{_power(v.MAX_MAGNITUDE)} in magnitude;",
        f"a number that must be > 0 must also be >= {_power(v.MIN_POSITIVE)}.",
        "b = (coil `inner_diameter` - channel `outer_diameter`)/2 is the half-height left for the tube.",
        "",
        "## Top level",
        "",
        "| field | unit | bound | default | meaning |",
        "|---|---|---|---|---|",
        "| `name` | - | text | `design` | a label for reports |",
    ]
    for header, cls, what in TABLES:
        lines += ["", f"## `{header}`", "", what[0].upper() + what[1:] + ".", ""]
        if cls is None:
            lines += [
                "| field | unit | bound | default | meaning |",
                "|---|---|---|---|---|",
                '| `material` | - | names a `[materials.*]` table, or `"none"` | `"none"` (void) '
                "| the filler material |",
            ]
        else:
            lines += _rows(cls)
    lines += [
        "",
        "## How the parts fit",
        "",
        "- The tube is squeezed beside the channel inside the coil: a catalogue tube wider than the",
        "  room (`catalogue_outer_diameter` + channel `outer_diameter` > coil `inner_diameter`) is valid,",
        "  and `softcath design validate` notes that it is squeezed to fit.",
        "- Without `a`, `a_int`, `b_int`, `h` the as-assembled shape follows the nominal rule (the outer",
        "  ellipse fills the width, the lumen keeps the catalogue ratio); `softcath design show` prints it.",
        '- `[assembly] filler = "coat"` needs a `[filler]` material.',
    ]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":  # pragma: no cover - the page's regeneration command
    target = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("docs/design-file.md")
    target.write_text(design_file_reference(), encoding="utf-8")
