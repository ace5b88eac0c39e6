"""Turn the two real lab data sets' own files into measurement CSVs (docs/measurement-csv.md).

The data are not in this repository (no licence was stated; see
docs/realdata.md): they are read from ``../shared/realdata`` next to the
checkout (or ``--source``) and written to ``--out``, which must lie outside
the repository.

    python examples/realdata/convert.py --out /tmp/realdata

writes

* ``ijpelaar_steps.csv``: the IJpelaar two-chamber pneumatic actuator, one run
  per single-chamber phase (``16069V_A``, ``16069V_B``, ``16067V_A``,
  ``16067V_B``, ``stepside_A``); ``time_s`` restarts at 0 in every run; the
  pressure is the driven chamber's gauge pressure and the curvature, tip x and
  bend angle are signed so that the driven chamber's bend is positive. The
  other chamber's pressure is kept as the extra column
  ``other_chamber_pressure_MPa``. Phases with both chambers driven are left
  out (no single driving pressure).
* ``marchese_static.csv`` and one ``marchese_<segment>.csv`` per segment
  (ribbed, cylindrical, pleated): quasi-static loading, ``time_s`` is the step
  index, ``volume_mL`` (supplied volume) is an extra column.
* a stand-in design per actuator (``ijpelaar_two_chamber.toml``,
  ``marchese_<segment>.toml``), made here from the converted data rather than
  kept in the repository: the paper's catheter with every Young's modulus (and
  Yeoh coefficient) divided by the factor that brings its formula gain (eq. 7,
  which scales as 1/E) to the data's line-fit gain, and the bending length set
  to the actuator's. It says nothing about the actuator's geometry; it gives
  calibrate and discrepancy a nominal model in the right range.

Source layouts (from each folder's PROVENANCE.md):

* IJpelaar ``raw/*.txt``: ``;``-separated, no header, 25 Hz; columns 0 t [s],
  1 p1 [mbar], 2 p01 [mbar, reference], 3 p2, 4 p02, 5 u1, 6 u2 [pump DAC
  counts], 7 x [m], 8 y [m], 9 kappa [1/m], 10 epsilon [-], 11 angle [deg];
  gauge pressure (p - p0) * 1e-4 MPa; L0 = 70 mm.
* Marchese ``raw_extracted.csv``: segment, step, voltage_V, piston_bits,
  curvature_per_m, length_m; pressure (V - V0) * 15/4 psi/V; volume
  bits * 5/4096 cm * pi (3.81 cm / 2)^2.
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from softcath.design.errors import DataError  # noqa: E402
from softcath.design.measurement import Measurement, write_measurement_csv  # noqa: E402

DEFAULT_SOURCE = ROOT.parent / "shared" / "realdata"
IJPELAAR = "ijpelaar_two_chamber_pneumatic"
MARCHESE = "marchese_recipe_static"
IJPELAAR_FILES = ("16069V.txt", "16067V.txt", "stepside.txt")
L0_MM = 70.0  # the author's initial length of the actuator
KPA_PER_PSI = 6.89475729
PSI_PER_VOLT = 15.0 / 4.0  # 15 psi transducer over 0.5-4.5 V
ML_PER_BIT = 5.0 / 4096 * math.pi * (3.81 / 2) ** 2  # piston travel (cm) times area (cm^2)


def _read_ijpelaar(path: Path) -> np.ndarray:
    rows = []
    with path.open() as fh:
        for n, line in enumerate(fh, start=1):
            if line.strip():
                try:
                    rows.append([float(v) for v in line.split(";")[:12]])
                except ValueError:
                    raise DataError(f"{path}: line {n}: not 12 ';'-separated numbers") from None
    return np.array(rows)


def _phases(u1: np.ndarray, u2: np.ndarray) -> list[tuple[str, int, int]]:
    """(label, first, end) per phase: a pump switches on, then everything is off until the next."""
    on = (u1 > 0) | (u2 > 0)
    starts = [i for i in range(1, on.size) if on[i] and not on[i - 1]]
    bounds = [0, *starts[1:], on.size]
    out = []
    for k, s in enumerate(starts):
        label = "AB" if (u1[s] > 0 and u2[s] > 0) else ("A" if u1[s] > 0 else "B")
        out.append((label, bounds[k], bounds[k + 1]))
    return out


def convert_ijpelaar(source: Path, out: Path) -> Path:
    """The single-chamber phases of the three IJpelaar logs as one measurement CSV."""
    cols: dict[str, list[np.ndarray]] = {
        k: []
        for k in (
            "time_s",
            "pressure_MPa",
            "curvature_per_mm",
            "arc_length_mm",
            "tip_x_mm",
            "tip_y_mm",
            "bend_angle_rad",
            "other_chamber_pressure_MPa",
        )
    }
    runs = []
    for name in IJPELAAR_FILES:
        a = _read_ijpelaar(source / IJPELAAR / "raw" / name)
        pa, pb = (a[:, 1] - a[:, 2]) * 1e-4, (a[:, 3] - a[:, 4]) * 1e-4
        for label, i, j in _phases(a[:, 5], a[:, 6]):
            if label == "AB":
                continue  # both chambers driven: no single pressure drives the bend
            sign = 1.0 if label == "A" else -1.0  # chamber B bends the other way
            r = a[i:j]
            cols["time_s"].append(r[:, 0] - r[0, 0])
            cols["pressure_MPa"].append((pa if label == "A" else pb)[i:j])
            cols["other_chamber_pressure_MPa"].append((pb if label == "A" else pa)[i:j])
            cols["curvature_per_mm"].append(sign * r[:, 9] * 1e-3)
            cols["arc_length_mm"].append(L0_MM * (1 + r[:, 10]))
            # the camera's x axis points away from chamber A's bend
            cols["tip_x_mm"].append(-sign * r[:, 7] * 1e3)
            cols["tip_y_mm"].append(r[:, 8] * 1e3)
            cols["bend_angle_rad"].append(sign * np.radians(r[:, 11]))
            runs.append(np.full(j - i, f"{name.removesuffix('.txt')}_{label}"))
    import pandas as pd

    table = pd.DataFrame({k: np.concatenate(v) for k, v in cols.items()})
    table["run"] = np.concatenate(runs)
    m = Measurement.from_table(table, source=str(source / IJPELAAR / "raw"))
    return write_measurement_csv(out / "ijpelaar_steps.csv", m)


def convert_marchese(source: Path, out: Path) -> list[Path]:
    """The three segments' quasi-static loading points: one CSV for all, one per segment."""
    import pandas as pd

    path = source / MARCHESE / "raw_extracted.csv"
    try:
        with path.open(newline="") as fh:
            raw = list(csv.DictReader(fh))
        table = pd.DataFrame(
            {
                "time_s": [float(r["step"]) for r in raw],  # a step index: no clock was recorded
                "pressure_MPa": [float(r["voltage_V"]) for r in raw],
                "curvature_per_mm": [float(r["curvature_per_m"]) * 1e-3 for r in raw],
                "bend_angle_rad": [float(r["curvature_per_m"]) * float(r["length_m"]) for r in raw],
                "volume_mL": [int(r["piston_bits"]) * ML_PER_BIT for r in raw],
                "run": [f"marchese_{r['segment']}" for r in raw],
            }
        )
    except FileNotFoundError:
        raise DataError(f"{path}: file not found") from None
    except (KeyError, ValueError) as exc:
        raise DataError(f"{path}: unexpected layout ({exc})") from None
    # the transducer's voltage over its value at step 0 of each segment, as the authors zeroed it
    v0 = table.groupby("run")["pressure_MPa"].transform("first")
    table["pressure_MPa"] = (table["pressure_MPa"] - v0) * PSI_PER_VOLT * KPA_PER_PSI * 1e-3
    written = [
        write_measurement_csv(out / "marchese_static.csv", Measurement.from_table(table, source=str(path)))
    ]
    for run, g in table.groupby("run", sort=False):
        m = Measurement.from_table(g.reset_index(drop=True), source=f"{path} ({run})")
        written.append(write_measurement_csv(out / f"{run}.csv", m))
    return written


