"""A sweep's swept design fields: the ``[parameters]`` and ``[sample]`` tables of a sweep spec.

Each parameter is a dotted path into the base design's TOML tables with one of
``grid = [start, stop, count]``, ``values = [...]`` or ``lhs = [low, high]``
(:mod:`softcath.studies.sweep.spec` describes the whole file). The grid's
factorial product times the Latin-hypercube sample is the sweep's design count,
refused above :data:`MAX_DESIGNS`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from softcath.core.errors import DesignError
from softcath.studies.sweep.variants import check_path

__all__ = ["MAX_DESIGNS", "MAX_GRID_POINTS", "Parameter"]

#: Designs of one sweep (10⁷ analytic designs take minutes; more would exhaust memory first).
MAX_DESIGNS = 10_000_000
#: Points of one grid axis (a product of a few such axes is already 10⁸ designs).
MAX_GRID_POINTS = 100_000


@dataclass(frozen=True)
class Parameter:
    """One swept design field.

    Attributes
    ----------
    path
        Dotted path into the base design's TOML tables, e.g. ``"tube.a"``.
    kind
        ``"grid"`` (linspace), ``"values"`` (explicit list) or ``"lhs"`` (Latin hypercube range).
    values
        The grid points or listed values (empty for ``"lhs"``).
    bounds
        (low, high) of a Latin-hypercube parameter, else ``None``.
    """

    path: str
    kind: str
    values: tuple[Any, ...] = ()
    bounds: tuple[float, float] | None = None


def _real(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise DesignError(name, value, "must be a finite number")
    return float(value)


def _parameter(path: str, entry: Any) -> Parameter:
    name = f"parameters.{path}"
    if not isinstance(entry, dict) or len(entry) != 1:
        raise DesignError(name, entry, "must be a table with exactly one of grid, values, lhs")
    ((kind, value),) = entry.items()
    if kind == "grid":
        if not isinstance(value, list) or len(value) != 3:
            raise DesignError(f"{name}.grid", value, "must be [start, stop, count]")
        start, stop = _real(f"{name}.grid[0]", value[0]), _real(f"{name}.grid[1]", value[1])
        count = value[2]
        if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= MAX_GRID_POINTS:
            raise DesignError(f"{name}.grid[2]", count, f"must be an integer in [1, {MAX_GRID_POINTS}]")
        step = (stop - start) / (count - 1) if count > 1 else 0.0
        return Parameter(path, "grid", tuple(start + i * step for i in range(count)))
    if kind == "values":
        if not isinstance(value, list) or not value:
            raise DesignError(f"{name}.values", value, "must be a non-empty list")
        for i, v in enumerate(value):
            if isinstance(v, float) and not math.isfinite(v):
                raise DesignError(f"{name}.values[{i}]", v, "must be a finite number")
            if not isinstance(v, (int, float, str)):
                raise DesignError(f"{name}.values[{i}]", v, "must be a number or a name")
        return Parameter(path, "values", tuple(value))
    if kind == "lhs":
        if not isinstance(value, list) or len(value) != 2:
            raise DesignError(f"{name}.lhs", value, "must be [low, high]")
        low, high = _real(f"{name}.lhs[0]", value[0]), _real(f"{name}.lhs[1]", value[1])
        if not high > low:
            raise DesignError(f"{name}.lhs[1]", high, f"must be > low = {low:g}")
        return Parameter(path, "lhs", (), (low, high))
    raise DesignError(name, kind, "unknown kind; use grid, values or lhs")


def _parameters(data: dict, base_table: dict) -> tuple[Parameter, ...]:
    """The ``[parameters]`` table's parameters, their paths checked against the base design."""
    raw_params = data.get("parameters", {})
    if not isinstance(raw_params, dict):
        raise DesignError("parameters", raw_params, "must be a table of dotted design paths")
    params = tuple(_parameter(k, v) for k, v in _flatten(raw_params))
    _check_paths(params, base_table)
    return params


def _design_count(params: tuple[Parameter, ...], n_samples: int) -> int:
    """Designs of a sweep: the factorial grid times the Latin-hypercube sample (0 samples: none)."""
    return max(n_samples, 1) * math.prod(len(p.values) for p in params if p.kind != "lhs")


def _n_samples(data: dict, params: tuple[Parameter, ...]) -> int:
    """``sample.n`` (required with an lhs parameter, else 0), after checking the sweep's size."""
    n_samples = 0
    if any(p.kind == "lhs" for p in params):
        sample = data.get("sample")
        if not isinstance(sample, dict) or "n" not in sample:
            raise DesignError("sample.n", None, "is required when a parameter uses lhs")
        n_samples = sample["n"]
        if isinstance(n_samples, bool) or not isinstance(n_samples, int) or n_samples < 1:
            raise DesignError("sample.n", n_samples, "must be an integer >= 1")
    n_designs = _design_count(params, n_samples)
    if n_designs > MAX_DESIGNS:
        raise DesignError(
            "parameters", f"{n_designs:.3g} designs", f"must give at most {MAX_DESIGNS:.0e} designs"
        )
    return n_samples


def _flatten(table: dict, prefix: str = ""):
    """Accept both ``"tube.a" = {...}`` and ``[parameters.tube] a = {...}``."""
    for key, value in table.items():
        path = f"{prefix}{key}"
        if isinstance(value, dict) and not (set(value) & {"grid", "values", "lhs"}):
            yield from _flatten(value, f"{path}.")
        else:
            yield path, value


def _check_paths(params: tuple[Parameter, ...], base_table: dict) -> None:
    seen = set()
    for p in params:
        if p.path in seen:
            raise DesignError(f"parameters.{p.path}", p.path, "is given twice")
        seen.add(p.path)
        check_path(base_table, p.path)
