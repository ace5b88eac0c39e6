"""Several designs' bend curves in one table and one picture: ``overlay.csv/.json/.png``.

:func:`overlay` solves every design as ``softcath section`` does for one (the linear
section model, or the finite-strain one) and returns an :class:`Overlay`, whose
:meth:`~Overlay.write` writes the files ``softcath section A.toml B.toml ...`` writes.
Each curve is labelled with its design, tier and load; each value is the single-design run's.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from softcath import models
from softcath.core.atomic import Outputs, prepare_out_dir
from softcath.core.plotting import pyplot
from softcath.fem.section_model import section_model
from softcath.fem.section_model.mesh import MESH_SIZE, SEGMENTS
from softcath.models.section_nonlinear_eval import curve_with_rest
from softcath.studies.model_validity import warn_linear_range, warn_self_contact
from softcath.studies.outputs.tables import write_rows

__all__ = ["COLUMNS", "TIER_LABEL", "Overlay", "OverlayCurve", "overlay"]

#: The overlay table's columns (units in the names; ``bend_angle_deg`` beside the radians).
COLUMNS = (
    "design",
    "tier",
    "load",
    "pressure_MPa",
    "curvature_per_mm",
    "elongation",
    "bend_angle_rad",
    "bend_angle_deg",
    "tip_x_mm",
    "tip_y_mm",
)
#: The curve's columns, as the single-design ``section.csv``.
_CURVE = tuple(k for k in COLUMNS[3:] if k != "bend_angle_deg")
#: The tiers an overlay runs, in words.
TIER_LABEL = {"section": "linear section model", "section-nonlinear": "finite-strain section model"}


@dataclass(frozen=True)
class OverlayCurve:
    """One design's curve: its label, name, where it came from and the ``section.csv`` columns."""

    label: str
    name: str
    source: str
    columns: dict[str, np.ndarray] = field(repr=False)


@dataclass(frozen=True)
class Overlay:
    """Bend curves of several designs on one tier, under one load."""

    tier: str
    load: str
    curves: tuple[OverlayCurve, ...]

    def to_table(self) -> list[dict]:
        """``overlay.csv``'s rows: one per design and pressure, keyed by :data:`COLUMNS`."""
        return [
            {
                "design": c.label,
                "tier": self.tier,
                "load": self.load,
                **{k: float(c.columns[k][i]) for k in _CURVE},
                "bend_angle_deg": math.degrees(float(c.columns["bend_angle_rad"][i])),
            }
            for c in self.curves
            for i in range(c.columns["pressure_MPa"].size)
        ]

    def to_json(self) -> dict:
        """``overlay.json``: the designs, their tier, load and source."""
        return {
            "tier": self.tier,
            "load": self.load,
            "designs": [
                {"label": c.label, "name": c.name, "source": c.source, "tier": self.tier, "load": self.load}
                for c in self.curves
            ],
            "csv": "overlay.csv",
        }

    def write(self, folder: str | Path, *, picture: bool = True) -> tuple[str, ...]:
        """Write ``overlay.csv``, ``overlay.json`` and (``picture``) ``overlay.png``, all or none."""
        names = ["overlay.csv", "overlay.json"]
        with Outputs(prepare_out_dir(folder, param="folder")) as o:
            write_rows(o.path("overlay.csv"), COLUMNS, ([r[k] for k in COLUMNS] for r in self.to_table()))
            o.json("overlay.json", self.to_json())
            if picture:
                self.picture(o.path("overlay.png"))
                names.append("overlay.png")
        return tuple(names)

    def picture(self, path: str | Path) -> None:
        """Curvature and bend angle against pressure, one labelled curve per design."""
        plt = pyplot()
        fig, (ax_k, ax_t) = plt.subplots(1, 2, figsize=(10, 4.2))
        for c in self.curves:
            order = np.argsort(c.columns["pressure_MPa"])
            p = c.columns["pressure_MPa"][order]
            name = f"{c.label} ({self.tier}, {self.load} load)"
            ax_k.plot(p, c.columns["curvature_per_mm"][order], "o-", ms=3, label=name)
            ax_t.plot(p, np.degrees(c.columns["bend_angle_rad"][order]), "o-", ms=3, label=name)
        ax_k.set_ylabel("curvature [1/mm]")
        ax_t.set_ylabel("bend angle [deg]")
        for ax in (ax_k, ax_t):
            ax.set_xlabel("pressure [MPa]")
            ax.grid(alpha=0.3)
        ax_t.legend(fontsize=8)
        fig.suptitle(f"bend curves: {TIER_LABEL[self.tier]}, {self.load} load")
        fig.tight_layout()
        fig.savefig(path, dpi=130)
        plt.close(fig)


