"""Property-based fuzzing of every command (hypothesis): TOML designs, sweep specs, selection
expressions, numeric options (not CSV content: tests/analytic/test_measurement_csv.py).

The property, for every input: exit 0 with finite outputs, or exit 2 with one line
``softcath CMD: error: ...`` naming the parameter; never a traceback, a NaN in a JSON
output, or an earlier good output destroyed. Commands whose valid runs take seconds
(fem, bench, record, discrepancy, demo) are fuzzed on the inputs they must refuse before
any work; the others on everything. Runs in-process through ``softcath.cli.main.main``.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, assume, event, given, settings
from hypothesis import strategies as st

from softcath import design
from softcath.fem.limits import check_fem_budget

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "studies" / "data"


def fuzz(examples: int) -> settings:
    """Reproducible, fast fuzzing: fixed examples (derandomised, no database), no per-example deadline."""
    return settings(
        max_examples=examples,
        deadline=None,
        derandomize=True,
        database=None,
        suppress_health_check=[HealthCheck.function_scoped_fixture],
    )


_counter = itertools.count()

# numbers as a user may type them: ordinary, extreme, non-finite, not numbers at all
anything_numeric = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-(10**6), 10**6).map(str),
    st.sampled_from(
        ["0", "-0", "1e300", "-1e300", "nan", "inf", "-inf", "1e-300", "", " ", "x", "1,2", "0x10"]
    ),
)


def _strict_json(path: Path) -> None:
    json.loads(path.read_text(encoding="utf-8"), parse_constant=lambda c: pytest.fail(f"{c} in {path}"))


def _digest(folder: Path) -> dict[str, str]:
    if not folder.is_dir():
        return {}
    files = [p for p in sorted(folder.rglob("*")) if p.is_file() and not p.name.startswith(".")]
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest() for p in files}


def _check(r, out: Path | None, before: dict[str, str], names: tuple[str, ...]) -> None:
    """The property: a finite success, or a one-line refusal naming one of ``names`` that kept ``out``."""
    assert r.status in (0, 2), (r.status, r.err)
    assert "Traceback" not in r.err, r.err
    event(f"exit {r.status}")
    if r.status == 0:
        for path in out.rglob("*.json") if out is not None and out.is_dir() else ():
            _strict_json(path)
        return
    line = r.error_line()
    norm = line.replace("-", "_")
    assert any(n in line or n.lstrip("-").replace("-", "_") in norm for n in names), (names, line)
    if out is not None:
        assert _digest(out) == before, line


def _out(tmp_path: Path, name: str) -> Path:
    return tmp_path / f"{name}{next(_counter)}"


# --- analytic -------------------------------------------------------------------------------------


pressure_specs = st.one_of(
    anything_numeric,
    st.tuples(anything_numeric, anything_numeric, anything_numeric).map(":".join),
    st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.integers(-3, 50)).map(lambda t: f"{t[0]}:{t[1]}:{t[2]}"),
)


@fuzz(15)
@given(spec=pressure_specs, load=st.sampled_from(["cap", "lumen"]))
def test_analytic(cli, tmp_path, spec, load):
    out = tmp_path / "a"  # one folder for every example: a refusal must keep the last good result
    before = _digest(out)
    r = cli("analytic", "paper", f"--pressure={spec}", "--load", load, "--out", out)
    _check(r, out, before, ("--pressure",))
    if r.status == 0:
        df = pd.read_csv(out / "analytic.csv")
        assert np.isfinite(df.to_numpy()).all() and len(df) >= 1


# --- design ----------------------------------------------------------------------------------------


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return json.dumps(str(v))


def _dump(table: dict) -> str:
    lines = [f"name = {_toml_value(table['name'])}"]
    for key, sub in table.items():
        if key in ("name", "materials"):
            continue
        lines += [f"[{key}]"] + [f"{k} = {_toml_value(v)}" for k, v in sub.items()]
    for mkey, m in table["materials"].items():
        lines += [f"[materials.{mkey}]"] + [f"{k} = {_toml_value(v)}" for k, v in m.items()]
    return "\n".join(lines) + "\n"


PAPER = design.to_dict(design.preset("paper"))
FIELDS = [(k, f) for k, sub in PAPER.items() if isinstance(sub, dict) and k != "materials" for f in sub] + [
    (f"materials.{m}", f) for m, sub in PAPER["materials"].items() for f in sub if f not in ("name", "source")
]
field_values = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(-1.0, 1.0),
    st.integers(-3, 10**6),
    st.sampled_from(["", "steel", "none", True]),
    st.just([0.017, -0.0002]),
)


@fuzz(40)
@given(
    changes=st.lists(
        st.tuples(
            st.sampled_from(FIELDS),
            st.one_of(field_values, *[st.floats(0.97, 1.03).map(lambda f: ("scale", f))] * 4),
        ),
        min_size=1,
        max_size=3,
    )
)
def test_design_toml(cli, tmp_path, changes):
    table = json.loads(json.dumps(PAPER))
    for (part, field), value in changes:
        node = table
        for k in part.split("."):
            node = node[k]
        if isinstance(value, tuple):  # a plausible change: the paper's value scaled
            old = node[field]
            value = old * value[1] if isinstance(old, float) else old
        node[field] = value
    path = tmp_path / "d.toml"
    path.write_text(_dump(table), encoding="utf-8")
    names = tuple({f for (_, f), _ in changes} | {p.split(".")[-1] for (p, _), _ in changes}) + (
        "tube.",
        "coil.",
        "channel.",
        "tip.",
        "filler",
        "material",
    )
    for argv in (["design", "validate", path], ["design", "show", path]):
        r = cli(*argv)
        _check(r, None, {}, names)
        if r.status == 0:
            nums = [float(x) for x in re.findall(r"[-+]?\d+\.?\d*(?:e[-+]?\d+)?", r.out)]
            assert all(math.isfinite(x) for x in nums)
            assert "nan" not in r.out.lower().split() and "inf" not in r.out.lower().split()


# --- sweep -----------------------------------------------------------------------------------------


BAD_NUMBERS = [math.nan, math.inf, -math.inf, 1e300, -1.0, "x", True]


@st.composite
def sweep_specs(draw):
    """A valid small spec, then (two times in three) one field replaced by a bad value."""
    fields = {
        "h": draw(st.lists(st.floats(-0.05, 0.05), min_size=1, max_size=3)),
        "pressures": draw(st.lists(st.floats(0, 2), min_size=1, max_size=3)),
        "grid": [draw(st.floats(3.0, 5.0)), draw(st.floats(5.0, 7.0)), draw(st.integers(1, 3))],
        "chunk": draw(st.integers(1, 4)),
    }
    bad = draw(st.sampled_from([None, "h", "pressures", "grid", "chunk"]))
    if bad == "h":
        fields["h"] = draw(st.lists(st.sampled_from(BAD_NUMBERS), max_size=2))
    elif bad == "pressures":
        fields["pressures"] = draw(st.lists(st.sampled_from([*BAD_NUMBERS, 1e6]), max_size=2))
    elif bad == "grid":
        fields["grid"][draw(st.integers(0, 2))] = draw(st.sampled_from([*BAD_NUMBERS, 0, 10**9]))
    elif bad == "chunk":
        fields["chunk"] = draw(st.sampled_from([0, -1, "2", 1.5]))
    return fields


@fuzz(30)
@given(f=sweep_specs())
def test_sweep_spec(cli, tmp_path, f):
    spec = tmp_path / f"spec{next(_counter)}.toml"
    spec.write_text(
        f'[sweep]\nbase = "paper"\npressures_MPa = {_toml_value(f["pressures"])}\n'
        f"chunk_size = {_toml_value(f['chunk'])}\n"
        f'[parameters]\n"tube.h" = {{ values = {_toml_value(f["h"])} }}\n'
        f'"tip.bending_length" = {{ grid = {_toml_value(f["grid"])} }}\n'
    )
    out = _out(tmp_path, "s")
    r = cli("sweep", spec, "--out", out, "--workers", "1", "--no-progress")
    _check(r, out, {}, ("sweep.", "parameters.", "spec"))
    if r.status == 0:
        df = pd.read_parquet(out / "results.parquet")
        ok = df[df.status == "ok"]
        assert np.isfinite(ok[["curvature_analytic_per_mm", "bend_angle_analytic_rad"]].to_numpy()).all()


# --- select and report -----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def sweep_dir(tmp_path_factory):
    from softcath.cli.main import main

    root = tmp_path_factory.mktemp("fuzz-sweep")
    spec = root / "spec.toml"
    spec.write_text(
        '[sweep]\nbase = "paper"\npressures_MPa = [0.0, 0.5, 1.0]\n'
        '[parameters]\n"tube.h" = { values = [-0.06, -0.02, 0.0, 0.02] }\n'
        '"tip.bending_length" = { values = [4.0, 6.0] }\n'
    )
    assert main(["sweep", str(spec), "--out", str(root / "s"), "--workers", "1", "--no-progress"]) == 0
    return root / "s"


TOKENS = [
    "bend_angle_deg",
    "max_strain",
    "elongation",
    "bend_per_MPa_deg",
    "tube.h",
    "nosuch",
    "status",
    "reason",
    "0",
    "1",
    "90",
    "1e999",
    "0.3",
    "-",
    "+",
    "*",
    "/",
    "**",
    "%",
    "(",
    ")",
    "abs(",
    "exp(",
    "<=",
    ">=",
    "<",
    "==",
    "and",
    "or",
    "not",
    "at p_max",
    "at p=0.5",
    "at p=7",
    "at",
    "'x'",
    "__import__",
    ".",
    ",",
    "lambda",
]
COLUMNS = ["bend_angle_deg", "max_strain", "elongation", "bend_per_MPa_deg", "tube.h", "curvature_per_mm"]
well_formed = st.builds(
    lambda col, op, num, where: f"{col} {op} {num}{where}",
    st.sampled_from(COLUMNS),
    st.sampled_from(["<=", ">=", "<", ">"]),
    st.one_of(st.floats(-100, 100).map(lambda x: f"{x:g}"), st.sampled_from(["0.3", "20", "abs(tube.h)"])),
    st.sampled_from(["", " at p_max", " at p=0.5", " at p_min"]),
)
random_tokens = st.lists(st.sampled_from(TOKENS), min_size=1, max_size=7).map(" ".join)
expressions = st.one_of(well_formed, well_formed, well_formed, random_tokens)
good_objective = st.builds(
    lambda d, c: f"{d} {c}", st.sampled_from(["maximise", "minimise"]), st.sampled_from(COLUMNS)
)
objectives_ = st.one_of(
    good_objective, good_objective, good_objective, random_tokens.map(lambda e: "maximise " + e)
)


@fuzz(60)
@given(
    constraints=st.lists(expressions, max_size=2),
    objectives=st.lists(objectives_, min_size=1, max_size=2) | st.just([]),
    top=st.sampled_from(["1", "5", "0", "-3", "50"]),
    load=st.sampled_from(["cap", "lumen"]),
)
def test_select(cli, sweep_dir, constraints, objectives, top, load):
    argv = ["select", sweep_dir, "--load", load, "--top", top]
    for c in constraints:
        argv += ["--constraint", c]
    for o in objectives:
        argv += ["--objective", o]
    before = _digest(sweep_dir)
    r = cli(*argv)
    event(f"exit {r.status}")
    names = tuple(constraints) + tuple(o.split(None, 1)[-1] for o in objectives) + ("--top", "objective")
    assert r.status in (0, 2)
    if r.status == 2:
        line = r.error_line()
        assert any(n.strip() and (n in line or n.split()[0] in line) for n in names), line
        assert _digest(sweep_dir) == before
    else:
        _strict_json(sweep_dir / "selection.json")


@fuzz(4)
@given(
    victim=st.sampled_from(
        ["sweep.json", "results.parquet", "designs.csv", "selection.json", "columns.json"]
    ),
    content=st.one_of(st.binary(max_size=64), st.just(b""), st.just(b'{"spec": 1}')),
)
def test_report_on_damaged_files(cli, tmp_path, sweep_dir, victim, content):
    import shutil

    work = _out(tmp_path, "r")
    shutil.copytree(sweep_dir, work)
    (work / victim).write_bytes(content)
    r = cli("report", work)
    _check(r, None, {}, (victim, str(work)))
    if r.status == 0:
        assert (work / "report" / "index.html").is_file()


# --- calibrate -------------------------------------------------------------------------------------


@fuzz(20)
@given(
    free=st.one_of(
        st.lists(st.sampled_from(["a", "a_int", "b_int", "h"]), min_size=0, max_size=4, unique=True).map(
            ",".join
        ),
        st.sampled_from(["a,a", "x", "a;h", ",", "A_INT"]),
    ),
    grid=st.one_of(st.integers(1, 3), st.integers(-2, 200)),
    load=st.sampled_from(["cap", "lumen"]),
)
def test_calibrate_options(cli, tmp_path, free, grid, load):
    out = tmp_path / "c"
    before = _digest(out)
    r = cli(
        "calibrate", DATA / "paper_sine.csv", "--out", out, "--free", free, "--grid", grid, "--load", load
    )
    _check(r, out, before, ("--grid", "free", "--free"))


# --- commands fuzzed on what they must refuse before any work -----------------------------------


@fuzz(30)
@given(mesh=anything_numeric, pressure=anything_numeric, nonlinear=st.booleans())
def test_fem_options(cli, tmp_path, mesh, pressure, nonlinear):
    def num(text):
        try:
            return float(text)
        except ValueError:
            return None

    m, p = num(mesh), num(pressure)
    if m is not None and p is not None and math.isfinite(p) and abs(p) <= 100 and (p > 0 or not nonlinear):
        try:
            check_fem_budget(design.preset("paper"), mesh_size=m)
            assume(False)  # a valid run: a solve of seconds, covered by the FEM tests
        except design.DesignError:
            pass
    out = tmp_path / "f"
    argv = ["fem", "paper", f"--pressure={pressure}", f"--mesh-size={mesh}", "--out", out]
    r = cli(*(argv + ["--nonlinear"] if nonlinear else argv))
    _check(r, out, {}, ("--pressure", "--mesh-size"))


@fuzz(25)
@given(
    duration=anything_numeric,
    pscale=anything_numeric,
    escale=anything_numeric,
    rate=st.sampled_from(["200", "0", "-1", "nan", "inf"]),
)
def test_record_options(cli, tmp_path, duration, pscale, escale, rate):
    def ok(text, positive):
        try:
            v = float(text)
        except ValueError:
            return True  # argparse refuses it
        return math.isfinite(v) and (v > 0 if positive else v != 0)

    assume(not (ok(duration, True) and ok(pscale, False) and ok(escale, False) and ok(rate, True)))
    argv = [
        "record",
        "--pressure-port",
        "loop://",
        "--encoder-port",
        "loop://",
        f"--duration={duration}",
        f"--pressure-scale={pscale}",
        f"--encoder-scale={escale}",
        f"--device-rate={rate}",
    ]
    r = cli(*argv, "--out", tmp_path / "r")
    _check(r, None, {}, ("--duration", "--pressure-scale", "--encoder-scale", "--device-rate"))


@fuzz(25)
@given(
    freq=st.one_of(anything_numeric, st.lists(anything_numeric, min_size=1, max_size=3).map(",".join)),
    cycles=st.integers(-3, 2000),
    pmax=anything_numeric,
    noise=anything_numeric,
    fps=anything_numeric,
    effect=st.sampled_from(
        ["hysteresis", "lag:tau_s=nan", "nosuch", "hysteresis:fraction=2", "lag:tau_s", "offset"]
    ),
    seed=st.sampled_from([0, 7, -1, 2**64]),
)
def test_bench_options(cli, tmp_path, freq, cycles, pmax, noise, fps, effect, seed):
    def num(text):
        try:
            return float(text)
        except ValueError:
            return None

    freqs = [num(f) for f in freq.split(",") if f.strip()]
    valid = (
        freqs
        and all(f is not None and math.isfinite(f) and 0.01 <= f <= 10 for f in freqs)
        and 1 <= cycles <= 1000
        and (num(pmax) is not None and 0 < num(pmax) <= 10)
        and (num(noise) is not None and 0 <= num(noise) <= 100)
        and (num(fps) is not None and 1 <= num(fps) <= 200)
        and effect in ("hysteresis", "offset")
        and 0 <= seed < 2**63
    )
    assume(not valid)  # a valid run takes seconds of simulated devices: tests/hardware/test_bench.py
    out = tmp_path / "b"
    argv = [
        "bench",
        f"--freq={freq}",
        "--cycles",
        cycles,
        f"--pressure-max={pmax}",
        f"--noise={noise}",
        f"--fps={fps}",
        "--effect",
        effect,
        "--seed",
        seed,
        "--out",
        out,
    ]
    r = cli(*argv)
    names = ("freq", "cycles", "pressure_max", "noise", "fps", "effect", "tau_s", "fraction", "seed")
    _check(r, out, {}, names)


@fuzz(20)
@given(margin=anything_numeric, max_effects=st.integers(-3, 50))
def test_discrepancy_options(cli, tmp_path, margin, max_effects):
    try:
        m = float(margin)
        assume(not (math.isfinite(m) and 0 <= m < 1 and 1 <= max_effects <= 10))
    except ValueError:
        pass
    out = tmp_path / "d"
    r = cli(
        "discrepancy",
        DATA / "paper_sine.csv",
        f"--margin={margin}",
        "--max-effects",
        max_effects,
        "--out",
        out,
    )
    _check(r, out, {}, ("--margin", "--max-effects"))


@fuzz(15)
@given(
    workers=st.integers(-3, 0),
    only=st.sampled_from(["model", "nosuch", "model,,fem", "", "MODEL"]),
    design_ref=st.sampled_from(["paper", "nosuch_preset", "/nonexistent.toml"]),
)
def test_demo_options(cli, tmp_path, workers, only, design_ref):
    out = tmp_path / "demo"
    r = cli("demo", design_ref, "--workers", workers, "--only", only, "--no-fem", "--out", out)
    _check(r, out, {}, ("workers", "only", "design", "nosuch", "nonexistent"))


@pytest.fixture(scope="module")
def frames(tmp_path_factory):
    cv2 = pytest.importorskip("cv2")
    from softcath.virtualbench.render import Scene, render_frame

    scene = Scene(px_per_mm=40.0)
    folder = tmp_path_factory.mktemp("frames")
    rng = np.random.default_rng(1)
    for i in range(2):
        img = render_frame(
            scene, curvature_per_mm=math.radians(40 + 30 * i) / 5.0, arc_length_mm=5.0, rng=rng
        )
        cv2.imwrite(str(folder / f"f{i}.png"), img)
    return folder, scene


@fuzz(25)
@given(
    scale=st.one_of(anything_numeric, st.just("40")),
    base=st.one_of(st.none(), st.just("good"), st.tuples(anything_numeric, anything_numeric).map(",".join)),
    angle=st.one_of(anything_numeric, st.just("90")),
    dy=st.sampled_from(["10", "0", "-1", "nan", "1e9"]),
    fps=st.sampled_from(["10", "0", "nan", "-5", "1e9"]),
)
def test_measure_options(cli, tmp_path, frames, scale, base, angle, dy, fps):
    folder, scene = frames
    out = tmp_path / "m"
    before = _digest(out)
    argv = ["measure", folder, f"--px-per-mm={scale}", f"--base-angle={angle}", f"--dy={dy}", f"--fps={fps}"]
    if base is not None:
        argv.append(f"--base={scene.base[0]},{scene.base[1]}" if base == "good" else f"--base={base}")
    r = cli(*argv, "--out", out)
    _check(r, out, before, ("--px-per-mm", "--base", "--base-angle", "--dy", "--fps", "no tip found"))
    if r.status == 0:
        df = pd.read_csv(out / "measurements.csv")
        k = df["curvature_per_mm"].to_numpy(float)
        assert np.isfinite(k[~np.isnan(k)]).all() and (~np.isnan(k)).any()
