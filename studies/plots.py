"""Matplotlib figures shared by the command line and the reports (Agg backend, PNG)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from softcath.analytic import composite_section
from softcath.core.plotting import pyplot


def analytic_plot(path: Path, response, *, title: str) -> Path:
    """Curvature, elongation and bend angle vs pressure, and the tip path in the bending plane."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(13, 4), constrained_layout=True)
    p = response.pressure
    axes[0].plot(p, response.curvature, label="curvature κ [1/mm]")
    axes[0].plot(p, response.elongation, label="elongation ε [-]")
    axes[0].set_xlabel("pressure [MPa]")
    axes[0].legend()
    axes[1].plot(p, np.degrees(response.bend_angle))
    axes[1].set_xlabel("pressure [MPa]")
    axes[1].set_ylabel("bend angle [deg]")
    axes[2].plot(response.tip_x, response.tip_y, "o-", ms=3)
    axes[2].plot([0], [0], "ks")
    axes[2].set_aspect("equal")
    axes[2].set_xlabel("tip x [mm]")
    axes[2].set_ylabel("tip y [mm]")
    axes[2].set_title("tip path (eq. 9)")
    fig.suptitle(title)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def section_plot(path: Path, design, *, title: str = "") -> Path:
    """The as-assembled cross-section with neutral axis and pressure centre."""
    plt = pyplot()
    s = design.section
    cs = composite_section(design)
    th = np.linspace(0, 2 * np.pi, 400)
    fig, ax = plt.subplots(figsize=(5, 5), constrained_layout=True)
    for r, style in ((s.coil_outer_radius, "k-"), (s.coil_inner_radius, "k--")):
        ax.plot(r * np.cos(th), r * np.sin(th), style, lw=1)
    ax.fill(s.a * np.cos(th), s.tube_center_y + s.b * np.sin(th), color="tab:orange", alpha=0.6, label="tube")
    ax.fill(s.a_int * np.cos(th), s.lumen_center_y + s.b_int * np.sin(th), color="white", ec="tab:orange")
    ax.fill(
        s.channel_outer_radius * np.cos(th),
        s.channel_center_y + s.channel_outer_radius * np.sin(th),
        color="tab:gray",
        alpha=0.7,
        label="channel",
    )
    ax.fill(
        s.channel_inner_radius * np.cos(th),
        s.channel_center_y + s.channel_inner_radius * np.sin(th),
        color="white",
    )
    ax.axhline(cs.neutral_axis_y, color="tab:blue", lw=1, label=f"neutral axis ȳ = {cs.neutral_axis_y:.3f}")
    ax.plot(
        [0], [cs.pressure_centre_y], "r+", ms=12, label=f"pressure centre y_p = {cs.pressure_centre_y:.3f}"
    )
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.legend(loc="lower right", fontsize=7)
    ax.set_title(title or f"{design.name}: as-assembled section")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def calibration_plot(path: Path, measurement, *, nominal, optimized, title: str) -> Path:
    """Data vs nominal vs optimised curvature over time and as curvature–pressure loops."""
    plt = pyplot()
    t, p, k = measurement.time_s, measurement.pressure_MPa, measurement.curvature_per_mm
    fig, axes = plt.subplots(1, 2, figsize=(12, 4), constrained_layout=True)
    axes[0].plot(t, k, ".", ms=1.5, color="0.6", label="data")
    axes[0].plot(t, nominal.curvature, label="nominal shape")
    axes[0].plot(t, optimized.curvature, label="optimised shape")
    axes[0].set_xlabel("time [s]")
    axes[0].set_ylabel("curvature [1/mm]")
    axes[0].legend()
    axes[1].plot(p, k, ".", ms=1.5, color="0.6", label="data")
    axes[1].plot(p, nominal.curvature, label="nominal")
    axes[1].plot(p, optimized.curvature, label="optimised")
    axes[1].set_xlabel("pressure [MPa]")
    axes[1].set_ylabel("curvature [1/mm]")
    axes[1].legend()
    fig.suptitle(title)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