def stand_in(csv_path: Path, name: str, *, length_mm: float) -> Path:
    """Write ``NAME.toml`` beside ``csv_path``: the paper design scaled to the data's gain (module
    docstring)."""
    import tomllib

    from softcath import analytic, design
    from softcath.design import presets
    from softcath.design.measurement import read_measurement_csv

    m = read_measurement_csv(csv_path)
    p, k = m.pressure_MPa, m.curvature_per_mm
    gain = float(p @ k / (p @ p))  # least-squares line through the origin, 1/(mm MPa)
    table = tomllib.loads(presets.text("paper"))
    # dividing every modulus by the factor multiplies the formula gain by it
    factor = round(gain / analytic.gains(design.from_dict(table), "cap")[0], 2)
    if not (math.isfinite(factor) and factor > 0):
        raise DataError(f"{csv_path}: line-fit gain {gain:g} 1/(mm MPa) cannot scale a stand-in design")
    table["name"] = name
    table["tip"]["bending_length"] = float(length_mm)
    for mat in table["materials"].values():
        mat["youngs_modulus"] = mat["youngs_modulus"] / factor
        if "yeoh" in mat:
            mat["yeoh"] = [c / factor for c in mat["yeoh"]]
        mat["source"] = f"{mat.get('source', '')}; divided by {factor:g} for the stand-in"
    header = (
        f"Stand-in for {name} (made by examples/realdata/convert.py from {csv_path.name}): the paper's\n"
        f"catheter with every modulus divided by {factor:g} (its formula gain becomes the data's line-fit\n"
        f"gain {gain:.3g} 1/(mm MPa)) and the bending length set to the actuator's {length_mm:g} mm.\n"
        "NOT a model of the actuator's geometry; see docs/realdata.md."
    )
    path = csv_path.parent / f"{name}.toml"
    design.save(design.from_dict(table), path, header=header)
    return path


