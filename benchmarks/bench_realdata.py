"""The two real lab data sets through calibration and the missing-effect workflow.

Reads ``../shared/realdata`` (next to the checkout; ``--source`` to point
elsewhere), converts each data set's own files with
``examples/realdata/convert.py`` into a temporary folder (the data stay out of
the repository: no licence), and for each file prints the calibrated data gain
with its standard error, the effects the workflow names (parameters ± s.e.),
what it cannot separate, the held-out NRMSE before/after and the run time.
Exits 0 with a message when the folder is absent.

    python benchmarks/bench_realdata.py [--source DIR] [--json out.json]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from softcath import design  # noqa: E402
from softcath.analytic.calibration import calibrate  # noqa: E402
from softcath.design.measurement import read_measurement_csv  # noqa: E402
from softcath.studies.discrepancy import run_workflow  # noqa: E402

EXAMPLES = ROOT / "examples" / "realdata"
#: converted file -> the stand-in design the converter writes beside it (docs/realdata.md)
CASES = {
    "ijpelaar_steps.csv": "ijpelaar_two_chamber",
    "marchese_ribbed.csv": "marchese_ribbed",
    "marchese_cylindrical.csv": "marchese_cylindrical",
    "marchese_pleated.csv": "marchese_pleated",
    # all three segments as one file: one gain cannot serve them, and calibration says so
    "marchese_static.csv": "marchese_cylindrical",
}


def _converter():
    spec = importlib.util.spec_from_file_location("realdata_convert", EXAMPLES / "convert.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def one(csv: Path, stand_in: str) -> dict:
    d = design.load(csv.parent / f"{stand_in}.toml")
    m = read_measurement_csv(csv)
    t0 = time.perf_counter()
    cal = calibrate(m, d, use_elongation=False)
    t_cal = time.perf_counter() - t0
    t0 = time.perf_counter()
    r = run_workflow(m, d)
    t_disc = time.perf_counter() - t0
    return {
        "file": csv.name,
        "design": stand_in,
        "rows": len(m),
        "runs": len(m.runs),
        "excitation": sorted({x["kind"] for x in r.runs}),
        "gain": cal.gains_data["curvature_per_mm_per_MPa"],
        "gain_stderr": cal.gain_data_stderr,
        "gain_by_group": cal.gain_data_by_group,
        "calibration_message": cal.message,
        "calibrate_s": t_cal,
        "named": list(r.named),
        "steps": [
            {
                "effect": s["effect"],
                "params": s["params"],
                "stderr": s["params_stderr"],
                "coefficient": s["coefficient"],
                "ambiguous_with": s["ambiguous_with"],
            }
            for s in r.steps
        ],
        "nrmse_before": r.nrmse_before,
        "nrmse_after": r.nrmse_after,
        "noise_floor_nrmse": r.noise_floor_nrmse,
        "notes": list(r.notes),
        "discrepancy_s": t_disc,
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--source", type=Path, default=ROOT.parent / "shared" / "realdata")
    ap.add_argument("--json", type=Path)
    args = ap.parse_args()
    if not args.source.is_dir():
        print(f"bench_realdata: {args.source} is absent: skipped (the real data are not in the repository)")
        return 0
    convert = _converter()
    rows = []
    with tempfile.TemporaryDirectory(prefix="softcath-realdata-") as tmp:
        convert.convert_all(args.source, Path(tmp))
        for name, stand_in in CASES.items():
            rows.append(one(Path(tmp) / name, stand_in))
    for r in rows:
        se = f" ± {r['gain_stderr']:.2g}" if r["gain_stderr"] is not None else ""
        print(
            f"\n== {r['file']} ({r['rows']} rows, {r['runs']} run(s), {', '.join(r['excitation'])}; "
            f"stand-in {r['design']})"
        )
        print(f"  data gain {r['gain']:.4g}{se} 1/(mm MPa)   calibrate {r['calibrate_s']:.2f} s")
        if r["gain_by_group"] and len(r["gain_by_group"]) > 1:
            g = r["gain_by_group"]
            print("  per group: " + ", ".join(f"{k} {v:.3g}" for k, v in g.items()))
        print(f"  named: {' + '.join(r['named']) or 'nothing'}")
        for s in r["steps"]:
            est = ", ".join(
                f"{k} {v:.3g}" + (f" ± {s['stderr'][k]:.2g}" if s["stderr"].get(k) is not None else "")
                for k, v in s["params"].items()
            )
            if s["coefficient"] is not None:
                est = f"coefficient {s['coefficient']:.3g}"
            amb = f"  (cannot tell from {', '.join(s['ambiguous_with'])})" if s["ambiguous_with"] else ""
            print(f"    {s['effect']}: {est}{amb}")
        print(
            f"  held-out NRMSE {r['nrmse_before']:.4f} -> {r['nrmse_after']:.4f} "
            f"(ratio {r['nrmse_before'] / r['nrmse_after']:.2f}, noise floor {r['noise_floor_nrmse']:.2g})"
            f"   discrepancy {r['discrepancy_s']:.1f} s"
        )
        for n in r["notes"]:
            print(f"  note: {n}")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1, default=float))
    return 0


if __name__ == "__main__":
    sys.exit(main())
