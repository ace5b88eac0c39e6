"""The report's figures (matplotlib, PNG): parity, error vs parameters, heat maps, sensitivity, renders."""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from softcath.core.plotting import pyplot
from softcath.design.reference import with_unit
from softcath.studies.tiers import TIERS

__all__ = [
    "parity_plot",
    "tiers_parity_plot",
    "tier_agreement",
    "parameter_plots",
    "heat_maps",
    "sensitivity",
    "render_design",
    "failed_summary",
    "pareto_plot",
]

log = logging.getLogger(__name__)
_LOAD_COLOURS = {"cap": "tab:blue", "lumen": "tab:orange"}
#: Panel key of the x-axis "the paper's formula under the cap load" (not a results column).
_FORMULA_CAP = "formula_cap_curvature"


def _plt():
    return pyplot()


def _save(fig, path: Path) -> Path:
    fig.savefig(path, dpi=110, bbox_inches="tight")
    _plt().close(fig)
    return path


def _numeric_params(df, params: list[str]) -> list[str]:
    out = []
    for p in params:
        v = np.asarray(df[p].to_numpy(), dtype=object)
        try:
            x = v.astype(float)
        except (TypeError, ValueError):
            continue
        if np.isfinite(x).any() and len(np.unique(x[np.isfinite(x)])) > 1:
            out.append(p)
    return out


def has_fem(df) -> bool:
    return bool(np.isfinite(df["curvature_fem_per_mm"].to_numpy(float)).any())


def has_section(df) -> bool:
    return "curvature_section_per_mm" in df and bool(
        np.isfinite(df["curvature_section_per_mm"].to_numpy(float)).any()
    )


def _formula(ok):
    """The paper's formula (analytic cap-load curvature) on the rows of ``ok`` (same design and pressure)."""
    paper = ok[ok.load == "cap"].set_index(["design_id", "pressure_MPa"]).curvature_analytic_per_mm
    return paper.reindex(pd_index(ok)).to_numpy(float)


#: (x column, y column, x label, y label) of the three-tier parity panels; "formula" is the paper's formula.
_TIER_PANELS = (
    ("formula", "curvature_section_per_mm", "paper's formula κ [1/mm]", "section model κ [1/mm]"),
    ("formula", "curvature_fem_per_mm", "paper's formula κ [1/mm]", "3-D FEM κ [1/mm]"),
    ("curvature_section_per_mm", "curvature_fem_per_mm", "section model κ [1/mm]", "3-D FEM κ [1/mm]"),
)


def tiers_parity_plot(df, path: Path) -> Path | None:
    """The paper's formula, the section model and the 3-D FEM side by side, where they exist.

    Panels: section model vs formula, FEM vs formula, FEM vs section model
    (every design and pressure, both loads). The formula is the paper's eq. 7
    (cap load) for both loads: what the paper would predict.
    """
    ok = df[(df.status == "ok") & (df.pressure_MPa > 0)]
    if ok.empty:
        return None
    x_formula = _formula(ok)
    panels = []
    for xcol, ycol, xl, yl in _TIER_PANELS:
        x = x_formula if xcol == "formula" else ok[xcol].to_numpy(float) if xcol in ok else None
        y = ok[ycol].to_numpy(float) if ycol in ok else None
        if x is not None and y is not None and (np.isfinite(x) & np.isfinite(y)).any():
            panels.append((x, y, xl, yl))
    if not panels:
        return None
    plt = _plt()
    fig, axes = plt.subplots(1, len(panels), figsize=(4.8 * len(panels), 4.4), squeeze=False)
    loads = ok.load.to_numpy()
    for ax, (x, y, xl, yl) in zip(axes[0], panels, strict=True):
        m = np.isfinite(x) & np.isfinite(y)
        for load in sorted(set(loads[m])):
            sel = m & (loads == load)
            ax.scatter(x[sel], y[sel], s=12, alpha=0.7, label=f"{load} load", color=_LOAD_COLOURS.get(load))
        lo, hi = min(x[m].min(), y[m].min()), max(x[m].max(), y[m].max())
        ax.plot([lo, hi], [lo, hi], "k--", lw=1, label="equal")
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.set_title(f"{yl.split(' κ')[0]} vs {xl.split(' κ')[0]}")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return _save(fig, path)


