"""``softcath optimise`` and ``select``: expressions checked before any work under one pressure rule,
worker counts bounded, an infeasible search writes its reason and no design, reruns leave no stale
designs and never replace an input."""

from __future__ import annotations

import json

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

FUZZ = settings(
    max_examples=40,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
BASE = [
    "optimise",
    "paper",
    "--model",
    "paper",
    "--vary",
    "tube.h=-0.04:0.04",
    "--no-fem-check",
    "--no-progress",
]


@FUZZ
@given(
    value=st.one_of(
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
        st.sampled_from(["e", "pi", "1e300", "-5", "0", "100", "100.5", "-0", "0x1", "1_0", "nan", "--1"]),
    )
)
def test_at_p_follows_the_pressure_rule_before_any_work(cli, tmp_path, value):
    out = tmp_path / "o"
    text = f"maximise bend_angle_deg at p={value}"
    try:
        p = float(value)
        ok = 0 <= p <= 100
    except ValueError:
        ok = False
    if ok:
        return  # a valid pressure: the search runs (tested below on one)
    r = cli(*BASE, "--objective", text, "--budget", "10", "--out", out)
    line = r.error_line()
    assert f"--objective = {text!r}" in line, line
    assert not out.exists()  # refused before the folder and the search


@FUZZ
@given(
    depth=st.integers(51, 5000),  # past the depth limit (parentheses: past the parser's own)
    kind=st.sampled_from(["-{}", "abs({})", "({})", "{}+1", "1*{}"]),
    option=st.sampled_from(["--objective", "--constraint"]),
)
def test_deep_or_long_expressions_are_refused_naming_the_option(cli, tmp_path, depth, kind, option):
    expr = "bend_angle_deg"
    if kind == "({})":
        depth += 200  # Python drops parentheses from the tree; its parser refuses more than 200
    for _ in range(depth):
        expr = kind.format(expr)
        if len(expr) > 3000:
            break
    text = f"maximise {expr}" if option == "--objective" else f"{expr} >= 1"
    argv = [*BASE, "--budget", "10", "--out", tmp_path / "o"]
    argv += ["--objective", text] if option == "--objective" else ["--objective", "maximise x", option, text]
    if option == "--constraint":
        argv[argv.index("maximise x")] = "maximise bend_angle_deg"
    line = cli(*argv).error_line()
    assert line.startswith(f"softcath optimise: error: {option} = "), line
    assert len(line) < 600
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("workers", ["1000000000000", "0", "257"])
def test_workers_out_of_range_are_refused_before_any_work(cli, tmp_path, workers):
    out = tmp_path / "o"
    line = cli(
        *BASE, "--objective", "maximise bend_angle_deg", "--workers", workers, "--out", out
    ).error_line()
    assert f"--workers = {workers}: must be an integer in [1, 256]" in line
    assert not out.exists()


def test_suction_is_refused_alike_in_pressures_and_expressions(cli, tmp_path):
    a = cli(*BASE, "--objective", "maximise bend_angle_deg at p=-5", "--out", tmp_path / "a").error_line()
    b = cli(
        *BASE, "--objective", "maximise bend_angle_deg", "--pressures=-5", "--out", tmp_path / "b"
    ).error_line()
    assert (
        "pressures must be finite and in [0, 100] MPa" in a
        and "pressures must be finite and in [0, 100] MPa" in b
    )


def test_an_unknown_column_is_refused_before_the_search(cli, tmp_path):
    out = tmp_path / "o"
    line = cli(*BASE, "--objective", "maximise bogus_col at p=0.5", "--out", out).error_line()
    assert "unknown column 'bogus_col'" in line and "columns.json" not in line
    assert not out.exists()


def test_an_infeasible_search_writes_its_reason_and_no_design(cli, tmp_path):
    out = tmp_path / "o"
    good = cli(*BASE, "--objective", "maximise bend_angle_deg at p=0.5", "--budget", "10", "--out", out)
    assert good.status == 0 and (out / "designs" / "best.toml").is_file()
    r = cli(
        *BASE,
        "--objective",
        "maximise bend_angle_deg at p=0.5",
        "--constraint",
        "max_strain <= 0.0001",
        "--budget",
        "10",
        "--out",
        out,
    )
    line = r.error_line()
    assert "--constraint = 'max_strain <= 0.0001': none of the" in line and "no design written" in line
    doc = json.loads((out / "optimum.json").read_text())
    assert doc["feasible"] is False and "max_strain <= 0.0001" in doc["reason"]
    assert doc["best"][0]["feasible"] is False and doc["best"][0]["reason"]
    # the earlier run's design is not left looking like this run's answer
    assert not (out / "designs" / "best.toml").exists()


def test_a_rerun_leaves_no_stale_pareto_designs_and_keeps_the_users_files(cli, tmp_path):
    out = tmp_path / "o"
    two = ["--objective", "maximise bend_angle_deg at p=0.5", "--objective", "minimise max_strain at p=0.5"]
    assert cli(*BASE, *two, "--budget", "20", "--out", out).status == 0
    assert sorted((out / "designs").glob("pareto_*.toml"))
    (out / "designs" / "notes.txt").write_text("mine")
    assert cli(*BASE, "--objective", "maximise bend_angle_deg", "--budget", "10", "--out", out).status == 0
    doc = json.loads((out / "optimum.json").read_text())
    listed = {f"{w['name']}.toml" for w in doc["best"]}
    assert {p.name for p in (out / "designs").glob("*.toml")} == listed == {"best.toml"}
    assert (out / "designs" / "notes.txt").read_text() == "mine"


def test_the_input_design_inside_out_is_refused_before_any_work(cli, tmp_path):
    out = tmp_path / "o"
    assert cli(*BASE, "--objective", "maximise bend_angle_deg", "--budget", "10", "--out", out).status == 0
    design = out / "designs" / "best.toml"
    before = design.read_bytes()
    argv = [BASE[0], design, *BASE[2:]]
    line = cli(*argv, "--objective", "maximise bend_angle_deg", "--budget", "10", "--out", out).error_line()
    assert "--out = " in line and "holds the input" in line and "(DESIGN)" in line
    assert design.read_bytes() == before


def _descendants(pid: int) -> list[tuple[int, int]]:
    """``(pid, depth)`` of every live descendant of ``pid`` (from /proc), children first."""
    import os

    parents = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat", encoding="ascii") as fh:
                    parents[int(entry)] = int(fh.read().rsplit(")", 1)[1].split()[1])
            except (OSError, ValueError, IndexError):
                continue
    out, todo = [], [(pid, 0)]
    while todo:
        p, depth = todo.pop()
        kids = [(c, depth + 1) for c, pp in parents.items() if pp == p]
        out.extend(kids)
        todo.extend(kids)
    return out


def test_a_killed_worker_fails_the_run_in_one_line_and_keeps_the_earlier_outputs(cli, tmp_path):
    """Fault injection: SIGKILL the search's worker processes mid-run (a real kill, no mock)."""
    import hashlib
    import os
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "o"
    assert cli(*BASE, "--objective", "maximise bend_angle_deg", "--budget", "10", "--out", out).status == 0

    def digest():
        return {
            p.relative_to(out).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(out.rglob("*"))
            if p.is_file()
        }

    before = digest()
    argv = ["optimise", "paper", "--model", "section", "--vary", "tube.h=-0.04:0.04", "--no-fem-check"]
    argv += ["--objective", "maximise bend_angle_deg at p=0.5", "--budget", "2000", "--workers", "2"]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    proc = subprocess.Popen(
        [sys.executable, "-m", "softcath", *argv, "--no-progress", "--out", str(out)],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        deadline = time.monotonic() + 60
        # the pool's workers: forked by its fork server (depth 2), beside the resource tracker
        while time.monotonic() < deadline and not [p for p, d in _descendants(proc.pid) if d >= 2]:
            time.sleep(0.2)
        time.sleep(2.0)  # the workers are evaluating
        workers = [p for p, d in _descendants(proc.pid) if d >= 2]
        assert workers, "no worker processes started"
        for pid in workers:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 2, err
    lines = [ln for ln in err.splitlines() if ": error: " in ln]
    assert len(lines) == 1 and "a worker process died" in lines[0] and "Traceback" not in err
    assert digest() == before  # the earlier run's optimum, designs, report and ledger as they were
