"""The demo's three tiers on one design: the paper's formula, the section model, the 3-D FEM.

A table of the gains per MPa under both loads (the formula is the paper's
eq. 7, cap force only: what the paper predicts for either load), and κ/p
against the silicone's Poisson ratio from the section model (the 3-D FEM
stops at ν = 0.49, where the answer is steepest). When the 3-D FEM runs, a
rotatable view of its deformed tip (:mod:`softcath.fem.html_view`, inline WebGL).

The section model and the 3-D FEM are their tiers' records
(:meth:`~softcath.models.section.SectionTier.record`, :meth:`~softcath.models.fem3d.FemTier.record`:
the DOFs, the gains and the solution the view draws), solved with the tiers' options
(``--model-option``) as their responses are.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from softcath.design.load_cases import LOADS
from softcath.fem.export import to_grid
from softcath.fem.html_view import surface_of_grid, tip_view_fragment
from softcath.fem.section_model import section_model
from softcath.models.fem3d import FEM
from softcath.models.section import SECTION
from softcath.studies.demo.context import SectionOutput
from softcath.studies.demo.paper import paper_gains
from softcath.studies.report.figures import _plt, _save
from softcath.studies.report.html_blocks import figure, fmt, note, table
from softcath.studies.sweep.evaluators import fem_check_function, fem_records

__all__ = ["NU_SWEEP", "section_tiers", "nu_plot", "tip_view"]

#: Silicone Poisson ratios of the demo's nu plot (tube and filler together).
NU_SWEEP = (0.45, 0.46, 0.47, 0.48, 0.49, 0.495, 0.498, 0.499, 0.4995, 0.4999)
#: Pressure of the 3-D view [MPa]: the selection's check pressure, where the linear FEM is still to be
#: trusted.
VIEW_PRESSURE_MPA = 0.5


def nu_plot(path: Path, nus, kappa: dict, *, formula: float, fem: dict | None, fem_nu: float) -> Path:
    """κ/p against silicone ν (x: 0.5 − ν, log scale), section model per load, FEM points, the formula."""

    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    x = 0.5 - np.asarray(nus, float)
    colours = {"cap": "tab:blue", "lumen": "tab:orange"}
    for load in LOADS:
        ax.plot(x, kappa[load], "o-", ms=4, color=colours[load], label=f"section model, {load} load")
        if fem and load in fem:
            ax.plot([0.5 - fem_nu], [fem[load]], "ks", ms=8, mfc="none", mew=1.6)
    if fem:
        ax.plot([], [], "ks", mfc="none", mew=1.6, label=f"3-D FEM (ν = {fem_nu:g})")
    ax.axhline(formula, color="k", ls="--", lw=1, label="paper's formula (eq. 7)")
    ax.set_xscale("log")
    ax.invert_xaxis()
    ticks = [0.45, 0.49, 0.499, 0.4999]
    ax.set_xticks([0.5 - t for t in ticks], [f"{t:g}" for t in ticks])
    ax.minorticks_off()
    ax.set_xlabel("silicone Poisson ratio ν (axis: 0.5 − ν, log)")
    ax.set_ylabel("κ / p [1/(mm MPa)]")
    ax.set_title("Curvature per MPa against the silicone's ν")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return _save(fig, path)


def tip_view(result, *, load: str = "lumen", pressure: float = VIEW_PRESSURE_MPA) -> str:
    """The 3-D FEM's deformed tip as a rotatable inline view (empty if ``result`` carries no solution)."""
    solution = getattr(result, "solution", None)
    if solution is None or load not in getattr(solution, "unit", {}):
        return ""

    view = surface_of_grid(to_grid(solution, load, pressure))
    return "<h3 id='fem-3d'>The deformed tip in 3-D</h3>" + tip_view_fragment(
        view,
        caption=f"3-D FEM (linear, true scale) under the {load} load at {pressure:g} MPa, "
        "cut along the bending plane (the cut face towards you), coloured by the largest principal strain.",
    )


def section_tiers(ctx):
    """Demo section: the three tiers on ``ctx.design``, and κ/p against ν (see module docstring)."""

    d = ctx.design
    k_f, e_f = paper_gains(d, "cap", ctx.options.get("paper"))
    sm = SECTION.record(d, options=ctx.options.get(SECTION.name))
    fem, fem_seconds, why, result = _run_fem_tier(d, ctx.fem, ctx.options.get(FEM.name))
    html = _tiers_table(k_f, e_f, sm, fem, fem_seconds)
    html += _tiers_facts(sm, fem, fem_seconds)
    if fem:
        html += tip_view(result)
    if why:
        html += note(f"<b>{why}; the section model stands in for it.")

    nu_html, fpath, kappa = _nu_dependence(d, ctx.out_dir, k_f, fem)
    html += nu_html
    ctx.shared["tiers"] = {
        "formula": k_f,
        "section": dict(sm.curvature_per_mm_per_MPa),
        "fem": {ld: r["curvature_per_mm"] for ld, r in fem.items()} if fem else None,
        "nu": dict(zip(NU_SWEEP, kappa["lumen"], strict=True)),
    }
    if fem:
        ctx.shared["fem"] = {ld: r["curvature_per_mm"] / k_f for ld, r in fem.items()}
    return SectionOutput(html, (fpath,))