def overlay(
    designs: Sequence,
    pressures,
    *,
    sources: Sequence[str],
    tier: str = "section",
    load: str = "lumen",
    mesh_size: float | None = None,
    segments: int | None = None,
    silicone_poisson: float | None = None,
    mesher: str = "template",
    hoop_cap: float | None = None,
    coil_options: dict | None = None,
    progress: bool = False,
) -> Overlay:
    """The bend curves of ``designs`` at ``pressures`` [MPa] on one tier, under one load.

    Warns (log), naming each design, where a curve leaves its model's range.

    Parameters
    ----------
    designs
        :class:`~softcath.design.TipDesign` objects.
    pressures
        The pressures [MPa] (``>= 0`` for the finite-strain tier).
    sources
        Where each design came from (a preset name or a path), one per design: a name
        that appears twice is labelled ``"name (source)"``.
    tier
        ``"section"`` (linear) or ``"section-nonlinear"`` (finite strain).
    load
        ``"lumen"`` or ``"cap"``.
    mesh_size, segments, silicone_poisson, mesher
        The section mesh and silicone, as ``softcath section``.
    hoop_cap
        Finite strain only: cap of the coils' hoop modulus (times the stiffest silicone's E).
    coil_options
        Linear only: :func:`~softcath.fem.section_model.section_model`'s coil keywords.
    progress
        Finite strain only: report each curve's progress.
    """
    names = [d.name for d in designs]
    labels = [
        d.name if names.count(d.name) == 1 else f"{d.name} ({src})"
        for d, src in zip(designs, sources, strict=True)
    ]
    p = np.asarray(pressures, dtype=float)
    linear = models.get(tier, parameter="tier", allowed=TIER_LABEL).linear
    curves = []
    for label, d, src in zip(labels, designs, sources, strict=True):
        if not linear:  # the finite-strain section model: a walk through the pressures
            c = curve_with_rest(
                d,
                sorted({float(x) for x in p}),
                load=load,
                mesh_size=mesh_size,
                segments=segments,
                silicone_poisson=silicone_poisson,
                hoop_cap=hoop_cap,
                mesher=mesher,
                progress=progress,
            )
            columns = {k: np.array([r[k] for r in c.rows()]) for k in _CURVE}
        else:
            r = section_model(
                d,
                silicone_poisson=silicone_poisson,
                mesher=mesher,
                mesh_size=MESH_SIZE if mesh_size is None else mesh_size,
                segments=SEGMENTS if segments is None else segments,
                **(coil_options or {}),
            )
            resp = r.response(p, load)
            values = (resp.pressure, resp.curvature, resp.elongation, resp.bend_angle, resp.tip_x, resp.tip_y)
            columns = dict(zip(_CURVE, values, strict=True))
        curves.append(OverlayCurve(label=label, name=d.name, source=str(src), columns=columns))
    _warn(curves, linear=linear)
    return Overlay(tier=tier, load=load, curves=tuple(curves))


def _warn(curves: list[OverlayCurve], *, linear: bool) -> None:
    """The single-design run's validity warnings, each naming its design."""
    for c in curves:
        k = c.columns
        if linear:
            model = f"the section model (linear) on {c.label}"
            warn_linear_range(k["pressure_MPa"], k["bend_angle_rad"], elongation=k["elongation"], model=model)
        else:
            model = f"the finite-strain section model on {c.label}"
            warn_self_contact(k["pressure_MPa"], k["bend_angle_rad"], model=model)
