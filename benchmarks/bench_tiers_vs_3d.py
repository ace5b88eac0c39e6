"""The fast tiers against the converged 3-D finite-strain FEM at mid-span, on random valid designs.

For the paper design and ``--designs - 1`` seeded random valid designs
(``studies.sweep.random_designs``, seed 1), at one pressure (lumen load):

- the 3-D reference: ``fem.nonlinear.reference.reference_curve`` (default layers, the
  half-layer companion solve and its Richardson error estimate), mid-span curvature;
- the finite-strain section model's curvature (``section_curve``);
- the linear section model's curvature (``section_response``);
- the analytic composite-beam formula (``analytic.response``);
- the tip's angle: the 3-D end rotation extrapolated in the layers (``ReferenceCurve.tip``) against
  the finite-strain section model's bend rate over the end-zone corrected length
  (``fem.section_model.end_zones``) and over the whole length (the uniform arc).

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
    "fem3d_tip_extrapolated_deg",
    "fem3d_tip_error_estimate",
    "section_tip_ratio",
    "section_uniform_arc_ratio",
)


def compare(d, pressure: float) -> dict:
    """One design's row: tier curvature / 3-D mid-span curvature."""
    from softcath import analytic
    from softcath.fem.nonlinear.reference import reference_curve
    from softcath.fem.section_model.api import section_response
    from softcath.fem.section_model.end_zones import end_zones, tip_angle
    from softcath.fem.section_model.finite_strain import section_curve

    t0 = time.perf_counter()
    ref = reference_curve(d, [pressure], load="lumen")
    seconds = time.perf_counter() - t0
    k3 = float(ref.curve.curvature_mid[-1])
    fs = section_curve(d, [pressure], load="lumen", linear_gain=False)
    k_fs = float(fs.curvature_per_mm[-1])
    rate_fs = float(fs.bend_rate_per_mm[-1])
    tip3 = float(ref.tip.extrapolated[-1])
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
        "fem3d_tip_extrapolated_deg": float(np.degrees(tip3)),
        "fem3d_tip_error_estimate": float(ref.tip.relative[-1]),
        "section_tip_ratio": float(tip_angle(rate_fs, end_zones(d))) / tip3,
        "section_uniform_arc_ratio": rate_fs * d.tip.bending_length / tip3,
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
        "| section (finite strain) | section (linear) | analytic "
        "| 3-D tip, extrapolated (error est.) | section tip + end zones / 3-D | uniform arc / 3-D |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['design']} | {r['layers']} | {r['fem3d_curvature_mid_per_mm']:.4f} "
            f"({100 * r['fem3d_error_estimate']:.2g} %) | {r['fem3d_tip_angle_deg']:.1f}° "
            f"| {r['section_nonlinear_ratio']:.3f} | {r['section_linear_ratio']:.3f} "
            f"| {r['analytic_ratio']:.3g} | {r['fem3d_tip_extrapolated_deg']:.1f}° "
            f"({100 * r['fem3d_tip_error_estimate']:.2g} %) | {r['section_tip_ratio']:.3f} "
            f"| {r['section_uniform_arc_ratio']:.3f} |"
        )


if __name__ == "__main__":
    main()
