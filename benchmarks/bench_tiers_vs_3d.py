"""The fast tiers against the converged 3-D finite-strain FEM at mid-span, on random valid designs.

For the paper design and ``--designs - 1`` seeded random valid designs
(``studies.sweep.random_designs``, seed 1), at one pressure (lumen load):

- the 3-D reference: ``fem.nonlinear.reference.reference_curve`` (default layers, the
  half-layer companion solve and its Richardson error estimate), mid-span curvature;
- the finite-strain section model's curvature (``section_curve``);
- the linear section model's curvature (``section_response``);
- the analytic composite-beam formula (``analytic.response``).

Writes ``tiers_vs_3d.csv`` and prints a Markdown table (the one in docs/validation.md).

Run: ``python benchmarks/bench_tiers_vs_3d.py [--designs 3 --pressure 0.3 --out out/bench]``.
Each 3-D reference takes minutes on 2 cores.
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

COLUMNS = (
    "design",
    "pressure_MPa",
    "layers",
    "fem3d_curvature_mid_per_mm",
    "fem3d_error_estimate",
    "fem3d_tip_angle_deg",
    "fem3d_seconds",
    "section_nonlinear_ratio",
    "section_linear_ratio",
    "analytic_ratio",
)


def compare(d, pressure: float) -> dict:
    """One design's row: tier curvature / 3-D mid-span curvature."""
    from softcath import analytic
    from softcath.fem.nonlinear.reference import reference_curve
    from softcath.fem.section_model.api import section_response
    from softcath.fem.section_model.finite_strain import section_curve

    t0 = time.perf_counter()
    ref = reference_curve(d, [pressure], load="lumen")
    seconds = time.perf_counter() - t0
    k3 = float(ref.curve.curvature_mid[-1])
    k_fs = float(section_curve(d, [pressure], load="lumen", linear_gain=False).curvature_per_mm[-1])
    k_lin = float(section_response(d, pressure, load="lumen").curvature)
    k_an = float(np.ravel(analytic.response(d, pressure, load="lumen").curvature)[-1])
    return {
        "design": d.name,
        "pressure_MPa": pressure,
        "layers": ref.curve.layers,
        "fem3d_curvature_mid_per_mm": k3,
        "fem3d_error_estimate": float(ref.error.relative[-1]),
        "fem3d_tip_angle_deg": float(np.degrees(ref.curve.bend_angle[-1])),
        "fem3d_seconds": seconds,
        "section_nonlinear_ratio": k_fs / k3,
        "section_linear_ratio": k_lin / k3,
        "analytic_ratio": k_an / k3,
    }


def main() -> None:
    from softcath import design
    from softcath.studies.sweep.random_designs import random_designs

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=3, help="designs (the paper's first)")
    ap.add_argument("--pressure", type=float, default=0.3, help="lumen pressure [MPa]")
    ap.add_argument("--out", type=Path, default=Path("out/bench"), help="folder of tiers_vs_3d.csv")
    args = ap.parse_args()
    designs = [design.preset("paper"), *random_designs(max(args.designs - 1, 0), seed=1)]
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    with open(args.out / "tiers_vs_3d.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS)
        w.writeheader()
        for d in designs:
            rows.append(compare(d, args.pressure))
            w.writerow(rows[-1])
            fh.flush()
    print(
        "| design | layers | 3-D κ_mid [1/mm] (error est.) | tip angle "
        "| section (finite strain) | section (linear) | analytic |"
    )
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['design']} | {r['layers']} | {r['fem3d_curvature_mid_per_mm']:.4f} "
            f"({100 * r['fem3d_error_estimate']:.2g} %) | {r['fem3d_tip_angle_deg']:.1f}° "
            f"| {r['section_nonlinear_ratio']:.3f} | {r['section_linear_ratio']:.3f} "
            f"| {r['analytic_ratio']:.3g} |"
        )


if __name__ == "__main__":
    main()
