"""What the app hands out as downloads: the design as TOML, the curves as CSV, the view as PNG.

All three are returned as text or bytes; the browser saves them (the app
writes no file). The TOML is :func:`softcath.design.dumps`, so it loads back
with ``softcath design validate``; the CSV has one row per tier and pressure,
every column's unit in its name.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Sequence

import numpy as np

from softcath import design as design_pkg
from softcath.core.plotting import pyplot
from softcath.studies.app.curves import TierCurve
from softcath.studies.app.shapes import bent_tip, section_shapes
from softcath.studies.outputs.overlay import COLUMNS as OVERLAY_COLUMNS

__all__ = ["CSV_COLUMNS", "curves_csv", "design_toml", "view_png"]

#: The overlay table's columns (one format for curves of several designs), and the strain.
CSV_COLUMNS = (*OVERLAY_COLUMNS, "max_strain")


def design_toml(design) -> str:
    """The design file of ``design`` (loads back to an equal design)."""
    return design_pkg.dumps(design, header="Written by softcath app.")


def curves_csv(curves: Sequence[tuple[str, TierCurve]]) -> str:
    """CSV text of ``(design label, curve)`` pairs: one row per pressure, :data:`CSV_COLUMNS`."""
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(CSV_COLUMNS)
    for label, c in curves:
        strain = c.max_strain if c.max_strain is not None else np.full(c.pressure_MPa.shape, np.nan)
        for i in range(c.pressure_MPa.size):
            theta = float(c.bend_angle_rad[i])
            w.writerow(
                [
                    label,
                    c.tier,
                    c.load,
                    *(
                        _num(v)
                        for v in (
                            c.pressure_MPa[i],
                            c.curvature_per_mm[i],
                            c.elongation[i],
                            theta,
                            math.degrees(theta),
                            c.tip_x_mm[i],
                            c.tip_y_mm[i],
                            strain[i],
                        )
                    ),
                ]
            )
    return out.getvalue()


def _num(v) -> str:
    v = float(v)
    return repr(v) if math.isfinite(v) else ""


def view_png(
    design,
    curves: Sequence[TierCurve],
    *,
    pressure: float,
    pinned: Sequence[TierCurve] = (),
    measured=None,
) -> bytes:
    """A PNG of the app's view: the section, κ and θ against pressure, the tip at ``pressure``."""
    plt = pyplot()

    fig, axes = plt.subplots(1, 4, figsize=(17, 4.2), constrained_layout=True)
    ax = axes[0]
    for shape in section_shapes(design):
        ax.fill(shape.x, shape.y, color=shape.color, label=shape.label if shape.label else None, lw=0)
    ax.set_aspect("equal")
    ax.set_title(f"{design.name}: as-assembled section")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.legend(fontsize=6, loc="lower right")
    for c_list, style in ((curves, "-"), (pinned, "--")):
        for c in c_list:
            tag = "" if style == "-" else "pinned: "
            axes[1].plot(c.pressure_MPa, c.curvature_per_mm, style, label=tag + c.label)
            axes[2].plot(c.pressure_MPa, np.degrees(c.bend_angle_rad), style, label=tag + c.label)
    if measured is not None:
        axes[1].plot(measured.pressure_MPa, measured.curvature_per_mm, ".", ms=3, label=measured.name)
        axes[2].plot(
            measured.pressure_MPa, np.degrees(measured.bend_angle_rad), ".", ms=3, label=measured.name
        )
    axes[1].set_ylabel("curvature κ [1/mm]")
    axes[2].set_ylabel("bend angle θ [°]")
    for a in axes[1:3]:
        a.set_xlabel("pressure [MPa]")
        a.grid(alpha=0.3)
        a.legend(fontsize=6)
    for c in curves:
        x, y = bent_tip(c, pressure)
        axes[3].plot(x, y, label=c.label)
    axes[3].set_aspect("equal")
    axes[3].set_title(f"the tip at {pressure:g} MPa")
    axes[3].set_xlabel("x [mm] (toward the channel side)")
    axes[3].set_ylabel("z [mm]")
    axes[3].legend(fontsize=6)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    plt.close(fig)
    return buf.getvalue()