def tier_agreement(df) -> list[tuple]:
    """Per load: rows, median section/formula and FEM/formula ratios, median and max ``|FEM/section − 1|``."""
    ok = df[(df.status == "ok") & (df.pressure_MPa > 0)]
    if ok.empty:
        return []
    ok = ok.assign(_formula=_formula(ok))
    rows = []
    for load, g in ok.groupby("load"):
        f = g._formula.to_numpy(float)
        sec = g["curvature_section_per_mm"].to_numpy(float) if "curvature_section_per_mm" in g else f * np.nan
        fem = g["curvature_fem_per_mm"].to_numpy(float)
        with np.errstate(divide="ignore", invalid="ignore"):
            r_sec, r_fem, agree = sec / f, fem / f, np.abs(fem / sec - 1)

        def med(v):
            v = v[np.isfinite(v)]
            return float(np.median(v)) if v.size else np.nan

        both = agree[np.isfinite(agree)]
        rows.append(
            (load, len(g), med(r_sec), med(r_fem), med(agree), float(both.max()) if both.size else np.nan)
        )
    return rows


def parity_plot(df, path: Path) -> Path | None:
    """FEM vs analytic curvature, every design and pressure, both loads.

    Left: each load against the analytic model of the same load. Right: each
    load against the paper's formula (the analytic cap load), i.e. how much of
    the paper's prediction the FEM finds under each load.
    """
    if not has_fem(df):
        return None
    plt = _plt()
    ok = df[df.status == "ok"]
    paper = ok[ok.load == "cap"].set_index(["design_id", "pressure_MPa"]).curvature_analytic_per_mm
    fig, axes = plt.subplots(
        1, 2 if len(paper) else 1, figsize=(10 if len(paper) else 5.2, 4.8), squeeze=False
    )
    panels = [
        ("curvature_analytic_per_mm", "analytic κ, same load [1/mm]", "vs the analytic model of each load")
    ]
    if len(paper):
        panels.append((_FORMULA_CAP, "paper's formula κ (cap load) [1/mm]", "vs the paper's formula"))
    for ax, (xcol, xlabel, title) in zip(axes[0], panels, strict=False):
        lo, hi = np.inf, -np.inf
        for load, g in ok.groupby("load"):
            if xcol is _FORMULA_CAP:
                x = paper.reindex(pd_index(g)).to_numpy(float)
            else:
                x = g[xcol].to_numpy(float)
            y = g.curvature_fem_per_mm.to_numpy(float)
            m = np.isfinite(x) & np.isfinite(y)
            ax.scatter(x[m], y[m], s=14, alpha=0.75, label=f"FEM, {load} load", color=_LOAD_COLOURS.get(load))
            if m.any():
                lo, hi = min(lo, x[m].min(), y[m].min()), max(hi, x[m].max(), y[m].max())
        if np.isfinite(lo):
            ax.plot([lo, hi], [lo, hi], "k--", lw=1, label="FEM = analytic")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("FEM curvature κ [1/mm]")
        ax.set_title(title)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return _save(fig, path)


def pd_index(g):
    """The (design_id, pressure_MPa) index of a group of result rows."""
    import pandas as pd

    return pd.MultiIndex.from_arrays([g.design_id.to_numpy(), g.pressure_MPa.to_numpy()])