def _run_fem_tier(d, enabled: bool, options=None):
    """The 3-D FEM at 1 MPa with the ``fem`` tier's ``options``: per-load records, seconds, why it did
    not run (or ``""``) and its result."""

    fem, fem_seconds, why, result = None, None, "", None
    if not enabled:
        why = "Not run:</b> the 3-D FEM (switched off with --no-fem)"
    elif fem_check_function() is None:
        why = "Not available:</b> the 3-D FEM (fem.check is not importable)"
    else:
        t0 = time.perf_counter()
        result = FEM.record(d, [1.0], loads=LOADS, options=options)  # at 1 MPa: the values are per MPa
        fem_seconds = time.perf_counter() - t0
        rows = fem_records(result)
        fem = {ld: rows[(ld, 1.0)] for ld in LOADS if (ld, 1.0) in rows}
    return fem, fem_seconds, why, result


def _per_load(values: dict) -> list:
    """``values`` in the order of :data:`LOADS` (NaN where missing)."""
    return [values.get(ld, np.nan) for ld in LOADS]


def _tiers_table(k_f: float, e_f: float, sm, fem: dict | None, fem_seconds: float | None) -> str:
    """The introduction and the table of the three tiers' gains (HTML)."""
    body = [
        ["paper's formula (eq. 7, cap force)", k_f, k_f, e_f, e_f, 1.0, 1.0, "closed form", "—"],
        [
            "section model (2-D)",
            *_per_load(sm.curvature_per_mm_per_MPa),
            *_per_load(sm.elongation_per_MPa),
            *_per_load(sm.fem_formula_ratio),
            sm.dofs,
            f"{sm.seconds:.2f}",
        ],
    ]
    if fem:
        kf_ = {ld: r["curvature_per_mm"] for ld, r in fem.items()}
        body.append(
            [
                "3-D FEM (linear, mid-span)",
                *_per_load(kf_),
                *_per_load({ld: r["elongation"] for ld, r in fem.items()}),
                *(v / k_f for v in _per_load(kf_)),
                int(fem["cap"]["dofs"]),
                f"{fem_seconds:.1f}",
            ]
        )
    return (
        "<p>Three models of the same tip, per MPa of pressure. The <b>paper's formula</b> is the composite "
        "beam under the end-cap force (eq. 7), the paper's prediction for either load. The <b>section "
        "model</b> solves the as-assembled cross-section in 2-D (generalised plane strain: regions, bonded "
        "lands, transversely isotropic coils; the Saint-Venant solution of a long tip) under the cap load "
        "and under the real <b>lumen</b> load (the pressure on the lumen wall too). The <b>3-D FEM</b> "
        "solves the whole tip; its mid-span curvature is what the section model reproduces.</p>"
        + table(
            [
                "model",
                "κ/p cap [1/(mm MPa)]",
                "κ/p lumen",
                "ε/p cap [1/MPa]",
                "ε/p lumen",
                "κ / formula, cap",
                "κ / formula, lumen",
                "DOFs",
                "seconds",
            ],
            body,
            left=1,
        )
    )


def _tiers_facts(sm, fem: dict | None, fem_seconds: float | None) -> str:
    """The paragraph of what the table shows (HTML)."""
    facts = [
        f"Under the real lumen load the tip bends {fmt(sm.fem_formula_ratio['lumen'], 3)}× what the paper's "
        f"formula says (cap load: {fmt(sm.fem_formula_ratio['cap'], 3)}×): the coil confines the silicone, "
        "so the wall pressure adds to the bending instead of cancelling it."
    ]
    if fem:
        gaps = {ld: sm.curvature_per_mm_per_MPa[ld] / fem[ld]["curvature_per_mm"] - 1 for ld in fem}
        facts.append(
            "The section model agrees with the 3-D FEM to "
            + ", ".join(f"{fmt(100 * g, 2)} % ({ld})" for ld, g in gaps.items())
            + f", in {sm.seconds:.2f} s against {fem_seconds:.0f} s."
        )
    return "<p>" + " ".join(facts) + "</p>"


def _nu_dependence(d, out_dir: Path, k_f: float, fem: dict | None) -> tuple[str, Path, dict]:
    """κ/p against the silicone's ν from the section model: the HTML (figure and text), the figure's
    path and the curvatures per load."""

    kappa = {ld: [] for ld in LOADS}
    for nu in NU_SWEEP:
        r = section_model(d, silicone_poisson=nu)
        for ld in LOADS:
            kappa[ld].append(r.curvature_per_mm_per_MPa[ld])
    nu_design = float(d.tube.material.poisson_ratio)
    fpath = nu_plot(
        out_dir / "tiers_nu.png",
        NU_SWEEP,
        kappa,
        formula=k_f,
        fem={ld: r["curvature_per_mm"] for ld, r in fem.items()} if fem else None,
        fem_nu=nu_design,
    )
    i49, last = NU_SWEEP.index(0.49), len(NU_SWEEP) - 1
    html = figure(
        fpath.name,
        "κ/p from the section model as the silicone's ν (tube and filler) goes to 0.5"
        + (", the 3-D FEM at its ν = 0.49 (squares)" if fem else "")
        + "; the formula does not depend on ν.",
    )
    html += (
        f"<p>The lumen-load curvature grows from {fmt(kappa['lumen'][i49], 3)} at ν = 0.49 to "
        f"{fmt(kappa['lumen'][last], 3)} 1/(mm MPa) at ν = {NU_SWEEP[last]:g} "
        f"({fmt(kappa['lumen'][last] / kappa['lumen'][i49], 3)}×) while the cap-load one changes by a factor "
        f"{fmt(kappa['cap'][last] / kappa['cap'][i49], 3)}×: silicone is close to incompressible, and the "
        "3-D FEM (capped at 0.49) cannot follow it there; the section model is locking-free to 0.49999.</p>"
    )
    return html, fpath, kappa
