"""Print the docs/coil.md tables of the section model's coil models (about 1 min on one core).

python examples/coil_model_tables.py [N_DESIGNS] [SEED]
"""

from __future__ import annotations

import sys

import numpy as np

from softcath import design
from softcath.fem.coil import resolved_coil_stiffness
from softcath.fem.section_model import bend_curve, section_model
from softcath.fem.section_model.coil_models import COIL_MODELS, coil_section_stiffness, model_options
from softcath.studies.coil_ranking import random_coil_designs, rank_by_coil_model


def coil_table() -> None:
    d = design.resolve("paper")
    ref = {"coil": resolved_coil_stiffness(d.coil), "channel": resolved_coil_stiffness(d.channel)}
    print("| model | outer EA/wire | outer EI/wire (open) | channel EA/wire | channel EI/wire (open) |")
    print("|---|---|---|---|---|")
    for m in COIL_MODELS:
        s = coil_section_stiffness("paper", coil_model=m)
        cells = [
            f"{s[n]['EA_N']:.4g} ({s[n]['EA_N'] / ref[n].axial_tension:.3f}) | "
            f"{s[n]['EI_N_mm2']:.4g} ({s[n]['EI_N_mm2'] / ref[n].bending:.3f})"
            for n in ("coil", "channel")
        ]
        print(f"| {m} | " + " | ".join(cells) + " |")


def paper_table() -> None:
    print("| model | cap kappa/p | lumen kappa/p | cap eps/p | lumen eps/p |")
    print("|---|---|---|---|---|")
    for m in COIL_MODELS:
        r = section_model("paper", **model_options(m))
        k, e = r.curvature_per_mm_per_MPa, r.elongation_per_MPa
        print(f"| {m} | {k['cap']:.4f} | {k['lumen']:.4f} | {e['cap']:.4f} | {e['lumen']:.4f} |")
    for placement in ("annulus", "resolved"):
        c = {ld: bend_curve("paper", [0.3], load=ld, coil_model=placement) for ld in ("cap", "lumen")}
        print(
            f"| coil-bound, {placement} | {c['cap'].gain_pivoting:.4f} | {c['lumen'].gain_pivoting:.4f} | "
            f"{c['cap'].elongation[0] / 0.3:.4f} | {c['lumen'].elongation[0] / 0.3:.4f} |"
        )


def curve_table() -> None:
    p = np.round(np.arange(0, 0.61, 0.1), 3)
    print("| load, F0 [N] | threshold [MPa] | " + " | ".join(f"{x:g}" for x in p) + " |")
    print("|---|---|" + "---|" * len(p))
    for ld in ("cap", "lumen"):
        for f0 in (0.0, 0.005, 0.02):
            c = bend_curve("paper", p, load=ld, initial_tension=(f0, 0.0))
            print(
                f"| {ld}, {f0:g} | {c.threshold_pressure:.4f} | "
                + " | ".join(f"{x:.4f}" for x in c.curvature)
                + " |"
            )


def ranking_table(n: int, seed: int) -> None:
    models = ("annulus", "annulus-bending", "wahl", "resolved", "coil-bound", "coil-bound-tensioned")
    r = rank_by_coil_model(random_coil_designs(n, seed=seed), models=models, top=5)
    print(f"{n} designs, seed {seed}; Spearman rho / top-5 overlap")
    print("| | " + " | ".join(models[1:]) + " |")
    print("|---|" + "---|" * (len(models) - 1))
    for i, a in enumerate(models[:-1]):
        cells = [
            "" if j <= i else f"{r.spearman[(a, b)]:.3f} / {r.top_overlap[(a, b)]:.1f}"
            for j, b in enumerate(models)
        ]
        print(f"| {a} | " + " | ".join(cells[1:]) + " |")
    for m in models:
        g = r.gains[m]
        print(f"{m}: kappa/p {g.min():.4f} .. {g.max():.4f}, top 5 {r.order(m)[:5]}")


if __name__ == "__main__":
    coil_table()
    paper_table()
    curve_table()
    ranking_table(int(sys.argv[1]) if len(sys.argv) > 1 else 30, int(sys.argv[2]) if len(sys.argv) > 2 else 0)
