"""Demo section 3: large bends in four tiers (formula, linear section, finite-strain section, 3-D
finite-strain FEM), the pressure each needs for 90 degrees, and the silicone strain.

Each tier answers with its options (``--model-option``, the context's ``options``): the two
linear tiers through the registry (:func:`softcath.models.get`), the two finite-strain ones
through their tiers' records (:meth:`~softcath.models.section_nonlinear.SectionNonlinearTier.record`,
:meth:`~softcath.models.fem_nonlinear.FemNonlinearTier.record`), which carry what the pictures
and the text need besides the bend (DOFs, the deformed tip, Newton's record).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import cast

import numpy as np

from softcath import models
from softcath.core.plotting import pyplot
from softcath.fem.nonlinear.outputs import plot_curve, plot_deformed
from softcath.models.fem_nonlinear import FEM_NONLINEAR
from softcath.models.section_nonlinear import SECTION_NONLINEAR
from softcath.studies.demo.context import DEMO_MAX_STRAIN, DemoContext, SectionOutput
from softcath.studies.report.html_blocks import figure, fmt, table

__all__ = ["DEMO_LARGE_BEND_PRESSURES_MPA", "DEMO_SECTION_CURVE_PRESSURES_MPA", "section_large_bends"]

#: Lumen-load pressures of the finite-strain section [MPa]: far enough to see the bend outgrow the linear
#: prediction and the silicone strain approach the demo's limit (0.47 at 0.5 MPa), in ~15 s on the coarse
#: default mesh.
DEMO_LARGE_BEND_PRESSURES_MPA = (0.1, 0.2, 0.3, 0.4, 0.5)

#: The finite-strain section model's curve [MPa]: past 90 degrees for the paper design (about 0.8 MPa), in
#: about two seconds.
DEMO_SECTION_CURVE_PRESSURES_MPA = tuple(round(0.1 * i, 1) for i in range(1, 11))


def _pressure_for(angle: float, pressure, bend) -> float | None:
    """First pressure where ``bend`` [rad] reaches ``angle`` (linear interpolation), None if it does not."""
    p = np.concatenate([[0.0], np.asarray(pressure, float)])
    a = np.concatenate([[0.0], np.asarray(bend, float)])
    hit = np.flatnonzero(a >= angle)
    if hit.size == 0:
        return None
    i = int(hit[0])
    return float(p[i - 1] + (angle - a[i - 1]) * (p[i] - p[i - 1]) / (a[i] - a[i - 1]))


def _bend_of(tier: str, d, load: str, options) -> Callable[[object], np.ndarray]:
    """``d``'s bend angle [rad] against pressures [MPa] from the registry's ``tier``, with its ``options``."""
    model = models.get(tier)

    def bend(p) -> np.ndarray:
        pressures = np.atleast_1d(np.asarray(p, dtype=float))
        return model.response(d, pressures, load=load, options=options).bend_angle_rad

    return bend


def four_tiers(d, fem_curve, path, *, options: Mapping[str, Mapping] | None = None) -> tuple[list, dict]:
    """The four tiers' bend angle against pressure (``path``: the PNG) and their pressures for 90 degrees.

    ``options`` are the tiers' options, tier name -> its options (the demo's ``--model-option``);
    ``fem_curve`` is the ``fem-nonlinear`` tier's record, or ``None``.
    """
    plt = pyplot()
    from scipy.optimize import brentq

    opts = options or {}
    length = float(d.tip.bending_length)
    fine = np.linspace(0.0, DEMO_SECTION_CURVE_PRESSURES_MPA[-1], 101)
    linear_tiers = {  # their own bend angle: kappa p over the stretched length (eq. 9)
        "paper's formula (eq. 7, cap load)": _bend_of("paper", d, "cap", opts.get("paper")),
        "linear section model": _bend_of("section", d, "lumen", opts.get("section")),
    }
    fs = SECTION_NONLINEAR.record(
        d, DEMO_SECTION_CURVE_PRESSURES_MPA, load="lumen", options=opts.get("section-nonlinear")
    )
    fs_response = fs.to_response(tier=SECTION_NONLINEAR.name)  # the tier's answer from its record
    tiers = {name: (fine, np.asarray(f(fine), float)) for name, f in linear_tiers.items()}
    tiers["finite-strain section model (tip angle)"] = (fs_response.pressures, fs_response.bend_angle_rad)
    if fem_curve is not None:
        tiers["3-D finite-strain FEM, tip end section"] = (fem_curve.pressure, fem_curve.bend_angle)
        rate = np.asarray(fem_curve.bend_rate_mid, float)
        if np.all(np.isfinite(rate)):
            tiers["3-D finite-strain FEM, mid-span rate x L"] = (fem_curve.pressure, rate * length)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for (name, (p, a)), style in zip(tiers.items(), ("--", "-.", "o-", "s", "^"), strict=False):
        ax.plot(p, np.degrees(a), style, label=name, ms=5)
    ax.axhline(90.0, color="0.6", lw=0.8)
    ax.set_xlabel("lumen pressure [MPa]")
    ax.set_ylabel("bend angle [deg]")
    ax.set_title(f"{d.name}: four tiers of the bend")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    p90 = {name: _pressure_for(np.pi / 2, p, a) for name, (p, a) in tiers.items()}
    for name, f in linear_tiers.items():  # beyond the plotted range: solve their own closed form
        root = brentq(lambda p, f=f: float(f(p)[0]) - np.pi / 2, 0.0, 100.0, xtol=1e-12)
        p90[name] = float(cast(float, root))  # full_output=False: the root alone
    reached = {name: (float(p[-1]), float(np.degrees(a[-1]))) for name, (p, a) in tiers.items()}
    return [(name, p90[name], *reached[name]) for name in tiers], {"section_curve": fs, "p90": p90}


def section_large_bends(ctx: DemoContext) -> SectionOutput:
    if not ctx.fem:
        return _three_tiers_only(ctx)
    d = ctx.design
    c = FEM_NONLINEAR.record(
        d, DEMO_LARGE_BEND_PRESSURES_MPA, load="lumen", options=ctx.options.get(FEM_NONLINEAR.name)
    )
    f1, f2 = ctx.out_dir / "large_bends_curve.png", ctx.out_dir / "large_bends_tip.png"
    f0 = ctx.out_dir / "large_bends_tiers.png"
    plot_curve(c, f1)
    plot_deformed(c, f2)
    rows90, tiers = four_tiers(d, c, f0, options=ctx.options)
    over = [float(p) for p, e in zip(c.pressure, c.max_strain, strict=True) if e > DEMO_MAX_STRAIN]
    ratio = float(c.bend_angle[-1] / c.linear_bend_angle[-1])
    html = (
        "<p>"
        + " ".join(_large_bend_facts(c, tiers["section_curve"], ratio, over))
        + "</p>"
        + figure(f0.name, "Bend angle vs lumen pressure in four tiers; the grey line is 90°.")
        + _table90(rows90)
        + _bend_curve_html(c, f1, f2)
    )
    ctx.shared["large_bends"] = {
        "pressure": float(c.pressure[-1]),
        "angle_deg": float(np.degrees(c.bend_angle[-1])),
        "ratio": ratio,
        "strain_over_at": over[0] if over else None,
    }
    ctx.shared["large_bends"]["p90_MPa"] = tiers["p90"]
    return SectionOutput(html, (f0, f1, f2))


def _three_tiers_only(ctx: DemoContext) -> SectionOutput:
    """The section without the finite-strain FEM (``--no-fem``): the other three tiers of the bend."""
    f0 = ctx.out_dir / "large_bends_tiers.png"
    rows90, _ = four_tiers(ctx.design, None, f0, options=ctx.options)
    return SectionOutput(
        "<p>Finite-strain FEM switched off (--no-fem): three tiers of the bend.</p>"
        + figure(f0.name, "Bend angle vs lumen pressure: formula, linear and finite-strain section models.")
        + _table90(rows90),
        (f0,),
    )


def _large_bend_facts(c, fs, ratio: float, over: list[float]) -> list[str]:
    """Sentences on the finite-strain bend ``c``: against the linear FEM, the strain limit and the
    finite-strain section model ``fs``."""
    dep = c.departure(0.05)["linear_fem"]
    text = [
        f"Finite-strain FEM of the same tip (follower pressure on the deformed lumen, hyperelastic silicone, "
        f"{c.ndofs} DOFs on the coarse default mesh): at {fmt(c.pressure[-1])} MPa the tip bends "
        f"{fmt(np.degrees(c.bend_angle[-1]), 3)}°, {fmt(ratio, 3)}× what the linear FEM predicts."
    ]
    if dep is not None:
        text.append(
            f"The linear FEM departs from it by 5 % at {fmt(np.degrees(dep), 2)}° of bend: beyond that, "
            "small-rotation answers (linear FEM, Euler–Bernoulli) underestimate the bend."
        )
    if over:
        text.append(
            f"The silicone's largest principal strain passes {fmt(DEMO_MAX_STRAIN)} at {fmt(over[0])} MPa "
            f"(it is {fmt(c.max_strain[-1], 2)} at {fmt(c.pressure[-1])} MPa): for this design the strain "
            "limit, not the bend, is what to design against."
        )
    text.append(
        f"The finite-strain section model (a 2-D solve of the section at finite strain, {fs.dofs} DOFs, "
        f"{fmt(fs.seconds, 2)} s for {fs.pressure.size} pressures) follows the 3-D FEM's mid-span bend; "
        "its tip angle takes off the end zones (the cap plug and the clamp), as the 3-D end section turns."
    )
    return text


def _bend_curve_html(c, f1, f2) -> str:
    """The finite-strain bend curve's figure and table, and the deformed tip's figure (HTML)."""
    rows = [
        (p, np.degrees(a), np.degrees(lin), np.degrees(ana), e, int(it))
        for p, a, lin, ana, e, it in zip(
            c.pressure,
            c.bend_angle,
            c.linear_bend_angle,
            c.analytic_bend_angle,
            c.max_strain,
            c.newton_iterations,
            strict=True,
        )
    ]
    return (
        figure(f1.name, "Bend angle vs lumen pressure: finite-strain FEM, linear FEM, analytic (lumen load).")
        + table(
            [
                "p [MPa]",
                "finite-strain FEM [deg]",
                "linear FEM [deg]",
                "analytic, lumen load [deg]",
                "max silicone strain",
                "Newton iterations",
            ],
            rows,
        )
        + figure(
            f2.name,
            f"The tip at {fmt(c.pressure[-1])} MPa (cut along the bending plane, side view) over its "
            "undeformed ghost, coloured by the largest principal stretch strain λ_max − 1.",
        )
    )


def _table90(rows90) -> str:
    rows = [
        (name, "not reached" if p90 is None else fmt(p90, 3), fmt(p_last), fmt(a_last, 3))
        for name, p90, p_last, a_last in rows90
    ]
    return table(["tier", "pressure for 90° [MPa]", "computed up to [MPa]", "bend there [deg]"], rows)