def parameter_plots(df, params: list[str], path: Path) -> tuple[Path | None, str]:
    """FEM/analytic curvature ratio (without FEM: section model / paper's formula, or the analytic
    bend per MPa) vs each parameter.

    With FEM, one row per load: the two loads' ratios differ by orders of magnitude.
    """
    params = _numeric_params(df, params)
    if not params:
        return None, ""
    ok = df[(df.status == "ok") & df.at_p_max]
    if ok.empty:
        return None, ""
    fem = has_fem(df)
    if fem:
        col, label = "fem_over_analytic", "κ_FEM / κ_analytic at p_max"
        ok = ok.assign(fem_over_analytic=1.0 + ok.rel_diff_curvature.to_numpy(float))
        groups = [(load, g) for load, g in ok.groupby("load")]
    elif has_section(df):
        col, label = "section_formula_ratio", "κ_section / paper's formula"
        groups = [(load, g) for load, g in ok.groupby("load")]
    else:
        col, label = "bend_per_MPa_deg", "analytic bend per MPa [deg/MPa]"
        groups = [(None, ok)]
    plt = _plt()
    n = len(params)
    fig, axes = plt.subplots(len(groups), n, figsize=(4 * n, 3.2 * len(groups)), squeeze=False)
    for row, (load, grp) in enumerate(groups):
        for ax, p in zip(axes[row], params, strict=True):
            for ld, g in grp.groupby("load"):
                ax.scatter(
                    g[p].astype(float),
                    g[col],
                    s=12,
                    alpha=0.7,
                    label=f"{ld} load",
                    color=_LOAD_COLOURS.get(ld),
                )
            ax.set_xlabel(with_unit(p))
            ax.grid(alpha=0.3)
        axes[row][0].set_ylabel(label if load is None else f"{label}\n({load} load)")
        axes[row][-1].legend(fontsize=8)
    fig.tight_layout()
    return _save(fig, path), label


