"""The picture: each tier's sample, its 90 % band and median, and the measured gain as a line."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from softcath.core.plotting import pyplot
from softcath.studies.tiers import TIERS

__all__ = ["band_picture", "curve_band_picture"]


def band_picture(
    tiers: Sequence,
    path: str | Path,
    *,
    measured_gain: float | None = None,
    points: Mapping[str, float] | None = None,
    title: str = "",
) -> Path:
    """Write the band picture of ``tiers`` (``TierPrediction``) to ``path``; ``points``: extra labelled
    gains."""
    plt = pyplot()

    points = dict(points or {})
    rows = len(tiers) + len(points)
    fig, ax = plt.subplots(figsize=(8.0, 1.2 + 0.75 * rows))
    rng = np.random.default_rng(0)  # jitter only: not part of any result
    labels = []
    for i, t in enumerate(tiers):
        y = rows - 1 - i
        g = t.gains[np.isfinite(t.gains)]
        p = t.gain_percentiles
        small = g.size < 200
        ax.scatter(
            g,
            y + 0.18 * (rng.random(g.size) - 0.5),
            s=12 if small else 4,
            alpha=0.7 if small else 0.25,
            color="C0",
            lw=0,
        )
        ax.add_patch(
            plt.Rectangle((p["p5"], y - 0.22), p["p95"] - p["p5"], 0.44, fill=False, color="C0", lw=1.5)
        )
        ax.plot([p["p50"]] * 2, [y - 0.22, y + 0.22], color="C0", lw=2)
        ax.plot(t.nominal_gain, y, marker="D", color="k", ms=5)
        label = TIERS[t.model].short_label if t.model in TIERS else t.model
        labels.append(f"{label}\n{t.load} load, n = {t.feasible_samples}")
    for j, (name, value) in enumerate(points.items()):
        y = rows - 1 - len(tiers) - j
        ax.plot(value, y, marker="o", color="C2", ms=7)
        labels.append(name)
    if measured_gain is not None:
        ax.axvline(measured_gain, color="C3", lw=1.5, ls="--")
        ax.text(measured_gain, rows - 0.45, f" measured {measured_gain:g}", color="C3", va="bottom")
    ax.set_yticks(range(rows - 1, -1, -1), labels, fontsize=8)
    ax.set_ylim(-0.6, rows - 0.2)
    ax.set_xlabel("curvature per pressure κ/p [1/(mm MPa)]")
    ax.set_title(title or "prediction bands: box p5–p95, bar p50, ◆ nominal design", fontsize=9)
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    out = Path(path)
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out


def curve_band_picture(nonlinear: Mapping, path: str | Path, *, measured=None, title: str = "") -> Path:
    """Curvature against pressure: the finite-strain section model's p5-p95 band, p50 and nominal,
    the measured points and their per-pressure medians (``nonlinear``: ``curve_bands``'s document)."""
    plt = pyplot()

    pts = nonlinear["pressures"]
    p = np.array([pt["pressure_MPa"] for pt in pts])
    band = {q: np.array([pt["curvature_percentiles"][q] for pt in pts]) for q in ("p5", "p50", "p95")}
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    ax.fill_between(p, band["p5"], band["p95"], alpha=0.25, label="p5-p95, finite-strain section")
    ax.plot(p, band["p50"], "o-", label="p50")
    ax.plot(p, [pt["nominal_curvature_per_mm"] for pt in pts], "d--", label="nominal design")
    if measured is not None:
        ax.plot(
            measured.pressure_MPa,
            measured.curvature_per_mm,
            ".",
            ms=2,
            alpha=0.3,
            color="0.3",
            label="measured",
        )
        med = nonlinear.get("measured", {}).get("points", [])
        mp = [m["pressure_MPa"] for m in med if m["measured_curvature_per_mm"] is not None]
        mk = [m["measured_curvature_per_mm"] for m in med if m["measured_curvature_per_mm"] is not None]
        ax.plot(mp, mk, "ks", label="measured, median per pressure")
    ax.set_xlabel("pressure [MPa]")
    ax.set_ylabel("curvature [1/mm]")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path)
