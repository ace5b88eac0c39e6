"""Uncertain parameters: dotted design paths (or model options) with a range and its source.

A range is either numeric (``low``..``high``, sampled uniformly, or
log-uniformly in 0.5 − ν with ``scale = "nu-log"``) or categorical
(``levels``, equally likely). Paths are the sweep specs' dotted paths into the
base design's TOML tables (``materials.medical_silicone_tubing.youngs_modulus``,
``tube.b_int``, ``tip.cap_thickness``); ``model.coil_modulus`` and
``model.coil_bending`` are options of the section and 3-D FEM tiers.

Ranges files (``ranges_<preset>.toml`` beside this module) hold one table per
path with ``source`` (where the range comes from) and ``default`` (varied when
no ``--vary`` is given)::

    [ranges."materials.medical_silicone_tubing.youngs_modulus"]
    low = 1.648
    high = 4.43
    source = "..."
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from softcath import design
from softcath.design import presets
from softcath.design.errors import DesignError
from softcath.studies.sweep.variants import build_variant, check_path

__all__ = [
    "MODEL_OPTIONS",
    "SCALES",
    "Range",
    "base_table",
    "check_ranges",
    "chosen_ranges",
    "default_ranges",
    "load_ranges",
    "parse_vary",
]

#: Model options a range may set (path -> allowed levels).
MODEL_OPTIONS: dict[str, tuple[str, ...]] = {
    "model.coil_modulus": ("tension", "bending"),
    "model.coil_bending": ("annulus", "wahl"),
}
#: ``uniform`` in the value; ``nu-log``: log-uniform in 0.5 − value (a Poisson ratio near 0.5,
#: so that the bulk-to-shear ratio spreads evenly over its decades).
SCALES = ("uniform", "nu-log")
#: Highest Poisson ratio a range may reach (the section model's locking-free limit is 0.49999).
NU_MAX = 0.4999
_HERE = Path(__file__).parent


@dataclass(frozen=True)
class Range:
    """One uncertain parameter.

    Attributes
    ----------
    path
        Dotted design path or a :data:`MODEL_OPTIONS` key.
    low, high
        Numeric bounds (``None`` for a categorical range).
    levels
        Categorical values (empty for a numeric range).
    scale
        One of :data:`SCALES` (numeric ranges).
    source
        Where the range comes from.
    """

    path: str
    low: float | None = None
    high: float | None = None
    levels: tuple[str, ...] = ()
    scale: str = "uniform"
    source: str = ""

    @property
    def categorical(self) -> bool:
        return bool(self.levels)

    def value(self, u: float) -> Any:
        """The parameter value at unit coordinate ``u`` in [0, 1)."""
        if self.categorical:
            return self.levels[min(int(u * len(self.levels)), len(self.levels) - 1)]
        if self.scale == "nu-log":
            g_low, g_high = math.log(0.5 - self.low), math.log(0.5 - self.high)
            return 0.5 - math.exp(g_low + u * (g_high - g_low))
        return self.low + u * (self.high - self.low)

    def to_json(self) -> dict:
        if self.categorical:
            return {"path": self.path, "levels": list(self.levels), "source": self.source}
        return {
            "path": self.path,
            "low": self.low,
            "high": self.high,
            "scale": self.scale,
            "source": self.source,
        }


def _number(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise DesignError(name, value, "must be a finite number")
    return float(value)


def make_range(path: str, entry: dict, *, origin: str) -> Range:
    """A checked :class:`Range` from a table (``low``/``high``/``scale`` or ``levels``, ``source``).

    ``origin`` (``"ranges"``, a ranges file, or ``"vary"``, a given range) prefixes the
    parameter name of any error.
    """
    sep = "." if origin == "ranges" else " "
    name = f"{origin}{sep}{path}"
    source = entry.get("source", "")
    if not isinstance(source, str):
        raise DesignError(f"{name}{sep}source", source, "must be a string")
    if path.startswith("model."):
        if path not in MODEL_OPTIONS:
            raise DesignError(name, path, f"unknown model option; known: {', '.join(MODEL_OPTIONS)}")
        levels = entry.get("levels")
        allowed = MODEL_OPTIONS[path]
        if not isinstance(levels, (list, tuple)) or not levels or any(v not in allowed for v in levels):
            raise DesignError(f"{name}{sep}levels", levels, f"must be a non-empty list from {allowed}")
        return Range(path, levels=tuple(levels), source=source)
    if "levels" in entry:
        raise DesignError(f"{name}{sep}levels", entry["levels"], "only model options are categorical")
    low = _number(f"{name}{sep}low", entry.get("low"))
    high = _number(f"{name}{sep}high", entry.get("high"))
    if not high > low:
        raise DesignError(f"{name}{sep}high", high, f"must be > low = {low:g}")
    scale = entry.get("scale", "uniform")
    if scale not in SCALES:
        raise DesignError(f"{name}{sep}scale", scale, f"must be one of {SCALES}")
    if scale == "nu-log" and not (low < 0.5 and high <= NU_MAX):
        raise DesignError(f"{name}{sep}high", high, f"a nu-log range must lie below {NU_MAX}")
    if path.endswith(".poisson_ratio") and high > NU_MAX:
        raise DesignError(f"{name}{sep}high", high, f"must be <= {NU_MAX} (Poisson ratio)")
    return Range(path, low=low, high=high, scale=scale, source=source)


def load_ranges(path: str | Path) -> dict[str, tuple[Range, bool]]:
    """Ranges file -> ``{path: (Range, default)}`` (see the module docstring)."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise DesignError("ranges", str(path), f"is not valid TOML: {exc}") from None
    except UnicodeDecodeError as exc:
        raise DesignError(
            "ranges", str(path), f"is not UTF-8 text (byte {exc.start}); give a TOML file"
        ) from None
    except OSError as exc:
        raise DesignError("ranges", str(path), f"cannot be read ({exc.strerror or exc})") from None
    table = data.get("ranges")
    if not isinstance(table, dict) or not table:
        raise DesignError("ranges", str(path), "needs a non-empty [ranges] table")
    out = {}
    for key, entry in table.items():
        if not isinstance(entry, dict):
            raise DesignError(f"ranges.{key}", entry, "must be a table")
        rest = {k: v for k, v in entry.items() if k != "default"}
        unknown = set(rest) - {"low", "high", "scale", "levels", "source"}
        if unknown:
            raise DesignError(f"ranges.{key}", sorted(unknown), "unknown keys")
        default = entry.get("default", True)
        if not isinstance(default, bool):
            raise DesignError(f"ranges.{key}.default", default, "must be true or false")
        out[key] = (make_range(key, rest, origin="ranges"), default)
    return out


