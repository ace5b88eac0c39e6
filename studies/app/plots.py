"""The app's live figures (Bokeh): the section, κ and θ against pressure, the bent tip.

The curves' data sources are named (``curve-<tier>``, ``pinned-<tier>``, ``measured``,
``section-parts``), so the page's script (and a browser test) can read what is drawn.

Each figure keeps its data sources; an update replaces a source's data, which
Panel sends to the browser as one small patch (no figure is rebuilt). Lines:
one colour per tier, solid for the current design, dashed for the pinned one;
the measurement as dots.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from softcath.studies.app.curves import LOAD_NOTE, TierCurve
from softcath.studies.app.shapes import bent_tip, section_marks, section_shapes
from softcath.studies.tiers import TIERS

__all__ = ["Figures", "TIER_COLORS"]

TIER_ORDER = ("paper", "section", "section-nonlinear")
TIER_COLORS = {"paper": "#1f77b4", "section": "#ff7f0e", "section-nonlinear": "#2ca02c"}
_EMPTY_CURVE = {"p": [], "kappa": [], "theta_deg": []}
_EMPTY_XY = {"x": [], "y": []}


def _legend_below(fig) -> None:
    """Move the figure's legend under the plot (inside it would hide the curves)."""
    legend = fig.legend[0]
    fig.center = [c for c in fig.center if c is not legend]
    fig.add_layout(legend, "below")
    legend.label_text_font_size = "7pt"
    legend.spacing, legend.padding, legend.margin = 0, 2, 2
    legend.label_height = legend.glyph_height = 12


def _legend(tier: str, pinned: bool = False) -> str:
    text = f"{TIERS[tier].short_label}, {LOAD_NOTE[tier]}"
    return f"pinned A: {text}" if pinned else text