def _segment_lengths_mm(source: Path) -> dict[str, float]:
    """Median length of each Marchese segment over its loading steps (mm)."""
    with (source / MARCHESE / "raw_extracted.csv").open(newline="") as fh:
        raw = list(csv.DictReader(fh))
    lengths: dict[str, list[float]] = {}
    for r in raw:
        lengths.setdefault(r["segment"], []).append(1e3 * float(r["length_m"]))
    return {seg: float(np.median(v)) for seg, v in lengths.items()}


def convert_all(source: Path = DEFAULT_SOURCE, out: Path | None = None) -> dict[str, list[Path]]:
    """Convert both data sets; returns the files written per data set."""
    if out is None:
        raise DataError("--out is required (a folder outside the repository)")
    out = Path(out).resolve()
    if out == ROOT or ROOT in out.parents:
        raise DataError(
            f"--out {out}: inside the repository {ROOT}; the data must stay out of it (no licence)"
        )
    source = Path(source)
    if not source.is_dir():
        raise DataError(f"{source}: no such folder (the real data sets live in ../shared/realdata)")
    out.mkdir(parents=True, exist_ok=True)
    files = {"ijpelaar": [convert_ijpelaar(source, out)], "marchese": convert_marchese(source, out)}
    designs = [stand_in(files["ijpelaar"][0], "ijpelaar_two_chamber", length_mm=L0_MM)]
    for seg, length in _segment_lengths_mm(source).items():
        designs.append(stand_in(out / f"marchese_{seg}.csv", f"marchese_{seg}", length_mm=length))
    files["stand_ins"] = designs
    return files


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--source", type=Path, default=DEFAULT_SOURCE, help="the realdata folder")
    ap.add_argument("--out", type=Path, required=True, help="output folder (outside the repository)")
    args = ap.parse_args(argv)
    try:
        files = convert_all(args.source, args.out)
    except DataError as exc:
        print(f"convert.py: error: {exc}", file=sys.stderr)
        return 2
    for paths in files.values():
        for p in paths:
            print(f"wrote {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
