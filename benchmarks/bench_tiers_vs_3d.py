"""The fast tiers against the converged 3-D finite-strain FEM at mid-span, on random valid designs.

For the paper design and ``--designs - 1`` seeded random valid designs
(``studies.sweep.random_designs``, ``--seed``), at ``--pressure`` or, with ``--target-deg``,
along each design's own walk up to the pressure at which the finite-strain section model bends
it that far (``--points`` pressures evenly spaced up to it; lumen load):

- the 3-D reference: ``fem.nonlinear.reference.reference_curve`` (default layers, the
  half-layer companion solve and the small-load refined-section solves: its stated error, layers
  and section parts summed), mid-span curvature;
- the finite-strain section model's curvature (``section_curve``);
- the linear section model's curvature (``section_response``);
- the analytic composite-beam formula (``analytic.response``);
- the tip's angle: the 3-D end rotation extrapolated in the layers (``ReferenceCurve.tip``) against
  the end-zone closed form (``fem.section_model.end_zones``: bend rate over the corrected length
  plus the cap plug's tilt at the pressure) on the 3-D's own extrapolated bend rate and on the
  finite-strain section model's, and against the section's uniform arc over the whole length.

Writes ``tiers_vs_3d.csv`` and prints a Markdown table (the one in docs/validation.md).

Run: ``python benchmarks/bench_tiers_vs_3d.py [--designs 3 --pressure 0.3 --out out/bench]`` or
``python benchmarks/bench_tiers_vs_3d.py --designs 6 --skip-paper --target-deg 90 --points 3``.
Each 3-D reference takes minutes on 2 cores (10-20 min at 90 deg: 16 layers and the
8-layer companion). A design whose 3-D walk fails is reported with its error, never dropped.
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
    "closed_form_tip_ratio",
    "section_tip_ratio",
    "section_uniform_arc_ratio",
)


#: Highest pressure of a walk [MPa]: the top of the pressures a tip of this kind is driven with.
P_MAX_MPA = 1.0


def pressure_for_angle(d, angle_deg: float) -> float:
    """The lumen pressure [MPa] at which the finite-strain section model bends ``d``'s tip
    ``angle_deg`` (its end-zone corrected tip angle), interpolated on a walk to ``P_MAX_MPA``; a
    stiff design that does not bend that far by then is taken to its bend at ``P_MAX_MPA``."""
    from softcath.fem.section_model.finite_strain import SectionConvergenceError, section_curve

    grid = np.linspace(0.0, P_MAX_MPA, 41)[1:]
    try:
        c = section_curve(d, grid, load="lumen", linear_gain=False)
    except SectionConvergenceError as exc:  # the walk stalled: use what it reached
        if exc.curve is None:
            raise
        c = exc.curve
    p, a = np.asarray(c.pressure, float), np.degrees(np.asarray(c.bend_angle_rad, float))
    if a[-1] < angle_deg:
        print(f"{d.name}: the section model reaches {a[-1]:.1f} deg at {p[-1]:.3g} MPa", file=sys.stderr)
        return float(p[-1])
    return float(np.interp(angle_deg, np.concatenate([[0.0], a]), np.concatenate([[0.0], p])))


def compare(d, pressures) -> list[dict]:
    """One design's rows (one per pressure): tier curvature / 3-D mid-span curvature."""
    from softcath import analytic
    from softcath.fem.nonlinear.reference import reference_curve
    from softcath.fem.section_model.api import section_response
    from softcath.fem.section_model.end_zones import end_zones, tip_angle
    from softcath.fem.section_model.finite_strain import section_curve

    pressures = [float(x) for x in np.atleast_1d(pressures)]
    t0 = time.perf_counter()
    ref = reference_curve(d, pressures, load="lumen")
    seconds = time.perf_counter() - t0
    fs = section_curve(d, pressures, load="lumen", linear_gain=False)
    zones = end_zones(d)
    rows = []
    nan = float("nan")
    for i, pressure in enumerate(pressures):
        k3 = float(ref.curve.curvature_mid[i])
        rate_fs = float(fs.bend_rate_per_mm[i])
        tip3 = float(ref.tip.extrapolated[i]) if ref.tip is not None else nan
        # the 3-D's own extrapolated bend rate: its extrapolated tip over L minus its extrapolated deficit
        rate3 = tip3 / (d.tip.bending_length - float(ref.tip.deficit[i])) if ref.tip is not None else nan
        k_lin = float(section_response(d, pressure, load="lumen").curvature)
        k_an = float(np.ravel(analytic.response(d, pressure, load="lumen").curvature)[-1])
        rows.append(
            {
                "design": d.name,
                "pressure_MPa": pressure,
                "layers": ref.curve.layers,
                "fem3d_curvature_mid_per_mm": k3,
                # the stated error: the layers part plus the cross-section part
                "fem3d_error_estimate": float(ref.stated.relative[i]) if ref.stated is not None else nan,
                "fem3d_tip_angle_deg": float(np.degrees(ref.curve.bend_angle[i])),
                "fem3d_seconds": seconds,
                "section_nonlinear_ratio": float(fs.curvature_per_mm[i]) / k3,
                "section_linear_ratio": k_lin / k3,
                "analytic_ratio": k_an / k3,
                "fem3d_tip_extrapolated_deg": float(np.degrees(tip3)),
                "fem3d_tip_error_estimate": float(ref.tip.relative[i]) if ref.tip is not None else nan,
                "closed_form_tip_ratio": float(tip_angle(rate3, zones, pressure=pressure)) / tip3,
                "section_tip_ratio": float(tip_angle(rate_fs, zones, pressure=pressure)) / tip3,
                "section_uniform_arc_ratio": rate_fs * d.tip.bending_length / tip3,
            }
        )
    return rows