class Figures:
    """The four live figures and their data sources."""

    def __init__(self) -> None:
        from bokeh.models import ColumnDataSource
        from bokeh.plotting import figure

        self.section_src = ColumnDataSource(
            {"xs": [], "ys": [], "color": [], "label": []}, name="section-parts"
        )
        self.axis_src = ColumnDataSource({"x": [], "y": []})
        self.centre_src = ColumnDataSource({"x": [], "y": []})
        s = figure(
            title="as-assembled section [mm]",
            width=330,
            height=480,
            match_aspect=True,
            tools="pan,wheel_zoom,reset",
        )
        s.patches(
            "xs",
            "ys",
            fill_color="color",
            line_color="#333333",
            line_width=0.5,
            source=self.section_src,
            legend_field="label",
        )
        s.line("x", "y", source=self.axis_src, color="#1f77b4", legend_label="neutral axis ȳ (formula)")
        s.scatter(
            "x",
            "y",
            source=self.centre_src,
            marker="cross",
            size=14,
            color="red",
            legend_label="pressure centre y_p (formula)",
        )
        _legend_below(s)
        s.xaxis.axis_label, s.yaxis.axis_label = "x [mm]", "y [mm]"
        self.section = s

        kw = {"width": 430, "height": 480, "tools": "pan,wheel_zoom,box_zoom,reset,save"}
        self.kappa = figure(title="curvature κ [1/mm] against pressure [MPa]", **kw)
        self.theta = figure(title="bend angle θ [°] against pressure [MPa]", **kw)
        self.tip = figure(title="the tip at the chosen pressure [mm]", match_aspect=True, **kw)
        self.curve_src: dict[tuple[str, bool], ColumnDataSource] = {}
        self.tip_src: dict[tuple[str, bool], ColumnDataSource] = {}
        for pinned in (False, True):
            for tier in TIER_ORDER:
                style = {"color": TIER_COLORS[tier], "line_width": 2 if not pinned else 1.5}
                if pinned:
                    style["line_dash"] = "dashed"
                src = ColumnDataSource(dict(_EMPTY_CURVE), name=f"{'pinned' if pinned else 'curve'}-{tier}")
                self.curve_src[(tier, pinned)] = src
                self.kappa.line("p", "kappa", source=src, legend_label=_legend(tier, pinned), **style)
                self.theta.line("p", "theta_deg", source=src, legend_label=_legend(tier, pinned), **style)
                tsrc = self.tip_src[(tier, pinned)] = ColumnDataSource(dict(_EMPTY_XY))
                self.tip.line("x", "y", source=tsrc, legend_label=_legend(tier, pinned), **style)
        self.measured_src = ColumnDataSource({"p": [], "kappa": [], "theta_deg": []}, name="measured")
        for fig, col in ((self.kappa, "kappa"), (self.theta, "theta_deg")):
            fig.scatter(
                "p",
                col,
                source=self.measured_src,
                size=4,
                color="black",
                alpha=0.6,
                legend_label="measured (uploaded CSV)",
            )
        self.tip.scatter([0.0], [0.0], marker="square", size=8, color="black", legend_label="clamp")
        for fig in (self.kappa, self.theta, self.tip):
            _legend_below(fig)
            fig.legend.click_policy = "hide"
            fig.xaxis.axis_label = "pressure [MPa]"
        self.kappa.yaxis.axis_label = "κ [1/mm]"
        self.theta.yaxis.axis_label = "θ [°]"
        self.tip.xaxis.axis_label = "x [mm] (toward the channel side)"
        self.tip.yaxis.axis_label = "z [mm]"

    def show_section(self, design) -> None:
        """Draw the as-assembled section of ``design`` with the formula's ȳ and y_p."""
        shapes = section_shapes(design)
        self.section_src.data = {
            "xs": [s.x.tolist() for s in shapes],
            "ys": [s.y.tolist() for s in shapes],
            "color": [s.color for s in shapes],
            "label": [s.label for s in shapes],
        }
        marks = section_marks(design)
        r = design.section.coil_outer_radius
        self.axis_src.data = {"x": [-r, r], "y": [marks["neutral_axis_y_mm"]] * 2}
        self.centre_src.data = {"x": [0.0], "y": [marks["pressure_centre_y_mm"]]}

    def show_curves(
        self, curves: Sequence[TierCurve], *, pinned: bool = False, tiers: Sequence[str] = ()
    ) -> None:
        """Replace the lines of ``tiers`` (default: those of ``curves``) by ``curves`` (none: cleared)."""
        by_tier = {c.tier: c for c in curves}
        for tier in tiers or tuple(by_tier):
            c = by_tier.get(tier)
            src = self.curve_src[(tier, pinned)]
            if c is None:
                src.data = dict(_EMPTY_CURVE)
            else:
                src.data = {
                    "p": c.pressure_MPa,
                    "kappa": c.curvature_per_mm,
                    "theta_deg": np.degrees(c.bend_angle_rad),
                }

    def show_tip(
        self, curves: Sequence[TierCurve], pressure: float, *, pinned: bool = False, tiers: Sequence[str] = ()
    ) -> None:
        """Draw the bent tip of each curve at ``pressure`` [MPa]."""
        by_tier = {c.tier: c for c in curves}
        for tier in tiers or tuple(by_tier):
            c = by_tier.get(tier)
            x, y = bent_tip(c, pressure) if c is not None else (np.zeros(0), np.zeros(0))
            self.tip_src[(tier, pinned)].data = {"x": x.tolist(), "y": y.tolist()}

    def show_measured(self, measured) -> None:
        """Overlay a :class:`~softcath.studies.app.measured.MeasuredCurve` (``None``: remove it)."""
        if measured is None:
            self.measured_src.data = {"p": [], "kappa": [], "theta_deg": []}
            return
        theta = np.degrees(measured.bend_angle_rad)
        self.measured_src.data = {
            "p": measured.pressure_MPa.tolist(),
            "kappa": measured.curvature_per_mm.tolist(),
            "theta_deg": np.where(np.isfinite(theta), theta, np.nan).tolist(),
        }