def default_ranges(design_ref: str) -> Path | None:
    """The ranges file shipped for a preset name (``None`` when there is none)."""
    candidate = _HERE / f"ranges_{design_ref}.toml"
    return candidate if isinstance(design_ref, str) and candidate.is_file() else None


def parse_vary(text: str, known: dict[str, tuple[Range, bool]]) -> Range:
    """One ``--vary`` item: ``PATH=LO:HI[:SCALE]``, ``PATH=LEVEL,LEVEL`` or ``PATH`` (range from the file)."""
    path, sep, spec = text.partition("=")
    path = path.strip()
    if not path:
        raise DesignError("vary", text, "must be PATH=LO:HI, PATH=LEVEL,LEVEL or PATH")
    if not sep:
        if path not in known:
            raise DesignError(f"vary {path}", text, "has no range in the ranges file; give PATH=LO:HI")
        return known[path][0]
    origin = "vary"
    if path in MODEL_OPTIONS:
        return make_range(path, {"levels": spec.split(","), "source": "command line"}, origin=origin)
    parts = spec.split(":")
    if len(parts) not in (2, 3):
        raise DesignError(f"vary {path}", spec, "must be LO:HI or LO:HI:SCALE")
    try:
        low, high = float(parts[0]), float(parts[1])
    except ValueError:
        raise DesignError(f"vary {path}", spec, "LO and HI must be numbers") from None
    entry = {"low": low, "high": high, "source": "command line"}
    if len(parts) == 3:
        entry["scale"] = parts[2]
    return make_range(path, entry, origin=origin)


def base_table(design_ref: str | Path) -> dict:
    """The base design's TOML tables exactly as written (so dotted paths match the file)."""

    if isinstance(design_ref, str) and design_ref in presets.names():
        table = tomllib.loads(presets.text(design_ref))
    else:
        path = Path(design_ref)
        if not path.is_file():
            raise DesignError(
                "design",
                str(design_ref),
                f"must be a preset ({', '.join(presets.names())}) or an existing .toml file",
            )
        try:
            table = tomllib.loads(path.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise DesignError("design", str(path), f"is not valid TOML: {exc}") from None
        except UnicodeDecodeError as exc:
            raise DesignError("design", str(path), f"is not UTF-8 text (byte {exc.start})") from None
    design.from_dict(table)  # the base itself must be valid
    return table


def check_ranges(ranges: list[Range], table: dict) -> None:
    """Refuse unknown or repeated paths, and bounds the design itself rejects (each end, others nominal)."""

    seen = set()
    for r in ranges:
        if r.path in seen:
            raise DesignError(f"vary {r.path}", r.path, "is given twice")
        seen.add(r.path)
        if r.categorical:
            continue
        try:
            check_path(table, r.path)
        except DesignError as exc:
            raise DesignError(f"vary {r.path}", r.path, exc.bound) from None
        for end, value in (("low", r.low), ("high", r.high)):
            try:
                build_variant(table, {r.path: value})
            except DesignError as exc:
                raise DesignError(f"vary {r.path} {end}", value, f"{exc.parameter}: {exc.bound}") from None


def chosen_ranges(
    design_ref, table: dict, vary=(), ranges_file: str | Path | None = None
) -> list[Range] | None:
    """The ranges to vary, checked against ``table``: each ``vary`` item, else the ranges file's
    defaults (default file: the one shipped for ``design_ref``); None when there is neither."""
    path = ranges_file if ranges_file is not None else default_ranges(str(design_ref))
    known = load_ranges(path) if path is not None else {}
    if vary:
        ranges = [parse_vary(v, known) for v in vary]
    elif known:
        ranges = [r for r, default in known.values() if default]
    else:
        return None
    check_ranges(ranges, dict(table))
    return ranges