def main() -> None:
    from softcath import design
    from softcath.studies.sweep.random_designs import random_designs

    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--designs", type=int, default=3, help="designs (the paper's first)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the random valid designs")
    ap.add_argument("--skip-paper", action="store_true", help="random designs only (--designs of them)")
    ap.add_argument("--pressure", type=float, default=0.3, help="lumen pressure [MPa]")
    ap.add_argument("--target-deg", type=float, default=None, help="walk each design to this bend instead")
    ap.add_argument("--points", type=int, default=3, help="pressures per walk with --target-deg")
    ap.add_argument("--out", type=Path, default=Path("out/bench"), help="folder of tiers_vs_3d.csv")
    args = ap.parse_args()
    if args.skip_paper:
        designs = random_designs(args.designs, seed=args.seed)
    else:
        designs = [design.preset("paper"), *random_designs(max(args.designs - 1, 0), seed=args.seed)]
    args.out.mkdir(parents=True, exist_ok=True)
    rows: list[dict] = []
    failed: list[str] = []
    with open(args.out / "tiers_vs_3d.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS)
        w.writeheader()
        for d in designs:
            if args.target_deg is None:
                pressures = [args.pressure]
            else:
                top = pressure_for_angle(d, args.target_deg)
                pressures = [round(top * (k + 1) / args.points, 4) for k in range(args.points)]
            try:
                new = compare(d, pressures)
            except Exception as exc:  # the reference could not reach the bend: a finding, reported
                failed.append(f"{d.name} at {pressures} MPa: {type(exc).__name__}: {exc}")
                print(failed[-1], file=sys.stderr, flush=True)
                continue
            rows.extend(new)
            for r in new:
                w.writerow(r)
            fh.flush()
    print(
        "| design | p [MPa] | layers | 3-D κ_mid [1/mm] (error est.) | 3-D tip angle "
        "| section (finite strain) | section (linear) | analytic "
        "| 3-D tip, extrapolated (error est.) | closed form on the 3-D's rate / 3-D "
        "| section tip + end zones / 3-D | uniform arc / 3-D |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['design']} | {r['pressure_MPa']:.3g} | {r['layers']} "
            f"| {r['fem3d_curvature_mid_per_mm']:.4f} "
            f"({100 * r['fem3d_error_estimate']:.2g} %) | {r['fem3d_tip_angle_deg']:.1f}° "
            f"| {r['section_nonlinear_ratio']:.3f} | {r['section_linear_ratio']:.3f} "
            f"| {r['analytic_ratio']:.3g} | {r['fem3d_tip_extrapolated_deg']:.1f}° "
            f"({100 * r['fem3d_tip_error_estimate']:.2g} %) | {r['closed_form_tip_ratio']:.3f} "
            f"| {r['section_tip_ratio']:.3f} "
            f"| {r['section_uniform_arc_ratio']:.3f} |"
        )
    for f in failed:
        print(f"failed: {f}")


if __name__ == "__main__":
    main()