def heat_maps(df, factorial: list[str], path: Path) -> tuple[Path | None, str]:
    """Heat maps over the first two grid/list parameters (others at their middle value), per load."""
    factorial = _numeric_params(df, factorial)
    if len(factorial) < 2:
        return None, ""
    px, py = factorial[:2]
    others = factorial[2:]
    sub = df[df.at_p_max & (df.status == "ok")]
    if sub.empty:
        return None, ""
    fixed = []
    for o in others:
        vals = np.unique(sub[o].astype(float))
        mid = vals[len(vals) // 2]
        sub = sub[np.isclose(sub[o].astype(float), mid)]
        fixed.append(f"{o} = {mid:g}")
    fem = has_fem(df)
    col, label = (
        ("rel_diff_curvature", "relative error (FEM − analytic)/|analytic|")
        if fem
        else (
            ("section_formula_ratio", "section model κ / paper's formula")
            if has_section(df)
            else ("bend_per_MPa_deg", "bend per MPa [deg/MPa]")
        )
    )
    loads = sorted(set(df.load))
    xs = np.unique(df[px].astype(float).dropna())
    ys = np.unique(df[py].astype(float).dropna())
    plt = _plt()
    fig, axes = plt.subplots(1, len(loads), figsize=(5 * len(loads), 4), squeeze=False)
    for ax, load in zip(axes[0], loads, strict=True):
        g = sub[sub.load == load]
        grid = np.full((len(ys), len(xs)), np.nan)
        for _, r in g.iterrows():
            i = np.searchsorted(ys, float(r[py]))
            j = np.searchsorted(xs, float(r[px]))
            grid[i, j] = r[col]
        im = ax.imshow(
            grid,
            origin="lower",
            aspect="auto",
            cmap="viridis",
            extent=(-0.5, len(xs) - 0.5, -0.5, len(ys) - 0.5),
        )
        ax.set_xticks(range(len(xs)), [f"{v:.3g}" for v in xs], rotation=45)
        ax.set_yticks(range(len(ys)), [f"{v:.3g}" for v in ys])
        ax.set_xlabel(with_unit(px))
        ax.set_ylabel(with_unit(py))
        ax.set_title(f"{load} load (white: invalid design)")
        fig.colorbar(im, ax=ax, label=label)
    fig.tight_layout()
    caption = f"{label} at p_max over {px} × {py}" + (f"; {', '.join(fixed)}" if fixed else "")
    return _save(fig, path), caption


def sensitivity(df, params: list[str], lhs: bool, path: Path) -> tuple[Path | None, list[tuple]]:
    """Sensitivity of the curvature at p_max to each parameter: the section model's under the lumen
    load when the sweep has it, else the analytic model's under the cap load.

    Standardised regression coefficients (SRC: the slope of the standardised
    output on the standardised inputs; SRC² sums to R² for a linear response)
    for every sweep, and RBD-FAST first-order indices (SALib) when the sweep
    is a Latin-hypercube sample.
    """
    params = _numeric_params(df, params)
    section = has_section(df)
    want = "lumen" if section else "cap"
    load = want if want in set(df.load) else sorted(set(df.load))[0]
    ycol = "curvature_section_per_mm" if section else "curvature_analytic_per_mm"
    sub = df[df.at_p_max & (df.status == "ok") & (df.load == load)]
    sub = sub[np.isfinite(sub[ycol].to_numpy(float))]
    if len(params) < 1 or len(sub) < len(params) + 3:
        return None, []
    x = sub[params].astype(float).to_numpy()
    y = sub[ycol].to_numpy(float)
    xs = (x - x.mean(0)) / x.std(0)
    ys = (y - y.mean()) / y.std() if y.std() > 0 else y * 0
    coef, *_ = np.linalg.lstsq(np.column_stack([xs, np.ones(len(ys))]), ys, rcond=None)
    src = coef[: len(params)]
    r2 = 1 - np.sum((ys - np.column_stack([xs, np.ones(len(ys))]) @ coef) ** 2) / max(np.sum(ys**2), 1e-300)
    s1 = [np.nan] * len(params)
    if lhs and len(sub) >= 30:
        from SALib.analyze import rbd_fast

        problem = {
            "num_vars": len(params),
            "names": params,
            "bounds": [[float(a), float(b)] for a, b in zip(x.min(0), x.max(0), strict=True)],
        }
        # M harmonics need N well above 2M samples (SALib's bias correction divides by 1 − 2M/N).
        m = max(1, min(10, len(sub) // 8))
        s1 = list(rbd_fast.analyze(problem, x, y, M=m, seed=0)["S1"])
    rows = [(p, float(src[i]), float(s1[i])) for i, p in enumerate(params)]
    plt = _plt()
    fig, ax = plt.subplots(figsize=(1.3 * len(params) + 3, 3.4))
    pos = np.arange(len(params))
    ax.bar(pos - 0.2, src, width=0.4, label=f"SRC (R² = {r2:.2f})")
    if np.isfinite(s1).any():
        ax.bar(pos + 0.2, s1, width=0.4, label="RBD-FAST S1")
    ax.set_xticks(pos, params, rotation=20)
    ax.axhline(0, color="k", lw=0.8)
    ax.set_ylabel(
        f"sensitivity of {TIERS['section' if section else 'paper'].short_label} κ at p_max ({load})"
    )
    ax.legend()
    ax.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    return _save(fig, path), rows


def render_design(design, path: Path, *, title: str, curvatures: dict[str, float] | None = None) -> Path:
    """Cross-section of the as-assembled tip and, optionally, its bent shape for given curvatures."""
    from matplotlib.patches import Circle, Ellipse

    plt = _plt()
    s = design.section
    ncols = 2 if curvatures else 1
    fig, axes = plt.subplots(1, ncols, figsize=(4.2 * ncols, 4), squeeze=False)
    ax = axes[0][0]
    ax.add_patch(Circle((0, 0), s.coil_outer_radius, color="#8a8f98", label="coil (homogenised)"))
    ax.add_patch(
        Circle(
            (0, 0),
            s.coil_inner_radius,
            color="#f4e9c8" if design.filler else "white",
            label="filler" if design.filler else "void",
        )
    )
    ax.add_patch(Ellipse((0, s.tube_center_y), 2 * s.a, 2 * s.b, color="#d95f5f", label="silicone tube"))
    ax.add_patch(Ellipse((0, s.lumen_center_y), 2 * s.a_int, 2 * s.b_int, color="white", label="lumen"))
    ax.add_patch(Circle((0, s.channel_center_y), s.channel_outer_radius, color="#5a6270", label="channel"))
    ax.add_patch(Circle((0, s.channel_center_y), s.channel_inner_radius, color="white"))
    r = s.coil_outer_radius * 1.1
    ax.set_xlim(-r, r)
    ax.set_ylim(-r, r)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title("cross-section")
    ax.legend(fontsize=7, loc="lower right")
    if curvatures:
        ax2 = axes[0][1]
        length = design.tip.bending_length
        sarc = np.linspace(0, length, 100)
        for label, k in curvatures.items():
            if not np.isfinite(k):
                continue
            th = k * sarc
            x = np.where(np.abs(th) > 1e-12, (1 - np.cos(th)) / np.where(k == 0, 1, k), 0.0)
            y = np.where(np.abs(th) > 1e-12, np.sin(th) / np.where(k == 0, 1, k), sarc)
            ax2.plot(x, y, lw=2, label=label)
        ax2.set_aspect("equal")
        ax2.set_xlabel("x [mm] (toward the channel side)")
        ax2.set_ylabel("y [mm]")
        ax2.set_title("bent tip (constant curvature)")
        ax2.grid(alpha=0.3)
        ax2.legend(fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return _save(fig, path)


def failed_summary(df) -> list[tuple[str, int, str]]:
    """(reason, number of designs, first design ids) for the failed designs."""
    per = df.drop_duplicates("design_id")
    bad = per[per.status == "failed"]
    out = []
    for reason, g in bad.groupby("reason", sort=False):
        ids = g.design_id.tolist()
        out.append(
            (str(reason), len(ids), ", ".join(str(i) for i in ids[:8]) + (" …" if len(ids) > 8 else ""))
        )
    return sorted(out, key=lambda t: -t[1])


def pareto_plot(selection: dict, path: Path) -> Path | None:
    """Feasible designs in the plane of the first two objectives, the Pareto front highlighted."""
    pts = np.asarray(selection.get("points") or [], dtype=float)
    objs = selection.get("objectives", [])
    if len(objs) < 2 or pts.size == 0:
        return None
    plt = _plt()
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    front = pts[:, 1] > 0
    ax.scatter(pts[~front, 2], pts[~front, 3], s=14, color="0.6", label="feasible")
    f = pts[front]
    f = f[np.argsort(f[:, 2])]
    ax.plot(f[:, 2], f[:, 3], "o-", color="tab:red", ms=5, label="Pareto front")
    best = pts[0]
    ax.scatter(
        [best[2]],
        [best[3]],
        s=160,
        facecolors="none",
        edgecolors="k",
        label=f"rank 1 (design {int(best[0])})",
    )
    ax.set_xlabel(with_unit(objs[0]))
    ax.set_ylabel(with_unit(objs[1]))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    model = TIERS[selection["model"]].short_label if selection.get("model") in TIERS else None
    ax.set_title(f"Selection ({model + ', ' if model else ''}{selection.get('load')} load)")
    return _save(fig, path)


def bend_curves(df, path: Path, *, max_designs: int = 6) -> Path | None:
    """Bend angle vs pressure per design and load: analytic, linear FEM and finite-strain FEM."""
    if "nonlinear_bend_angle_rad" not in df.columns:
        return None
    ok = df[(df.status == "ok") & np.isfinite(df["nonlinear_bend_angle_rad"].astype(float))]
    if ok.empty:
        return None
    loads = sorted(ok.load.unique())
    ids = list(dict.fromkeys(ok.design_id))[:max_designs]
    plt = _plt()
    fig, axes = plt.subplots(1, len(loads), figsize=(6 * len(loads), 4.2), squeeze=False)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, load in zip(axes[0], loads, strict=True):
        for n, did in enumerate(ids):
            g = ok[(ok.design_id == did) & (ok.load == load)].sort_values("pressure_MPa")
            if g.empty:
                continue
            c = colors[n % len(colors)]
            p = g.pressure_MPa.to_numpy(float)
            ax.plot(
                p,
                np.degrees(g["nonlinear_bend_angle_rad"].to_numpy(float)),
                "-o",
                color=c,
                ms=3,
                label=f"design {did}: nonlinear FEM",
            )
            if "bend_angle_fem_rad" in g and np.isfinite(g["bend_angle_fem_rad"].astype(float)).any():
                ax.plot(
                    p, np.degrees(g["bend_angle_fem_rad"].to_numpy(float)), "--", color=c, label="linear FEM"
                )
            ax.plot(
                p,
                np.degrees(g["bend_angle_analytic_rad"].to_numpy(float)),
                ":",
                color=c,
                label=TIERS["paper"].short_label,
            )
        ax.set_title(f"{load} load")
        ax.set_xlabel("pressure [MPa]")
        ax.set_ylabel("bend angle [deg]")
        ax.legend(fontsize=7)
    return _save(fig, path)
