"""Run the virtual bench: virtual stage, pressure sensor, encoder and camera on pseudo-terminals.

The plant is the analytic model of DESIGN plus optional hidden effects
(--effect NAME or NAME:param=value,...; repeatable). Everything is recorded
through the real recorder and tip-measurement pipeline. Outputs in DIR:
run.csv (the measurement schema with a run column per excitation
frequency, plus encoder_mm), frames.avi (the virtual camera), truth.json
(plant, excitation, noise, seed, device statistics), truth.csv (the noise-free
truth on the 200 Hz base) and bench.png. Deterministic for a given --seed.
"""

from __future__ import annotations

import argparse

from softcath import design
from softcath.cli.options import add_design, add_out, add_seed
from softcath.core.atomic import prepare_out_dir, staged_dir, unstage
from softcath.core.errors import DesignError
from softcath.core.plotting import pyplot
from softcath.design.measurement import read_recording
from softcath.virtualbench.bench import BenchConfig, make_plant, run_bench

HELP = "virtual bench: simulated devices and camera recorded through the real pipeline"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of ``softcath bench``."""
    add_design(parser, optional=True)
    parser.add_argument(
        "--effect",
        action="append",
        default=[],
        metavar="NAME[:k=v,...]",
        help="hidden plant effect: hysteresis, lag, delay, dead_zone, "
        "viscoelastic, offset, nonlinear_gain (repeatable)",
    )
    parser.add_argument("--waveform", choices=("sine", "triangle", "steps"), default="sine")
    parser.add_argument(
        "--freq", default="0.5,1", metavar="F1,F2,...", help="excitation frequencies, Hz (default 0.5,1)"
    )
    parser.add_argument("--cycles", type=int, default=2, help="cycles per frequency (2)")
    parser.add_argument(
        "--pressure-max", type=float, default=2.0, metavar="MPA", help="peak pressure, MPa (2)"
    )
    parser.add_argument(
        "--noise",
        type=float,
        default=1.0,
        metavar="LEVEL",
        help="noise multiplier: 1 = 2 kPa sensor, 2 grey levels camera (1)",
    )
    add_seed(parser, what="random seed of the sensors' noise")
    parser.add_argument("--fps", type=float, default=50.0, help="camera frame rate, Hz (50)")
    parser.add_argument(
        "--method", choices=("default", "paper"), default="default", help="tip measurement method"
    )
    parser.add_argument(
        "--load", choices=("cap", "lumen"), default="cap", help="analytic load case of the plant"
    )
    add_out(parser)


def parse_effect(text: str) -> tuple[str, dict[str, float | int]]:
    """``"lag:tau_s=0.2"`` -> ``("lag", {"tau_s": 0.2})``."""
    name, _, rest = text.partition(":")
    params: dict[str, float | int] = {}
    for item in filter(None, rest.split(",")):
        key, eq, value = item.partition("=")
        try:
            if not eq:
                raise ValueError(item)
            v = value.strip()
            params[key.strip()] = int(v) if v.lstrip("+-").isdigit() else float(v)  # counts stay int
        except ValueError as exc:
            raise DesignError("--effect", text, "must look like NAME or NAME:key=value,...") from exc
    return name.strip(), params


def _plot(out, truth_csv, run_csv) -> None:
    plt = pyplot()

    d = read_recording(run_csv)
    tr = read_recording(truth_csv)
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    ax[0].plot(d["time_s"], d["curvature_per_mm"], lw=0.8, label="measured (camera)")
    ax[0].plot(tr["time_s"], tr["curvature_per_mm"], "k--", lw=0.8, label="plant truth")
    ax[0].set_xlabel("time [s]")
    ax[0].set_ylabel("curvature [1/mm]")
    ax[0].legend()
    for run in dict.fromkeys(d["run"]):
        sel = d["run"] == run
        ax[1].plot(d["pressure_MPa"][sel], d["curvature_per_mm"][sel], lw=0.6, label=run)
    ax[1].set_xlabel("pressure [MPa]")
    ax[1].set_ylabel("curvature [1/mm]")
    ax[1].legend()
    fig.suptitle("softcath virtual bench")
    fig.tight_layout()
    fig.savefig(out / "bench.png", dpi=110)
    plt.close(fig)


def run(args: argparse.Namespace) -> int:
    """Run ``softcath bench``."""
    from pathlib import Path

    try:
        freqs = tuple(float(f) for f in args.freq.split(",") if f.strip())
    except ValueError as exc:
        raise DesignError("--freq", args.freq, "must be numbers F1,F2,... in Hz") from exc
    if not 0 <= args.seed < 2**63:
        raise DesignError("--seed", args.seed, "must be an integer >= 0")
    d = design.resolve(args.design)
    cfg = BenchConfig(
        waveform=args.waveform,
        freqs_hz=freqs,
        cycles=args.cycles,
        pressure_max_MPa=args.pressure_max,
        noise=args.noise,
        seed=args.seed,
        fps=args.fps,
        method=args.method,
    )
    effects = [parse_effect(e) for e in args.effect]

    make_plant(d, effects=effects, load=args.load)  # bad effect names or parameters fail here, first

    out = prepare_out_dir(args.out)
    print(
        f"virtual bench: {cfg.waveform} at {', '.join(f'{f:g}' for f in freqs)} Hz, "
        f"{cfg.cycles} cycles, 0..{cfg.pressure_max_MPa:g} MPa, {cfg.duration_s:.1f} s of data"
    )
    from tqdm import tqdm

    total = int(round(cfg.duration_s * 200)) + 1
    bar = tqdm(total=total, unit="row", leave=False)

    def progress(rows: int, _n: int) -> None:
        bar.update(rows - bar.n)

    with staged_dir(out) as stage:  # the run's files replace an earlier run's only as a whole
        try:
            res = run_bench(
                d,
                stage,
                cfg,
                effects=effects,
                load=args.load,
                design_label=str(args.design),
                progress=progress,
            )
        finally:
            bar.close()
        _plot(stage, stage / "truth.csv", Path(res.run_csv))
    run_csv, frames_avi, truth_json = (
        unstage(p, stage, out) for p in (res.run_csv, res.frames_avi, res.truth_json)
    )
    print(
        f"wrote {run_csv} ({res.rows} rows), {frames_avi} ({res.frames} frames), "
        f"{truth_json}, {out / 'bench.png'}"
    )
    eff = ", ".join(n for n, _ in effects) or "none"
    print(f"plant effects: {eff}; frames without a tip: {res.frames_without_tip}")
    print(
        f"camera vs plant truth: curvature RMS error {res.curvature_rms_error_per_mm:.2e} 1/mm "
        f"(peak curvature {res.curvature_peak_per_mm:.4f} 1/mm)"
    )
    return 0
