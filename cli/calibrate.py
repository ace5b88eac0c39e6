"""Fit the tube's as-assembled shape to a measurement CSV (paper eq. 8, CasADi + IPOPT multistart).

``--model paper`` (default) fits through the paper's formula; ``--model section``
through the 2-D section model (space mapping: the formula's gains times the
section model's correction factors, iterated to the section model's own
optimum; default load lumen, the real one).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from softcath import analytic, design, models
from softcath.analytic.calibration import calibrate
from softcath.cli.options import add_design, add_out, model_name
from softcath.core.atomic import Outputs, check_finite_json, prepare_out_dir
from softcath.core.limits import check_pressure
from softcath.design.measurement import Measurement, read_measurement_csv
from softcath.fem.section_model import section_model
from softcath.fem.section_model.calibration import calibrate_section
from softcath.hardware.filtering import filtfilt
from softcath.studies.plots import calibration_plot

HELP = "the paper's ellipse shape optimisation against a measurement CSV"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_design(p, optional=True)
    p.add_argument(
        "measured", type=Path, help="measurement CSV (time_s, pressure_MPa, curvature_per_mm, ...)"
    )
    add_out(p)
    p.add_argument(
        "--free",
        default="a,a_int,b_int,h",
        help="shape parameters to optimise (default: all four, as the paper)",
    )
    p.add_argument(
        "--model",
        type=model_name,
        choices=("paper", "section"),
        default="paper",
        help="paper: the paper's formula (default); section: the 2-D section model (3-D-FEM grade)",
    )
    p.add_argument(
        "--load",
        choices=("cap", "lumen"),
        default=None,
        help="load model (default: cap for the paper's formula, lumen for the section model)",
    )
    p.add_argument(
        "--grid", type=int, default=3, help="multistart grid points per free parameter (default 3)"
    )
    p.add_argument("--filter", action="store_true", help="apply the paper's IIR low-pass to all series first")


#: Most multistart points (grid^free IPOPT starts) and grid points per parameter.
MAX_STARTS = 10_000
MAX_GRID = 20


def _grid_max(n_free: int) -> int:
    """Largest ``--grid`` with ``n_free`` free parameters: grid^n_free <= MAX_STARTS, grid <= MAX_GRID."""
    g = MAX_GRID
    while g > 1 and g ** max(n_free, 1) > MAX_STARTS:
        g -= 1
    return g


def run(args: argparse.Namespace) -> int:
    free = tuple(s.strip() for s in args.free.split(",") if s.strip())
    _check_grid(args.grid, free)
    d = design.resolve(args.design)
    m = _read_measurement(args.measured, args.filter)
    out = prepare_out_dir(args.out)  # after every input is read and checked
    tier = models.get(args.model)
    load = args.load or tier.default_load
    if tier.closed_form:  # the formula's gains fit the shape directly
        res = calibrate(m, d, free=free, load=load, grid=args.grid)

        def model(dd):
            return analytic.response(dd, m.pressure_MPa, load)

        what = f"paper's formula, {load} load"
    else:  # the section model: space mapping on the formula's gains
        res = calibrate_section(m, d, free=free, load=load, grid=args.grid)

        def model(dd):
            return section_model(dd, loads=(load,)).response(m.pressure_MPa, load)

        what = f"section model, {load} load"
    if getattr(res, "usable", True) is False:
        # A calibration that neither converged nor reached the data is not a calibrated design:
        # nothing is written (earlier outputs stay as they were) and the command fails with the
        # reason. One that reaches the data with a shape the data cannot pin is a result, and
        # calibration.json says so ("identifiable": false).
        raise design.DataError(
            f"{res.message}; nothing written (no calibrated_design.toml): free fewer parameters "
            "(--free) or check the measurement"
        )
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
            nominal=model(d),
            optimized=model(res.design),
            title=f"{d.name}: eq. 8 calibration ({what}), NRMSE ratio nominal/optimised = {res.ratio:.3g}",
        )
    x = res.x_opt
    inner = getattr(res, "inner", res)
    print(
        f"{what}: x_opt = [a {x['a']:.4f}, a_int {x['a_int']:.4f}, b_int {x['b_int']:.4f}, h {x['h']:.4f}] "
        f"mm; NRMSE {res.nrmse_nominal:.4g} -> {res.nrmse_optimized:.4g} (ratio {res.ratio:.3g}); "
        f"{inner.starts_at_optimum}/{inner.starts} starts at the optimum"
    )
    if not tier.closed_form:  # the space mapping's iterations and gains
        g, dg = res.gains_model, res.gains_data
        print(
            f"{res.iterations} space-mapping iteration(s), "
            f"{'converged' if res.converged else 'reaches the data, shape not identified'}; "
            f"section-model gains {g['curvature_per_mm_per_MPa']:.5g} 1/(mm MPa), "
            f"{g['elongation_per_MPa']:.4g} "
            f"1/MPa vs data {dg['curvature_per_mm_per_MPa']:.5g}, "
            + (f"{dg['elongation_per_MPa']:.4g}" if dg["elongation_per_MPa"] is not None else "-")
        )
    print(res.message)
    print(f"wrote {out}/calibration.json, calibration.png, calibrated_design.toml")
    return 0


def _check_grid(grid: int, free: tuple[str, ...]) -> None:
    """Refuse a ``--grid`` beyond the multistart budget of ``free``."""
    grid_max = _grid_max(len(free))
    if not 1 <= grid <= grid_max:  # one bound, stated once: grid^len(free) IPOPT starts
        raise design.DesignError(
            "--grid",
            grid,
            f"must be an integer in [1, {grid_max}] with {len(free)} free parameter(s) (grid^{len(free)} "
            f"multistart points, at most {MAX_STARTS}, and at most {MAX_GRID} per parameter)",
        )


def _read_measurement(path: Path, low_pass: bool):
    """Read and check the measurement CSV; with ``low_pass`` filter every series."""
    m = read_measurement_csv(path)
    check_pressure(m.pressure_MPa, param=f"{path}: pressure_MPa")
    if low_pass:
        opt = {k: filtfilt(v) for k, v in m.optional.items()}
        m = Measurement.from_arrays(
            time_s=m.time_s,
            pressure_MPa=filtfilt(m.pressure_MPa),
            curvature_per_mm=filtfilt(m.curvature_per_mm),
            run=m.run,
            source=m.source,
            **opt,
        )
    return m
