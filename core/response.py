"""What every model tier answers: :class:`TipResponse` for one design, :class:`ResponseBatch` for many.

It stands on the ground floor so that every tier's own detailed record (the finite-strain
FEM's, the section models') converts itself into it with ``to_response`` without importing
the tier registry (:mod:`softcath.models`) that sits above them.

A response holds, per pressure, the observables every consumer of a tier needs (sweeps,
selection, optimisation, prediction bands, the discrepancy workflows): the mid-span and
tip-level curvature, the elongation, the bend angle, the tip pose, the lumen volume change
and the largest silicone strain, with the tier's validity warnings, the parameters it
actually used and its wall time. A quantity a tier cannot give is NaN.

Files (:meth:`TipResponse.write`): ``<stem>.csv``, one row per pressure, the columns of
:meth:`TipResponse.to_table` (names carry their unit: ``_MPa``, ``_per_mm``, ``_rad``,
``_deg``, ``_mm``, ``_mm3``; ``elongation`` and ``max_strain`` are ratios); and
``<stem>.json``: ``{"tier", "load", "warnings", "parameters", "seconds", "columns": {name: unit},
"table": "<stem>.csv", "rows": [{column: value or null}]}`` (NaN is written as ``null``).
Both are written atomically (whole or not at all).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from softcath.core.atomic import write_text

__all__ = ["OBSERVABLES", "ResponseBatch", "TipResponse"]

#: The per-pressure observables of a response: field -> (table column, unit).
OBSERVABLES: dict[str, tuple[str, str]] = {
    "curvature_per_mm": ("curvature_per_mm", "1/mm"),
    "tip_curvature_per_mm": ("tip_curvature_per_mm", "1/mm"),
    "elongation": ("elongation", "-"),
    "bend_angle_rad": ("bend_angle_rad", "rad"),
    "tip_x_mm": ("tip_x_mm", "mm"),
    "tip_y_mm": ("tip_y_mm", "mm"),
    "lumen_volume_change_mm3": ("lumen_volume_change_mm3", "mm^3"),
    "max_strain": ("max_strain", "-"),
}


def tip_curvature(bend_angle_rad, elongation, bending_length_mm) -> np.ndarray:
    """Tip-level curvature [1/mm]: the bend angle over the deformed bending length L0 (1 + ε).

    The mean curvature of the whole bending length; for a uniform arc (the paper's formula)
    it is the arc's curvature, i.e. the mid-span curvature to rounding; the section tiers'
    angle is the tip's (end zones taken off), so theirs is the mid-span curvature times
    the end zones' factor. Where the elongation is unknown (NaN), L0 is used.
    """
    eps = np.asarray(elongation, float)
    arc = np.asarray(bending_length_mm, float) * (1.0 + np.where(np.isfinite(eps), eps, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(bend_angle_rad, float) / arc


@dataclass(frozen=True)
class TipResponse:
    """One tier's response of one design at a set of pressures (arrays indexed like ``pressures``).

    Attributes
    ----------
    tier
        The tier's name (:func:`softcath.models.names`).
    load
        ``"cap"`` (end-cap force only) or ``"lumen"`` (wall and cap).
    pressures
        Pressures [MPa].
    curvature_per_mm
        Mid-span curvature [1/mm].
    tip_curvature_per_mm
        Tip-level curvature [1/mm]: bend angle over the deformed bending length
        (:func:`tip_curvature`). The paper's formula (a uniform arc) has it equal to the
        mid-span curvature; the section tiers take off the end zones
        (:mod:`softcath.fem.section_model.end_zones`).
    elongation
        Axial elongation of the bending length [-].
    bend_angle_rad
        Bend angle of the tip [rad].
    tip_x_mm, tip_y_mm
        Tip pose in the bending plane [mm].
    lumen_volume_change_mm3
        Change of the lumen's volume from rest [mm^3]; NaN where the tier cannot give it.
    max_strain
        Largest silicone strain [-]; NaN where the tier cannot give it.
    warnings
        Where the answer leaves the tier's validity (:mod:`softcath.models.validity`).
    parameters
        The parameters the tier actually used (its options with their defaults, the design's
        name and bending length).
    seconds
        Wall time of the tier for this design and load [s] (a batch's share where batched).
    extras
        Tier-specific per-pressure diagnostics (e.g. the 3-D FEM's residual), name -> array.
    """

    tier: str
    load: str
    pressures: np.ndarray
    curvature_per_mm: np.ndarray
    tip_curvature_per_mm: np.ndarray
    elongation: np.ndarray
    bend_angle_rad: np.ndarray
    tip_x_mm: np.ndarray
    tip_y_mm: np.ndarray
    lumen_volume_change_mm3: np.ndarray
    max_strain: np.ndarray
    warnings: tuple[str, ...] = ()
    parameters: Mapping[str, Any] = field(default_factory=dict)
    seconds: float = math.nan
    extras: Mapping[str, np.ndarray] = field(default_factory=dict, repr=False)

    def to_table(self):
        """The response as a :class:`pandas.DataFrame`, one row per pressure (unit-bearing column names)."""
        import pandas as pd

        cols: dict[str, Any] = {"pressure_MPa": np.asarray(self.pressures, float)}
        for name, (column, _unit) in OBSERVABLES.items():
            cols[column] = np.asarray(getattr(self, name), float)
        cols["bend_angle_deg"] = np.degrees(cols["bend_angle_rad"])
        for name, values in self.extras.items():
            cols[name] = np.asarray(values, float)
        return pd.DataFrame(cols)

    def units(self) -> dict[str, str]:
        """Column -> unit of :meth:`to_table` (extras: from their name's suffix, else ``"-"``)."""
        out = {"pressure_MPa": "MPa"}
        out.update({column: unit for column, unit in OBSERVABLES.values()})
        out["bend_angle_deg"] = "deg"
        for name in self.extras:
            out[name] = _unit_of(name)
        return out

    def to_json(self) -> dict:
        """The JSON document of :meth:`write` (NaN as ``None``)."""
        rows = self.to_table().to_dict(orient="records")
        return {
            "tier": self.tier,
            "load": self.load,
            "warnings": list(self.warnings),
            "parameters": _plain(dict(self.parameters)),
            "seconds": _plain(self.seconds),
            "columns": self.units(),
            "rows": [{k: _plain(v) for k, v in r.items()} for r in rows],
        }

    def write(self, folder: str | Path, *, stem: str = "response") -> tuple[Path, Path]:
        """Write ``<stem>.csv`` and ``<stem>.json`` into ``folder`` (each atomically); return their paths.

        See the module docstring for the format; :meth:`read` reads it back.
        """
        import json

        out = Path(folder)
        out.mkdir(parents=True, exist_ok=True)
        csv = write_text(out / f"{stem}.csv", self.to_table().to_csv(index=False, float_format="%.17g"))
        doc = {**self.to_json(), "table": csv.name}
        text = json.dumps(doc, indent=2, allow_nan=False) + "\n"  # strict JSON: NaN is already null
        return csv, write_text(out / f"{stem}.json", text)

    @classmethod
    def read(cls, path: str | Path) -> TipResponse:
        """The response written by :meth:`write` (``path``: its JSON file)."""
        import json

        doc = json.loads(Path(path).read_text())
        rows = doc["rows"]

        def col(name: str) -> np.ndarray:
            return np.array([math.nan if r.get(name) is None else r[name] for r in rows], float)

        known = {"pressure_MPa", "bend_angle_deg", *(c for c, _u in OBSERVABLES.values())}
        extras = {k: col(k) for k in doc["columns"] if k not in known}
        seconds = doc.get("seconds")
        return cls(
            tier=doc["tier"],
            load=doc["load"],
            pressures=col("pressure_MPa"),
            **{name: col(column) for name, (column, _u) in OBSERVABLES.items()},
            warnings=tuple(doc["warnings"]),
            parameters=dict(doc["parameters"]),
            seconds=math.nan if seconds is None else float(seconds),
            extras=extras,
        )


@dataclass(frozen=True)
class ResponseBatch:
    """One tier's responses of many designs under one load: each observable (n_designs, n_pressures).

    A design the tier could not solve has NaN rows and its exception in ``errors``;
    ``batch[i]`` is design ``i``'s :class:`TipResponse` (its warnings computed then), and
    raises that design's exception if it failed.

    Attributes
    ----------
    tier, load, pressures
        As in :class:`TipResponse`.
    curvature_per_mm, tip_curvature_per_mm, elongation, bend_angle_rad, tip_x_mm, tip_y_mm,
    lumen_volume_change_mm3, max_strain
        (n_designs, n_pressures) arrays; units as in :class:`TipResponse`.
    seconds
        (n_designs,) wall time per design [s].
    options
        The options the tier was given (its defaults fill the rest in each design's parameters).
    designs
        The designs, in order (each response's parameters name its design and length).
    extras
        Tier-specific (n_designs, n_pressures) diagnostics.
    errors
        Design index -> the exception that design raised.
    partial
        Design index -> the response a design in ``errors`` reached before it failed (a
        finite-strain walk that stalled: the pressures past its last converged one NaN);
        :meth:`partial_response`. Its rows above stay NaN, so a sweep counts it failed.
    model
        The :class:`~softcath.models.Tier` that answered (its validity rule gives the warnings).
    """

    tier: str
    load: str
    pressures: np.ndarray
    curvature_per_mm: np.ndarray
    tip_curvature_per_mm: np.ndarray
    elongation: np.ndarray
    bend_angle_rad: np.ndarray
    tip_x_mm: np.ndarray
    tip_y_mm: np.ndarray
    lumen_volume_change_mm3: np.ndarray
    max_strain: np.ndarray
    seconds: np.ndarray
    options: Mapping[str, Any] = field(default_factory=dict)
    designs: tuple = field(default=(), repr=False, compare=False)
    extras: Mapping[str, np.ndarray] = field(default_factory=dict, repr=False)
    errors: Mapping[int, Exception] = field(default_factory=dict)
    model: Any = field(default=None, repr=False, compare=False)
    partial: Mapping[int, TipResponse] = field(default_factory=dict, repr=False, compare=False)

    def __len__(self) -> int:
        return int(np.shape(self.curvature_per_mm)[0])

    def __getitem__(self, i: int) -> TipResponse:
        if i in self.errors:
            raise self.errors[i]
        values = {name: np.asarray(getattr(self, name))[i].copy() for name in OBSERVABLES}
        warnings = self.model.warnings(
            self.pressures, values["bend_angle_rad"], values["max_strain"], values["elongation"]
        )
        return TipResponse(
            tier=self.tier,
            load=self.load,
            pressures=np.asarray(self.pressures, float).copy(),
            warnings=warnings,
            parameters=self.model.parameters(self.designs[i], self.options) if self.designs else {},
            seconds=float(self.seconds[i]),
            extras={k: np.asarray(v)[i].copy() for k, v in self.extras.items()},
            **values,
        )

    def partial_response(self, i: int) -> TipResponse:
        """Design ``i``'s response as far as it was solved: ``batch[i]`` for a design that did not
        fail, its :attr:`partial` response for one that failed part-way.

        Raises
        ------
        Exception
            Design ``i``'s own error when it failed with nothing solved.
        """
        if i in self.errors and i in self.partial:
            return self.partial[i]
        return self[i]


def _unit_of(name: str) -> str:
    for suffix, unit in (
        ("_per_mm", "1/mm"),
        ("_mm3", "mm^3"),
        ("_mm", "mm"),
        ("_rad", "rad"),
        ("_deg", "deg"),
        ("_seconds", "s"),
        ("_MPa", "MPa"),
    ):
        if name.endswith(suffix):
            return unit
    return "-"


def _plain(v: Any) -> Any:
    """``v`` as strict JSON: numpy scalars to Python, NaN and infinities to ``None``."""
    if isinstance(v, dict):
        return {str(k): _plain(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v
