"""Fit the tube's as-assembled shape to a measurement CSV (paper eq. 8, CasADi + IPOPT multistart)."""

from __future__ import annotations

import argparse
from pathlib import Path

HELP = "the paper's ellipse shape optimisation against a measurement CSV"


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "measured", type=Path, help="measurement CSV (time_s, pressure_MPa, curvature_per_mm, ...)"
    )
    p.add_argument("--design", default="paper", help="preset name or TOML path (default: paper)")
    p.add_argument("--out", type=Path, required=True, help="output directory")
    p.add_argument(
        "--free",
        default="a,a_int,b_int,h",
        help="shape parameters to optimise (default: all four, as the paper)",
    )
    p.add_argument("--load", choices=("cap", "lumen"), default="cap")
    p.add_argument(
        "--grid", type=int, default=3, help="multistart grid points per free parameter (default 3)"
    )
    p.add_argument("--filter", action="store_true", help="apply the paper's IIR low-pass to all series first")


def run(args: argparse.Namespace) -> int:
    import analytic
    import design
    from analytic.calibration import calibrate
    from analytic.io import Measurement, read_measurement_csv
    from studies.atomic import Outputs, check_finite_json, prepare_out_dir
    from studies.plots import calibration_plot
    from studies.validity import check_pressure

    out = prepare_out_dir(args.out)
    if not 1 <= args.grid <= 20:
        raise design.DesignError("--grid", args.grid, "must be an integer in [1, 20]")
    d = design.resolve(args.design)
    m = read_measurement_csv(args.measured)
    check_pressure(m.pressure_MPa, param=f"{args.measured}: pressure_MPa")
    if args.filter:
        from hardware.filtering import filtfilt

        opt = {k: filtfilt(v) for k, v in m.optional.items()}
        m = Measurement.from_arrays(
            time_s=m.time_s,
            pressure_MPa=filtfilt(m.pressure_MPa),
            curvature_per_mm=filtfilt(m.curvature_per_mm),
            run=m.run,
            source=m.source,
            **opt,
        )
    free = tuple(s.strip() for s in args.free.split(",") if s.strip())
    if args.grid ** max(len(free), 1) > 10_000:  # the multistart grid: grid^len(free) IPOPT starts
        raise design.DesignError(
            "--grid", args.grid, f"gives {args.grid}^{len(free)} starts; at most 10000 (use a smaller --grid)"
        )
    res = calibrate(m, d, free=free, load=args.load, grid=args.grid)
    doc = res.to_json()
    check_finite_json(doc)  # a failed fit is refused before any earlier good output is touched
    with Outputs(out) as o:
        o.json("calibration.json", doc)
        o.text(
            "calibrated_design.toml",
            design.dumps(res.design, header=f"calibrated by softcath from {m.source}"),
        )
        calibration_plot(
            o.path("calibration.png"),
            m,
            nominal=analytic.response(d, m.pressure_MPa, args.load),
            optimized=analytic.response(res.design, m.pressure_MPa, args.load),
            title=f"{d.name}: eq. 8 calibration, NRMSE ratio nominal/optimised = {res.ratio:.3g}",
        )
    x = res.x_opt
    print(
        f"x_opt = [a {x['a']:.4f}, a_int {x['a_int']:.4f}, b_int {x['b_int']:.4f}, h {x['h']:.4f}] mm; "
        f"NRMSE {res.nrmse_nominal:.4g} -> {res.nrmse_optimized:.4g} (ratio {res.ratio:.3g}); "
        f"{res.starts_at_optimum}/{res.starts} starts at the optimum"
    )
    print(res.message)
    print(f"wrote {out}/calibration.json, calibration.png, calibrated_design.toml")
    return 0
